//! A small builder for clarabel conic programs: constraints are added as blocks
//! `c + Σ_k x_k M_k ∈ cone` and the program minimizes costᵀx. Symmetric matrix constraints use
//! clarabel's PSD triangle cone: the upper triangle in column-major order with off-diagonal entries
//! scaled by √2, so that ⟨svec A, svec B⟩ = ⟨A, B⟩.

use std::collections::BTreeMap;

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

use crate::linalg::Mat;

/// A solved program.
#[derive(Clone, Debug)]
pub struct Solution {
    pub x: Vec<f64>,
    pub iterations: u32,
    pub seconds: f64,
}

#[derive(Default)]
pub struct Conic {
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
    pub fn nonnegative(&mut self, rows: Vec<(f64, Vec<(usize, f64)>)>) {
        let n = rows.len();
        for (c, t) in rows {
            self.push_row(c, t);
        }
        self.cones.push(SupportedConeT::NonnegativeConeT(n));
    }

    /// (constant_i + Σ coef·x)_i in the second-order cone (first entry ≥ norm of the rest).
    pub fn second_order(&mut self, rows: Vec<(f64, Vec<(usize, f64)>)>) {
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

    /// Minimizes costᵀx; anything but an (almost) solved status is an error naming it.
    pub fn minimize(self, cost: &[f64]) -> Result<Solution, String> {
        let nvar = cost.len();
        let a = CscMatrix::new_from_triplets(self.b.len(), nvar, self.rows, self.cols, self.vals);
        let p = CscMatrix::zeros((nvar, nvar));
        let settings = DefaultSettingsBuilder::default()
            .verbose(false)
            .tol_gap_abs(1e-10)
            .tol_gap_rel(1e-10)
            .tol_feas(1e-10)
            .max_iter(500)
            .max_threads(1)
            .build()
            .map_err(|e| format!("clarabel settings: {e}"))?;
        let mut solver = DefaultSolver::new(&p, cost, &a, &self.b, &self.cones, settings)
            .map_err(|e| format!("clarabel setup: {e:?}"))?;
        solver.solve();
        let sol = &solver.solution;
        match sol.status {
            SolverStatus::Solved | SolverStatus::AlmostSolved => {
                Ok(Solution { x: sol.x.clone(), iterations: sol.iterations, seconds: sol.solve_time })
            }
            s => Err(format!("clarabel status {s:?}")),
        }
    }
}
