//! Matrices from files (docs/experiment-files.md, "Matrices from files"): every inline table
//! `{ file = "…" }` or `{ file = "…", key = "…" }` of the experiment file is replaced by the array
//! it names before the file is read into its schema, so every key that accepts a matrix (or a list
//! of matrices, one per step) accepts a file, with the same size and PSD checks.

use std::path::{Path, PathBuf};

use serde::Serialize;
use sha2::{Digest, Sha256};

use super::formats::{self, Array, Format};
use crate::error::{Error, Result};

/// One file an experiment read, as the manifest records it (`files` in manifest.json).
#[derive(Clone, Debug, Serialize, PartialEq, Eq)]
pub struct FileInput {
    /// The experiment key the array went to, e.g. `plant.A`.
    pub key: String,
    /// The path as written in the experiment file.
    pub file: String,
    /// The array's name inside an .npz or .mat.
    pub array: Option<String>,
    /// The path read: relative paths are taken from the experiment file's folder.
    pub resolved: PathBuf,
    /// The SHA-256 of the file's bytes, in hex.
    pub sha256: String,
    /// The shape read (the first axis first).
    pub shape: Vec<usize>,
}

/// Whether `v` is (or holds) a file reference: a table with a `file` key.
pub(super) fn has_refs(v: &toml::Value) -> bool {
    match v {
        toml::Value::Table(t) => t.contains_key("file") || t.values().any(has_refs),
        toml::Value::Array(a) => a.iter().any(has_refs),
        _ => false,
    }
}

/// Replaces every file reference inside `table` by the array it names, recording each file read
/// in `out`. `prefix` is the key path of `table` ("" at the top); `base` the experiment's folder.
pub(super) fn resolve_refs(table: &mut toml::Table, prefix: &str, base: &Path, out: &mut Vec<FileInput>) -> Result<()> {
    for (k, v) in table.iter_mut() {
        let key = if prefix.is_empty() { k.clone() } else { format!("{prefix}.{k}") };
        resolve_value(v, &key, base, out)?;
    }
    Ok(())
}

fn resolve_value(v: &mut toml::Value, key: &str, base: &Path, out: &mut Vec<FileInput>) -> Result<()> {
    match v {
        toml::Value::Table(t) if t.contains_key("file") => {
            let (value, input) = read_ref(t, key, base)?;
            *v = value;
            out.push(input);
            Ok(())
        }
        toml::Value::Table(t) => resolve_refs(t, key, base, out),
        toml::Value::Array(a) => {
            for (i, x) in a.iter_mut().enumerate() {
                resolve_value(x, &format!("{key}[{i}]"), base, out)?;
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

/// Reads the array a reference table names and checks it: rank 1 to 3, every value finite.
fn read_ref(t: &toml::Table, key: &str, base: &Path) -> Result<(toml::Value, FileInput)> {
    let Some(toml::Value::String(file)) = t.get("file") else {
        return Err(Error::invalid(format!("{key}.file"), "must be a string: the path of an array file"));
    };
    let fail = |cause: String| Error::invalid(key, format!("file `{file}`: {cause}"));
    if let Some(extra) = t.keys().find(|k| *k != "file" && *k != "key") {
        return Err(fail(format!("unexpected key `{extra}` in a file reference: only `file` and `key` are allowed")));
    }
    let array = match t.get("key") {
        None => None,
        Some(toml::Value::String(s)) => Some(s.clone()),
        Some(_) => return Err(fail("`key` must be a string: the array's name in the file".into())),
    };
    let format = Format::of(file).ok_or_else(|| fail("unknown extension: expected .npy, .npz, .mat or .csv".into()))?;
    match (format.keyed(), &array) {
        (true, None) => return Err(fail("an .npz or .mat holds several arrays: name one with `key = \"…\"`".into())),
        (false, Some(_)) => return Err(fail("`key` applies to .npz and .mat files only".into())),
        _ => {}
    }
    let resolved = base.join(file);
    let bytes = std::fs::read(&resolved).map_err(|e| fail(format!("cannot read {} ({e})", resolved.display())))?;
    let Array { shape, data } = formats::read(format, &bytes, array.as_deref()).map_err(fail)?;
    let what = array.as_ref().map(|a| format!("array `{a}`")).unwrap_or_else(|| "the array".into());
    if shape.is_empty() || shape.len() > 3 {
        return Err(fail(format!(
            "{what} has rank {} (shape {shape:?}): a vector, a matrix or a matrix per step (rank 1 to 3) is expected",
            shape.len()
        )));
    }
    if let Some(i) = data.iter().position(|x| !x.is_finite()) {
        return Err(fail(format!(
            "{what} holds {} at flat index {i} (row-major): every value must be finite",
            data[i]
        )));
    }
    let sha256 = crate::numerics::linalg::hex(&Sha256::digest(&bytes));
    let value = to_value(&shape, &data);
    let input = FileInput { key: key.to_string(), file: file.clone(), array, resolved, sha256, shape };
    Ok((value, input))
}

/// The array as TOML: a list of numbers for rank 1, a list of rows for rank 2, a list of matrices
/// (the first axis the step) for rank 3.
fn to_value(shape: &[usize], data: &[f64]) -> toml::Value {
    let Some((&first, rest)) = shape.split_first() else { return toml::Value::Float(data[0]) };
    if rest.is_empty() {
        return toml::Value::Array(data.iter().map(|&x| toml::Value::Float(x)).collect());
    }
    let stride: usize = rest.iter().product();
    toml::Value::Array((0..first).map(|i| to_value(rest, &data[i * stride..(i + 1) * stride])).collect())
}

/// Adds the file an error's key came from to its message, so that a check made after reading
/// (a size, a PSD test, a per-step count) names the file too.
pub(super) fn name_file(e: Error, inputs: &[FileInput]) -> Error {
    let from = |key: &str| {
        inputs.iter().find(|i| {
            key.strip_prefix(i.key.as_str())
                .is_some_and(|rest| rest.is_empty() || rest.starts_with(['[', '.', ' ', '`']))
        })
    };
    let tell = |i: &FileInput| match &i.array {
        Some(a) => format!(" (read from `{}`, array `{a}`)", i.file),
        None => format!(" (read from `{}`)", i.file),
    };
    // A key the message compares with (`plant.A` in "the rows of plant.A"), as a whole key.
    let mentioned = |text: &str| {
        inputs.iter().find(|i| {
            text.match_indices(i.key.as_str())
                .any(|(at, k)| !text[at + k.len()..].starts_with(|c: char| c.is_alphanumeric() || c == '_'))
        })
    };
    match e {
        Error::Invalid { key, cause } => match (from(&key), mentioned(&cause)) {
            (Some(i), _) => Error::Invalid { cause: format!("{cause}{}", tell(i)), key },
            (None, Some(i)) => {
                Error::Invalid { cause: format!("{cause} ({} {}", i.key, tell(i).trim_start_matches(" (")), key }
            }
            (None, None) => Error::Invalid { key, cause },
        },
        Error::Parse { file, message } => {
            let key = message.strip_prefix("key `").and_then(|m| m.split('`').next()).unwrap_or_default();
            match from(key) {
                Some(i) if !key.is_empty() => Error::Parse { message: format!("{message}{}", tell(i)), file },
                _ => Error::Parse { file, message },
            }
        }
        e => e,
    }
}
