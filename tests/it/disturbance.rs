//! Energy-bounded deterministic disturbances (seed 000 §5): the generators land on the bound, the
//! worst case beats every random sequence, Monte Carlo matches the exact error with a deterministic
//! mean, and the minimax guarantee holds.

use filterbench::analysis::exact;
use filterbench::config::Experiment;
use filterbench::model::disturbance::{self, energy};
use filterbench::pipeline;

fn load(trials: usize) -> Experiment {
    crate::common::load("minimax_energy", trials)
}

#[test]
fn sequences_lie_on_the_energy_bound_and_the_worst_beats_random_ones() {
    let exp = load(10);
    let filters = pipeline::design_all(&exp).unwrap();
    let blocks: Vec<(usize, &disturbance::Disturbance)> =
        exp.disturbances.iter().skip(1).enumerate().filter_map(|(b, d)| d.as_ref().map(|d| (b, d))).collect();
    assert_eq!(blocks.len(), 2);
    for seed in 0..50 {
        let wm = disturbance::random(&exp.plant, &exp.disturbances, seed);
        for &(b, d) in &blocks {
            let e = energy(&exp.plant, &wm, b, d);
            assert!((e - d.energy).abs() <= 1e-12 * d.energy, "random sequence energy {e} vs bound {}", d.energy);
        }
    }
    for f in &filters {
        let real = &f.design.realization;
        let worst = f.worst.as_ref().unwrap().disturbance.as_ref().unwrap();
        for &(b, d) in &blocks {
            let e = energy(&exp.plant, worst, b, d);
            assert!((e - d.energy).abs() <= 1e-9 * d.energy, "worst sequence energy {e} vs bound {}", d.energy);
        }
        let w = exact::mean_error(&exp.plant, real, worst);
        for seed in 0..300 {
            let r =
                exact::mean_error(&exp.plant, real, &disturbance::random(&exp.plant, &exp.disturbances, 1000 + seed));
            assert!(r <= w * (1.0 + 1e-12), "a random sequence gives {r} > the worst case {w}");
        }
    }
}

#[test]
fn monte_carlo_matches_the_exact_error_with_disturbances() {
    crate::exact_vs_mc::check(&load(4000));
}

/// For every scenario (covariance in the sets, disturbance within its bounds) the minimax filter's
/// empirical error stays below its guarantee (4σ), and so do its exact error and its worst case.
#[test]
fn minimax_guarantee_holds_with_disturbances() {
    let exp = load(4000);
    let out = pipeline::run(&exp, false).unwrap();
    let m = exp.filter_index("minimax").unwrap();
    let bound = out.filters[m].design.guarantee.as_ref().unwrap().total;
    let worst = out.filters[m].worst.as_ref().unwrap().total;
    assert!(worst <= bound, "worst case {worst} above the guarantee {bound}");
    for sc in &out.scenarios {
        let st = &sc.mc.filters[m].total;
        assert!((st.mean - bound) / st.std_error() <= 4.0, "{}: {} vs guarantee {bound}", sc.name, st.mean);
        assert!(
            sc.exact[m].total <= worst * (1.0 + 1e-9),
            "{}: exact {} above the worst case {worst}",
            sc.name,
            sc.exact[m].total
        );
    }
    eprintln!("minimax_energy: guarantee (seed 000 Theorem 3) {bound:.4}, exact worst case {worst:.4}");
}
