//! The structures of seed 003 §4.2 that make Theorem 1's LMIs convex in the filter (3.3),
//!
//! ```text
//! x̂(k+1) = W x̂ + H (y − Γ x̂),   ẑ = F x̂ + G (y − Γ x̂),   x̂(0) = E x0,
//! ```
//!
//! on the error system (4.7)–(4.11) in X = (x, e), e = x − x̂, with X(k) = W − HΓ and Y(k) = F − GΓ:
//!
//! ```text
//! 𝒜 = [[A, 0], [A − X − H Cy, X]],  ℬ = [B; B − H Dy],  𝒞 = [Cz − Y − G Cy, Y],  𝒟 = Dz − G Dy,
//! ```
//!
//! every plant matrix a mean plus Σᵢ ζᵢ Mᵢ (the factors of (2.1); a dropout is the term
//! √(p(1 − p)) Cy of λ Cy, whose mean is p Cy).
//!
//! - **`predictor`** (§4.2.3, G = 0, F = E\[Cz], Γ = E\[Cy]; with dropouts this is §4.2.1, (4.31)):
//!   P = diag(P1, P2), Q = P2(k+1)W, 𝒴 = P2(k+1)H make P'𝒜, P'ℬ linear ((4.39)–(4.41)).
//! - **`static`** (§4.2.2, H = 0): x̂ ≡ 0 and ẑ = G y; the error system is the plant's own with
//!   𝒞 = Cz − G Cy, 𝒟 = Dz − G Dy (4.44), linear in G with P(k) full: no restriction.
//! - **`gamma_zero`** (§4.2.4, Γ = 0, Theorem 2) and **`gamma_mean`** (§4.2.5, Γ = E\[Cy],
//!   Theorem 3): W, H, F, G all free. With P = diag(P1, P2) the substitution (П.2.1)
//!   𝒴 = 𝒳P(k+1), 𝒳 = [[0, 0], [W, H]], is Q = P2'W, 𝒴 = P2'H, and 𝒞 is linear in (Y, G). The two
//!   differ only in where H E\[Cy] sits ((4.53) against (4.69)): X = W − HΓ is free either way, so
//!   they describe the same filters and give the same γ up to the solver's tolerance.
//!
//! **What the restriction costs.** A full P(k) would leave P12(k+1)W in P'𝒜, which no linear
//! substitution removes; P12 = 0 is a restriction of Theorem 1's feasible set, so the bound holds
//! and may be larger than what Theorem 1 certifies for the same filter with a full P. The design
//! check ([`super::synthesize_checked`]) measures exactly that: Theorem 1 with a full P on the
//! designed filter. `static` needs no restriction but gives up the filter's state.
//!
//! **Nesting.** `gamma_*` contains `predictor` (G = 0, Y = E\[Cz]) with the same P, so its γ is never
//! larger; it contains `static` (W = H = 0, Y = 0) only as P2 → 0, which the floor P2 ⪰ εI
//! (needed to recover W = P2⁻¹Q) excludes: γ(gamma_*) ≤ γ(static) up to O(ε).

use crate::analysis::theorem1::{Conditions, Level, Step, Term};
use crate::filter::realization::{Gains, Realization};
use crate::model::plant::Plant;
use crate::numerics::linalg::Mat;
use crate::numerics::solve::affine::{AffMat, Vars};
use crate::numerics::solve::conic::{Conic, Failure, Tuning};

/// Which filter of §4.2 the SDP designs (the module docs); a filter's `structure` key.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Structure {
    Predictor,
    Static,
    GammaZero,
    GammaMean,
}

impl Structure {
    pub fn name(self) -> &'static str {
        match self {
            Structure::Predictor => "predictor",
            Structure::Static => "static",
            Structure::GammaZero => "gamma_zero",
            Structure::GammaMean => "gamma_mean",
        }
    }
    /// The section of seed 003 it implements.
    pub fn section(self) -> &'static str {
        match self {
            Structure::Predictor => "§4.2.3 (§4.2.1 with dropouts)",
            Structure::Static => "§4.2.2",
            Structure::GammaZero => "§4.2.4, Theorem 2",
            Structure::GammaMean => "§4.2.5, Theorem 3",
        }
    }
    /// Whether ẑ(k) uses y(k) (through G).
    pub fn filtering(self) -> bool {
        self != Structure::Predictor
    }
    /// Whether P(k) = diag(P1, P2) on X = (x, e).
    fn block_diagonal(self) -> bool {
        self != Structure::Static
    }
}

