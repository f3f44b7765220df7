//! Theorem 1's LMIs (4.25)–(4.29) written into a conic program, for the analysis of a given filter
//! and for every synthesis of `families::anisotropic` alike (the module docs of
//! [`super`]): a caller gives, per step, P(k), P(k+1) and the products P(k+1)𝒜ᵢ, P(k+1)ℬᵢ, 𝒞ᵢ, 𝒟ᵢ
//! as affine matrices.

use crate::numerics::linalg::Mat;
use crate::numerics::solve::affine::{AffMat, Vars};
use crate::numerics::solve::conic::Conic;

/// The level of a bound: a total anisotropy a ≥ 0 (over lw = mw(N+1)), or H∞ (a = ∞).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Level {
    Anisotropy(f64),
    Hinf,
}

impl Level {
    /// a, with H∞ as +∞.
    pub fn value(self) -> f64 {
        match self {
            Level::Anisotropy(a) => a,
            Level::Hinf => f64::INFINITY,
        }
    }
}

/// One term of the error system at step k (index 0 the mean, then one per factor), as affine
/// matrices: P(k+1)𝒜ᵢ, P(k+1)ℬᵢ, 𝒞ᵢ, 𝒟ᵢ; None where the term does not enter (no zero blocks are
/// written, so the program is as small as the plant's noise).
#[derive(Clone, Debug, Default)]
pub(crate) struct Term {
    pub pa: Option<AffMat>,
    pub pb: Option<AffMat>,
    pub c: Option<AffMat>,
    pub d: Option<AffMat>,
}

/// Step k of (4.25)–(4.28): P(k), P(k+1) (None at k = N, where P(N+1) = 0), the terms, and any
/// constraint of the caller's change of variables that belongs to this step (written first).
#[derive(Clone, Debug)]
pub(crate) struct Step {
    pub p: AffMat,
    pub next: Option<AffMat>,
    pub terms: Vec<Term>,
    pub extra_psd: Vec<AffMat>,
}

/// The scalar variables η = 1/q and γ² and, for a finite level, Ψ(k) and the triangular Z(k) of the
/// determinant bound; in the H2 limit (a = 0, [`Conditions::h2_limit`]) only the matrices N(k) whose
/// traces make the objective.
pub(crate) struct Conditions {
    pub level: Level,
    /// η's index; none in the H2 limit, where η = ∞.
    eta: Option<usize>,
    /// γ²'s index (η's at a = ∞); none in the H2 limit, where γ² is Σₖ tr N(k)/lw.
    gsq: Option<usize>,
    /// Ψ(k) for 0 < a < ∞, N(k) in the H2 limit.
    psi: Vec<AffMat>,
    zl: Vec<AffMat>,
}

/// An affine scalar: constant + Σ coef·x.
type Scalar = (f64, Vec<(usize, f64)>);

impl Conditions {
    /// Creates η and γ² (the same variable at a = ∞, where (4.29) forces η = γ²; neither in the H2
    /// limit).
    pub fn new(vars: &mut Vars, level: Level) -> Self {
        let (eta, gsq) = match level {
            Level::Anisotropy(a) if a == 0.0 => (None, None),
            Level::Anisotropy(_) => (Some(vars.scalar()), Some(vars.scalar())),
            Level::Hinf => {
                let eta = vars.scalar();
                (Some(eta), Some(eta))
            }
        };
        Conditions { level, eta, gsq, psi: Vec::new(), zl: Vec::new() }
    }

    /// Whether the program is the H2 limit of (4.25)–(4.29): at a = 0 their infimum is approached
    /// only as η → ∞ (the determinant condition with a = 0 gives γ² ≥ η − (∏ det Ψ)^{1/lw}, which
    /// tends to Σₖ tr(ηI − Ψ(k))/lw from above), so the program written at a = 0 is that limit,
    /// attained at finite matrices: letting η → ∞ in the Schur complement of (4.25) leaves
    /// P(k) ⪰ E\[𝒜ᵀP'𝒜 + 𝒞ᵀ𝒞] (the coupling through ℬ, 𝒟 vanishes with (ηI − ·)⁻¹), and (4.27)
    /// becomes N(k) ⪰ E\[ℬᵀP'ℬ + 𝒟ᵀ𝒟] with ηI − Ψ(k) = N(k); minimize Σₖ tr N(k)/lw. Every point of
    /// (4.25)–(4.29) at a = 0 gives a point of this program with Σ tr N/lw ≤ γ² (the arithmetic–
    /// geometric mean inequality on the eigenvalues of Ψ), and every strictly feasible point of it is
    /// approached by points of (4.25)–(4.29) as η grows, so the two share their infimum; for a fixed
    /// filter it is tr E\[ℬᵀP̄'ℬ + 𝒟ᵀ𝒟]/lw with P̄ the Lyapunov recursion's solution, ‖F‖₂²/lw, the
    /// exact |||F|||²₀.
    pub(crate) fn h2_limit(&self) -> bool {
        self.eta.is_none()
    }

