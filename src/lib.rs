//! filterbench: Monte Carlo benchmarking of robust state estimators. Every filter family compiles
//! to one linear [`filter::realization::Realization`]; the exact analysis ([`analysis::exact`]) and
//! the Monte Carlo engine ([`sim::montecarlo`]) are generic over it. See the README for the picture.

pub mod analysis;
pub mod config;
pub mod error;
pub mod families;
pub mod filter;
pub mod model;
pub mod numerics;
pub mod pipeline;
pub mod report;
pub mod sim;
pub mod verdict;

pub use error::{Error, Result};

// clarabel's SDP support calls BLAS/LAPACK: link the system OpenBLAS (`system` feature; .ci/run
// installs Debian's libopenblas-dev and gfortran) rather than building one from source.
extern crate openblas_src as _;

use std::path::{Path, PathBuf};

/// The folder of the shipped experiment files: `./experiments` if it exists, else the one in the
/// source tree this binary was built from.
pub fn experiments_dir() -> PathBuf {
    let local = PathBuf::from("experiments");
    if local.is_dir() { local } else { Path::new(env!("CARGO_MANIFEST_DIR")).join("experiments") }
}

/// Resolves `experiment NAME` (experiments/NAME.toml) or `experiment path/to/file.toml`.
pub fn experiment_path(name_or_path: &str) -> Result<PathBuf> {
    let p = PathBuf::from(name_or_path);
    if p.is_file() {
        return Ok(p);
    }
    let named = experiments_dir().join(format!("{name_or_path}.toml"));
    if named.is_file() {
        return Ok(named);
    }
    Err(Error::UnknownExperiment { name: name_or_path.to_string(), path: named })
}

/// Every shipped experiment with its one-line description, sorted by name.
pub fn list_experiments() -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = std::fs::read_dir(experiments_dir())
        .into_iter()
        .flatten()
        .flatten()
        .filter_map(|e| {
            let p = e.path();
            (p.extension()? == "toml").then(|| {
                let name = p.file_stem()?.to_str()?.to_string();
                Some((name, config::describe(&p).unwrap_or_else(|| "(unreadable experiment file)".into())))
            })?
        })
        .collect();
    out.sort();
    out
}
