//! Standard normal draws for a whole block of lanes at once (docs/math.md §7; docs/architecture.md,
//! "Drawing"): Marsaglia and Tsang's ziggurat (J. Stat. Softw. 5(8), 2000) with [`LAYERS`] = 1024
//! layers, in the form rand_distr uses — one u64 per try, its low 10 bits the layer i and its high
//! 52 bits a uniform u ∈ [−1, 1), so the two are independent (Doornik's remark on ZIGNOR) — exact
//! in distribution. A batch of rows (a step's noise, x0, a joint input) is drawn lane by lane as
//! its tries first, one output of the lane's stream per row, then the rows whose try was rejected,
//! in row order, from the outputs that follow. The fast path (x = u·X\[i], kept when
//! |x| < X\[i+1], 99.57 % of tries) runs a chunk of lanes at a time over the whole batch with the
//! chunk's generator state in registers; the rejected tries (about one in 230) finish one by one on
//! the scalar path. Each lane's values are therefore a function of its own stream only, and both
//! paths use only IEEE-exact operations (no fused multiply–add), so the SSE2, AVX2 and AVX-512
//! builds give the same bits. On the scalar path a wedge try compares a uniform height with the
//! density; two lines bounding the density on the wedge ([`Squeeze`]) decide 99.9 % of those
//! comparisons without the exponential, each the way the exponential would, so the squeeze changes
//! no draw.
//!
//! The tables are computed at compile time from the two constants r and v, with exp, ln and sqrt
//! written here from +, −, ×, ÷ alone: the same bits on every platform, whatever its libm.

use super::lane_rng::LaneRng;
use crate::sim::lanes::{self, Build, LANES, Row};

/// The number of layers, picked by the low bits of a try.
pub const LAYERS: usize = 1024;

/// r, the start of the tail, and v, the area of each layer, for [`LAYERS`] layers: the solution of
/// Marsaglia and Tsang's equations (the layers' edges from x₁ = r by x_{i+1} = f⁻¹(v/x_i + f(x_i)),
/// v = r f(r) + ∫_r^∞ f, and the top layer's area x_{n−1}(1 − f(x_{n−1})) = v), solved to 60 digits
/// by tools/ziggurat_constants.py (which also gives the paper's 256-layer r = 3.6541528853610088).
const R: f64 = 4.038_849_846_109_504_5;
const V: f64 = 0.001_226_324_646_353_088_1;

const LN2_HI: f64 = 6.931_471_803_691_238_2e-1;
const LN2_LO: f64 = 1.908_214_929_270_587_7e-10;

/// 1/n! for n = 0..=13.
const INV_FACTORIAL: [f64; 14] = {
    let mut c = [1.0; 14];
    let mut n = 1;
    while n < 14 {
        c[n] = c[n - 1] / n as f64;
        n += 1;
    }
    c
};

/// e^x for −700 < x < 700: x = k ln 2 + r with |r| ≤ ln 2 / 2 (ln 2 in two parts, so k ln 2 is
/// exact to 2⁻⁸⁰), e^r by its Taylor polynomial of degree 13 (remainder below 5·10⁻¹⁸ relative)
/// in Estrin's form (four dependent steps instead of Horner's thirteen: the ziggurat's wedges
/// wait on it), then 2^k.
pub const fn exp(x: f64) -> f64 {
    let t = x * std::f64::consts::LOG2_E;
    let k = if t >= 0.0 { (t + 0.5) as i64 } else { (t - 0.5) as i64 };
    let kf = k as f64;
    let r = (x - kf * LN2_HI) - kf * LN2_LO;
    let c = &INV_FACTORIAL;
    let (r2, r4) = (r * r, r * r * (r * r));
    let p01 = c[0] + c[1] * r;
    let p23 = c[2] + c[3] * r;
    let p45 = c[4] + c[5] * r;
    let p67 = c[6] + c[7] * r;
    let p89 = c[8] + c[9] * r;
    let p1011 = c[10] + c[11] * r;
    let p1213 = c[12] + c[13] * r;
    let lo = (p01 + p23 * r2) + (p45 + p67 * r2) * r4;
    let hi = (p89 + p1011 * r2) + p1213 * r4;
    (lo + hi * (r4 * r4)) * f64::from_bits(((1023 + k) as u64) << 52)
}

