//! The `[plant]` table: the matrices (constant or per step, seed 003 (3.1)), the mean of x0, the
//! known input, dropouts or modes, and the multiplicative noise factors, each error naming its key.

use super::experiment::check_name;
use super::modes::resolve_modes;
use super::schema::*;
use crate::error::{Error, Result};
use crate::model::kind::Strict;
use crate::model::plant::{Factor, Measurement, Plant, Steps};
use crate::numerics::linalg::{Mat, Vector, from_rows};

/// The plant's matrices as read, each checked against the state dimension n = rows of A.
pub(super) struct Matrices {
    pub(super) a: Mat,
    pub(super) b: Mat,
    pub(super) c: Mat,
    pub(super) d: Mat,
    pub(super) cz: Mat,
    pub(super) dz: Mat,
    pub(super) x0_mean: Vector,
    pub(super) known_input: Vec<Vector>,
}

/// Reads `[plant]`'s matrices, the mean of x0 and the known input r\[k] (docs/math.md §0).
pub(super) fn plant_matrices(p: &PlantFile) -> Result<Matrices> {
    let a = from_rows("plant.A", &p.A, None)?;
    let n = a.nrows();
    if n == 0 || !a.is_square() {
        return Err(Error::invalid(
            "plant.A",
            format!("must be square and non-empty, found {}×{}", a.nrows(), a.ncols()),
        ));
    }
    let b = from_rows("plant.B", &p.B, None)?;
    if b.nrows() != n {
        return Err(Error::invalid(
            "plant.B",
            format!("expected {n} rows (the state dimension: the rows of plant.A), found {}", b.nrows()),
        ));
    }
    let nw = b.ncols();
    let c = from_rows("plant.C", &p.C, None)?;
    if c.ncols() != n {
        return Err(Error::invalid(
            "plant.C",
            format!("expected {n} columns (the state dimension: the rows of plant.A), found {}", c.ncols()),
        ));
    }
    let ny = c.nrows();
    let d = from_rows("plant.D", &p.D, Some((ny, nw)))?;
    let cz = match &p.Cz {
        Some(r) => from_rows("plant.Cz", r, None)?,
        None => Mat::identity(n, n),
    };
    if cz.ncols() != n {
        return Err(Error::invalid(
            "plant.Cz",
            format!("expected {n} columns (the state dimension: the rows of plant.A), found {}", cz.ncols()),
        ));
    }
    let nz = cz.nrows();
    let dz = match &p.Dz {
        Some(r) => from_rows("plant.Dz", r, Some((nz, nw)))?,
        None => Mat::zeros(nz, nw),
    };
    let x0_mean = match &p.x0_mean {
        Some(v) if v.len() != n => {
            return Err(Error::invalid("plant.x0_mean", format!("expected {n} entries, found {}", v.len())));
        }
        Some(v) => Vector::from_column_slice(v),
        None => Vector::zeros(n),
    };
    if p.sum_from > p.horizon {
        return Err(Error::invalid("plant.sum_from", "must not exceed the horizon"));
    }
    if p.first_measurement > p.horizon {
        return Err(Error::invalid("plant.first_measurement", "must not exceed the horizon"));
    }
    let known_input = match &p.known_input {
        None => Vec::new(),
        Some(Strict(KnownInputFile::Values { values })) => {
            let m = from_rows("plant.known_input.values", values, Some((p.horizon, n)))?;
            (0..p.horizon).map(|k| m.row(k).transpose()).collect()
        }
        Some(Strict(KnownInputFile::Sine { amplitude, frequency, phase })) => {
            if amplitude.len() != n {
                return Err(Error::invalid(
                    "plant.known_input.amplitude",
                    format!("expected {n} entries, found {}", amplitude.len()),
                ));
            }
            (0..p.horizon)
                .map(|k| Vector::from_iterator(n, amplitude.iter().map(|a| a * (frequency * k as f64 + phase).sin())))
                .collect()
        }
    };

    Ok(Matrices { a, b, c, d, cz, dz, x0_mean, known_input })
}

