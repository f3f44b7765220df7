//! The per-trial noise draw: x0 = m0 + L0 u0 and w[k] = Lw u[k] for k = 0..N, with u i.i.d. of the
//! scenario's shape and L Lᵀ equal to the scenario's covariance. Factors are computed once per
//! scenario; a draw writes into a preallocated [`TrialDraw`] and allocates nothing.

use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

use super::joint::JointInput;
use crate::model::plant::{Covariances, Plant};
use crate::model::shape::{Shape, StandardDraw};
use crate::numerics::linalg::{Mat, Vector, psd_factor};
use crate::numerics::linop::LinOp;

/// The random stream of one trial. It depends on (seed, scenario, trial) only, never on the thread
/// that runs it, so results are identical for any thread count: the key is derived from the
/// experiment seed and the scenario index, and ChaCha's 64-bit stream id is the trial index.
pub fn trial_rng(seed: u64, scenario: usize, trial: u64) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(splitmix(seed ^ splitmix(scenario as u64 + 1)));
    rng.set_stream(trial);
    rng
}

fn splitmix(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

#[derive(Clone, Debug)]
pub struct NoiseSampler {
    m0: Vector,
    l0: Mat,
    lw: LinOp,
    draw: StandardDraw,
    steps: usize,
    /// Deterministic part of w[k] (column k), if any: energy-bounded disturbances.
    w_mean: Option<Mat>,
    /// Inputs drawn jointly over the horizon instead of block by block.
    joint: Option<JointInput>,
    /// The Markov chain of the plant's modes (dropouts included), drawn after the noise.
    chain: Option<crate::model::plant::Modes>,
    /// The multiplicative factors' ζ_i(k) (seed 003 (3.1)), drawn after the modes.
    factors: Vec<StandardDraw>,
}

/// One trial's draws: the initial state and w[k] as column k of `w`.
#[derive(Clone, Debug)]
pub struct TrialDraw {
    pub x0: Vector,
    pub w: Mat,
    /// θ[k], the plant's mode at step k (all 0 for a plant that does not switch; for dropouts
    /// 0 = lost, 1 = arrived).
    pub modes: Vec<usize>,
    /// ζ_i(k): row i is factor i of the plant's multiplicative noise.
    pub zeta: Mat,
    u0: Vector,
    u: Vector,
    uj: Vector,
    xi: Vector,
}

impl NoiseSampler {
    pub fn new(plant: &Plant, cov: &Covariances, shape: &Shape) -> Self {
        NoiseSampler {
            m0: plant.x0_mean.clone(),
            l0: psd_factor(cov.x0()),
            lw: LinOp::new(&psd_factor(&cov.w())),
            draw: shape.sampler(),
            steps: plant.steps(),
            w_mean: None,
            joint: None,
            chain: plant.modes().map(std::borrow::Cow::into_owned),
            factors: plant.factors.iter().map(|f| f.shape.sampler()).collect(),
        }
    }

    /// Draws ξ = col(x0 − E x0, w[0..N−1]) jointly (w[N] = 0) instead of independently.
    pub fn with_joint(mut self, joint: Option<JointInput>) -> Self {
        self.joint = joint;
        self
    }

    /// Adds a deterministic sequence to w (column k is added to w[k]).
    pub fn with_mean(mut self, w_mean: Option<Mat>) -> Self {
        self.w_mean = w_mean;
        self
    }

    pub fn workspace(&self) -> TrialDraw {
        TrialDraw {
            x0: Vector::zeros(self.m0.len()),
            w: Mat::zeros(self.lw.nrows(), self.steps),
            modes: vec![0; self.steps],
            zeta: Mat::zeros(self.factors.len(), self.steps),
            u0: Vector::zeros(self.l0.ncols()),
            u: Vector::zeros(self.lw.ncols()),
            uj: Vector::zeros(self.joint.as_ref().map_or(0, JointInput::dim)),
            xi: Vector::zeros(self.joint.as_ref().map_or(0, JointInput::dim)),
        }
    }

    /// Fills `out` with one trial's draws from `rng`: the noise, then the mode sequence
    /// θ[0] ~ p(0), θ[k+1] ~ Π[θ[k], ·] (seed 001 (11)), then the multiplicative factors ζ_i(k)
    /// (so a plant without factors draws exactly what it drew before they existed).
    pub fn draw_into<R: rand::Rng + ?Sized>(&self, rng: &mut R, out: &mut TrialDraw) {
        self.draw_noise(rng, out);
        if let Some(chain) = &self.chain {
            let pick = |rng: &mut R, p: &mut dyn Iterator<Item = f64>| {
                let u: f64 = rand::RngExt::random(rng);
                let mut acc = 0.0;
                let mut last = 0;
                for (i, pi) in p.enumerate() {
                    acc += pi;
                    last = i;
                    if u < acc {
                        return i;
                    }
                }
                last
            };
            let mut theta = pick(rng, &mut chain.initial.iter().copied());
            for m in out.modes.iter_mut() {
                *m = theta;
                theta = pick(rng, &mut chain.transition.row(theta).iter().copied());
            }
        }
        for k in 0..self.steps {
            for (i, f) in self.factors.iter().enumerate() {
                out.zeta[(i, k)] = f.draw(rng);
            }
        }
    }

    fn draw_noise<R: rand::Rng + ?Sized>(&self, rng: &mut R, out: &mut TrialDraw) {
        if let Some(j) = &self.joint {
            j.draw(rng, &self.draw, &mut out.uj, &mut out.xi);
            let n = self.m0.len();
            let nw = out.w.nrows();
            out.x0.copy_from(&self.m0);
            out.x0 += out.xi.rows(0, n);
            out.w.fill(0.0);
            // w[N] is part of ξ only when ξ is long enough (anisotropic inputs: lw = mw(N+1)).
            let steps = ((out.xi.len() - n) / nw).min(self.steps);
            for k in 0..steps {
                out.w.column_mut(k).copy_from(&out.xi.rows(n + k * nw, nw));
            }
            return;
        }
        for v in out.u0.iter_mut() {
            *v = self.draw.draw(rng);
        }
        out.x0.copy_from(&self.m0);
        out.x0.gemv(1.0, &self.l0, &out.u0, 1.0);
        for k in 0..self.steps {
            for v in out.u.iter_mut() {
                *v = self.draw.draw(rng);
            }
            self.lw.apply(1.0, &out.u, 0.0, &mut out.w.column_mut(k));
        }
        if let Some(m) = &self.w_mean {
            out.w += m;
        }
    }

    /// Number of standardized scalars one trial consumes.
    pub fn scalars_per_trial(&self) -> usize {
        self.l0.ncols() + self.steps * (self.lw.ncols() + self.factors.len())
    }
}
