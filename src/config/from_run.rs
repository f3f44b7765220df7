//! A filter from an earlier run (docs/experiment-files.md, "A filter from an earlier run"): a
//! `linear` filter table with `from_run = "FOLDER"` and `filter = "NAME"` (and `variant` when the
//! run has several) gets that filter's realization, read from the run's gains.parquet with the
//! sizes its manifest records, in place of those keys, before the file is read into its schema.
//! The table keeps `from_run` as a record of the run, its filter and its plant, which the family's
//! design compares with this experiment's plant (`linear` family, module docs).

use std::path::Path;

use polars::prelude::*;
use sha2::{Digest, Sha256};

use super::files::FileInput;
use crate::error::{Error, Result};

/// Whether any table inside `v` names an earlier run (`from_run` as a string).
pub(super) fn has_runs(v: &toml::Value) -> bool {
    match v {
        toml::Value::Table(t) => matches!(t.get("from_run"), Some(toml::Value::String(_))) || t.values().any(has_runs),
        toml::Value::Array(a) => a.iter().any(has_runs),
        _ => false,
    }
}

/// Replaces every `from_run` reference inside `v` by the realization it names, recording the files
/// read in `out`; `base` is the experiment's folder.
pub(super) fn resolve_runs(v: &mut toml::Value, base: &Path, out: &mut Vec<FileInput>) -> Result<()> {
    match v {
        toml::Value::Table(t) if matches!(t.get("from_run"), Some(toml::Value::String(_))) => resolve(t, base, out),
        toml::Value::Table(t) => t.iter_mut().try_for_each(|(_, x)| resolve_runs(x, base, out)),
        toml::Value::Array(a) => a.iter_mut().try_for_each(|x| resolve_runs(x, base, out)),
        _ => Ok(()),
    }
}

/// The keys a `from_run` filter may not give: the run gives its whole realization.
const GIVEN_BY_RUN: [&str; 10] = ["Af", "Bf", "Cf", "Df", "Gf", "s0", "known_input", "gain", "form", "modes"];

