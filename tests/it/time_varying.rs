//! Time-varying plants (seed 003 (3.1), seed 002 §5): every matrix given per step through
//! `plant.*_steps`. The Monte Carlo agrees with the exact error per step (4.5σ) and in total (4σ)
//! for every family that accepts such a plant, with dropouts and with Markov modes; the Kalman
//! filter of a time-varying plant is optimal there (any perturbed gain does worse, exactly); the
//! designs that need constant matrices refuse them with the reason. The anisotropic structures on
//! such a plant: tests/it/aniso_structures.rs.

use filterbench::analysis::exact;
use filterbench::config::{self, Experiment};
use filterbench::model::plant::Pattern;

/// One matrix per step k = 0..N as TOML, `f(k)` giving its rows.
fn steps(n: usize, f: impl Fn(usize) -> Vec<Vec<f64>>) -> String {
    let list: Vec<String> = (0..=n).map(|k| format!("{:?}", f(k))).collect();
    format!("[{}]", list.join(", "))
}

/// A 2-state plant whose A rotates and shrinks, B, C, D, Cz (and Dz when `dz`) changing with k.
/// With `split`, D only reaches the measurement block and B only the process block (seed 002's
/// noise split (5.5)), Dz = 0.
pub(crate) fn plant_text(
    pattern: &str,
    horizon: usize,
    split: bool,
    extra: &str,
    filters: &str,
    scenarios: &str,
) -> String {
    let a = steps(horizon, |k| {
        let (t, r) = (0.15 * k as f64, 0.97 - 0.1 * (0.2 * k as f64).sin().abs());
        vec![vec![r * t.cos(), -r * t.sin()], vec![r * t.sin(), r * t.cos()]]
    });
    let b = steps(horizon, |k| {
        let s = 1.0 + 0.5 * (0.3 * k as f64).cos();
        if split { vec![vec![0.5 * s, 0.0], vec![0.2, 0.0]] } else { vec![vec![0.5 * s, 0.1], vec![0.2, 0.3 * s]] }
    });
    let c = steps(horizon, |k| vec![vec![1.0, 0.5 * (0.25 * k as f64).sin()]]);
    let d = steps(horizon, |k| {
        let s = 0.6 + 0.3 * (0.1 * k as f64).cos();
        if split { vec![vec![0.0, s]] } else { vec![vec![0.1 * s, s]] }
    });
    let cz = steps(horizon, |k| vec![vec![1.0, 0.0], vec![0.2 * (0.05 * k as f64).cos(), 1.0]]);
    let dz = if split {
        String::new()
    } else {
        format!("Dz_steps = {}\n", steps(horizon, |k| vec![vec![0.0, 0.05 * (k % 3) as f64], vec![0.0, 0.0]]))
    };
    format!(
        r#"description = "time-varying plant"
seed = 31
trials = 6000
pattern = "{pattern}"

[plant]
horizon = {horizon}
noise_blocks = ["process", "measurement"]
A = [[0.9, 0.0], [0.0, 0.9]]
B = [[0.5, 0.0], [0.2, 0.0]]
C = [[1.0, 0.0]]
D = [[0.0, 1.0]]
Cz = [[1.0, 0.0], [0.0, 1.0]]
A_steps = {a}
B_steps = {b}
C_steps = {c}
D_steps = {d}
Cz_steps = {cz}
{dz}{extra}

[nominal]
x0 = [[1.0, 0.2], [0.2, 0.5]]
process = [[1.0]]
measurement = [[0.5]]

[sets.process]
kind = "box"
half_width = 0.4

{filters}
{scenarios}
"#
    )
}

pub(crate) fn parse(text: &str) -> Experiment {
    config::parse("time_varying", "time_varying.toml", text).unwrap_or_else(|e| panic!("parses: {e}"))
}

const FILTERING: &str = r#"
[[filters]]
name = "kalman"
family = "kalman"

[[filters]]
name = "kalman_vertex"
family = "kalman"
design = { kind = "vertex", seed = 4 }

[[filters]]
name = "minimax"
family = "minimax"
"#;

const SCENARIOS: &str = r#"
[[scenarios]]
name = "nominal"

[[scenarios]]
name = "laplace_vertex"
covariance = { kind = "vertex", seed = 9 }
shape = "laplace"

[[scenarios]]
name = "worst_for_kalman"
covariance = { kind = "worst_for", filter = "kalman" }
"#;

const PREDICTION: &str = r#"
[[filters]]
name = "hinf"
family = "hinf"
lambda = "min"

[[filters]]
name = "h2"
family = "h2"

[[filters]]
name = "intermittent"
family = "intermittent"

[[filters]]
name = "kalman"
family = "kalman"
"#;