/// ln x for a positive normal x: x = m 2^e with m ∈ [√½, √2), ln m = 2 atanh s with
/// s = (m−1)/(m+1), |s| < 0.172, by its series to s⁴¹ (remainder below 10⁻³²).
pub const fn ln(x: f64) -> f64 {
    let bits = x.to_bits();
    let mut e = ((bits >> 52) & 0x7ff) as i64 - 1023;
    let mut m = f64::from_bits((bits & 0x000f_ffff_ffff_ffff) | (1023 << 52));
    if m > std::f64::consts::SQRT_2 {
        m *= 0.5;
        e += 1;
    }
    let s = (m - 1.0) / (m + 1.0);
    let s2 = s * s;
    let mut p = 0.0;
    let mut n = 41;
    while n > 1 {
        p = s2 * (1.0 / n as f64 + p);
        n -= 2;
    }
    let ef = e as f64;
    ef * LN2_HI + (ef * LN2_LO + 2.0 * s * (1.0 + p))
}

/// √x for x > 0 by Newton's iteration from a start within a factor 2, to convergence.
const fn sqrt(x: f64) -> f64 {
    let e = ((x.to_bits() >> 52) & 0x7ff) as i64 - 1023;
    let mut y = f64::from_bits(((1023 + e / 2) as u64) << 52);
    let mut i = 0;
    while i < 60 {
        y = 0.5 * (y + x / y);
        i += 1;
    }
    y
}

/// The unnormalized density e^(−x²/2).
const fn pdf(x: f64) -> f64 {
    exp(-x * x / 2.0)
}

/// X\[i], the right edge of layer i (X\[0] = v/f(r) for the base layer with its tail, X\[1] = r,
/// X\[LAYERS] = 0), F\[i] = f(X\[i]), and each wedge's [`Squeeze`].
struct Tables {
    x: [f64; LAYERS + 1],
    f: [f64; LAYERS + 1],
    squeeze: [Squeeze; LAYERS],
    /// (X\[i], X\[i+1]) side by side: the fast path's two values of layer i in one 16-byte load.
    pair: [[f64; 2]; LAYERS],
}

/// Two lines bounding the density on wedge i, |x| ∈ \[X\[i+1], X\[i]], that decide most wedge tries
/// without the exponential (Marsaglia's squeeze): a height below `lo` is under the density, one at
/// or above `hi` is over it. f(t) = e^(−t²/2) is convex for t ≥ 1 and concave for t ≤ 1, so the chord
/// through the wedge's corners is an upper bound on a convex wedge and a lower one on a concave
/// wedge, and the tangent at the wedge's middle is the other bound; the wedge across t = 1 gets
/// none (lo never holds, hi never holds). Each line is moved away from the density by 10⁻¹⁰ of the
/// wedge's top, far more than the rounding of the lines (~10⁻¹⁵) and of the density as `slow`
/// computes it (a few units in its last place): a height the squeeze decides is on the same side
/// of the computed density as of the line, so every decision, and every draw, is the one the
/// exponential alone gives (tests/it/lane_draws.rs checks it against the exponential).
#[derive(Clone, Copy)]
struct Squeeze {
    lo: (f64, f64),
    hi: (f64, f64),
}

const NO_SQUEEZE: Squeeze = Squeeze { lo: (f64::NEG_INFINITY, 0.0), hi: (f64::INFINITY, 0.0) };

/// Wedge i's lines from its corners (a, f(a)), (b, f(b)), a = X\[i+1] < b = X\[i] ([`Squeeze`]):
/// each as (intercept, slope) in t = |x|.
const fn squeeze(a: f64, b: f64, fa: f64, fb: f64) -> Squeeze {
    let slope = (fb - fa) / (b - a);
    let chord = (fa - slope * a, slope);
    let m = 0.5 * (a + b);
    let fm = pdf(m);
    let tangent = (fm + m * m * fm, -m * fm);
    let margin = 1e-10 * fa;
    let (lo, hi) = if a >= 1.0 {
        (tangent, chord)
    } else if b <= 1.0 {
        (chord, tangent)
    } else {
        return NO_SQUEEZE;
    };
    Squeeze { lo: (lo.0 - margin, lo.1), hi: (hi.0 + margin, hi.1) }
}

