//! The plant of docs/math.md §0 on a finite horizon k = 0..N:
//!
//! ```text
//! x[k+1] = A x[k] + B w[k] + r[k],   x[0] ~ (x0_mean, S_x0)
//! y[k]   = C[k] x[k] + D w[k]         (no measurement before `first_measurement`; C[k] = C
//!                                      unless the file gives one matrix per step)
//! z[k]   = Cz x[k] + Dz w[k]
//! ```
//!
//! `w` stacks named noise blocks (seed 000: `w = (ε, w_meas)`, `B = [b 0]`, `D = [0 d]`); each block
//! has its own covariance, so an uncertainty set can constrain one block and leave the others fixed.
//!
//! Markov-switching matrices (seed 001, docs/math.md §3): with `modes` the plant uses A_θ, B_θ, C_θ, D_θ of
//! the mode θ\[k] of a finite Markov chain with transition matrix Π (Π\[s]\[k] = P(θ\[n+1] = k | θ\[n] = s))
//! and initial distribution p(0), independent of x0 and of the noise.
//!
//! Measurement dropouts (seed 003 (4.30), docs/math.md §0) are the two-mode case of independent modes: with
//! [`Measurement::Dropout`] the measurement is y\[k] = λ\[k] C x\[k] + D w\[k], λ\[k] ~ Bernoulli(p),
//! i.e. mode 0 ("lost", C_0 = 0) with probability 1 − p and mode 1 ("arrived", C_1 = C) with
//! probability p, every row of Π equal to (1 − p, p). Equivalently C\[k] = p C + (λ\[k] − p) C, the
//! multiplicative noise form the anisotropic family is written in. The modes of a dropout plant
//! are derived from p and the plant's matrices when asked for, never stored beside them.

use std::borrow::Cow;

use crate::error::{Error, Result};
use crate::model::shape::Shape;
use crate::numerics::linalg::{Mat, Vector, block_diag, digest_mat, hex};

/// How the measurement depends on a random mode (docs/math.md §0, §3).
#[derive(Clone, Debug)]
pub enum Measurement {
    /// y\[k] = C\[k] x\[k] + D w\[k] at every measured step.
    Always,
    /// Seed 003 (4.30): the measurement arrives with probability `arrival`, independently over k.
    Dropout { arrival: f64 },
    /// Seed 001: the matrices switch with a Markov chain.
    Markov(Modes),
}

/// Information pattern (docs/math.md §0): filtering lets ẑ\[k] use y\[k]; prediction uses y\[0..k-1] only.
#[derive(Clone, Copy, Debug, serde::Deserialize, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Pattern {
    Filtering,
    Prediction,
}

/// A plant matrix over the horizon: the same at every step, or one per step k = 0..N (the
/// time-varying plant of seed 003 (3.1) and seed 002 §5). Read it at a step with [`Steps::at`].
#[derive(Clone, Debug, PartialEq)]
pub struct Steps(Vec<Mat>);

impl Steps {
    pub fn constant(m: Mat) -> Self {
        Steps(vec![m])
    }
    /// One matrix per step k = 0..N (every one of the same shape).
    pub fn per_step(ms: Vec<Mat>) -> Self {
        debug_assert!(!ms.is_empty() && ms.iter().all(|m| m.shape() == ms[0].shape()));
        Steps(ms)
    }
    /// The matrix of step k.
    #[inline]
    pub fn at(&self, k: usize) -> &Mat {
        &self.0[if self.0.len() == 1 { 0 } else { k }]
    }
    /// Whether the matrix changes over the steps.
    pub fn varies(&self) -> bool {
        self.0.len() > 1
    }
    pub fn nrows(&self) -> usize {
        self.0[0].nrows()
    }
    pub fn ncols(&self) -> usize {
        self.0[0].ncols()
    }
    /// The same steps with `f` applied to every matrix.
    pub fn map(&self, f: impl Fn(&Mat) -> Mat) -> Steps {
        Steps(self.0.iter().map(f).collect())
    }
    /// Every distinct matrix (one for a constant, one per step otherwise).
    pub fn all(&self) -> &[Mat] {
        &self.0
    }
}

