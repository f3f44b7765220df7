//! The output place of a run (`--out DIR`, default `results/NAME`): which folders may be replaced,
//! the lock that keeps two runs apart, and the temporary folder that becomes DIR only when every
//! file is complete.
//!
//! Nothing of the user's is ever removed. DIR is replaced only when it is empty or holds an earlier
//! filterbench result and nothing else; everything else (a file, `/`, `.`, `..`, an ancestor of the
//! working directory, a folder with other files) is refused before any work. The only other things
//! removed are filterbench's own temporary folders, which carry a marker file.

use std::fs::{self, File, OpenOptions};
use std::io::{Read, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::Mutex;

use crate::error::{Error, Result};
use crate::pipeline::shards::partial;

/// The file name of the manifest; its `filterbench_version` field marks a folder as a result.
pub(crate) const MANIFEST: &str = "manifest.json";
/// The marker file of a temporary folder, written first, so a stale one is recognised as ours.
const STAGING_MARKER: &str = ".filterbench-staging";
/// The longest output name in bytes: `.NAME.tmp-PID` (PID up to 10 digits) must fit the 255-byte
/// limit on a file name of every common file system.
pub(crate) const MAX_NAME_BYTES: usize = 255 - ".".len() - ".tmp-".len() - 10;

/// The cell table `filterbench check` writes beside a result's tables (docs/checks.md).
pub const CHECK_FILE: &str = "check.parquet";

/// The files a result folder holds: the tables, the manifest, the recording and check's cell
/// table; or a shard's partial result ([`partial`]).
pub(crate) fn result_files() -> Vec<&'static str> {
    let mut v: Vec<&str> = super::parquet::TABLES.iter().map(|(f, _)| *f).collect();
    v.extend([MANIFEST, "recording.rrd", CHECK_FILE, partial::META, partial::NODES]);
    v
}

/// What the run in progress has created beside the target, for the signal handler to remove.
#[derive(Default)]
struct Active {
    /// The temporary folder (None once committed).
    tmp: Option<PathBuf>,
    /// The lock file.
    lock: Option<PathBuf>,
}

static ACTIVE: Mutex<Active> = Mutex::new(Active { tmp: None, lock: None });

fn active() -> std::sync::MutexGuard<'static, Active> {
    ACTIVE.lock().unwrap_or_else(|e| e.into_inner())
}

/// Removes the temporary folder of the run in progress on SIGINT, SIGTERM or SIGHUP, then exits
/// with 128 + the signal number. A commit in progress finishes first (it holds the same lock), so
/// the target is either the old result or the new one, never missing.
pub fn install_signal_cleanup() -> Result<()> {
    use signal_hook::consts::{SIGHUP, SIGINT, SIGTERM};
    let mut signals =
        signal_hook::iterator::Signals::new([SIGINT, SIGTERM, SIGHUP]).map_err(|e| Error::io("signal handler", e))?;
    std::thread::spawn(move || {
        if let Some(sig) = signals.forever().next() {
            let mut guard = active();
            if let Some(tmp) = guard.tmp.take() {
                let _ = fs::remove_dir_all(&tmp);
                eprintln!("\ninterrupted: removed the unfinished output {}", tmp.display());
            } else {
                eprintln!("\ninterrupted");
            }
            // Still holding the lock: removing its file now cannot let two runs in (see `lock`).
            if let Some(lock) = guard.lock.take() {
                let _ = fs::remove_file(lock);
            }
            std::process::exit(128 + sig);
        }
    });
    Ok(())
}

/// A path with its last component resolved through the deepest existing ancestor, without requiring
/// the path itself to exist (so symlinks and `..` in the parent are followed as the kernel would).
fn absolute(p: &Path) -> Result<PathBuf> {
    let abs = std::path::absolute(p).map_err(|e| Error::io(p, e))?;
    let mut existing = abs.as_path();
    let mut rest = Vec::new();
    while fs::symlink_metadata(existing).is_err() {
        match (existing.parent(), existing.file_name()) {
            (Some(parent), Some(name)) => {
                rest.push(name.to_os_string());
                existing = parent;
            }
            _ => break,
        }
    }
    let mut out = fs::canonicalize(existing).unwrap_or_else(|_| existing.to_path_buf());
    for name in rest.into_iter().rev() {
        out.push(name);
    }
    Ok(out)
}

