//! Linear maximization over sets of symmetric matrices with clarabel: the linear oracle of seed 000
//! Algorithm 1 step 3 when the set is not a plain box or ball (a Loewner interval, or any set
//! intersected with {S ⪰ 0}). Variables are the upper-triangle entries s_ij (i ≤ j).

use super::conic::Conic;
use crate::numerics::linalg::{Mat, sym_unit, symmetrize};

/// Constraints on a symmetric n×n matrix S; every one that is `Some` applies.
#[derive(Clone, Debug, Default)]
pub struct SymConstraints {
    /// Elementwise bounds lo ≤ S ≤ hi.
    pub bounds: Option<(Mat, Mat)>,
    /// Frobenius ball ‖S − center‖_F ≤ radius.
    pub ball: Option<(Mat, f64)>,
    /// S ⪰ lower (Loewner order).
    pub lower: Option<Mat>,
    /// S ⪯ upper.
    pub upper: Option<Mat>,
    /// S ⪰ 0.
    pub psd: bool,
}

/// The maximizer of a linear function over a constrained set.
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
    let gs = symmetrize(g);
    let cost: Vec<f64> = idx.iter().map(|&(i, j)| if i == j { -gs[(i, i)] } else { -2.0 * gs[(i, j)] }).collect();
    // The symmetric matrix of variable t, for the matrix-valued constraints.
    let units: Vec<(usize, Mat)> = idx.iter().enumerate().map(|(t, &(i, j))| (t, sym_unit(n, i, j))).collect();
    let negated: Vec<(usize, Mat)> = units.iter().map(|(t, e)| (*t, -e)).collect();
    let mut p = Conic::default();
    if let Some((lo, hi)) = &cons.bounds {
        let upper = idx.iter().enumerate().map(|(t, &(i, j))| (hi[(i, j)], vec![(t, -1.0)]));
        let lower = idx.iter().enumerate().map(|(t, &(i, j))| (-lo[(i, j)], vec![(t, 1.0)]));
        p.nonnegative(upper.chain(lower).collect());
    }
    if let Some((center, radius)) = &cons.ball {
        let scale = |i: usize, j: usize| if i == j { 1.0 } else { std::f64::consts::SQRT_2 };
        let mut rows = vec![(*radius, vec![])];
        rows.extend(idx.iter().enumerate().map(|(t, &(i, j))| (-scale(i, j) * center[(i, j)], vec![(t, scale(i, j))])));
        p.second_order(rows);
    }
    if let Some(l) = &cons.lower {
        p.psd(&-l, &units);
    }
    if let Some(u) = &cons.upper {
        p.psd(u, &negated);
    }
    if cons.psd {
        p.psd(&Mat::zeros(n, n), &units);
    }
    let sol = p.minimize(&cost)?;
    let mut s = Mat::zeros(n, n);
    for (t, &(i, j)) in idx.iter().enumerate() {
        s[(i, j)] = sol.x[t];
        s[(j, i)] = sol.x[t];
    }
    Ok(LinearMax {
        value: crate::numerics::linalg::frob_dot(&gs, &s),
        argmax: s,
        iterations: sol.iterations,
        solve_seconds: sol.seconds,
    })
}
