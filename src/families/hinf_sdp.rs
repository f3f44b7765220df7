//! The design form of seed 002's SDP (4.7) (docs/seed002_notes.md): H∞-λ predictors
//! s\[t+1] = A s + Θ\[t](y − C s) from one semidefinite program instead of the Riccati recursion
//! (5.9)–(5.10). With the change of variables Z\[t] = X\[t+1] Θ\[t] the analysis LMI of (4.7) becomes,
//! by a Schur complement on X\[t+1] (the Bc = B − ΘD term as X⁺B − ZD), linear in (X, Z, λ):
//!
//! ```text
//! [[−X[t], 0, Czᵀ, (X⁺A − ZC)ᵀ], [0, −I, 0, (X⁺BL − ZDL)ᵀ], [Cz, 0, −λI, 0],
//!  [X⁺A − ZC, X⁺BL − ZDL, 0, −X⁺]] ⪯ 0,  t = 0..N−1,   X[0] = R⁻¹,
//! [[X[N], S^½], [S^½ᵀ, λI]] ⪰ 0,
//! ```
//!
//! where G = L Lᵀ (the weight of w written as w = L u, |w|²_G = |u|², which also covers a singular
//! G). Θ\[t] = X\[t+1]⁻¹ Z\[t]. eᵀX\[t]e is a storage function of the error system: summing the
//! dissipation inequalities gives Σ|e_z|² + e\[N]ᵀSe\[N] ≤ λ(|e0|²_R + Σ|w|²_G).
//!
//! Minimizing λ gives λ_min in one program. At a fixed λ > λ_min many (X, Z) are feasible; which
//! filter is returned is the objective's choice, see [`Choice`](crate::families::hinf_sdp::Choice).

use crate::error::{Error, Result};
use crate::model::plant::{Covariances, Plant};
use crate::numerics::linalg::{Mat, psd_factor};
use crate::numerics::solve::affine::{AffMat, Vars};
use crate::numerics::solve::conic::{Conic, Failure, Solution, Tuning};

/// Which feasible filter the SDP at a fixed λ returns.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Choice {
    /// Maximize Σ_t tr X\[t]. Given X\[t], the largest X\[t+1] allowed by the LMI is attained by the
    /// completed square of seed 002 l.1368–1376 at Θ∞ and equals P∞\[t+1]⁻¹, so the maximizer is the
    /// Riccati's central filter (5.9)–(5.10), reached through the SDP: a cross-check.
    Central,
    /// Minimize Σ_t tr X\[t]: the storage eᵀX\[t]e pushed down to the worst-case cost-to-go
    /// (backward dissipation from X\[N] = S/λ), so the gains make the worst future error from every
    /// error state small, while the whole-horizon guarantee at λ still holds. A non-central filter
    /// that plays for the future where the central one accounts for the past; it needs S ≻ 0
    /// (with S = 0, X\[N] = 0 and the last gain is not determined). Pushing the storage down makes
    /// every dissipation inequality tight, so its norm² is λ itself, not below it: it is designed
    /// at λ (1 − `STRICT`) so that the solver's residuals cannot carry it over λ.
    MinStorage,
}

/// The relative amount by which the min-storage filter's λ is tightened: 10× clarabel's loosest
/// tolerance (1e-8, the robust retry); its norm² lands at λ − O(1e-10) otherwise.
pub(crate) const STRICT: f64 = 1e-7;

/// A solved design SDP.
#[derive(Clone, Debug)]
pub struct SdpDesign {
    /// λ at the solution (the optimum when λ was minimized, else the given λ).
    pub lambda: f64,
    /// Θ\[t] for t = 0..N; Θ\[N] moves s\[N+1], past the horizon, and is zero.
    pub gains: Vec<Mat>,
    /// X\[0..N] at the solution.
    pub storage: Vec<Mat>,
    /// clarabel's first-order bound on |costᵀx − optimum| (`Solution::objective_error`): for
    /// [`minimize_lambda`], how far λ may be from λ_min on the solver's side.
    pub objective_error: f64,
    pub iterations: u32,
    pub seconds: f64,
    /// Scalar variables, PSD blocks (their sizes).
    pub variables: usize,
    pub blocks: Vec<usize>,
}

/// The program: the LMIs above with λ a variable (`lambda = None`) or fixed.
struct Program {
    conic: Conic,
    vars: usize,
    lambda: Option<usize>,
    x: Vec<AffMat>,
    z: Vec<AffMat>,
    blocks: Vec<usize>,
}