    /// Creates Ψ(k) and Z(k) for `steps` steps of an input of size mw (nothing at a = ∞; N(k) alone
    /// in the H2 limit).
    pub(crate) fn determinant_variables(&mut self, vars: &mut Vars, steps: usize, mw: usize) {
        if matches!(self.level, Level::Anisotropy(_)) {
            self.psi = (0..steps).map(|_| vars.symmetric(mw)).collect();
            if !self.h2_limit() {
                self.zl = (0..steps).map(|_| vars.matrix(mw, mw, true)).collect();
            }
        }
    }

    /// The objective's coefficients over `count` variables: γ², or Σₖ tr N(k)/lw in the H2 limit
    /// (no variable for γ² there: it would be one dense row of the normal equations).
    pub(crate) fn cost(&self, count: usize) -> Vec<f64> {
        let mut cost = vec![0.0; count];
        match self.gsq {
            Some(g) => cost[g] = 1.0,
            None => {
                let lw = self.psi.iter().map(|n| n.shape().0).sum::<usize>() as f64;
                for n in &self.psi {
                    for i in 0..n.shape().0 {
                        cost[diagonal_variable(n, i)] = 1.0 / lw;
                    }
                }
            }
        }
        cost
    }

    /// γ² at the solution x: the objective's value.
    pub(crate) fn gamma_sq(&self, x: &[f64]) -> f64 {
        match self.gsq {
            Some(g) => x[g],
            None => self.cost(x.len()).iter().zip(x).map(|(c, v)| c * v).sum(),
        }
    }

    /// η = 1/q at the solution x: +∞ in the H2 limit.
    pub(crate) fn eta(&self, x: &[f64]) -> f64 {
        self.eta.map_or(f64::INFINITY, |e| x[e])
    }

    /// Writes (4.25)–(4.29) for every step into `conic`, or their H2 limit ([`Conditions::h2_limit`]).
    pub fn add(&self, vars: &mut Vars, conic: &mut Conic, steps: &[Step], mw: usize) {
        let aniso = matches!(self.level, Level::Anisotropy(_));
        let eta_i = self.eta.map(|eta| AffMat::scalar_times(eta, Mat::identity(mw, mw)));
        for (k, st) in steps.iter().enumerate() {
            for extra in &st.extra_psd {
                extra.psd_into(conic);
            }
            let n = st.p.shape().0;
            // (4.25)/(4.26): P(k), ηI, then a P' row for every term with 𝒜ᵢ or ℬᵢ (none at k = N),
            // then an I row for every term with 𝒞ᵢ or 𝒟ᵢ. In the H2 limit the ηI row and column go,
            // and with them ℬᵢ and 𝒟ᵢ (they move to the N(k) condition below).
            let input = eta_i.is_some();
            let state_rows: Vec<&Term> = match &st.next {
                Some(_) => st.terms.iter().filter(|t| t.pa.is_some() || (input && t.pb.is_some())).collect(),
                None => Vec::new(),
            };
            let out_rows: Vec<&Term> = st.terms.iter().filter(|t| t.c.is_some() || (input && t.d.is_some())).collect();
            let pz = st.terms.iter().find_map(|t| t.c.as_ref().or(t.d.as_ref()).map(|m| m.shape().0)).unwrap_or(0);
            let mut sizes = vec![n];
            let mut lower: Vec<Vec<Option<AffMat>>> = vec![vec![Some(st.p.clone())]];
            if let Some(eta_i) = &eta_i {
                sizes.push(mw);
                lower.push(vec![None, Some(eta_i.clone())]);
            }
            // The input column (ℬᵢ, 𝒟ᵢ) follows the state column only where ηI is written.
            let row_of = |first: &Option<AffMat>, second: Option<AffMat>| -> Vec<Option<AffMat>> {
                let mut row = vec![first.clone()];
                if input {
                    row.push(second);
                }
                row
            };
            for t in &state_rows {
                let mut row = row_of(&t.pa, t.pb.clone());
                row.resize(sizes.len(), None);
                row.push(st.next.clone());
                lower.push(row);
                sizes.push(n);
            }
            for t in &out_rows {
                let mut row = row_of(&t.c, t.d.clone());
                row.resize(sizes.len(), None);
                row.push(Some(AffMat::constant(Mat::identity(pz, pz))));
                lower.push(row);
                sizes.push(pz);
            }
            AffMat::symmetric_blocks(&sizes, &lower).psd_into(conic);
            if aniso {
                // (4.27)/(4.28): ηI − Ψ(k) (N(k) in the H2 limit), a P' row per term with ℬᵢ, an I
                // row per term with 𝒟ᵢ.
                let top = match &eta_i {
                    Some(eta_i) => eta_i.sub(&self.psi[k]),
                    None => self.psi[k].clone(),
                };
                let mut sizes = vec![mw];
                let mut lower: Vec<Vec<Option<AffMat>>> = vec![vec![Some(top)]];
                if st.next.is_some() {
                    for t in st.terms.iter().filter(|t| t.pb.is_some()) {
                        let mut row = vec![t.pb.clone()];
                        row.resize(sizes.len(), None);
                        row.push(st.next.clone());
                        lower.push(row);
                        sizes.push(n);
                    }
                }
                for t in st.terms.iter().filter(|t| t.d.is_some()) {
                    let mut row = vec![t.d.clone()];
                    row.resize(sizes.len(), None);
                    row.push(Some(AffMat::constant(Mat::identity(pz, pz))));
                    lower.push(row);
                    sizes.push(pz);
                }
                AffMat::symmetric_blocks(&sizes, &lower).psd_into(conic);
                if !self.h2_limit() {
                    // det Ψ(k) ≥ ∏ Z_ii:  [[Ψ, Z], [Zᵀ, Diag Z]] ⪰ 0.
                    AffMat::symmetric_blocks(
                        &[mw, mw],
                        &[
                            vec![Some(self.psi[k].clone())],
                            vec![Some(self.zl[k].transpose()), Some(self.zl[k].diagonal())],
                        ],
                    )
                    .psd_into(conic);
                }
            }
        }
        match self.level {
            Level::Anisotropy(alevel) if !self.h2_limit() => {
                self.determinant_tree(vars, conic, alevel, mw * steps.len())
            }
            _ => {}
        }
    }