/// The solved synthesis: the filter (3.3) per step, Γ's choice implied by the structure.
#[derive(Clone, Debug)]
pub struct Synthesis {
    pub structure: Structure,
    pub w: Vec<Mat>,
    pub h: Vec<Mat>,
    pub f: Vec<Mat>,
    pub g: Vec<Mat>,
    /// The solver's γ² (the program's objective) and η = 1/q (+∞ in the H2 limit program, a = 0).
    /// Not itself a proven bound: an interior-point value within `objective_error` of the optimum
    /// (the certified bound is `anisotropic::Checked::certified_sq`).
    pub gamma_sq: f64,
    pub eta: f64,
    /// clarabel's first-order bound on |γ² − the program's optimum| (`Solution::objective_error`).
    pub objective_error: f64,
    pub variables: usize,
    pub rows: usize,
    pub cones: std::collections::BTreeMap<String, usize>,
    pub iterations: u32,
    pub solve_seconds: f64,
    /// clarabel stopped at its reduced tolerances.
    pub almost: bool,
}

/// A matrix kept as (M, s) for s·M, so that the dropout's p Cy and √(p(1−p)) Cy are formed as the
/// §4.2.1 program always formed them (bit for bit: aniso_dropout's designs do not move).
type Scaled = (Mat, f64);

/// One source of multiplicative noise at step k: its matrices, None where it does not enter.
struct Noise {
    a: Option<Mat>,
    b: Option<Mat>,
    cy: Option<Scaled>,
    dy: Option<Mat>,
    cz: Option<Mat>,
    dz: Option<Mat>,
}

/// The plant at step k as seed 003 (2.1) writes it: the means and the noise terms (the dropout,
/// then each factor in file order).
struct PlantStep {
    a: Mat,
    b: Mat,
    cy: Scaled,
    dy: Mat,
    cz: Mat,
    dz: Mat,
    noise: Vec<Noise>,
}

fn plant_step(plant: &Plant, k: usize) -> PlantStep {
    let mut noise = Vec::new();
    let v = plant.dropout_variance();
    if v > 0.0 {
        noise.push(Noise { a: None, b: None, cy: Some((plant.c.at(k).clone(), v.sqrt())), dy: None, cz: None, dz: None });
    }
    for f in &plant.factors {
        let at = |m: &Option<crate::model::plant::Steps>| m.as_ref().map(|s| s.at(k).clone());
        noise.push(Noise {
            a: at(&f.a),
            b: at(&f.b),
            cy: at(&f.c).map(|c| (c, 1.0)),
            dy: at(&f.d),
            cz: at(&f.cz),
            dz: at(&f.dz),
        });
    }
    PlantStep {
        a: plant.a_at(k).clone(),
        b: plant.b_at(k).clone(),
        cy: (plant.c.at(k).clone(), plant.arrival_mean()),
        dy: plant.d.at(k).clone(),
        cz: plant.cz_at(k).clone(),
        dz: plant.dz_at(k).clone(),
        noise,
    }
}

/// y · (s M).
fn times(y: &AffMat, m: &Scaled) -> AffMat {
    y.rmul(&m.0).scale(m.1)
}

/// The filter variables of a step: Q = P2'W and 𝒴 = P2'H (k < N, block-diagonal structures), and
/// Y = F − GΓ and G where the structure leaves them free.
struct FilterVars {
    q: Option<AffMat>,
    y: Option<AffMat>,
    out: Option<AffMat>,
    g: Option<AffMat>,
}

