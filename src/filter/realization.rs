//! The one form every filter compiles to (docs/math.md §0):
//!
//!     s[k+1] = Af[k] s[k] + Bf[k] y[k] + Gf[k] r[k]
//!     ẑ[k]   = Cf[k] s[k] + Df[k] y[k]
//!
//! with s\[0] = s0 and gains that do not depend on the data. The Monte Carlo engine and the exact
//! analysis only ever see this. A mode-indexed realization (seed 001) has one set of gains per
//! (step, mode) and at step k uses those of the mode θ\[k] it observes.
//!
//! A step whose gains are bit-identical to the step before's shares its allocation (a filter in its
//! steady state stores it once), so a long horizon of a time-invariant filter costs a pointer per
//! step, not five matrices (docs/architecture.md, "Memory"). Sharing changes no number: it is
//! decided on the bits, and every change goes through [`Realization::gains_mut`] or
//! [`Realization::map_gains`], which copy a shared step before writing it.

use std::sync::Arc;

use crate::error::{Error, Result};
use crate::model::plant::Pattern;
use crate::model::plant::Plant;
use crate::numerics::linalg::{Mat, Vector, digest_mat};

/// The gains of one step.
#[derive(Clone, Debug)]
pub struct Gains {
    pub af: Mat,
    pub bf: Mat,
    pub cf: Mat,
    pub df: Mat,
    /// How the known input r\[k] (plant-state sized) enters the filter state; may have no columns
    /// when the plant has no known input (a filter built on another model than the truth's).
    pub gf: Mat,
}

impl Gains {
    /// A one-step predictor of z = Cz x whose state estimates x: the given Af and Bf, ẑ = Cz s
    /// (Df = 0) and Gf = I (the known input enters as in the plant).
    pub fn predicting(af: Mat, bf: Mat, cz: &Mat) -> Self {
        let (n, nz, ny) = (af.nrows(), cz.nrows(), bf.ncols());
        Gains { af, bf, cf: cz.clone(), df: Mat::zeros(nz, ny), gf: Mat::identity(n, n) }
    }
    /// The predictor with gain K on y = C x + …: Af = A − K C, Bf = K, Cf = Cz (seed 000 eq (4),
    /// seed 001 eq (6), seed 002 eq (5.7)).
    pub fn predictor(a: &Mat, c: &Mat, k: &Mat, cz: &Mat) -> Self {
        Self::predicting(a - k * c, k.clone(), cz)
    }
    fn matrices(&self) -> [&Mat; 5] {
        [&self.af, &self.bf, &self.cf, &self.df, &self.gf]
    }
}

/// Whether two steps' gains are the same bits (shapes and every entry, so −0 ≠ 0 and NaN = NaN).
fn same_bits(a: &[Gains], b: &[Gains]) -> bool {
    let mat =
        |m: &Mat, n: &Mat| m.shape() == n.shape() && m.iter().zip(n.iter()).all(|(x, y)| x.to_bits() == y.to_bits());
    a.len() == b.len()
        && a.iter().zip(b).all(|(g, h)| g.matrices().into_iter().zip(h.matrices()).all(|(m, n)| mat(m, n)))
}

/// Appends step k's gains (one set per mode, or one) to `steps`, sharing step k − 1's allocation
/// when they are bit-identical: a recursion that builds a long horizon calls it step by step, so it
/// never holds the repeated steps.
pub fn push_step(steps: &mut Vec<Arc<Vec<Gains>>>, gains: Vec<Gains>) {
    match steps.last() {
        Some(prev) if same_bits(prev, &gains) => {
            let shared = Arc::clone(prev);
            steps.push(shared);
        }
        _ => steps.push(Arc::new(gains)),
    }
}

#[derive(Clone, Debug)]
pub struct Realization {
    pub s0: Vector,
    /// gains\[k]\[θ] for k = 0..=N (the Af, Bf, Gf of step N are never used): one entry per mode of
    /// the plant for a mode-indexed realization, a single entry (used in every mode) otherwise.
    /// Consecutive bit-identical steps share one allocation (module docs): change them with
    /// [`Realization::gains_mut`] or [`Realization::map_gains`] only.
    pub gains: Vec<Arc<Vec<Gains>>>,
    /// M: what the filter's state tracks, s\[k] ≈ M x\[k] (the identity for a state estimator), if
    /// the family declares it. The exact analysis and the Monte Carlo may then carry ε = s − M x
    /// instead of s, but only at steps and modes where they have checked that the realization
    /// keeps ε independent of x ([`crate::analysis::exact::error_form`]).
    pub tracks: Option<Mat>,
}

