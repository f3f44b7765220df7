//! The one form every filter compiles to (SPEC §0):
//!
//!     s[k+1] = Af[k] s[k] + Bf[k] y[k] + Gf[k] r[k]
//!     ẑ[k]   = Cf[k] s[k] + Df[k] y[k]
//!
//! with s[0] = s0 and gains that do not depend on the data. The Monte Carlo engine and the exact
//! analysis only ever see this. A mode-indexed realization (seed 001) has one set of gains per
//! (step, mode) and at step k uses those of the mode θ[k] it observes.

use crate::error::{Error, Result};
use crate::model::plant::Pattern;
use crate::model::plant::Plant;
use crate::numerics::linalg::{Mat, Vector};

/// The gains of one step.
#[derive(Clone, Debug)]
pub struct Gains {
    pub af: Mat,
    pub bf: Mat,
    pub cf: Mat,
    pub df: Mat,
    /// How the known input r[k] (plant-state sized) enters the filter state; may have no columns
    /// when the plant has no known input (a filter built on another model than the truth's).
    pub gf: Mat,
}

#[derive(Clone, Debug)]
pub struct Realization {
    pub s0: Vector,
    /// Gains for k = 0..=N (the Af, Bf, Gf of step N are never used).
    pub steps: Vec<Gains>,
    /// Mode-indexed gains [k][mode], replacing `steps` when not empty.
    pub by_mode: Vec<Vec<Gains>>,
    /// M: what the filter's state tracks, s[k] ≈ M x[k] (the identity for a state estimator), if
    /// the family declares it. The exact analysis and the Monte Carlo may then carry ε = s − M x
    /// instead of s, but only at steps and modes where they have checked that the realization
    /// keeps ε independent of x ([`crate::analysis::exact::error_form`]).
    pub tracks: Option<Mat>,
}

impl Realization {
    pub fn new(s0: Vector, steps: Vec<Gains>) -> Self {
        Realization { s0, steps, by_mode: Vec::new(), tracks: None }
    }
    /// The same realization, declaring that its state estimates M x (see `tracks`).
    pub fn tracking(mut self, m: Mat) -> Self {
        self.tracks = Some(m);
        self
    }
    /// A realization that uses the gains of the observed mode: `by_mode[k][θ]`.
    pub fn mode_indexed(s0: Vector, by_mode: Vec<Vec<Gains>>) -> Self {
        let steps = by_mode.iter().map(|g| g[0].clone()).collect();
        Realization { s0, steps, by_mode, tracks: None }
    }
    /// The gains of step k in mode θ.
    #[inline]
    pub fn gains(&self, k: usize, mode: usize) -> &Gains {
        if self.by_mode.is_empty() { &self.steps[k] } else { &self.by_mode[k][mode] }
    }

    pub fn ns(&self) -> usize {
        self.s0.len()
    }

    /// ẑ[k] = Cf s + Df y in mode θ, written into `zhat`.
    #[inline]
    pub fn output(&self, k: usize, mode: usize, s: &Vector, y: &Vector, zhat: &mut Vector) {
        let g = self.gains(k, mode);
        zhat.gemv(1.0, &g.cf, s, 0.0);
        zhat.gemv(1.0, &g.df, y, 1.0);
    }

    /// s[k+1] = Af s + Bf y + Gf r in mode θ, written into `next`.
    #[inline]
    pub fn advance(&self, k: usize, mode: usize, s: &Vector, y: &Vector, r: Option<&Vector>, next: &mut Vector) {
        let g = self.gains(k, mode);
        next.gemv(1.0, &g.af, s, 0.0);
        next.gemv(1.0, &g.bf, y, 1.0);
        if let Some(r) = r {
            next.gemv(1.0, &g.gf, r, 1.0);
        }
    }

    /// Checks sizes against the plant and, for prediction, that ẑ[k] does not use y[k].
    pub fn check(&self, name: &str, plant: &Plant, pattern: Pattern) -> Result<()> {
        if self.steps.len() != plant.steps() {
            return Err(Error::design(
                name,
                format!("{} steps of gains for a horizon of {}", self.steps.len(), plant.steps()),
            ));
        }
        let ns = self.ns();
        if !self.by_mode.is_empty()
            && (self.by_mode.len() != plant.steps() || self.by_mode.iter().any(|g| g.len() != plant.n_modes()))
        {
            return Err(Error::design(name, format!("mode-indexed gains need {} modes at each step", plant.n_modes())));
        }
        let modal = self.by_mode.iter().enumerate().flat_map(|(k, gs)| gs.iter().map(move |g| (k, g)));
        for (k, g) in self.steps.iter().enumerate().chain(modal) {
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
