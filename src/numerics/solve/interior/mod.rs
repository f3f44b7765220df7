//! The project's own primal–dual interior-point method for the conic programs [`super::conic`]
//! builds (nonnegative, second-order and PSD-triangle cones), chosen per filter with
//! `solver = "own"` (docs/families.md, "The project's own interior-point method").
//!
//! The program is min cᵀx subject to s = b − Ax in K; its dual is max −bᵀz subject to Aᵀz + c = 0,
//! z in K. Each iteration takes the Nesterov–Todd scaling W of every cone (W z = W⁻ᵀ s = λ),
//! eliminates the slacks and solves the normal equations
//!
//! ```text
//! Aᵀ W⁻¹ W⁻ᵀ A Δx = −r_d − Aᵀ W⁻¹ (W⁻ᵀ r_p + u),
//! ```
//!
//! twice (Mehrotra's predictor and corrector; Vandenberghe, "The CVXOPT linear and quadratic cone
//! program solvers", 2010, §5–§8 for the scaling, the Jordan algebra and the step), from the
//! infeasible starting point of CVXOPT's `conelp` (the least-norm primal slack and dual point, each
//! shifted into the cones). What makes it cheaper than clarabel on seed 003's design
//! programs: a PSD block of the chain (4.42)–(4.43) touches only the variables of steps k and k + 1,
//! so the normal matrix is a band of about 40 variables with two dense rows (γ², η), factored by
//! QDLDL with its AMD ordering, and each entry tr(A_i M A_j M) is a sum over the two coefficient
//! matrices' few nonzeros; before that, every sparse PSD block is split into its cliques by
//! clarabel's own chordal decomposition (see `solve`), so the n³ work of a 16 × 16 block becomes
//! that of blocks of 10, 6 and 3. The cones' work (scalings, products, step lengths, the normal
//! matrix's terms) runs in parallel, a cone's result depending on its own rows only and every sum
//! over cones taken in a fixed order, so the result is the same bits on any number of threads; each
//! entry of the normal matrix sums its own terms, also in parallel, and the serial factorization
//! runs beside the predictor's right-hand side, which does not need it. The scalings are written
//! over the previous iteration's, so an iteration allocates nothing per cone. What
//! keeps it accurate: each normal-equations solve is finished by conjugate gradients on the operator
//! Aᵀ W⁻¹ W⁻ᵀ A itself, preconditioned by the factored matrix (one step or none where the
//! factorization is accurate; a few more near the optimum of a decomposed program, where the
//! matrix grows too ill-conditioned for plain iterative refinement to converge); the primal step is
//! Δs = −(AΔx + r_p) in the original coordinates (not Wᵀ of the scaled one), so the primal residual
//! falls as (1 − α) r_p however ill-conditioned W grows. No product goes through a kernel chosen by
//! the processor at run time (the small matrices are nalgebra's fixed-size ones or its dot-based
//! products, the blocks' sandwiches AVX2 without fused multiply–add), and no BLAS: the design does
//! not depend on the OpenBLAS kernel.
//!
//! Where it stops: at relative residuals and gap of 10⁻⁸ (`TOL`); or, on a slow linear tail
//! (degenerate programs — the H∞ designs, whose optimal filters are not unique), once they are
//! below 10⁻⁶ and five iterations gained less than a factor ten; or after five iterations without a
//! better point. A point short of `TOL` is returned only within clarabel's own AlmostSolved
//! thresholds, and marked so (its objective error is then held to clarabel's reduced gap, in
//! `conic`'s `minimize_own`); a decomposed program that ends otherwise is solved again as written,
//! and anything else is an error, on which the design falls back to clarabel. (The H2 designs,
//! a = 0, are solved as the LMIs' limit η → ∞, a program whose optimum is attained; written with a
//! finite η they ended on the slow tail.)
//!
//! Whatever this solver returns is checked as clarabel's designs are
//! (`families::anisotropic::synthesize_checked`): the exact norm of the filter and Theorem 1 with a
//! full P certify the printed bound; the solver's objective is never the guarantee alone.

use clarabel::algebra::CscMatrix;
use clarabel::qdldl::{QDLDLFactorisation, QDLDLSettingsBuilder};
use clarabel::solver::DefaultSettings;
use clarabel::solver::chordal::Decomposition;

use crate::numerics::linalg::Mat;

mod cone;
mod normal;
mod sandwich;

