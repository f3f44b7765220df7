//! What the exact analysis returns: the error per step and in total, the coordinates it was carried
//! in, and how many digits it kept.

use crate::error::{Error, Result};

/// Exact expected squared error E|z\[k] − ẑ\[k]|² per step and its sum J over the steps that count
/// (k ≥ `plant.sum_from`).
#[derive(Clone, Debug)]
pub struct ExactError {
    pub per_step: Vec<f64>,
    pub total: f64,
    /// Σ_k E[|e\[k]|² 1{θ\[k] = j}] over the counted steps, per mode j (one entry without modes).
    pub per_mode: Vec<f64>,
    /// How many digits the worst step lost to cancellation, and which step.
    pub resolution: Resolution,
    /// The coordinates the moments were carried in.
    pub coordinates: Coordinates,
    /// Why error coordinates could not be used, when they were needed and could not be.
    pub untracked: Option<String>,
}

/// The coordinates of the moment recursion: the plant's ξ = (x, s) (the reference), or the error
/// coordinates ε = s − M x alone, where M is what the filter's state tracks.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coordinates {
    Plant,
    Error,
}

/// Cancellation in one step's error: E|e|² is a sum of terms of magnitude
/// Σ |H| |Y| |H|ᵀ + 2|H| |Z| |G|ᵀ + |G| |R| |G|ᵀ (absolute values entrywise, traces taken), each
/// accurate to about one rounding unit of its own size; the ratio of that magnitude to the result is
/// the factor by which rounding is amplified, and its log10 the decimal digits lost.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Resolution {
    pub step: usize,
    pub digits_lost: f64,
}

/// A double carries about 16 significant digits. A result that lost more than this many (at least
/// ~8 left after the rounding a long recursion accumulates) is not reported: error coordinates are
/// tried, and if they cannot be used the number is refused.
pub const MAX_DIGITS_LOST: f64 = 6.0;

impl ExactError {
    /// Why the value cannot be trusted (the step and the digits lost when double precision does
    /// not resolve it), or None.
    pub(crate) fn unresolved(&self) -> Option<String> {
        let Resolution { step, digits_lost } = self.resolution;
        if digits_lost <= MAX_DIGITS_LOST {
            return None;
        }
        let lost = if digits_lost >= 16.0 && digits_lost.is_finite() {
            "all ~16 digits lost to cancellation".to_string()
        } else if digits_lost.is_finite() {
            format!("{digits_lost:.1} of ~16 digits lost to cancellation")
        } else {
            "the moments overflowed".to_string()
        };
        let why = match (&self.untracked, self.coordinates) {
            (Some(why), _) => format!("; error coordinates s − M x do not apply: {why}"),
            (None, Coordinates::Error) => " even in error coordinates s − M x".to_string(),
            (None, Coordinates::Plant) => String::new(),
        };
        Some(format!(
            "double precision cannot resolve its exact error at step {step} ({lost}{why}); the plant's state grows \
             much faster than the error: shorten the horizon or use a filter whose state tracks the plant's in every mode"
        ))
    }

    /// The value, or an error naming the filter, the step and the digits lost.
    pub fn trusted(self, filter: &str) -> Result<Self> {
        match self.unresolved() {
            None => Ok(self),
            Some(cause) => Err(Error::design(filter, cause)),
        }
    }
}
