//! The `linear` family (docs/families.md): a filter the user gives by its matrices, in one of two
//! forms, on which every analysis of the run is made like on a designed one.
//!
//! - Its realization (docs/math.md §0): s\[k+1] = Af s + Bf y + Gf r, ẑ = Cf s + Df y, with Gf = I
//!   when `known_input` (allowed only when the state has the plant's size) and Gf = 0 otherwise.
//! - A gain K on the plant's own model (A, C, Cz of each step), in predictor form
//!   x̂\[k+1] = A x̂ + K (y − C x̂) + r, ẑ = Cz x̂ (seed 000 eq (4), seed 002 eq (5.7): the
//!   realization [`Gains::predictor`] builds), or in filter form x̂⁻\[k+1] = A x̂ + r,
//!   x̂ = x̂⁻ + K (y − C x̂⁻), ẑ = Cz x̂, realized on the prior x̂⁻ like the Kalman family's filtering
//!   form (seed 000 eqs (4)–(6)): Af = A − (A K) C, Bf = A K, Cf = Cz − (Cz K) C, Df = Cz K. The
//!   part Dz w\[k] of z is estimated as zero: a gain on x carries no estimate of w.
//!
//! Each matrix is constant or given per step (N + 1 of them, first axis k). The family promises
//! nothing; the user may state the error covariance of x it believes (`claimed`, for the claimed
//! error and NEES) and a bound on its summed error (`claimed_bound`), which the run checks
//! against the exact and Monte Carlo errors and never shows as guaranteed.

use serde::{Deserialize, Deserializer};

use crate::error::{Error, Result};
use crate::filter::design::{Design, DesignInput, Figures, Record};
use crate::filter::realization::{Gains, Realization};
use crate::model::plant::Pattern;
use crate::numerics::linalg::{Mat, Vector, check_psd};

use super::family::{ANY_PATTERN, Family, Finding, Footprint, PlantSize, RunView, Supports};

/// A matrix given once for every step, or one per step k = 0..N (a 3-D array, first axis k).
#[derive(Clone, Debug)]
pub enum Matrices {
    Constant(Mat),
    PerStep(Vec<Mat>),
}

impl Matrices {
    fn first(&self) -> &Mat {
        match self {
            Matrices::Constant(m) => m,
            Matrices::PerStep(ms) => &ms[0],
        }
    }
    fn shape(&self) -> (usize, usize) {
        self.first().shape()
    }
    /// The matrix of every step k = 0..steps−1, or why not (a per-step array of another length).
    fn steps(&self, key: &str, steps: usize) -> Result<Vec<Mat>> {
        match self {
            Matrices::Constant(m) => Ok(vec![m.clone(); steps]),
            Matrices::PerStep(ms) if ms.len() == steps => Ok(ms.clone()),
            Matrices::PerStep(ms) => Err(Error::invalid(
                key,
                format!(
                    "{} matrices given per step; the horizon needs N + 1 = {steps} (k = 0..{})",
                    ms.len(),
                    steps - 1
                ),
            )),
        }
    }
}

/// A TOML array read as the rows of one matrix, or of one matrix per step (`per_step`): the
/// entries, or why not (a wrong rank, a non-number, a non-finite entry, an empty array).
fn entries(v: &toml::Value, per_step: bool) -> std::result::Result<Vec<Vec<Vec<f64>>>, String> {
    let num = |v: &toml::Value| match v {
        toml::Value::Float(x) if x.is_finite() => Ok(*x),
        toml::Value::Float(x) => Err(format!("entry {x} is not finite")),
        toml::Value::Integer(i) => Ok(*i as f64),
        other => Err(format!("expected a number, found a {}", other.type_str())),
    };
    let list = |v: &toml::Value| match v {
        toml::Value::Array(a) if !a.is_empty() => Ok(a.clone()),
        toml::Value::Array(_) => Err("an empty array".to_string()),
        other => Err(format!(
            "expected a matrix (an array of rows of numbers) or one per step, found a {}",
            other.type_str()
        )),
    };
    let matrix = |m: &toml::Value| -> std::result::Result<Vec<Vec<f64>>, String> {
        list(m)?
            .iter()
            .map(|row| match row {
                toml::Value::Array(r) => r.iter().map(num).collect(),
                _ => Err("expected a matrix (an array of rows of numbers), found a vector".to_string()),
            })
            .collect()
    };
    if per_step { list(v)?.iter().map(matrix).collect() } else { Ok(vec![matrix(v)?]) }
}

