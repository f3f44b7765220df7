//! The statistics every expectation of `filterbench check` is built from: normal and χ² tail
//! probabilities, the normal quantile, Holm's step-down procedure and the smallest discrepancy a
//! test detects at a given power (docs/checks.md, "Error rates and power"). The distributions are
//! statrs's (its normal tails go through erfc, so p-values far in the tail keep their digits); no
//! special function is written here.

use statrs::distribution::{ChiSquared, ContinuousCDF, Normal};

/// Which discrepancy a test looks for, relative to its reference: any (`TwoSided`), the observed
/// value above the reference (`Upper`: a mean above its guarantee) or below it (`Lower`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Sided {
    TwoSided,
    Upper,
    Lower,
}

impl Sided {
    /// The name used in check.parquet and the docs.
    pub fn name(self) -> &'static str {
        match self {
            Sided::TwoSided => "two-sided",
            Sided::Upper => "upper",
            Sided::Lower => "lower",
        }
    }
}

fn standard() -> Normal {
    Normal::standard()
}

/// Φ⁻¹(q), the standard normal quantile; ±∞ at q = 0 and q = 1. `q` outside [0, 1] or NaN gives NaN
/// (statrs would panic).
pub fn normal_quantile(q: f64) -> f64 {
    if !(0.0..=1.0).contains(&q) {
        return f64::NAN;
    }
    standard().inverse_cdf(q)
}

/// The p-value of a z statistic (observed − reference)/std_error under a standard normal null:
/// 2·(1 − Φ(|z|)) two-sided, 1 − Φ(z) for `Upper`, Φ(z) for `Lower`. Computed from the tail
/// (`sf`), never as 1 − cdf, so a z of 30 gives 5e-198 rather than 0.
pub fn normal_p(z: f64, sided: Sided) -> f64 {
    if z.is_nan() {
        return f64::NAN;
    }
    let n = standard();
    match sided {
        Sided::TwoSided => (2.0 * n.sf(z.abs())).min(1.0),
        Sided::Upper => n.sf(z),
        Sided::Lower => n.cdf(z),
    }
}

/// The tail probabilities of χ²(dof) at x: (P[X ≤ x], P[X ≥ x]). `dof` must be positive.
pub fn chi2_tails(x: f64, dof: f64) -> (f64, f64) {
    match ChiSquared::new(dof) {
        Ok(c) if x.is_finite() => {
            let x = x.max(0.0);
            (c.cdf(x), c.sf(x))
        }
        _ => (f64::NAN, f64::NAN),
    }
}

/// The p-value of an observed χ²(dof) statistic x: two-sided 2·min(lower, upper) capped at 1, or
/// one tail.
pub fn chi2_p(x: f64, dof: f64, sided: Sided) -> f64 {
    let (lower, upper) = chi2_tails(x, dof);
    match sided {
        Sided::TwoSided => (2.0 * lower.min(upper)).min(1.0),
        Sided::Upper => upper,
        Sided::Lower => lower,
    }
}

/// The z critical value of a test at level `level`: Φ⁻¹(1 − level/2) two-sided, Φ⁻¹(1 − level)
/// one-sided.
pub fn critical_z(level: f64, sided: Sided) -> f64 {
    match sided {
        Sided::TwoSided => -normal_quantile(level / 2.0),
        Sided::Upper | Sided::Lower => -normal_quantile(level),
    }
}

/// The smallest true discrepancy |μ − reference| a z-test with standard error `se` at per-cell level
/// `level` detects with probability at least 1 − β: (z_crit + z_{1−β})·se. For a two-sided test the
/// far tail's rejections are left out, so the power at this size is at least 1 − β. `level` is the
/// Bonferroni level α/m of a family of m cells: Holm rejects whatever Bonferroni rejects, so the
/// stated power is conservative for Holm (docs/checks.md, "Error rates and power").
pub fn detectable(se: f64, level: f64, beta: f64, sided: Sided) -> f64 {
    (critical_z(level, sided) - normal_quantile(beta)) * se
}

/// The trials a z-test of a mean needs to detect a discrepancy `delta` with probability 1 − β at
/// per-cell level `level`, given the per-trial standard deviation σ: n = ⌈((z_crit + z_{1−β})·σ/δ)²⌉
/// (the inverse of [`detectable`] with se = σ/√n). Infinite when δ ≤ 0 or σ is not finite.
pub fn trials_for(sigma: f64, delta: f64, level: f64, beta: f64, sided: Sided) -> f64 {
    if !(delta > 0.0) || !sigma.is_finite() {
        return f64::INFINITY;
    }
    let z = critical_z(level, sided) - normal_quantile(beta);
    ((z * sigma / delta).powi(2)).ceil().max(2.0)
}

/// Holm's step-down procedure over one family of p-values at family-wise level α (Holm 1979):
/// sort the m p-values ascending, p₍₁₎ ≤ … ≤ p₍ₘ₎, and reject p₍ᵢ₎ while p₍ⱼ₎ ≤ α/(m − j + 1) for
/// every j ≤ i. Under any dependence between the cells, the probability of rejecting any true
/// hypothesis is at most α. A NaN p-value counts as 1 (never rejected).
#[derive(Clone, Debug, PartialEq)]
pub struct Holm {
    /// Whether each cell's hypothesis is rejected (the cell fails), in the input order.
    pub rejected: Vec<bool>,
    /// Each cell's Holm threshold α/(m − rank), rank its 0-based position in the sorted order (ties
    /// keep the input order).
    pub threshold: Vec<f64>,
}

/// See [`Holm`].
pub fn holm(p: &[f64], alpha: f64) -> Holm {
    let m = p.len();
    let key = |i: usize| if p[i].is_nan() { 1.0 } else { p[i] };
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| key(a).total_cmp(&key(b)));
    let mut rejected = vec![false; m];
    let mut threshold = vec![0.0; m];
    let mut stepping = true;
    for (rank, &i) in order.iter().enumerate() {
        threshold[i] = alpha / (m - rank) as f64;
        stepping = stepping && key(i) <= threshold[i];
        rejected[i] = stepping;
    }
    Holm { rejected, threshold }
}

/// The q-quantile of χ²(dof) (statrs's inversion of the regularized gamma function).
pub fn chi2_quantile(q: f64, dof: f64) -> f64 {
    match ChiSquared::new(dof) {
        Ok(c) if (0.0..=1.0).contains(&q) => c.inverse_cdf(q),
        _ => f64::NAN,
    }
}

/// The smallest factor c − 1 by which the true error second moment may exceed the claimed one
/// (E\[e eᵀ] = c·P_z) and be detected with probability 1 − β by the two-sided χ²(dof) test at level
/// `level`: n·r·NEES is then c·χ²(dof), beyond the test's upper critical value q₁₋ₗₑᵥₑₗ/₂ with
/// probability P\[χ² > q₁₋ₗₑᵥₑₗ/₂ / c] = 1 − β, so c = q₁₋ₗₑᵥₑₗ/₂ / q_β. Exact under the χ² model.
pub fn chi2_detectable(dof: f64, level: f64, beta: f64) -> f64 {
    chi2_quantile(1.0 - level / 2.0, dof) / chi2_quantile(beta, dof) - 1.0
}
