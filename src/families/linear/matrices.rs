//! A matrix parameter of the `linear` family given once, or once per step (docs/families.md).

use serde::{Deserialize, Deserializer};

use crate::error::{Error, Result};
use crate::numerics::linalg::Mat;

/// A matrix given once for every step, or one per step k = 0..N (a 3-D array, first axis k).
#[derive(Clone, Debug)]
pub enum Matrices {
    Constant(Mat),
    PerStep(Vec<Mat>),
}

impl Matrices {
    pub(super) fn first(&self) -> &Mat {
        match self {
            Matrices::Constant(m) => m,
            Matrices::PerStep(ms) => &ms[0],
        }
    }
    pub(super) fn shape(&self) -> (usize, usize) {
        self.first().shape()
    }
    /// The matrix of every step k = 0..steps−1, or why not (a per-step array of another length).
    pub(super) fn steps(&self, key: &str, steps: usize) -> Result<Vec<Mat>> {
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

