//! The array file formats a matrix may come from (docs/experiment-files.md, "Matrices from files"):
//! NumPy `.npy` and `.npz` (npyz), MATLAB v5/v7 `.mat` (matfile) and plain `.csv` (csv). Each reader
//! returns the array in row-major order with its shape; the caller checks rank and finiteness.

use std::io::Cursor;

/// An array as read: its shape (the first axis first) and its values in row-major (C) order.
pub(super) struct Array {
    pub(super) shape: Vec<usize>,
    pub(super) data: Vec<f64>,
}

/// The formats by extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Format {
    Npy,
    Npz,
    Mat,
    Csv,
}

impl Format {
    /// The format of a file name by its extension (case-insensitive), if it is one of the four.
    pub(super) fn of(file: &str) -> Option<Format> {
        let ext = std::path::Path::new(file).extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "npy" => Some(Format::Npy),
            "npz" => Some(Format::Npz),
            "mat" => Some(Format::Mat),
            "csv" => Some(Format::Csv),
            _ => None,
        }
    }
    /// Whether the file holds several arrays, so a `key` names one.
    pub(super) fn keyed(self) -> bool {
        matches!(self, Format::Npz | Format::Mat)
    }
}

/// Reads the array of `bytes` in `format` (`key` for the archives). The error is the cause only;
/// the caller adds the experiment key and the file.
pub(super) fn read(format: Format, bytes: &[u8], key: Option<&str>) -> Result<Array, String> {
    match format {
        Format::Npy => npy(npyz::NpyFile::new(Cursor::new(bytes)).map_err(|e| format!("not a valid .npy file ({e})"))?),
        Format::Npz => npz(bytes, key.unwrap_or_default()),
        Format::Mat => mat(bytes, key.unwrap_or_default()),
        Format::Csv => csv(bytes),
    }
}

/// The largest integer every smaller one of which an f64 holds exactly (2⁵³).
const EXACT_INT: f64 = 9_007_199_254_740_992.0;

/// An integer converted to f64, refused when the conversion would round it.
fn int_to_f64(v: i128) -> Result<f64, String> {
    let x = v as f64;
    if x.abs() > EXACT_INT {
        return Err(format!("the integer {v} is not exact in a float64 (beyond 2^53)"));
    }
    Ok(x)
}

fn ints<T: Into<i128> + Copy>(v: Vec<T>) -> Result<Vec<f64>, String> {
    v.into_iter().map(|x| int_to_f64(x.into())).collect()
}

/// Row-major values from column-major (Fortran) ones of `shape`.
fn to_row_major(shape: &[usize], col: Vec<f64>) -> Vec<f64> {
    if shape.len() < 2 {
        return col;
    }
    let len = col.len();
    let mut out = vec![0.0; len];
    // Column-major strides: the first axis varies fastest.
    let mut cstride = vec![1usize; shape.len()];
    for a in 1..shape.len() {
        cstride[a] = cstride[a - 1] * shape[a - 1];
    }
    let mut idx = vec![0usize; shape.len()];
    for o in out.iter_mut() {
        *o = col[idx.iter().zip(&cstride).map(|(i, s)| i * s).sum::<usize>()];
        // Advance the row-major index: the last axis fastest.
        for a in (0..shape.len()).rev() {
            idx[a] += 1;
            if idx[a] < shape[a] {
                break;
            }
            idx[a] = 0;
        }
    }
    out
}

/// One `.npy` array: float64, float32 or an integer dtype of either byte order, C or Fortran order.
fn npy<R: std::io::Read>(file: npyz::NpyFile<R>) -> Result<Array, String> {
    let shape: Vec<usize> = file.shape().iter().map(|&d| d as usize).collect();
    let fortran = file.order() == npyz::Order::Fortran;
    let npyz::DType::Plain(ts) = file.dtype() else {
        return Err("a structured dtype: only float64, float32 and integer arrays are accepted".into());
    };
    let bad = || format!("dtype `{ts}`: only float64, float32 and integer arrays are accepted");
    let io = |e: std::io::Error| format!("cannot read the data ({e})");
    let data = match (ts.type_char(), ts.size_field()) {
        (npyz::TypeChar::Float, 8) => file.into_vec::<f64>().map_err(io)?,
        (npyz::TypeChar::Float, 4) => file.into_vec::<f32>().map_err(io)?.into_iter().map(f64::from).collect(),
        (npyz::TypeChar::Int, 1) => ints(file.into_vec::<i8>().map_err(io)?)?,
        (npyz::TypeChar::Int, 2) => ints(file.into_vec::<i16>().map_err(io)?)?,
        (npyz::TypeChar::Int, 4) => ints(file.into_vec::<i32>().map_err(io)?)?,
        (npyz::TypeChar::Int, 8) => ints(file.into_vec::<i64>().map_err(io)?)?,
        (npyz::TypeChar::Uint, 1) => ints(file.into_vec::<u8>().map_err(io)?)?,
        (npyz::TypeChar::Uint, 2) => ints(file.into_vec::<u16>().map_err(io)?)?,
        (npyz::TypeChar::Uint, 4) => ints(file.into_vec::<u32>().map_err(io)?)?,
        (npyz::TypeChar::Uint, 8) => ints(file.into_vec::<u64>().map_err(io)?)?,
        _ => return Err(bad()),
    };
    let data = if fortran { to_row_major(&shape, data) } else { data };
    Ok(Array { shape, data })
}