/// The plant (docs/math.md §0): its matrices, each constant or given per step (seed 003 (3.1)), dropouts
/// (`plant.arrival`) or Markov modes (seed 001), which exclude each other.
pub(super) fn plant(
    p: &PlantFile,
    m: Matrices,
    dims: Vec<(String, usize)>,
    modes: Option<&ModesFile>,
) -> Result<Plant> {
    let Matrices { a, b, c, d, cz, dz, x0_mean, known_input } = m;
    let per_step = [
        ("A", &p.A_steps, a.shape()),
        ("B", &p.B_steps, b.shape()),
        ("C", &p.C_steps, c.shape()),
        ("D", &p.D_steps, d.shape()),
        ("Cz", &p.Cz_steps, cz.shape()),
        ("Dz", &p.Dz_steps, dz.shape()),
    ]
    .map(|(name, list, shape)| steps(p.horizon, name, list, shape));
    let mut plant = Plant::new(p.horizon, a, b, c, d, cz, dz, x0_mean, p.first_measurement, known_input, dims);
    plant.sum_from = p.sum_from;
    let [a, b, c, d, cz, dz] = per_step;
    for (field, given) in [&mut plant.a, &mut plant.b, &mut plant.c, &mut plant.d, &mut plant.cz, &mut plant.dz]
        .into_iter()
        .zip([a?, b?, c?, d?, cz?, dz?])
    {
        if let Some(s) = given {
            *field = s;
        }
    }
    plant.factors = factors(p, &plant)?;
    if let Some(pa) = p.arrival {
        if !(pa > 0.0 && pa <= 1.0) {
            return Err(Error::invalid("plant.arrival", format!("a probability in (0, 1] is needed, got {pa}")));
        }
        plant.set_arrival(pa);
    }
    if let Some(mf) = modes {
        if plant.arrival().is_some() {
            return Err(Error::invalid("modes", "a plant has either dropouts (plant.arrival) or [modes], not both"));
        }
        plant.measurement = Measurement::Markov(resolve_modes(mf, &plant)?);
    }
    Ok(plant)
}

/// `[[plant.multiplicative]]`: each factor's name, shape (scaled to unit variance) and the
/// matrices it multiplies, of the shapes of the plant's (seed 003 (3.1)).
fn factors(p: &PlantFile, plant: &Plant) -> Result<Vec<Factor>> {
    let mut names = std::collections::BTreeSet::new();
    let mut out = Vec::new();
    for (i, f) in p.multiplicative.iter().enumerate() {
        let key = format!("plant.multiplicative[{i}]");
        check_name(&format!("{key}.name"), &f.name)?;
        if !names.insert(f.name.as_str()) {
            return Err(Error::invalid(format!("{key}.name"), format!("factor name `{}` is repeated", f.name)));
        }
        f.shape.validate(&format!("{key}.shape"))?;
        let one = |name: &str,
                   constant: &Option<Rows>,
                   list: &Option<Vec<Rows>>,
                   shape: (usize, usize)|
         -> Result<Option<Steps>> {
            match (constant, list) {
                (Some(_), Some(_)) => {
                    Err(Error::invalid(format!("{key}.{name}"), format!("give {name} or {name}_steps, not both")))
                }
                (Some(r), None) => Ok(Some(Steps::constant(from_rows(&format!("{key}.{name}"), r, Some(shape))?))),
                (None, Some(_)) => steps(p.horizon, &format!("multiplicative[{i}].{name}"), list, shape),
                (None, None) => Ok(None),
            }
        };
        let shape = |s: &Steps| (s.nrows(), s.ncols());
        let factor = Factor {
            name: f.name.clone(),
            shape: f.shape.clone(),
            a: one("A", &f.A, &f.A_steps, shape(&plant.a))?,
            b: one("B", &f.B, &f.B_steps, shape(&plant.b))?,
            c: one("C", &f.C, &f.C_steps, shape(&plant.c))?,
            d: one("D", &f.D, &f.D_steps, shape(&plant.d))?,
            cz: one("Cz", &f.Cz, &f.Cz_steps, shape(&plant.cz))?,
            dz: one("Dz", &f.Dz, &f.Dz_steps, shape(&plant.dz))?,
        };
        if [&factor.a, &factor.b, &factor.c, &factor.d, &factor.cz, &factor.dz].iter().all(|m| m.is_none()) {
            return Err(Error::invalid(key, "a factor multiplies at least one of A, B, C, D, Cz, Dz"));
        }
        out.push(factor);
    }
    Ok(out)
}

/// `plant.NAME_steps`: one matrix of `shape` per step k = 0..N, replacing NAME.
fn steps(horizon: usize, name: &str, list: &Option<Vec<Rows>>, shape: (usize, usize)) -> Result<Option<Steps>> {
    let Some(list) = list else { return Ok(None) };
    let key = format!("plant.{name}_steps");
    if list.len() != horizon + 1 {
        return Err(Error::invalid(
            &key,
            format!("expected one matrix per step k = 0..N ({}), found {}", horizon + 1, list.len()),
        ));
    }
    let ms = list
        .iter()
        .enumerate()
        .map(|(k, r)| from_rows(&format!("{key}[{k}]"), r, Some(shape)))
        .collect::<Result<_>>()?;
    Ok(Some(Steps::per_step(ms)))
}
