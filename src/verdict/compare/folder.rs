//! A result folder read back for `compare`: that it is one (a manifest with `filterbench_version`
//! and a summary table), what its manifest says the experiment is, and its tables as columns.

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};

use polars::prelude::*;

use crate::error::{Error, Result};

/// What the manifest of a result folder says about the run.
#[derive(Clone, Debug)]
pub(crate) struct Manifest {
    pub experiment: String,
    pub seed: Option<u64>,
    pub trials: Option<u64>,
    /// The variants' names (empty without variants).
    pub variants: Vec<String>,
    /// Per run (one per variant, or the one run): its scenarios' and filters' names.
    pub runs: Vec<(Vec<String>, Vec<String>)>,
}

/// A result folder: its path and manifest.
#[derive(Clone, Debug)]
pub(crate) struct Folder {
    pub path: PathBuf,
    pub manifest: Manifest,
}

fn not_result(path: &Path, why: impl std::fmt::Display) -> Error {
    Error::invalid(path.display().to_string(), format!("not a result folder: {why}"))
}

fn names(v: Option<&serde_json::Value>) -> Vec<String> {
    v.and_then(|v| v.as_array())
        .map(|a| a.iter().filter_map(|x| x.get("name")?.as_str().map(str::to_string)).collect())
        .unwrap_or_default()
}

impl Folder {
    /// Reads the folder's manifest; refused (one line naming the folder or file) when it is not a
    /// result folder: missing, a file, a shard's partial result, no manifest or no summary table.
    pub fn open(path: &Path) -> Result<Folder> {
        if !path.is_dir() {
            let why = if path.exists() { "it is a file" } else { "no such folder" };
            return Err(not_result(path, why));
        }
        let mpath = path.join("manifest.json");
        if !mpath.is_file() {
            if path.join(crate::pipeline::shards::partial::META).is_file() {
                return Err(not_result(path, "it is one shard's partial result; `filterbench merge` the shards first"));
            }
            return Err(not_result(path, "no manifest.json"));
        }
        let text = std::fs::read_to_string(&mpath).map_err(|e| Error::io(&mpath, e))?;
        let doc: serde_json::Value = serde_json::from_str(&text)
            .map_err(|e| Error::invalid(mpath.display().to_string(), format!("not a filterbench manifest: {e}")))?;
        if doc.get("filterbench_version").and_then(|v| v.as_str()).is_none() {
            return Err(Error::invalid(
                mpath.display().to_string(),
                "not a filterbench manifest: no `filterbench_version`",
            ));
        }
        if !path.join("summary.parquet").is_file() {
            return Err(not_result(path, "no summary.parquet"));
        }
        let experiment = doc.get("experiment").and_then(|v| v.as_str()).unwrap_or_default().to_string();
        let variants_json = doc.get("variants").and_then(|v| v.as_array()).cloned().unwrap_or_default();
        let variants: Vec<String> =
            variants_json.iter().filter_map(|v| v.get("variant")?.as_str().map(str::to_string)).collect();
        let runs = if variants_json.is_empty() {
            vec![(names(doc.get("scenarios")), names(doc.get("filters")))]
        } else {
            variants_json.iter().map(|v| (names(v.get("scenarios")), names(v.get("filters")))).collect()
        };
        let manifest = Manifest {
            experiment,
            seed: doc.get("seed").and_then(|v| v.as_u64()),
            trials: doc.get("trials").and_then(|v| v.as_u64()),
            variants,
            runs,
        };
        Ok(Folder { path: path.to_path_buf(), manifest })
    }
}

/// `what differs: only in OLD: …; only in NEW: …` for two lists of names, None when the same set.
fn differ(what: &str, old: &[String], new: &[String]) -> Option<String> {
    let (a, b): (BTreeSet<_>, BTreeSet<_>) = (old.iter().collect(), new.iter().collect());
    if a == b {
        return None;
    }
    let list = |s: Vec<&&String>| s.iter().map(|x| format!("`{x}`")).collect::<Vec<_>>().join(", ");
    let mut parts = vec![];
    let only_old: Vec<_> = a.difference(&b).collect();
    let only_new: Vec<_> = b.difference(&a).collect();
    if !only_old.is_empty() {
        parts.push(format!("only in OLD: {}", list(only_old)));
    }
    if !only_new.is_empty() {
        parts.push(format!("only in NEW: {}", list(only_new)));
    }
    Some(format!("{what} differ ({})", parts.join("; ")))
}

