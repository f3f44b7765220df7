//! docs/architecture.md's recipe, shown true: a family that exists only in this test crate is one
//! file (this one) plus one registry line (`families::register::<Inflated>()`). Nothing else in the
//! program names it, yet it is read and checked when the file is loaded, refused on a plant it does
//! not design for, designed, simulated, analysed exactly, and its own figure reaches the summary.

use filterbench::config;
use filterbench::error::Result;
use filterbench::families::kalman::design_at;
use filterbench::families::{self, Family, Supports};
use filterbench::filter::design::{Design, DesignInput, Figures, Record};
use filterbench::model::plant::Covariances;
use polars::prelude::*;

/// A Kalman filter that believes the last noise block (the measurement noise in the experiments
/// used here) is `inflation` times its nominal covariance: the usual hand-tuned detuning.
struct Inflated;

#[derive(serde::Deserialize, Debug)]
#[serde(deny_unknown_fields)]
struct Params {
    inflation: f64,
}

/// Its own figure: the Frobenius norm of its last gain Bf.
#[derive(Debug, serde::Serialize)]
struct InflatedFigures {
    gain_norm: f64,
}

impl Record for InflatedFigures {
    fn summary(&self) -> Vec<(&'static str, f64)> {
        vec![("gain_norm", self.gain_norm)]
    }
}

impl Family for Inflated {
    const NAME: &'static str = "inflated_test";
    type Params = Params;

    /// The capability: it has no model of Markov modes.
    fn supports(_: &Params) -> Supports {
        Supports { markov_modes: false, ..Supports::ALL }
    }

    /// The parameter checked when the file is loaded.
    fn check(p: &Params) -> std::result::Result<(), (&'static str, String)> {
        if p.inflation > 0.0 && p.inflation.is_finite() {
            Ok(())
        } else {
            Err(("inflation", "must be a positive number".into()))
        }
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let mut blocks = input.nominal.blocks.clone();
        let last = blocks.len() - 1;
        blocks[last] *= p.inflation;
        let mut d = design_at(input.plant, Covariances::new(blocks), input.pattern);
        let gain_norm = d.realization.gains.last().expect("a horizon")[0].bf.norm();
        d.figures = Figures::of(InflatedFigures { gain_norm });
        Ok(d)
    }
}

const FILTER: &str = "\n[[filters]]\nname = \"inflated\"\nfamily = \"inflated_test\"\ninflation = 4.0\n";

fn parse(text: &str) -> std::result::Result<config::Experiment, String> {
    config::parse("recipe", "recipe.toml", text).map_err(|e| e.to_string())
}

#[test]
fn a_family_of_the_test_crate_runs_and_shows_its_figure() {
    families::register::<Inflated>();
    let mut exp = parse(&(crate::common::text("kalman_baseline") + FILTER)).expect("loads");
    exp.trials = 400;
    let out = filterbench::pipeline::run(&exp, false).expect("runs");
    let tmp = crate::common::TempDir::new();
    filterbench::report::write_all(&[(&exp, &out)], tmp.path(), &Default::default()).expect("writes");
    let summary =
        ParquetReader::new(std::fs::File::open(tmp.path().join("summary.parquet")).unwrap()).finish().unwrap();
    assert!(summary.column("figure_gain_norm").is_ok(), "the family's figure is a summary column");
    let filters = summary.column("filter").unwrap().str().unwrap().clone();
    let filters: Vec<String> = (0..filters.len()).map(|i| filters.get(i).unwrap().to_string()).collect();
    let values = summary.column("figure_gain_norm").unwrap().f64().unwrap().clone();
    let values: Vec<Option<f64>> = (0..values.len()).map(|i| values.get(i)).collect();
    let f = exp.filter_index("inflated").unwrap();
    let want = out.filters[f].design.realization.gains.last().unwrap()[0].bf.norm();
    for (name, v) in filters.iter().zip(&values) {
        match name.as_str() {
            "inflated" => assert_eq!(*v, Some(want), "its own figure, as designed"),
            _ => assert_eq!(*v, None, "{name} has no such figure"),
        }
    }
    // Kalman at the nominal covariances is the least exact error there (seed 000 eqs (4)–(6)); the
    // detuned filter's exact error is above it by more than the recursion's rounding (1e-12 relative).
    let sc = exp.scenarios.iter().position(|s| s.name == "nominal_gaussian").expect("a nominal scenario");
    let k = exp.filter_index("kalman_nominal").unwrap();
    let (detuned, optimal) = (out.scenarios[sc].exact[f].total, out.scenarios[sc].exact[k].total);
    assert!(detuned > optimal * (1.0 + 1e-12), "detuned {detuned} vs Kalman {optimal}");
}

#[test]
fn its_parameter_is_checked_when_the_file_is_loaded() {
    families::register::<Inflated>();
    let bad = crate::common::text("kalman_baseline") + &FILTER.replace("4.0", "-1.0");
    let err = parse(&bad).expect_err("refused");
    assert!(err.contains("filters.inflated.inflation") && err.contains("positive"), "{err}");
    let unknown = crate::common::text("kalman_baseline") + &FILTER.replace("inflation", "inflaton");
    assert!(parse(&unknown).expect_err("refused").contains("filters.inflated"), "unknown key named");
}

#[test]
fn its_capability_refuses_a_markov_plant_when_the_file_is_loaded() {
    families::register::<Inflated>();
    let err = parse(&(crate::common::text("markov_jump") + FILTER)).expect_err("refused");
    assert!(err.contains("filter `inflated`: the inflated_test family does not design for Markov modes"), "{err}");
}