use cone::{
    Cone, Kind, Op, Scaling, Scratch, apply, dot, identity, jdiv, jprod, jsquare, max_step, norm, scaling, smat,
    step_bound,
};
pub(crate) use normal::Program;
use normal::{CONES_PER_TASK, Data, Normal, split_mut};
use rayon::prelude::*;

/// Stopping tolerance on the relative primal and dual residuals and the relative gap: what the
/// normal equations reach in double precision on the design programs (`aniso_dropout`'s a = 20
/// designs end at 7·10⁻¹⁰ from 10⁻⁸ in one iteration), well inside the 10⁻⁶ a design is checked to.
const TOL: f64 = 1e-8;
/// A point that stalls short of [`TOL`] is still returned when its relative residuals are below
/// the first and its relative gap below the second: clarabel's AlmostSolved thresholds
/// (`reduced_tol_feas`, `reduced_tol_gap_rel`), so that the two methods are held to one standard.
const ALMOST_FEAS: f64 = 1e-4;
const ALMOST_GAP: f64 = 5e-5;
const MAX_ITER: usize = 120;
/// Below this measure a slowly converging run stops (see the loop).
const SLOW: f64 = 1e-6;
/// The conjugate gradients of a normal-equations solve stop at this relative residual (or after
/// [`CG_STEPS`]). Two orders below [`TOL`]: a direction solved to 10⁻¹⁰ moves the iterate by far
/// less than the stopping test can see (the residuals it tests are recomputed from A, b and c at
/// every iteration, never carried over from a solve). At 10⁻¹² the a = 20 design's factored solves
/// (relative residuals 10⁻¹²–2·10⁻¹¹ from its twelfth iteration on) each took one more step, an
/// operator product and a solve (docs/families.md, "Where an iteration's time goes").
const REFINE: f64 = 1e-10;
/// At most this many conjugate-gradient steps per normal-equations solve.
const CG_STEPS: usize = 20;
/// The fraction of the step to the boundary taken.
const STEP: f64 = 0.99;

/// A solved program: the primal and dual points, and how well they solve it.
pub(crate) struct Outcome {
    pub x: Vec<f64>,
    pub s: Vec<f64>,
    pub z: Vec<f64>,
    pub iterations: u32,
    pub primal_objective: f64,
    pub dual_objective: f64,
    /// The largest of the relative primal and dual residuals and the relative gap.
    pub measure: f64,
    /// The larger relative residual, and the relative gap.
    feasibility: f64,
    gap: f64,
    /// Stopped short of [`TOL`] (a stall), but within [`ALMOST_FEAS`] and [`ALMOST_GAP`].
    pub almost: bool,
}

/// Per-cone work on whole vectors.
fn each(d: &Data, f: impl FnMut(&Cone, std::ops::Range<usize>)) {
    let mut f = f;
    for c in &d.cones {
        f(c, c.rows.clone());
    }
}

/// The cones' parts of a whole vector (the cones cover its rows in order), for per-cone work in
/// parallel: each cone's result depends on its own rows only, so the bits do not depend on the
/// thread count.
fn parts<'a>(d: &Data, v: &'a mut [f64]) -> Vec<&'a mut [f64]> {
    split_mut(v, d.cones.iter().map(|c| c.rows.len()))
}

fn apply_all(d: &Data, sc: &[Scaling], op: Op, v: &[f64], out: &mut [f64]) {
    d.cones
        .par_iter()
        .zip(sc)
        .zip(parts(d, out))
        .with_min_len(CONES_PER_TASK)
        .for_each_init(|| Scratch::new(d.largest), |w, ((c, s), o)| apply(s, op, &v[c.rows.clone()], o, w));
}

/// Aᵀ W⁻¹ W⁻ᵀ A v through the operator (q1, q2: scratch of the rows' length).
fn normal_op(d: &Data, sc: &[Scaling], v: &[f64], out: &mut [f64], q1: &mut [f64], q2: &mut [f64]) {
    d.ax(v, q1);
    apply_all(d, sc, Op::Normal, q1, q2);
    d.atz(q2, out);
}

