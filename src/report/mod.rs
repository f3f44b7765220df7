//! The output contract of ARCHITECTURE.md: `summary.parquet`, `steps.parquet`, `gains.parquet`,
//! `paired.parquet`, `design_trace.parquet`, `manifest.json` and `recording.rrd` in one folder, plus
//! the console table.
//!
//! Everything is written into a temporary sibling folder that is renamed onto the target only when
//! every file is complete, so a failed run leaves the previous results untouched.

pub mod console;
pub mod manifest;
pub mod parquet;
pub mod recording;

use std::path::{Path, PathBuf};

use crate::error::{Error, Result};
use crate::run::RunOutcome;
use crate::spec::Experiment;

/// A temporary output folder beside the target; removed on drop unless [`Staging::commit`] ran.
pub struct Staging {
    tmp: PathBuf,
    target: PathBuf,
    committed: bool,
}

impl Staging {
    /// Creates the temporary folder now, so an unwritable destination fails before any work.
    pub fn new(target: &Path) -> Result<Self> {
        let name = target.file_name().and_then(|s| s.to_str()).unwrap_or("results").to_string();
        let parent = match target.parent() {
            Some(p) if !p.as_os_str().is_empty() => p.to_path_buf(),
            _ => PathBuf::from("."),
        };
        std::fs::create_dir_all(&parent)
            .map_err(|e| Error::io(&parent, format!("cannot create the output folder: {e}")))?;
        let tmp = parent.join(format!(".{name}.tmp-{}", std::process::id()));
        if tmp.exists() {
            std::fs::remove_dir_all(&tmp).map_err(|e| Error::io(&tmp, e))?;
        }
        std::fs::create_dir(&tmp).map_err(|e| Error::io(&parent, format!("output folder is not writable: {e}")))?;
        Ok(Staging { tmp, target: target.to_path_buf(), committed: false })
    }
    pub fn path(&self) -> &Path {
        &self.tmp
    }
    /// Replaces the target folder by the completed temporary one.
    pub fn commit(mut self) -> Result<PathBuf> {
        let old = self.tmp.with_file_name(format!(
            ".{}.old-{}",
            self.target.file_name().and_then(|s| s.to_str()).unwrap_or("results"),
            std::process::id()
        ));
        let had_old = self.target.exists();
        if had_old {
            std::fs::rename(&self.target, &old).map_err(|e| Error::io(&self.target, e))?;
        }
        if let Err(e) = std::fs::rename(&self.tmp, &self.target) {
            if had_old {
                let _ = std::fs::rename(&old, &self.target);
            }
            return Err(Error::io(&self.target, e));
        }
        self.committed = true;
        if had_old {
            let _ = std::fs::remove_dir_all(&old);
        }
        Ok(self.target.clone())
    }
}

impl Drop for Staging {
    fn drop(&mut self) {
        if !self.committed {
            let _ = std::fs::remove_dir_all(&self.tmp);
        }
    }
}

/// Writes every file of the output contract into `dir`, for the runs of one experiment (one per
/// variant; a file without variants is one run).
pub fn write_all(runs: &[(&Experiment, &RunOutcome)], dir: &Path, overrides: &manifest::Overrides) -> Result<()> {
    parquet::write_tables(runs, dir)?;
    recording::write(runs, &dir.join("recording.rrd"))?;
    manifest::write(runs, overrides, &dir.join("manifest.json"))?;
    Ok(())
}