/// Refuses two folders of different experiments: another `experiment` name, other variants, or
/// (per variant) other scenarios or filters, by name. Everything else is what `compare` reports.
pub(crate) fn same_experiment(old: &Folder, new: &Folder) -> Result<()> {
    let (a, b) = (&old.manifest, &new.manifest);
    let mut why = vec![];
    if a.experiment != b.experiment {
        why.push(format!("experiment `{}` against `{}`", a.experiment, b.experiment));
    }
    why.extend(differ("variants", &a.variants, &b.variants));
    if why.is_empty() {
        for (i, ((sa, fa), (sb, fb))) in a.runs.iter().zip(&b.runs).enumerate() {
            let at = a.variants.get(i).map(|v| format!(" of variant `{v}`")).unwrap_or_default();
            why.extend(differ(&format!("scenarios{at}"), sa, sb));
            why.extend(differ(&format!("filters{at}"), fa, fb));
        }
    }
    if why.is_empty() {
        return Ok(());
    }
    Err(Error::invalid(
        format!("{} and {}", old.path.join("manifest.json").display(), new.path.join("manifest.json").display()),
        format!("not the same experiment: {}", why.join("; ")),
    ))
}

/// A column read back: numbers as f64 (integers up to 2⁵³ exactly), everything else as text.
pub(crate) enum Col {
    Num(Float64Chunked),
    Text(StringChunked),
}

impl Col {
    pub fn value(&self, i: usize) -> super::cell::Value {
        use super::cell::Value;
        match self {
            Col::Num(c) => c.get(i).map_or(Value::Null, Value::Num),
            Col::Text(c) => c.get(i).map_or(Value::Null, |s| Value::Text(s.to_string())),
        }
    }
    pub fn num(&self, i: usize) -> Option<f64> {
        match self {
            Col::Num(c) => c.get(i),
            Col::Text(_) => None,
        }
    }
    pub fn text(&self, i: usize) -> Option<String> {
        match self {
            Col::Num(c) => c.get(i).map(|x| x.to_string()),
            Col::Text(c) => c.get(i).map(str::to_string),
        }
    }
}

/// One table of a result folder, every column in one chunk (constant-time access by row).
pub(crate) struct Frame {
    pub height: usize,
    pub columns: Vec<(String, Col)>,
}

impl Frame {
    /// Reads `dir/file`; None when the file is not there.
    pub fn read(dir: &Path, file: &str) -> Result<Option<Frame>> {
        let path = dir.join(file);
        if !path.exists() {
            return Ok(None);
        }
        let shown = path.display().to_string();
        let bad = |e: &dyn std::fmt::Display| Error::invalid(&shown, format!("not a readable table: {e}"));
        let f = std::fs::File::open(&path).map_err(|e| Error::io(&path, e))?;
        let df = ParquetReader::new(f).finish().map_err(|e| bad(&e))?;
        let mut columns = vec![];
        for c in df.columns() {
            let s = c.as_materialized_series();
            let col = if s.dtype().is_primitive_numeric() {
                Col::Num(
                    s.cast(&DataType::Float64).map_err(|e| bad(&e))?.f64().map_err(|e| bad(&e))?.rechunk().into_owned(),
                )
            } else {
                Col::Text(
                    s.cast(&DataType::String).map_err(|e| bad(&e))?.str().map_err(|e| bad(&e))?.rechunk().into_owned(),
                )
            };
            columns.push((c.name().to_string(), col));
        }
        Ok(Some(Frame { height: df.height(), columns }))
    }

    pub fn column(&self, name: &str) -> Option<&Col> {
        self.columns.iter().find(|(n, _)| n == name).map(|(_, c)| c)
    }
}