/// The normal equations' right-hand side for the scaled complementarity term u,
/// −r_d − Aᵀ W⁻¹ (W⁻ᵀ r_p + u), into `rhs`, given W⁻ᵀ r_p (`scaled_rz`) and r_d (`rx`).
fn right_side(
    d: &Data,
    sc: &[Scaling],
    u: &[f64],
    scaled_rz: &[f64],
    rx: &[f64],
    (q1, q2, t): (&mut [f64], &mut [f64], &mut [f64]),
    rhs: &mut [f64],
) {
    q1.iter_mut().zip(u.iter().zip(scaled_rz)).for_each(|(w, (u, r))| *w = r + u);
    apply_all(d, sc, Op::Inverse, q1, q2);
    d.atz(q2, t);
    for i in 0..rhs.len() {
        rhs[i] = -rx[i] - t[i];
    }
}

/// Shifts v into the cone's interior (the initial point's last step): v + (1 + t) e where t is
/// the most negative eigenvalue, if v is not interior already.
fn shift_inside(d: &Data, v: &mut [f64]) {
    let mut worst = f64::INFINITY;
    each(d, |c, r| {
        let x = &v[r];
        let e = match c.kind {
            Kind::Nonnegative => x.iter().copied().fold(f64::INFINITY, f64::min),
            Kind::SecondOrder => x[0] - norm(&x[1..]),
            Kind::Psd(n) => {
                let mut m = Mat::zeros(n, n);
                smat(x, n, &mut m);
                m.symmetric_eigenvalues().min()
            }
        };
        worst = worst.min(e);
    });
    if worst < 1e-8 {
        let mut e = vec![0.0; v.len()];
        each(d, |c, r| identity(c.kind, &mut e[r]));
        v.iter_mut().zip(&e).for_each(|(v, e)| *v += (1.0 - worst) * e);
    }
}

/// Solves min costᵀx subject to b − Ax in the cones; an error names why it could not.
///
/// A program whose PSD cones are sparse is first split by clarabel's own chordal decomposition
/// (`clarabel::solver::chordal::Decomposition`; Kim, Kojima, Mevissen and Yamashita 2011, the
/// compact form), the cliques merged parent into child where that pays, solved, and taken back, the
/// dual completed to PSD matrices. On seed 003's programs each 16 × 16 block of (4.42)–(4.43) is
/// then blocks of 10, 6 and 3 (a fifth of the n³ work per block) for 800 more variables at N = 200.
/// The parent–child merge, not clarabel's default clique-graph merge: the latter keeps more,
/// smaller cliques and twice the variables, which suits clarabel's KKT system and not the
/// normal equations here (`aniso_dropout`'s a = 20 design at p = 0.97: 0.33 s against 0.43 s).
pub(crate) fn solve(p: &Program, cost: &[f64]) -> Result<Outcome, String> {
    let a = CscMatrix::new_from_triplets(p.b.len(), cost.len(), p.rows.to_vec(), p.cols.to_vec(), p.vals.to_vec());
    let settings = DefaultSettings { chordal_decomposition_merge_method: "parent_child".into(), ..Default::default() };
    let Some(dec) = Decomposition::new(&a, p.b, p.cones, settings) else {
        return solve_program(p, cost);
    };
    let (mut rows, mut cols) = (Vec::with_capacity(dec.a.nnz()), Vec::with_capacity(dec.a.nnz()));
    for j in 0..dec.a.n {
        for k in dec.a.colptr[j]..dec.a.colptr[j + 1] {
            rows.push(dec.a.rowval[k]);
            cols.push(j);
        }
    }
    let mut extended = cost.to_vec();
    extended.resize(cost.len() + dec.added, 0.0);
    let split = Program { rows: &rows, cols: &cols, vals: &dec.a.nzval, b: &dec.b, cones: &dec.cones };
    match solve_program(&split, &extended) {
        Ok(mut out) => {
            (out.x, out.s, out.z) = dec.reverse(&out.x, &out.s, &out.z);
            out.dual_objective = -dot(p.b, &out.z);
            Ok(out)
        }
        // The decomposed program is the same optimum in other coordinates, and on a degenerate
        // program (one whose optimum is not attained, as the H2 designs' were when written with
        // a finite η) its slow tail can stall where the program as written does not.
        Err(why) => solve_program(p, cost).map_err(|again| format!("{why}; as written: {again}")),
    }
}