/// Solves the structure's SDP: Theorem 1's LMIs (`Conditions`) with its change of variables,
/// minimizing γ² at `level`.
pub(crate) fn synthesize_tuned(
    plant: &Plant,
    structure: Structure,
    level: Level,
    tuning: &Tuning,
) -> std::result::Result<Synthesis, Failure> {
    let (nx, mw, pz, ny) = (plant.nx(), plant.nw(), plant.nz(), plant.ny());
    let (steps, nn) = (plant.steps(), plant.horizon);
    let diag = structure.block_diagonal();
    let mut vars = Vars::default();
    let mut cond = Conditions::new(&mut vars, level);
    // P(k) = diag(P1, P2) on (x, e), or a full P on x alone (static).
    let p1: Vec<AffMat> = (0..steps).map(|_| vars.symmetric(nx)).collect();
    let p2: Vec<AffMat> = if diag { (0..steps).map(|_| vars.symmetric(nx)).collect() } else { Vec::new() };
    let q: Vec<AffMat> = if diag { (0..nn).map(|_| vars.matrix(nx, nx, false)).collect() } else { Vec::new() };
    let y: Vec<AffMat> = if diag { (0..nn).map(|_| vars.matrix(nx, ny, false)).collect() } else { Vec::new() };
    let free_output = matches!(structure, Structure::GammaZero | Structure::GammaMean);
    let out: Vec<AffMat> = if free_output { (0..steps).map(|_| vars.matrix(pz, nx, false)).collect() } else { Vec::new() };
    let g: Vec<AffMat> = if structure.filtering() { (0..steps).map(|_| vars.matrix(pz, ny, false)).collect() } else { Vec::new() };
    cond.determinant_variables(&mut vars, steps, mw);

    let state = |k: usize| -> AffMat {
        if diag {
            AffMat::symmetric_blocks(&[nx, nx], &[vec![Some(p1[k].clone())], vec![None, Some(p2[k].clone())]])
        } else {
            p1[k].clone()
        }
    };
    let lmis: Vec<Step> = (0..steps)
        .map(|k| {
            let ps = plant_step(plant, k);
            let fv = FilterVars {
                q: q.get(k).cloned(),
                y: y.get(k).cloned(),
                out: out.get(k).cloned(),
                g: g.get(k).cloned(),
            };
            let next = (k < nn).then(|| (p1[k + 1].clone(), p2.get(k + 1).cloned()));
            Step {
                p: state(k),
                next: (k < nn).then(|| state(k + 1)),
                terms: terms(structure, &ps, next.as_ref(), &fv),
                extra_psd: p2.get(k).and_then(|p2k| floor(plant, structure, k).map(|eps| p2k.sub(&AffMat::constant(Mat::identity(nx, nx) * eps)))).into_iter().collect(),
            }
        })
        .collect();
    let mut conic = Conic::default();
    cond.add(&mut vars, &mut conic, &lmis, mw);

    let cost = cond.cost(vars.count);
    let (rows, cones) = conic.size();
    let sol = conic.minimize_tuned(&cost, tuning)?;
    let x = &sol.x;
    let singular =
        || Failure { status: "solved, but P2(k+1) is singular: W, H cannot be recovered".into(), infeasible: false };
    let (mut ws, mut hs, mut fs, mut gs) = (Vec::new(), Vec::new(), Vec::new(), Vec::new());
    for k in 0..steps {
        if diag && k < nn {
            let lu = p2[k + 1].value(x).lu();
            ws.push(lu.solve(&q[k].value(x)).ok_or_else(singular)?);
            hs.push(lu.solve(&y[k].value(x)).ok_or_else(singular)?);
        } else {
            // W, H of step N are never used (and the static filter has none).
            ws.push(if diag { plant.a_at(k).clone() } else { Mat::zeros(nx, nx) });
            hs.push(Mat::zeros(nx, ny));
        }
        fs.push(match structure {
            Structure::Predictor => plant.cz_at(k).clone(),
            Structure::Static => Mat::zeros(pz, nx),
            Structure::GammaZero | Structure::GammaMean => out[k].value(x),
        });
        gs.push(if structure.filtering() { g[k].value(x) } else { Mat::zeros(pz, ny) });
    }
    Ok(Synthesis {
        structure,
        w: ws,
        h: hs,
        f: fs,
        g: gs,
        gamma_sq: cond.gamma_sq(x),
        eta: cond.eta(x),
        objective_error: sol.objective_error,
        variables: vars.count,
        rows,
        cones,
        iterations: sol.iterations,
        solve_seconds: sol.seconds,
        almost: sol.almost,
    })
}

