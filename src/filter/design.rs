//! What a design hands on: its realization, what its theory promises, the covariance it was
//! designed at, and the iterations of an iterative design.

use crate::error::{Error, Result};
use crate::filter::realization::Realization;
use crate::model::choice::{CovChoice, CovChoiceFile, check_point};
use crate::model::plant::{Covariances, Pattern, Plant};
use crate::model::string::StringModel;
use crate::model::uncertainty::CovSet;
use crate::numerics::linalg::Mat;

/// What a family designs from: the plant and its information pattern, the nominal covariances
/// (a disturbance block holds its design surrogate, seed 000 eq (39)) and their uncertainty sets,
/// and, for seed 004, the string. `name` is the filter's, for the keys in messages.
#[derive(Clone)]
pub struct DesignInput<'a> {
    pub name: &'a str,
    pub plant: &'a Plant,
    pub pattern: Pattern,
    pub nominal: Covariances,
    pub sets: &'a [Option<CovSet>],
    pub string: Option<&'a StringModel>,
}

impl DesignInput<'_> {
    /// `filters.NAME.sub`, the key a message about this filter's parameter `sub` names.
    pub fn key(&self, sub: &str) -> String {
        format!("filters.{}.{sub}", self.name)
    }

    pub(crate) fn has_sets(&self) -> bool {
        self.sets.iter().any(Option::is_some)
    }

    /// The covariance a design parameter names (docs/math.md §7's choices, without the ones that name
    /// another filter: the caller refuses those with its own reason). `has_sets`: whether the
    /// choices that need an uncertainty set may be taken.
    pub(crate) fn design_point(&self, key: &str, choice: &CovChoiceFile, has_sets: bool) -> Result<Covariances> {
        let c = CovChoice::resolve(key, choice, self.plant, &self.nominal, has_sets, |_| None)?;
        let cov = c
            .point(&self.nominal, self.sets)?
            .ok_or_else(|| Error::invalid(key, "refers to a filter, which is not allowed here"))?;
        check_point(key, &c.label(|_| ""), self.plant, &cov)?;
        Ok(cov)
    }
}

/// What a family's theory promises about its error.
#[derive(Clone, Debug)]
pub struct Guarantee {
    pub kind: GuaranteeKind,
    pub total: f64,
    pub per_step: Vec<f64>,
}

/// The kinds of [`Guarantee`]; [`GuaranteeKind::name`] is the `guarantee_kind` column and the
/// manifest's `guarantee.kind`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum GuaranteeKind {
    /// The summed error the filter attains when the noise has its design covariance (Kalman,
    /// intermittent, Markov-jump): the filter's belief, not a promise under another covariance.
    ExactAtDesign,
    /// Seed 000's minimax bound: the summed error at the least favourable covariance K̂, which no
    /// covariance of the sets exceeds (Theorem 1.2).
    Minimax,
}

impl GuaranteeKind {
    pub fn name(self) -> &'static str {
        match self {
            GuaranteeKind::ExactAtDesign => "exact_at_design",
            GuaranteeKind::Minimax => "minimax",
        }
    }

    /// Whether the guarantee is a bound over the experiment's uncertainty (seed 000 Theorem 3),
    /// rather than the filter's error at one covariance.
    pub(crate) fn bounds_the_sets(self) -> bool {
        match self {
            GuaranteeKind::ExactAtDesign => false,
            GuaranteeKind::Minimax => true,
        }
    }
}

/// A typed record the reports format without knowing its type: its JSON for the manifest, and the
/// numbers it names for the summary table. A family's design figures ([`Figures`]) and its analysis
/// of a finished run are records; whoever knows the type reads it back with [`AsAny::as_any`].
pub trait Record: ToJson + AsAny + std::fmt::Debug + Send + Sync {
    /// The numbers shown as summary columns, `figure_<name>` (none unless the family asks).
    fn summary(&self) -> Vec<(&'static str, f64)> {
        Vec::new()
    }
}

/// A record's JSON (every `Serialize` type has one).
pub trait ToJson {
    fn json(&self) -> serde_json::Value;
}

impl<T: serde::Serialize> ToJson for T {
    fn json(&self) -> serde_json::Value {
        serde_json::to_value(self).unwrap_or_default()
    }
}

/// A record as `Any`, to read it back as its type.
pub trait AsAny {
    fn as_any(&self) -> &dyn std::any::Any;
}

impl<T: std::any::Any> AsAny for T {
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}

/// A family's own design figures, typed by the family ([`Figures::of`]) and read back as that
/// type ([`Figures::get`]); the manifest lists their fields under `diagnostics`.
#[derive(Clone, Debug, Default)]
pub struct Figures(Option<std::sync::Arc<dyn Record>>);

impl Figures {
    pub fn of(record: impl Record + 'static) -> Self {
        Figures(Some(std::sync::Arc::new(record)))
    }
    /// The figures as the family's type `T`, if they are one.
    pub fn get<T: 'static>(&self) -> Option<&T> {
        self.0.as_deref()?.as_any().downcast_ref()
    }
    /// The fields, as the manifest lists them (none when the family has no figures).
    pub fn json(&self) -> serde_json::Map<String, serde_json::Value> {
        match self.0.as_deref().map(ToJson::json) {
            Some(serde_json::Value::Object(m)) => m,
            _ => serde_json::Map::new(),
        }
    }
    /// The numbers for the summary table ([`Record::summary`]).
    pub fn summary(&self) -> Vec<(&'static str, f64)> {
        self.0.as_deref().map(Record::summary).unwrap_or_default()
    }
}

