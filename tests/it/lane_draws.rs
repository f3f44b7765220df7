//! The lane generator (docs/architecture.md, "Drawing"): every lane of the vectorized xoshiro256++
//! is rand's `Xoshiro256PlusPlus` stream of its trial; the vectorized ziggurat gives each lane the
//! values its scalar path gives, batch by batch, the same bits in the SSE2, AVX2 and AVX-512 builds (and so does
//! the whole engine), and its draws follow the standard normal law (Kolmogorov–Smirnov at p = 0.001, moments
//! and tail frequency within 4.5σ).

use std::sync::Mutex;

use rand::rngs::Xoshiro256PlusPlus;
use rand::{Rng, RngExt, SeedableRng};
use statrs::distribution::{ContinuousCDF, Normal};

use filterbench::sim::lanes::{Build, best_build, force_build};
use filterbench::sim::noise::{LaneRng, Stream, exp, ln, normal_lane, normal_rows, trial_rng};

use crate::common;

/// The tests that switch the build path hold this, so that one never switches it under another.
static PATH: Mutex<()> = Mutex::new(());

const LANES: usize = 64;

/// Every build this processor runs, the baseline first.
fn builds() -> Vec<Build> {
    let all = [Build::Baseline, Build::Avx2, Build::Avx512];
    let b: Vec<Build> = all.into_iter().filter(|b| *b <= best_build()).collect();
    if b.len() == 1 {
        eprintln!("only the baseline build runs here: nothing to compare it with");
    }
    b
}

fn seeded(base: u64) -> Box<LaneRng> {
    let mut r = LaneRng::new();
    for l in 0..LANES {
        r.seed_lane(l, base.wrapping_mul(1_000_003) + l as u64 * 7919);
    }
    r
}

#[test]
fn each_lane_is_rands_xoshiro_stream() {
    let mut lanes = seeded(5);
    let mut refs: Vec<_> =
        (0..LANES).map(|l| Xoshiro256PlusPlus::seed_from_u64(5u64.wrapping_mul(1_000_003) + l as u64 * 7919)).collect();
    let mut row = [0u64; LANES];
    for round in 0..300 {
        lanes.next_row(&mut row);
        for (l, r) in refs.iter_mut().enumerate() {
            assert_eq!(row[l], r.next_u64(), "round {round}, lane {l}");
        }
        // A lane stepped alone (the ziggurat's slow path) stays in step with its stream.
        let l = round % LANES;
        assert_eq!(lanes.next_lane(l), refs[l].next_u64(), "lane {l} alone, round {round}");
    }
    // trial_rng is the stream the engine seeds lane by lane.
    let a = trial_rng(7, 1, 42, Stream::Noise).next_u64();
    let b = trial_rng(7, 1, 42, Stream::Modes).next_u64();
    assert_ne!(a, b, "distinct purposes, distinct streams");
}

#[test]
fn a_batch_gives_each_lane_its_scalar_draws_in_every_build() {
    let _g = PATH.lock().unwrap_or_else(|e| e.into_inner());
    // Batches of 1, 6 and 3 rows (a step's sizes), then one of 4000: 64 × 4010 = 256,640 normals,
    // about 1,100 (0.43 %) through the slow path (wedges, tails), each finished after its batch's tries.
    let batches = [1, 6, 3, 4000];
    let draw = |build: Build| {
        force_build(Some(build));
        let mut r = seeded(11);
        let out: Vec<Vec<[f64; LANES]>> = batches
            .iter()
            .map(|&rows| {
                let mut out = vec![[0.0; LANES]; rows];
                normal_rows(&mut r, &mut out);
                out
            })
            .collect();
        force_build(None);
        out
    };
    let runs: Vec<_> = builds().into_iter().map(|b| (b, draw(b))).collect();
    let mut scalar = seeded(11);
    for l in 0..LANES {
        for (n, &rows) in batches.iter().enumerate() {
            let mut s = vec![0.0; rows];
            normal_lane(&mut scalar, l, &mut s);
            for (b, run) in &runs {
                for (k, s) in s.iter().enumerate() {
                    assert_eq!(
                        run[n][k][l].to_bits(),
                        s.to_bits(),
                        "lane {l}, batch {n}, row {k}: {b:?} batch against the lane's scalar draws"
                    );
                }
            }
        }
    }
}