fn resolve(t: &mut toml::Table, base: &Path, out: &mut Vec<FileInput>) -> Result<()> {
    let name = t.get("name").and_then(toml::Value::as_str).unwrap_or("?").to_string();
    let key = |sub: &str| format!("filters.{name}.{sub}");
    let run = t.remove("from_run").and_then(|v| v.as_str().map(str::to_string)).expect("a from_run string");
    let fail = |cause: String| Error::invalid(key("from_run"), format!("run `{run}`: {cause}"));
    if let Some(k) = GIVEN_BY_RUN.iter().find(|k| t.contains_key(**k)) {
        return Err(Error::invalid(key(k), "from_run gives the filter's whole realization: remove this key"));
    }
    let filter = match t.remove("filter") {
        Some(toml::Value::String(f)) => f,
        Some(_) => return Err(Error::invalid(key("filter"), "must be a string: the filter's name in that run")),
        None => return Err(Error::invalid(key("filter"), "missing: from_run needs the name of a filter of that run")),
    };
    let variant = match t.remove("variant") {
        Some(toml::Value::String(v)) => Some(v),
        Some(_) => return Err(Error::invalid(key("variant"), "must be a string: the run's variant")),
        None => None,
    };
    let folder = base.join(&run);
    if !folder.is_dir() {
        return Err(fail(format!(
            "{} is not a folder (a result folder of `filterbench experiment`)",
            folder.display()
        )));
    }
    let manifest_path = folder.join("manifest.json");
    let manifest_bytes = std::fs::read(&manifest_path)
        .map_err(|e| fail(format!("cannot read {} ({e}): not a result folder", manifest_path.display())))?;
    let manifest: serde_json::Value = serde_json::from_slice(&manifest_bytes)
        .map_err(|e| fail(format!("{} is not a manifest ({e})", manifest_path.display())))?;
    let entry = run_entry(&manifest, variant.as_deref()).map_err(&fail)?;
    let plant = entry.get("plant").or_else(|| manifest.get("plant")).cloned().ok_or_else(|| {
        fail("its manifest has no `plant` record (an older filterbench wrote it): run it again".into())
    })?;
    let filters = entry.get("filters").and_then(|f| f.as_array()).cloned().unwrap_or_default();
    let names: Vec<&str> = filters.iter().filter_map(|f| f.get("name")?.as_str()).collect();
    let Some(spec) = filters.iter().find(|f| f.get("name").and_then(|n| n.as_str()) == Some(filter.as_str())) else {
        return Err(Error::invalid(
            key("filter"),
            format!("run `{run}` has no filter `{filter}` (it has: {})", names.join(", ")),
        ));
    };
    let size = |v: &serde_json::Value, k: &str| {
        v.get(k).and_then(serde_json::Value::as_u64).map(|x| x as usize).ok_or_else(|| {
            fail(format!(
                "its manifest lacks `{k}` for the filter `{filter}` (an older filterbench wrote it): run it again"
            ))
        })
    };
    let r = spec.get("realization").cloned().unwrap_or_default();
    let sizes = Sizes {
        ns: size(&r, "states")?,
        modes: size(&r, "modes")?,
        gf_cols: size(&r, "known_input_columns")?,
        ny: size(&plant, "measurements")?,
        nz: size(&plant, "outputs")?,
        steps: size(&plant, "steps")?,
    };
    let gains_path = folder.join("gains.parquet");
    let gains_bytes =
        std::fs::read(&gains_path).map_err(|e| fail(format!("cannot read {} ({e})", gains_path.display())))?;
    let shown = gains_path.display().to_string();
    let bad = |why: String| fail(format!("{shown}: {why}"));
    let df = ParquetReader::new(std::io::Cursor::new(&gains_bytes[..])).finish().map_err(|e| bad(e.to_string()))?;
    let rows = read_rows(&df, &filter, variant.as_deref()).map_err(|e| bad(e.to_string()))?;
    let real = assemble(&sizes, &rows).map_err(bad)?;
    for (k, v) in real {
        t.insert(k.into(), v);
    }
    let mut origin = toml::Table::new();
    origin.insert("run".into(), run.clone().into());
    origin.insert("filter".into(), filter.into());
    if let Some(v) = &variant {
        origin.insert("variant".into(), v.clone().into());
    }
    let plant: toml::Value =
        toml::Value::try_from(&plant).map_err(|e| fail(format!("its manifest's plant record: {e}")))?;
    origin.insert("plant".into(), plant);
    t.insert("from_run".into(), toml::Value::Table(origin));
    for (file, bytes, shape) in
        [("manifest.json", &manifest_bytes, vec![]), ("gains.parquet", &gains_bytes, vec![df.height()])]
    {
        out.push(FileInput {
            key: key("from_run"),
            file: format!("{run}/{file}"),
            array: None,
            resolved: folder.join(file),
            sha256: crate::numerics::linalg::hex(&Sha256::digest(bytes)),
            shape,
        });
    }
    Ok(())
}

/// The manifest's record of the run a filter is taken from: the run itself, or its variant.
fn run_entry<'a>(
    manifest: &'a serde_json::Value,
    variant: Option<&str>,
) -> std::result::Result<&'a serde_json::Value, String> {
    let variants = manifest.get("variants").and_then(|v| v.as_array()).map(Vec::as_slice).unwrap_or_default();
    let names: Vec<&str> = variants.iter().filter_map(|v| v.get("variant")?.as_str()).collect();
    match (variant, names.is_empty()) {
        (None, true) => Ok(manifest),
        (Some(v), true) => Err(format!("has no variants, but variant = \"{v}\" is given")),
        (None, false) => Err(format!("has variants ({}): name one with variant = \"…\"", names.join(", "))),
        (Some(v), false) => variants
            .iter()
            .find(|e| e.get("variant").and_then(|n| n.as_str()) == Some(v))
            .ok_or_else(|| format!("has no variant `{v}` (it has: {})", names.join(", "))),
    }
}

/// The sizes gains.parquet leaves out with its zero entries.
struct Sizes {
    ns: usize,
    modes: usize,
    gf_cols: usize,
    ny: usize,
    nz: usize,
    steps: usize,
}

/// One nonzero entry of gains.parquet.
struct Entry {
    step: usize,
    mode: usize,
    matrix: String,
    row: usize,
    col: usize,
    value: f64,
}

