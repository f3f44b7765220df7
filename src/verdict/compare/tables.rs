//! Which columns of each result table are keys, Monte Carlo means (with the standard error that
//! goes with each), other sampled figures, or deterministic values (docs/output-columns.md), and
//! the comparison of one table of two folders, row by row and column by column.

use std::collections::HashMap;

use super::cell::{Cell, CompareOptions, Kind, Status, Value, deterministic, two_sample};
use super::folder::{Col, Frame};
use super::outcome::ColumnSummary;
use crate::sim::stats::Z95;

/// Where a Monte Carlo mean's standard error comes from.
pub(crate) enum Se {
    Column(&'static str),
    /// The standard-error column when the table has it, else the 95 % interval's half-width over
    /// z₀.₉₇₅ (the interval is mean ± z₀.₉₇₅·se, docs/output-columns.md): results written before
    /// `mse_std_error` existed.
    OrInterval(&'static str, &'static str, &'static str),
}

/// One table of the output contract as `compare` reads it.
pub(crate) struct Spec {
    pub name: &'static str,
    pub file: &'static str,
    /// The columns that identify a row.
    pub keys: &'static [&'static str],
    /// Monte Carlo means and their standard errors.
    pub mc: &'static [(&'static str, Se)],
    /// Sampled figures without a test of their own.
    pub sampled: &'static [&'static str],
    /// A row missing on one side is a value of 0 (gains.parquet leaves exact zeros out).
    pub absent_is_zero: bool,
}

pub(crate) const SPECS: &[Spec] = &[
    Spec {
        name: "summary",
        file: "summary.parquet",
        keys: &["variant", "scenario", "filter"],
        mc: &[("empirical_mean", Se::Column("std_error"))],
        sampled: &[
            "std_error",
            "ci_low",
            "ci_high",
            "median",
            "p95",
            "nees_empirical",
            "nis_empirical",
            "violations",
            "max_ratio",
            "gain_empirical",
            "gain_ci_low",
            "gain_ci_high",
        ],
        absent_is_zero: false,
    },
    Spec {
        name: "steps",
        file: "steps.parquet",
        keys: &["variant", "scenario", "filter", "step"],
        mc: &[
            ("mse_mean", Se::OrInterval("mse_std_error", "mse_ci_low", "mse_ci_high")),
            ("nees_mean", Se::OrInterval("nees_std_error", "nees_ci_low", "nees_ci_high")),
            ("nis_mean", Se::OrInterval("nis_std_error", "nis_ci_low", "nis_ci_high")),
        ],
        sampled: &[
            "mse_ci_low",
            "mse_ci_high",
            "mse_std_error",
            "nees_ci_low",
            "nees_ci_high",
            "nees_std_error",
            "nis_ci_low",
            "nis_ci_high",
            "nis_std_error",
        ],
        absent_is_zero: false,
    },
    Spec {
        name: "paired",
        file: "paired.parquet",
        keys: &["variant", "scenario", "filter_a", "filter_b"],
        mc: &[("mean_diff", Se::Column("std_error"))],
        sampled: &["std_error", "ci_low", "ci_high"],
        absent_is_zero: false,
    },
    Spec {
        name: "gains",
        file: "gains.parquet",
        keys: &["variant", "filter", "step", "mode", "matrix", "row", "col"],
        mc: &[],
        sampled: &[],
        absent_is_zero: true,
    },
    Spec {
        name: "design_trace",
        file: "design_trace.parquet",
        keys: &["variant", "filter", "iteration"],
        mc: &[],
        sampled: &[],
        absent_is_zero: false,
    },
];

