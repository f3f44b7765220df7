//! Linear maximization over sets of symmetric matrices with clarabel: the linear oracle of seed 000
//! Algorithm 1 step 3 when the set is not a plain box or ball (a Loewner interval, or any set
//! intersected with {S ⪰ 0}).
//!
//! Variables are the upper-triangle entries s_ij (i ≤ j) in clarabel's column-major order
//! (0,0), (0,1), (1,1), (0,2), …; a PSD constraint on M(S) is svec(M) in clarabel's PSD triangle
//! cone, with off-diagonal entries scaled by √2 so that ⟨svec A, svec B⟩ = ⟨A, B⟩.

use clarabel::algebra::CscMatrix;
use clarabel::solver::{DefaultSettingsBuilder, DefaultSolver, IPSolver, SolverStatus, SupportedConeT};

use crate::linalg::{Mat, symmetrize};

/// Constraints on a symmetric n×n matrix S; every one that is `Some` applies.
#[derive(Clone, Debug, Default)]
pub struct SymConstraints {
    /// Elementwise bounds lo ≤ S ≤ hi.
    pub bounds: Option<(Mat, Mat)>,
    /// Frobenius ball ‖S − center‖_F ≤ radius.
    pub ball: Option<(Mat, f64)>,
    /// S ⪰ lower (Loewner order); `Some(0)` is S ⪰ 0.
    pub lower: Option<Mat>,
    /// S ⪯ upper.
    pub upper: Option<Mat>,
    /// S ⪰ 0.
    pub psd: bool,
}

/// The maximizer of a linear function over a constrained set, as clarabel returned it.
#[derive(Clone, Debug)]
pub struct LinearMax {
    pub value: f64,
    pub argmax: Mat,
    pub iterations: u32,
    pub solve_seconds: f64,
}

/// max ⟨G, S⟩ over symmetric S subject to `cons`. An infeasible set or a solver failure is an
/// error that carries clarabel's status.
pub fn max_linear(g: &Mat, n: usize, cons: &SymConstraints) -> Result<LinearMax, String> {
    let idx: Vec<(usize, usize)> = (0..n).flat_map(|j| (0..=j).map(move |i| (i, j))).collect();
    let m = idx.len();
    let scale = |i: usize, j: usize| if i == j { 1.0 } else { std::f64::consts::SQRT_2 };
    let gs = symmetrize(g);
    let c: Vec<f64> = idx.iter().map(|&(i, j)| if i == j { -gs[(i, i)] } else { -2.0 * gs[(i, j)] }).collect();

    // Rows of A (as triplets) and b; cones in order.
    let (mut ri, mut ci, mut v, mut b, mut cones) = (vec![], vec![], vec![], vec![], vec![]);
    let mut row = 0;
    if let Some((lo, hi)) = &cons.bounds {
        for (t, &(i, j)) in idx.iter().enumerate() {
            ri.push(row);
            ci.push(t);
            v.push(1.0);
            b.push(hi[(i, j)]);
            row += 1;
        }
        for (t, &(i, j)) in idx.iter().enumerate() {
            ri.push(row);
            ci.push(t);
            v.push(-1.0);
            b.push(-lo[(i, j)]);
            row += 1;
        }
        cones.push(SupportedConeT::NonnegativeConeT(2 * m));
    }
    if let Some((center, radius)) = &cons.ball {
        b.push(*radius);
        row += 1;
        for (t, &(i, j)) in idx.iter().enumerate() {
            ri.push(row);
            ci.push(t);
            v.push(-scale(i, j));
            b.push(-scale(i, j) * center[(i, j)]);
            row += 1;
        }
        cones.push(SupportedConeT::SecondOrderConeT(m + 1));
    }
    let zero = cons.psd.then(|| Mat::zeros(n, n));
    for (bound, sign) in [(&cons.lower, -1.0), (&cons.upper, 1.0), (&zero, -1.0)] {
        if let Some(l) = bound {
            // lower: svec(S − L) = −A x + b with A = −scale, b = −scale·l; upper: svec(U − S).
            for (t, &(i, j)) in idx.iter().enumerate() {
                ri.push(row);
                ci.push(t);
                v.push(sign * scale(i, j));
                b.push(sign * scale(i, j) * l[(i, j)]);
                row += 1;
            }
            cones.push(SupportedConeT::PSDTriangleConeT(n));
        }
    }
    let a = CscMatrix::new_from_triplets(row, m, ri, ci, v);
    let p = CscMatrix::zeros((m, m));
    let settings = DefaultSettingsBuilder::default()
        .verbose(false)
        .tol_gap_abs(1e-10)
        .tol_gap_rel(1e-10)
        .tol_feas(1e-10)
        .max_threads(1)
        .build()
        .map_err(|e| format!("clarabel settings: {e}"))?;
    let mut solver =
        DefaultSolver::new(&p, &c, &a, &b, &cones, settings).map_err(|e| format!("clarabel setup: {e:?}"))?;
    solver.solve();
    let sol = &solver.solution;
    match sol.status {
        SolverStatus::Solved | SolverStatus::AlmostSolved => {}
        s => return Err(format!("clarabel status {s:?}")),
    }
    let mut s = Mat::zeros(n, n);
    for (t, &(i, j)) in idx.iter().enumerate() {
        s[(i, j)] = sol.x[t];
        s[(j, i)] = sol.x[t];
    }
    Ok(LinearMax {
        value: crate::linalg::frob_dot(&gs, &s),
        argmax: s,
        iterations: sol.iterations,
        solve_seconds: sol.solve_time,
    })
}
