//! The plant of SPEC §0 on a finite horizon k = 0..N:
//!
//!     x[k+1] = A x[k] + B w[k] + r[k],   x[0] ~ (x0_mean, S_x0)
//!     y[k]   = C[k] x[k] + D w[k]         (no measurement before `first_measurement`; C[k] = C
//!                                          unless the file gives one matrix per step)
//!     z[k]   = Cz x[k] + Dz w[k]
//!
//! `w` stacks named noise blocks (seed 000: `w = (ε, w_meas)`, `B = [b 0]`, `D = [0 d]`); each block
//! has its own covariance, so an uncertainty set can constrain one block and leave the others fixed.
//!
//! Measurement dropouts (seed 003 (4.30), SPEC §0): with `arrival = Some(p)` the measurement is
//! y[k] = λ[k] C x[k] + D w[k] with λ[k] ~ Bernoulli(p) independent over k and of the noise, i.e.
//! C[k] = p C + (λ[k] − p) C: a multiplicative noise ζ = (λ − p)/sqrt(p(1 − p)) on C.

use crate::linalg::{Mat, Vector, block_diag};

#[derive(Clone, Debug)]
pub struct Plant {
    /// N: the horizon; steps run k = 0..=N.
    pub horizon: usize,
    pub a: Mat,
    pub b: Mat,
    pub c: Mat,
    pub d: Mat,
    pub cz: Mat,
    pub dz: Mat,
    pub x0_mean: Vector,
    /// Steps k < first_measurement have no measurement (seed 000 measures from n = 1).
    pub first_measurement: usize,
    /// r[k] for k = 0..N-1 (all zero when the file gives none). The filters know it.
    pub known_input: Vec<Vector>,
    /// Names and sizes of the blocks of w, in the order they are stacked.
    pub noise_blocks: Vec<(String, usize)>,
    /// The summed error J counts steps k ≥ sum_from (seed 000 sums n = 1..N; default 0).
    pub sum_from: usize,
    /// Time-varying measurement matrices C[k], k = 0..N (regressors Φ[k] of seed 002 §5), or empty
    /// when C is constant.
    pub c_steps: Vec<Mat>,
    /// Probability p that a measurement arrives (λ[k] = 1); None when every measurement arrives.
    pub arrival: Option<f64>,
    c_none: Mat,
    d_none: Mat,
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
        let c_none = Mat::zeros(c.nrows(), c.ncols());
        let d_none = Mat::zeros(d.nrows(), d.ncols());
        Plant {
            horizon,
            a,
            b,
            c,
            d,
            cz,
            dz,
            x0_mean,
            first_measurement,
            known_input,
            noise_blocks,
            sum_from: 0,
            c_steps: Vec::new(),
            arrival: None,
            c_none,
            d_none,
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
    /// Whether step k counts in the summed error J.
    pub fn counts(&self, k: usize) -> bool {
        k >= self.sum_from
    }
    pub fn measured(&self, k: usize) -> bool {
        k >= self.first_measurement
    }
    /// C[k]: zero before the first measurement.
    pub fn c_at(&self, k: usize) -> &Mat {
        match (self.measured(k), self.c_steps.get(k)) {
            (false, _) => &self.c_none,
            (true, Some(c)) => c,
            (true, None) => &self.c,
        }
    }
    /// p(1 − p), the variance of λ[k] (0 without dropouts).
    pub fn dropout_variance(&self) -> f64 {
        self.arrival.map_or(0.0, |p| p * (1.0 - p))
    }
    /// E λ[k] = p (1 without dropouts).
    pub fn arrival_mean(&self) -> f64 {
        self.arrival.unwrap_or(1.0)
    }
    /// D[k]: zero before the first measurement.
    pub fn d_at(&self, k: usize) -> &Mat {
        if self.measured(k) { &self.d } else { &self.d_none }
    }
    /// r[k], or None when the plant has no known input.
    pub fn r_at(&self, k: usize) -> Option<&Vector> {
        self.known_input.get(k)
    }
    /// Names of the covariance blocks: "x0" first, then the noise blocks of w.
    pub fn block_names(&self) -> Vec<&str> {
        std::iter::once("x0").chain(self.noise_blocks.iter().map(|(n, _)| n.as_str())).collect()
    }
}

/// One covariance per block: `blocks[0]` is the covariance of x0, `blocks[1..]` those of the noise
/// blocks of w, in the plant's order. The noise is white in time with W = blockdiag(blocks[1..]).
#[derive(Clone, Debug, PartialEq)]
pub struct Covariances {
    pub blocks: Vec<Mat>,
}

impl Covariances {
    pub fn x0(&self) -> &Mat {
        &self.blocks[0]
    }
    /// W = cov w[k] = blockdiag of the noise blocks.
    pub fn w(&self) -> Mat {
        let refs: Vec<&Mat> = self.blocks[1..].iter().collect();
        block_diag(&refs)
    }
}
