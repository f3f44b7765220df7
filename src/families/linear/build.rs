//! The realizations of the `linear` family's forms (module docs of [`super`]), their sizes
//! checked against the plant with the key named.

use crate::error::{Error, Result};
use crate::filter::design::DesignInput;
use crate::filter::realization::{Gains, Realization};
use crate::model::plant::Pattern;
use crate::numerics::linalg::{Mat, Vector, check_psd};

use super::matrices::Matrices;
use super::params::{GainForm, ModeMatrices, Params, RunOrigin};

/// The modes the filter's matrices are given for: one table per mode of a switching plant
/// (`modes`), or a single empty one (every key the filter's own) when the filter does not switch.
fn mode_tables<'a>(input: &DesignInput, p: &'a Params) -> Result<Vec<Option<&'a ModeMatrices>>> {
    let Some(modes) = &p.modes else { return Ok(vec![None]) };
    let plant = input.plant;
    let Some(names) = plant.modes().map(|m| m.names.clone()) else {
        return Err(Error::invalid(
            input.key("modes"),
            "per-mode matrices need a switching plant ([modes] or plant.arrival), and this one does not switch",
        ));
    };
    if modes.len() != names.len() {
        return Err(Error::invalid(
            input.key("modes"),
            format!("has {} tables, the plant has {} modes ({})", modes.len(), names.len(), names.join(", ")),
        ));
    }
    Ok(modes.iter().map(Some).collect())
}

/// `key` of mode `m` (its own, else the filter's), as N + 1 matrices, with the key that names it.
fn per_step(
    input: &DesignInput,
    mode: Option<&ModeMatrices>,
    m: usize,
    key: &str,
    pick: impl Fn(&ModeMatrices) -> &Option<Matrices>,
    own: &Option<Matrices>,
) -> Result<Option<(Vec<Mat>, String)>> {
    let (given, name) = match mode.and_then(|t| pick(t).as_ref()) {
        Some(x) => (Some(x), input.key(&format!("modes[{m}].{key}"))),
        None => (own.as_ref(), input.key(key)),
    };
    given.map(|x| Ok((x.steps(&name, input.plant.steps())?, name))).transpose()
}

/// Refuses a filter from a run whose plant model differs from this one's (sizes first, then the
/// matrices by their digest), naming the run's folder.
pub(super) fn check_origin(input: &DesignInput, origin: &RunOrigin) -> Result<()> {
    let plant = input.plant;
    let run = &origin.plant;
    let fail = |what: String| {
        Err(Error::invalid(
            input.key("from_run"),
            format!("the filter `{}` of `{}` was designed for another plant: {what}", origin.filter, origin.run),
        ))
    };
    let sizes = [
        ("states", run.states, plant.nx()),
        ("measurements", run.measurements, plant.ny()),
        ("outputs z", run.outputs, plant.nz()),
        ("steps", run.steps, plant.steps()),
        ("modes", run.modes, plant.n_modes()),
    ];
    if let Some((what, was, is)) = sizes.iter().find(|(_, was, is)| was != is) {
        return fail(format!("its plant has {was} {what}, this one {is}"));
    }
    if run.sha256 != plant.model_digest() {
        return fail("its plant's matrices (A, B, C, D, Cz, Dz) differ from this one's".into());
    }
    Ok(())
}

/// The realization form (module docs), per mode when `modes` is given.
pub(super) fn from_realization(input: &DesignInput, p: &Params) -> Result<Realization> {
    let plant = input.plant;
    let (n, ny, nz, steps) = (plant.nx(), plant.ny(), plant.nz(), plant.steps());
    let tables = mode_tables(input, p)?;
    let mut by_mode: Vec<Vec<Gains>> = vec![Vec::with_capacity(tables.len()); steps];
    let mut ns = None;
    for (m, t) in tables.iter().enumerate() {
        let get = |key, pick: fn(&ModeMatrices) -> &Option<Matrices>, own| per_step(input, *t, m, key, pick, own);
        let missing = |key: &str| {
            Error::invalid(input.key(key), format!("missing for mode {m}: give it for the filter or in modes[{m}]"))
        };
        let (af, kaf) = get("Af", |t| &t.af, &p.af)?.ok_or_else(|| missing("Af"))?;
        let (bf, kbf) = get("Bf", |t| &t.bf, &p.bf)?.ok_or_else(|| missing("Bf"))?;
        let (cf, kcf) = get("Cf", |t| &t.cf, &p.cf)?.ok_or_else(|| missing("Cf"))?;
        let s = af[0].nrows();
        if af[0].ncols() != s {
            return Err(Error::invalid(kaf, format!("must be square, found {}×{}", s, af[0].ncols())));
        }
        if let Some(first) = ns.filter(|first| *first != s) {
            return Err(Error::invalid(kaf, format!("is {s}×{s}, mode 0's is {first}×{first}")));
        }
        ns = Some(s);
        if bf[0].shape() != (s, ny) {
            let (r, c) = bf[0].shape();
            return Err(Error::invalid(kbf, format!("is {r}×{c}, the filter's state and the plant's measurements make it {s}×{ny}")));
        }
        if cf[0].shape() != (nz, s) {
            let (r, c) = cf[0].shape();
            return Err(Error::invalid(kcf, format!("is {r}×{c}, the plant's outputs z and the filter's state make it {nz}×{s}")));
        }
        let df = match get("Df", |t| &t.df, &p.df)? {
            Some((df, key)) if df[0].shape() != (nz, ny) => {
                return Err(Error::invalid(key, format!("is {}×{}, Cf and Bf make it {nz}×{ny}", df[0].nrows(), df[0].ncols())));
            }
            Some((df, key)) => {
                if input.pattern == Pattern::Prediction {
                    if let Some(k) = df.iter().position(|d| d.amax() != 0.0) {
                        return Err(Error::invalid(
                            key,
                            format!("must be 0 under pattern = \"prediction\" (ẑ[k] may not use y[k]), but step {k}'s is not"),
                        ));
                    }
                }
                df
            }
            None => vec![Mat::zeros(nz, ny); steps],
        };
        let gf = match get("Gf", |t| &t.gf, &p.gf)? {
            Some((gf, key)) if gf[0].nrows() != s || (gf[0].ncols() != n && gf[0].ncols() != 0) => {
                return Err(Error::invalid(
                    key,
                    format!("is {}×{}, the filter's state and the plant's state make it {s}×{n}", gf[0].nrows(), gf[0].ncols()),
                ));
            }
            Some((gf, _)) => gf,
            None => vec![known_input_gain(input, p, s, n)?; steps],
        };
        for (k, step) in by_mode.iter_mut().enumerate() {
            step.push(Gains {
                af: af[k].clone(),
                bf: bf[k].clone(),
                cf: cf[k].clone(),
                df: df[k].clone(),
                gf: gf[k].clone(),
            });
        }
    }
    let ns = ns.expect("at least one mode");
    let s0 = match &p.s0 {
        Some(s) if s.len() != ns => {
            return Err(Error::invalid(input.key("s0"), format!("has {} entries, Af has {ns} rows", s.len())));
        }
        Some(s) => Vector::from_column_slice(s),
        None => Vector::zeros(ns),
    };
    let r = if p.modes.is_some() {
        Realization::mode_indexed(s0, by_mode)
    } else {
        Realization::new(s0, by_mode.into_iter().map(|mut g| g.remove(0)).collect())
    };
    // A state of the plant's size is offered to the exact analysis as an estimate of x: its error
    // coordinates are used only where they are needed and `error_form` finds the identity
    // Af + Bf C − A = 0, Cz − Df C − Cf = 0 at every step and mode (docs/math.md §0).
    Ok(if ns == n { r.tracking(Mat::identity(n, n)) } else { r })
}