/// [`solve`] on a program as given.
fn solve_program(p: &Program, cost: &[f64]) -> Result<Outcome, String> {
    let d = Data::new(p, cost.len())?;
    let (m, n) = (d.m, d.n);
    let normal = Normal::new(&d);
    let mut hv = vec![0.0; normal.rowval.len()];
    let mut terms = vec![0.0; normal.terms()];
    // Each iteration writes the cones' scalings over these.
    let mut sc: Vec<Scaling> = d
        .cones
        .iter()
        .map(|c| match c.kind {
            Kind::Nonnegative => Scaling::Nonnegative(vec![1.0; c.rows.len()]),
            Kind::SecondOrder => Scaling::SecondOrder(Mat::identity(c.rows.len(), c.rows.len())),
            Kind::Psd(k) => {
                Scaling::Psd { rinv: Mat::identity(k, k), rinv_t: Mat::identity(k, k), m: Mat::identity(k, k) }
            }
        })
        .collect();
    normal.assemble(&d, &sc, &mut terms, &mut hv);
    let h = CscMatrix::new(n, n, normal.colptr.clone(), normal.rowval.clone(), hv.clone());
    let settings = QDLDLSettingsBuilder::default().regularize_enable(false).build().map_err(|e| e.to_string())?;
    let mut fact = QDLDLFactorisation::new(&h, Some(settings)).map_err(|e| format!("the normal matrix: {e:?}"))?;
    let every: Vec<usize> = (0..hv.len()).collect();

    // Initial point (CVXOPT's `conelp` without a given start): the least-norm slack, AᵀA x = Aᵀb
    // and s = b − Ax, and the least-norm dual point, AᵀA y = −c and z = Ay (so that Aᵀz + c = 0),
    // each then shifted into its cone's interior: two solves with the one factorization. `coneqp`'s
    // single system, AᵀA x = Aᵀb − c with z = −s, took 208 iterations over `aniso_dropout`'s nine
    // designs against 201 (docs/families.md, "Where an iteration's time goes").
    let mut x = vec![0.0; n];
    d.atz(p.b, &mut x);
    fact.solve(&mut x);
    let mut s = vec![0.0; m];
    d.ax(&x, &mut s);
    s.iter_mut().zip(p.b).for_each(|(s, b)| *s = b - *s);
    let mut y: Vec<f64> = cost.iter().map(|c| -c).collect();
    fact.solve(&mut y);
    let mut z = vec![0.0; m];
    d.ax(&y, &mut z);
    shift_inside(&d, &mut s);
    shift_inside(&d, &mut z);

    let mut e = vec![0.0; m];
    each(&d, |c, r| identity(c.kind, &mut e[r]));
    let (bn, cn) = (norm(p.b).max(1.0), norm(cost).max(1.0));
    let (mut lam, mut rz, mut w1, mut w2, mut u) =
        (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    let (mut dsa, mut dza, mut ds, mut dz) = (vec![0.0; m], vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    let (mut rx, mut dx, mut t, mut rhs) = (vec![0.0; n], vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let (mut q1, mut q2, mut scaled_rz) = (vec![0.0; m], vec![0.0; m], vec![0.0; m]);
    let (mut cg_r, mut cg_z, mut cg_p) = (vec![0.0; n], vec![0.0; n], vec![0.0; n]);
    let widest = d.cones.iter().map(|c| c.rows.len()).max().unwrap_or(0);
    let mut best: Option<Outcome> = None;
    let mut since_best = 0;
    let mut history = Vec::new();
    for it in 0..MAX_ITER {
        let inside = d
            .cones
            .par_iter()
            .zip(sc.par_iter_mut())
            .zip(parts(&d, &mut lam))
            .with_min_len(CONES_PER_TASK)
            .all(|((c, w), l)| scaling(&s[c.rows.clone()], &z[c.rows.clone()], l, w));
        if !inside {
            return finish(best, "an iterate left the cone's interior numerically");
        }
        d.atz(&z, &mut rx);
        rx.iter_mut().zip(cost).for_each(|(r, c)| *r += c);
        d.ax(&x, &mut rz);
        rz.iter_mut().zip(s.iter().zip(p.b)).for_each(|(r, (s, b))| *r += s - b);
        let gap = dot(&s, &z);
        let mu = gap / d.degree as f64;
        let (pcost, dcost) = (dot(cost, &x), -dot(p.b, &z));
        let feasibility = (norm(&rz) / bn).max(norm(&rx) / cn);
        let relgap = gap / pcost.abs().max(1.0);
        let measure = feasibility.max(relgap);
        if best.as_ref().is_none_or(|b| measure < b.measure) {
            // The best point's vectors are allocated once and overwritten.
            let b = best.get_or_insert_with(|| Outcome {
                x: vec![0.0; n],
                s: vec![0.0; m],
                z: vec![0.0; m],
                iterations: 0,
                primal_objective: 0.0,
                dual_objective: 0.0,
                measure: 0.0,
                feasibility: 0.0,
                gap: 0.0,
                almost: false,
            });
            b.x.copy_from_slice(&x);
            b.s.copy_from_slice(&s);
            b.z.copy_from_slice(&z);
            (b.iterations, b.primal_objective, b.dual_objective) = (it as u32, pcost, dcost);
            (b.measure, b.feasibility, b.gap, b.almost) = (measure, feasibility, relgap, measure > TOL);
            since_best = 0;
        } else {
            since_best += 1;
        }
        history.push(measure);
        // A slow tail (linear convergence: degenerate programs such as the H∞ designs, whose
        // optimal filters are not unique) ends once the point is good to SLOW and the last five
        // iterations gained less than a factor of ten; a stall ends after five without a better point.
        let slow = it >= 5 && measure > 0.1 * history[it - 5] && best.as_ref().is_some_and(|b| b.measure <= SLOW);
        if measure <= TOL || since_best >= 5 || slow {
            break;
        }
        normal.assemble(&d, &sc, &mut terms, &mut hv);
        // The factorization runs on one thread; the predictor's right-hand side, which does not
        // need it, is formed on the other meanwhile (the same operations either way).
        u.iter_mut().zip(&lam).for_each(|(u, l)| *u = -l);
        let (factored, ()) = rayon::join(
            || {
                fact.update_values(&every, &hv);
                fact.refactor()
            },
            || {
                apply_all(&d, &sc, Op::InvTranspose, &rz, &mut scaled_rz);
                let scratch = (&mut q1[..], &mut q2[..], &mut t[..]);
                right_side(&d, &sc, &u, &scaled_rz, &rx, scratch, &mut rhs);
            },
        );
        if factored.is_err() {
            return finish(best, "the normal matrix could not be factored");
        }
        // The Newton direction for the scaled complementarity right-hand side u (the predictor's
        // −λ, the corrector's λ⁻¹∘(…)): Δx, and the scaled Δs̃ = −W⁻ᵀ(AΔx + r_p), Δz̃ = u − Δs̃.
        // `rhs_ready`: `rhs` already holds u's right-hand side.
        let mut direction = |u: &[f64], rhs_ready: bool, dx: &mut [f64], dst: &mut [f64], dzt: &mut [f64]| {
            if !rhs_ready {
                right_side(&d, &sc, u, &scaled_rz, &rx, (&mut q1[..], &mut q2[..], &mut t[..]), &mut rhs);
            }
            dx.copy_from_slice(&rhs);
            fact.solve(dx);
            // Conjugate gradients on the operator itself, preconditioned by the factored matrix:
            // where the factorization is accurate one step or none; where the normal matrix has
            // grown too ill-conditioned for it (near the optimum of a decomposed program) plain
            // refinement stalls and CG still converges.
            let rn = norm(&rhs);
            normal_op(&d, &sc, dx, &mut t, &mut q1, &mut q2);
            cg_r.iter_mut().zip(rhs.iter().zip(&t)).for_each(|(r, (b, t))| *r = b - t);
            let mut res = norm(&cg_r);
            if res > REFINE * rn {
                cg_z.copy_from_slice(&cg_r);
                fact.solve(&mut cg_z);
                cg_p.copy_from_slice(&cg_z);
                let mut rz = dot(&cg_r, &cg_z);
                for _ in 0..CG_STEPS {
                    normal_op(&d, &sc, &cg_p, &mut t, &mut q1, &mut q2);
                    let pq = dot(&cg_p, &t);
                    if pq <= 0.0 || rz <= 0.0 {
                        break;
                    }
                    let a = rz / pq;
                    dx.iter_mut().zip(&cg_p).for_each(|(x, p)| *x += a * p);
                    cg_r.iter_mut().zip(&t).for_each(|(r, t)| *r -= a * t);
                    res = norm(&cg_r);
                    if res <= REFINE * rn {
                        break;
                    }
                    cg_z.copy_from_slice(&cg_r);
                    fact.solve(&mut cg_z);
                    let rz_next = dot(&cg_r, &cg_z);
                    let beta = rz_next / rz;
                    rz = rz_next;
                    cg_p.iter_mut().zip(&cg_z).for_each(|(p, z)| *p = z + beta * *p);
                }
            }
            d.ax(dx, &mut q1);
            apply_all(&d, &sc, Op::InvTranspose, &q1, &mut q2);
            for i in 0..m {
                let v = q2[i] + scaled_rz[i];
                dst[i] = -v;
                dzt[i] = v + u[i];
            }
        };
        // First a bound every cone's limit respects (exact for the small cones, the diagonal's for a
        // PSD block); then fixed runs of cones, each folded in order with its running minimum as
        // the cap, so that a block that cannot limit the step below it is done by a Cholesky test,
        // without eigenvalues. Neither depends on the thread count.
        let step_to_boundary = |ds: &[f64], dz: &[f64], cap: f64| {
            let over_runs = |cap: f64, f: fn(Kind, &[f64], &[f64], f64, &mut Scratch) -> f64| {
                d.cones
                    .par_chunks(CONES_PER_TASK)
                    .map_init(
                        || Scratch::new(d.largest),
                        |w, run| {
                            run.iter().fold(cap, |a, c| {
                                let r = c.rows.clone();
                                let a = f(c.kind, &lam[r.clone()], &ds[r.clone()], a, w);
                                f(c.kind, &lam[r.clone()], &dz[r], a, w)
                            })
                        },
                    )
                    .reduce(|| cap, f64::min)
            };
            over_runs(over_runs(cap, step_bound), max_step)
        };
        // Predictor (u = −λ, its right-hand side formed above).
        direction(&u, true, &mut dx, &mut dsa, &mut dza);
        let alpha = step_to_boundary(&dsa, &dza, 1.0);
        let predicted: f64 = (0..m).map(|i| (lam[i] + alpha * dsa[i]) * (lam[i] + alpha * dza[i])).sum();
        let sigma = (predicted / gap).clamp(0.0, 1.0).powi(3);
        // Corrector: λ∘(Δs̃ + Δz̃) = −λ∘λ − Δs̃ₐ∘Δz̃ₐ + σμe.
        d.cones.par_iter().zip(parts(&d, &mut u)).with_min_len(CONES_PER_TASK).for_each_init(
            || (Scratch::new(d.largest), vec![0.0; widest], vec![0.0; widest]),
            |(w, sq, ab), (c, out)| {
                let r = c.rows.clone();
                let (sq, ab) = (&mut sq[..r.len()], &mut ab[..r.len()]);
                jsquare(c.kind, &lam[r.clone()], sq, w);
                jprod(c.kind, &dsa[r.clone()], &dza[r.clone()], ab, w);
                for i in 0..r.len() {
                    sq[i] = -sq[i] - ab[i] + sigma * mu * e[r.start + i];
                }
                jdiv(c.kind, &lam[r], sq, out);
            },
        );
        direction(&u, false, &mut dx, &mut ds, &mut dz);
        let alpha = STEP * step_to_boundary(&ds, &dz, 1.0 / STEP);
        // Δs = −(AΔx + r_p) in the original coordinates, not Wᵀ Δs̃: the two agree in exact
        // arithmetic, but this keeps the primal residual falling as (1 − α) r_p however
        // ill-conditioned W grows near the optimum.
        d.ax(&dx, &mut w1);
        w1.iter_mut().zip(&rz).for_each(|(w, r)| *w = -(*w + r));
        apply_all(&d, &sc, Op::Inverse, &dz, &mut w2);
        x.iter_mut().zip(&dx).for_each(|(x, d)| *x += alpha * d);
        for i in 0..m {
            s[i] += alpha * w1[i];
            z[i] += alpha * w2[i];
        }
    }
    finish(best, "no progress")
}

/// The best point met, if it is within [`ALMOST_FEAS`] and [`ALMOST_GAP`]; else the reason and how
/// far it got.
fn finish(best: Option<Outcome>, why: &str) -> Result<Outcome, String> {
    match best {
        Some(b) if b.feasibility <= ALMOST_FEAS && b.gap <= ALMOST_GAP => Ok(b),
        Some(b) => Err(format!(
            "{why}; the best point's relative residual was {:.1e} and its relative gap {:.1e}",
            b.feasibility, b.gap
        )),
        None => Err(why.to_string()),
    }
}