/// One multiplicative noise factor of seed 003 (2.1)/(3.1): a scalar ζ(k), zero mean and unit
/// variance, independent over k, of the other factors, of x0, w and the modes, entering every matrix
/// it names: A(k) = Ā(k) + Σ_i ζ_i(k) A_i(k), and likewise B, C, D, Cz, Dz. One ζ may enter several
/// matrices (the shared factors of (2.1)); a matrix it does not name it leaves alone.
#[derive(Clone, Debug)]
pub struct Factor {
    pub name: String,
    /// The distribution of ζ (scaled to unit variance).
    pub shape: Shape,
    pub a: Option<Steps>,
    pub b: Option<Steps>,
    pub c: Option<Steps>,
    pub d: Option<Steps>,
    pub cz: Option<Steps>,
    pub dz: Option<Steps>,
}

#[derive(Clone, Debug)]
pub struct Plant {
    /// N: the horizon; steps run k = 0..=N.
    pub horizon: usize,
    pub a: Steps,
    pub b: Steps,
    /// C\[k] where a measurement is taken (see [`Plant::c_at`] for the steps before the first).
    pub c: Steps,
    pub d: Steps,
    pub cz: Steps,
    pub dz: Steps,
    pub x0_mean: Vector,
    /// Steps k < first_measurement have no measurement (seed 000 measures from n = 1).
    pub first_measurement: usize,
    /// r\[k] for k = 0..N-1 (all zero when the file gives none). The filters know it.
    pub known_input: Vec<Vector>,
    /// Names and sizes of the blocks of w, in the order they are stacked.
    pub noise_blocks: Vec<(String, usize)>,
    /// The summed error J counts steps k ≥ sum_from (seed 000 sums n = 1..N; default 0).
    pub sum_from: usize,
    /// Whether measurements drop out or the matrices switch.
    pub measurement: Measurement,
    /// The multiplicative noise factors (seed 003 (3.1)); the matrices above are their means.
    pub factors: Vec<Factor>,
}