    /// (4.29) in the convex form η − γ² ≤ e^{−2a/lw} (∏ det Ψ(k))^{1/lw}: t = e^{2a/lw}(η − γ²) ≥ 0
    /// must not exceed the geometric mean of the Z_ii.
    fn determinant_tree(&self, vars: &mut Vars, conic: &mut Conic, alevel: f64, lw: usize) {
        let mw = self.psi.first().map_or(0, |p| p.shape().0);
        let s = (2.0 * alevel / lw as f64).exp();
        let (eta, gsq) = (self.eta.expect("η at a finite level"), self.gsq.expect("γ² at a finite level"));
        let t: Scalar = (0.0, vec![(eta, s), (gsq, -s)]);
        conic.nonnegative(vec![t.clone()]);
        let mut nodes: Vec<Scalar> = Vec::new();
        for z in &self.zl {
            for i in 0..mw {
                nodes.push((0.0, vec![(diagonal_variable(z, i), 1.0)]));
            }
        }
        while !nodes.len().is_power_of_two() {
            nodes.push(t.clone());
        }
        while nodes.len() > 1 {
            let mut next = Vec::with_capacity(nodes.len() / 2);
            for pair in nodes.chunks(2) {
                let u = vars.scalar();
                rotated_cone(conic, &pair[0], &pair[1], u);
                next.push((0.0, vec![(u, 1.0)]));
            }
            nodes = next;
        }
        // root ≥ t
        let root = &nodes[0];
        let mut terms = root.1.clone();
        terms.extend(t.1.iter().map(|(k, c)| (*k, -c)));
        conic.nonnegative(vec![(root.0 - t.0, terms)]);
    }
}

/// The variable of a matrix variable's diagonal entry i (the one whose coefficient has a unit there).
fn diagonal_variable(m: &AffMat, i: usize) -> usize {
    m.terms.iter().find(|(_, c)| c[(i, i)] == 1.0).map(|(k, _)| *k).expect("diagonal variable")
}

/// u² ≤ a·b with a, b ≥ 0, as the second-order cone ‖(2u, a − b)‖ ≤ a + b.
fn rotated_cone(conic: &mut Conic, a: &Scalar, b: &Scalar, u: usize) {
    let comb = |sa: f64, sb: f64| -> Scalar {
        let mut t: Vec<(usize, f64)> = a.1.iter().map(|(k, c)| (*k, sa * c)).collect();
        t.extend(b.1.iter().map(|(k, c)| (*k, sb * c)));
        (sa * a.0 + sb * b.0, t)
    };
    conic.second_order(vec![comb(1.0, 1.0), (0.0, vec![(u, 2.0)]), comb(1.0, -1.0)]);
}