#[test]
fn the_engine_gives_the_same_bits_in_every_build() {
    let _g = PATH.lock().unwrap_or_else(|e| e.into_inner());
    // kalman_baseline (Gaussian, white) and hinf_tradeoff (joint ellipsoid inputs, error
    // coordinates, per-trial checks): 1000 trials, 15 full blocks and a partial one.
    for exp in [common::baseline(1000), common::load("hinf_tradeoff", 1000)] {
        let runs: Vec<_> = builds()
            .into_iter()
            .map(|b| {
                force_build(Some(b));
                let out = filterbench::pipeline::run(&exp, false).unwrap();
                force_build(None);
                (b, out)
            })
            .collect();
        let (_, base) = &runs[0];
        for (b, run) in &runs[1..] {
            for (x, y) in base.scenarios.iter().zip(&run.scenarios) {
                let (p, q) = (crate::determinism::bits(&x.mc), crate::determinism::bits(&y.mc));
                assert_eq!(p, q, "{}: scenario {}, {b:?} against the baseline build", exp.name, x.name);
            }
        }
    }
}

#[test]
fn normals_follow_the_standard_normal_law() {
    let rows = 16_384;
    let mut r = seeded(3);
    let mut out = vec![[0.0; LANES]; rows];
    normal_rows(&mut r, &mut out);
    let mut v: Vec<f64> = out.into_iter().flatten().collect();
    let n = v.len() as f64;
    let (m1, m2, m4) = v.iter().fold((0.0, 0.0, 0.0), |(a, b, c), x| (a + x, b + x * x, c + x.powi(4)));
    let (m1, m2, m4) = (m1 / n, m2 / n, m4 / n);
    // Standard errors of the sample moments of N(0, 1): √(1/n), √(2/n), √(96/n) (Var x⁴ = 105 − 9).
    assert!(m1.abs() < 4.5 / n.sqrt(), "mean {m1}");
    assert!((m2 - 1.0).abs() < 4.5 * (2.0 / n).sqrt(), "second moment {m2}");
    assert!((m4 - 3.0).abs() < 4.5 * (96.0 / n).sqrt(), "fourth moment {m4}");
    // Beyond r = 4.0388 the draws come only from the slow path's exponential method for the tail
    // (about 55 of them here); beyond 3 from the base layer, the wedges and the tail together.
    let normal = Normal::standard();
    for t in [3.0, 4.038_849_846_109_504_5] {
        let p = 2.0 * normal.cdf(-t);
        let tail = v.iter().filter(|x| x.abs() > t).count() as f64;
        assert!((tail - n * p).abs() < 4.5 * (n * p * (1.0 - p)).sqrt(), "{tail} draws beyond {t}, expected {}", n * p);
    }
    // Kolmogorov–Smirnov: √n D above 1.949 has probability 0.001 under the null.
    v.sort_by(f64::total_cmp);
    let d = v.iter().enumerate().fold(0.0f64, |d, (i, x)| {
        let f = normal.cdf(*x);
        d.max((f - i as f64 / n).abs()).max(((i + 1) as f64 / n - f).abs())
    });
    assert!(n.sqrt() * d < 1.949, "KS statistic √n D = {}", n.sqrt() * d);
}

#[test]
fn exp_and_ln_of_the_tables_match_libm() {
    // Both are a few correctly rounded operations after an exact range reduction (series remainders
    // below 1e-22): within 4 ulp of the platform's (itself within 1 ulp).
    for k in 0..4000 {
        let x = -30.0 + k as f64 * 0.00737;
        let (a, b) = (exp(x), x.exp());
        assert!((a - b).abs() <= 4.0 * f64::EPSILON * b, "exp({x}): {a} vs {b}");
        let y = 1e-16 + k as f64 * 0.0137;
        let (a, b) = (ln(y), y.ln());
        assert!((a - b).abs() <= 4.0 * f64::EPSILON * b.abs().max(1.0), "ln({y}): {a} vs {b}");
    }
}