/// An .npz is a zip archive of `NAME.npy` members (numpy's `savez` stores them, `savez_compressed`
/// deflates them).
fn npz(bytes: &[u8], key: &str) -> Result<Array, String> {
    let mut archive =
        zip::ZipArchive::new(Cursor::new(bytes)).map_err(|e| format!("not a valid .npz archive ({e})"))?;
    let names: Vec<String> = archive.file_names().filter_map(|n| n.strip_suffix(".npy")).map(str::to_string).collect();
    let mut member = match archive.by_name(&format!("{key}.npy")) {
        Ok(m) => m,
        Err(zip::result::ZipError::FileNotFound) => {
            let mut names = names;
            names.sort();
            return Err(format!("no array `{key}` in the archive (it holds: {})", names.join(", ")));
        }
        Err(e) => return Err(format!("array `{key}` cannot be read ({e})")),
    };
    let mut npy_bytes = Vec::with_capacity(member.size() as usize);
    std::io::Read::read_to_end(&mut member, &mut npy_bytes)
        .map_err(|e| format!("array `{key}` cannot be read ({e})"))?;
    npy(npyz::NpyFile::new(&npy_bytes[..]).map_err(|e| format!("array `{key}` is not an .npy ({e})"))?)
}

/// The 128-byte header of a v7.3 .mat says so in its text, and an HDF5 signature follows at 512.
fn is_v73(bytes: &[u8]) -> bool {
    let head = String::from_utf8_lossy(&bytes[..bytes.len().min(116)]);
    head.contains("MATLAB 7.3") || bytes.get(512..520) == Some(b"\x89HDF\r\n\x1a\n")
}

fn mat(bytes: &[u8], key: &str) -> Result<Array, String> {
    if is_v73(bytes) {
        return Err("a MATLAB v7.3 (HDF5) file, which is not read: save it with `save(..., '-v7')`".into());
    }
    let file =
        matfile::MatFile::parse(Cursor::new(bytes)).map_err(|e| format!("not a readable MATLAB v5/v7 file ({e})"))?;
    let Some(a) = file.find_by_name(key) else {
        let names: Vec<&str> = file.arrays().iter().map(|a| a.name()).collect();
        return Err(format!("no numeric array `{key}` in the file (it holds: {})", names.join(", ")));
    };
    use matfile::NumericData as N;
    let complex = || Err(format!("array `{key}` is complex: only real arrays are accepted"));
    let data = match a.data() {
        N::Double { real, imag: None } => real.clone(),
        N::Single { real, imag: None } => real.iter().map(|&x| f64::from(x)).collect(),
        N::Int8 { real, imag: None } => ints(real.clone())?,
        N::UInt8 { real, imag: None } => ints(real.clone())?,
        N::Int16 { real, imag: None } => ints(real.clone())?,
        N::UInt16 { real, imag: None } => ints(real.clone())?,
        N::Int32 { real, imag: None } => ints(real.clone())?,
        N::UInt32 { real, imag: None } => ints(real.clone())?,
        N::Int64 { real, imag: None } => ints(real.clone())?,
        N::UInt64 { real, imag: None } => ints(real.clone())?,
        _ => return complex(),
    };
    let shape = a.size().clone();
    Ok(Array { data: to_row_major(&shape, data), shape })
}

/// A CSV of numbers only: no header, one row per line, the same number of fields on every row.
fn csv(bytes: &[u8]) -> Result<Array, String> {
    let mut reader =
        csv::ReaderBuilder::new().has_headers(false).flexible(true).trim(csv::Trim::All).from_reader(bytes);
    let mut data = Vec::new();
    let mut cols = None;
    let mut rows = 0;
    for (r, rec) in reader.records().enumerate() {
        let rec = rec.map_err(|e| format!("not valid CSV ({e})"))?;
        let width = *cols.get_or_insert(rec.len());
        if rec.len() != width {
            return Err(format!("ragged: row {} has {} fields, row 1 has {width}", r + 1, rec.len()));
        }
        for (c, field) in rec.iter().enumerate() {
            let x: f64 = field.parse().map_err(|_| {
                format!(
                    "row {}, column {}: `{field}` is not a number (a CSV holds numbers only, no header)",
                    r + 1,
                    c + 1
                )
            })?;
            data.push(x);
        }
        rows += 1;
    }
    if rows == 0 {
        return Err("the CSV is empty".into());
    }
    Ok(Array { shape: vec![rows, cols.unwrap_or(0)], data })
}
