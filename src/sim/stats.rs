//! Streaming, mergeable mean and variance (Welford's update, Chan et al.'s merge) and the 95 %
//! confidence interval of a mean. Merging in a fixed order makes the result independent of how
//! trials were spread over threads.

/// Σ f(v) in a fixed order that vectorizes: eight interleaved partial sums, then added in turn.
#[inline(always)]
fn sum(values: &[f64], f: impl Fn(f64) -> f64) -> f64 {
    let mut acc = [0.0; 8];
    let mut chunks = values.chunks_exact(8);
    for c in &mut chunks {
        for (a, v) in acc.iter_mut().zip(c) {
            *a += f(*v);
        }
    }
    for (a, v) in acc.iter_mut().zip(chunks.remainder()) {
        *a += f(*v);
    }
    acc.iter().sum()
}

/// Chan, Golub & LeVeque's combination of the (mean, M2) of `na` values with that of `nb` more
/// (both counts positive): [`Welford::merge`]'s arithmetic, which [`crate::sim::series::Series`]
/// also runs over whole series of steps with one pair of counts.
#[inline(always)]
pub(crate) fn chan(a: (f64, f64), na: u64, b: (f64, f64), nb: u64) -> (f64, f64) {
    let n = (na + nb) as f64;
    let d = b.0 - a.0;
    (a.0 + d * nb as f64 / n, a.1 + (b.1 + d * d * na as f64 * nb as f64 / n))
}

/// z-quantile of a two-sided 95 % normal interval.
pub(crate) const Z95: f64 = 1.959_963_984_540_054;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Welford {
    pub n: u64,
    pub mean: f64,
    /// Σ (x − mean)²: with n and mean, the whole state (a shard hands all three on).
    pub m2: f64,
}

impl Welford {
    #[inline]
    pub fn push(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
    }

    /// The accumulator of a block of values, two-pass (the mean, then the squared deviations from
    /// it): what a lane block contributes before it is merged with [`Welford::merge`]. The mean is
    /// taken as the first value plus the mean deviation from it, so equal values (a fixed input)
    /// give their value exactly and no spread, as Welford's update does.
    #[inline(always)]
    pub fn of(values: &[f64]) -> Welford {
        if values.is_empty() {
            return Welford::default();
        }
        let n = values.len();
        let x0 = values[0];
        let mean = x0 + sum(values, |v| v - x0) / n as f64;
        let m2 = sum(values, |v| (v - mean) * (v - mean));
        Welford { n: n as u64, mean, m2 }
    }

    /// Chan, Golub & LeVeque's pairwise combination.
    pub fn merge(&mut self, o: &Welford) {
        if o.n == 0 {
            return;
        }
        if self.n == 0 {
            *self = *o;
            return;
        }
        (self.mean, self.m2) = chan((self.mean, self.m2), self.n, (o.mean, o.m2), o.n);
        self.n += o.n;
    }

    /// Unbiased sample variance.
    pub fn variance(&self) -> f64 {
        if self.n < 2 { f64::NAN } else { self.m2 / (self.n - 1) as f64 }
    }

    /// Standard error of the mean.
    pub fn std_error(&self) -> f64 {
        (self.variance() / self.n as f64).sqrt()
    }

    /// 95 % confidence interval of the mean (normal approximation).
    pub(crate) fn ci95(&self) -> (f64, f64) {
        let h = Z95 * self.std_error();
        (self.mean - h, self.mean + h)
    }
}