impl Plant {
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        horizon: usize,
        a: Mat,
        b: Mat,
        c: Mat,
        d: Mat,
        cz: Mat,
        dz: Mat,
        x0_mean: Vector,
        first_measurement: usize,
        known_input: Vec<Vector>,
        noise_blocks: Vec<(String, usize)>,
    ) -> Self {
        Plant {
            horizon,
            a: Steps::constant(a),
            b: Steps::constant(b),
            c: Steps::constant(c),
            d: Steps::constant(d),
            cz: Steps::constant(cz),
            dz: Steps::constant(dz),
            x0_mean,
            first_measurement,
            known_input,
            noise_blocks,
            sum_from: 0,
            measurement: Measurement::Always,
            factors: Vec::new(),
        }
    }
    pub fn nx(&self) -> usize {
        self.a.nrows()
    }
    pub fn nw(&self) -> usize {
        self.b.ncols()
    }
    pub fn ny(&self) -> usize {
        self.c.nrows()
    }
    pub fn nz(&self) -> usize {
        self.cz.nrows()
    }
    pub fn steps(&self) -> usize {
        self.horizon + 1
    }
    /// The SHA-256 (hex) of the plant's model: its sizes and, at every step and in every mode, A,
    /// B, C, D, Cz and Dz as used there (docs/math.md §0, §3). Not the noise, the modes' chain or
    /// the known input: a filter designed for one model may be judged under other statistics. A
    /// filter taken from an earlier run (`from_run`) must come from a plant of the same digest.
    pub fn model_digest(&self) -> String {
        use sha2::Digest;
        let mut h = sha2::Sha256::new();
        for k in 0..self.steps() {
            for s in 0..self.n_modes() {
                for m in [self.a_of(k, s), self.b_of(k, s), &self.c_of(k, s), &self.d_of(k, s)] {
                    digest_mat(&mut h, m);
                }
            }
            digest_mat(&mut h, self.cz_at(k));
            digest_mat(&mut h, self.dz_at(k));
        }
        hex(&h.finalize())
    }
    /// Whether step k counts in the summed error J.
    pub fn counts(&self, k: usize) -> bool {
        k >= self.sum_from
    }
    pub fn measured(&self, k: usize) -> bool {
        k >= self.first_measurement
    }
    /// Whether the plant's matrices are random: modes, dropouts or multiplicative noise. A
    /// deterministic operator from the noise to the error (Ψ, a worst disturbance sequence, the
    /// block-diagonal fast path) exists only when they are not.
    pub(crate) fn random_matrices(&self) -> bool {
        self.switches() || !self.factors.is_empty()
    }
    /// Whether any matrix of the plant changes over the steps.
    pub fn time_varying(&self) -> bool {
        [&self.a, &self.b, &self.c, &self.d, &self.cz, &self.dz].iter().any(|s| s.varies())
    }
    /// A\[k].
    #[inline]
    pub fn a_at(&self, k: usize) -> &Mat {
        self.a.at(k)
    }
    /// B\[k].
    #[inline]
    pub fn b_at(&self, k: usize) -> &Mat {
        self.b.at(k)
    }
    /// Cz\[k].
    #[inline]
    pub fn cz_at(&self, k: usize) -> &Mat {
        self.cz.at(k)
    }
    /// Dz\[k].
    #[inline]
    pub(crate) fn dz_at(&self, k: usize) -> &Mat {
        self.dz.at(k)
    }
    /// C\[k]: zero before the first measurement.
    pub fn c_at(&self, k: usize) -> Cow<'_, Mat> {
        if self.measured(k) {
            Cow::Borrowed(self.c.at(k))
        } else {
            Cow::Owned(Mat::zeros(self.c.nrows(), self.c.ncols()))
        }
    }
    /// D\[k]: zero before the first measurement.
    pub fn d_at(&self, k: usize) -> Cow<'_, Mat> {
        if self.measured(k) {
            Cow::Borrowed(self.d.at(k))
        } else {
            Cow::Owned(Mat::zeros(self.d.nrows(), self.d.ncols()))
        }
    }
    /// p, the probability that a measurement arrives, for a plant with dropouts.
    pub fn arrival(&self) -> Option<f64> {
        match self.measurement {
            Measurement::Dropout { arrival } => Some(arrival),
            _ => None,
        }
    }
    /// p(1 − p), the variance of λ\[k] (0 without dropouts).
    pub(crate) fn dropout_variance(&self) -> f64 {
        self.arrival().map_or(0.0, |p| p * (1.0 - p))
    }
    /// E λ\[k] = p (1 without dropouts).
    pub(crate) fn arrival_mean(&self) -> f64 {
        self.arrival().unwrap_or(1.0)
    }
    /// Makes the measurement arrive with probability p: the two modes of the module docs.
    pub fn set_arrival(&mut self, p: f64) {
        self.measurement = Measurement::Dropout { arrival: p };
    }
    /// The modes: a Markov plant's own, a dropout plant's two (derived from p), None otherwise.
    pub fn modes(&self) -> Option<Cow<'_, Modes>> {
        match &self.measurement {
            Measurement::Always => None,
            Measurement::Dropout { arrival: p } => Some(Cow::Owned(Modes {
                names: vec!["lost".into(), "arrived".into()],
                transition: Mat::from_row_slice(2, 2, &[1.0 - p, *p, 1.0 - p, *p]),
                initial: vec![1.0 - p, *p],
                a: vec![self.a.clone(); 2],
                b: vec![self.b.clone(); 2],
                c: vec![Steps::constant(Mat::zeros(self.c.nrows(), self.c.ncols())), self.c.clone()],
                d: vec![self.d.clone(); 2],
            })),
            Measurement::Markov(m) => Some(Cow::Borrowed(m)),
        }
    }
    /// Whether the matrices depend on a random mode (dropouts included).
    pub(crate) fn switches(&self) -> bool {
        !matches!(self.measurement, Measurement::Always)
    }
    /// Π, the transition matrix of the modes (\[1] for a plant that does not switch).
    pub fn transition(&self) -> Mat {
        match &self.measurement {
            Measurement::Always => Mat::identity(1, 1),
            Measurement::Dropout { arrival: p } => Mat::from_row_slice(2, 2, &[1.0 - p, *p, 1.0 - p, *p]),
            Measurement::Markov(m) => m.transition.clone(),
        }
    }
    /// p(0), the distribution of the first mode ([1] for a plant that does not switch).
    fn initial(&self) -> Vec<f64> {
        match &self.measurement {
            Measurement::Always => vec![1.0],
            Measurement::Dropout { arrival: p } => vec![1.0 - p, *p],
            Measurement::Markov(m) => m.initial.clone(),
        }
    }
    /// Number of modes (1 for a plant that does not switch).
    pub fn n_modes(&self) -> usize {
        match &self.measurement {
            Measurement::Always => 1,
            Measurement::Dropout { .. } => 2,
            Measurement::Markov(m) => m.names.len(),
        }
    }
    /// A_θ\[k] (a Markov plant's modes have constant matrices).
    pub fn a_of(&self, k: usize, mode: usize) -> &Mat {
        match &self.measurement {
            Measurement::Markov(m) => m.a[mode].at(k),
            _ => self.a.at(k),
        }
    }
    /// B_θ\[k].
    pub fn b_of(&self, k: usize, mode: usize) -> &Mat {
        match &self.measurement {
            Measurement::Markov(m) => m.b[mode].at(k),
            _ => self.b.at(k),
        }
    }
    /// C_θ\[k]: zero before the first measurement and when a measurement is lost.
    pub fn c_of(&self, k: usize, mode: usize) -> Cow<'_, Mat> {
        match &self.measurement {
            Measurement::Markov(m) if self.measured(k) => Cow::Borrowed(m.c[mode].at(k)),
            Measurement::Dropout { .. } if mode == 0 => Cow::Owned(Mat::zeros(self.c.nrows(), self.c.ncols())),
            _ => self.c_at(k),
        }
    }
    /// D_θ\[k]: zero before the first measurement.
    pub fn d_of(&self, k: usize, mode: usize) -> Cow<'_, Mat> {
        match &self.measurement {
            Measurement::Markov(m) if self.measured(k) => Cow::Borrowed(m.d[mode].at(k)),
            _ => self.d_at(k),
        }
    }
    /// p(k) = P(θ\[k] = ·) for k = 0..N (\[1] for a plant that does not switch).
    pub(crate) fn mode_probabilities(&self) -> Vec<Vec<f64>> {
        let (pi, mut p) = (self.transition(), self.initial());
        let mut out = Vec::with_capacity(self.steps());
        for _ in 0..self.steps() {
            let next = (0..p.len()).map(|k| (0..p.len()).map(|s| p[s] * pi[(s, k)]).sum()).collect();
            out.push(std::mem::replace(&mut p, next));
        }
        out
    }
    /// Whether θ\[k] are independent over k with one distribution (every row of Π equal to p(0)).
    pub(crate) fn independent_modes(&self) -> bool {
        let (pi, p0) = (self.transition(), self.initial());
        (0..pi.nrows()).all(|s| (0..p0.len()).all(|k| pi[(s, k)] == p0[k]))
    }
    /// r\[k], or None when the plant has no known input.
    pub fn r_at(&self, k: usize) -> Option<&Vector> {
        self.known_input.get(k)
    }
    /// Names of the covariance blocks: "x0" first, then the noise blocks of w.
    pub fn block_names(&self) -> Vec<&str> {
        std::iter::once("x0").chain(self.noise_blocks.iter().map(|(n, _)| n.as_str())).collect()
    }
    /// The index of covariance block `name` in [`Self::block_names`]; the error names `key`.
    pub(crate) fn block_index(&self, key: &str, name: &str) -> Result<usize> {
        let names = self.block_names();
        names
            .iter()
            .position(|n| *n == name)
            .ok_or_else(|| Error::invalid(key, format!("unknown covariance block (known: {})", names.join(", "))))
    }
}

