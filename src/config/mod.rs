//! Layer 7, the experiment file: its schema (`schema`), its validation into a resolved
//! [`Experiment`] (`resolve`; every error names the offending key), its variants and sweeps.
//! Every key is documented in docs/experiment-files.md.

mod disturbance;
mod expect;
mod experiment;
mod files;
mod formats;
mod from_run;
mod modes;
mod plant;
mod resolve;
mod schema;

use std::path::Path;

use serde::Deserialize;

use crate::error::{Error, Result};
pub use crate::model::choice::CovChoice;
pub use crate::model::plant::Pattern;
pub use expect::{check_min_detectable, check_probability};
pub use experiment::{
    CheckSettings, Expectation, Experiment, FilterSpec, Input, InputChoice, MAX_TRIALS, Overrides, Scenario,
    check_max_trials, check_name, check_trials, sample_count,
};
pub use files::FileInput;
use resolve::{deserialize, resolve_file};
use schema::ExperimentFile;

/// Reads and validates an experiment file. `name` is the experiment's name (the file stem).
pub fn load(path: &Path) -> Result<Experiment> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("experiment").to_string();
    parse_with(&name, &path.display().to_string(), &text, &Overrides::default(), folder(path))
}

/// The folder an experiment file's relative file references are taken from.
fn folder(path: &Path) -> Option<&Path> {
    path.parent().filter(|p| !p.as_os_str().is_empty())
}

/// Reads an experiment file and returns one experiment per `[[variants]]` entry: the file with the
/// entry's keys merged in (tables key by key, anything else replaced), named by its `name`. A file
/// without variants gives itself. The base file must be valid on its own. The command line's
/// `overrides` apply to every variant.
pub fn load_variants(path: &Path, overrides: &Overrides) -> Result<Vec<Experiment>> {
    let text = std::fs::read_to_string(path).map_err(|e| Error::io(path, e))?;
    let name = path.file_stem().and_then(|s| s.to_str()).unwrap_or("experiment").to_string();
    variants_of(&name, &path.display().to_string(), &text, overrides, folder(path))
}

/// [`load_variants`] of experiment text: `name` is the experiment's name, `file` only for messages,
/// `folder` where relative file references are read from (None: the current directory).
pub(crate) fn variants_of(
    name: &str,
    file: &str,
    text: &str,
    overrides: &Overrides,
    folder: Option<&Path>,
) -> Result<Vec<Experiment>> {
    let base = parse_with(name, file, text, overrides, folder)?;
    let file = file.to_string();
    let mut doc: toml::Table =
        toml::from_str(&base.source).map_err(|e| Error::Parse { file: file.clone(), message: e.to_string() })?;
    let Some(variants) = doc.remove("variants") else { return Ok(vec![base]) };
    let variants = variants.as_array().cloned().unwrap_or_default();
    let mut out = Vec::with_capacity(variants.len());
    let mut seen = std::collections::BTreeSet::new();
    for (i, v) in variants.into_iter().enumerate() {
        let key = format!("variants[{i}]");
        let mut patch = match v {
            toml::Value::Table(t) => t,
            _ => return Err(Error::invalid(key, "each variant is a table")),
        };
        let name = match patch.remove("name") {
            Some(toml::Value::String(n)) => n,
            _ => return Err(Error::invalid(format!("{key}.name"), "each variant needs a `name` (a string)")),
        };
        check_name(&format!("{key}.name"), &name)?;
        if !seen.insert(name.clone()) {
            return Err(Error::invalid(format!("{key}.name"), format!("variant name `{name}` is repeated")));
        }
        let mut merged = doc.clone();
        merge(&mut merged, patch);
        let raw: ExperimentFile =
            serde_path_to_error::deserialize(toml::Value::Table(merged)).map_err(|e| Error::Parse {
                file: file.clone(),
                message: format!("variant `{name}`: key `{}`: {}", e.path(), e.inner().message().trim()),
            })?;
        let mut exp = resolve_file(&base.name, raw, &base.source, overrides).map_err(|e| {
            let e = files::name_file(e, &base.inputs);
            Error::Parse { file: file.clone(), message: format!("variant `{name}`: {e}") }
        })?;
        exp.variant = Some(name);
        exp.inputs = base.inputs.clone();
        out.push(exp);
    }
    if out.is_empty() {
        return Err(Error::invalid("variants", "the list of variants is empty"));
    }
    Ok(out)
}

/// Merges `patch` into `doc`: tables key by key, any other value replaced.
fn merge(doc: &mut toml::Table, patch: toml::Table) {
    for (k, v) in patch {
        match (doc.get_mut(&k), v) {
            (Some(toml::Value::Table(d)), toml::Value::Table(p)) => merge(d, p),
            (_, v) => {
                doc.insert(k, v);
            }
        }
    }
}

/// Parses experiment text; `file` is only used in messages. Relative file references are read
/// from the current directory ([`load`] reads them from the experiment file's folder).
pub fn parse(name: &str, file: &str, text: &str) -> Result<Experiment> {
    parse_with(name, file, text, &Overrides::default(), None)
}

/// [`parse`] with the command line's `overrides`, reading relative file references from `folder`.
/// A file with references is read with each replaced by its array: the experiment's `source`
/// (the manifest's `experiment_file`, what shards are merged from) is then that text, which
/// builds the same experiment without the files, and `inputs` lists the files read.
pub(crate) fn parse_with(
    name: &str,
    file: &str,
    text: &str,
    overrides: &Overrides,
    folder: Option<&Path>,
) -> Result<Experiment> {
    check_name("experiment name", name)?;
    let doc = toml::from_str::<toml::Table>(text)
        .ok()
        .filter(|d| d.values().any(|v| files::has_refs(v) || from_run::has_runs(v)));
    let Some(mut doc) = doc else {
        let raw: ExperimentFile = deserialize(file, text)?;
        return resolve_file(name, raw, text, overrides);
    };
    let mut inputs = Vec::new();
    let base = folder.unwrap_or(Path::new("."));
    files::resolve_refs(&mut doc, "", base, &mut inputs)?;
    doc.iter_mut().try_for_each(|(_, v)| from_run::resolve_runs(v, base, &mut inputs))?;
    let resolved =
        toml::to_string(&doc).map_err(|e| Error::Parse { file: file.to_string(), message: e.to_string() })?;
    let named = |e| files::name_file(e, &inputs);
    // Read from the table, not the text: a line number would be one of the text with arrays inline.
    let raw: ExperimentFile = serde_path_to_error::deserialize(toml::Value::Table(doc))
        .map_err(|e| Error::Parse {
            file: file.to_string(),
            message: format!("key `{}`: {}", e.path(), e.inner().message().trim()),
        })
        .map_err(named)?;
    let mut exp = resolve_file(name, raw, &resolved, overrides).map_err(named)?;
    exp.inputs = inputs;
    Ok(exp)
}

/// The one-line description of an experiment file, for `filterbench list` (None if unreadable).
pub fn describe(path: &Path) -> Option<String> {
    #[derive(Deserialize)]
    struct Head {
        description: String,
    }
    let text = std::fs::read_to_string(path).ok()?;
    toml::from_str::<Head>(&text).ok().map(|h| h.description)
}