impl<'de> Deserialize<'de> for Matrices {
    fn deserialize<D: Deserializer<'de>>(d: D) -> std::result::Result<Self, D::Error> {
        use serde::de::Error as _;
        let v = toml::Value::deserialize(d)?;
        let per_step = matches!(&v, toml::Value::Array(a) if matches!(a.first(), Some(toml::Value::Array(r)) if matches!(r.first(), Some(toml::Value::Array(_)))));
        let nested = entries(&v, per_step).map_err(D::Error::custom)?;
        let mut mats = Vec::with_capacity(nested.len());
        for (k, rows) in nested.iter().enumerate() {
            let cols = rows[0].len();
            if cols == 0 {
                return Err(D::Error::custom("a row is empty"));
            }
            if let Some((i, r)) = rows.iter().enumerate().find(|(_, r)| r.len() != cols) {
                let at = if per_step { format!(" of step {k}") } else { String::new() };
                return Err(D::Error::custom(format!("row {i}{at} has {} entries, row 0 has {cols}", r.len())));
            }
            let m = Mat::from_fn(rows.len(), cols, |i, j| rows[i][j]);
            if let Some(first) = mats.first().map(Mat::shape).filter(|s| *s != m.shape()) {
                return Err(D::Error::custom(format!(
                    "step {k}'s matrix is {}×{}, step 0's is {}×{}",
                    m.nrows(),
                    m.ncols(),
                    first.0,
                    first.1
                )));
            }
            mats.push(m);
        }
        Ok(if per_step { Matrices::PerStep(mats) } else { Matrices::Constant(mats.remove(0)) })
    }
}

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
    af: Option<Matrices>,
    #[serde(rename = "Bf")]
    bf: Option<Matrices>,
    #[serde(rename = "Cf")]
    cf: Option<Matrices>,
    /// Default 0 (and must be 0 under the prediction pattern).
    #[serde(rename = "Df")]
    df: Option<Matrices>,
    /// The filter's initial state; default 0 in the realization form, the plant's E x0 in the gain form.
    s0: Option<Vec<f64>>,
    /// Whether the known input enters as Gf = I; default: when the state has the plant's size.
    known_input: Option<bool>,
    /// K, n × ny (or per step), on the plant's model.
    gain: Option<Matrices>,
    form: Option<GainForm>,
    /// The error covariance of x the filter believes, n × n (or per step).
    claimed: Option<Matrices>,
    /// A bound on the summed error the user states; checked, never guaranteed.
    claimed_bound: Option<f64>,
}

impl Params {
    fn is_gain_form(&self) -> bool {
        self.gain.is_some() || self.form.is_some()
    }
}

/// The family's figures: its form, its state size and the bound the user states (the summary's
/// `figure_claimed_bound`, never a guarantee).
#[derive(Debug, serde::Serialize)]
pub struct LinearFigures {
    pub form: &'static str,
    pub state: usize,
    pub claimed_bound: Option<f64>,
}

impl Record for LinearFigures {
    fn summary(&self) -> Vec<(&'static str, f64)> {
        self.claimed_bound.map(|b| vec![("claimed_bound", b)]).unwrap_or_default()
    }
}

/// What the run says of a stated bound: per `linear` filter with a `claimed_bound` and per
/// scenario, whether the exact summed error exceeds it, and whether the Monte Carlo mean does so
/// significantly (its 95 % interval lies wholly above the bound).
#[derive(Debug, serde::Serialize)]
pub struct ClaimedBounds {
    pub checks: Vec<BoundCheck>,
}

#[derive(Debug, serde::Serialize)]
pub struct BoundCheck {
    pub filter: String,
    pub scenario: String,
    pub claimed_bound: f64,
    pub exact: f64,
    pub mc_mean: f64,
    pub mc_ci_low: f64,
    pub broken_by_exact: bool,
    pub broken_by_monte_carlo: bool,
}

impl Record for ClaimedBounds {}

