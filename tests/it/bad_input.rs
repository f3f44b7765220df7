//! Bad input gets one clear line naming the key or path and the cause, a non-zero exit, no panic,
//! and leaves the output folder as it was.
use crate::common::Patch;

use std::path::Path;
use std::process::Command;

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");

fn baseline_text() -> String {
    crate::common::text("kalman_baseline")
}

/// Runs `experiment FILE --out DIR` where DIR already holds a previous result, and checks the run
/// fails cleanly, mentions every `needles`, and leaves DIR untouched.
fn fails_cleanly(text: &str, needles: &[&str]) {
    let tmp = crate::common::TempDir::new();
    let file = tmp.path().join("bad.toml");
    std::fs::write(&file, text).unwrap();
    let out = tmp.path().join("results").join("bad");
    std::fs::create_dir_all(&out).unwrap();
    std::fs::write(out.join("summary.parquet"), b"previous").unwrap();
    let o = Command::new(BIN)
        .args(["experiment", file.to_str().unwrap(), "--trials", "2", "--quiet", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    check_failure(&o, needles);
    let entries: Vec<_> = std::fs::read_dir(out.parent().unwrap()).unwrap().flatten().map(|e| e.file_name()).collect();
    assert_eq!(entries, vec![std::ffi::OsString::from("bad")], "no temporary folder is left behind");
    assert_eq!(std::fs::read(out.join("summary.parquet")).unwrap(), b"previous", "previous results untouched");
    assert_eq!(std::fs::read_dir(&out).unwrap().count(), 1);
}

/// Bad input's contract: exit code 2 (a panic would be 101), no panic, one line naming every needle.
pub(crate) fn check_failure(o: &std::process::Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "bad input exits with 2: {err}");
    assert!(!err.contains("panicked"), "no panic: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    for n in needles {
        assert!(err.contains(n), "message should mention `{n}`: {err}");
    }
}

#[test]
fn unknown_key() {
    let t = baseline_text().patch("first_measurement = 1", "first_measurement = 1\nhorizn = 3");
    fails_cleanly(&t, &["plant", "unknown field `horizn`"]);
}

#[test]
fn missing_field() {
    let t = baseline_text().patch("trials = 20000\n", "");
    fails_cleanly(&t, &["missing field `trials`"]);
}

#[test]
fn wrong_matrix_size() {
    let t = baseline_text().patch("C = [[0.5, 0.4,  0.1],", "C = [[0.5, 0.4],");
    fails_cleanly(&t, &["plant.C", "row 2 has 3 entries"]);
    let t = baseline_text().patch("x0 = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "x0 = [[1, 0], [0, 1]]");
    fails_cleanly(&t, &["nominal.x0", "3×3"]);
}

#[test]
fn covariance_not_symmetric_or_not_psd() {
    let t = baseline_text().patch("measurement = [[ 0.9, -0.4, 0.2],", "measurement = [[ 0.9, -0.3, 0.2],");
    fails_cleanly(&t, &["nominal.measurement", "not symmetric"]);
    let t = baseline_text().patch("x0 = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]", "x0 = [[1, 2, 0], [2, 1, 0], [0, 0, 1]]");
    fails_cleanly(&t, &["nominal.x0", "not positive semidefinite"]);
}

#[test]
fn horizon_zero() {
    let t = baseline_text().patch("horizon = 50", "horizon = 0");
    fails_cleanly(&t, &["plant.horizon", "at least 1"]);
}

#[test]
fn unknown_family_and_filter_reference() {
    let t = baseline_text().replacen("family = \"kalman\"", "family = \"kalmann\"", 1);
    fails_cleanly(&t, &["filters.kalman_nominal.family", "unknown family"]);
    let t = baseline_text().patch("filter = \"kalman_nominal\" }", "filter = \"nobody\" }");
    fails_cleanly(&t, &["scenarios.worst_for_kalman_nominal.covariance.filter", "nobody"]);
}

#[test]
fn nonexistent_experiment_name() {
    let o = Command::new(BIN).args(["experiment", "no_such_experiment", "--quiet"]).output().unwrap();
    check_failure(&o, &["no_such_experiment", "filterbench list"]);
}

#[test]
fn unwritable_output_folder() {
    let tmp = crate::common::TempDir::new();
    let blocker = tmp.path().join("a_file");
    std::fs::write(&blocker, b"x").unwrap();
    let out = blocker.join("results");
    let o = Command::new(BIN)
        .args(["experiment", "kalman_baseline", "--trials", "2", "--quiet", "--out", out.to_str().unwrap()])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .unwrap();
    check_failure(&o, &[blocker.to_str().unwrap()]);
    assert!(!Path::new(&out).exists());
}

fn minimax_box_text() -> String {
    crate::common::text("minimax_box")
}

#[test]
fn bad_uncertainty_sets() {
    let measurement_set = "[sets.measurement]\nkind = \"box\"\nhalf_width = 0.25\npsd = true\n";
    assert!(minimax_box_text().contains(measurement_set));
    // Empty: the lower end is above the upper end.
    let t = minimax_box_text().patch(
        measurement_set,
        "[sets.measurement]\nkind = \"loewner\"\nlower = [[2, 0, 0], [0, 2, 0], [0, 0, 2]]\nupper = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n",
    );
    fails_cleanly(&t, &["sets.measurement", "empty"]);
    // The nominal covariance outside its own set.
    let t = minimax_box_text().patch(
        measurement_set,
        "[sets.measurement]\nkind = \"box\"\nhalf_width = 0.1\ncenter = [[2, 0, 0], [0, 2, 0], [0, 0, 2]]\n",
    );
    fails_cleanly(&t, &["sets.measurement", "outside its own box"]);
    let t = minimax_box_text().patch(
        measurement_set,
        "[sets.measurement]\nkind = \"ball\"\nradius = 0.1\ncenter = [[2, 0, 0], [0, 2, 0], [0, 0, 2]]\n",
    );
    fails_cleanly(&t, &["sets.measurement", "outside its own ball"]);
    // Wrong size.
    let t = minimax_box_text()
        .patch(measurement_set, "[sets.measurement]\nkind = \"box\"\nhalf_width = [[0.1, 0.1], [0.1, 0.1]]\n");
    fails_cleanly(&t, &["sets.measurement.half_width", "3×3"]);
    // A set on a block that does not exist.
    let t = minimax_box_text().patch("[sets.measurement]", "[sets.measurment]");
    fails_cleanly(&t, &["sets.measurment", "unknown covariance block"]);
}

#[test]
fn minimax_without_a_set() {
    let t = baseline_text()
        .patch("[sets.process]\nkind = \"ball\"\nradius = 0.1\n", "")
        .patch("[sets.measurement]\nkind = \"box\"\nhalf_width = 0.1\n", "")
        .patch("[[scenarios]]\nname = \"box_vertex\"\ncovariance = { kind = \"vertex\", seed = 1 }\nshape = { kind = \"gaussian\" }\n", "")
        .patch("[[scenarios]]\nname = \"worst_for_kalman_nominal\"\ncovariance = { kind = \"worst_for\", filter = \"kalman_nominal\" }\nshape = { kind = \"gaussian\" }\n", "")
        + "\n[[filters]]\nname = \"minimax\"\nfamily = \"minimax\"\n";
    fails_cleanly(&t, &["minimax", "needs an uncertainty set"]);
}

#[test]
fn bad_disturbances() {
    let text = crate::common::text("minimax_energy");
    let t = text.patch(
        "[disturbances.u]\nweight = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
        "[disturbances.u]\nweight = [[1, 0, 0], [0, 0, 0], [0, 0, 1]]",
    );
    fails_cleanly(&t, &["disturbances.u.weight", "positive definite"]);
    let t = text.patch("energy = 0.5\n\n[disturbances.v]", "energy = -1\n\n[disturbances.v]");
    fails_cleanly(&t, &["disturbances.u.energy"]);
    let t = text.patch("[nominal]\n", "[nominal]\nu = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]\n");
    fails_cleanly(&t, &["nominal.u", "disturbance block has no covariance"]);
    let t = text.patch("[disturbances.v]", "[disturbances.w]");
    fails_cleanly(&t, &["disturbances.w", "not a noise block"]);
    let t = baseline_text().patch(
        "name = \"nominal_laplace\"\n",
        "name = \"nominal_laplace\"\ndisturbance = { kind = \"random\", seed = 1 }\n",
    );
    fails_cleanly(&t, &["scenarios.nominal_laplace.disturbance", "no [disturbances]"]);
}

/// The keys of time-varying weights and per-step bounds (seed 000 (33)–(36)).
#[test]
fn bad_time_varying_disturbances() {
    let text = crate::common::text("minimax_time_varying");
    fails_cleanly(
        &text.patch("weights = [[[0.5]],", "weights = ["),
        &["disturbances.u.weights", "one matrix per step"],
    );
    fails_cleanly(&text.patch("weights = [[[0.5]],", "weights = [[[-0.5]],"), &["disturbances.u.weights[0]"]);
    fails_cleanly(&text.patch("[[0.55]],", "[[0.55, 0.0]],"), &["disturbances.u.weights[1]", "1×1"]);
    fails_cleanly(
        &text.patch("step_energy = [0.05,", "step_energy = ["),
        &["disturbances.u.step_energy", "one bound per step"],
    );
    fails_cleanly(
        &text.patch("step_energy = [0.05,", "step_energy = [-0.05,"),
        &["disturbances.u.step_energy[0]", "≥ 0"],
    );
    fails_cleanly(
        &text.patch("energy = 0.4\n", "energy = 0.4\nweight = [[1.0]]\n"),
        &["disturbances.u", "exactly one of `weight`"],
    );
    let only_weights = text.patch("energy = 0.4\n", "").patch("step_energy", "# step_energy");
    fails_cleanly(&only_weights, &["disturbances.u", "needs `energy`"]);
    let aniso = text.patch("family = \"minimax\"\ntolerance = 1e-10", "family = \"anisotropic\"\nanisotropy = 0.5");
    fails_cleanly(&aniso, &["minimax", "time-varying weights", "kalman or minimax"]);
}

#[test]
fn time_varying_c_of_the_wrong_length_or_size() {
    let text = crate::common::text("hinf_regression");
    let t = text.patch("horizon = 60", "horizon = 59");
    fails_cleanly(&t, &["plant.C_steps", "one matrix per step"]);
    let t = text.replacen("[[1.0, 0.000000, 1.000000]]", "[[1.0, 0.000000]]", 1);
    fails_cleanly(&t, &["plant.C_steps[0]", "1×3"]);
}

#[test]
fn bad_dropouts_anisotropy_and_variants() {
    let base = crate::common::text("aniso_dropout").patch("horizon = 200", "horizon = 10");
    fails_cleanly(&base.patch("arrival = 0.97", "arrival = 1.5"), &["plant.arrival", "probability in (0, 1]"]);
    fails_cleanly(
        &base.patch("anisotropy = 20.0\n\n[[filters]]\nname = \"h2", "anisotropy = -1.0\n\n[[filters]]\nname = \"h2"),
        &["filters.anisotropic.anisotropy", "≥ 0"],
    );
    fails_cleanly(&base.patch("anisotropy = \"inf\"", "anisotropy = \"infinite\""), &["hinf_suboptimal", "\"inf\""]);
    let static_filter = "anisotropy = 20.0\nstructure = \"static\"\n\n[[filters]]\nname = \"h2";
    fails_cleanly(
        &base.patch("anisotropy = 20.0\n\n[[filters]]\nname = \"h2", static_filter),
        &["anisotropic", "structure = \"static\"", "pattern = \"filtering\""],
    );
    fails_cleanly(
        &base.patch(
            "anisotropy = 20.0\n\n[[filters]]\nname = \"h2",
            "anisotropy = 20.0\nstructure = \"general\"\n\n[[filters]]\nname = \"h2",
        ),
        &["filters.anisotropic.structure", "general"],
    );
    fails_cleanly(
        &base.patch("x0 = [[0.0, 0.0], [0.0, 0.0]]", "x0 = [[1.0, 0.0], [0.0, 1.0]]"),
        &["anisotropic", "x(0) known"],
    );
    fails_cleanly(
        &base.patch("kind = \"coloured\", anisotropy = 60.0", "kind = \"coloured\", anisotropy = -2.0"),
        &["scenarios.coloured_beyond_design.input.anisotropy", "≥ 0"],
    );
    fails_cleanly(
        &base.patch("plant = { arrival = 0.99 }", "plant = { arival = 0.99 }"),
        &["variant `p=0.99`", "unknown field `arival`"],
    );
    fails_cleanly(
        &base.patch("plant = { arrival = 0.95 }", "plant = { arrival = 0.0 }"),
        &["variant `p=0.95`", "plant.arrival"],
    );
}

#[test]
fn invalid_markov_chains() {
    let base = crate::common::text("markov_jump");
    let pi = "transition = [[0.9, 0.08, 0.02], [0.08, 0.9, 0.02], [0.1, 0.1, 0.8]]";
    fails_cleanly(
        &base.patch(pi, "transition = [[0.9, 0.08, 0.03], [0.08, 0.9, 0.02], [0.1, 0.1, 0.8]]"),
        &["modes.transition row 1 (left)", "sum to 1"],
    );
    fails_cleanly(
        &base.patch(pi, "transition = [[1.1, -0.1, 0.0], [0.08, 0.9, 0.02], [0.1, 0.1, 0.8]]"),
        &["modes.transition row 1 (left)", "≥ 0"],
    );
    fails_cleanly(&base.patch(pi, "transition = [[0.9, 0.1], [0.1, 0.9]]"), &["modes.transition", "2"]);
    fails_cleanly(&base.patch(pi, &format!("{pi}\ninitial = [0.5, 0.5]")), &["modes.initial", "expected 3"]);
    fails_cleanly(&base.patch(pi, &format!("{pi}\ninitial = [0.5, 0.6, -0.1]")), &["modes.initial", "≥ 0"]);
    fails_cleanly(&base.patch("C = [[0.0, 0.0]]", "C = [[0.0, 0.0, 1.0]]"), &["modes.sensor_failed.C"]);
    // A periodic chain has no stationary distribution to start from.
    fails_cleanly(
        &base.patch(pi, "transition = [[0.0, 1.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0]]"),
        &["modes.initial", "stationary"],
    );
    fails_cleanly(
        &base.patch("pattern = \"prediction\"", "pattern = \"filtering\""),
        &["mode_dependent", "pattern = \"prediction\""],
    );
}

#[test]
fn bad_string_and_galerkin_parameters() {
    let base = crate::common::text("galerkin_string").patch("truth_modes = 128", "truth_modes = 8");
    let sweep = "n = [2, 4, 8, 16], alpha = [1e-1, 1e-4, 1e-8, 1e-12]";
    fails_cleanly(&base.patch(sweep, "n = [2], alpha = [-1e-3]"), &["filters.eigen_n2_alpha-0.001.alpha", "≥ 0"]);
    fails_cleanly(&base.patch(sweep, "n = [0], alpha = [1e-3]"), &["filters.eigen_n0_alpha0.001.n", "at least 1"]);
    fails_cleanly(&base.patch("sensors = [0.142857,", "sensors = [1.2,"), &["string.sensors[0]", "leaves the string"]);
    fails_cleanly(&base.patch("outputs = [0.1,", "outputs = [-0.1,"), &["string.outputs[0]", "outside"]);
    fails_cleanly(&base.patch("dt = 0.0025", "dt = 0.0"), &["string.dt", "> 0"]);
    fails_cleanly(
        &base.patch("sensor_width = 0.05", "sensor_width = 0.05\nprojections = 4"),
        &["string.projections", "only with observation"],
    );
    let tiling = crate::common::text("galerkin_projections").patch("truth_modes = 32", "truth_modes = 8");
    fails_cleanly(
        &tiling.patch("noise_rank = 8", "noise_rank = 8\nsensor_width = 0.1"),
        &["string.sensor_width", "only with observation = \"windows\""],
    );
    fails_cleanly(&tiling.patch("projections = 8\n", ""), &["string.projections", "missing"]);
    // Time-varying intensities (issue 24): a negative value, and a profile of the wrong length.
    fails_cleanly(
        &base.patch("forcing_intensity = 1.0", "forcing_intensity = { times = [0.0, 0.5], values = [1.0, -1.0] }"),
        &["string.forcing_intensity.values[1]", "≥ 0"],
    );
    fails_cleanly(
        &tiling.patch("noise_intensity = 0.0001", "noise_intensity = { times = [0.0, 0.5], values = [1e-4] }"),
        &["string.noise_intensity.values", "1 values for 2 times"],
    );
    // An α too small for a Cholesky solve in double precision at Δ/2 (galerkin::alpha_too_small_…).
    fails_cleanly(
        &base.patch("dt = 0.0025", "dt = 0.00125").patch(sweep, "n = [16], alpha = [1e-16]"),
        &["filters.eigen_n16_alpha0.0000000000000001.alpha", "condition number"],
    );
    fails_cleanly(
        &tiling
            .patch("observation = \"tiling\"", "observation = \"eigen\"")
            .patch("truth_modes = 8", "truth_modes = 4"),
        &["string.projections", "only 4 modes"],
    );
}
