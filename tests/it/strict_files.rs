//! Experiment files are read strictly (issue 14 §2): every table chosen by `kind` refuses keys its
//! kind does not take, naming the key and the valid ones; a kind without parameters may be written
//! as its bare name; scenarios are checked before any filter is designed; runs that cannot fit in
//! memory or whose counts would overflow are refused up front. Every refusal exits 2 with one line
//! and leaves the previous result byte for byte as it was.

use std::process::Command;
use std::time::Instant;

use filterbench::config;

use super::output_safety::{refused, snapshot};

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");

fn baseline() -> String {
    crate::common::text("kalman_baseline")
}

/// Runs `experiment bad.toml --out results/bad ARGS…` beside an earlier result and checks the
/// refusal: exit 2, one line with every needle, every file unchanged.
fn refuses_file(text: &str, args: &[&str], needles: &[&str]) {
    let tmp = crate::common::TempDir::new();
    let root = tmp.path();
    let out = root.join("results/bad");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("manifest.json"), br#"{"filterbench_version": "0.1.0"}"#).unwrap();
    std::fs::write(out.join("summary.parquet"), b"previous").unwrap();
    std::fs::write(root.join("bad.toml"), text).unwrap();
    let before = snapshot(root);
    let o = Command::new(BIN)
        .args(["experiment", "bad.toml", "--quiet", "--out", "results/bad"])
        .args(args)
        .current_dir(root)
        .output()
        .unwrap();
    refused(&o, needles);
    assert_eq!(snapshot(root), before, "nothing changed");
}

/// `text` with `from` replaced by `to` (which must occur).
fn patch(text: &str, from: &str, to: &str) -> String {
    assert!(text.contains(from), "fixture contains {from}");
    text.replacen(from, to, 1)
}

