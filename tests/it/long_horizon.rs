//! A long horizon: steps.parquet keeps every step while the recording decimates each per-step
//! series to buckets whose envelope is exactly each bucket's minimum and maximum (a spike of one
//! step stays visible), and a short horizon is written step by step, as before.

use std::collections::BTreeMap;
use std::io::BufReader;

use filterbench::config;
use filterbench::report::{parquet, recording};
use rerun::external::re_log_encoding::DecoderApp;
use rerun::log::{Chunk, LogMsg};

use crate::common::TempDir;

/// Per data entity of a recording: its rows as (step, scalars).
fn series(path: &std::path::Path) -> BTreeMap<String, Vec<(i64, Vec<f64>)>> {
    let mut out: BTreeMap<String, Vec<(i64, Vec<f64>)>> = BTreeMap::new();
    let id = rerun::Scalars::descriptor_scalars().component;
    for msg in DecoderApp::decode_lazy(BufReader::new(std::fs::File::open(path).unwrap())) {
        let LogMsg::ArrowMsg(store, m) = msg.expect("decodes") else { continue };
        if store.kind() != rerun::StoreKind::Recording {
            continue;
        }
        let chunk = Chunk::from_arrow_msg(&m).expect("a chunk");
        let Some(steps) = chunk.timelines().get(&"step".into()) else { continue };
        let steps: Vec<i64> = steps.times_raw().to_vec();
        let rows: Vec<Vec<f64>> =
            chunk.iter_component::<rerun::components::Scalar>(id).map(|r| r.iter().map(|s| s.0.0).collect()).collect();
        if rows.is_empty() {
            continue;
        }
        let entity: Vec<String> = chunk.entity_path().iter().map(|p| p.unescaped_str().to_string()).collect();
        out.entry(entity.join("/")).or_default().extend(steps.into_iter().zip(rows));
    }
    out
}

#[test]
fn a_long_horizon_keeps_every_step_in_the_table_and_an_exact_envelope_in_the_recording() {
    // N = 9999: 10 000 steps, beyond the 4096 written whole, so buckets of ⌈9999/2048⌉ = 5 steps.
    let text = crate::common::text("long_horizon").replace("horizon = 100000", "horizon = 9999");
    let mut exp = config::parse("long_horizon", "long_horizon.toml", &text).expect("parses");
    exp.trials = 64;
    let out = filterbench::pipeline::run(&exp, false).expect("runs");
    let tmp = TempDir::new();
    let runs = [(&exp, &out)];
    parquet::write_tables(&runs, tmp.path()).expect("tables");
    use polars::prelude::SerReader;
    let steps = polars::prelude::ParquetReader::new(std::fs::File::open(tmp.path().join("steps.parquet")).unwrap())
        .finish()
        .expect("reads");
    assert_eq!(steps.height(), exp.scenarios.len() * exp.filters.len() * 10_000, "every step in the table");

    let rrd = tmp.path().join("recording.rrd");
    recording::write(&runs, &rrd).expect("recording");
    let rec = series(&rrd);
    let sc = &out.scenarios[0];
    let exact = &sc.exact[0].per_step;
    let key = |leaf: &str| format!("mse/{}/{}/{leaf}", sc.name, exp.filters[0].name);
    let line = &rec[&key("exact")];
    let envelope = &rec[&key("exact/envelope")];
    assert_eq!(line.len(), 1 + 2000, "step 0, then 2000 buckets of 5 steps (the last of 4)");
    assert_eq!(envelope.len(), line.len());
    for (i, (step, v)) in envelope.iter().enumerate() {
        let ks = if i == 0 { 0..1 } else { (*step as usize)..(*step as usize + 5).min(10_000) };
        assert_eq!(*step, line[i].0);
        assert_eq!(*step as usize, if i == 0 { 0 } else { 1 + 5 * (i - 1) });
        let lo = ks.clone().map(|k| exact[k]).fold(f64::INFINITY, f64::min);
        let hi = ks.clone().map(|k| exact[k]).fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(v.as_slice(), &[lo, hi], "bucket {i}: the envelope is the bucket's min and max");
        let mean = ks.clone().map(|k| exact[k]).sum::<f64>() / ks.len() as f64;
        assert_eq!(line[i].1, vec![mean]);
    }
    // The empirical band covers every step's 95 % interval (the table's first 10 000 rows are
    // this scenario's and filter's) and touches it.
    let column = |name: &str| -> Vec<f64> {
        steps.column(name).unwrap().f64().unwrap().into_no_null_iter().take(10_000).collect()
    };
    let (low, high) = (column("mse_ci_low"), column("mse_ci_high"));
    let emp = &rec[&key("empirical")];
    for (step, v) in emp.iter().skip(1) {
        let ks = (*step as usize)..(*step as usize + 5).min(10_000);
        assert!(ks.clone().all(|k| v[1] <= low[k] && high[k] <= v[2]), "step {step}");
        assert!(ks.clone().any(|k| v[1] == low[k]) && ks.clone().any(|k| v[2] == high[k]), "step {step}");
    }
    // Every series of the recording is decimated: no entity has more rows than buckets.
    assert!(rec.values().all(|r| r.len() <= 2001), "decimated everywhere");
}

#[test]
fn a_short_horizon_is_written_step_by_step() {
    let exp = crate::common::load("kalman_baseline", 64);
    let out = filterbench::pipeline::run(&exp, false).expect("runs");
    let tmp = TempDir::new();
    let rrd = tmp.path().join("recording.rrd");
    recording::write(&[(&exp, &out)], &rrd).expect("recording");
    let rec = series(&rrd);
    assert!(rec.keys().all(|k| !k.ends_with("envelope")), "no envelope");
    let sc = &out.scenarios[0];
    let line = &rec[&format!("mse/{}/{}/exact", sc.name, exp.filters[0].name)];
    let written: Vec<(i64, Vec<f64>)> =
        sc.exact[0].per_step.iter().enumerate().map(|(k, v)| (k as i64, vec![*v])).collect();
    assert_eq!(line, &written, "every step, its exact value");
}
