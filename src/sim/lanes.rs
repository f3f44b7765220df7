//! Trials in lanes: the engine simulates `LANES` trials at once, a vector v of n components as n
//! rows of `LANES` values (row i holds component i of every lane's v: the lanes' vectors are the
//! columns of an n × LANES matrix stored row by row). One step of the plant or a filter is then a
//! few matrix–matrix products M·V whose inner loop runs over contiguous lanes and vectorizes, and
//! each matrix is read once per block instead of once per trial.
//!
//! The kernels here compute M V column by column in exact arithmetic order Σ_j M_ij V_j (j
//! ascending) for small matrices, skipping zero entries (the plant's stacked B = [B 0] and
//! D = [0 D], the string's 2×2 modal blocks in CSR): a lane's result never depends on the other
//! lanes, so any split of trials into blocks gives the same per-trial numbers.

use nalgebra::{DMatrixView, DMatrixViewMut};

use crate::numerics::linalg::Mat;
use crate::numerics::linop::LinOp;

/// Trials per lane block: the unit of simulation, drawing and of the fixed reduction order.
/// Chosen by measurement (`filterbench bench`, docs/architecture.md): 16 and 32 lanes pay the
/// per-matrix overhead of each product more often (5.3–5.5 and 4.4–4.8 µs per trial of Example 2's
/// plant against 4.0–4.4 µs at 64); 128 lanes are no faster (3.9–4.0 µs, within the machine's
/// noise) and double every per-thread buffer.
pub(crate) const LANES: usize = 64;

/// The builds of the lane kernels: drawing and simulation are compiled from the same code for the
/// x86-64 baseline (SSE2), for AVX2 and for AVX-512, and every build gives the same bits (Rust
/// never fuses a·b + c, and no kernel's order depends on the vector width).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord)]
pub enum Build {
    Baseline = 1,
    Avx2 = 2,
    Avx512 = 3,
}

/// Set by [`force_build`]: 0 for the best build the processor has, else a cap on it.
static FORCED: std::sync::atomic::AtomicU8 = std::sync::atomic::AtomicU8::new(0);

/// The best build this processor runs (detected once: the lane kernels ask at every step).
pub fn best_build() -> Build {
    static BEST: std::sync::OnceLock<Build> = std::sync::OnceLock::new();
    *BEST.get_or_init(detect)
}

fn detect() -> Build {
    #[cfg(target_arch = "x86_64")]
    {
        use std::arch::is_x86_feature_detected as has;
        if has!("avx512f") && has!("avx512vl") && has!("avx512dq") && has!("avx512bw") && has!("avx2") {
            return Build::Avx512;
        }
        if has!("avx2") {
            return Build::Avx2;
        }
    }
    Build::Baseline
}

/// The build the lane kernels run now: the best one, unless [`force_build`] capped it.
#[inline]
pub fn build() -> Build {
    let best = best_build();
    match FORCED.load(std::sync::atomic::Ordering::Relaxed) {
        1 => Build::Baseline,
        2 => best.min(Build::Avx2),
        _ => best,
    }
}

/// Caps every later block's build at `cap` (`None`: the best the processor has, the default):
/// for the tests that compare the builds bit for bit, and `bench --build`.
pub fn force_build(cap: Option<Build>) {
    FORCED.store(cap.map_or(0, |b| b as u8), std::sync::atomic::Ordering::Relaxed);
}

/// One component of a vector across the lanes.
pub(crate) type Row = [f64; LANES];

/// A lane vector of `n` components, all zero.
pub fn zeros(n: usize) -> Vec<Row> {
    vec![[0.0; LANES]; n]
}

/// Dense matrices with at least this many entries go through matrixmultiply (blocked, packed);
/// smaller ones through the zero-skipping loop below, which has no packing cost.
pub(crate) const BLOCKED_MIN_ENTRIES: usize = 4096;

/// out ← M x (`add`: out ← out + M x) for a dense M, x with M.ncols() rows.
#[inline(always)]
pub(crate) fn gemm(m: &Mat, x: &[Row], add: bool, out: &mut [Row]) {
    gemm_in::<CHUNK>(m, x, add, out)
}

