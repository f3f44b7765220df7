//! Streaming, mergeable mean and variance (Welford's update, Chan et al.'s merge) and the 95 %
//! confidence interval of a mean. Merging in a fixed order makes the result independent of how
//! trials were spread over threads.

/// z-quantile of a two-sided 95 % normal interval.
pub const Z95: f64 = 1.959_963_984_540_054;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Welford {
    pub n: u64,
    pub mean: f64,
    m2: f64,
}

impl Welford {
    #[inline]
    pub fn push(&mut self, x: f64) {
        self.n += 1;
        let d = x - self.mean;
        self.mean += d / self.n as f64;
        self.m2 += d * (x - self.mean);
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
        let n = (self.n + o.n) as f64;
        let d = o.mean - self.mean;
        self.mean += d * o.n as f64 / n;
        self.m2 += o.m2 + d * d * self.n as f64 * o.n as f64 / n;
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
    pub fn ci95(&self) -> (f64, f64) {
        let h = Z95 * self.std_error();
        (self.mean - h, self.mean + h)
    }
}