/// The entries of one filter (and variant) of gains.parquet (docs/output-columns.md).
fn read_rows(df: &DataFrame, filter: &str, variant: Option<&str>) -> PolarsResult<Vec<Entry>> {
    let (f, v, m) = (df.column("filter")?.str()?, df.column("variant")?.str()?, df.column("matrix")?.str()?);
    let (step, mode) = (df.column("step")?.u32()?, df.column("mode")?.u32()?);
    let (row, col, value) = (df.column("row")?.u32()?, df.column("col")?.u32()?, df.column("value")?.f64()?);
    let mut out = Vec::new();
    for i in 0..df.height() {
        if f.get(i) != Some(filter) || v.get(i) != variant {
            continue;
        }
        let num = |x: Option<u32>, what: &str| {
            x.map(|x| x as usize).ok_or_else(|| polars_err!(ComputeError: "row {i}: `{what}` is null"))
        };
        out.push(Entry {
            step: num(step.get(i), "step")?,
            mode: mode.get(i).unwrap_or(0) as usize,
            matrix: m.get(i).unwrap_or_default().to_string(),
            row: num(row.get(i), "row")?,
            col: num(col.get(i), "col")?,
            value: value.get(i).ok_or_else(|| polars_err!(ComputeError: "row {i}: `value` is null"))?,
        });
    }
    Ok(out)
}

/// The realization's keys as the `linear` family reads them: `s0`, and `Af`, `Bf`, `Cf`, `Df`,
/// `Gf` one matrix per step, for the filter or (mode-indexed) in `modes`.
fn assemble(z: &Sizes, rows: &[Entry]) -> std::result::Result<Vec<(&'static str, toml::Value)>, String> {
    let shapes: [(&'static str, usize, usize); 5] =
        [("Af", z.ns, z.ns), ("Bf", z.ns, z.ny), ("Cf", z.nz, z.ns), ("Df", z.nz, z.ny), ("Gf", z.ns, z.gf_cols)];
    let zero = |(_, r, c): (&str, usize, usize)| vec![vec![0.0; c]; r];
    let mut mats: Vec<Vec<Vec<Vec<Vec<f64>>>>> =
        (0..z.modes).map(|_| shapes.iter().map(|&s| vec![zero(s); z.steps]).collect()).collect();
    let mut s0 = vec![0.0; z.ns];
    for (i, e) in rows.iter().enumerate() {
        let at = || format!("entry {i} ({} step {} mode {} [{}, {}])", e.matrix, e.step, e.mode, e.row, e.col);
        if e.matrix == "s0" {
            *s0.get_mut(e.row).ok_or_else(|| format!("{}: beyond the filter's {} states", at(), z.ns))? = e.value;
            continue;
        }
        let which = shapes.iter().position(|s| s.0 == e.matrix).ok_or_else(|| format!("{}: unknown matrix", at()))?;
        let (_, r, c) = shapes[which];
        if e.step >= z.steps || e.mode >= z.modes || e.row >= r || e.col >= c {
            return Err(format!(
                "{}: outside the sizes the manifest records ({} steps, {} modes, {r}×{c})",
                at(),
                z.steps,
                z.modes
            ));
        }
        mats[e.mode][which][e.step][e.row][e.col] = e.value;
    }
    if rows.is_empty() {
        return Err("holds no entry of this filter".into());
    }
    let to_value = |m: &Vec<Vec<Vec<f64>>>| toml::Value::try_from(m).expect("numbers");
    let per_mode = |mode: &Vec<Vec<Vec<Vec<f64>>>>| -> Vec<(&'static str, toml::Value)> {
        shapes.iter().zip(mode).map(|(s, m)| (s.0, to_value(m))).collect()
    };
    let mut out = vec![("s0", toml::Value::try_from(&s0).expect("numbers"))];
    if z.modes == 1 {
        out.extend(per_mode(&mats[0]));
    } else {
        let tables =
            mats.iter().map(|m| toml::Value::Table(per_mode(m).into_iter().map(|(k, v)| (k.to_string(), v)).collect()));
        out.push(("modes", toml::Value::Array(tables.collect())));
    }
    Ok(out)
}