/// [`gemm`] with `C` lanes per pass: the block loop's AVX-512 build uses [`WIDE_CHUNK`].
#[inline(always)]
pub(crate) fn gemm_in<const C: usize>(m: &Mat, x: &[Row], add: bool, out: &mut [Row]) {
    debug_assert!(x.len() == m.ncols() && out.len() == m.nrows());
    if m.len() >= BLOCKED_MIN_ENTRIES {
        let xs = DMatrixView::from_slice_with_strides(x.as_flattened(), x.len(), LANES, LANES, 1);
        let n = out.len();
        let mut os = DMatrixViewMut::from_slice_with_strides_mut(out.as_flattened_mut(), n, LANES, LANES, 1);
        os.gemm(1.0, m, &xs, if add { 1.0 } else { 0.0 });
        return;
    }
    let (rows, cols) = m.shape();
    let entries = m.as_slice();
    for c in (0..LANES).step_by(C) {
        for (i, o) in out.iter_mut().enumerate() {
            let o: &mut [f64; C] = (&mut o[c..c + C]).try_into().expect("C divides LANES");
            let mut acc = if add { *o } else { [0.0; C] };
            for (j, xj) in x.iter().enumerate().take(cols) {
                // Column-major: entry (i, j) at j·rows + i.
                let a = entries[j * rows + i];
                if a != 0.0 {
                    madd(a, &xj[c..c + C], &mut acc);
                }
            }
            *o = acc;
        }
    }
}

/// Rows per panel of [`gemm_panels`]: a multiple of matrixmultiply's row blocks, small enough that
/// a triangular factor's panels skip nearly half of its columns.
const PANEL: usize = 64;

/// For each panel of [`PANEL`] rows of `m`, how many leading columns hold all of its nonzero entries:
/// computed once per matrix, for [`gemm_panels`].
pub(crate) fn panel_widths(m: &Mat) -> Vec<usize> {
    (0..m.nrows())
        .step_by(PANEL)
        .map(|r0| {
            let rows = m.rows(r0, PANEL.min(m.nrows() - r0));
            (0..m.ncols()).rev().find(|&j| rows.column(j).iter().any(|v| *v != 0.0)).map_or(0, |j| j + 1)
        })
        .collect()
}

/// out ← M x for a large dense M, panel by panel of rows, each over its first `widths[p]` columns
/// only ([`panel_widths`]): a lower-triangular factor (the Cholesky factor of a joint input's
/// covariance over the horizon) costs half a full product. The columns skipped hold only zeros,
/// whose products would add exact zeros to each sum.
pub(crate) fn gemm_panels(m: &Mat, widths: &[usize], x: &[Row], out: &mut [Row]) {
    debug_assert!(x.len() == m.ncols() && out.len() == m.nrows());
    for (p, &w) in widths.iter().enumerate() {
        let r0 = p * PANEL;
        let rows = PANEL.min(m.nrows() - r0);
        let o = &mut out[r0..r0 + rows];
        if w == 0 {
            o.fill([0.0; LANES]);
            continue;
        }
        let xs = DMatrixView::from_slice_with_strides(x[..w].as_flattened(), w, LANES, LANES, 1);
        let mut os = DMatrixViewMut::from_slice_with_strides_mut(o.as_flattened_mut(), rows, LANES, LANES, 1);
        os.gemm(1.0, &m.view((r0, 0), (rows, w)), &xs, 0.0);
    }
}

/// Lanes per pass of [`gemm`] and [`apply`]: an out row's chunk stays in registers (eight AVX2
/// registers) while it sums M_ij x_j over j, instead of being loaded and stored once per entry.
/// The sum is the same in the same order, so chunking changes no bit.
pub(crate) const CHUNK: usize = 32;

/// Lanes per pass in the AVX-512 build: a whole row in eight of its 32 registers, so each matrix
/// entry is read once per block (measured about 7 % faster per trial than [`CHUNK`] there, and
/// slower in the AVX2 and baseline builds, which have 16 registers).
pub(crate) const WIDE_CHUNK: usize = LANES;

/// acc ← acc + a·x over one chunk of lanes.
#[inline(always)]
pub(crate) fn madd<const C: usize>(a: f64, x: &[f64], acc: &mut [f64; C]) {
    let x: &[f64; C] = x.try_into().expect("a whole chunk");
    for (o, v) in acc.iter_mut().zip(x) {
        *o += a * v;
    }
}

/// out ← out + a·x over the lanes.
#[inline(always)]
pub(crate) fn axpy(a: f64, x: &Row, out: &mut Row) {
    for (o, v) in out.iter_mut().zip(x) {
        *o += a * v;
    }
}

/// out ← M x (`add`: out + M x) for a plant operator, dense or CSR.
#[inline(always)]
pub fn apply(op: &LinOp, x: &[Row], add: bool, out: &mut [Row]) {
    apply_in::<CHUNK>(op, x, add, out)
}

/// [`apply`] with `C` lanes per pass ([`gemm_in`]).
#[inline(always)]
pub(crate) fn apply_in<const C: usize>(op: &LinOp, x: &[Row], add: bool, out: &mut [Row]) {
    match op {
        LinOp::Dense(m) => gemm_in::<C>(m, x, add, out),
        LinOp::Sparse(m) => {
            let (offsets, cols, vals) = m.csr_data();
            for c in (0..LANES).step_by(C) {
                for (i, o) in out.iter_mut().enumerate() {
                    let o: &mut [f64; C] = (&mut o[c..c + C]).try_into().expect("C divides LANES");
                    let mut acc = if add { *o } else { [0.0; C] };
                    for p in offsets[i]..offsets[i + 1] {
                        madd(vals[p], &x[cols[p]][c..c + C], &mut acc);
                    }
                    *o = acc;
                }
            }
        }
    }
}