/// The ziggurat's layers (`sim/noise/ziggurat.rs`) all have the area v: layer i ≥ 1 is the box
/// [0, X\[i]] × [f(X\[i]), f(X\[i+1])] (the top one reaching f(0) = 1), each edge computed from the
/// one below it. Below the top, each area is v to the rounding of its own edge and heights: a few
/// units of 2⁻⁵³ over the smallest height difference, v/X\[LAYERS−1] ≈ 0.009, about 10⁻¹³ relative
/// (measured 2·10⁻¹³); asserted within 10⁻¹². The top layer's area is where the recursion closes,
/// and every step's rounding reaches it: the closure moves by 1.3·10³ times a relative change of v
/// (tools/ziggurat_constants.py prints the factor), so 1023 steps of a few units of 2⁻⁵³ each, of
/// random sign, give √1023 · 4 · 2⁻⁵³ · 1.3·10³ ≈ 2·10⁻¹¹ (measured 5.4·10⁻¹²); asserted within 10⁻¹⁰.
/// Either is far below what any number of draws could see.
#[test]
fn the_layers_have_equal_areas() {
    use filterbench::sim::noise::{LAYERS, wedge};
    let area = |i: usize| {
        let ((_, b), (fa, fb)) = wedge(i);
        b * (fa - fb)
    };
    let v = area(1);
    let worst = (2..LAYERS - 1).map(|i| (area(i) / v - 1.0).abs()).fold(0.0, f64::max);
    let top = area(LAYERS - 1) / v - 1.0;
    eprintln!("layer areas: below the top within {worst:e} of layer 1's, the top {top:e}");
    assert!(worst < 1e-12, "a layer's area is {worst:e} (relative) off layer 1's");
    assert_eq!(wedge(LAYERS - 1).0.0, 0.0, "the top layer reaches x = 0");
    assert!(top.abs() < 1e-10, "the top layer's area is {top:e} (relative) off layer 1's");
}

/// The ziggurat's squeeze (`sim/noise/ziggurat.rs`, `Squeeze`) decides a wedge try without the
/// exponential only where the exponential decides it the same way: on every wedge, 5 000 uniform
/// heights and 500 heights within 10⁻⁹…10⁻¹⁶ (relative) of the density, above and below it, where
/// the lines' margins are tested hardest. It must also decide most uniform tries (it is there to
/// skip the exponential): 99 % of them, and half of every wedge's but the one across the inflection
/// point t = 1, which it leaves to the exponential.
#[test]
fn the_wedge_squeeze_decides_as_the_exponential() {
    use filterbench::sim::noise::{LAYERS, wedge, wedge_decisions};
    const TRIES: usize = 5_000;
    const NEAR: usize = 500;
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(2026_12_02);
    let (mut skipped_layers, mut near_decided, mut worst, mut total) = (0, 0usize, TRIES, 0usize);
    for i in 1..LAYERS {
        let ((a, b), (fa, fb)) = wedge(i);
        assert!(a < b && fb < fa, "wedge {i}: corners {a} < {b}, heights {fb} < {fa}");
        let mut decided = 0;
        for _ in 0..TRIES {
            let x = (a + (b - a) * rng.random::<f64>()) * if rng.random::<bool>() { 1.0 } else { -1.0 };
            let y = fa + (fb - fa) * rng.random::<f64>();
            let (squeeze, exact) = wedge_decisions(i, x, y);
            if let Some(s) = squeeze {
                assert_eq!(s, exact, "wedge {i}, x = {x}, y = {y}");
                decided += 1;
            }
        }
        for k in 0..NEAR {
            let x = a + (b - a) * rng.random::<f64>();
            let rel = 10f64.powf(-9.0 - 7.0 * rng.random::<f64>()) * if k % 2 == 0 { 1.0 } else { -1.0 };
            let y = (-x * x / 2.0).exp() * (1.0 + rel);
            let (squeeze, exact) = wedge_decisions(i, x, y);
            if let Some(s) = squeeze {
                assert_eq!(s, exact, "wedge {i}, x = {x}, y = {y} (density × (1 + {rel:e}))");
                near_decided += 1;
            }
        }
        if a < 1.0 && b > 1.0 {
            skipped_layers += 1;
            assert_eq!(decided, 0, "wedge {i} straddles t = 1: no squeeze");
        } else {
            worst = worst.min(decided);
            total += decided;
        }
    }
    assert_eq!(skipped_layers, 1, "exactly one wedge straddles the inflection point");
    // Within 1e-9 of the density the squeeze may decide only where its lines' margin (1e-10 of the
    // wedge's top) leaves room: some, not all.
    let wedges = LAYERS - 2;
    eprintln!("near-density heights the squeeze decided: {near_decided} of {}", (LAYERS - 1) * NEAR);
    eprintln!("uniform tries decided: {total} of {} (worst wedge {worst} of {TRIES})", wedges * TRIES);
    assert!(total * 100 >= 99 * wedges * TRIES, "the squeeze decided only {total} of the uniform tries");
    assert!(worst * 2 >= TRIES, "a wedge's squeeze decided only {worst} of {TRIES} tries");
}