type Check = std::result::Result<(), (&'static str, String)>;

/// The family's entry: `family = "linear"`.
pub struct Linear;

impl Family for Linear {
    const NAME: &'static str = "linear";
    type Params = Params;

    /// Any plant but a Markov one: per-mode matrices are not read yet, and a gain on "the plant's
    /// model" has no single model there. Dropouts and multiplicative factors are part of the truth
    /// the filter runs on; the gain form uses the plant's mean matrices of each step.
    fn supports(_: &Params) -> Supports {
        Supports { patterns: ANY_PATTERN, markov_modes: false, varying_weights: true, ..Supports::ALL }
    }

    /// Exactly one form, its keys complete, and the sizes that do not need the plant consistent.
    fn check(p: &Params) -> Check {
        let realization_keys: [(&'static str, bool); 5] = [
            ("Af", p.af.is_some()),
            ("Bf", p.bf.is_some()),
            ("Cf", p.cf.is_some()),
            ("Df", p.df.is_some()),
            ("known_input", p.known_input.is_some()),
        ];
        if p.is_gain_form() {
            if let Some((key, _)) = realization_keys.iter().find(|(_, given)| *given) {
                return Err((key, "belongs to the realization form (Af, Bf, Cf), but gain/form of the gain form are given: give one form".into()));
            }
            if p.gain.is_none() {
                return Err(("gain", "missing: the gain form needs gain (n × ny, or one per step) and form".into()));
            }
            if p.form.is_none() {
                return Err(("form", "missing: \"predictor\" or \"filter\"".into()));
            }
        } else {
            for (key, given) in &realization_keys[..3] {
                if !given {
                    return Err((
                        key,
                        "missing: a linear filter is given by its realization (Af, Bf, Cf) or by a gain (gain, form)"
                            .into(),
                    ));
                }
            }
            let (af, bf, cf) =
                (p.af.as_ref().unwrap().shape(), p.bf.as_ref().unwrap().shape(), p.cf.as_ref().unwrap().shape());
            let ns = af.0;
            if af.1 != ns {
                return Err(("Af", format!("must be square, found {}×{}", af.0, af.1)));
            }
            if bf.0 != ns {
                return Err(("Bf", format!("has {} rows, Af has {ns}", bf.0)));
            }
            if cf.1 != ns {
                return Err(("Cf", format!("has {} columns, Af has {ns} rows", cf.1)));
            }
            if let Some(df) = p.df.as_ref().map(Matrices::shape).filter(|df| *df != (cf.0, bf.1)) {
                return Err(("Df", format!("is {}×{}, but Cf and Bf make it {}×{}", df.0, df.1, cf.0, bf.1)));
            }
            if let Some(s0) = p.s0.as_ref().filter(|s0| s0.len() != ns) {
                return Err(("s0", format!("has {} entries, Af has {ns} rows", s0.len())));
            }
        }
        if let Some(x) = p.s0.iter().flatten().find(|x| !x.is_finite()) {
            return Err(("s0", format!("entry {x} is not finite")));
        }
        if let Some((r, c)) = p.claimed.as_ref().map(Matrices::shape).filter(|(r, c)| r != c) {
            return Err(("claimed", format!("an error covariance must be square, found {r}×{c}")));
        }
        match p.claimed_bound {
            Some(b) if !(b.is_finite() && b >= 0.0) => {
                Err(("claimed_bound", format!("must be a finite number ≥ 0, found {b}")))
            }
            _ => Ok(()),
        }
    }

    fn footprint(p: &Params, plant: PlantSize) -> Footprint {
        let state = p.af.as_ref().map_or(plant.nx, |af| af.shape().0);
        Footprint { state, gain_sets: 1, dense_horizon: false }
    }

    fn design(input: &DesignInput, p: &Params) -> Result<Design> {
        let (realization, form) = match (&p.gain, p.form) {
            (Some(k), Some(form)) => (from_gain(input, k, form, p.s0.as_ref())?, form_name(form)),
            _ => (from_realization(input, p)?, "realization"),
        };
        let mut d = Design::new(realization, serde_json::Map::new());
        if let Some(claimed) = &p.claimed {
            d.claimed_error = Some(claimed_output(input, claimed)?);
        }
        let state = d.realization.ns();
        d.figures = Figures::of(LinearFigures { form, state, claimed_bound: p.claimed_bound });
        Ok(d)
    }

    fn after_run(run: &RunView, mine: &[usize]) -> Result<Option<Finding>> {
        let mut checks = Vec::new();
        for &f in mine {
            let (name, _, design) = run.filters[f];
            let Some(bound) = design.figures.get::<LinearFigures>().and_then(|l| l.claimed_bound) else { continue };
            for ((scenario, exact), mc) in run.exact.iter().zip(&run.monte_carlo) {
                let (mean, low, _) = mc[f];
                checks.push(BoundCheck {
                    filter: name.to_string(),
                    scenario: scenario.to_string(),
                    claimed_bound: bound,
                    exact: exact[f],
                    mc_mean: mean,
                    mc_ci_low: low,
                    broken_by_exact: exact[f] > bound,
                    broken_by_monte_carlo: low > bound,
                });
            }
        }
        Ok((!checks.is_empty())
            .then(|| Finding { family: Self::NAME, record: std::sync::Arc::new(ClaimedBounds { checks }) }))
    }
}

fn form_name(form: GainForm) -> &'static str {
    match form {
        GainForm::Predictor => "gain, predictor",
        GainForm::Filter => "gain, filter",
    }
}

/// The realization form (module docs), its sizes checked against the plant with the key named.
fn from_realization(input: &DesignInput, p: &Params) -> Result<Realization> {
    let plant = input.plant;
    let (n, ny, nz, steps) = (plant.nx(), plant.ny(), plant.nz(), plant.steps());
    let get = |key: &str, m: &Option<Matrices>| m.as_ref().map(|m| m.steps(&input.key(key), steps)).transpose();
    let (af, bf, cf) = (
        get("Af", &p.af)?.unwrap_or_default(),
        get("Bf", &p.bf)?.unwrap_or_default(),
        get("Cf", &p.cf)?.unwrap_or_default(),
    );
    let ns = af[0].nrows();
    if bf[0].ncols() != ny {
        return Err(Error::invalid(
            input.key("Bf"),
            format!("has {} columns, the plant has {ny} measurements", bf[0].ncols()),
        ));
    }
    if cf[0].nrows() != nz {
        return Err(Error::invalid(
            input.key("Cf"),
            format!("has {} rows, the plant has {nz} outputs z", cf[0].nrows()),
        ));
    }
    let df = get("Df", &p.df)?.unwrap_or_else(|| vec![Mat::zeros(nz, ny); steps]);
    if input.pattern == Pattern::Prediction {
        if let Some(k) = df.iter().position(|d| d.amax() != 0.0) {
            return Err(Error::invalid(
                input.key("Df"),
                format!("must be 0 under pattern = \"prediction\" (ẑ[k] may not use y[k]), but step {k}'s is not"),
            ));
        }
    }
    let known_input = p.known_input.unwrap_or(ns == n);
    if known_input && ns != n {
        return Err(Error::invalid(
            input.key("known_input"),
            format!(
                "the known input enters as Gf = I, which needs the filter's state to have the plant's size {n}, not {ns}"
            ),
        ));
    }
    let gf = if known_input { Mat::identity(ns, n) } else { Mat::zeros(ns, n) };
    let s0 = p.s0.as_ref().map_or(Vector::zeros(ns), |s| Vector::from_column_slice(s));
    let gains = (0..steps)
        .map(|k| Gains { af: af[k].clone(), bf: bf[k].clone(), cf: cf[k].clone(), df: df[k].clone(), gf: gf.clone() })
        .collect();
    let r = Realization::new(s0, gains);
    // A state of the plant's size is offered to the exact analysis as an estimate of x: its error
    // coordinates are used only where they are needed and `error_form` finds the identity
    // Af + Bf C − A = 0, Cz − Df C − Cf = 0 at every step (docs/math.md §0).
    Ok(if ns == n { r.tracking(Mat::identity(n, n)) } else { r })
}

/// The gain form (module docs) on the plant's matrices of each step.
fn from_gain(input: &DesignInput, k: &Matrices, form: GainForm, s0: Option<&Vec<f64>>) -> Result<Realization> {
    let plant = input.plant;
    let (n, ny) = (plant.nx(), plant.ny());
    let ks = k.steps(&input.key("gain"), plant.steps())?;
    if ks[0].shape() != (n, ny) {
        let (r, c) = ks[0].shape();
        return Err(Error::invalid(
            input.key("gain"),
            format!("is {r}×{c}, the plant's model needs n × ny = {n}×{ny}"),
        ));
    }
    let s0 = match s0 {
        Some(s) if s.len() != n => {
            return Err(Error::invalid(input.key("s0"), format!("has {} entries, the plant has {n} states", s.len())));
        }
        Some(s) => Vector::from_column_slice(s),
        None => plant.x0_mean.clone(),
    };
    let steps = (0..plant.steps())
        .map(|j| {
            let (a, c, cz, k) = (plant.a_at(j), &*plant.c_at(j), plant.cz_at(j), &ks[j]);
            match form {
                GainForm::Predictor => Gains::predictor(a, c, k, cz),
                // Kalman's filtering form (families/kalman.rs) with L = A K and Lz = Cz K.
                GainForm::Filter => {
                    let lz = cz * k;
                    Gains { cf: cz - &lz * c, df: lz, ..Gains::predictor(a, c, &(a * k), cz) }
                }
            }
        })
        .collect();
    Ok(Realization::state_estimator(s0, steps))
}

/// The output error's second moment the filter believes, Cz P\[k] Czᵀ from its stated error
/// covariance P of x (the Dz w part of z is not in it), each P checked symmetric PSD.
fn claimed_output(input: &DesignInput, claimed: &Matrices) -> Result<Vec<Mat>> {
    let plant = input.plant;
    let key = input.key("claimed");
    let ps = claimed.steps(&key, plant.steps())?;
    let n = plant.nx();
    if ps[0].shape() != (n, n) {
        return Err(Error::invalid(&key, format!("is {}×{}, the plant has {n} states", ps[0].nrows(), ps[0].ncols())));
    }
    let per_step = matches!(claimed, Matrices::PerStep(_));
    ps.iter()
        .enumerate()
        .map(|(k, p)| {
            let at = if per_step { format!("{key} (step {k})") } else { key.clone() };
            check_psd(&at, p)?;
            Ok(plant.cz_at(k) * p * plant.cz_at(k).transpose())
        })
        .collect()
}
