//! `--out` never loses a user's files (issue 14 §1): only an empty folder or an earlier filterbench
//! result is replaced; everything else is refused with exit 2 before any work, and every file is
//! byte for byte as before. Interrupted and killed runs leave nothing behind for long, and two runs
//! into one place never race.

use std::collections::BTreeMap;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};
use std::time::{Duration, Instant};

use crate::common::TempDir;

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");

/// Every file and folder under `root` with its contents (folders: empty), by relative path: equal
/// snapshots mean nothing was added, removed or changed (a stronger check than checksums).
pub fn snapshot(root: &Path) -> BTreeMap<PathBuf, Vec<u8>> {
    let mut out = BTreeMap::new();
    let mut todo = vec![root.to_path_buf()];
    while let Some(dir) = todo.pop() {
        for e in std::fs::read_dir(&dir).unwrap().flatten() {
            let p = e.path();
            let rel = p.strip_prefix(root).unwrap().to_path_buf();
            let t = e.file_type().unwrap();
            if t.is_dir() {
                out.insert(rel, Vec::new());
                todo.push(p);
            } else if t.is_symlink() {
                out.insert(rel, std::fs::read_link(&p).unwrap().into_os_string().into_encoded_bytes());
            } else {
                out.insert(rel, std::fs::read(&p).unwrap());
            }
        }
    }
    out
}

/// `filterbench experiment kalman_baseline --trials 2 --quiet ARGS…` run in `cwd`.
fn run_in(cwd: &Path, args: &[&str]) -> Output {
    Command::new(BIN)
        .args(["experiment", "kalman_baseline", "--trials", "2", "--quiet"])
        .args(args)
        .current_dir(cwd)
        .output()
        .unwrap()
}

/// Exit 2, one line, no panic, mentioning every needle.
pub fn refused(o: &Output, needles: &[&str]) {
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(2), "exit 2; stderr: {err}");
    assert!(!err.contains("panicked"), "no panic: {err}");
    assert_eq!(err.trim_end().lines().count(), 1, "one line: {err}");
    for n in needles {
        assert!(err.contains(n), "message should mention `{n}`: {err}");
    }
}

/// A workspace: a copy of the shipped experiments (so `kalman_baseline` resolves) and a user's
/// files beside them, all of which must survive.
fn workspace() -> TempDir {
    let tmp = TempDir::new();
    let exp = tmp.path().join("experiments");
    std::fs::create_dir_all(&exp).unwrap();
    std::fs::copy(
        format!("{}/experiments/kalman_baseline.toml", env!("CARGO_MANIFEST_DIR")),
        exp.join("kalman_baseline.toml"),
    )
    .unwrap();
    let home = tmp.path().join("home");
    std::fs::create_dir_all(home.join("thesis")).unwrap();
    std::fs::write(home.join("thesis/chapter1.tex"), b"\\section{Results}").unwrap();
    std::fs::write(home.join("notes.txt"), b"do not lose me").unwrap();
    tmp
}

#[test]
fn foreign_folders_files_and_special_paths_are_refused_and_untouched() {
    let ws = workspace();
    let root = ws.path();
    std::fs::write(root.join("a_file"), b"precious").unwrap();
    let deep = root.join("home/thesis");
    let before = snapshot(root);
    let cases: Vec<(PathBuf, String, &str)> = vec![
        (root.to_path_buf(), root.join("home").display().to_string(), "not an earlier filterbench result"),
        (root.to_path_buf(), root.join("a_file").display().to_string(), "is a file"),
        (root.to_path_buf(), "/".into(), "is `/`, `.` or `..`"),
        (deep.clone(), ".".into(), "is `/`, `.` or `..`"),
        (deep.clone(), "..".into(), "is `/`, `.` or `..`"),
        (deep.clone(), "../..".into(), "is `/`, `.` or `..`"),
        (deep.clone(), root.join("home").display().to_string(), "working directory or one of its ancestors"),
        (deep.clone(), "../../home".into(), "working directory or one of its ancestors"),
        (root.to_path_buf(), "experiments".into(), "not an earlier filterbench result"),
    ];
    for (cwd, out, needle) in &cases {
        let t = Instant::now();
        let o = run_in(cwd, &["--out", out]);
        refused(&o, &["--out", needle]);
        assert!(t.elapsed() < Duration::from_secs(20), "refused before any work: {out}");
        assert_eq!(snapshot(root), before, "nothing touched by --out {out}");
    }
}

