//! Linear maximization over sets of symmetric matrices with clarabel: the linear oracle of seed 000
//! Algorithm 1 step 3 when the set is not a plain box or ball (a Loewner interval, or any set
//! intersected with {S ⪰ 0}). Variables are the upper-triangle entries s_ij (i ≤ j).

use super::conic::Conic;
use crate::numerics::linalg::{Mat, sym_unit, symmetrize, unpack_triangle};

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
    /// ⟨G, S⟩ at the solver's point: within the solver's accuracy of the maximum, on either side.
    pub value: f64,
    /// A certified upper bound on the maximum ([`certified_upper`]): what a guarantee may use.
    pub upper: f64,
    pub argmax: Mat,
    /// clarabel's first-order bound on |value − the maximum| (`Solution::objective_error`).
    pub objective_error: f64,
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
    let psd_rows = p.size().0;
    if cons.psd {
        p.psd(&Mat::zeros(n, n), &units);
    }
    let sol = p.minimize(&cost)?;
    let multiplier = cons.psd.then(|| {
        let mut m = Mat::zeros(n, n);
        unpack_triangle(&sol.z[psd_rows..], n, &mut m);
        m
    });
    let mut s = Mat::zeros(n, n);
    for (t, &(i, j)) in idx.iter().enumerate() {
        s[(i, j)] = sol.x[t];
        s[(j, i)] = sol.x[t];
    }
    Ok(LinearMax {
        value: crate::numerics::linalg::frob_dot(&gs, &s),
        upper: certified_upper(&gs, cons, multiplier.as_ref())?,
        argmax: s,
        objective_error: sol.objective_error,
        iterations: sol.iterations,
        solve_seconds: sol.seconds,
    })
}

/// A certified upper bound on max ⟨G, S⟩ over the set `cons`, by weak duality: for every Z ⪰ 0,
/// ⟨Z, S⟩ ≥ 0 on {S ⪰ 0}, so the maximum over (shape ∩ PSD) is at most the maximum of ⟨G + Z, S⟩
/// over the shape alone, which has a closed form — a box: Σ max(H_ij lo_ij, H_ij hi_ij); a ball:
/// ⟨H, C⟩ + ρ‖H‖_F; a Loewner interval L ⪯ S ⪯ U with U − L = FFᵀ: ⟨H, L⟩ + the sum of the positive
/// eigenvalues of FᵀHF (S = L + FXFᵀ, 0 ⪯ X ⪯ I). Z is the solver's multiplier of the PSD
/// constraint with its negative eigenvalues dropped; the bound holds for any Z, the solver's only
/// makes it tight. Every eigenvalue computed here carries [`crate::numerics::accuracy::eigenvalue_error`], which is
/// added: Z's own (times the largest trace on the shape, since ⟨Z, S⟩ ≥ −δ tr S) and the Loewner
/// form's (times n). Where several shapes are given the first is used (a superset of the
/// intersection, so still a bound).
pub fn certified_upper(g: &Mat, cons: &SymConstraints, multiplier: Option<&Mat>) -> Result<f64, String> {
    use crate::numerics::accuracy;
    let n = g.nrows();
    let (mut h, mut slack) = (symmetrize(g), 0.0);
    if let Some(z) = multiplier {
        let eig = symmetrize(z).symmetric_eigen();
        let clipped = Mat::from_diagonal(&eig.eigenvalues.map(|v| v.max(0.0)));
        let zp = symmetrize(&(&eig.eigenvectors * clipped * eig.eigenvectors.transpose()));
        slack = accuracy::eigenvalue_error(&zp);
        h += zp;
    }
    let entries = |a: &Mat, b: &Mat| a.iter().zip(b.iter()).map(|(x, y)| (x * y).abs()).sum::<f64>();
    let (value, trace, scale) = if let Some((lo, hi)) = &cons.bounds {
        let v: f64 = h.iter().zip(lo.iter().zip(hi.iter())).map(|(h, (l, u))| (h * l).max(h * u)).sum();
        (v, hi.trace(), entries(&h, lo).max(entries(&h, hi)))
    } else if let Some((c, r)) = &cons.ball {
        let v = crate::numerics::linalg::frob_dot(&h, c) + r * h.norm();
        (v, c.trace() + r * (n as f64).sqrt(), entries(&h, c) + r * h.norm())
    } else if let (Some(l), Some(u)) = (&cons.lower, &cons.upper) {
        let f = crate::numerics::linalg::psd_factor(&(u - l));
        let inner = symmetrize(&(f.transpose() * &h * &f));
        let pos: f64 = inner.symmetric_eigenvalues().iter().map(|v| v.max(0.0)).sum();
        let v = crate::numerics::linalg::frob_dot(&h, l) + pos + n as f64 * accuracy::eigenvalue_error(&inner);
        (v, u.trace(), entries(&h, l) + pos)
    } else {
        return Err("no bounded shape: the maximum has no certified bound".into());
    };
    // The closed forms sum n² products: each rounds by ε relative, so n² ε times their magnitudes.
    let rounding = (n * n) as f64 * f64::EPSILON * scale;
    Ok(accuracy::round_up(value, slack * trace.max(0.0) + rounding))
}
