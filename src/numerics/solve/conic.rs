//! A small builder for clarabel conic programs: constraints are added as blocks
//! `c + Σ_k x_k M_k ∈ cone` and the program minimizes costᵀx. Symmetric matrix constraints use
//! clarabel's PSD triangle cone: the upper triangle in column-major order with off-diagonal entries
//! scaled by √2, so that ⟨svec A, svec B⟩ = ⟨A, B⟩.

use std::collections::BTreeMap;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

use crate::numerics::linalg::Mat;

unsafe extern "C" {
    /// OpenBLAS's own switch (openblas_config.h); the symbol is in every OpenBLAS build that
    /// `openblas-src` links, threaded or not.
    fn openblas_set_num_threads(num_threads: std::ffi::c_int);
}

/// Makes OpenBLAS run every call on the calling thread, once per process, and stops the pool of
/// worker threads it started when the library was loaded. Designs already run in parallel on
/// rayon's workers; an OpenBLAS pool per call on top of them oversubscribes the cores
/// (aniso_dropout: 17 s of system time and 405 000 involuntary context switches for the same
/// numbers). Its idle workers also spin with `sched_yield` for about 0.1 s after the library is
/// loaded, whether or not a BLAS call ever comes: on a 2-core Zen 4 that took 2–6 % of
/// `filterbench bench`'s throughput, on a 2-core Zen 2 less than that machine's noise
/// (docs/architecture.md, "OpenBLAS's idle pool"), so the binary calls this first thing. `blas_thread_shutdown_` is looked up at run time because only OpenBLAS's
/// threaded builds have it (a serial build has no pool to stop); with one thread set first, a later
/// call runs on its caller and never restarts the pool. Called here too, before the first clarabel
/// solve, so that library users get the same; neither depends on the user's OPENBLAS_NUM_THREADS.
pub fn single_threaded_blas() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // SAFETY: a plain setter of OpenBLAS's global thread count, called before any BLAS call of
        // ours; it takes no pointers.
        unsafe { openblas_set_num_threads(1) };
        // SAFETY: dlsym with RTLD_DEFAULT and a NUL-terminated name only reads the name.
        let stop = unsafe { libc::dlsym(libc::RTLD_DEFAULT, c"blas_thread_shutdown_".as_ptr()) };
        if !stop.is_null() {
            // SAFETY: OpenBLAS's `int blas_thread_shutdown_(void)` (driver/others/blas_server.c),
            // which joins its idle workers; no BLAS call of ours is running (this runs once, before
            // the first).
            let stop: unsafe extern "C" fn() -> std::ffi::c_int = unsafe { std::mem::transmute(stop) };
            unsafe { stop() };
        }
    });
}

/// A solved program.
#[derive(Clone, Debug)]
pub(crate) struct Solution {
    pub x: Vec<f64>,
    /// The dual point, row by row as the constraints were added (certified bounds use it).
    pub z: Vec<f64>,
    pub iterations: u32,
    pub seconds: f64,
    /// clarabel stopped at its reduced tolerances (AlmostSolved): the caller checks the result.
    pub almost: bool,
    /// A first-order bound on |costᵀx − the program's optimum|: the duality gap |cᵀx − dual
    /// objective| plus |zᵀr_p| and |xᵀr_d|, the primal and dual residuals of the returned point
    /// weighted by the other side's variables (`numerics::accuracy`'s module docs). What a comparison with another route allows the
    /// solver.
    pub objective_error: f64,
    /// The dual objective clarabel reports (a lower bound on a minimum when the dual is feasible).
    pub dual_objective: f64,
    /// The larger of clarabel's relative primal and dual residuals.
    pub residual: f64,
}

/// Why a program was not solved: the solver and its status (printed as is), and whether it is a certificate that the
/// program is infeasible (as opposed to a numerical failure: the solver could not finish).
#[derive(Clone, Debug)]
pub struct Failure {
    pub status: String,
    pub infeasible: bool,
}

impl std::fmt::Display for Failure {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.status)
    }
}

/// Which interior-point method solves a program: clarabel (every shipped design), or the
/// project's own ([`super::interior`]: Nesterov–Todd scaling and sparse normal equations, faster on
/// seed 003's chains; a filter's `solver = "own"`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Solver {
    #[default]
    Clarabel,
    Own,
}

impl Solver {
    pub fn name(self) -> &'static str {
        match self {
            Solver::Clarabel => "clarabel",
            Solver::Own => "own",
        }
    }
}

/// The clarabel settings of one attempt. [`Tuning::default`] is what every program is first solved
/// with; [`Tuning::robust`] is the retry after a numerical failure: more equilibration passes over a
/// wider range (the blocks of a long-horizon SDP differ by orders of magnitude), stronger static
/// regularization and more iterative refinement for the ill-conditioned KKT systems near the
/// optimum, and tolerances of 1e-8 (what a design needs; its result is checked anyway).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tuning {
    /// The method; the settings below are clarabel's and the own method ignores them.
    pub solver: Solver,
    pub tolerance: f64,
    pub equilibrate_iter: u32,
    pub equilibrate_range: f64,
    pub static_regularization: f64,
    pub refinement_iter: u32,
    pub max_iter: u32,
}

