//! Matrices from files (docs/experiment-files.md, "Matrices from files"): kalman_baseline with its
//! plant matrices and nominal covariances read from .npy, .npz, .mat (v5 and compressed v7) and
//! .csv gives the same figures to the bit as the file with the matrices inline, and every bad file
//! is refused with one line naming the key and the file, exit code 2.

use std::path::Path;
use std::process::Command;

use filterbench::{config, pipeline};
use npyz::WriterBuilder;

const BIN: &str = env!("CARGO_BIN_EXE_filterbench");
/// The matrices moved to files: the plant's and the nominal covariances.
const PLANT: [&str; 4] = ["A", "B", "C", "D"];
const NOMINAL: [&str; 3] = ["x0", "process", "measurement"];

fn baseline() -> toml::Table {
    toml::from_str(&crate::common::text("kalman_baseline")).unwrap()
}

fn rows(v: &toml::Value) -> Vec<Vec<f64>> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|r| {
            r.as_array().unwrap().iter().map(|x| x.as_float().or(x.as_integer().map(|i| i as f64)).unwrap()).collect()
        })
        .collect()
}

/// Every matrix moved to files, by name (A, …, x0, process, measurement).
fn matrices() -> Vec<(&'static str, Vec<Vec<f64>>)> {
    let doc = baseline();
    let mut out: Vec<_> = PLANT.iter().map(|k| (*k, rows(&doc["plant"][*k]))).collect();
    out.extend(NOMINAL.iter().map(|k| (*k, rows(&doc["nominal"][*k]))));
    out
}

fn write_npy(path: &Path, shape: &[u64], data: &[f64]) {
    let mut f = std::io::BufWriter::new(std::fs::File::create(path).unwrap());
    let mut w = npyz::WriteOptions::new().default_dtype().shape(shape).writer(&mut f).begin_nd().unwrap();
    w.extend(data.iter().copied()).unwrap();
    w.finish().unwrap();
}

/// An .npz as numpy's `savez_compressed` writes it: a zip of deflated `NAME.npy` members.
fn write_npz(path: &Path, arrays: &[(&str, Vec<u64>, Vec<f64>)]) {
    use std::io::Write;
    let mut zip = zip::ZipWriter::new(std::fs::File::create(path).unwrap());
    let options = zip::write::FileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    for (name, shape, data) in arrays {
        let mut bytes = Vec::new();
        let mut w = npyz::WriteOptions::new().default_dtype().shape(shape).writer(&mut bytes).begin_nd().unwrap();
        w.extend(data.iter().copied()).unwrap();
        w.finish().unwrap();
        zip.start_file(format!("{name}.npy"), options).unwrap();
        zip.write_all(&bytes).unwrap();
    }
    zip.finish().unwrap();
}

fn flat(m: &[Vec<f64>]) -> (Vec<u64>, Vec<f64>) {
    (vec![m.len() as u64, m[0].len() as u64], m.iter().flatten().copied().collect())
}

/// kalman_baseline with each matrix replaced by `reference(name)`, written into `dir`.
fn with_refs(dir: &Path, reference: impl Fn(&str) -> toml::Value) -> std::path::PathBuf {
    let mut doc = baseline();
    for k in PLANT {
        doc["plant"].as_table_mut().unwrap().insert(k.into(), reference(k));
    }
    for k in NOMINAL {
        doc["nominal"].as_table_mut().unwrap().insert(k.into(), reference(k));
    }
    let path = dir.join("from_files.toml");
    std::fs::write(&path, toml::to_string(&doc).unwrap()).unwrap();
    path
}

fn file_ref(file: &str, key: Option<&str>) -> toml::Value {
    let mut t = toml::Table::new();
    t.insert("file".into(), file.into());
    if let Some(k) = key {
        t.insert("key".into(), k.into());
    }
    toml::Value::Table(t)
}

/// Every figure of a run as text: `{:?}` prints each f64 in its shortest round-trip form, so equal
/// text is equal bits.
fn figures(exp: &config::Experiment) -> Vec<String> {
    let out = pipeline::run(exp, false).expect("runs");
    out.scenarios.iter().map(|s| format!("{:?} {:?} {:?}", s.exact, s.mc, s.filters)).collect()
}

