//! Distribution shapes with zero mean and unit variance. A vector draw is `L u` with u i.i.d. of
//! the chosen shape and L Lᵀ = S, so every shape has exactly the covariance S; only the higher
//! moments differ (the minimax and H∞ guarantees are distribution-free, Kalman optimality is not).

use rand::Rng;
use rand_distr::{Distribution, Exp1, StandardNormal, StudentT, Uniform};
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

#[derive(Clone, Debug, Default, Deserialize, Serialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Shape {
    #[default]
    Gaussian,
    /// Uniform on [−√3, √3].
    Uniform,
    /// Laplace with scale 1/√2.
    Laplace,
    /// Student-t with ν > 2 degrees of freedom, scaled by sqrt((ν−2)/ν).
    StudentT { nu: f64 },
    /// ±1 with probability ½ each.
    Rademacher,
    /// Two-component Gaussian scale mixture: with probability `weight` the wide component, whose
    /// standard deviation is `ratio` times the narrow one's; scaled to unit variance.
    Mixture { weight: f64, ratio: f64 },
}

impl Shape {
    pub(crate) fn validate(&self, key: &str) -> Result<()> {
        match self {
            Shape::StudentT { nu } if !(*nu > 2.0 && nu.is_finite()) => Err(Error::invalid(
                format!("{key}.nu"),
                format!("Student-t needs ν > 2 for a finite variance, got {nu}"),
            )),
            Shape::Mixture { weight, ratio }
                if !((0.0..=1.0).contains(weight) && *ratio > 0.0 && ratio.is_finite()) =>
            {
                Err(Error::invalid(key, format!("mixture needs 0 ≤ weight ≤ 1 and ratio > 0, got {weight}, {ratio}")))
            }
            _ => Ok(()),
        }
    }
    pub fn label(&self) -> String {
        match self {
            Shape::Gaussian => "gaussian".into(),
            Shape::Uniform => "uniform".into(),
            Shape::Laplace => "laplace".into(),
            Shape::StudentT { nu } => format!("student_t(nu={nu})"),
            Shape::Rademacher => "rademacher".into(),
            Shape::Mixture { weight, ratio } => format!("mixture(weight={weight},ratio={ratio})"),
        }
    }
    /// The differential entropy of the shape's zero-mean, unit-variance draw (nats), or None for a
    /// discrete one (Rademacher): the h(u) of A(W) = (lw/2) ln(2πe E|W|²/lw) − h(W) with
    /// h(L u) = Σ h(u_i) + ln|det L| (seed 003 §2, for non-Gaussian inputs). Closed forms except
    /// the mixture, whose density has none: there a composite Simpson rule on ±40 wide standard
    /// deviations (the integrand is smooth and its tails below 1e-300 there).
    pub fn entropy(&self) -> Option<f64> {
        use std::f64::consts::{E, PI};
        match *self {
            Shape::Gaussian => Some(0.5 * (2.0 * PI * E).ln()),
            Shape::Uniform => Some((2.0 * 3f64.sqrt()).ln()),
            // Laplace with scale b = 1/√2: 1 + ln(2b).
            Shape::Laplace => Some(1.0 + std::f64::consts::SQRT_2.ln()),
            Shape::StudentT { nu } => {
                use statrs::function::beta::ln_beta;
                use statrs::function::gamma::digamma;
                let standard = 0.5 * (nu + 1.0) * (digamma(0.5 * (nu + 1.0)) - digamma(0.5 * nu))
                    + 0.5 * nu.ln()
                    + ln_beta(0.5 * nu, 0.5);
                Some(standard + 0.5 * ((nu - 2.0) / nu).ln())
            }
            Shape::Rademacher => None,
            Shape::Mixture { weight, ratio } => {
                let narrow = 1.0 / (1.0 - weight + weight * ratio * ratio).sqrt();
                let wide = narrow * ratio;
                let phi = |x: f64, s: f64| (-0.5 * (x / s).powi(2)).exp() / (s * (2.0 * PI).sqrt());
                let p = |x: f64| (1.0 - weight) * phi(x, narrow) + weight * phi(x, wide);
                let f = |x: f64| {
                    let v = p(x);
                    if v > 0.0 { -v * v.ln() } else { 0.0 }
                };
                let (half, panels) = (40.0 * wide.max(narrow), 1 << 16);
                let h = 2.0 * half / panels as f64;
                let sum: f64 = (0..=panels)
                    .map(|i| {
                        let w = if i == 0 || i == panels {
                            1.0
                        } else if i % 2 == 1 {
                            4.0
                        } else {
                            2.0
                        };
                        w * f(-half + i as f64 * h)
                    })
                    .sum();
                Some(sum * h / 3.0)
            }
        }
    }

    /// A sampler of standardized draws; built once per scenario, used for every trial.
    pub fn sampler(&self) -> StandardDraw {
        match *self {
            Shape::Gaussian => StandardDraw::Gaussian,
            Shape::Uniform => {
                StandardDraw::Uniform(Uniform::new_inclusive(-3f64.sqrt(), 3f64.sqrt()).expect("valid interval"))
            }
            Shape::Laplace => StandardDraw::Laplace,
            Shape::StudentT { nu } => {
                StandardDraw::StudentT(StudentT::new(nu).expect("validated ν > 2"), ((nu - 2.0) / nu).sqrt())
            }
            Shape::Rademacher => StandardDraw::Rademacher,
            Shape::Mixture { weight, ratio } => {
                let narrow = 1.0 / (1.0 - weight + weight * ratio * ratio).sqrt();
                StandardDraw::Mixture { weight, narrow, wide: narrow * ratio }
            }
        }
    }
}

/// A prepared zero-mean, unit-variance scalar distribution.
#[derive(Clone, Debug)]
pub enum StandardDraw {
    Gaussian,
    Uniform(Uniform<f64>),
    Laplace,
    StudentT(StudentT<f64>, f64),
    Rademacher,
    Mixture { weight: f64, narrow: f64, wide: f64 },
}

impl StandardDraw {
    /// Fills `out` with i.i.d. draws, the shape matched once for all of them (a lane's noise).
    #[inline]
    pub(crate) fn fill<'a, R: Rng + ?Sized>(&self, rng: &mut R, out: impl Iterator<Item = &'a mut f64>) {
        match self {
            StandardDraw::Gaussian => out.for_each(|v| *v = StandardNormal.sample(rng)),
            _ => out.for_each(|v| *v = self.draw(rng)),
        }
    }

    #[inline]
    pub fn draw<R: Rng + ?Sized>(&self, rng: &mut R) -> f64 {
        match self {
            StandardDraw::Gaussian => StandardNormal.sample(rng),
            StandardDraw::Uniform(u) => u.sample(rng),
            StandardDraw::Laplace => {
                // ±Exp(1) has variance E[e²] = 2, hence the 1/√2.
                let e: f64 = Exp1.sample(rng);
                let s = if rng.next_u32() & 1 == 0 { -1.0 } else { 1.0 };
                s * e * std::f64::consts::FRAC_1_SQRT_2
            }
            StandardDraw::StudentT(t, scale) => t.sample(rng) * scale,
            StandardDraw::Rademacher => {
                if rng.next_u32() & 1 == 0 {
                    -1.0
                } else {
                    1.0
                }
            }
            StandardDraw::Mixture { weight, narrow, wide } => {
                let g: f64 = StandardNormal.sample(rng);
                let u: f64 = rand::RngExt::random(rng);
                if u < *weight { g * wide } else { g * narrow }
            }
        }
    }
}