/// A finite Markov chain and the plant's matrices in each of its modes.
#[derive(Clone, Debug)]
pub struct Modes {
    pub names: Vec<String>,
    /// Π\[s]\[k] = P(θ\[n+1] = k | θ\[n] = s): rows sum to 1.
    pub transition: Mat,
    /// p(0) = P(θ\[0] = ·).
    pub initial: Vec<f64>,
    /// Each mode's matrices, per step on a time-varying plant (a mode that does not override a
    /// matrix has the plant's, varying as it does).
    pub a: Vec<Steps>,
    pub b: Vec<Steps>,
    pub c: Vec<Steps>,
    pub d: Vec<Steps>,
}

impl Modes {
    /// The stationary distribution of an ergodic chain: the distribution reached from every
    /// starting mode (power iteration on pᵀΠ); None if the starts do not all settle on one
    /// distribution (a reducible or periodic chain).
    pub fn stationary(&self) -> Option<Vec<f64>> {
        let q = self.initial.len().max(self.transition.nrows());
        let settle = |start: usize| -> Option<Vec<f64>> {
            let mut p = vec![0.0; q];
            p[start] = 1.0;
            for _ in 0..200_000 {
                let next: Vec<f64> = (0..q).map(|k| (0..q).map(|s| p[s] * self.transition[(s, k)]).sum()).collect();
                let diff = next.iter().zip(&p).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                p = next;
                if diff < 1e-15 {
                    return Some(p);
                }
            }
            None
        };
        let first = settle(0)?;
        for s in 1..q {
            let other = settle(s)?;
            if other.iter().zip(&first).any(|(a, b)| (a - b).abs() > 1e-9) {
                return None;
            }
        }
        Some(first)
    }
}