#[test]
fn monte_carlo_matches_exact_on_time_varying_plants() {
    let filtering = parse(&plant_text("filtering", 40, false, "", FILTERING, SCENARIOS));
    assert!(filtering.plant.time_varying());
    crate::exact_vs_mc::check(&filtering);
    let scen = "[[scenarios]]\nname = \"nominal\"\n\n[[scenarios]]\nname = \"student\"\nshape = { kind = \"student_t\", nu = 6 }\n";
    let prediction = parse(&plant_text("prediction", 40, true, "", PREDICTION, scen));
    crate::exact_vs_mc::check(&prediction);
    // Dropouts on a time-varying plant: λ[k] C[k] x + D[k] w (the H∞-λ and H2 filters' seed 002
    // setting has no dropouts).
    let kept = &PREDICTION[PREDICTION.find("[[filters]]\nname = \"intermittent\"").unwrap()..];
    let dropouts = parse(&plant_text("prediction", 40, true, "arrival = 0.8", kept, scen));
    crate::exact_vs_mc::check(&dropouts);
}

/// The Kalman filter of a time-varying plant minimizes the exact error at its design covariance:
/// perturbing its gain at any one step raises it (an exact, deterministic comparison).
#[test]
fn kalman_is_optimal_on_a_time_varying_plant() {
    for pattern in [Pattern::Filtering, Pattern::Prediction] {
        let name = if pattern == Pattern::Filtering { "filtering" } else { "prediction" };
        let exp = parse(&plant_text(name, 30, false, "", FILTERING, SCENARIOS));
        let real = filterbench::families::kalman::kalman(&exp.plant, &exp.nominal, pattern);
        let j0 = exact::error(&exp.plant, &real, &exp.nominal).total;
        for k in [0, 7, 15, 29] {
            for delta in [1e-3, -1e-3] {
                let mut r = real.clone();
                let g = &mut r.gains_mut(k)[0];
                g.bf[(0, 0)] += delta;
                g.af[(0, 0)] -= delta * exp.plant.c_at(k)[(0, 0)];
                g.af[(0, 1)] -= delta * exp.plant.c_at(k)[(0, 1)];
                let j = exact::error(&exp.plant, &r, &exp.nominal).total;
                assert!(j > j0, "{name}: a perturbed gain at step {k} gives {j} ≤ the Kalman error {j0}");
            }
        }
        // The Kalman filter designed with the step-0 matrices everywhere is worse on this plant.
        let mut frozen = exp.plant.clone();
        for s in [&mut frozen.a, &mut frozen.b, &mut frozen.c, &mut frozen.d, &mut frozen.cz, &mut frozen.dz] {
            *s = filterbench::model::plant::Steps::constant(s.at(0).clone());
        }
        let wrong = filterbench::families::kalman::kalman(&frozen, &exp.nominal, pattern);
        let jw = exact::error(&exp.plant, &wrong, &exp.nominal).total;
        assert!(jw > 1.05 * j0, "{name}: the time-invariant design gives {jw} vs {j0}");
    }
}

/// Markov modes on a time-varying plant: a mode that gives its own A keeps it constant, the other
/// matrices vary with the plant's; the Markov-jump filter's finite-horizon recursion (15)–(16) and
/// the Kalman filter on the mode-averaged plant follow them, and the Monte Carlo agrees with the
/// exact moments (4σ in total, 4.5σ per step).
#[test]
fn markov_modes_on_a_time_varying_plant() {
    let filters = "[[filters]]\nname = \"mj\"\nfamily = \"markov_jump\"\n\n[[filters]]\nname = \"averaged\"\nfamily = \"kalman\"\nplant = \"mode_averaged\"\n";
    let modes = "[modes]\ntransition = [[0.9, 0.1], [0.2, 0.8]]\n[[modes.mode]]\nname = \"x\"\n[[modes.mode]]\nname = \"y\"\nA = [[0.5, 0.0], [0.0, 0.5]]\n";
    let exp =
        parse(&plant_text("prediction", 30, true, "", filters, &format!("[[scenarios]]\nname = \"n\"\n\n{modes}")));
    assert!(exp.plant.time_varying() && exp.plant.n_modes() == 2);
    assert!(exp.plant.a_of(3, 0) != exp.plant.a_of(4, 0) && exp.plant.a_of(3, 1) == exp.plant.a_of(4, 1));
    assert!(exp.plant.c_of(3, 1).as_ref() != exp.plant.c_of(4, 1).as_ref());
    crate::exact_vs_mc::check(&exp);
}

/// Designs written for constant matrices refuse a time-varying plant and say why.
#[test]
fn constant_matrix_designs_refuse_time_varying_plants() {
    let mj = "[[filters]]\nname = \"m\"\nfamily = \"markov_jump\"\ngains = \"steady\"\n";
    let text = plant_text("prediction", 10, true, "arrival = 0.9", mj, "[[scenarios]]\nname = \"n\"\n");
    // Refused when the file is loaded, by the one capability check (families::Supports).
    let err = config::parse("tv", "tv.toml", &text).err().expect("refused").to_string();
    assert!(
        err.contains("markov_jump family with gains = \"steady\" does not design for matrices that change")
            && err.contains("constant matrices"),
        "{err}"
    );
    let short = plant_text("prediction", 10, true, "", PREDICTION, "[[scenarios]]\nname = \"n\"\n").replacen(
        "A_steps = [",
        "A_steps = [[[0.9, 0.0], [0.0, 0.9]], ",
        1,
    );
    let err = config::parse("tv", "tv.toml", &short).err().expect("refused").to_string();
    assert!(err.contains("plant.A_steps") && err.contains("one matrix per step"), "{err}");
}