const fn tables() -> Tables {
    let mut x = [0.0; LAYERS + 1];
    let mut f = [0.0; LAYERS + 1];
    x[0] = V / pdf(R);
    x[1] = R;
    let mut i = 2;
    while i < LAYERS {
        x[i] = sqrt(-2.0 * ln(V / x[i - 1] + pdf(x[i - 1])));
        i += 1;
    }
    let mut i = 0;
    while i <= LAYERS {
        f[i] = pdf(x[i]);
        i += 1;
    }
    let mut squeeze_of = [NO_SQUEEZE; LAYERS];
    let mut i = 1;
    while i < LAYERS {
        squeeze_of[i] = squeeze(x[i + 1], x[i], f[i + 1], f[i]);
        i += 1;
    }
    let mut pair = [[0.0; 2]; LAYERS];
    let mut i = 0;
    while i < LAYERS {
        pair[i] = [x[i], x[i + 1]];
        i += 1;
    }
    Tables { x, f, squeeze: squeeze_of, pair }
}

static TABLES: Tables = tables();

/// The low bits of a try that pick its layer: below the 12 bits u leaves out, so i and u are
/// independent.
const LAYER_BITS: u64 = LAYERS as u64 - 1;
const _: () = assert!(LAYERS.is_power_of_two() && LAYERS <= 1 << 12);

/// The bits 2.0 has: or-ed with 52 random mantissa bits, a uniform double in [2, 4).
const TWO: u64 = 0x4000_0000_0000_0000;

/// One try's layer and x from its u64: i = the low 10 bits, u = the high 52 bits as a uniform in
/// [−1, 1), x = u X\[i].
#[inline(always)]
fn try_of(bits: u64) -> (usize, f64, f64) {
    let i = (bits & LAYER_BITS) as usize;
    let u = f64::from_bits((bits >> 12) | TWO) - 3.0;
    (i, u, u * TABLES.x[i])
}

/// A uniform in (0, 1) from one u64 (rand's `Open01`).
fn open01(bits: u64) -> f64 {
    f64::from_bits((bits >> 12) | 0x3FF0_0000_0000_0000) - (1.0 - f64::EPSILON / 2.0)
}

/// Whether height `y` of wedge i (1 ≤ i < LAYERS) at x is under the density, y < e^(−x²/2): decided
/// by the wedge's [`Squeeze`] where it can, by the exponential otherwise, with the same answer.
#[inline(always)]
fn wedge_accepts(i: usize, x: f64, y: f64) -> bool {
    squeezed(i, x, y).unwrap_or_else(|| y < pdf(x))
}

/// The [`Squeeze`]'s decision for height `y` of wedge i at x, if it makes one.
#[inline(always)]
fn squeezed(i: usize, x: f64, y: f64) -> Option<bool> {
    let (t, s) = (x.abs(), &TABLES.squeeze[i]);
    if y < s.lo.0 + s.lo.1 * t {
        Some(true)
    } else if y >= s.hi.0 + s.hi.1 * t {
        Some(false)
    } else {
        None
    }
}

/// For the test that the squeeze changes no draw: its decision for height `y` of wedge i at x (if
/// it makes one) and the exponential's, y < e^(−x²/2) as the slow path computes it.
pub fn wedge_decisions(i: usize, x: f64, y: f64) -> (Option<bool>, bool) {
    (squeezed(i, x, y), y < pdf(x))
}

/// Wedge i's corners: (X\[i+1], X\[i]) and (F\[i+1], F\[i]).
pub fn wedge(i: usize) -> ((f64, f64), (f64, f64)) {
    ((TABLES.x[i + 1], TABLES.x[i]), (TABLES.f[i + 1], TABLES.f[i]))
}

