//! What a scenario's Monte Carlo run accumulates, per filter and per pair of filters: the
//! statistics the block loop ([`crate::sim::montecarlo`]) fills, the reduction tree
//! ([`crate::sim::tree`]) merges and the shards hand on. Below the engine, so that the per-trial
//! checks and the tree need not import it.

use crate::sim::scenario::Scenario;
use crate::sim::series::Series;
use crate::sim::stats::Welford;

/// Per-filter statistics of one scenario.
#[derive(Clone, Debug, PartialEq)]
pub struct FilterStats {
    /// Summed squared error J over the steps that count, one value per trial.
    pub total: Welford,
    /// Squared error |z\[k] − ẑ\[k]|² at each step.
    pub steps: Series,
    /// For a filter with a per-trial bound: the largest ratio seen and the trials at or above it.
    pub max_ratio: f64,
    pub violations: u64,
    /// e\[k]ᵀ W\[k] e\[k] at each step, for a filter with a claimed covariance ([`crate::analysis::nees`]);
    /// empty otherwise (and at a step without a weight the accumulator stays empty).
    pub nees: Series,
    /// ν\[k]ᵀ W\[k] ν\[k] at each step for a filter with an innovation and a claimed S (NIS); empty
    /// otherwise.
    pub nis: Series,
}

/// Everything one scenario's Monte Carlo run accumulates.
#[derive(Clone, Debug, PartialEq)]
pub struct McStats {
    pub filters: Vec<FilterStats>,
    /// Paired differences J_i − J_j of the summed error on the same draws, for i < j, in the order
    /// (0,1), (0,2), …, (1,2), …: their CI is much narrower than that of either mean.
    pub paired: Vec<Welford>,
}

impl McStats {
    pub fn new(sc: &Scenario) -> Self {
        let (nf, steps) = (sc.filters.len(), sc.plant.steps());
        McStats {
            filters: (0..nf)
                .map(|f| FilterStats {
                    total: Welford::default(),
                    steps: Series::new(steps),
                    max_ratio: 0.0,
                    violations: 0,
                    nees: Series::new(if sc.nees_weights(f).is_some() { steps } else { 0 }),
                    nis: Series::new(if sc.nis_weights(f).is_some() { steps } else { 0 }),
                })
                .collect(),
            paired: vec![Welford::default(); nf * nf.saturating_sub(1) / 2],
        }
    }
    pub(crate) fn merge(&mut self, o: &McStats) {
        for (a, b) in self.filters.iter_mut().zip(&o.filters) {
            a.total.merge(&b.total);
            a.max_ratio = a.max_ratio.max(b.max_ratio);
            a.violations += b.violations;
            a.steps.merge(&b.steps);
            a.nees.merge(&b.nees);
            a.nis.merge(&b.nis);
        }
        for (a, b) in self.paired.iter_mut().zip(&o.paired) {
            a.merge(b);
        }
    }
    /// Whether `o` has the same accumulators (filters, steps, NEES, NIS, pairs): only then do they
    /// merge.
    pub(crate) fn same_shape(&self, o: &McStats) -> bool {
        let f = |m: &McStats| m.filters.iter().map(|f| (f.steps.len(), f.nees.len(), f.nis.len())).collect::<Vec<_>>();
        self.paired.len() == o.paired.len() && f(self) == f(o)
    }
    /// The pairs (i, j) in the order of `paired`.
    pub(crate) fn pairs(nf: usize) -> Vec<(usize, usize)> {
        (0..nf).flat_map(|i| (i + 1..nf).map(move |j| (i, j))).collect()
    }
}