/// P2(k) ⪰ P2_FLOOR · λmax(CzᵀCz) I where the LMIs do not force P2 ≻ 0 (see `floor`).
const P2_FLOOR: f64 = 1e-6;

/// P2(k) ⪰ P2_FLOOR · λmax(CzᵀCz) I keeps W = P2⁻¹Q recoverable where the LMIs do not force
/// P2 ≻ 0: in `predictor` they give P2(k) ⪰ CzᵀCz (the output row [0, Cz]), so the floor is needed
/// only for a column-rank-deficient Cz; in `gamma_*` the output row carries the free Y, so always.
/// A restriction of the feasible set (the bound still holds), small enough to cost nothing
/// measurable in γ.
fn floor(plant: &Plant, structure: Structure, k: usize) -> Option<f64> {
    let cz = plant.cz_at(k);
    let needed = match structure {
        Structure::Predictor => cz.rank(1e-12) < plant.nx(),
        Structure::Static => false,
        Structure::GammaZero | Structure::GammaMean => true,
    };
    needed.then(|| {
        let czz = cz.transpose() * cz;
        P2_FLOOR * czz.symmetric_eigenvalues().max().max(f64::MIN_POSITIVE)
    })
}

/// The terms of step k (mean first, then each noise source) as Theorem 1 takes them, after the
/// structure's change of variables. `next` is (P1(k+1), P2(k+1)) (P2 absent for `static`), None at
/// k = N.
fn terms(structure: Structure, ps: &PlantStep, next: Option<&(AffMat, Option<AffMat>)>, fv: &FilterVars) -> Vec<Term> {
    let nx = ps.a.nrows();
    let zero = |r: usize, c: usize| AffMat::zeros(r, c);
    let mean_out = |cz: &Mat| -> (AffMat, AffMat) {
        match structure {
            // 𝒞 = [0, Cz] (Y = E[Cz], G = 0), 𝒟 = Dz.
            Structure::Predictor => {
                let mut c = Mat::zeros(cz.nrows(), 2 * nx);
                c.view_mut((0, nx), (cz.nrows(), nx)).copy_from(cz);
                (AffMat::constant(c), AffMat::constant(ps.dz.clone()))
            }
            Structure::Static => {
                let g = fv.g.as_ref().expect("static has G");
                (AffMat::constant(cz.clone()).sub(&times(g, &ps.cy)), AffMat::constant(ps.dz.clone()).sub(&g.rmul(&ps.dy)))
            }
            Structure::GammaZero | Structure::GammaMean => {
                let (g, y) = (fv.g.as_ref().expect("G"), fv.out.as_ref().expect("Y"));
                let left = AffMat::constant(cz.clone()).sub(y).sub(&times(g, &ps.cy));
                (AffMat::hstack(&left, y), AffMat::constant(ps.dz.clone()).sub(&g.rmul(&ps.dy)))
            }
        }
    };
    let (c0, d0) = mean_out(&ps.cz);
    let mut mean = Term { pa: None, pb: None, c: Some(c0), d: Some(d0) };
    if let Some((p1n, p2n)) = next {
        match p2n {
            None => {
                mean.pa = Some(p1n.rmul(&ps.a));
                mean.pb = Some(p1n.rmul(&ps.b));
            }
            Some(p2n) => {
                let (q, y) = (fv.q.as_ref().expect("Q"), fv.y.as_ref().expect("𝒴"));
                let top = AffMat::hstack(&p1n.rmul(&ps.a), &zero(nx, nx));
                // P2'(A − X − H E[Cy]) and P2'X, with X = W − HΓ.
                let bottom = match structure {
                    Structure::GammaZero => AffMat::hstack(&p2n.rmul(&ps.a).sub(q).sub(&times(y, &ps.cy)), q),
                    _ => AffMat::hstack(&p2n.rmul(&ps.a).sub(q), &q.sub(&times(y, &ps.cy))),
                };
                mean.pa = Some(AffMat::vstack(&top, &bottom));
                mean.pb = Some(AffMat::vstack(&p1n.rmul(&ps.b), &p2n.rmul(&ps.b).sub(&y.rmul(&ps.dy))));
            }
        }
    }
    let mut out = vec![mean];
    for n in &ps.noise {
        let mut t = Term::default();
        if let Some((p1n, p2n)) = next {
            match p2n {
                None => {
                    t.pa = n.a.as_ref().map(|a| p1n.rmul(a));
                    t.pb = n.b.as_ref().map(|b| p1n.rmul(b));
                }
                Some(p2n) => {
                    let y = fv.y.as_ref().expect("𝒴");
                    if n.a.is_some() || n.cy.is_some() {
                        let top = n.a.as_ref().map_or_else(|| zero(nx, 2 * nx), |a| AffMat::hstack(&p1n.rmul(a), &zero(nx, nx)));
                        // P2'(Aᵢ − H Cyᵢ): the dropout's −𝒴 Cy √(p(1−p)) exactly as §4.2.1 forms it.
                        let hc = n.cy.as_ref().map(|c| y.rmul(&c.0).scale(-1.0).scale(c.1));
                        let left = match (&n.a, hc) {
                            (Some(a), Some(hc)) => p2n.rmul(a).add(&hc),
                            (Some(a), None) => p2n.rmul(a),
                            (None, Some(hc)) => hc,
                            (None, None) => unreachable!(),
                        };
                        t.pa = Some(AffMat::vstack(&top, &AffMat::hstack(&left, &zero(nx, nx))));
                    }
                    if n.b.is_some() || n.dy.is_some() {
                        let bi = n.b.clone().unwrap_or_else(|| Mat::zeros(nx, ps.b.ncols()));
                        let mut bottom = p2n.rmul(&bi);
                        if let Some(dy) = &n.dy {
                            bottom = bottom.sub(&y.rmul(dy));
                        }
                        t.pb = Some(AffMat::vstack(&p1n.rmul(&bi), &bottom));
                    }
                }
            }
        }
        // 𝒞ᵢ = [Czᵢ − G Cyᵢ, 0] (one block for `static`), 𝒟ᵢ = Dzᵢ − G Dyᵢ.
        let g = fv.g.as_ref();
        let gc = match (g, &n.cy) {
            (Some(g), Some(c)) => Some(times(g, c).scale(-1.0)),
            _ => None,
        };
        let ci = match (&n.cz, gc) {
            (Some(cz), Some(gc)) => Some(AffMat::constant(cz.clone()).add(&gc)),
            (Some(cz), None) => Some(AffMat::constant(cz.clone())),
            (None, gc) => gc,
        };
        t.c = ci.map(|c| if structure.block_diagonal() { AffMat::hstack(&c, &zero(c.shape().0, nx)) } else { c });
        let gd = match (g, &n.dy) {
            (Some(g), Some(dy)) => Some(g.rmul(dy).scale(-1.0)),
            _ => None,
        };
        t.d = match (&n.dz, gd) {
            (Some(dz), Some(gd)) => Some(AffMat::constant(dz.clone()).add(&gd)),
            (Some(dz), None) => Some(AffMat::constant(dz.clone())),
            (None, gd) => gd,
        };
        out.push(t);
    }
    out
}