/// One covariance per block: `blocks[0]` is the covariance of x0, `blocks[1..]` those of the noise
/// blocks of w, in the plant's order. The noise is white in time with W = blockdiag(blocks\[1..]).
///
/// `varying` overrides a block's covariance step by step (index into `blocks`, one matrix per step
/// k = 0..N). Only the designs' surrogate of a deterministic disturbance with time-varying weights
/// uses it (seed 000 eq (39): r W_k⁻¹); the Kalman filter and the exact analysis honour it, the
/// other families and the sampler refuse or never see it.
#[derive(Clone, Debug, PartialEq)]
pub struct Covariances {
    pub blocks: Vec<Mat>,
    pub varying: Vec<(usize, Vec<Mat>)>,
}

impl Covariances {
    /// Constant covariances.
    pub fn new(blocks: Vec<Mat>) -> Self {
        Covariances { blocks, varying: Vec::new() }
    }
    /// Whether some block's covariance changes with the step.
    pub fn varies(&self) -> bool {
        !self.varying.is_empty()
    }
    /// W\[k]: [`Covariances::w`] with the step-k matrix of every varying block.
    pub fn w_at(&self, k: usize) -> Mat {
        if self.varying.is_empty() {
            return self.w();
        }
        let mut blocks: Vec<&Mat> = self.blocks[1..].iter().collect();
        for (b, steps) in &self.varying {
            blocks[b - 1] = &steps[k];
        }
        block_diag(&blocks)
    }
    pub fn x0(&self) -> &Mat {
        &self.blocks[0]
    }
    /// W = cov w\[k] = blockdiag of the noise blocks.
    pub fn w(&self) -> Mat {
        let refs: Vec<&Mat> = self.blocks[1..].iter().collect();
        block_diag(&refs)
    }
}