impl Default for Tuning {
    fn default() -> Self {
        Tuning {
            solver: Solver::Clarabel,
            tolerance: 1e-10,
            equilibrate_iter: 10,
            equilibrate_range: 1e4,
            static_regularization: 1e-8,
            refinement_iter: 10,
            max_iter: 500,
        }
    }
}

impl Tuning {
    /// The project's own method ([`Solver::Own`]).
    pub fn own() -> Self {
        Tuning { solver: Solver::Own, ..Tuning::default() }
    }
    pub fn robust() -> Self {
        Tuning {
            solver: Solver::Clarabel,
            tolerance: 1e-8,
            equilibrate_iter: 50,
            equilibrate_range: 1e6,
            static_regularization: 1e-7,
            refinement_iter: 50,
            max_iter: 1000,
        }
    }
}

/// clarabel's default reduced relative gap tolerance (`reduced_tol_gap_rel`), what its
/// AlmostSolved status promises of the objective.
pub(crate) const ALMOST_GAP_REL: f64 = 5e-5;

#[derive(Default, Clone)]
pub(crate) struct Conic {
    rows: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
}

impl Conic {
    /// One row of the slack s = b − A x, written as the affine value constant + Σ coef·x.
    fn push_row(&mut self, constant: f64, terms: impl IntoIterator<Item = (usize, f64)>) {
        let r = self.b.len();
        self.b.push(constant);
        for (k, c) in terms {
            if c != 0.0 {
                self.rows.push(r);
                self.cols.push(k);
                self.vals.push(-c);
            }
        }
    }

    /// constant + Σ coef·x ≥ 0, one row per entry.
    pub(crate) fn nonnegative(&mut self, rows: Vec<(f64, Vec<(usize, f64)>)>) {
        let n = rows.len();
        for (c, t) in rows {
            self.push_row(c, t);
        }
        self.cones.push(SupportedConeT::NonnegativeConeT(n));
    }

    /// (constant_i + Σ coef·x)_i in the second-order cone (first entry ≥ norm of the rest).
    pub(crate) fn second_order(&mut self, rows: Vec<(f64, Vec<(usize, f64)>)>) {
        let n = rows.len();
        for (c, t) in rows {
            self.push_row(c, t);
        }
        self.cones.push(SupportedConeT::SecondOrderConeT(n));
    }

    /// c + Σ_k x_k M_k ⪰ 0 for symmetric m×m matrices.
    pub fn psd(&mut self, c: &Mat, terms: &[(usize, Mat)]) {
        let m = c.nrows();
        for j in 0..m {
            for i in 0..=j {
                let s = if i == j { 1.0 } else { std::f64::consts::SQRT_2 };
                self.push_row(s * c[(i, j)], terms.iter().map(|(k, mk)| (*k, s * mk[(i, j)])));
            }
        }
        self.cones.push(SupportedConeT::PSDTriangleConeT(m));
    }

    /// The program's size: constraint rows, and the cones as (kind, size) counts.
    pub fn size(&self) -> (usize, BTreeMap<String, usize>) {
        let mut cones = BTreeMap::new();
        for c in &self.cones {
            let key = match c {
                SupportedConeT::NonnegativeConeT(n) => format!("nonnegative({n})"),
                SupportedConeT::SecondOrderConeT(n) => format!("second_order({n})"),
                SupportedConeT::PSDTriangleConeT(n) => format!("psd({n}x{n})"),
                other => format!("{other:?}"),
            };
            *cones.entry(key).or_insert(0) += 1;
        }
        (self.b.len(), cones)
    }

