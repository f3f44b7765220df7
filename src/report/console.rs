//! The console table printed after each run, drawn by comfy-table: numbers have four significant
//! figures (the tables keep every digit) and the columns fit the filters' names, so a table of
//! names up to about 30 characters fits 100 columns with nothing on a line of its own.

use comfy_table::{CellAlignment, ContentArrangement, Table, presets};

use crate::config::Experiment;
use crate::pipeline::{RunOutcome, ScenarioOutcome};

/// A number in at most 8 characters with four significant figures: every console table's format.
pub fn num(x: f64) -> String {
    let a = x.abs();
    if !x.is_finite() || a == 0.0 {
        return format!("{x}");
    }
    if (1e-2..1e5).contains(&a) {
        let prec = (3 - a.log10().floor() as i32).max(0) as usize;
        format!("{x:.prec$}")
    } else {
        format!("{x:.2e}")
    }
}

fn opt(v: Option<f64>) -> String {
    v.map_or("—".to_string(), num)
}

/// z = (empirical − exact) / standard error; a deterministic input has every trial equal, so its
/// empirical mean is exact (standard error zero to rounding) and z would only amplify rounding.
fn z_score(mean: f64, se: f64, exact: f64) -> String {
    let scale = mean.abs().max(exact.abs()).max(f64::MIN_POSITIVE);
    if se <= 1e-9 * scale {
        return if (mean - exact).abs() <= 1e-9 * scale { "exact".into() } else { "≠".into() };
    }
    let z = (mean - exact) / se;
    if z.abs() < 100.0 { format!("{z:.2}") } else { format!("{z:.0}") }
}

/// A table of the run's figures drawn by comfy-table: no borders, every column as wide as its
/// widest cell (names included, so nothing wraps), numbers right-aligned, indented by two spaces.
fn grid(header: &[&str], rows: Vec<Vec<String>>) -> String {
    let mut t = Table::new();
    t.load_preset(presets::NOTHING).set_content_arrangement(ContentArrangement::Disabled).set_header(header.to_vec());
    for r in rows {
        t.add_row(r);
    }
    for (i, c) in t.column_iter_mut().enumerate() {
        c.set_cell_alignment(if i == 0 { CellAlignment::Left } else { CellAlignment::Right });
    }
    t.lines().map(|l| format!(" {}\n", l.trim_end())).collect()
}

/// Console width the tables are laid out for.
const WIDTH: usize = 100;

/// `text` broken at spaces into lines of at most [`WIDTH`] characters (a longer word stays whole),
/// continuation lines indented by `indent`; ends with a newline.
fn wrap(text: &str, indent: &str) -> String {
    let mut out = String::new();
    let mut line = String::new();
    for word in text.split(' ') {
        let len = line.chars().count();
        if len > 0 && len + 1 + word.chars().count() > WIDTH {
            out += &line;
            out += "\n";
            line = indent.to_string();
        } else if len > 0 && line != indent {
            line.push(' ');
        }
        line += word;
    }
    out + &line + "\n"
}

/// One block per scenario, one line per filter: empirical mean ± 95 % half-width, exact, z-score of
/// (empirical − exact) in standard errors ("exact" for a deterministic input), the guaranteed bound
/// where the filter's promise holds in this scenario, worst case over the set.
pub fn table(exp: &Experiment, out: &RunOutcome) -> String {
    let gains = exp.anisotropy.is_some() || out.filters.iter().any(|f| f.design.gain_bound.is_some());
    let mut s = wrap(
        &format!(
            "{}{}: {} trials × {} scenarios, N = {}, {} thread(s), {:.2} s",
            exp.name,
            exp.variant.as_deref().map_or(String::new(), |v| format!(" [{v}]")),
            exp.trials,
            exp.scenarios.len(),
            exp.plant.horizon,
            out.threads,
            out.total_seconds
        ),
        "",
    );
    for sc in &out.scenarios {
        let mut head = format!("{} — covariance {}, shape {}", sc.name, sc.covariance_label, sc.shape_label);
        if sc.disturbance.is_some() {
            head += &format!(", disturbance {}", sc.disturbance_label);
        }
        s += "\n";
        s += &wrap(&head, "    ");
        let rows = exp
            .filters
            .iter()
            .enumerate()
            .map(|(f, spec)| {
                let st = &sc.mc.filters[f].total;
                let ex = sc.exact[f].total;
                vec![
                    spec.name.clone(),
                    format!("{} ± {}", num(st.mean), num(st.ci95().1 - st.mean)),
                    num(ex),
                    z_score(st.mean, st.std_error(), ex),
                    opt(sc.filters[f].guaranteed),
                    opt(out.filters[f].worst.as_ref().map(|w| w.total)),
                ]
            })
            .collect();
        s += &grid(&["filter", "empirical ± 95%", "exact", "z", "guaranteed", "worst case"], rows);
        if gains {
            s += &gain_block(exp, out, sc);
        }
    }
    s
}

/// Seed 003's figures: mean-square gain E|Z̃|²/E|W|² (empirical with its 95 % half-width, exact, and
/// exact for the noise alone; "—" where the outcome has none: an input without power, or the noise
/// alone beside a deterministic disturbance), the filter's a-anisotropic norm² and its guaranteed γ²
/// with the anisotropy level it holds up to: a filter designed for a lower level (an `h2_suboptimal`
/// at a = 0) guarantees nothing at the file's level, and its γ² must not be read beside norm²_a.
fn gain_block(exp: &Experiment, out: &RunOutcome, sc: &ScenarioOutcome) -> String {
    let a = sc.input_anisotropy.map_or("—".to_string(), |a| format!("{a:.3}"));
    let level = exp.anisotropy.map_or(String::new(), |a| format!(", norm² at a = {a}"));
    let mut s = format!("  mean-square gain, E|W|² = {:.3}, input anisotropy {a}{level}\n", sc.input_power);
    let rows = exp
        .filters
        .iter()
        .enumerate()
        .map(|(f, spec)| {
            let d = &out.filters[f];
            let g = sc.filters[f].gain;
            vec![
                spec.name.clone(),
                g.map_or("—".to_string(), |g| format!("{} ± {}", num(g.empirical), num(g.ci_high - g.empirical))),
                opt(g.map(|g| g.exact)),
                opt(g.and_then(|g| g.exact_noise)),
                opt(d.anisotropic.map(|x| x.norm_sq)),
                opt(d.design.gain_bound.map(|g| g.gamma_sq)),
                opt(d.design.gain_bound.map(|g| g.anisotropy)),
            ]
        })
        .collect();
    s += &grid(&["filter", "gain ± 95%", "exact", "noise only", "norm²_a", "γ² guaranteed", "for a ≤"], rows);
    s
}