/// Why `dir` is not an earlier filterbench result, or None if it is one (or is empty): it may hold
/// only the files of [`result_files`], and its manifest or partial.json, if any, must be filterbench's.
fn foreign_content(dir: &Path) -> Result<Option<String>> {
    let allowed = result_files();
    let mut others = Vec::new();
    let mut manifests = Vec::new();
    for entry in fs::read_dir(dir).map_err(|e| Error::io(dir, e))? {
        let entry = entry.map_err(|e| Error::io(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_file = entry.file_type().map(|t| t.is_file()).unwrap_or(false);
        // The marker can only be left by a commit interrupted between its rename and its removal.
        if is_file && (allowed.contains(&name.as_str()) || name == STAGING_MARKER) {
            if name == MANIFEST || name == partial::META {
                manifests.push(name);
            }
        } else {
            others.push(name);
        }
    }
    if !others.is_empty() {
        others.sort();
        let shown: Vec<String> = others.iter().take(3).map(|n| format!("`{}`", n.escape_debug())).collect();
        let more = if others.len() > 3 { format!(" and {} more", others.len() - 3) } else { String::new() };
        return Ok(Some(format!("it holds {}{more}, which filterbench did not write", shown.join(", "))));
    }
    if let Some(m) = manifests.iter().find(|m| !is_result_manifest(&dir.join(m))) {
        return Ok(Some(format!("its {m} was not written by filterbench")));
    }
    Ok(None)
}

/// A manifest filterbench wrote: a JSON object with a `filterbench_version` string.
fn is_result_manifest(path: &Path) -> bool {
    let mut text = String::new();
    let Ok(f) = File::open(path) else { return false };
    if f.take(64 << 20).read_to_string(&mut text).is_err() {
        return false;
    }
    serde_json::from_str::<serde_json::Value>(&text)
        .ok()
        .and_then(|v| v.get("filterbench_version").map(serde_json::Value::is_string))
        .unwrap_or(false)
}

/// Checks that `target` may receive a result, before anything is created or any work is done.
/// Returns the target's parent folder (possibly not existing yet) and its name.
pub(crate) fn check_target(target: &Path) -> Result<(PathBuf, String)> {
    let key = |p: &Path| format!("--out {}", p.display().to_string().escape_debug());
    let shown = key(target);
    crate::config::check_name("--out", &target.to_string_lossy())?;
    if target.as_os_str().is_empty() {
        return Err(Error::invalid("--out", "the output folder is empty"));
    }
    let last = target.components().next_back();
    if matches!(last, Some(Component::RootDir | Component::Prefix(_) | Component::CurDir | Component::ParentDir))
        || target.file_name().is_none()
    {
        return Err(Error::invalid(
            shown,
            "is `/`, `.` or `..`: give the folder the results should go to, e.g. results/NAME",
        ));
    }
    let name = target
        .file_name()
        .and_then(|s| s.to_str())
        .ok_or_else(|| Error::invalid(&shown, "the folder name is not valid UTF-8"))?
        .to_string();
    if name.len() > MAX_NAME_BYTES {
        return Err(Error::invalid(
            shown,
            format!("the folder name has {} bytes; at most {MAX_NAME_BYTES} are allowed", name.len()),
        ));
    }
    let abs = absolute(target)?;
    if abs.as_os_str().len() > 4000 {
        return Err(Error::invalid(shown, "the path is longer than 4000 bytes"));
    }
    let cwd = std::env::current_dir().ok().and_then(|c| fs::canonicalize(c).ok());
    if let Some(cwd) = &cwd {
        if cwd.starts_with(&abs) {
            return Err(Error::invalid(
                shown,
                "is the working directory or one of its ancestors; it cannot be replaced by results",
            ));
        }
    }
    if let Ok(meta) = fs::symlink_metadata(target) {
        if meta.file_type().is_symlink() {
            return Err(Error::invalid(shown, "is a symbolic link; give the folder it points to"));
        }
        if !meta.is_dir() {
            return Err(Error::invalid(shown, "is a file, not a folder: it is never replaced"));
        }
        if let Some(why) = foreign_content(target)? {
            return Err(Error::invalid(
                shown,
                format!("is not an earlier filterbench result: {why}; choose another folder (nothing was changed)"),
            ));
        }
    }
    let parent = match abs.parent() {
        Some(p) => p.to_path_buf(),
        None => return Err(Error::invalid(shown, "has no parent folder")),
    };
    Ok((parent, name))
}

/// The claimed output place: the lock on it and the temporary folder being written.
pub struct OutputPlace {
    target: PathBuf,
    parent: PathBuf,
    name: String,
    tmp: PathBuf,
    lock_path: PathBuf,
    /// Held (flock) until dropped; the kernel releases it even on SIGKILL.
    _lock: File,
    committed: bool,
}

impl OutputPlace {
    /// Checks the target (`check_target`), takes the lock `.NAME.lock` beside it (a second run into
    /// the same place is refused at once, naming the holder), clears what dead runs left there and
    /// creates the temporary folder, all before any work.
    pub fn claim(target: &Path, what: &str) -> Result<Self> {
        let (parent, name) = check_target(target)?;
        fs::create_dir_all(&parent).map_err(|e| Error::io(&parent, format!("cannot create the output folder: {e}")))?;
        let lock_path = parent.join(format!(".{name}.lock"));
        let lock = lock(&lock_path, target, what)?;
        active().lock = Some(lock_path.clone());
        let mut place = OutputPlace {
            // The checked form of the path (a trailing `/.` or a symlinked parent resolved).
            target: parent.join(&name),
            parent,
            name,
            tmp: PathBuf::new(),
            lock_path,
            _lock: lock,
            committed: false,
        };
        place.clear_stale()?;
        let tmp = place.parent.join(format!(".{}.tmp-{}", place.name, std::process::id()));
        fs::create_dir(&tmp).map_err(|e| Error::io(&place.parent, format!("output folder is not writable: {e}")))?;
        active().tmp = Some(tmp.clone());
        place.tmp = tmp;
        File::create(place.tmp.join(STAGING_MARKER)).map_err(|e| Error::io(&place.tmp, e))?;
        Ok(place)
    }

    /// What runs that died (SIGKILL, power loss) left beside the target, now that the lock shows no
    /// run is writing here: temporary folders (recognised by their marker, or empty) are removed; a
    /// previous result moved aside by an interrupted commit is put back if the target is missing.
    fn clear_stale(&self) -> Result<()> {
        let tmp_prefix = format!(".{}.tmp-", self.name);
        let old_prefix = format!(".{}.old-", self.name);
        let pid_suffix = |n: &str, prefix: &str| {
            n.strip_prefix(prefix).is_some_and(|p| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit()))
        };
        let Ok(entries) = fs::read_dir(&self.parent) else { return Ok(()) };
        for entry in entries.flatten() {
            let n = entry.file_name().to_string_lossy().into_owned();
            let p = entry.path();
            if !entry.file_type().map(|t| t.is_dir()).unwrap_or(false) {
                continue;
            }
            if pid_suffix(&n, &tmp_prefix) {
                let ours = p.join(STAGING_MARKER).is_file()
                    || fs::read_dir(&p).map(|mut d| d.next().is_none()).unwrap_or(false);
                if ours {
                    fs::remove_dir_all(&p)
                        .map_err(|e| Error::io(&p, format!("cannot remove a stale temporary folder: {e}")))?;
                }
            } else if pid_suffix(&n, &old_prefix) && foreign_content(&p)?.is_none() {
                if fs::symlink_metadata(&self.target).is_err() {
                    fs::rename(&p, &self.target).map_err(|e| Error::io(&p, e))?;
                } else {
                    fs::remove_dir_all(&p).map_err(|e| Error::io(&p, e))?;
                }
            }
        }
        Ok(())
    }

    pub fn path(&self) -> &Path {
        &self.tmp
    }

    /// Replaces the target by the completed temporary folder. The target was checked to be empty or
    /// an earlier result when the place was claimed, and the lock kept other runs out since.
    pub fn commit(mut self) -> Result<PathBuf> {
        let mut guard = active();
        let changed = match fs::symlink_metadata(&self.target) {
            Err(_) => None,
            Ok(m) if m.is_dir() => foreign_content(&self.target).unwrap_or(None),
            Ok(_) => Some("it is no longer a folder".to_string()),
        };
        if let Some(why) = changed {
            // Someone put files there during the run: keep both, replace nothing.
            self.committed = true;
            guard.tmp = None;
            return Err(Error::invalid(
                format!("--out {}", self.target.display()),
                format!("changed during the run ({why}); the new results are in {}", self.tmp.display()),
            ));
        }
        let old = self.parent.join(format!(".{}.old-{}", self.name, std::process::id()));
        let had_old = fs::symlink_metadata(&self.target).is_ok();
        if had_old {
            fs::rename(&self.target, &old).map_err(|e| Error::io(&self.target, e))?;
        }
        if let Err(e) = fs::rename(&self.tmp, &self.target) {
            if had_old {
                let _ = fs::rename(&old, &self.target);
            }
            return Err(Error::io(&self.target, e));
        }
        self.committed = true;
        guard.tmp = None;
        drop(guard);
        let _ = fs::remove_file(self.target.join(STAGING_MARKER));
        if had_old {
            let _ = fs::remove_dir_all(&old);
        }
        Ok(self.target.clone())
    }
}

impl Drop for OutputPlace {
    /// Removes the unfinished temporary folder and the lock file, while the lock is still held.
    fn drop(&mut self) {
        let mut guard = active();
        if !self.committed && !self.tmp.as_os_str().is_empty() {
            let _ = fs::remove_dir_all(&self.tmp);
        }
        guard.tmp = None;
        let _ = fs::remove_file(&self.lock_path);
        guard.lock = None;
    }
}

/// Takes the lock file `path` (std's `File::try_lock`: flock on Unix, LockFileEx on Windows, the API
/// fs4 offered before std had it), or says who holds it. The file is removed by its
/// holder when done, so after taking the lock we check that the path still names the file we
/// locked: if the holder removed it in between, we locked an orphan and start over.
fn lock(path: &Path, target: &Path, what: &str) -> Result<File> {
    for _ in 0..100 {
        let mut file = OpenOptions::new()
            .read(true)
            .write(true)
            .create(true)
            .truncate(false)
            .open(path)
            .map_err(|e| Error::io(path.parent().unwrap_or(path), format!("output folder is not writable: {e}")))?;
        match file.try_lock() {
            Ok(()) => {}
            Err(std::fs::TryLockError::WouldBlock) => {
                let mut holder = String::new();
                let _ = file.read_to_string(&mut holder);
                let holder = holder.trim();
                let holder =
                    if holder.is_empty() { "another run".to_string() } else { holder.escape_debug().to_string() };
                return Err(Error::invalid(
                    format!("--out {}", target.display().to_string().escape_debug()),
                    format!(
                        "another filterbench run is writing there ({holder}); wait for it or choose another folder"
                    ),
                ));
            }
            Err(std::fs::TryLockError::Error(e)) => return Err(Error::io(path, format!("cannot lock: {e}"))),
        }
        if !same_file(&file, path) {
            continue;
        }
        let _ = file.set_len(0);
        let _ = write!(file, "pid {}: {what}", std::process::id());
        let _ = file.flush();
        return Ok(file);
    }
    Err(Error::io(path, "cannot take the lock: its file keeps being replaced"))
}

#[cfg(unix)]
fn same_file(file: &File, path: &Path) -> bool {
    use std::os::unix::fs::MetadataExt;
    match (file.metadata(), fs::metadata(path)) {
        (Ok(a), Ok(b)) => a.dev() == b.dev() && a.ino() == b.ino(),
        _ => false,
    }
}

#[cfg(not(unix))]
fn same_file(_: &File, path: &Path) -> bool {
    path.exists()
}