/// One iteration of an iterative design (seed 000 Algorithm 1: s, I(K(s)), the gap δ(s), the step
/// τ(s) taken after it).
#[derive(Clone, Debug)]
pub struct TraceRow {
    pub iteration: usize,
    pub objective: f64,
    pub gap: f64,
    pub step: f64,
}

/// The objective along one line search of an iterative design, sampled on [0, 1] (seed 000
/// Fig. 1: I(K(s) + τ(K̃ − K(s)))/N against τ, N the number of counted steps).
#[derive(Clone, Debug)]
pub struct LineSearch {
    /// s, the iteration whose segment K(s) → K̃ this is.
    pub iteration: usize,
    /// τ, ascending; includes the step taken.
    pub tau: Vec<f64>,
    /// I/N at each τ.
    pub value: Vec<f64>,
}

/// A designed filter.
#[derive(Clone, Debug)]
pub struct Design {
    pub realization: Realization,
    pub guarantee: Option<Guarantee>,
    /// The covariance the filter was designed at (Kalman: its `design`; minimax: K̂), if any.
    pub design_covariance: Option<Covariances>,
    /// The second moment E\[e eᵀ] of the output error e = z − ẑ per step that the filter states
    /// it believes, when given directly (the `linear` family's `claimed`: Cz P Czᵀ) rather than as
    /// its error at a design covariance: the claimed error and the NEES weights then come from it.
    pub claimed_error: Option<Vec<Mat>>,
    /// Iterations of the design procedure (empty for closed-form designs).
    pub trace: Vec<TraceRow>,
    /// The first line searches of the design procedure, sampled (minimax: seed 000 Fig. 1).
    pub line_searches: Vec<LineSearch>,
    /// The family's own figures ([`Figures`]).
    pub figures: Figures,
    /// Anything else worth keeping in the manifest (solver figures, timings, …); nothing reads
    /// these back.
    pub diagnostics: serde_json::Map<String, serde_json::Value>,
    /// A guarantee that holds for every single trial (seed 002's H∞-λ), checked on each one.
    pub per_trial: Option<PerTrialBound>,
    /// A bound on the mean-square gain over inputs of bounded anisotropy (seed 003).
    pub gain_bound: Option<GainBound>,
}

impl Design {
    /// A filter with no promise attached; families add theirs with struct update syntax.
    pub fn new(realization: Realization, diagnostics: serde_json::Map<String, serde_json::Value>) -> Self {
        Design {
            realization,
            guarantee: None,
            design_covariance: None,
            claimed_error: None,
            trace: Vec::new(),
            line_searches: Vec::new(),
            figures: Figures::default(),
            diagnostics,
            per_trial: None,
            gain_bound: None,
        }
    }

    /// The manifest's `diagnostics`: the typed [`Figures`] and the extras in one JSON object.
    pub(crate) fn manifest_diagnostics(&self) -> serde_json::Map<String, serde_json::Value> {
        let mut all = self.diagnostics.clone();
        all.extend(self.figures.json());
        all
    }
}

/// Seed 003's promise: E|Z̃|² ≤ γ² E|W|² for every input W = col(w\[0..N]) with anisotropy ≤ a
/// (a = ∞: every input; the H∞-suboptimal filter).
#[derive(Clone, Copy, Debug)]
pub struct GainBound {
    /// The guaranteed γ², certified: at least Theorem 1's bound for the returned filter rounded up
    /// past its error (`families::anisotropic::Checked::certified_sq`).
    pub gamma_sq: f64,
    /// The design program's γ² as clarabel returned it (the `design_gain` column).
    pub design_gamma_sq: f64,
    pub anisotropy: f64,
    /// What seed 003's Theorem 1 certifies for the designed filter with a full P(k)
    /// (`analysis::theorem1::analyze`): between the exact norm² and γ²; its gap to γ² is what the
    /// design's restriction of P costs.
    pub theorem1_sq: f64,
}

/// Seed 002's per-realization promises, with the input energy
/// E_t = |x0 − E x0|²_R + Σ_{k<t} |w\[k]|²_G (R, G the nominal covariances of x0 and w).
#[derive(Clone, Debug)]
pub enum PerTrialBound {
    /// H∞-λ (eqs (5.9)–(5.10)): (Σ_{k<N} |e_z\[k]|² + e\[N]ᵀ S e\[N]) / E_N < bound, e = x − s.
    Ratio { bound: f64, terminal_weight: Mat },
    /// Generalized H2 (Theorem 3.1 on (5.6)–(5.7)): e_z\[t]ᵀ Q\[t] e_z\[t] ≤ E_t at every step t, with
    /// Q\[t] = (Cz P2\[t] Czᵀ)⁺: the error lies in the ellipsoid of Cz P2 Czᵀ scaled by the energy.
    Ellipsoid { weights: Vec<Mat> },
}

impl PerTrialBound {
    /// The bound on the reported ratio (1 for the ellipsoid form).
    pub fn bound(&self) -> f64 {
        match self {
            PerTrialBound::Ratio { bound, .. } => *bound,
            PerTrialBound::Ellipsoid { .. } => 1.0,
        }
    }
}
