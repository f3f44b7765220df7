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
    let mut s = format!(
        "{}: {} trials × {} scenarios, N = {}, {} thread(s), {:.2} s\n",
        exp.name,
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
    }
    s
}
