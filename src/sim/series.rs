//! A run of per-step accumulators ([`Welford`]) stored in 16 bytes and a bit a step instead of
//! 24: the Monte Carlo gives every step of a series the same count (the block's trials, or 0 at a
//! step where the filter claims no NEES weight), so the count is kept once with one bit per step
//! saying whether the step has it. Any other counts (a merge's shards could hold them) are kept
//! step by step, so a [`Series`] holds exactly the accumulators it was given, whatever they are.
//! At N = 10⁶ with 2 filters each scenario keeps 6 × 10⁶ accumulators until the reports.

use bit_vec::BitVec;

use crate::sim::stats::{Welford, chan};

/// Bytes a step costs in a series: its mean and M2, and its bit (rounded up to a byte).
pub(crate) const STEP_BYTES: u64 = 2 * 8 + 1;

#[derive(Clone, Debug, PartialEq)]
enum Counts {
    /// Step k's count is `n` where bit k is set, else 0 (`n` = 0: none set yet).
    Uniform { n: u64, present: BitVec },
    /// Any counts, one per step.
    PerStep(Vec<u64>),
}

/// The accumulators of every step of one statistic (the squared error, NEES or NIS) of one filter.
#[derive(Clone, Debug, PartialEq)]
pub struct Series {
    mean: Vec<f64>,
    m2: Vec<f64>,
    counts: Counts,
}

impl Default for Series {
    fn default() -> Self {
        Series::new(0)
    }
}

impl Series {
    /// `len` empty accumulators.
    pub fn new(len: usize) -> Self {
        Series {
            mean: vec![0.0; len],
            m2: vec![0.0; len],
            counts: Counts::Uniform { n: 0, present: BitVec::from_elem(len, false) },
        }
    }

    pub fn len(&self) -> usize {
        self.mean.len()
    }

    pub fn is_empty(&self) -> bool {
        self.mean.is_empty()
    }

    fn count(&self, k: usize) -> u64 {
        match &self.counts {
            Counts::Uniform { n, present } => n * u64::from(present[k]),
            Counts::PerStep(n) => n[k],
        }
    }

    /// The accumulator of step k (panics beyond the end, as indexing does).
    pub fn at(&self, k: usize) -> Welford {
        Welford { n: self.count(k), mean: self.mean[k], m2: self.m2[k] }
    }

    /// The accumulator of step k, None beyond the end.
    pub fn get(&self, k: usize) -> Option<Welford> {
        (k < self.len()).then(|| self.at(k))
    }

    pub fn iter(&self) -> impl Iterator<Item = Welford> + '_ {
        (0..self.len()).map(|k| self.at(k))
    }

    /// Keeps every count step by step from now on.
    fn per_step(&mut self) -> &mut Vec<u64> {
        if let Counts::Uniform { .. } = self.counts {
            self.counts = Counts::PerStep((0..self.len()).map(|k| self.count(k)).collect());
        }
        match &mut self.counts {
            Counts::PerStep(n) => n,
            Counts::Uniform { .. } => unreachable!("just made per step"),
        }
    }

    fn set_count(&mut self, k: usize, count: u64) {
        if let Counts::Uniform { n, present } = &mut self.counts {
            if *n == 0 {
                *n = count;
            }
            if count == 0 || *n == count {
                present.set(k, count != 0);
                return;
            }
        }
        self.per_step()[k] = count;
    }

    /// Sets step k's accumulator to `w`.
    pub fn set(&mut self, k: usize, w: Welford) {
        self.mean[k] = w.mean;
        self.m2[k] = w.m2;
        self.set_count(k, w.n);
    }

    /// Appends `w` as the next step.
    pub fn push(&mut self, w: Welford) {
        let k = self.len();
        self.mean.push(w.mean);
        self.m2.push(w.m2);
        match &mut self.counts {
            Counts::Uniform { present, .. } => present.push(false),
            Counts::PerStep(n) => n.push(0),
        }
        self.set_count(k, w.n);
    }

    /// Merges `o` into this series step by step with [`Welford::merge`] (over the steps both have,
    /// as a zip would), the same bits as merging each step's accumulators one by one.
    pub fn merge(&mut self, o: &Series) {
        let len = self.len().min(o.len());
        let sum = match (&self.counts, &o.counts) {
            // Both have their count at the same steps: the merged count is their sum there.
            (Counts::Uniform { n, present }, Counts::Uniform { n: m, present: p })
                if present == p && self.len() == o.len() =>
            {
                Some(n + m)
            }
            _ => None,
        };
        if let (Some(_), Counts::Uniform { n, present }, Counts::Uniform { n: m, .. }) =
            (sum, &mut self.counts, &o.counts)
            && *n > 0
            && *m > 0
        {
            // One pair of counts for every step that has one (the Monte Carlo's blocks): the steps'
            // merges without a count to look up, and the same arithmetic (`stats::chan`).
            let steps = self.mean.iter_mut().zip(self.m2.iter_mut()).zip(o.mean.iter().zip(&o.m2));
            for (((a, a2), (b, b2)), here) in steps.zip(present.iter()) {
                if here {
                    (*a, *a2) = chan((*a, *a2), *n, (*b, *b2), *m);
                }
            }
            *n += *m;
            return;
        }
        if sum.is_none() {
            self.per_step();
        }
        for k in 0..len {
            let mut a = self.at(k);
            a.merge(&o.at(k));
            self.mean[k] = a.mean;
            self.m2[k] = a.m2;
            if let Counts::PerStep(n) = &mut self.counts {
                n[k] = a.n;
            }
        }
        if let (Some(s), Counts::Uniform { n, .. }) = (sum, &mut self.counts) {
            *n = s;
        }
    }
}
