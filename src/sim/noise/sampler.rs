//! The noise draw, a block of [`LANES`] trials at a time: x0 = m0 + L0 u0 and w\[k] = Lw u\[k] + w̄\[k]
//! for k = 0..N, with u i.i.d. of the scenario's shape and L Lᵀ equal to the scenario's covariance
//! (docs/math.md §7), then the plant's mode θ\[k] and its multiplicative factors ζ_i(k). Each lane draws its
//! standardized scalars from its own trial's streams, all lanes' streams stepped together
//! ([`LaneRng`]); Gaussian rows are drawn a batch of rows for all lanes at once (a step's u\[k],
//! [`ziggurat::normal_batch`]), other shapes lane by lane from the same streams. The factors L are then applied to the whole
//! block with one product per step. Factors are computed once per scenario; a block draws into a
//! preallocated [`LaneDraw`] and allocates nothing.

use rand::SeedableRng;
use rand::rngs::Xoshiro256PlusPlus;

use super::joint::JointInput;
use super::lane_rng::LaneRng;
use super::shaping::Shaping;
use super::ziggurat;
use crate::model::plant::{Covariances, Modes, Plant};
use crate::model::shape::{Shape, StandardDraw};
use crate::numerics::linalg::{Mat, Vector, psd_factor};
use crate::numerics::linop::LinOp;
use crate::sim::lanes::{self, Build, LANES, Row};

/// The generator of every trial stream: xoshiro256++, its state seeded as rand's
/// `Xoshiro256PlusPlus::seed_from_u64` and stepped for all lanes at once by [`LaneRng`]. Measured
/// against ChaCha8 (rand_chacha, and rand's SIMD chacha20) with rand_distr's ziggurat
/// StandardNormal, seeding included: 3.4 ns per normal against 4.8–4.9 ns (docs/architecture.md).
pub type TrialRng = Xoshiro256PlusPlus;

/// What a trial stream is drawn for. Separate streams keep the noise of a trial the same whether
/// or not the plant switches modes or carries multiplicative factors, and let a lane draw step by
/// step without fixing how the three kinds interleave.
#[derive(Clone, Copy, Debug)]
pub enum Stream {
    Noise = 0,
    Modes = 1,
    Factors = 2,
}

/// The random stream `purpose` of one trial. It depends on (seed, scenario, trial, purpose) only,
/// never on the thread or the block that runs it, so results are identical for any thread count.
/// SplitMix64 (a bijection of u64) mixes them: distinct (trial, purpose) give distinct 64-bit
/// seeds, which xoshiro's own SplitMix64 expansion turns into 256-bit states.
pub fn trial_rng(seed: u64, scenario: usize, trial: u64, purpose: Stream) -> TrialRng {
    TrialRng::seed_from_u64(trial_seed(seed, scenario, trial, purpose))
}

/// The 64-bit seed of [`trial_rng`]'s stream, which [`LaneRng::seed_lane`] expands as it does.
pub(crate) fn trial_seed(seed: u64, scenario: usize, trial: u64, purpose: Stream) -> u64 {
    let base = splitmix(seed ^ splitmix(scenario as u64 + 1));
    splitmix(base ^ splitmix(trial.wrapping_mul(4) + purpose as u64))
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
    /// Deterministic part of w\[k] (column k), if any: energy-bounded disturbances.
    w_mean: Option<Mat>,
    /// Inputs drawn jointly over the horizon instead of block by block, and the columns each
    /// panel of its factor's rows needs.
    joint: Option<JointInput>,
    joint_widths: Vec<usize>,
    /// The joint input's recursion, where it has one that draws what its factor does.
    shaping: Option<Shaping>,
    /// The Markov chain of the plant's modes (dropouts included), as [`pick`] reads it: per mode
    /// the cumulative sums of its transition row, then those of the initial distribution.
    chain: Option<Vec<Vec<f64>>>,
    /// The multiplicative factors' ζ_i(k) (seed 003 (3.1)).
    factors: Vec<StandardDraw>,
}

/// One block's draws, step by step: x0 after [`NoiseSampler::start`], w\[k], θ\[k] and ζ_i(k) after
/// [`NoiseSampler::step`]`(k)`. Lanes at and beyond `active` hold stale but finite values.
pub struct LaneDraw {
    /// Each lane's noise, mode and factor streams ([`Stream`]).
    noise: Box<LaneRng>,
    mode_rng: Box<LaneRng>,
    factor_rng: Box<LaneRng>,
    active: usize,
    pub x0: Vec<Row>,
    pub w: Vec<Row>,
    /// θ\[k] per lane (for dropouts 0 = lost, 1 = arrived).
    pub modes: [u32; LANES],
    /// ζ_i(k): row i is factor i.
    pub zeta: Vec<Row>,
    u: Vec<Row>,
    uj: Vec<Row>,
    /// A Gaussian batch's rejected lanes, one word per row ([`ziggurat::normal_batch`]).
    masks: Vec<u64>,
    xi: Vec<Row>,
    /// The shaping recursion's state and the next one.
    shape_m: Vec<Row>,
    shape_next: Vec<Row>,
}

