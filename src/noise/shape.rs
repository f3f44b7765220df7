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
    pub fn validate(&self, key: &str) -> Result<()> {
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
