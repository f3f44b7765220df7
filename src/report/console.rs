//! The console table printed after each run.

use crate::run::RunOutcome;
use crate::spec::Experiment;

fn opt(v: Option<f64>) -> String {
    v.map_or("—".to_string(), |x| format!("{x:.5}"))
}

/// One block per scenario, one line per filter: empirical mean ± 95 % half-width, exact, z-score of
/// (empirical − exact) in standard errors (0 for a deterministic input, whose trials are all the
/// same), guaranteed bound, worst case over the set.
pub fn table(exp: &Experiment, out: &RunOutcome) -> String {
    let gains = exp.anisotropy.is_some() || out.filters.iter().any(|f| f.design.gain_bound.is_some());
    let mut s = format!(
        "{}{}: {} trials × {} scenarios, N = {}, {} thread(s), {:.2} s\n",
        exp.name,
        exp.variant.as_deref().map_or(String::new(), |v| format!(" [{v}]")),
        exp.trials,
        exp.scenarios.len(),
        exp.plant.horizon,
        out.threads,
        out.total_seconds
    );
    let w = exp.filters.iter().map(|f| f.name.len()).max().unwrap_or(6).max(6);
    for sc in &out.scenarios {
        s += &format!("\n{} — covariance {}, shape {}", sc.name, sc.covariance_label, sc.shape_label);
        if sc.disturbance.is_some() {
            s += &format!(", disturbance {}", sc.disturbance_label);
        }
        s += "\n";
        s += &format!(
            "  {:w$}  {:>22}  {:>10}  {:>6}  {:>10}  {:>10}\n",
            "filter", "empirical ± 95%", "exact", "z", "guaranteed", "worst case"
        );
        for (f, spec) in exp.filters.iter().enumerate() {
            let st = &sc.mc.filters[f].total;
            let half = st.ci95().1 - st.mean;
            let ex = sc.exact[f].total;
            let d = &out.filters[f];
            s += &format!(
                "  {:w$}  {:>12.5} ± {:<7.5}  {:>10.5}  {:>6.2}  {:>10}  {:>10}\n",
                spec.name,
                st.mean,
                half,
                ex,
                if st.std_error() > 0.0 { (st.mean - ex) / st.std_error() } else { 0.0 },
                opt(d.design.guarantee.as_ref().map(|g| g.total)),
                opt(d.worst.as_ref().map(|w| w.total)),
            );
        }
        if gains {
            s += &gain_block(exp, out, sc, w);
        }
    }
    s
}

/// Seed 003's figures: mean-square gain E|Z̃|²/E|W|² (empirical with its 95 % half-width, exact, and
/// exact for the noise alone), the filter's a-anisotropic norm² and its guaranteed γ².
fn gain_block(exp: &Experiment, out: &RunOutcome, sc: &crate::run::ScenarioOutcome, w: usize) -> String {
    let a = sc.input_anisotropy.map_or("—".to_string(), |a| format!("{a:.3}"));
    let mut s = format!("  mean-square gain, E|W|² = {:.3}, input anisotropy {a}\n", sc.input_power);
    s += &format!(
        "  {:w$}  {:>22}  {:>10}  {:>10}  {:>10}  {:>10}\n",
        "filter",
        "gain ± 95%",
        "exact",
        "noise only",
        exp.anisotropy.map_or("norm²_a".to_string(), |a| format!("norm²(a={a})")),
        "γ²"
    );
    for (f, spec) in exp.filters.iter().enumerate() {
        let st = &sc.mc.filters[f].total;
        let d = &out.filters[f];
        let p = sc.input_power;
        s += &format!(
            "  {:w$}  {:>12.5} ± {:<7.5}  {:>10.5}  {:>10.5}  {:>10}  {:>10}\n",
            spec.name,
            st.mean / p,
            (st.ci95().1 - st.mean) / p,
            sc.exact[f].total / p,
            (sc.exact[f].total - d.deterministic_error) / p,
            opt(d.anisotropic.map(|x| x.norm_sq)),
            opt(d.design.gain_bound.map(|g| g.gamma_sq)),
        );
    }
    s
}