/// Finishes lane `lane`'s normal whose first try `bits` the fast path rejected: the base layer's
/// tail beyond r by Marsaglia's exponential method, a wedge by comparing a uniform height with the
/// density, and a fresh try (fast path included) after a rejected wedge.
fn slow(rng: &mut LaneRng, lane: usize, mut bits: u64) -> f64 {
    loop {
        let (i, u, x) = try_of(bits);
        if x.abs() < TABLES.x[i + 1] {
            return x;
        }
        if i == 0 {
            let (mut t, mut y) = (1.0, 0.0);
            while -2.0 * y < t * t {
                t = ln(open01(rng.next_lane(lane))) / R;
                y = ln(open01(rng.next_lane(lane)));
            }
            return if u < 0.0 { t - R } else { R - t };
        }
        // A uniform in [0, 1) from 53 bits (rand's StandardUniform for f64).
        let h = (rng.next_lane(lane) >> 11) as f64 * (1.0 / (1u64 << 53) as f64);
        if wedge_accepts(i, x, TABLES.f[i + 1] + (TABLES.f[i] - TABLES.f[i + 1]) * h) {
            return x;
        }
        bits = rng.next_lane(lane);
    }
}

/// Rows `out` ← one batch of standard normals per lane: lane l tries rows 0, 1, … with the next
/// outputs of its stream, one each — the fast path, x = u X\[i] kept when |x| < X\[i+1] — and then
/// finishes the rows whose try was rejected, in row order, from the outputs that follow ([`slow`]).
/// A lane's values are a function of its own stream and of the batch's length only. In the AVX-512
/// and AVX2 builds the tries run a chunk of 8 or 4 lanes at a time over all rows, the chunk's
/// generator state in registers; the baseline build runs them row by row ([`tries`]). `masks` (one
/// word per row at least) is scratch.
///
/// # Safety
/// The processor has `build`'s features (the caller passes the build it runs in, which
/// [`lanes::build`] chose; [`Build::Baseline`] is always safe).
#[inline(always)]
pub(crate) unsafe fn normal_batch(rng: &mut LaneRng, out: &mut [Row], masks: &mut [u64], build: Build) {
    let masks = &mut masks[..out.len()];
    masks.fill(0);
    match build {
        // SAFETY: the caller guarantees the features.
        #[cfg(target_arch = "x86_64")]
        Build::Avx512 => unsafe { tries_avx512(rng, out, masks) },
        #[cfg(target_arch = "x86_64")]
        Build::Avx2 => unsafe { tries_avx2(rng, out, masks) },
        _ => tries(rng, out, masks),
    }
    // Each try is rejected with p ≈ 0.43 %: most rows have no rejected lane.
    for (row, &m) in out.iter_mut().zip(masks.iter()) {
        let mut word = m;
        while word != 0 {
            let l = word.trailing_zeros() as usize;
            row[l] = slow(rng, l, row[l].to_bits());
            word &= word - 1;
        }
    }
}

/// One bit per lane of a row: the rejection masks.
const _: () = assert!(LANES <= 64);

/// One lane's batch of normals on the scalar path alone: every try first, then `slow` on each in
/// turn (which returns an accepted try as it is) — the values [`normal_rows`] gives that lane, by
/// other code (tests check it).
pub fn normal_lane(rng: &mut LaneRng, lane: usize, out: &mut [f64]) {
    let tries: Vec<u64> = out.iter().map(|_| rng.next_lane(lane)).collect();
    for (o, bits) in out.iter_mut().zip(tries) {
        *o = slow(rng, lane, bits);
    }
}

/// The fast path over every row: each row's try from the next output of each lane's stream (a
/// whole row of lanes per step, [`LaneRng::next_row`]), x = u X\[i] into `out` where it is kept,
/// else the try's bits (for [`slow`]), and the rejected lanes' bits in `masks`. The AVX-512 and
/// AVX2 kernels below give the same values and masks with each chunk's state in registers; in the
/// baseline build (two lanes per vector, scalar lookups) row by row measured faster.
#[inline(always)]
fn tries(rng: &mut LaneRng, out: &mut [Row], masks: &mut [u64]) {
    let mut bits = [0u64; LANES];
    for (row, mask) in out.iter_mut().zip(masks.iter_mut()) {
        rng.next_row(&mut bits);
        let mut rejected = 0;
        for (l, (o, &b)) in row.iter_mut().zip(&bits).enumerate() {
            let (i, _, x) = try_of(b);
            let reject = x.abs() >= TABLES.x[i + 1];
            *o = if reject { f64::from_bits(b) } else { x };
            rejected |= u64::from(reject) << l;
        }
        *mask = rejected;
    }
}

