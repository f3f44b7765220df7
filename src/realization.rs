//! The one form every filter compiles to (SPEC §0):
//!
//!     s[k+1] = Af[k] s[k] + Bf[k] y[k] + Gf[k] r[k]
//!     ẑ[k]   = Cf[k] s[k] + Df[k] y[k]
//!
//! with s[0] = s0 and gains that do not depend on the data. The Monte Carlo engine and the exact
//! analysis only ever see this.

use crate::error::{Error, Result};
use crate::linalg::{Mat, Vector};
use crate::plant::Plant;
use crate::spec::Pattern;

/// The gains of one step.
#[derive(Clone, Debug)]
pub struct Gains {
    pub af: Mat,
    pub bf: Mat,
    pub cf: Mat,
    pub df: Mat,
    /// How the known input r[k] (plant-state sized) enters the filter state.
    pub gf: Mat,
}

#[derive(Clone, Debug)]
pub struct Realization {
    pub s0: Vector,
    /// Gains for k = 0..=N (the Af, Bf, Gf of step N are never used).
    pub steps: Vec<Gains>,
}

impl Realization {
    pub fn ns(&self) -> usize {
        self.s0.len()
    }

    /// ẑ[k] = Cf s + Df y, written into `zhat`.
    #[inline]
    pub fn output(&self, k: usize, s: &Vector, y: &Vector, zhat: &mut Vector) {
        let g = &self.steps[k];
        zhat.gemv(1.0, &g.cf, s, 0.0);
        zhat.gemv(1.0, &g.df, y, 1.0);
    }

    /// s[k+1] = Af s + Bf y + Gf r, written into `next`.
    #[inline]
    pub fn advance(&self, k: usize, s: &Vector, y: &Vector, r: Option<&Vector>, next: &mut Vector) {
        let g = &self.steps[k];
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
        for (k, g) in self.steps.iter().enumerate() {
            let ok = g.af.shape() == (ns, ns)
                && g.bf.shape() == (ns, plant.ny())
                && g.cf.shape() == (plant.nz(), ns)
                && g.df.shape() == (plant.nz(), plant.ny())
                && g.gf.shape() == (ns, plant.nx());
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
