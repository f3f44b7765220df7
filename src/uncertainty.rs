//! Covariance uncertainty sets around a nominal matrix (seed 000 §6): the elementwise box
//! {S : |S_ij − S0_ij| ≤ h_ij} and the Frobenius ball {‖S − S0‖_F ≤ ρ}. A filter's error is affine in
//! the covariance, so its worst case over a set is a linear maximization with a closed form.

use rand::Rng;
use rand_distr::{Distribution, StandardNormal, Uniform};

use crate::error::{Error, Result};
use crate::linalg::{Mat, frob_dot};

#[derive(Clone, Debug)]
pub enum CovSet {
    /// Elementwise box: center ± half_width (half_width symmetric, non-negative).
    Box { center: Mat, half_width: Mat },
    /// Frobenius ball of symmetric matrices around center.
    Ball { center: Mat, radius: f64 },
}

impl CovSet {
    pub fn new_box(key: &str, center: Mat, half_width: Mat) -> Result<Self> {
        if half_width.iter().any(|v| *v < 0.0 || !v.is_finite()) {
            return Err(Error::invalid(
                format!("{key}.half_width"),
                "half-widths must be finite and ≥ 0",
            ));
        }
        if (&half_width - half_width.transpose()).amax() > 0.0 {
            return Err(Error::invalid(
                format!("{key}.half_width"),
                "the half-width matrix must be symmetric",
            ));
        }
        Ok(CovSet::Box { center, half_width })
    }
    pub fn new_ball(key: &str, center: Mat, radius: f64) -> Result<Self> {
        if radius < 0.0 || !radius.is_finite() {
            return Err(Error::invalid(
                format!("{key}.radius"),
                "the radius must be finite and ≥ 0",
            ));
        }
        Ok(CovSet::Ball { center, radius })
    }
    pub fn center(&self) -> &Mat {
        match self {
            CovSet::Box { center, .. } | CovSet::Ball { center, .. } => center,
        }
    }
    pub fn kind(&self) -> &'static str {
        match self {
            CovSet::Box { .. } => "box",
            CovSet::Ball { .. } => "ball",
        }
    }

    /// max over the set of ⟨G, S − center⟩ for a symmetric G, and the maximizing S.
    /// Box: the sign pattern S0 + h∘sign(G) (seed 000 Example 2's LP); ball: S0 + ρ G/‖G‖_F
    /// (seed 000 Example 2, "example 2.1 of [18]").
    pub fn argmax_linear(&self, g: &Mat) -> (f64, Mat) {
        match self {
            CovSet::Box { center, half_width } => {
                let step = Mat::from_fn(g.nrows(), g.ncols(), |i, j| {
                    half_width[(i, j)] * g[(i, j)].signum_or_zero()
                });
                (frob_dot(g, &step), center + step)
            }
            CovSet::Ball { center, radius } => {
                let norm = g.norm();
                if norm == 0.0 {
                    return (0.0, center.clone());
                }
                (radius * norm, center + g * (radius / norm))
            }
        }
    }

    /// A random extreme point: a box vertex (independent random sign per entry of the upper
    /// triangle) or a point on the ball's sphere (uniform direction among symmetric matrices).
    pub fn random_vertex<R: Rng + ?Sized>(&self, rng: &mut R) -> Mat {
        self.random_point(rng, true)
    }

    /// A uniformly distributed point of the set (box: each upper-triangle entry uniform in its
    /// interval; ball: uniform in the ball of symmetric matrices).
    pub fn random_interior<R: Rng + ?Sized>(&self, rng: &mut R) -> Mat {
        self.random_point(rng, false)
    }

    fn random_point<R: Rng + ?Sized>(&self, rng: &mut R, extreme: bool) -> Mat {
        let center = self.center();
        let n = center.nrows();
        let mut delta = Mat::zeros(n, n);
        match self {
            CovSet::Box { half_width, .. } => {
                let u = Uniform::new_inclusive(-1.0, 1.0).expect("valid interval");
                for i in 0..n {
                    for j in i..n {
                        let t: f64 = if extreme {
                            if rng.next_u32() & 1 == 0 { -1.0 } else { 1.0 }
                        } else {
                            u.sample(rng)
                        };
                        delta[(i, j)] = t * half_width[(i, j)];
                        delta[(j, i)] = delta[(i, j)];
                    }
                }
            }
            CovSet::Ball { radius, .. } => {
                for i in 0..n {
                    for j in i..n {
                        let g: f64 = StandardNormal.sample(rng);
                        // Off-diagonal coordinates count twice in ‖·‖_F: scale by 1/√2 so the
                        // direction is uniform on the sphere of symmetric matrices.
                        let v = if i == j {
                            g
                        } else {
                            g / std::f64::consts::SQRT_2
                        };
                        delta[(i, j)] = v;
                        delta[(j, i)] = v;
                    }
                }
                let dim = (n * (n + 1) / 2) as f64;
                let r = if extreme {
                    *radius
                } else {
                    let u: f64 = Uniform::new(0.0, 1.0).expect("valid interval").sample(rng);
                    radius * u.powf(1.0 / dim)
                };
                let norm = delta.norm();
                if norm > 0.0 {
                    delta *= r / norm;
                }
            }
        }
        center + delta
    }
}

trait SignumOrZero {
    fn signum_or_zero(self) -> f64;
}
impl SignumOrZero for f64 {
    fn signum_or_zero(self) -> f64 {
        if self > 0.0 {
            1.0
        } else if self < 0.0 {
            -1.0
        } else {
            0.0
        }
    }
}
