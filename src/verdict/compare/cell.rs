//! The cells of a comparison of two result folders and the rule that classifies each one
//! (docs/regression-tests.md, "Comparing two runs"): a deterministic value against a relative
//! tolerance, a Monte Carlo mean by a two-sample z with the combined standard error.

use serde::Serialize;
use serde::ser::Serializer;

use crate::verdict::stats::{Sided, normal_p};

/// The default relative tolerance of deterministic columns: the accuracy the solvers state for one
/// solve. The SDPs are solved by clarabel to a relative gap and feasibility of 1e-10, and after a
/// numerical failure again at 1e-8 (`numerics::solve::conic`'s `Tuning::robust`); two routes to one
/// SDP figure agree to 1.1e-8 relative at worst (λ_min by the SDP (4.7) and by bisection,
/// docs/families.md, the `hinf` row); the moment recursions' rounding (steps · n · ε ≈ 1e-12,
/// docs/families.md "What is certified, and how") is far below. A larger move is not the same
/// computation rounded differently (another OpenBLAS kernel returns other SDP designs, measured in
/// docs/regression-tests.md).
pub const DEFAULT_REL_TOL: f64 = 1e-8;

/// The default family-wise false-alarm rate of the Monte Carlo cells (issue 27: one α per check).
pub const DEFAULT_ALPHA: f64 = 1e-3;

/// What `compare` is asked to do.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// Family-wise level of the two-sample tests, split over every Monte Carlo cell by Holm's
    /// procedure.
    pub alpha: f64,
    /// Relative tolerance of the deterministic columns.
    pub rel_tol: f64,
    /// Keep the identical cells in [`crate::verdict::compare::Comparison::cells`] too (by default
    /// only those that moved are kept; the counts include every cell).
    pub keep_identical: bool,
    /// Test Monte Carlo means by the two-sample z even when both runs used the same seed and
    /// trials (`matches_baseline`: a rounding difference in a mean is then no failure; the test is
    /// conservative, since common draws make the difference's variance smaller than the sum).
    pub independent_draws: bool,
}

impl Default for CompareOptions {
    fn default() -> Self {
        CompareOptions {
            alpha: DEFAULT_ALPHA,
            rel_tol: DEFAULT_REL_TOL,
            keep_identical: false,
            independent_draws: false,
        }
    }
}

/// What a column holds, which decides how its cells are compared.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Kind {
    /// A design or exact value: equal within the relative tolerance.
    Deterministic,
    /// A Monte Carlo mean with its standard error: two-sample z, Holm over all of them.
    MonteCarlo,
    /// Another sampled figure (an interval, a standard error, a quantile, a count of violations)
    /// with no test of its own.
    Sampled,
    /// Text or a flag (labels, parameters): equal or changed.
    Label,
    /// A table, column or row present in one folder only.
    Presence,
}

impl Kind {
    pub fn name(self) -> &'static str {
        match self {
            Kind::Deterministic => "deterministic",
            Kind::MonteCarlo => "monte carlo",
            Kind::Sampled => "sampled",
            Kind::Label => "label",
            Kind::Presence => "presence",
        }
    }
}

/// The verdict on one cell.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Status {
    /// Bit-equal (both NaN, or both null, count as equal).
    Identical,
    /// Moved, but not beyond the Monte Carlo noise (Holm) or the relative tolerance.
    WithinNoise,
    /// Moved beyond the noise or the tolerance.
    Changed,
    /// A sampled figure without a test that moved between independent draws: nothing is claimed.
    NotTested,
}

impl Status {
    pub fn name(self) -> &'static str {
        match self {
            Status::Identical => "identical",
            Status::WithinNoise => "moved within noise",
            Status::Changed => "changed beyond noise",
            Status::NotTested => "not tested",
        }
    }
}

impl Serialize for Status {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        s.serialize_str(self.name())
    }
}

/// One side's value of a cell.
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Num(f64),
    Text(String),
    /// The table has the row and column, and the value is null.
    Null,
    /// The table, column or row is not in this folder.
    Absent,
}

impl Value {
    pub fn num(&self) -> Option<f64> {
        match self {
            Value::Num(x) => Some(*x),
            _ => None,
        }
    }
}

impl std::fmt::Display for Value {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Value::Num(x) => write!(f, "{x}"),
            Value::Text(t) => write!(f, "{t:?}"),
            Value::Null => write!(f, "null"),
            Value::Absent => write!(f, "absent"),
        }
    }
}

