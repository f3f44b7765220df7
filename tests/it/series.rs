//! The per-step accumulators' compact store (`sim::series`): whatever counts it is given (the
//! Monte Carlo's uniform ones or any others, as a merge's shards could hold), it gives back the
//! same accumulators, and its merge is Welford's step by step, bit for bit.

use filterbench::sim::series::Series;
use filterbench::sim::stats::Welford;

fn acc(n: u64, x: f64) -> Welford {
    let mut w = Welford::default();
    for i in 0..n {
        w.push(x + i as f64 * 0.37);
    }
    w
}

fn same(s: &Series, v: &[Welford]) {
    assert_eq!(s.len(), v.len());
    for (k, w) in v.iter().enumerate() {
        let got = s.at(k);
        assert_eq!((got.n, got.mean.to_bits(), got.m2.to_bits()), (w.n, w.mean.to_bits(), w.m2.to_bits()), "step {k}");
    }
    assert_eq!(s.get(v.len()), None);
}

#[test]
fn any_counts_are_kept_and_merged_as_welford_merges_them() {
    // Uniform counts with gaps (NEES at steps without a weight; the last case has them where the
    // first does once `b` reads it backwards, the Monte Carlo's case), counts that differ by step
    // and none, over more than one 64-step word.
    let cases: Vec<Box<dyn Fn(usize) -> u64>> = vec![
        Box::new(|k| if k % 7 == 3 { 0 } else { 5 }),
        Box::new(|k| (k % 4) as u64),
        Box::new(|_| 0),
        Box::new(|k| if (150 - k) % 7 == 3 { 0 } else { 2 }),
    ];
    for a in &cases {
        for b in &cases {
            let va: Vec<Welford> = (0..150).map(|k| acc(a(k), k as f64)).collect();
            let vb: Vec<Welford> = (0..150).map(|k| acc(b(150 - k), -(k as f64))).collect();
            let mut sa = Series::new(150);
            for (k, w) in va.iter().enumerate() {
                sa.set(k, *w);
            }
            let mut sb = Series::default();
            for w in &vb {
                sb.push(*w);
            }
            same(&sa, &va);
            same(&sb, &vb);
            let mut merged = va.clone();
            for (x, y) in merged.iter_mut().zip(&vb) {
                x.merge(y);
            }
            sa.merge(&sb);
            same(&sa, &merged);
        }
    }
}