#[test]
fn a_folder_with_a_foreign_manifest_or_extra_files_is_refused() {
    let ws = workspace();
    let root = ws.path();
    let web = root.join("webapp");
    std::fs::create_dir_all(&web).unwrap();
    std::fs::write(web.join("manifest.json"), br#"{"name": "my app"}"#).unwrap();
    let before = snapshot(root);
    refused(&run_in(root, &["--out", "webapp"]), &["--out webapp", "manifest.json was not written by filterbench"]);
    assert_eq!(snapshot(root), before);

    // An earlier result is replaced; the same result with a user's file added is not.
    assert!(run_in(root, &["--out", "results/kb"]).status.success());
    assert!(run_in(root, &["--out", "results/kb"]).status.success(), "an earlier result is replaced");
    std::fs::write(root.join("results/kb/my_plot.png"), b"png").unwrap();
    let before = snapshot(root);
    refused(&run_in(root, &["--out", "results/kb"]), &["results/kb", "`my_plot.png`", "did not write"]);
    assert_eq!(snapshot(root), before);
}

#[test]
fn names_too_long_or_with_control_characters_are_refused_up_front() {
    let ws = workspace();
    let root = ws.path();
    let before = snapshot(root);
    let long = "r".repeat(250);
    refused(&run_in(root, &["--out", &long]), &["--out", "250 bytes", "at most 239"]);
    refused(&run_in(root, &["--out", "results/\u{1b}[2Jclear"]), &["--out", "control character U+001B"]);
    assert_eq!(snapshot(root), before);
    // The longest allowed name works end to end (its temporary name fits in 255 bytes).
    let ok = "r".repeat(239);
    let o = run_in(root, &["--out", &ok]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(root.join(&ok).join("manifest.json").is_file());

    // Control characters in names inside the file.
    std::fs::create_dir_all(root.join("results")).unwrap();
    let text = crate::common::text("kalman_baseline");
    for (from, to, key) in [
        ("name = \"nominal_gaussian\"", "name = \"nominal\\u001b[2J\"", "scenarios[0].name"),
        ("name = \"kalman_nominal\"", "name = \"kalman\\u0007\"", "filters[0].name"),
    ] {
        assert!(text.contains(from));
        let file = root.join("bad.toml");
        std::fs::write(&file, text.replacen(from, to, 1)).unwrap();
        let before = snapshot(&root.join("results"));
        let o = Command::new(BIN)
            .args(["experiment", file.to_str().unwrap(), "--trials", "2", "--quiet", "--out", "results/kb"])
            .current_dir(root)
            .output()
            .unwrap();
        refused(&o, &[key, "control character"]);
        assert_eq!(snapshot(&root.join("results")), before);
    }
}

/// Starts a long run into `out` and waits until its temporary folder exists.
fn start_long_run(root: &Path, out: &str) -> (std::process::Child, PathBuf) {
    let child = Command::new(BIN)
        .args(["experiment", "kalman_baseline", "--trials", "50000000", "--threads", "1", "--quiet", "--out", out])
        .current_dir(root)
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let parent = root.join(out).parent().unwrap().to_path_buf();
    let name = Path::new(out).file_name().unwrap().to_string_lossy().into_owned();
    let tmp = parent.join(format!(".{name}.tmp-{}", child.id()));
    let t = Instant::now();
    while !tmp.is_dir() {
        assert!(t.elapsed() < Duration::from_secs(60), "the run creates its temporary folder");
        std::thread::sleep(Duration::from_millis(20));
    }
    (child, tmp)
}

#[test]
fn a_second_run_into_the_same_place_is_refused_at_once_and_signals_clean_up() {
    let ws = workspace();
    let root = ws.path();
    assert!(run_in(root, &["--out", "results/kb"]).status.success());
    let previous = snapshot(&root.join("results/kb"));
    for signal in ["-INT", "-TERM"] {
        let (mut child, tmp) = start_long_run(root, "results/kb");
        let t = Instant::now();
        let o = run_in(root, &["--out", "results/kb"]);
        refused(&o, &["another filterbench run is writing there", &format!("pid {}", child.id())]);
        assert!(t.elapsed() < Duration::from_secs(20), "refused at once");
        let st = Command::new("kill").args([signal, &child.id().to_string()]).status().unwrap();
        assert!(st.success());
        let status = child.wait().unwrap();
        let expected = if signal == "-INT" { 130 } else { 143 };
        assert_eq!(status.code(), Some(expected), "exit 128 + signal");
        assert!(!tmp.exists(), "{signal}: temporary folder removed");
        assert_eq!(snapshot(&root.join("results/kb")), previous, "previous result intact");
    }
    let names: Vec<String> = std::fs::read_dir(root.join("results"))
        .unwrap()
        .flatten()
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .collect();
    assert!(names.iter().all(|n| n == "kb" || n == ".kb.lock"), "nothing else left: {names:?}");
}

#[test]
fn what_a_killed_run_left_is_cleared_by_the_next_run_and_nothing_else() {
    let ws = workspace();
    let root = ws.path();
    let (mut child, tmp) = start_long_run(root, "results/kb");
    child.kill().unwrap(); // SIGKILL: no handler runs.
    child.wait().unwrap();
    assert!(tmp.is_dir(), "SIGKILL leaves the temporary folder");
    // A folder of the user's that merely looks like a temporary one (no marker, not empty) stays.
    let lookalike = root.join("results/.kb.tmp-1");
    std::fs::create_dir_all(&lookalike).unwrap();
    std::fs::write(lookalike.join("mine.txt"), b"mine").unwrap();
    let o = run_in(root, &["--out", "results/kb"]);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(!tmp.exists(), "the dead run's temporary folder is removed");
    assert_eq!(std::fs::read(lookalike.join("mine.txt")).unwrap(), b"mine");
    assert!(root.join("results/kb/manifest.json").is_file());

    // A run killed between moving the previous result aside and renaming the new one into place
    // left `.kb.old-PID` and no `kb`: the next run puts the previous result back before its own
    // replaces it, so a result is never lost in between.
    let previous = snapshot(&root.join("results/kb"));
    std::fs::rename(root.join("results/kb"), root.join("results/.kb.old-999999")).unwrap();
    // This run fails at design time (an anisotropic filter must be a predictor), after the claim.
    let bad = crate::common::text("kalman_baseline")
        + "\n[[filters]]\nname = \"aniso\"\nfamily = \"anisotropic\"\nanisotropy = 1.0\n";
    std::fs::write(root.join("bad.toml"), bad).unwrap();
    let o = Command::new(BIN)
        .args(["experiment", "bad.toml", "--trials", "2", "--quiet", "--out", "results/kb"])
        .current_dir(root)
        .output()
        .unwrap();
    refused(&o, &["aniso"]);
    assert!(!root.join("results/.kb.old-999999").exists());
    assert_eq!(snapshot(&root.join("results/kb")), previous, "the previous result is back in place");
}

#[test]
fn a_lock_held_elsewhere_names_its_holder() {
    let ws = workspace();
    let root = ws.path();
    std::fs::create_dir_all(root.join("results")).unwrap();
    let lock_path = root.join("results/.kb.lock");
    let mut lock = std::fs::File::create(&lock_path).unwrap();
    lock.try_lock().unwrap();
    std::io::Write::write_all(&mut lock, b"pid 4242, filterbench experiment other").unwrap();
    refused(&run_in(root, &["--out", "results/kb"]), &["results/kb", "pid 4242"]);
    assert!(!root.join("results/kb").exists());
}