/// [`tries`] 8 lanes at a time: the xoshiro256++ step of [`LaneRng::next_row`] on one vector per state
/// word, held in registers over all rows, and each lane's (X\[i], X\[i+1]) by a 16-byte load of its
/// [`Tables::pair`], interleaved — AVX-512 gathers are microcoded on AMD's Zen 4, where they made
/// the draw twice as slow. Software-pipelined: the next row's generator step and table loads come
/// before this row's arithmetic, so the loads' latency overlaps that arithmetic instead of holding
/// up the row that waits for them (on Zen 4 about 5–10 % less time a normal; docs/architecture.md,
/// "The draw pipelined"). The same operations on the same values: the same bits and masks.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2")]
#[inline]
unsafe fn tries_avx512(rng: &mut LaneRng, out: &mut [Row], masks: &mut [u64]) {
    use std::arch::x86_64::*;
    let (low, two, three) = (_mm512_set1_epi64(LAYER_BITS as i64), _mm512_set1_epi64(TWO as i64), _mm512_set1_pd(3.0));
    let rows = out.len().min(masks.len());
    if rows == 0 {
        return;
    }
    let mut index = [0u64; 8];
    for c in (0..LANES).step_by(8) {
        // SAFETY: the chunk's 8 lanes and the table's entries (i < LAYERS) are in bounds; the state
        // arrays and the vectors have the same size.
        unsafe {
            let [mut a, mut b, mut s2, mut d]: [__m512i; 4] = std::mem::transmute(rng.chunk::<8>(c));
            // One row's try: the generator's next output and its lanes' table pairs.
            let mut next = || {
                let bits = _mm512_add_epi64(_mm512_rol_epi64::<23>(_mm512_add_epi64(a, d)), a);
                let t = _mm512_slli_epi64::<17>(b);
                s2 = _mm512_xor_si512(s2, a);
                d = _mm512_xor_si512(d, b);
                b = _mm512_xor_si512(b, s2);
                a = _mm512_xor_si512(a, d);
                s2 = _mm512_xor_si512(s2, t);
                d = _mm512_rol_epi64::<45>(d);
                _mm512_storeu_si512(index.as_mut_ptr().cast(), _mm512_and_si512(bits, low));
                let p: [__m128d; 8] = std::array::from_fn(|l| _mm_loadu_pd(TABLES.pair[index[l] as usize].as_ptr()));
                (bits, p)
            };
            let mut ahead = next();
            for r in 0..rows {
                let (bits, p) = ahead;
                if r + 1 < rows {
                    ahead = next();
                }
                let half = |l: usize, m: usize| _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(p[l]), p[m]);
                let even = _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(half(0, 2)), half(4, 6));
                let odd = _mm512_insertf64x4::<1>(_mm512_castpd256_pd512(half(1, 3)), half(5, 7));
                let u = _mm512_sub_pd(_mm512_castsi512_pd(_mm512_or_si512(_mm512_srli_epi64::<12>(bits), two)), three);
                let x = _mm512_mul_pd(u, _mm512_unpacklo_pd(even, odd));
                let m = _mm512_cmp_pd_mask::<_CMP_GE_OQ>(_mm512_abs_pd(x), _mm512_unpackhi_pd(even, odd));
                let kept = _mm512_mask_blend_pd(m, x, _mm512_castsi512_pd(bits));
                _mm512_storeu_pd(out[r].as_mut_ptr().add(c), kept);
                masks[r] |= u64::from(m) << c;
            }
            rng.set_chunk::<8>(c, &std::mem::transmute::<[__m512i; 4], [[u64; 8]; 4]>([a, b, s2, d]));
        }
    }
}

