//! Display decimation of per-step series, so the recording stays small whatever the horizon (every
//! step is in steps.parquet). A horizon of at most [`DISPLAY_STEPS`] steps is written whole. A
//! longer one is cut into buckets of consecutive steps: step 0 alone (the prior's error, which the
//! per-step views leave out), then buckets of `b` steps from step 1 on, at most [`BUCKETS`] of
//! them; each bucket is one row at its first step holding the bucket's mean (the line) and, in a
//! child entity `envelope`, its minimum and maximum, so a spike of a single step stays visible.

use std::ops::Range;

/// The longest horizon (in steps, N + 1) whose series are written step by step.
pub(crate) const DISPLAY_STEPS: usize = 4096;
/// The most buckets after step 0 in a decimated series.
pub(crate) const BUCKETS: usize = 2048;

/// How a series of `steps` steps is written: None (every step), or its buckets of steps.
pub(crate) fn buckets(steps: usize) -> Option<Vec<Range<usize>>> {
    if steps <= DISPLAY_STEPS {
        return None;
    }
    let b = (steps - 1).div_ceil(BUCKETS);
    Some(std::iter::once(0..1).chain((1..steps).step_by(b).map(|s| s..(s + b).min(steps))).collect())
}

/// What a decimated instance shows on its line: the bucket's mean, or (for the lower and upper
/// edge of a 95 % band) its minimum or maximum, so the band covers every step's band.
#[derive(Clone, Copy, PartialEq)]
pub(crate) enum Reduce {
    Mean,
    Min,
    Max,
}

/// The mean, minimum and maximum of `value` over `ks`.
pub(crate) fn reduce(ks: Range<usize>, value: impl Fn(usize) -> f64) -> (f64, f64, f64) {
    let n = ks.len() as f64;
    let (mut sum, mut lo, mut hi) = (0.0, f64::INFINITY, f64::NEG_INFINITY);
    for k in ks {
        let v = value(k);
        sum += v;
        lo = lo.min(v);
        hi = hi.max(v);
    }
    (sum / n, lo, hi)
}
