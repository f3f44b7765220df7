//! One run's place in the recording and the names its views share: entity paths (each part
//! escaped), the filters a per-step view shows, the application id.

use crate::config::Experiment;
use crate::pipeline::{RunOutcome, ScenarioOutcome};

pub(super) type RecResult = std::result::Result<(), Box<dyn std::error::Error + Send + Sync>>;

/// The application id the recording and its blueprint share (the viewer pairs them by it).
pub(super) const APP: &str = "filterbench";

/// Filters shown by default in a scenario's per-step views; the rest are in the recording, one
/// click away in the viewer's tree.
pub const MAX_SHOWN: usize = 8;

/// An entity path from user-given and fixed parts, each escaped as one part.
pub fn path(parts: &[&str]) -> String {
    parts.iter().map(|s| rerun::EntityPathPart::new(*s).escaped_string()).collect::<Vec<_>>().join("/")
}

/// One run's place in the recording: its variant (if the file has variants) in front of every path.
pub(super) struct Run<'a> {
    pub(super) exp: &'a Experiment,
    pub(super) out: &'a RunOutcome,
}

impl Run<'_> {
    pub(super) fn at(&self, rest: &[&str]) -> String {
        match self.exp.variant.as_deref() {
            Some(v) => path(&[&[v], rest].concat()),
            None => path(rest),
        }
    }
}

/// The entity leaf of line search `s` under `design/<filter>/`.
pub(super) fn line_search_leaf(s: usize) -> String {
    format!("line_search_{s}")
}

/// The filters a scenario's per-step views show: all of them up to [`MAX_SHOWN`], else the
/// [`MAX_SHOWN`] with the smallest exact summed error, in the file's order.
pub fn shown(exp: &Experiment, sc: &ScenarioOutcome) -> Vec<usize> {
    let mut idx: Vec<usize> = (0..exp.filters.len()).collect();
    if idx.len() > MAX_SHOWN {
        idx.sort_by(|a, b| sc.exact[*a].total.total_cmp(&sc.exact[*b].total));
        idx.truncate(MAX_SHOWN);
        idx.sort_unstable();
    }
    idx
}