/// Gf from `known_input`: I (only for a state of the plant's size) or 0.
fn known_input_gain(input: &DesignInput, p: &Params, ns: usize, n: usize) -> Result<Mat> {
    let known_input = p.known_input.unwrap_or(ns == n);
    if known_input && ns != n {
        return Err(Error::invalid(
            input.key("known_input"),
            format!(
                "the known input enters as Gf = I, which needs the filter's state to have the plant's size {n}, not {ns}"
            ),
        ));
    }
    Ok(if known_input { Mat::identity(ns, n) } else { Mat::zeros(ns, n) })
}

/// The gain form (module docs) on the plant's matrices of each step, and with `modes` on mode θ's
/// matrices with θ's gain (seed 001 (6)).
pub(super) fn from_gain(input: &DesignInput, p: &Params, form: GainForm) -> Result<Realization> {
    let plant = input.plant;
    let (n, ny) = (plant.nx(), plant.ny());
    let tables = mode_tables(input, p)?;
    if p.modes.is_none() && plant.modes().is_some_and(|_| plant.arrival().is_none()) {
        return Err(Error::invalid(
            input.key("gain"),
            "a Markov plant has one model per mode: give modes = [{ gain = … }, …], one table per mode (an empty table uses this gain on that mode's model)",
        ));
    }
    let s0 = match &p.s0 {
        Some(s) if s.len() != n => {
            return Err(Error::invalid(input.key("s0"), format!("has {} entries, the plant has {n} states", s.len())));
        }
        Some(s) => Vector::from_column_slice(s),
        None => plant.x0_mean.clone(),
    };
    let mut by_mode: Vec<Vec<Gains>> = vec![Vec::with_capacity(tables.len()); plant.steps()];
    for (m, t) in tables.iter().enumerate() {
        let (ks, key) = per_step(input, *t, m, "gain", |t| &t.gain, &p.gain)?
            .ok_or_else(|| Error::invalid(input.key("gain"), format!("missing for mode {m}")))?;
        if ks[0].shape() != (n, ny) {
            let (r, c) = ks[0].shape();
            return Err(Error::invalid(key, format!("is {r}×{c}, the plant's model needs n × ny = {n}×{ny}")));
        }
        for (j, step) in by_mode.iter_mut().enumerate() {
            // Without modes, the one model of a plant that does not switch (a dropout plant's
            // filter does not see the dropouts); with modes, mode m's.
            let (a, c) = if p.modes.is_some() {
                (plant.a_of(j, m), plant.c_of(j, m))
            } else {
                (plant.a_at(j), plant.c_at(j))
            };
            let (cz, k) = (plant.cz_at(j), &ks[j]);
            step.push(match form {
                GainForm::Predictor => Gains::predictor(a, &c, k, cz),
                // Kalman's filtering form (families/kalman.rs) with L = A K and Lz = Cz K.
                GainForm::Filter => {
                    let lz = cz * k;
                    Gains { cf: cz - &lz * &*c, df: lz, ..Gains::predictor(a, &c, &(a * k), cz) }
                }
            });
        }
    }
    let r = if p.modes.is_some() {
        Realization::mode_indexed(s0, by_mode)
    } else {
        Realization::new(s0, by_mode.into_iter().map(|mut g| g.remove(0)).collect())
    };
    Ok(r.tracking(Mat::identity(n, n)))
}

/// The output error's second moment the filter believes, Cz P\[k] Czᵀ from its stated error
/// covariance P of x (the Dz w part of z is not in it), each P checked symmetric PSD.
pub(super) fn claimed_output(input: &DesignInput, claimed: &Matrices) -> Result<Vec<Mat>> {
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
