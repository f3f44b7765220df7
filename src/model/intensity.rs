//! A white-noise intensity that may change with time: seed 004's 𝒱(τ) and 𝒲(τ) (the seed's
//! statement of the problem, eqs (2)–(3), and V_(n)(τ), W_(m)(τ) of (7)–(8)), scaled in time by a
//! scalar profile in the experiment file: a number (constant) or `{ times = [t_0, …], values =
//! [v_0, …] }`, piecewise linear through the points (t_i, v_i) and constant beyond the first and
//! last time.
//!
//! **Sampling.** Over step k, [t_k, t_{k+1}) with t_k = kΔ, the intensity is replaced by its mean
//! over the step (the exact integral of the piecewise-linear profile divided by Δ). The sampled
//! model then is exactly the continuous one with that step-wise constant intensity: the integrated
//! process noise over the step is the constant-intensity one scaled by the mean, and the sampled
//! measurement noise (1/Δ)∫ dw over the step has covariance mean · W/Δ.

use crate::error::{Error, Result};

/// A validated intensity profile.
#[derive(Clone, Debug, PartialEq)]
pub enum Intensity {
    Constant(f64),
    /// Piecewise linear through (times\[i], values\[i]), times strictly increasing, values ≥ 0.
    Profile {
        times: Vec<f64>,
        values: Vec<f64>,
    },
}

impl Intensity {
    /// Reads `value` (a number or a `{ times, values }` table) of the key `key`: one error line
    /// naming the key (or the offending entry) and the cause.
    pub fn parse(key: &str, value: &toml::Value) -> Result<Self> {
        let number = |k: &str, v: &toml::Value| match v {
            toml::Value::Float(x) => Ok(*x),
            toml::Value::Integer(i) => Ok(*i as f64),
            other => Err(Error::invalid(k, format!("must be a number, found {}", other.type_str()))),
        };
        let nonnegative = |k: &str, x: f64| {
            if x >= 0.0 && x.is_finite() {
                Ok(x)
            } else {
                Err(Error::invalid(k, format!("must be ≥ 0 and finite, got {x}")))
            }
        };
        let table = match value {
            toml::Value::Float(_) | toml::Value::Integer(_) => {
                return Ok(Intensity::Constant(nonnegative(key, number(key, value)?)?));
            }
            toml::Value::Table(t) => t,
            other => {
                return Err(Error::invalid(
                    key,
                    format!("a number ≥ 0 or a table {{ times = [...], values = [...] }}, found {}", other.type_str()),
                ));
            }
        };
        if let Some(stray) = table.keys().find(|k| *k != "times" && *k != "values") {
            return Err(Error::invalid(format!("{key}.{stray}"), "unknown key (a profile has `times` and `values`)"));
        }
        let list = |name: &str| -> Result<Vec<f64>> {
            let k = format!("{key}.{name}");
            match table.get(name) {
                None => Err(Error::invalid(&k, "missing")),
                Some(toml::Value::Array(a)) => {
                    a.iter().enumerate().map(|(i, v)| number(&format!("{k}[{i}]"), v)).collect()
                }
                Some(other) => {
                    Err(Error::invalid(&k, format!("must be a list of numbers, found {}", other.type_str())))
                }
            }
        };
        let (times, values) = (list("times")?, list("values")?);
        if times.is_empty() {
            return Err(Error::invalid(format!("{key}.times"), "at least one point"));
        }
        if values.len() != times.len() {
            return Err(Error::invalid(
                format!("{key}.values"),
                format!("{} values for {} times (one value per time)", values.len(), times.len()),
            ));
        }
        for (i, t) in times.iter().enumerate() {
            if !t.is_finite() {
                return Err(Error::invalid(format!("{key}.times[{i}]"), format!("must be finite, got {t}")));
            }
            if i > 0 && *t <= times[i - 1] {
                return Err(Error::invalid(format!("{key}.times[{i}]"), "the times must increase strictly"));
            }
        }
        for (i, v) in values.iter().enumerate() {
            nonnegative(&format!("{key}.values[{i}]"), *v)?;
        }
        Ok(Intensity::Profile { times, values })
    }

    /// Whether the intensity changes with time.
    pub fn varies(&self) -> bool {
        matches!(self, Intensity::Profile { .. })
    }

    /// The value at time t (linear interpolation, constant beyond the ends).
    pub fn at(&self, t: f64) -> f64 {
        match self {
            Intensity::Constant(v) => *v,
            Intensity::Profile { times, values } => {
                let i = times.partition_point(|x| *x <= t);
                if i == 0 {
                    values[0]
                } else if i == times.len() {
                    values[i - 1]
                } else {
                    let (t0, t1, v0, v1) = (times[i - 1], times[i], values[i - 1], values[i]);
                    v0 + (v1 - v0) * (t - t0) / (t1 - t0)
                }
            }
        }
    }

    /// The mean over [a, b] (a < b): the trapezoid rule on the pieces between the profile's kinks,
    /// exact for a piecewise-linear function.
    pub fn mean(&self, a: f64, b: f64) -> f64 {
        match self {
            Intensity::Constant(v) => *v,
            Intensity::Profile { times, .. } => {
                let mut knots = vec![a];
                knots.extend(times.iter().copied().filter(|t| *t > a && *t < b));
                knots.push(b);
                let area: f64 = knots.windows(2).map(|w| (w[1] - w[0]) * (self.at(w[0]) + self.at(w[1])) / 2.0).sum();
                area / (b - a)
            }
        }
    }

    /// The mean over step k, [kΔ, (k+1)Δ) (module docs).
    pub(crate) fn step_mean(&self, k: usize, dt: f64) -> f64 {
        self.mean(k as f64 * dt, (k + 1) as f64 * dt)
    }
}