/// A Monte Carlo cell waiting for Holm's procedure: its p-value and, when it is kept, its index
/// in the cells.
pub(crate) struct Pending {
    pub p: f64,
    pub cell: Option<usize>,
    pub column: (&'static str, String),
}

/// What the tables' comparisons collect.
#[derive(Default)]
pub(crate) struct Sink {
    pub cells: Vec<Cell>,
    /// One per (table, column), in the order first met.
    pub columns: Vec<ColumnSummary>,
    index: HashMap<(&'static str, String), usize>,
    pub pending: Vec<Pending>,
}

/// What every table's comparison needs besides its two frames.
pub(crate) struct Ctx<'a> {
    pub opts: &'a CompareOptions,
    /// Both runs drew the same numbers (same seed and trials): a Monte Carlo value is then compared
    /// like a deterministic one.
    pub common_draws: bool,
    /// (variant, scenario, filter) → the larger |exact| and |empirical_mean| of the two summaries:
    /// the scale of the paired differences.
    pub filter_scale: HashMap<(String, String, String), (f64, f64)>,
}

fn key_text(f: &Frame, name: &str, i: usize) -> Option<String> {
    f.column(name).and_then(|c| c.text(i))
}

/// The rows of the two frames that belong together, in OLD's order then NEW's rows not in OLD.
/// When both have the same keys in the same order (every run of the same experiment writes them
/// so), row i is row i and no index is built.
fn align(spec: &Spec, old: &Frame, new: &Frame) -> Vec<(Option<usize>, Option<usize>)> {
    let key = |f: &Frame, i: usize| -> String {
        let parts: Vec<String> =
            spec.keys.iter().map(|k| key_text(f, k, i).unwrap_or_else(|| "\u{0}".into())).collect();
        parts.join("\u{1f}")
    };
    let same = old.height == new.height
        && spec.keys.iter().all(|k| match (old.column(k), new.column(k)) {
            (None, None) => true,
            (Some(Col::Num(a)), Some(Col::Num(b))) => (0..old.height).all(|i| a.get(i) == b.get(i)),
            (Some(Col::Text(a)), Some(Col::Text(b))) => (0..old.height).all(|i| a.get(i) == b.get(i)),
            _ => false,
        });
    if same {
        return (0..old.height).map(|i| (Some(i), Some(i))).collect();
    }
    let index: HashMap<String, usize> = (0..new.height).map(|j| (key(new, j), j)).collect();
    let mut seen = vec![false; new.height];
    let mut out = vec![];
    for i in 0..old.height {
        let j = index.get(&key(old, i)).copied();
        if let Some(j) = j {
            seen[j] = true;
        }
        out.push((Some(i), j));
    }
    out.extend((0..new.height).filter(|&j| !seen[j]).map(|j| (None, Some(j))));
    out
}

/// A cell with its place filled from the row's key.
fn blank(spec: &Spec, f: &Frame, i: Option<usize>, column: &str, kind: Kind) -> Cell {
    let k = |n: &str| i.and_then(|i| key_text(f, n, i));
    let entry = match spec.name {
        "gains" => Some(format!(
            "{}[{},{}]{}",
            k("matrix").unwrap_or_default(),
            k("row").unwrap_or_default(),
            k("col").unwrap_or_default(),
            k("mode").map(|m| format!(" mode {m}")).unwrap_or_default()
        )),
        "design_trace" => k("iteration").map(|it| format!("iteration {it}")),
        _ => None,
    };
    let (filter, filter_b) =
        if spec.keys.contains(&"filter_a") { (k("filter_a"), k("filter_b")) } else { (k("filter"), None) };
    Cell {
        table: spec.name,
        variant: k("variant"),
        scenario: k("scenario"),
        filter,
        filter_b,
        step: spec.keys.contains(&"step").then(|| k("step")?.parse::<f64>().ok().map(|s| s as u32)).flatten(),
        entry,
        column: column.to_string(),
        old: Value::Absent,
        new: Value::Absent,
        kind,
        status: Status::Changed,
        rel_diff: None,
        z: None,
        std_error: None,
        p: None,
        holm_threshold: None,
    }
}

/// The standard error of a Monte Carlo column at row i of one frame.
fn std_error(se: &Se, f: &Frame, i: usize) -> Option<f64> {
    match se {
        Se::Column(c) => f.column(c)?.num(i),
        Se::OrInterval(c, lo, hi) => match f.column(c) {
            Some(col) => col.num(i),
            None => Some((f.column(hi)?.num(i)? - f.column(lo)?.num(i)?) / (2.0 * Z95)),
        },
    }
}

/// The scale a relative difference is taken against, beyond the two values themselves: a gain
/// entry's matrix (its largest entry in either folder), a paired difference's two filters.
struct Scales {
    gains: HashMap<String, f64>,
}

fn gain_group(f: &Frame, i: usize) -> String {
    ["variant", "filter", "step", "mode", "matrix"].map(|k| key_text(f, k, i).unwrap_or_default()).join("\u{1f}")
}

impl Scales {
    fn new(spec: &Spec, old: &Frame, new: &Frame) -> Scales {
        let mut gains = HashMap::new();
        if spec.name == "gains" {
            for f in [old, new] {
                let Some(v) = f.column("value") else { continue };
                for i in 0..f.height {
                    let e = gains.entry(gain_group(f, i)).or_insert(0.0f64);
                    *e = e.max(v.num(i).unwrap_or(0.0).abs());
                }
            }
        }
        Scales { gains }
    }