/// out ← out + c ⊙ t row by row: a per-lane coefficient (a multiplicative factor's ζ_i(k)).
#[inline(always)]
pub(crate) fn add_scaled(c: &Row, t: &[Row], out: &mut [Row]) {
    for (o, r) in out.iter_mut().zip(t) {
        for ((o, v), c) in o.iter_mut().zip(r).zip(c) {
            *o += c * v;
        }
    }
}

/// out ← out + α v in every lane (a known input r\[k], a mean).
#[inline(always)]
pub(crate) fn add_vector(alpha: f64, v: &[f64], out: &mut [Row]) {
    for (o, &a) in out.iter_mut().zip(v) {
        for x in o.iter_mut() {
            *x += alpha * a;
        }
    }
}

/// out ← out − t.
#[inline(always)]
pub(crate) fn subtract(t: &[Row], out: &mut [Row]) {
    for (o, t) in out.iter_mut().zip(t) {
        for (o, v) in o.iter_mut().zip(t) {
            *o -= v;
        }
    }
}

/// out ← a − b.
#[inline(always)]
pub fn difference(a: &[Row], b: &[Row], out: &mut [Row]) {
    for ((o, a), b) in out.iter_mut().zip(a).zip(b) {
        for ((o, a), b) in o.iter_mut().zip(a).zip(b) {
            *o = a - b;
        }
    }
}

/// Where lane l is in mode `mode`, out ← t (`add`: out + t): assembles M_θ V from the product
/// with each mode's matrix when the lanes' modes differ.
#[inline(always)]
pub(crate) fn select(modes: &[u32; LANES], mode: u32, t: &[Row], add: bool, out: &mut [Row]) {
    // A mask of the lanes' own width: the choice by a u32 beside f64 lanes compiled to a branch
    // per lane, which the modes (random per lane) mispredict.
    let mut keep = [0u64; LANES];
    for (k, m) in keep.iter_mut().zip(modes) {
        *k = if *m == mode { u64::MAX } else { 0 };
    }
    for (o, r) in out.iter_mut().zip(t) {
        for ((o, v), k) in o.iter_mut().zip(r).zip(&keep) {
            let new = if add { *o + v } else { *v };
            *o = f64::from_bits((new.to_bits() & k) | (o.to_bits() & !k));
        }
    }
}

/// |e|² per lane, each chunk of lanes summed in registers (rows in order: the same bits as row
/// after row over the whole block).
#[inline(always)]
pub(crate) fn squared_norm(e: &[Row], out: &mut Row) {
    squared_norm_in::<CHUNK>(e, out)
}

/// [`squared_norm`] with `C` lanes per pass ([`gemm_in`]).
#[inline(always)]
pub(crate) fn squared_norm_in<const C: usize>(e: &[Row], out: &mut Row) {
    for c in (0..LANES).step_by(C) {
        let mut acc = [0.0; C];
        for r in e {
            let r: &[f64; C] = r[c..c + C].try_into().expect("C divides LANES");
            for (o, v) in acc.iter_mut().zip(r) {
                *o += v * v;
            }
        }
        out[c..c + C].copy_from_slice(&acc);
    }
}

/// eᵀ W e per lane (NEES and the per-trial ellipsoid checks): Σ_j (W_jj e_j² + Σ_{i<j} (W_ij + W_ji)
/// e_i e_j) with j outer and i inner — the form's own symmetric part, n(n+1)/2 terms instead of n² —
/// each chunk of lanes summed in registers (the same order, so the same bits, in every build).
#[inline(always)]
pub fn quadratic(w: &Mat, e: &[Row], out: &mut Row) {
    quadratic_in::<CHUNK>(w, e, out)
}

/// [`quadratic`] with `C` lanes per pass ([`gemm_in`]).
#[inline(always)]
pub(crate) fn quadratic_in<const C: usize>(w: &Mat, e: &[Row], out: &mut Row) {
    for c in (0..LANES).step_by(C) {
        let mut acc = [0.0; C];
        for (j, ej) in e.iter().enumerate() {
            let ej: &[f64; C] = ej[c..c + C].try_into().expect("C divides LANES");
            for (i, ei) in e.iter().enumerate().take(j + 1) {
                let a = if i == j { w[(j, j)] } else { w[(i, j)] + w[(j, i)] };
                if a != 0.0 {
                    let ei: &[f64; C] = ei[c..c + C].try_into().expect("C divides LANES");
                    for ((o, x), y) in acc.iter_mut().zip(ei).zip(ej) {
                        *o += x * a * y;
                    }
                }
            }
        }
        out[c..c + C].copy_from_slice(&acc);
    }
}