#[test]
fn every_kind_refuses_keys_it_does_not_take() {
    let laplace = "shape = { kind = \"laplace\" }";
    let vertex = "covariance = { kind = \"vertex\", seed = 1 }";
    let scen = "name = \"nominal_gaussian\"\n";
    let cases: Vec<(String, &str, &str, &str)> = vec![
        // (replacement, for, unknown key, valid keys)
        (
            "shape = { kind = \"laplace\", nu = 3 }".into(),
            laplace,
            "`nu` for shape kind `laplace`",
            "(valid keys: `kind`)",
        ),
        (
            "shape = { kind = \"gaussian\", df = 3 }".into(),
            laplace,
            "`df` for shape kind `gaussian`",
            "(valid keys: `kind`)",
        ),
        ("shape = { kind = \"rademacher\", p = 0.9 }".into(), laplace, "`p` for shape kind `rademacher`", "`kind`)"),
        ("shape = { kind = \"uniform\", a = 1.0 }".into(), laplace, "`a` for shape kind `uniform`", "`kind`)"),
        ("shape = { kind = \"student_t\", nu = 5, mu = 1 }".into(), laplace, "`mu`", "`kind`, `nu`)"),
        (
            "shape = { kind = \"mixture\", weight = 0.1, ratio = 4.0, w = 1 }".into(),
            laplace,
            "`w` for shape kind `mixture`",
            "`kind`, `weight`, `ratio`)",
        ),
        (
            format!("{vertex}\ninput = {{ kind = \"independent\", seed = 3 }}"),
            vertex,
            "`seed` for input kind `independent`",
            "`kind`)",
        ),
        (
            format!("{scen}input = {{ kind = \"ellipsoid_surface\", seed = 3 }}\n"),
            scen,
            "`seed` for input kind",
            "`kind`)",
        ),
        (format!("{scen}input = {{ kind = \"ellipsoid_interior\", r = 3 }}\n"), scen, "`r` for input kind", "`kind`)"),
        (format!("{scen}input = {{ kind = \"random_covariance\", sed = 3 }}\n"), scen, "`sed`", "`kind`, `seed`)"),
        (
            format!("{scen}input = {{ kind = \"ellipsoid_worst_for\", filters = \"a\" }}\n"),
            scen,
            "`filters`",
            "`kind`, `filter`)",
        ),
        (
            format!("{scen}input = {{ kind = \"coloured\", anisotropi = 3 }}\n"),
            scen,
            "`anisotropi`",
            "`kind`, `anisotropy`)",
        ),
        (
            format!("{scen}input = {{ kind = \"anisotropic_worst_for\", filter = \"a\", level = 3 }}\n"),
            scen,
            "`level`",
            "`kind`, `filter`, `anisotropy`)",
        ),
        (
            format!("{scen}disturbance = {{ kind = \"none\", energy = 5 }}\n"),
            scen,
            "`energy` for disturbance kind `none`",
            "`kind`)",
        ),
        (format!("{scen}disturbance = {{ kind = \"random\", sed = 5 }}\n"), scen, "`sed`", "`kind`, `seed`)"),
        (
            format!("{scen}disturbance = {{ kind = \"worst_for\", filer = \"a\" }}\n"),
            scen,
            "`filer`",
            "`kind`, `filter`)",
        ),
        (
            "covariance = { kind = \"vertex\", seed = 1, sed = 4 }".into(),
            vertex,
            "`sed` for covariance kind `vertex`",
            "`kind`, `seed`)",
        ),
        (
            "covariance = { kind = \"nominal\", seed = 1 }".into(),
            vertex,
            "`seed` for covariance kind `nominal`",
            "`kind`)",
        ),
        ("covariance = { kind = \"interior\", sed = 1 }".into(), vertex, "`sed`", "`kind`, `seed`)"),
        ("covariance = { kind = \"elementwise_max\", seed = 1 }".into(), vertex, "`seed`", "`kind`)"),
        (
            "covariance = { kind = \"worst_for\", filter = \"a\", seed = 1 }".into(),
            vertex,
            "`seed`",
            "`kind`, `filter`)",
        ),
        ("covariance = { kind = \"design_of\", flter = \"a\" }".into(), vertex, "`flter`", "`kind`, `filter`)"),
        (
            "first_measurement = 1\nknown_input = { kind = \"sine\", amplitude = [0, 0, 0], frequency = 1, phse = 0 }"
                .into(),
            "first_measurement = 1",
            "`phse` for known input kind `sine`",
            "`kind`, `amplitude`, `frequency`, `phase`)",
        ),
        (
            "first_measurement = 1\nknown_input = { kind = \"values\", values = [], step = 1 }".into(),
            "first_measurement = 1",
            "`step`",
            "`kind`, `values`)",
        ),
        (
            "kind = \"ball\"\nradius = 0.1\nhalf_width = 1\n".into(),
            "kind = \"ball\"\nradius = 0.1\n",
            "`half_width` for set kind `ball`",
            "`kind`, `radius`, `center`, `psd`)",
        ),
        (
            "kind = \"box\"\nhalf_width = 0.1\nradius = 1\n".into(),
            "kind = \"box\"\nhalf_width = 0.1\n",
            "`radius` for set kind `box`",
            "`kind`, `half_width`, `center`, `psd`)",
        ),
        (
            "kind = \"loewner\"\nlower = [[0.0]]\nupper = [[1.0]]\ncenter = 1\n".into(),
            "kind = \"box\"\nhalf_width = 0.1\n",
            "`center` for set kind `loewner`",
            "`kind`, `lower`, `upper`, `psd`)",
        ),
        ("shape = \"laplac\"".into(), laplace, "unknown shape kind `laplac`", "\"laplace\""),
        ("shape = \"student_t\"".into(), laplace, "missing field `nu`", "scenarios[1].shape"),
    ];
    for (to, from, unknown, valid) in cases {
        let t = patch(&baseline(), from, &to);
        refuses_file(&t, &["--trials", "2"], &[unknown, valid]);
    }
}

#[test]
fn bare_kind_names_are_accepted_everywhere_a_kind_table_is() {
    let table = patch(
        &baseline(),
        "name = \"nominal_gaussian\"\ncovariance = { kind = \"nominal\" }\nshape = { kind = \"gaussian\" }",
        "name = \"nominal_gaussian\"\ncovariance = { kind = \"nominal\" }\nshape = { kind = \"gaussian\" }\ninput = { kind = \"ellipsoid_surface\" }",
    );
    let bare = patch(
        &patch(
            &table,
            "covariance = { kind = \"nominal\" }\nshape = { kind = \"gaussian\" }\ninput = { kind = \"ellipsoid_surface\" }",
            "covariance = \"nominal\"\nshape = \"gaussian\"\ninput = \"ellipsoid_surface\"\ndisturbance = \"none\"",
        ),
        "shape = { kind = \"laplace\" }",
        "shape = \"laplace\"",
    );
    let a = config::parse("t", "t.toml", &table).expect("tables parse");
    let b = config::parse("t", "t.toml", &bare).expect("bare names parse");
    for (x, y) in a.scenarios.iter().zip(&b.scenarios) {
        assert_eq!(x.shape, y.shape);
        assert_eq!(x.input, y.input);
        assert_eq!(x.disturbance, y.disturbance);
        assert_eq!(format!("{:?}", x.covariance), format!("{:?}", y.covariance));
    }
    assert_eq!(b.scenarios[1].shape, filterbench::model::shape::Shape::Laplace);
}