/// JSON: a number (NaN and ±∞ as the strings "NaN", "inf", "-inf"), a string, null, or the string
/// "(absent)".
impl Serialize for Value {
    fn serialize<S: Serializer>(&self, s: S) -> std::result::Result<S::Ok, S::Error> {
        match self {
            Value::Num(x) if x.is_finite() => s.serialize_f64(*x),
            Value::Num(x) => s.serialize_str(&x.to_string()),
            Value::Text(t) => s.serialize_str(t),
            Value::Null => s.serialize_none(),
            Value::Absent => s.serialize_str("(absent)"),
        }
    }
}

/// One compared value: where it is (table, variant, scenario, filter[, filter_b], step, and for
/// gains and design traces the entry), both sides, and the verdict with its evidence.
#[derive(Clone, Debug, Serialize)]
pub struct Cell {
    /// The table's name (`summary`, `steps`, `paired`, `gains`, `design_trace`).
    pub table: &'static str,
    pub variant: Option<String>,
    pub scenario: Option<String>,
    /// The filter (`filter_a` of the paired table).
    pub filter: Option<String>,
    /// `filter_b` of the paired table.
    pub filter_b: Option<String>,
    pub step: Option<u32>,
    /// The rest of the row's key: `Af[1,0]` (with ` mode m` for a mode-indexed gain), `iteration 3`.
    pub entry: Option<String>,
    pub column: String,
    pub old: Value,
    pub new: Value,
    pub kind: Kind,
    pub status: Status,
    /// |new − old| / scale for a deterministic comparison (the scale is the larger |value| of the two,
    /// or of the gain matrix, or of the two filters' exact errors for a paired difference).
    pub rel_diff: Option<f64>,
    /// (new − old) / √(se_old² + se_new²) for a Monte Carlo cell of independent draws.
    pub z: Option<f64>,
    /// √(se_old² + se_new²), the standard error `z` divides by.
    pub std_error: Option<f64>,
    /// Two-sided p-value of `z`.
    pub p: Option<f64>,
    /// Holm's threshold for `p` at the comparison's α.
    pub holm_threshold: Option<f64>,
}

impl Cell {
    /// Where the cell is, for a line of text: `scenario=… filter=… step=3`.
    pub fn place(&self) -> String {
        let mut parts = vec![];
        let mut put = |k: &str, v: &Option<String>| {
            if let Some(v) = v {
                parts.push(format!("{k}={v}"));
            }
        };
        put("variant", &self.variant);
        put("scenario", &self.scenario);
        put(if self.filter_b.is_some() { "filter_a" } else { "filter" }, &self.filter);
        put("filter_b", &self.filter_b);
        put("step", &self.step.map(|s| s.to_string()));
        put("entry", &self.entry);
        parts.join(" ")
    }
}

/// Classifies two deterministic values: identical when equal (NaN = NaN, null = null), within
/// tolerance when |a − b| ≤ `rel_tol` · max(scale, |a|, |b|), else changed. Returns the relative
/// difference with the status (∞ when one side is null, NaN or infinite and the other not).
pub(crate) fn deterministic(old: &Value, new: &Value, scale: f64, rel_tol: f64) -> (Status, Option<f64>) {
    match (old, new) {
        (Value::Num(a), Value::Num(b)) => {
            if a == b || (a.is_nan() && b.is_nan()) {
                return (Status::Identical, Some(0.0));
            }
            if !a.is_finite() || !b.is_finite() {
                return (Status::Changed, Some(f64::INFINITY));
            }
            let rel = (a - b).abs() / scale.max(a.abs()).max(b.abs());
            (if rel <= rel_tol { Status::WithinNoise } else { Status::Changed }, Some(rel))
        }
        (a, b) if a == b => (Status::Identical, None),
        (Value::Num(_), _) | (_, Value::Num(_)) => (Status::Changed, Some(f64::INFINITY)),
        _ => (Status::Changed, None),
    }
}

/// The two-sample z of two independent Monte Carlo means, (new − old)/√(se_old² + se_new²), with
/// its two-sided p-value; None when the combined standard error is zero or not finite (every
/// trial equal: the value is then compared as a deterministic one).
pub(crate) fn two_sample(old: f64, se_old: f64, new: f64, se_new: f64) -> Option<(f64, f64)> {
    let se = (se_old * se_old + se_new * se_new).sqrt();
    if !(se > 0.0) || !se.is_finite() || !old.is_finite() || !new.is_finite() {
        return None;
    }
    let z = (new - old) / se;
    Some((z, normal_p(z, Sided::TwoSided)))
}