/// The filter (3.3) as a realization: s\[k+1] = X s + H y + r with X = W − HΓ, ẑ = Y s + G y with
/// Y = F − GΓ (F is stored as Y already; W as W). Γ = E\[Cy] for `predictor` and `gamma_mean`, 0 for
/// `gamma_zero`; the static filter's state stays zero (W = H = 0, Y = 0).
pub fn realization(plant: &Plant, syn: &Synthesis) -> Realization {
    let p = plant.arrival_mean();
    let nx = plant.nx();
    let steps: Vec<Gains> = (0..plant.steps())
        .map(|k| {
            let af = match syn.structure {
                Structure::Predictor | Structure::GammaMean => &syn.w[k] - p * &syn.h[k] * plant.c.at(k),
                Structure::GammaZero | Structure::Static => syn.w[k].clone(),
            };
            let mut gains = Gains::predicting(af, syn.h[k].clone(), &syn.f[k]);
            gains.df = syn.g[k].clone();
            if syn.structure == Structure::Static {
                gains.gf = Mat::zeros(nx, nx);
            }
            gains
        })
        .collect();
    match syn.structure {
        Structure::Static => Realization::new(crate::numerics::linalg::Vector::zeros(nx), steps),
        _ => Realization::state_estimator(plant.x0_mean.clone(), steps),
    }
}