    fn of(&self, ctx: &Ctx, spec: &Spec, f: &Frame, i: usize, column: &str) -> f64 {
        match spec.name {
            "gains" => self.gains.get(&gain_group(f, i)).copied().unwrap_or(0.0),
            "paired" => {
                let v = key_text(f, "variant", i).unwrap_or_default();
                let s = key_text(f, "scenario", i).unwrap_or_default();
                let pick = |k: &str| {
                    let key = (v.clone(), s.clone(), key_text(f, k, i).unwrap_or_default());
                    ctx.filter_scale.get(&key).map_or(0.0, |&(ex, emp)| if column == "exact_diff" { ex } else { emp })
                };
                pick("filter_a").max(pick("filter_b"))
            }
            _ => 0.0,
        }
    }
}

/// Compares one table of the two folders into `sink`. A table or column in one folder only is
/// one Presence cell; a row in one folder only is one Presence cell (column "(row)"), except in
/// gains.parquet where a missing entry is 0. Keys, `experiment` (the manifest's check covers it)
/// and timings (`*_seconds`) are not compared.
pub(crate) fn compare_table(spec: &Spec, old: Option<&Frame>, new: Option<&Frame>, ctx: &Ctx, sink: &mut Sink) {
    let (old, new) = match (old, new) {
        (Some(a), Some(b)) => (a, b),
        (None, None) => return,
        (a, b) => {
            let mut c = blank(spec, a.or(b).expect("one side"), None, "(table)", Kind::Presence);
            c.old = if a.is_some() { Value::Text(spec.file.into()) } else { Value::Absent };
            c.new = if b.is_some() { Value::Text(spec.file.into()) } else { Value::Absent };
            push(sink, ctx, c);
            return;
        }
    };
    let mut names: Vec<&str> = old.columns.iter().map(|(n, _)| n.as_str()).collect();
    names.extend(new.columns.iter().map(|(n, _)| n.as_str()).filter(|n| old.column(n).is_none()));
    names.retain(|n| !spec.keys.contains(n) && *n != "experiment" && !n.ends_with("_seconds"));
    let rows = align(spec, old, new);
    let scales = Scales::new(spec, old, new);
    for name in names {
        let (a, b) = (old.column(name), new.column(name));
        let (Some(a), Some(b)) = (a, b) else {
            let mut c = blank(spec, old, None, name, Kind::Presence);
            c.old = if a.is_some() { Value::Text("(column)".into()) } else { Value::Absent };
            c.new = if b.is_some() { Value::Text("(column)".into()) } else { Value::Absent };
            push(sink, ctx, c);
            continue;
        };
        let mc = spec.mc.iter().find(|(n, _)| *n == name).map(|(_, se)| se);

        let kind = if mc.is_some() {
            Kind::MonteCarlo
        } else if spec.sampled.contains(&name) {
            Kind::Sampled
        } else if matches!(a, Col::Text(_)) || matches!(b, Col::Text(_)) {
            Kind::Label
        } else {
            Kind::Deterministic
        };
        summary_of(sink, spec.name, name, kind);
        for &(i, j) in &rows {
            let (va, vb) = match (i, j) {
                (Some(i), Some(j)) => (a.value(i), b.value(j)),
                (Some(i), None) if spec.absent_is_zero => (a.value(i), Value::Num(0.0)),
                (None, Some(j)) if spec.absent_is_zero => (Value::Num(0.0), b.value(j)),
                _ => continue,
            };
            if va == Value::Null && vb == Value::Null {
                continue;
            }
            let (f, r) = match (i, j) {
                (_, Some(j)) => (new, j),
                (Some(i), None) => (old, i),
                _ => unreachable!(),
            };
            let bit_equal = deterministic(&va, &vb, 0.0, 0.0).0 == Status::Identical;
            let tested = kind == Kind::MonteCarlo && !ctx.common_draws;
            if bit_equal && !tested && !ctx.opts.keep_identical {
                // Most cells of a large table: counted without building a cell.
                summary_of(sink, spec.name, name, kind).count(Status::Identical);
                continue;
            }
            let mut c = blank(spec, f, Some(r), name, kind);
            let scale = scales.of(ctx, spec, f, r, name);
            let mut test = None;
            (c.status, c.rel_diff) = match kind {
                _ if bit_equal => (Status::Identical, None),
                Kind::Sampled if !ctx.common_draws && va != Value::Null && vb != Value::Null => {
                    (Status::NotTested, None)
                }
                Kind::MonteCarlo if !ctx.common_draws => {
                    let se = |f: &Frame, i: Option<usize>| i.and_then(|i| std_error(mc.expect("mc"), f, i));
                    test = match (va.num(), vb.num(), se(old, i), se(new, j)) {
                        (Some(x), Some(y), Some(sx), Some(sy)) => {
                            c.std_error = Some(sx.hypot(sy));
                            two_sample(x, sx, y, sy)
                        }
                        _ => None,
                    };
                    deterministic(&va, &vb, scale, ctx.opts.rel_tol)
                }
                _ => deterministic(&va, &vb, scale, ctx.opts.rel_tol),
            };
            if bit_equal && kind == Kind::MonteCarlo && !ctx.common_draws {
                // An identical mean is still one of the family's hypotheses (p = 1).
                let se = |f: &Frame, i: Option<usize>| i.and_then(|i| std_error(mc.expect("mc"), f, i));
                test = match (va.num(), se(old, i), se(new, j)) {
                    (Some(x), Some(sx), Some(sy)) => {
                        c.std_error = Some(sx.hypot(sy));
                        two_sample(x, sx, x, sy)
                    }
                    _ => None,
                };
            }
            (c.old, c.new) = (va, vb);
            if let Some((z, p)) = test {
                (c.z, c.p, c.rel_diff) = (Some(z), Some(p), None);
                let keep = c.status != Status::Identical || ctx.opts.keep_identical;
                let column = (spec.name, name.to_string());
                let idx = keep.then(|| {
                    sink.cells.push(c.clone());
                    sink.cells.len() - 1
                });
                sink.pending.push(Pending { p, cell: idx, column });
                continue;
            }
            push(sink, ctx, c);
        }
    }
    for &(i, j) in &rows {
        if spec.absent_is_zero || (i.is_some() && j.is_some()) {
            continue;
        }
        let (f, r) = if let Some(i) = i { (old, i) } else { (new, j.expect("one side")) };
        let mut c = blank(spec, f, Some(r), "(row)", Kind::Presence);
        c.old = if i.is_some() { Value::Text("(row)".into()) } else { Value::Absent };
        c.new = if j.is_some() { Value::Text("(row)".into()) } else { Value::Absent };
        push(sink, ctx, c);
    }
}

/// Counts a finished cell and keeps it unless it is identical (or identical ones are kept).
pub(crate) fn push(sink: &mut Sink, ctx: &Ctx, c: Cell) {
    let s = summary_of(sink, c.table, &c.column, c.kind);
    s.count(c.status);
    if let Some(r) = c.rel_diff.filter(|r| *r > 0.0) {
        s.max_rel_diff = Some(s.max_rel_diff.map_or(r, |m| m.max(r)));
    }
    if let Some(z) = c.z {
        s.max_abs_z = Some(s.max_abs_z.map_or(z.abs(), |m| m.max(z.abs())));
    }
    if c.status != Status::Identical || ctx.opts.keep_identical {
        sink.cells.push(c);
    }
}

pub(crate) fn summary_of<'a>(
    sink: &'a mut Sink,
    table: &'static str,
    column: &str,
    kind: Kind,
) -> &'a mut ColumnSummary {
    let key = (table, column.to_string());
    let i = match sink.index.get(&key) {
        Some(&i) => i,
        None => {
            sink.columns.push(ColumnSummary { table, column: column.to_string(), ..Default::default() });
            sink.index.insert(key, sink.columns.len() - 1);
            sink.columns.len() - 1
        }
    };
    let s = &mut sink.columns[i];
    // A column that is a Presence cell in one place keeps its own kind when it has one.
    if s.kind.is_none() || s.kind == Some(Kind::Presence) {
        s.kind = Some(kind);
    }
    s
}