fn load(path: &Path) -> config::Experiment {
    let mut e = config::load(path).unwrap_or_else(|e| panic!("loads: {e}"));
    e.trials = 200;
    e.sample_trajectories = 0;
    e
}

#[test]
fn round_trips_are_bit_identical() {
    let mut inline = crate::common::baseline(200);
    inline.sample_trajectories = 0;
    let want = figures(&inline);
    let tmp = crate::common::TempDir::new();
    let dir = tmp.path();
    let mats = matrices();

    // .npy, one file per matrix; .csv likewise.
    for (k, m) in &mats {
        let (shape, data) = flat(m);
        write_npy(&dir.join(format!("{k}.npy")), &shape, &data);
        let text: String =
            m.iter().map(|r| r.iter().map(|x| format!("{x:?}")).collect::<Vec<_>>().join(", ") + "\n").collect();
        std::fs::write(dir.join(format!("{k}.csv")), text).unwrap();
    }
    // .npz, one archive, deflated like numpy's savez_compressed.
    let arrays: Vec<(&str, Vec<u64>, Vec<f64>)> = mats.iter().map(|(k, m)| (*k, flat(m).0, flat(m).1)).collect();
    write_npz(&dir.join("m.npz"), &arrays);
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/files");
    for mat in ["kalman_baseline_v6.mat", "kalman_baseline_v7.mat"] {
        std::fs::copy(data.join(mat), dir.join(mat)).unwrap();
    }

    let cases: Vec<(&str, Box<dyn Fn(&str) -> toml::Value>)> = vec![
        ("npy", Box::new(|k| file_ref(&format!("{k}.npy"), None))),
        ("csv", Box::new(|k| file_ref(&format!("{k}.csv"), None))),
        ("npz", Box::new(|k| file_ref("m.npz", Some(k)))),
        ("mat v6", Box::new(|k| file_ref("kalman_baseline_v6.mat", Some(k)))),
        ("mat v7", Box::new(|k| file_ref("kalman_baseline_v7.mat", Some(k)))),
    ];
    for (name, reference) in cases {
        let exp = load(&with_refs(dir, reference));
        assert_eq!(exp.inputs.len(), 7, "{name}: every file recorded");
        assert!(exp.inputs.iter().all(|i| i.sha256.len() == 64 && i.shape.len() == 2), "{name}");
        assert_eq!(exp.plant.a_at(0), inline.plant.a_at(0), "{name}: A read exactly");
        assert_eq!(figures(&exp), want, "{name}: every exact and Monte Carlo figure identical to the bit");
    }
}