    /// The first-order effects of the solver's residuals on its objective: zᵀr_p with the primal
    /// residual r_p = Ax + s − b (the slack is s = b − Ax in the rows as written), and xᵀr_d with
    /// the dual residual r_d = Aᵀz + cost (clarabel's stationarity Aᵀz + q = 0 with P = 0): the
    /// point is optimal for a program moved by r_p in b and by r_d in the cost, whose optimum
    /// differs from this one's by about zᵀr_p and xᵀr_d.
    fn residual_dots(&self, cost: &[f64], x: &[f64], s: &[f64], z: &[f64]) -> [f64; 2] {
        let mut rp: Vec<f64> = s.iter().zip(&self.b).map(|(s, b)| s - b).collect();
        let mut rd: Vec<f64> = cost.to_vec();
        for ((&i, &j), &v) in self.rows.iter().zip(&self.cols).zip(&self.vals) {
            rp[i] += v * x[j];
            rd[j] += v * z[i];
        }
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(a, b)| a * b).sum::<f64>();
        [dot(&rp, z), dot(&rd, x)]
    }

    /// `Solution::objective_error` of a point (x, s, z) with primal and dual objectives: the
    /// duality gap plus the first-order effects of the residuals ([`Self::residual_dots`]). A point
    /// that stopped short of the tolerances (clarabel's AlmostSolved, the own method's slow tail)
    /// is vouched for only to clarabel's reduced gap tolerance, and the first-order estimate is not
    /// to be trusted alone near such a point.
    fn objective_error(&self, cost: &[f64], objectives: [f64; 2], [x, s, z]: [&[f64]; 3], almost: bool) -> f64 {
        let first_order = (objectives[0] - objectives[1]).abs()
            + self.residual_dots(cost, x, s, z).iter().map(|v| v.abs()).sum::<f64>();
        if almost { first_order.max(ALMOST_GAP_REL * objectives[0].abs().max(1.0)) } else { first_order }
    }

    /// Minimizes costᵀx; anything but an (almost) solved status is an error naming it.
    pub(crate) fn minimize(self, cost: &[f64]) -> Result<Solution, String> {
        self.minimize_tuned(cost, &Tuning::default()).map_err(|f| f.to_string())
    }

    /// Minimizes costᵀx with the project's own interior-point method ([`super::interior`]). Its
    /// `objective_error` is the same first-order bound as clarabel's; a point that stalled short of
    /// the method's tolerances (`almost`) is held to clarabel's AlmostSolved gap as well. It has no
    /// infeasibility certificates: every failure is a numerical one.
    fn minimize_own(&self, cost: &[f64]) -> Result<Solution, Failure> {
        let start = std::time::Instant::now();
        let program = super::interior::Program {
            rows: &self.rows,
            cols: &self.cols,
            vals: &self.vals,
            b: &self.b,
            cones: &self.cones,
        };
        let out = super::interior::solve(&program, cost).map_err(|why| Failure {
            status: format!("the own interior-point method failed: {why}"),
            infeasible: false,
        })?;
        Ok(Solution {
            objective_error: self.objective_error(
                cost,
                [out.primal_objective, out.dual_objective],
                [&out.x, &out.s, &out.z],
                out.almost,
            ),
            x: out.x,
            z: out.z,
            iterations: out.iterations,
            seconds: start.elapsed().as_secs_f64(),
            almost: out.almost,
            dual_objective: out.dual_objective,
            residual: out.measure,
        })
    }

    /// Minimizes costᵀx with the given settings; a failure says whether it is infeasibility.
    pub(crate) fn minimize_tuned(&self, cost: &[f64], tuning: &Tuning) -> Result<Solution, Failure> {
        if tuning.solver == Solver::Own {
            return self.minimize_own(cost);
        }
        single_threaded_blas();
        let nvar = cost.len();
        let a =
            CscMatrix::new_from_triplets(self.b.len(), nvar, self.rows.clone(), self.cols.clone(), self.vals.clone());
        let p = CscMatrix::zeros((nvar, nvar));
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_gap_abs(tuning.tolerance)
            .tol_gap_rel(tuning.tolerance)
            .tol_feas(tuning.tolerance)
            .max_iter(tuning.max_iter)
            .max_threads(1)
            .equilibrate_max_iter(tuning.equilibrate_iter)
            .equilibrate_min_scaling(1.0 / tuning.equilibrate_range)
            .equilibrate_max_scaling(tuning.equilibrate_range)
            .static_regularization_constant(tuning.static_regularization)
            .iterative_refinement_max_iter(tuning.refinement_iter)
            .build()
            .map_err(|e| Failure { status: format!("clarabel settings error {e}"), infeasible: false })?;
        let mut solver = DefaultSolver::new(&p, cost, &a, &self.b, &self.cones, settings)
            .map_err(|e| Failure { status: format!("clarabel setup error {e:?}"), infeasible: false })?;
        solver.solve();
        let sol = &solver.solution;
        match sol.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => Ok(Solution {
                x: sol.x.clone(),
                z: sol.z.clone(),
                iterations: sol.iterations,
                seconds: sol.solve_time,
                almost: sol.status == SolverStatus::AlmostSolved,
                objective_error: self.objective_error(
                    cost,
                    [sol.obj_val, sol.obj_val_dual],
                    [&sol.x, &sol.s, &sol.z],
                    sol.status == SolverStatus::AlmostSolved,
                ),
                dual_objective: sol.obj_val_dual,
                residual: sol.r_prim.max(sol.r_dual),
            }),
            s => Err(Failure {
                status: format!("clarabel status {s:?}"),
                infeasible: matches!(
                    s,
                    SolverStatus::PrimalInfeasible
                        | SolverStatus::DualInfeasible
                        | SolverStatus::AlmostPrimalInfeasible
                        | SolverStatus::AlmostDualInfeasible
                ),
            }),
        }
    }
}