#[test]
fn a_coloured_input_below_white_noise_is_refused_before_any_design() {
    let text = crate::common::text("aniso_dropout");
    // With W = diag(4, 1/4) white noise has anisotropy 201 · A(W) ≈ 152 > 20, the first coloured level.
    let t = patch(&text, "w = [[1.0, 0.0], [0.0, 1.0]]", "w = [[4.0, 0.0], [0.0, 0.25]]");
    // The parser alone refuses it: no filter is designed to find out.
    let err = config::parse("aniso_dropout", "a.toml", &t).err().expect("refused by the parser").to_string();
    assert!(err.contains("scenarios.coloured_design.input.anisotropy (scenarios[1])"), "{err}");
    assert!(err.contains("white noise"), "{err}");
    let start = Instant::now();
    refuses_file(
        &t,
        &["--trials", "2"],
        &["scenarios.coloured_design.input.anisotropy (scenarios[1])", "cannot have less"],
    );
    assert!(start.elapsed().as_secs() < 30, "refused before the designs");
}

#[test]
fn trial_counts_are_bounded_and_memory_is_estimated_before_the_run() {
    refuses_file(&baseline(), &["--trials", "18446744073709551615"], &["--trials", "limit of 1000000000000"]);
    refuses_file(&baseline(), &["--trials", "1"], &["--trials", "at least 2"]);
    refuses_file(&baseline(), &["--trials", "2", "--threads", "18446744073709551615"], &["--threads", "limit of 1024"]);
    refuses_file(&patch(&baseline(), "trials = 20000", "trials = 10000000000000"), &[], &["trials", "limit"]);
    // A horizon whose per-step statistics alone need terabytes is refused at once with the figure.
    let start = Instant::now();
    refuses_file(
        &patch(&baseline(), "horizon = 50", "horizon = 1000000000"),
        &["--trials", "2"],
        &["plant.horizon", "the run needs about", "TB of memory", "available"],
    );
    assert!(start.elapsed().as_secs() < 30, "refused before the run");
}

#[test]
fn sample_trajectories_follows_one_rule_from_the_file_and_from_trials() {
    let t = patch(&baseline(), "sample_trajectories = 3", "sample_trajectories = 50");
    let t = patch(&t, "trials = 20000", "trials = 20");
    let e = config::parse("t", "t.toml", &t).expect("more trajectories than trials is capped, not refused");
    assert_eq!(e.sample_trajectories, 20);
    assert_eq!(config::sample_count(3, 2), 2, "--trials 2 caps the same way");
}

/// The names serde lists after "expected" in an error message (`a`, `b` or one of `a`, `b`).
fn listed(message: &str) -> Vec<String> {
    let Some((_, tail)) = message.split_once("expected") else { return Vec::new() };
    // toml appends where it happened on a line of its own: not part of the list.
    let tail = tail.lines().next().unwrap_or("");
    let mut names: Vec<String> = tail.split('`').skip(1).step_by(2).map(str::to_string).collect();
    names.sort();
    names
}

/// A [`Kinds`] list agrees with the enum it describes: the same kinds, and for each kind the keys
/// its variant takes (read from serde's own messages, so a variant added without its entry fails).
fn kinds_match_the_enum<T: filterbench::model::kind::Kinds>() {
    let probe =
        |table: &str| T::deserialize(toml::from_str::<toml::Value>(table).unwrap()).err().map(|e| e.to_string());
    let mut kinds: Vec<String> = T::KINDS.iter().map(|(k, _)| k.to_string()).collect();
    kinds.sort();
    let m = probe("kind = \"no_such_kind\"").unwrap();
    assert_eq!(listed(&m), kinds, "{}: the kinds ({m})", T::WHAT);
    for (kind, keys) in T::KINDS {
        let mut keys: Vec<String> = keys.iter().map(|k| k.to_string()).collect();
        keys.sort();
        // A unit variant ignores the extra key (why kind tables are checked by hand); a struct
        // variant refuses it and lists its fields.
        let got = probe(&format!("kind = \"{kind}\"\nno_such_key = 1")).map_or(Vec::new(), |m| listed(&m));
        assert_eq!(got, keys, "{}: the keys of kind `{kind}`", T::WHAT);
    }
}

#[test]
fn every_kinds_list_matches_its_enum() {
    kinds_match_the_enum::<filterbench::model::shape::Shape>();
    kinds_match_the_enum::<filterbench::config::Input<String>>();
    kinds_match_the_enum::<filterbench::model::disturbance::DisturbanceChoice<String>>();
}