/// A per-step array: `A_steps` as one (N+1) × n × n .npy equals the constant A.
#[test]
fn per_step_array_and_wrong_step_count() {
    let tmp = crate::common::TempDir::new();
    let dir = tmp.path();
    let a = rows(&baseline()["plant"]["A"]);
    let steps = 51; // horizon 50: k = 0..50
    let data: Vec<f64> = (0..steps).flat_map(|_| a.iter().flatten().copied()).collect();
    write_npy(&dir.join("A_steps.npy"), &[steps, 3, 3], &data);
    write_npy(&dir.join("A_short.npy"), &[steps - 1, 3, 3], &data[..data.len() - 9]);
    let text = crate::common::text("kalman_baseline");
    let end = text.find("A = [[").unwrap();
    // A must still be given with A_steps (its shape is what each step is checked against).
    let with = |r: &str| format!("{}A_steps = {r}\n{}", &text[..end], &text[end..]);
    std::fs::write(dir.join("steps.toml"), with(r#"{ file = "A_steps.npy" }"#)).unwrap();
    let exp = load(&dir.join("steps.toml"));
    assert_eq!(exp.inputs[0].shape, vec![51, 3, 3]);
    for k in [0, 25, 50] {
        assert_eq!(exp.plant.a_at(k), crate::common::baseline(2).plant.a_at(0));
    }
    std::fs::write(dir.join("short.toml"), with(r#"{ file = "A_short.npy" }"#)).unwrap();
    refused(&run(&dir.join("short.toml")), &["plant.A_steps", "A_short.npy"]);
}

/// `experiment FILE --trials 2` into a scratch folder next to FILE.
fn run(file: &Path) -> std::process::Output {
    let out = file.with_extension("out");
    Command::new(BIN)
        .args(["experiment", file.to_str().unwrap(), "--trials", "2", "--quiet", "--out", out.to_str().unwrap()])
        .output()
        .unwrap()
}

/// An .npy written byte by byte (format 1.0), for a dtype the writer here does not offer.
fn raw_npy(path: &Path, descr: &str, shape: &str, data: &[u8]) {
    let mut header = format!("{{'descr': '{descr}', 'fortran_order': False, 'shape': {shape}, }}");
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    bytes.extend_from_slice(data);
    std::fs::write(path, bytes).unwrap();
}

use crate::bad_input::check_failure as refused;

/// Every bad file: one line, exit 2, naming the key, the file and the cause.
#[test]
fn bad_files_are_refused() {
    let tmp = crate::common::TempDir::new();
    let dir = tmp.path();
    let a = rows(&baseline()["plant"]["A"]);
    let (shape, data) = flat(&a);
    write_npy(&dir.join("A.npy"), &shape, &data);
    write_npy(&dir.join("nan.npy"), &shape, &[f64::NAN; 9]);
    write_npy(&dir.join("inf.npy"), &shape, &[0.0, f64::INFINITY, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0]);
    write_npy(&dir.join("rank4.npy"), &[1, 1, 3, 3], &data);
    write_npy(&dir.join("wrong_shape.npy"), &[3, 2], &data[..6]);
    raw_npy(&dir.join("complex.npy"), "<c16", "(1,)", &[0; 16]);
    raw_npy(&dir.join("int.npy"), ">i4", "(3, 3)", &[0, 0, 0, 1].repeat(9));
    raw_npy(&dir.join("big.npy"), "<i8", "(3, 3)", &[[0, 0, 0, 0, 0, 0, 0x40, 0].as_slice(), &[0; 64]].concat());
    write_npz(&dir.join("m.npz"), &[("A", shape.clone(), data.clone())]);
    std::fs::write(dir.join("ragged.csv"), "0.8, 0.2, -0.1\n0.2, 0.3\n0.5, 0.3, 0.7\n").unwrap();
    std::fs::write(dir.join("header.csv"), "a, b, c\n0.8, 0.2, -0.1\n").unwrap();
    std::fs::write(dir.join("A.txt"), "0.8").unwrap();
    // What MATLAB's `save -v7.3` writes: a 128-byte text header naming 7.3, then HDF5 at byte 512.
    let mut v73 =
        b"MATLAB 7.3 MAT-file, Platform: GLNXA64, Created on: Mon Jan  1 00:00:00 2024 HDF5 schema 1.00 .".to_vec();
    v73.resize(512, b' ');
    v73.extend_from_slice(b"\x89HDF\r\n\x1a\n");
    v73.resize(1024, 0);
    std::fs::write(dir.join("v73.mat"), v73).unwrap();
    let data = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/files");
    std::fs::copy(data.join("kalman_baseline_v7.mat"), dir.join("k.mat")).unwrap();

    let text = crate::common::text("kalman_baseline");
    let start = text.find("A = [[").unwrap();
    let end = start + text[start..].find("]]\n").unwrap() + 3;
    let cases: &[(&str, &[&str])] = &[
        (r#"{ file = "missing.npy" }"#, &["missing.npy", "cannot read"]),
        (r#"{ file = "m.npz", key = "Q" }"#, &["m.npz", "no array `Q`", "it holds: A"]),
        (r#"{ file = "m.npz" }"#, &["m.npz", "name one with `key"]),
        (r#"{ file = "A.npy", key = "A" }"#, &["A.npy", "`key` applies to .npz and .mat"]),
        (r#"{ file = "A.npy", sheet = 1 }"#, &["A.npy", "unexpected key `sheet`"]),
        (r#"{ file = "complex.npy" }"#, &["complex.npy", "dtype `<c16`", "float64, float32 and integer"]),
        (r#"{ file = "big.npy" }"#, &["big.npy", "not exact in a float64"]),
        (r#"{ file = "rank4.npy" }"#, &["rank4.npy", "rank 4"]),
        (r#"{ file = "nan.npy" }"#, &["nan.npy", "NaN", "finite"]),
        (r#"{ file = "inf.npy" }"#, &["inf.npy", "inf at flat index 1"]),
        (r#"{ file = "wrong_shape.npy" }"#, &["wrong_shape.npy"]),
        (r#"{ file = "ragged.csv" }"#, &["ragged.csv", "ragged: row 2 has 2 fields, row 1 has 3"]),
        (r#"{ file = "header.csv" }"#, &["header.csv", "`a` is not a number"]),
        (r#"{ file = "A.txt" }"#, &["A.txt", "unknown extension"]),
        (r#"{ file = "v73.mat", key = "A" }"#, &["v73.mat", "v7.3", "-v7"]),
        (r#"{ file = "k.mat", key = "Q" }"#, &["k.mat", "no numeric array `Q`", "measurement"]),
        (r#"{ file = "k.mat", key = "Zc" }"#, &["k.mat", "`Zc` is complex"]),
        (r#"{ file = 3 }"#, &["plant.A.file", "must be a string"]),
    ];
    for (i, (reference, needles)) in cases.iter().enumerate() {
        let file = dir.join(format!("bad{i}.toml"));
        std::fs::write(&file, format!("{}A = {reference}\n{}", &text[..start], &text[end..])).unwrap();
        let o = run(&file);
        let mut all = vec!["plant.A"];
        all.extend_from_slice(needles);
        refused(&o, &all);
    }
    // Integers are accepted, in either byte order (big-endian int32 ones here), as f64.
    let file = dir.join("int.toml");
    std::fs::write(&file, format!("{}A = {{ file = \"int.npy\" }}\n{}", &text[..start], &text[end..])).unwrap();
    assert!(load(&file).plant.a_at(0).iter().all(|&x| x == 1.0));
}

/// The manifest lists each file read with its path as written, the path read, its SHA-256 and
/// the shape.
#[test]
fn manifest_records_files() {
    let tmp = crate::common::TempDir::new();
    let dir = tmp.path();
    for (k, m) in matrices() {
        let (shape, data) = flat(&m);
        write_npy(&dir.join(format!("{k}.npy")), &shape, &data);
    }
    let path = with_refs(dir, |k| file_ref(&format!("{k}.npy"), None));
    let out = dir.join("out");
    let o = Command::new(BIN)
        .args(["experiment", path.to_str().unwrap(), "--trials", "2", "--quiet", "--out", out.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("manifest.json")).unwrap()).unwrap();
    let files = m["files"].as_array().expect("a files list");
    assert_eq!(files.len(), 7);
    let a = files.iter().find(|f| f["key"] == "plant.A").expect("plant.A recorded");
    assert_eq!(a["file"], "A.npy");
    assert_eq!(a["shape"], serde_json::json!([3, 3]));
    let bytes = std::fs::read(dir.join("A.npy")).unwrap();
    use sha2::Digest;
    let sha: String = sha2::Sha256::digest(&bytes).iter().map(|b| format!("{b:02x}")).collect();
    assert_eq!(a["sha256"], sha.as_str());
    assert_eq!(Path::new(a["resolved"].as_str().unwrap()), dir.join("A.npy"));
    // The recorded experiment text has the arrays inline, so it rebuilds the run without the files.
    let again = config::parse("again", "again.toml", m["experiment_file"].as_str().unwrap()).expect("self-contained");
    assert!(again.inputs.is_empty());
    assert_eq!(again.plant.a_at(0), load(&path).plant.a_at(0));
}

/// References outside the plant: a set's center, a disturbance's weight, a filter's design
/// covariance and a variant's patch each read from a file give the figures of the inline file, to
/// the bit, and the manifest's list names each key.
#[test]
fn references_in_sets_disturbances_filters_and_variants() {
    use crate::common::Patch;
    let tmp = crate::common::TempDir::new();
    let dir = tmp.path();
    let eye = [vec![1.0, 0.0, 0.0], vec![0.0, 1.0, 0.0], vec![0.0, 0.0, 1.0]];
    let (shape, data) = flat(&eye);
    write_npy(&dir.join("eye.npy"), &shape, &data);
    let zeros = vec![vec![0.0; 3]; 3];
    let (shape, data) = flat(&zeros);
    write_npy(&dir.join("zeros.npy"), &shape, &data);
    let measurement = [vec![0.5, 0.0, 0.0], vec![0.0, 0.8, 0.0], vec![0.0, 0.0, 0.1]];
    let (shape, data) = flat(&measurement);
    write_npy(&dir.join("measurement.npy"), &shape, &data);
    let half = [vec![0.2, 0.0, 0.0], vec![0.0, 0.2, 0.0], vec![0.0, 0.0, 0.2]];
    let inline = crate::common::text("minimax_energy").patch("trials = 20000", "trials = 300").patch(
        "[sets.measurement]\nkind = \"box\"\nhalf_width = 0.1\n",
        "[sets.measurement]\nkind = \"box\"\nhalf_width = 0.1\ncenter = [[0.5, 0, 0], [0, 0.8, 0], [0, 0, 0.1]]\n",
    ) + "\n[[variants]]\nname = \"plain\"\n\n[[variants]]\nname = \"wide\"\nsets = { process = { half_width = [[0.2, 0, 0], [0, 0.2, 0], [0, 0, 0.2]] } }\n";
    let (shape, data) = flat(&half);
    write_npy(&dir.join("half.npy"), &shape, &data);
    let from_files = inline
        .patch("center = [[0.5, 0, 0], [0, 0.8, 0], [0, 0, 0.1]]", "center = { file = \"measurement.npy\" }")
        .patch(
            "[disturbances.u]\nweight = [[1, 0, 0], [0, 1, 0], [0, 0, 1]]",
            "[disturbances.u]\nweight = { file = \"eye.npy\" }",
        )
        .patch(
            "design = { kind = \"given\", u = [[0, 0, 0], [0, 0, 0], [0, 0, 0]],",
            "design = { kind = \"given\", u = { file = \"zeros.npy\" },",
        )
        .patch("half_width = [[0.2, 0, 0], [0, 0.2, 0], [0, 0, 0.2]]", "half_width = { file = \"half.npy\" }");
    let load_all = |name: &str, text: &str| {
        let path = dir.join(format!("{name}.toml"));
        std::fs::write(&path, text).unwrap();
        config::load_variants(&path, &Default::default()).unwrap_or_else(|e| panic!("{name} loads: {e}"))
    };
    let (a, b) = (load_all("inline", &inline), load_all("files", &from_files));
    assert_eq!(a.len(), 2);
    let keys: Vec<&str> = b[0].inputs.iter().map(|i| i.key.as_str()).collect();
    for k in [
        "sets.measurement.center",
        "disturbances.u.weight",
        "filters[0].design.u",
        "variants[1].sets.process.half_width",
    ] {
        assert!(keys.contains(&k), "{k} recorded in {keys:?}");
    }
    for (x, y) in a.iter().zip(&b) {
        assert_eq!(figures(x), figures(y), "variant {:?}: identical to the bit", x.variant);
    }
}

/// A matrix read from a file that makes another key's size wrong: the message names both keys and
/// the file.
#[test]
fn a_wrong_size_from_a_file_names_the_file_behind_the_size() {
    let tmp = crate::common::TempDir::new();
    let dir = tmp.path();
    write_npy(&dir.join("A2.npy"), &[2, 2], &[1.0, 0.0, 0.0, 1.0]);
    let path = with_refs(dir, |k| {
        if k == "A" {
            file_ref("A2.npy", None)
        } else {
            baseline()[if PLANT.contains(&k) { "plant" } else { "nominal" }][k].clone()
        }
    });
    let o = run(&path);
    crate::bad_input::check_failure(
        &o,
        &[
            "plant.B: expected 2 rows (the state dimension: the rows of plant.A), found 3",
            "(plant.A read from `A2.npy`)",
        ],
    );
}
