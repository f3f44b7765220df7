//! Inputs drawn jointly over the whole horizon (docs/math.md §7; seed 002 §2): ξ = col(x0 − E x0,
//! w\[0..N−1]) with w\[N] = 0, either with a full (not white) covariance, uniformly on or inside the
//! weighted ellipsoid ξᵀK⁻¹ξ ≤ 1, or fixed (a filter's worst case). The factor is computed once per
//! scenario; a block of lanes draws into preallocated buffers and is mapped with one product.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal, Uniform};

use crate::numerics::linalg::{Mat, Vector, psd_factor};
use crate::sim::lanes::{self, LANES, Row};

#[derive(Clone, Debug)]
pub enum JointInput {
    /// ξ = factor · u with u i.i.d. of the scenario's shape: covariance factor·factorᵀ.
    Correlated { factor: Mat },
    /// Uniform direction in the K-metric, on the ellipsoid's surface or uniform inside it.
    Ellipsoid { k_half: Mat, surface: bool },
    /// The same ξ in every trial.
    Fixed { xi: Vector },
}

impl JointInput {
    /// A random full covariance over the horizon, K^½ B K^½ᵀ with B = AAᵀ (A Gaussian) scaled so
    /// that E\[ξᵀK⁻¹ξ] = dim, as for white noise of covariance K.
    pub fn random_covariance(k: &Mat, seed: u64) -> Self {
        let d = k.nrows();
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let a = Mat::from_fn(d, d, |_, _| StandardNormal.sample(&mut rng));
        let mut b = &a * a.transpose();
        b *= d as f64 / b.trace();
        let k_half = psd_factor(k);
        JointInput::Correlated { factor: k_half * psd_factor(&b) }
    }

    pub(crate) fn dim(&self) -> usize {
        match self {
            JointInput::Correlated { factor } => factor.nrows(),
            JointInput::Ellipsoid { k_half, .. } => k_half.nrows(),
            JointInput::Fixed { xi } => xi.len(),
        }
    }

    /// E ξ and Cov ξ: ellipsoid surface K/d, uniform inside K/(d+2) (E r² = d/(d+2)).
    pub fn moments(&self) -> (Vector, Mat) {
        let d = self.dim();
        match self {
            JointInput::Correlated { factor } => (Vector::zeros(d), factor * factor.transpose()),
            JointInput::Ellipsoid { k_half, surface } => {
                let k = k_half * k_half.transpose();
                (Vector::zeros(d), k / if *surface { d as f64 } else { d as f64 + 2.0 })
            }
            JointInput::Fixed { xi } => (xi.clone(), Mat::zeros(d, d)),
        }
    }

    pub fn label(&self) -> &'static str {
        match self {
            JointInput::Correlated { .. } => "joint_correlated",
            JointInput::Ellipsoid { surface: true, .. } => "ellipsoid_surface",
            JointInput::Ellipsoid { surface: false, .. } => "ellipsoid_interior",
            JointInput::Fixed { .. } => "fixed",
        }
    }

    /// Draws lane `lane`'s standardized vector into column `lane` of `u` (dim rows) from `rng`:
    /// i.i.d. draws of the scenario's shape (`std`) for the correlated kind, a Gaussian direction
    /// scaled to the ellipsoid's radius for the ellipsoid kinds; [`JointInput::map`] then turns the
    /// whole block into ξ with one product.
    pub(super) fn draw_lane<R: rand::Rng + ?Sized>(
        &self,
        rng: &mut R,
        std: &crate::model::shape::StandardDraw,
        lane: usize,
        u: &mut [Row],
    ) {
        match self {
            JointInput::Correlated { .. } => {
                for r in u.iter_mut() {
                    r[lane] = std.draw(rng);
                }
            }
            JointInput::Ellipsoid { surface, .. } => {
                let mut norm2 = 0.0;
                for r in u.iter_mut() {
                    let v: f64 = StandardNormal.sample(rng);
                    r[lane] = v;
                    norm2 += v * v;
                }
                let radius = if *surface {
                    1.0
                } else {
                    let r: f64 = Uniform::new(0.0, 1.0).expect("valid interval").sample(rng);
                    r.powf(1.0 / u.len() as f64)
                };
                let scale = radius / norm2.sqrt();
                for r in u.iter_mut() {
                    r[lane] *= scale;
                }
            }
            JointInput::Fixed { .. } => {}
        }
    }

    /// ξ of every lane from the lanes' standardized draws: factor·u, K^½·u, or the fixed ξ.
    pub(super) fn map(&self, u: &[Row], xi: &mut [Row]) {
        match self {
            JointInput::Correlated { factor } => lanes::gemm(factor, u, false, xi),
            JointInput::Ellipsoid { k_half, .. } => lanes::gemm(k_half, u, false, xi),
            JointInput::Fixed { xi: fixed } => {
                for (r, v) in xi.iter_mut().zip(fixed.iter()) {
                    *r = [*v; LANES];
                }
            }
        }
    }
}
