//! What the Monte Carlo engine needs to run one scenario: the plant, its filters, the noise and
//! the optional per-trial checks and NEES weights. Below the engine ([`crate::sim::montecarlo`]),
//! the block simulation ([`crate::sim::block`]) and the checks, which all read it.

use crate::analysis::exact::ErrorForm;
use crate::filter::design::PerTrialBound;
use crate::filter::realization::Realization;
use crate::model::plant::Plant;
use crate::numerics::linalg::Mat;
use crate::sim::noise::NoiseSampler;
use crate::sim::plant_ops::PlantOps;
use crate::sim::stacked::Stacked;
use std::sync::Arc;

/// What the engine needs to run one scenario.
pub struct Scenario<'a> {
    pub plant: &'a Plant,
    /// The plant's matrices as the trial loop applies them.
    pub ops: &'a PlantOps,
    pub filters: &'a [&'a Realization],
    pub sampler: &'a NoiseSampler,
    pub seed: u64,
    pub index: usize,
    /// Per-trial ratio checks (seed 002), if any filter has one.
    pub ratios: Option<&'a RatioCheck<'a>>,
    /// Per filter, the NEES weights W\[k] of a filter with a claimed covariance (empty: none),
    /// borrowed from the designs: a long horizon has one matrix per step and filter.
    pub nees: &'a [Option<&'a [Option<Arc<Mat>>]>],
    /// Per filter, the NIS weights of a filter with an innovation and a claimed S\[k] (empty: none).
    pub nis: &'a [Option<&'a [Option<Arc<Mat>>]>],
    /// Per filter, its error form when it is simulated in error coordinates ε = s − M x (the plant's
    /// state is then never differenced); empty or None: the filter's own state s.
    pub forms: &'a [Option<ErrorForm>],
    /// Per filter, its steps stacked into one product each ([`crate::sim::stacked`]), in the
    /// coordinates of `forms`; None (or empty): a filter too large for it, whose five matrices are
    /// applied one by one.
    pub stacked: &'a [Option<Stacked>],
}

impl Scenario<'_> {
    pub(super) fn nees_weights(&self, f: usize) -> Option<&[Option<Arc<Mat>>]> {
        *self.nees.get(f)?
    }
    pub(super) fn nis_weights(&self, f: usize) -> Option<&[Option<Arc<Mat>>]> {
        *self.nis.get(f)?
    }
    pub(super) fn form(&self, f: usize) -> Option<&ErrorForm> {
        self.forms.get(f).and_then(Option::as_ref)
    }
    pub(super) fn stacked(&self, f: usize) -> Option<&Stacked> {
        self.stacked.get(f).and_then(Option::as_ref)
    }
    /// Whether the statistics need nothing of the plant's x, y and z: every filter runs in error
    /// coordinates, where e comes from ε and w alone, and no per-trial check reads x\[N]. The
    /// engine then skips the plant's products (the same bits for every statistic).
    pub(super) fn errors_alone(&self) -> bool {
        self.ratios.is_none() && (0..self.filters.len()).all(|f| self.form(f).is_some())
    }
}

/// The weights of the input energy (R⁻¹ for x0 − E x0, G⁻¹ for w\[k], k < N) and, per filter, its
/// per-trial bound, if it has one.
pub struct RatioCheck<'a> {
    pub x0_weight: Mat,
    pub w_weight: Mat,
    pub bounds: Vec<Option<&'a PerTrialBound>>,
}
