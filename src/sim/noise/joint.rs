//! Inputs drawn jointly over the whole horizon (docs/math.md §7; seed 002 §2): ξ = col(x0 − E x0,
//! w\[0..N−1]) with w\[N] = 0, either with a full (not white) covariance, uniformly on or inside the
//! weighted ellipsoid ξᵀK⁻¹ξ ≤ 1, or fixed (a filter's worst case). The factor is computed once per
//! scenario; a block of lanes draws into preallocated buffers, its Gaussian rows as one batch (the
//! ziggurat's, as every other input's), and is mapped with one (triangular) product.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal, Uniform};

use super::lane_rng::LaneRng;

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

    /// Turns a block's Gaussian rows `u` (dim rows, drawn row by row from the lanes' noise
    /// streams) into each lane's uniform direction scaled to the ellipsoid's radius: 1 on the
    /// surface, U^(1/dim) inside with U from the lane's stream after its normals. The correlated
    /// kind's rows are the scenario's shape as drawn; nothing to do.
    pub(super) fn scale_lanes(&self, rng: &mut LaneRng, active: usize, u: &mut [Row]) {
        let JointInput::Ellipsoid { surface, .. } = self else { return };
        let mut scale = [0.0; LANES];
        for r in u.iter() {
            for (s, v) in scale.iter_mut().zip(r) {
                *s += v * v;
            }
        }
        for (l, s) in scale.iter_mut().enumerate().take(active) {
            let radius = if *surface {
                1.0
            } else {
                let r: f64 = Uniform::new(0.0, 1.0).expect("valid interval").sample(&mut rng.lane(l));
                r.powf(1.0 / u.len() as f64)
            };
            *s = radius / s.sqrt();
        }
        for r in u.iter_mut() {
            for (v, s) in r.iter_mut().zip(&scale).take(active) {
                *v *= s;
            }
        }
    }

    /// Which columns each panel of the factor's rows needs ([`lanes::panel_widths`]), for [`JointInput::map`].
    pub(super) fn panel_widths(&self) -> Vec<usize> {
        match self {
            JointInput::Correlated { factor } => lanes::panel_widths(factor),
            JointInput::Ellipsoid { k_half, .. } => lanes::panel_widths(k_half),
            JointInput::Fixed { .. } => Vec::new(),
        }
    }

    /// ξ of every lane from the lanes' standardized draws: factor·u, K^½·u, or the fixed ξ.
    /// `widths` is [`JointInput::panel_widths`]: the factors are Cholesky factors where the
    /// covariance is definite, and a triangular product costs half a full one.
    pub(super) fn map(&self, widths: &[usize], u: &[Row], xi: &mut [Row]) {
        match self {
            JointInput::Correlated { factor } => lanes::gemm_panels(factor, widths, u, xi),
            JointInput::Ellipsoid { k_half, .. } => lanes::gemm_panels(k_half, widths, u, xi),
            JointInput::Fixed { xi: fixed } => {
                for (r, v) in xi.iter_mut().zip(fixed.iter()) {
                    *r = [*v; LANES];
                }
            }
        }
    }
}
