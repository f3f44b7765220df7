//! Stage 5: what each family adds to the finished run ([`crate::families::Family::after_run`]),
//! computed once here so the reports only format it.

use crate::config::Experiment;
use crate::error::Result;
use crate::families::{Finding, RunView};
use crate::model::shape::Shape;
use crate::numerics::linalg::Mat;
use crate::sim::noise::NoiseSampler;

use super::{DesignedFilter, ScenarioOutcome};

/// The stream index of the pilot record: no scenario has it.
const PILOT_STREAM: usize = 1 << 40;

/// One record y\[0..N] (column k = y\[k]) of the experiment's truth at the nominal covariances, drawn
/// Gaussian from the pilot stream: the one record a user would have to tune a filter on
/// ([`RunView::pilot_record`]).
pub fn pilot_record(exp: &Experiment) -> Mat {
    let plant = &exp.plant;
    let sampler = NoiseSampler::new(plant, &exp.nominal, &Shape::Gaussian);
    let mut draw = sampler.workspace();
    sampler.draw_trial(exp.seed, PILOT_STREAM, 0, &mut draw);
    let mut x = draw.x0.clone();
    let mut y = Mat::zeros(plant.ny(), plant.steps());
    for k in 0..plant.steps() {
        let w = draw.w.column(k);
        y.set_column(k, &(&*plant.c_at(k) * &x + &*plant.d_at(k) * w));
        x = plant.a_at(k) * &x + plant.b_at(k) * w;
    }
    y
}

/// Every family's finding on the run, in the order the families first appear in the file.
pub(crate) fn after_run(
    exp: &Experiment,
    filters: &[DesignedFilter],
    scenarios: &[ScenarioOutcome],
) -> Result<Vec<Finding>> {
    let pilot = || pilot_record(exp);
    let view = RunView {
        plant: &exp.plant,
        nominal: &exp.nominal,
        string: exp.string.as_ref(),
        filters: exp
            .filters
            .iter()
            .zip(filters)
            .map(|(spec, d)| (spec.name.as_str(), spec.configured.family(), &d.design))
            .collect(),
        exact: scenarios.iter().map(|s| (s.name.as_str(), s.exact.iter().map(|e| e.total).collect())).collect(),
        monte_carlo: scenarios
            .iter()
            .map(|s| {
                s.mc.filters
                    .iter()
                    .map(|f| {
                        let (low, high) = f.total.ci95();
                        (f.total.mean, low, high)
                    })
                    .collect()
            })
            .collect(),
        pilot_record: &pilot,
    };
    let mut families: Vec<&'static str> = Vec::new();
    let mut out = Vec::new();
    for (i, spec) in exp.filters.iter().enumerate() {
        let family = spec.configured.family();
        if families.contains(&family) {
            continue;
        }
        families.push(family);
        let mine: Vec<usize> =
            (i..exp.filters.len()).filter(|&j| exp.filters[j].configured.family() == family).collect();
        if let Some(f) = spec.configured.after_run(&view, &mine)? {
            out.push(f);
        }
    }
    Ok(out)
}