fn build(plant: &Plant, weights: &Covariances, s: &Mat, lambda: Option<f64>) -> Result<Program> {
    let (n, ny, nw, nz, nn) = (plant.nx(), plant.ny(), plant.nw(), plant.nz(), plant.horizon);
    let r_inv = weights.x0().clone().try_inverse().ok_or_else(|| Error::invalid("hinf", "R must be invertible"))?;
    let l = psd_factor(&weights.w());
    let s_half = psd_factor(s).transpose();
    let mut vars = Vars::default();
    let lam_var = lambda.is_none().then(|| vars.scalar());
    let lam_times = |k: usize| match (lam_var, lambda) {
        (Some(v), _) => AffMat::scalar_times(v, Mat::identity(k, k)),
        (None, Some(l)) => AffMat::constant(Mat::identity(k, k) * l),
        (None, None) => unreachable!("λ is a variable or given"),
    };
    let mut x = vec![AffMat::constant(r_inv)];
    x.extend((0..nn).map(|_| vars.symmetric(n)));
    // Before the first measurement C = D = 0: Θ is fixed at zero there, so Z is too.
    let z: Vec<AffMat> =
        (0..nn).map(|t| if plant.measured(t) { vars.matrix(n, ny, false) } else { AffMat::zeros(n, ny) }).collect();
    let mut conic = Conic::default();
    let mut blocks = Vec::new();
    let sizes = [n, nw, nz, n];
    for t in 0..nn {
        let (c, d) = (&*plant.c_at(t), &*plant.d_at(t));
        let xa = x[t + 1].rmul(plant.a_at(t)).sub(&z[t].rmul(c));
        let xb = x[t + 1].rmul(&(plant.b_at(t) * &l)).sub(&z[t].rmul(&(d * &l)));
        // −(the LMI) ⪰ 0, lower blocks.
        let lower = vec![
            vec![Some(x[t].clone())],
            vec![None, Some(AffMat::constant(Mat::identity(nw, nw)))],
            vec![Some(AffMat::constant(-plant.cz_at(t))), None, Some(lam_times(nz))],
            vec![Some(xa.scale(-1.0)), Some(xb.scale(-1.0)), None, Some(x[t + 1].clone())],
        ];
        AffMat::symmetric_blocks(&sizes, &lower).psd_into(&mut conic);
        blocks.push(sizes.iter().sum());
    }
    let lower = vec![vec![Some(x[nn].clone())], vec![Some(AffMat::constant(s_half)), Some(lam_times(n))]];
    AffMat::symmetric_blocks(&[n, n], &lower).psd_into(&mut conic);
    blocks.push(2 * n);
    Ok(Program { conic, vars: vars.count, lambda: lam_var, x, z, blocks })
}

/// Solves with clarabel's default settings, then once more with [`Tuning::robust`] after a
/// numerical failure; an infeasibility certificate is final.
fn solve(conic: &Conic, cost: &[f64]) -> std::result::Result<Solution, Failure> {
    match conic.minimize_tuned(cost, &Tuning::default()) {
        Err(f) if !f.infeasible => conic.minimize_tuned(cost, &Tuning::robust()),
        other => other,
    }
}

fn finish(p: &Program, plant: &Plant, sol: &Solution, lambda: f64) -> Result<SdpDesign> {
    let storage: Vec<Mat> = p.x.iter().map(|x| crate::numerics::linalg::symmetrize(&x.value(&sol.x))).collect();
    let mut gains = Vec::with_capacity(plant.steps());
    for (t, z) in p.z.iter().enumerate() {
        let chol = nalgebra::Cholesky::new(storage[t + 1].clone()).ok_or_else(|| {
            Error::invalid(
                "hinf",
                format!("the SDP (4.7) gave a singular X[{}]: the gain Θ = X⁻¹Z is not defined", t + 1),
            )
        })?;
        gains.push(chol.solve(&z.value(&sol.x)));
    }
    gains.push(Mat::zeros(plant.nx(), plant.ny()));
    Ok(SdpDesign {
        lambda,
        gains,
        storage,
        objective_error: sol.objective_error,
        iterations: sol.iterations,
        seconds: sol.seconds,
        variables: p.vars,
        blocks: p.blocks.clone(),
    })
}

/// λ_min of seed 002 §5 directly: minimize λ subject to the design LMIs of (4.7). The gains are
/// the SDP's own filter at λ_min (its norm² is λ_min up to the solver's tolerance).
pub fn minimize_lambda(plant: &Plant, weights: &Covariances, s: &Mat) -> Result<SdpDesign> {
    let p = build(plant, weights, s, None)?;
    let lam = p.lambda.expect("λ is a variable");
    let mut cost = vec![0.0; p.vars];
    cost[lam] = 1.0;
    let sol = solve(&p.conic, &cost)
        .map_err(|f| Error::invalid("hinf", format!("the design SDP (4.7) for λ_min was not solved: {f}")))?;
    finish(&p, plant, &sol, sol.x[lam])
}

/// A filter with norm² ≤ λ from the design LMIs of (4.7) at the given λ, chosen by `choice`.
/// An infeasible program means λ < λ_min.
pub fn design_at(plant: &Plant, weights: &Covariances, s: &Mat, lambda: f64, choice: Choice) -> Result<SdpDesign> {
    if choice == Choice::MinStorage && crate::numerics::linalg::min_eigenvalue(s) <= 0.0 {
        return Err(Error::invalid(
            "hinf",
            "sdp_filter = \"min_storage\" needs a positive definite terminal_weight (with S singular X[N] is singular and the last gain is not determined)",
        ));
    }
    let strict = if choice == Choice::MinStorage { lambda * (1.0 - STRICT) } else { lambda };
    let p = build(plant, weights, s, Some(strict))?;
    let sign = if choice == Choice::Central { -1.0 } else { 1.0 };
    let mut cost = vec![0.0; p.vars];
    for x in &p.x[1..] {
        for (k, m) in &x.terms {
            cost[*k] += sign * m.trace();
        }
    }
    let sol = solve(&p.conic, &cost).map_err(|f| {
        let why = if f.infeasible { " (λ is below λ_min)" } else { "" };
        Error::invalid("hinf", format!("the design SDP (4.7) at λ = {lambda} was not solved: {f}{why}"))
    })?;
    finish(&p, plant, &sol, lambda)
}