impl Realization {
    pub fn new(s0: Vector, steps: Vec<Gains>) -> Self {
        Realization::mode_indexed(s0, steps.into_iter().map(|g| vec![g]).collect())
    }
    /// A realization from steps already appended with [`push_step`], one set of gains per step.
    pub fn from_shared(s0: Vector, steps: Vec<Arc<Vec<Gains>>>) -> Self {
        Realization { s0, gains: steps, tracks: None }
    }
    /// A state estimator, one set of gains per step: its state tracks x (M = I).
    pub fn state_estimator(s0: Vector, steps: Vec<Gains>) -> Self {
        let n = s0.len();
        Realization::new(s0, steps).tracking(Mat::identity(n, n))
    }
    /// The same realization, declaring that its state estimates M x (see `tracks`).
    pub fn tracking(mut self, m: Mat) -> Self {
        self.tracks = Some(m);
        self
    }
    /// A realization that uses the gains of the observed mode: `by_mode[k][θ]`.
    pub fn mode_indexed(s0: Vector, by_mode: Vec<Vec<Gains>>) -> Self {
        let mut steps = Vec::with_capacity(by_mode.len());
        for g in by_mode {
            push_step(&mut steps, g);
        }
        Realization::from_shared(s0, steps)
    }
    /// The gains of step k (one set per mode, or one), to change: a step shared with its
    /// neighbours is copied first, so the change is to step k alone.
    pub fn gains_mut(&mut self, k: usize) -> &mut Vec<Gains> {
        Arc::make_mut(&mut self.gains[k])
    }
    /// Applies `f` to every set of gains of every step, once per shared allocation (the steps that
    /// share one are the same bits, so `f` gives them the same result and they stay shared).
    pub fn map_gains(&mut self, f: impl Fn(&mut Gains)) {
        let mut last: Option<(Arc<Vec<Gains>>, Arc<Vec<Gains>>)> = None;
        for slot in &mut self.gains {
            if let Some((old, new)) = &last
                && Arc::ptr_eq(slot, old)
            {
                *slot = Arc::clone(new);
                continue;
            }
            let old = Arc::clone(slot);
            let mut gains = (**slot).clone();
            gains.iter_mut().for_each(&f);
            *slot = Arc::new(gains);
            last = Some((old, Arc::clone(slot)));
        }
    }
    /// Whether the gains depend on the observed mode.
    /// Feeds every number of the realization (s0, every gain matrix of every step and mode, and
    /// the tracking map), with its shape, as bits into `h`: equal digests mean bit-equal filters.
    pub(crate) fn digest(&self, h: &mut impl sha2::Digest) {
        let mut mat = |m: &Mat| digest_mat(h, m);
        mat(&Mat::from_column_slice(self.s0.len(), 1, self.s0.as_slice()));
        for g in self.gains.iter().flat_map(|g| g.iter()) {
            for m in g.matrices() {
                mat(m);
            }
        }
        if let Some(m) = &self.tracks {
            mat(m);
        }
    }
    pub(crate) fn is_mode_indexed(&self) -> bool {
        self.gains.iter().any(|g| g.len() > 1)
    }
    /// The gains of step k of a realization that does not read the mode.
    pub fn step(&self, k: usize) -> &Gains {
        debug_assert!(self.gains[k].len() == 1, "step() of a mode-indexed realization");
        &self.gains[k][0]
    }
    /// The gains of step k in mode θ.
    #[inline]
    pub fn gains(&self, k: usize, mode: usize) -> &Gains {
        let g = &self.gains[k];
        if g.len() == 1 { &g[0] } else { &g[mode] }
    }

    pub fn ns(&self) -> usize {
        self.s0.len()
    }

    /// ẑ\[k] = Cf s + Df y in mode θ, written into `zhat`.
    #[inline]
    pub fn output(&self, k: usize, mode: usize, s: &Vector, y: &Vector, zhat: &mut Vector) {
        let g = self.gains(k, mode);
        zhat.gemv(1.0, &g.cf, s, 0.0);
        zhat.gemv(1.0, &g.df, y, 1.0);
    }

    /// s\[k+1] = Af s + Bf y + Gf r in mode θ, written into `next`.
    #[inline]
    pub fn advance(&self, k: usize, mode: usize, s: &Vector, y: &Vector, r: Option<&Vector>, next: &mut Vector) {
        let g = self.gains(k, mode);
        next.gemv(1.0, &g.af, s, 0.0);
        next.gemv(1.0, &g.bf, y, 1.0);
        if let Some(r) = r {
            next.gemv(1.0, &g.gf, r, 1.0);
        }
    }

    /// Checks sizes against the plant and, for prediction, that ẑ\[k] does not use y\[k].
    pub fn check(&self, name: &str, plant: &Plant, pattern: Pattern) -> Result<()> {
        if self.gains.len() != plant.steps() {
            return Err(Error::design(
                name,
                format!("{} steps of gains for a horizon of {}", self.gains.len(), plant.steps()),
            ));
        }
        let ns = self.ns();
        if self.gains.iter().any(|g| g.len() != 1 && g.len() != plant.n_modes()) {
            return Err(Error::design(name, format!("mode-indexed gains need {} modes at each step", plant.n_modes())));
        }
        for (k, g) in self.gains.iter().enumerate().flat_map(|(k, gs)| gs.iter().map(move |g| (k, g))) {
            let ok = g.af.shape() == (ns, ns)
                && g.bf.shape() == (ns, plant.ny())
                && g.cf.shape() == (plant.nz(), ns)
                && g.df.shape() == (plant.nz(), plant.ny())
                && g.gf.nrows() == ns
                && (g.gf.ncols() == plant.nx() || (g.gf.ncols() == 0 && plant.known_input.is_empty()));
            if !ok {
                return Err(Error::design(name, format!("gain sizes at step {k} do not fit the plant")));
            }
            if pattern == Pattern::Prediction && g.df.amax() != 0.0 {
                return Err(Error::design(name, format!("a predictor must have Df = 0, but step {k} uses y[k]")));
            }
        }
        Ok(())
    }
}
