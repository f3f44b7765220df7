//! The `linear` family's parameters as the experiment file gives them (docs/experiment-files.md).

use serde::Deserialize;

use super::matrices::Matrices;

/// How a `gain` is applied (module docs).
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum GainForm {
    /// x̂\[k+1] = A x̂ + K (y − C x̂) + r, ẑ = Cz x̂.
    Predictor,
    /// x̂⁻\[k+1] = A x̂ + r, x̂ = x̂⁻ + K (y − C x̂⁻), ẑ = Cz x̂.
    Filter,
}

#[derive(Deserialize, Debug)]
#[serde(deny_unknown_fields)]
pub struct Params {
    #[serde(rename = "Af")]
    pub(super) af: Option<Matrices>,
    #[serde(rename = "Bf")]
    pub(super) bf: Option<Matrices>,
    #[serde(rename = "Cf")]
    pub(super) cf: Option<Matrices>,
    /// Default 0 (and must be 0 under the prediction pattern).
    #[serde(rename = "Df")]
    pub(super) df: Option<Matrices>,
    /// How the known input enters, ns × n; default from `known_input`.
    #[serde(rename = "Gf")]
    pub(super) gf: Option<Matrices>,
    /// The filter's initial state; default 0 in the realization form, the plant's E x0 in the gain form.
    pub(super) s0: Option<Vec<f64>>,
    /// Whether the known input enters as Gf = I; default: when the state has the plant's size.
    pub(super) known_input: Option<bool>,
    /// K, n × ny (or per step), on the plant's model.
    pub(super) gain: Option<Matrices>,
    pub(super) form: Option<GainForm>,
    /// Per-mode matrices of a switching plant, one table per mode (module docs).
    pub(super) modes: Option<Vec<ModeMatrices>>,
    /// The error covariance of x the filter believes, n × n (or per step).
    pub(super) claimed: Option<Matrices>,
    /// A bound on the summed error the user states; checked, never guaranteed.
    pub(super) claimed_bound: Option<f64>,
    /// Where the realization was read from (written by the configuration, docs/experiment-files.md
    /// "A filter from an earlier run").
    pub(super) from_run: Option<RunOrigin>,
}

/// One mode's matrices; a key not given is the filter's own.
#[derive(Deserialize, Debug, Default)]
#[serde(deny_unknown_fields)]
pub struct ModeMatrices {
    #[serde(rename = "Af")]
    pub(super) af: Option<Matrices>,
    #[serde(rename = "Bf")]
    pub(super) bf: Option<Matrices>,
    #[serde(rename = "Cf")]
    pub(super) cf: Option<Matrices>,
    #[serde(rename = "Df")]
    pub(super) df: Option<Matrices>,
    #[serde(rename = "Gf")]
    pub(super) gf: Option<Matrices>,
    pub(super) gain: Option<Matrices>,
}

/// The run a `from_run` filter came from and the plant it was designed on.
#[derive(Deserialize, Debug, Clone)]
#[serde(deny_unknown_fields)]
pub struct RunOrigin {
    /// The result folder, as written.
    pub run: String,
    /// The filter's name in that run.
    pub filter: String,
    /// The run's variant, if it has several.
    pub variant: Option<String>,
    /// The run's plant: sizes and [`crate::model::plant::Plant::model_digest`].
    pub plant: RunPlant,
}

/// The sizes and model digest of a run's plant, as its manifest records them.
#[derive(Deserialize, serde::Serialize, Debug, Clone, PartialEq, Eq)]
#[serde(deny_unknown_fields)]
pub struct RunPlant {
    pub states: usize,
    pub measurements: usize,
    pub outputs: usize,
    pub steps: usize,
    pub modes: usize,
    pub sha256: String,
}

impl Params {
    pub(super) fn is_gain_form(&self) -> bool {
        self.gain.is_some() || self.form.is_some()
    }
}