/// One trial's draws, all steps: the initial state and w\[k] as column k of `w` (for tests and
/// the discrepancy pilot; drawn by the block code with one lane).
pub struct TrialDraw {
    pub x0: Vector,
    pub w: Mat,
    /// θ\[k], the plant's mode at step k (all 0 for a plant that does not switch).
    pub modes: Vec<usize>,
    /// ζ_i(k): row i is factor i of the plant's multiplicative noise.
    pub zeta: Mat,
    lanes: LaneDraw,
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
            joint_widths: Vec::new(),
            shaping: None,
            chain: plant.modes().map(|m| cumulative(&m)),
            factors: plant.factors.iter().map(|f| f.shape.sampler()).collect(),
        }
    }

    /// Draws ξ = col(x0 − E x0, w\[0..N−1]) jointly (w\[N] = 0) instead of independently.
    pub fn with_joint(mut self, joint: Option<JointInput>) -> Self {
        self.joint_widths = joint.as_ref().map_or_else(Vec::new, JointInput::panel_widths);
        self.joint = joint;
        self
    }

    /// Draws the joint input's correlated ξ by `shaping` instead of its factor (the same ξ to
    /// rounding: [`Shaping::matching`]).
    pub fn with_shaping(mut self, shaping: Option<Shaping>) -> Self {
        self.shaping = shaping;
        self
    }

    /// Whether the joint input is drawn by its recursion rather than its factor.
    pub fn is_shaped(&self) -> bool {
        self.shaping.is_some()
    }

    /// Adds a deterministic sequence to w (column k is added to w\[k]).
    pub(crate) fn with_mean(mut self, w_mean: Option<Mat>) -> Self {
        self.w_mean = w_mean;
        self
    }

    pub fn lanes(&self) -> LaneDraw {
        let jd = self.joint.as_ref().map_or(0, JointInput::dim);
        LaneDraw {
            noise: LaneRng::new(),
            mode_rng: LaneRng::new(),
            factor_rng: LaneRng::new(),
            active: 0,
            x0: lanes::zeros(self.m0.len()),
            w: lanes::zeros(self.lw.nrows()),
            modes: [0; LANES],
            zeta: lanes::zeros(self.factors.len()),
            u: lanes::zeros(self.l0.ncols().max(self.lw.ncols())),
            uj: lanes::zeros(jd),
            masks: vec![0; self.l0.ncols().max(self.lw.ncols()).max(jd)],
            xi: lanes::zeros(jd),
            shape_m: lanes::zeros(self.shaping.as_ref().map_or(0, Shaping::states)),
            shape_next: lanes::zeros(self.shaping.as_ref().map_or(0, Shaping::states)),
        }
    }

    pub fn workspace(&self) -> TrialDraw {
        TrialDraw {
            x0: Vector::zeros(self.m0.len()),
            w: Mat::zeros(self.lw.nrows(), self.steps),
            modes: vec![0; self.steps],
            zeta: Mat::zeros(self.factors.len(), self.steps),
            lanes: self.lanes(),
        }
    }

    /// Starts the block of trials first..first+active: seeds each lane's streams (the mode and
    /// factor streams only where the plant draws from them) and draws x0 (and, for a joint input,
    /// the whole ξ).
    pub fn start(&self, seed: u64, scenario: usize, first: u64, active: usize, out: &mut LaneDraw) {
        match lanes::build() {
            // SAFETY: build() names only a build whose features the processor has.
            #[cfg(target_arch = "x86_64")]
            lanes::Build::Avx512 => unsafe { self.start_avx512(seed, scenario, first, active, out) },
            #[cfg(target_arch = "x86_64")]
            lanes::Build::Avx2 => unsafe { self.start_avx2(seed, scenario, first, active, out) },
            // SAFETY: the baseline build runs everywhere.
            _ => unsafe { self.start_lanes(seed, scenario, first, active, out, Build::Baseline) },
        }
    }

    /// [`NoiseSampler::start`] compiled for AVX-512 (the same bits as the baseline build).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2")]
    unsafe fn start_avx512(&self, seed: u64, scenario: usize, first: u64, active: usize, out: &mut LaneDraw) {
        // SAFETY: this function runs only where the processor has AVX-512.
        unsafe { self.start_lanes(seed, scenario, first, active, out, Build::Avx512) }
    }

    /// [`NoiseSampler::start`] compiled for AVX2 (the same bits as the baseline build).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn start_avx2(&self, seed: u64, scenario: usize, first: u64, active: usize, out: &mut LaneDraw) {
        // SAFETY: this function runs only where the processor has AVX2.
        unsafe { self.start_lanes(seed, scenario, first, active, out, Build::Avx2) }
    }

    /// The body of the build-specific entry points.
    ///
    /// # Safety
    /// The processor has `build`'s features.
    #[inline(always)]
    unsafe fn start_lanes(
        &self,
        seed: u64,
        scenario: usize,
        first: u64,
        active: usize,
        out: &mut LaneDraw,
        build: Build,
    ) {
        debug_assert!(active <= LANES);
        out.active = active;
        for l in 0..active {
            let t = first + l as u64;
            out.noise.seed_lane(l, trial_seed(seed, scenario, t, Stream::Noise));
            if self.chain.is_some() {
                out.mode_rng.seed_lane(l, trial_seed(seed, scenario, t, Stream::Modes));
            }
            if !self.factors.is_empty() {
                out.factor_rng.seed_lane(l, trial_seed(seed, scenario, t, Stream::Factors));
            }
        }
        if let Some(j) = &self.joint {
            match j {
                JointInput::Correlated { .. } => unsafe {
                    self.standard(&mut out.noise, active, &mut out.uj, &mut out.masks, build)
                },
                JointInput::Ellipsoid { .. } => {
                    unsafe { ziggurat::normal_batch(&mut out.noise, &mut out.uj, &mut out.masks, build) };
                    j.scale_lanes(&mut out.noise, active, &mut out.uj);
                }
                JointInput::Fixed { .. } => {}
            }
            match &self.shaping {
                Some(sh) => sh.map(&out.uj, &mut out.xi, &mut out.shape_m, &mut out.shape_next),
                None => j.map(&self.joint_widths, &out.uj, &mut out.xi),
            }
            let n = self.m0.len();
            out.x0.copy_from_slice(&out.xi[..n]);
            lanes::add_vector(1.0, self.m0.as_slice(), &mut out.x0);
            return;
        }
        let u0 = &mut out.u[..self.l0.ncols()];
        // SAFETY: the caller guarantees `build`.
        unsafe { self.standard(&mut out.noise, active, u0, &mut out.masks, build) };
        lanes::gemm(&self.l0, u0, false, &mut out.x0);
        lanes::add_vector(1.0, self.m0.as_slice(), &mut out.x0);
    }

    /// u\[i]\[l] i.i.d. of the shape, lane l from its noise stream: Gaussian rows as one batch for
    /// all lanes at once ([`ziggurat::normal_batch`]), other shapes lane by lane (row 0 first).
    /// `masks` is the batch's scratch.
    ///
    /// # Safety
    /// The processor has `build`'s features.
    #[inline(always)]
    unsafe fn standard(&self, rng: &mut LaneRng, active: usize, u: &mut [Row], masks: &mut [u64], build: Build) {
        match self.draw {
            // SAFETY: the caller guarantees `build`.
            StandardDraw::Gaussian => unsafe { ziggurat::normal_batch(rng, u, masks, build) },
            _ => {
                for l in 0..active {
                    self.draw.fill(&mut rng.lane(l), u.iter_mut().map(|row| &mut row[l]));
                }
            }
        }
    }

    /// Draws step k of the block: w\[k], then θ\[k] (θ\[0] ~ p(0), θ\[k] ~ Π[θ\[k−1], ·], seed 001 (11))
    /// and ζ_i(k), each from its own stream.
    pub fn step(&self, k: usize, out: &mut LaneDraw) {
        match lanes::build() {
            // SAFETY: build() names only a build whose features the processor has.
            #[cfg(target_arch = "x86_64")]
            lanes::Build::Avx512 => unsafe { self.step_avx512(k, out) },
            #[cfg(target_arch = "x86_64")]
            lanes::Build::Avx2 => unsafe { self.step_avx2(k, out) },
            // SAFETY: the baseline build runs everywhere.
            _ => unsafe { self.step_lanes(k, out, Build::Baseline) },
        }
    }

    /// [`NoiseSampler::step`] compiled for AVX-512 (the same bits as the baseline build).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2")]
    unsafe fn step_avx512(&self, k: usize, out: &mut LaneDraw) {
        // SAFETY: this function runs only where the processor has AVX-512.
        unsafe { self.step_lanes(k, out, Build::Avx512) }
    }

    /// [`NoiseSampler::step`] compiled for AVX2 (the same bits as the baseline build).
    #[cfg(target_arch = "x86_64")]
    #[target_feature(enable = "avx2")]
    unsafe fn step_avx2(&self, k: usize, out: &mut LaneDraw) {
        // SAFETY: this function runs only where the processor has AVX2.
        unsafe { self.step_lanes(k, out, Build::Avx2) }
    }

    /// The body of the build-specific entry points.
    ///
    /// # Safety
    /// The processor has `build`'s features.
    #[inline(always)]
    unsafe fn step_lanes(&self, k: usize, out: &mut LaneDraw, build: Build) {
        let active = out.active;
        match &self.joint {
            Some(_) => {
                let n = self.m0.len();
                let nw = out.w.len();
                // w[N] is part of ξ only when ξ is long enough (anisotropic inputs: lw = mw(N+1)).
                if n + (k + 1) * nw <= out.xi.len() {
                    out.w.copy_from_slice(&out.xi[n + k * nw..n + (k + 1) * nw]);
                } else {
                    out.w.fill([0.0; LANES]);
                }
            }
            None => {
                let u = &mut out.u[..self.lw.ncols()];
                // SAFETY: the caller guarantees `build`.
                unsafe { self.standard(&mut out.noise, active, u, &mut out.masks, build) };
                // The simulation's lanes per pass in each build (the same bits either way).
                if build == Build::Avx512 {
                    lanes::apply_in::<{ lanes::WIDE_CHUNK }>(&self.lw, u, false, &mut out.w);
                } else {
                    lanes::apply(&self.lw, u, false, &mut out.w);
                }
                if let Some(m) = &self.w_mean {
                    lanes::add_vector(1.0, &m.as_slice()[k * m.nrows()..(k + 1) * m.nrows()], &mut out.w);
                }
            }
        }
        if let Some(chain) = &self.chain {
            // Every lane steps (those beyond `active` are never read): one row of the streams'
            // outputs, then each lane's pick without a branch.
            let mut x = [0; LANES];
            out.mode_rng.next_row(&mut x);
            let first = chain.len() - 1;
            for (th, x) in out.modes.iter_mut().zip(&x) {
                *th = pick(*x, &chain[if k == 0 { first } else { *th as usize }]);
            }
        }
        for (i, f) in self.factors.iter().enumerate() {
            for l in 0..active {
                out.zeta[i][l] = f.draw(&mut out.factor_rng.lane(l));
            }
        }
    }

    /// Trial `trial`'s draws over the whole horizon, exactly as the engine draws them in its block.
    pub fn draw_trial(&self, seed: u64, scenario: usize, trial: u64, out: &mut TrialDraw) {
        let b = &mut out.lanes;
        self.start(seed, scenario, trial, 1, b);
        for (v, r) in out.x0.iter_mut().zip(&b.x0) {
            *v = r[0];
        }
        for k in 0..self.steps {
            self.step(k, b);
            for (i, r) in b.w.iter().enumerate() {
                out.w[(i, k)] = r[0];
            }
            out.modes[k] = b.modes[0] as usize;
            for (i, r) in b.zeta.iter().enumerate() {
                out.zeta[(i, k)] = r[0];
            }
        }
    }

    /// Number of standardized scalars one trial consumes.
    pub(crate) fn scalars_per_trial(&self) -> usize {
        self.l0.ncols() + self.steps * (self.lw.ncols() + self.factors.len())
    }
}

/// Per mode the cumulative sums of its row of the transition matrix, then those of the initial
/// distribution, each summed in order as [`pick`]'s comparisons need them.
fn cumulative(m: &Modes) -> Vec<Vec<f64>> {
    let sums = |p: &mut dyn Iterator<Item = f64>| {
        let mut acc = 0.0;
        p.map(|v| {
            acc += v;
            acc
        })
        .collect()
    };
    let mut out: Vec<Vec<f64>> = m.transition.row_iter().map(|r| sums(&mut r.iter().copied())).collect();
    out.push(sums(&mut m.initial.iter().copied()));
    out
}

/// The index a stream's output `x` draws from the cumulative probabilities `cum`: the first i
/// with u < cum\[i] for u = rand's uniform on [0, 1) from x (its 53 high bits), the last index when
/// rounding leaves u above them all. The sums never decrease, so that index is the number of sums
/// before the last that are ≤ u: a count instead of a branch per lane, the same index.
#[inline(always)]
fn pick(x: u64, cum: &[f64]) -> u32 {
    let u = (x >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
    cum[..cum.len() - 1].iter().map(|&a| (a <= u) as u32).sum()
}
