//! The summed figures as Markdown tables (the viewer renders them in text views): one per scenario
//! beside its plots, and all of a run's scenarios in the overview.

use crate::config::Experiment;
use crate::pipeline::{RunOutcome, ScenarioOutcome};

/// Six significant figures, without the exponent unless the magnitude needs it.
fn num(x: f64) -> String {
    if !x.is_finite() {
        return x.to_string();
    }
    let a = x.abs();
    if a != 0.0 && !(1e-3..1e6).contains(&a) {
        format!("{x:.5e}")
    } else {
        let decimals = if a == 0.0 { 0 } else { (5 - a.log10().floor() as i32).clamp(0, 8) as usize };
        format!("{x:.decimals$}")
    }
}

/// Filter names may hold Markdown's own characters.
fn cell(s: &str) -> String {
    s.replace('\\', "\\\\").replace('|', "\\|").replace('*', "\\*").replace('_', "\\_")
}

/// One scenario: every filter's empirical mean with its 95 % interval, the exact value, the exact
/// error at the last step, and what the filter guarantees or claims.
pub fn scenario(exp: &Experiment, out: &RunOutcome, sc: &ScenarioOutcome) -> String {
    let mut s = format!(
        "### {}\n\ninput: {}, {}; disturbance: {}; {} trials\n\n",
        cell(&sc.name),
        cell(&sc.covariance_label),
        cell(&sc.shape_label),
        cell(&sc.disturbance_label),
        sc.mc.filters.first().map_or(0, |f| f.total.n)
    );
    s.push_str("| filter | empirical [95 % CI] | exact | exact, last step | guaranteed | claimed |\n");
    s.push_str("|---|---:|---:|---:|---:|---:|\n");
    for (f, spec) in exp.filters.iter().enumerate() {
        let st = &sc.mc.filters[f].total;
        let (lo, hi) = st.ci95();
        let guaranteed = sc.filters[f].guaranteed.map_or(String::new(), num);
        let claimed = out.filters[f].claimed.as_ref().map_or(String::new(), |c| num(c.total));
        s.push_str(&format!(
            "| {} | {} [{}, {}] | {} | {} | {} | {} |\n",
            cell(&spec.name),
            num(st.mean),
            num(lo),
            num(hi),
            num(sc.exact[f].total),
            sc.exact[f].per_step.last().map_or(String::new(), |v| num(*v)),
            guaranteed,
            claimed
        ));
    }
    s
}

/// Every scenario of a run, headed by the experiment and its variant.
pub fn summary(exp: &Experiment, out: &RunOutcome) -> String {
    let mut s = format!("## {}", cell(&exp.name));
    if let Some(v) = &exp.variant {
        s.push_str(&format!(" · variant {}", cell(v)));
    }
    s.push_str(&format!(
        "\n\nSummed squared error over {} steps. *guaranteed*: a bound the family's theory proves; *claimed*: \
         the error the filter attains at its own design covariance, which another input may exceed.\n\n",
        exp.plant.steps()
    ));
    if let Some(a) = exp.anisotropy {
        s.push_str(&anisotropic_norms(exp, out, a));
    }
    for sc in &out.scenarios {
        s.push_str(&scenario(exp, out, sc));
        s.push('\n');
    }
    s
}

/// Seed 003's figures of every filter, which do not depend on the scenario: the exact a-anisotropic
/// norm² at the file's level and its limits, beside the γ² a design guarantees, what Theorem 1
/// certifies for the designed filter with a full P, and the design's structure (§4.2).
fn anisotropic_norms(exp: &Experiment, out: &RunOutcome, a: f64) -> String {
    let mut s = format!(
        "### norms at anisotropy a = {a}\n\n| filter | structure | \\|\\|\\|F\\|\\|\\|²_a | ‖F‖₂²/lw (a = 0) | ‖F‖∞² (a → ∞) \
         | γ² guaranteed | γ² of the solver | Theorem 1, full P | for a ≤ |\n|---|---|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    for (spec, d) in exp.filters.iter().zip(&out.filters) {
        let Some(n) = d.anisotropic else { continue };
        let gb = d.design.gain_bound;
        let structure = d.design.diagnostics.get("structure").and_then(|v| v.as_str()).unwrap_or("");
        s.push_str(&format!(
            "| {} | {} | {} | {} | {} | {} | {} | {} | {} |\n",
            cell(&spec.name),
            cell(structure),
            num(n.norm_sq),
            num(n.h2_sq),
            num(n.hinf_sq),
            gb.map_or(String::new(), |g| num(g.gamma_sq)),
            gb.map_or(String::new(), |g| num(g.design_gamma_sq)),
            gb.map_or(String::new(), |g| num(g.theorem1_sq)),
            gb.map_or(String::new(), |g| num(g.anisotropy)),
        ));
    }
    s.push('\n');
    s
}