/// [`tries_avx512`] 4 lanes at a time (AVX2 has no 64-bit rotate: shifts and an or).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
#[inline]
unsafe fn tries_avx2(rng: &mut LaneRng, out: &mut [Row], masks: &mut [u64]) {
    use std::arch::x86_64::*;
    let (low, two, three) =
        (_mm256_set1_epi64x(LAYER_BITS as i64), _mm256_set1_epi64x(TWO as i64), _mm256_set1_pd(3.0));
    let sign = _mm256_set1_pd(-0.0);
    let mut index = [0u64; 4];
    for c in (0..LANES).step_by(4) {
        // SAFETY: as in tries_avx512.
        unsafe {
            let rotl23 = |v: __m256i| _mm256_or_si256(_mm256_slli_epi64::<23>(v), _mm256_srli_epi64::<41>(v));
            let rotl45 = |v: __m256i| _mm256_or_si256(_mm256_slli_epi64::<45>(v), _mm256_srli_epi64::<19>(v));
            let [mut a, mut b, mut s2, mut d]: [__m256i; 4] = std::mem::transmute(rng.chunk::<4>(c));
            for (row, mask) in out.iter_mut().zip(masks.iter_mut()) {
                let bits = _mm256_add_epi64(rotl23(_mm256_add_epi64(a, d)), a);
                let t = _mm256_slli_epi64::<17>(b);
                s2 = _mm256_xor_si256(s2, a);
                d = _mm256_xor_si256(d, b);
                b = _mm256_xor_si256(b, s2);
                a = _mm256_xor_si256(a, d);
                s2 = _mm256_xor_si256(s2, t);
                d = rotl45(d);
                _mm256_storeu_si256(index.as_mut_ptr().cast(), _mm256_and_si256(bits, low));
                let p = |l: usize| _mm_loadu_pd(TABLES.pair[index[l] as usize].as_ptr());
                let even = _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(p(0)), p(2));
                let odd = _mm256_insertf128_pd::<1>(_mm256_castpd128_pd256(p(1)), p(3));
                let u = _mm256_sub_pd(_mm256_castsi256_pd(_mm256_or_si256(_mm256_srli_epi64::<12>(bits), two)), three);
                let x = _mm256_mul_pd(u, _mm256_unpacklo_pd(even, odd));
                let reject = _mm256_cmp_pd::<_CMP_GE_OQ>(_mm256_andnot_pd(sign, x), _mm256_unpackhi_pd(even, odd));
                let kept = _mm256_blendv_pd(x, _mm256_castsi256_pd(bits), reject);
                _mm256_storeu_pd(row.as_mut_ptr().add(c), kept);
                *mask |= (_mm256_movemask_pd(reject) as u64) << c;
            }
            rng.set_chunk::<4>(c, &std::mem::transmute::<[__m256i; 4], [[u64; 4]; 4]>([a, b, s2, d]));
        }
    }
}

/// Rows `out` ← one batch of standard normals per lane (`normal_batch`), with the best vector
/// build the processor has (the sampler calls `normal_batch` from inside its own vector build).
pub fn normal_rows(rng: &mut LaneRng, out: &mut [Row]) {
    let mut masks = vec![0; out.len()];
    match lanes::build() {
        // SAFETY: build() names only a build whose features the processor has.
        #[cfg(target_arch = "x86_64")]
        Build::Avx512 => unsafe { normal_rows_avx512(rng, out, &mut masks) },
        #[cfg(target_arch = "x86_64")]
        Build::Avx2 => unsafe { normal_rows_avx2(rng, out, &mut masks) },
        // SAFETY: the baseline build runs everywhere.
        _ => unsafe { normal_batch(rng, out, &mut masks, Build::Baseline) },
    }
}

/// [`normal_rows`] compiled for AVX-512: eight lanes per instruction; the same bits as SSE2's.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2")]
unsafe fn normal_rows_avx512(rng: &mut LaneRng, out: &mut [Row], masks: &mut [u64]) {
    // SAFETY: this function runs only where the processor has AVX-512.
    unsafe { normal_batch(rng, out, masks, Build::Avx512) }
}

/// [`normal_rows`] compiled for AVX2: four lanes per instruction; the same bits as SSE2's.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn normal_rows_avx2(rng: &mut LaneRng, out: &mut [Row], masks: &mut [u64]) {
    // SAFETY: this function runs only where the processor has AVX2.
    unsafe { normal_batch(rng, out, masks, Build::Avx2) }
}
