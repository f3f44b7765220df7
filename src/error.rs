//! The one error type of filterbench. Every variant renders as a single line that names the cause
//! and the key (or path) it concerns, so the command line can print it and exit non-zero.

use std::path::PathBuf;

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The experiment file could not be read or parsed (syntax, unknown key, missing field, type).
    #[error("{file}: {message}")]
    Parse { file: String, message: String },
    /// A value parsed but is not acceptable (wrong size, not PSD, horizon 0, …).
    #[error("{key}: {cause}")]
    Invalid { key: String, cause: String },
    /// A filter could not be designed (infeasible, unstable, unsupported pattern, …).
    #[error("filter `{filter}`: {cause}")]
    Design { filter: String, cause: String },
    /// No experiment of that name in the experiments folder.
    #[error("no experiment `{name}`: neither {path} nor a file of that path exists (see `filterbench list`)")]
    UnknownExperiment { name: String, path: PathBuf },
    /// Reading or writing a file failed.
    #[error("{path}: {cause}")]
    Io { path: PathBuf, cause: String },
    /// Writing a Parquet table or a recording failed.
    #[error("writing {what}: {cause}")]
    Output { what: String, cause: String },
}

impl Error {
    pub fn invalid(key: impl Into<String>, cause: impl Into<String>) -> Self {
        Error::Invalid { key: key.into(), cause: cause.into() }
    }
    pub fn design(filter: impl Into<String>, cause: impl Into<String>) -> Self {
        Error::Design { filter: filter.into(), cause: cause.into() }
    }
    /// `{key}.filter` names no filter of the experiment.
    pub(crate) fn no_filter(key: &str, name: &str) -> Self {
        Error::invalid(format!("{key}.filter"), format!("no filter named `{name}` in this experiment"))
    }
    pub fn io(path: impl Into<PathBuf>, cause: impl std::fmt::Display) -> Self {
        Error::Io { path: path.into(), cause: cause.to_string() }
    }
    pub fn output(what: impl Into<String>, cause: impl std::fmt::Display) -> Self {
        Error::Output { what: what.into(), cause: cause.to_string() }
    }
}

pub type Result<T> = std::result::Result<T, Error>;
