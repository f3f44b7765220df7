//! A small filter's whole step as one product (docs/architecture.md, "One product per filter and
//! step"): its next state and its output from the state, the input and the known input,
//!
//! ```text
//! [ s[k+1] ]   [ Af  Bf  Gf ] [ s ]        [ ε[k+1] ]   [ F  E  R ] [ ε ]
//! [ ẑ[k]   ] = [ Cf  Df  0  ] [ y ]   or   [ e[k]   ] = [ H  G  0 ] [ w ]
//!                             [ r ]                                 [ r ]
//! ```
//!
//! (the filter (docs/math.md §6), or its error form ε = s − M x, e = z − ẑ
//! ([`crate::analysis::exact::error_form`])). A filter in error coordinates whose NIS is reported
//! gets three more blocks of rows, its innovation ν = y − C x̂ = D w − C ε whitened by the step's NIS
//! weight W = L Lᵀ: Lᵀν = [−LᵀC, LᵀD, 0] (ε, w, r), whose squared norm is νᵀWν, so the NIS costs a
//! few more rows of the one product instead of two products, a difference and a quadratic form of
//! its own. Each step's matrices, per mode of the plant, sit in
//! one contiguous buffer instead of five matrices of their own, and a block whose lanes are in
//! different modes applies to each lane its own mode's entry instead of one product per mode: each
//! lane's sum is then the one a block of lanes all in its mode computes, term by term in the same
//! order (entries zero in its mode skipped), so a lane's result never depends on the other lanes'
//! modes.

use std::ops::Range;
use std::sync::Arc;

use crate::analysis::exact::ErrorForm;
use crate::filter::realization::Realization;
use crate::model::plant::Plant;
use crate::numerics::linalg::Mat;
use crate::sim::lanes::{self, LANES, Row};

/// One filter's stacked step matrices over the horizon (module docs).
pub struct Stacked {
    /// State rows (the first `ns` of a block), then the output's (`nz`), then the whitened
    /// innovation's (none without it).
    ns: usize,
    nz: usize,
    rows: usize,
    /// Columns: the state's, the input's (w in error coordinates, y otherwise), the known input's.
    cols: [usize; 3],
    modes: usize,
    /// Column-major blocks, `modes` of them at a step whose modes differ, else one.
    data: Vec<f64>,
    /// Per step: the offset of its first block, and whether it has one per mode. Consecutive steps
    /// with the same bits share their blocks (a long horizon's converged gains are stored once).
    steps: Vec<(usize, bool)>,
}

impl Stacked {
    /// The stacked steps of `real`, in error coordinates when `form` is given; None when one of its
    /// matrices is large enough for the blocked product of `lanes::gemm`, whose order of summation
    /// this one would not reproduce (the engine then applies the five matrices one by one). With
    /// `nis` (the filter's NIS weights per step) and a form, the whitened innovation's rows follow
    /// (module docs), unless a weight has no Cholesky factor.
    pub fn new(
        plant: &Plant,
        real: &Realization,
        form: Option<&ErrorForm>,
        nis: Option<&[Option<Arc<Mat>>]>,
    ) -> Option<Self> {
        let modes = plant.n_modes();
        let parts = |k: usize, m: usize| -> [&Mat; 5] {
            match form {
                Some(fm) => {
                    let a = &fm.steps[k][m];
                    [&a.f, &a.e, &a.r_map, &a.h, &a.g]
                }
                None => {
                    let g = real.gains(k, m);
                    [&g.af, &g.bf, &g.gf, &g.cf, &g.df]
                }
            }
        };
        let first = parts(0, 0);
        let (ns, nz) = (first[0].nrows(), first[3].nrows());
        let cols = [first[0].ncols(), first[1].ncols(), first[2].ncols()];
        let white = form.and(nis).and_then(|w| whiteners(plant, cols, w));
        let nu = white.as_ref().map_or(0, |w| w.nu);
        let rows = ns + nz + nu;
        let size = rows * cols.iter().sum::<usize>();
        let mut data = Vec::new();
        let mut steps: Vec<(usize, bool)> = Vec::with_capacity(plant.steps());
        let mut here = vec![0.0; size * modes];
        for k in 0..plant.steps() {
            for m in 0..modes {
                let p = parts(k, m);
                if p.iter().any(|a| a.len() >= lanes::BLOCKED_MIN_ENTRIES)
                    || p[..3].iter().zip(&cols).any(|(a, &c)| a.shape() != (ns, c))
                    || p[3..].iter().zip(&cols).any(|(a, &c)| a.shape() != (nz, c))
                {
                    return None;
                }
                let block = &mut here[m * size..(m + 1) * size];
                block.fill(0.0);
                let mut j0 = 0;
                for (c, (top, bottom)) in cols.iter().zip([(p[0], Some(p[3])), (p[1], Some(p[4])), (p[2], None)]) {
                    for j in 0..*c {
                        let col = &mut block[(j0 + j) * rows..(j0 + j + 1) * rows];
                        for (d, v) in col[..ns].iter_mut().zip(top.column(j).iter()) {
                            *d = *v;
                        }
                        if let Some(b) = bottom {
                            for (d, v) in col[ns..].iter_mut().zip(b.column(j).iter()) {
                                *d = *v;
                            }
                        }
                    }
                    j0 += c;
                }
                if let Some(w) = &white {
                    w.write(k, rows, ns + nz, block);
                }
            }
            let same_bits = |a: &[f64], b: &[f64]| a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits());
            let per_mode = (1..modes).any(|m| !same_bits(&here[..size], &here[m * size..(m + 1) * size]));
            let stored = if per_mode { &here[..] } else { &here[..size] };
            let reuse =
                steps.last().filter(|&&(off, pm)| pm == per_mode && same_bits(&data[off..off + stored.len()], stored));
            let entry = match reuse {
                Some(&e) => e,
                None => {
                    data.extend_from_slice(stored);
                    (data.len() - stored.len(), per_mode)
                }
            };
            steps.push(entry);
        }
        Some(Stacked { ns, nz, rows, cols, modes, data, steps })
    }

    /// Rows of the state part; the output's follow up to [`Stacked::rows`].
    pub(crate) fn ns(&self) -> usize {
        self.ns
    }

    pub(crate) fn rows(&self) -> usize {
        self.rows
    }

    /// The output's rows (e in error coordinates, ẑ otherwise).
    pub(crate) fn output(&self) -> Range<usize> {
        self.ns..self.ns + self.nz
    }

    /// The whitened innovation's rows, if the product computes it (zero at a step without a NIS
    /// weight).
    pub(crate) fn whitened(&self) -> Option<Range<usize>> {
        (self.rows > self.ns + self.nz).then_some(self.ns + self.nz..self.rows)
    }

    /// Whether the known input enters (the filter may have been built on a model without one).
    pub(crate) fn has_known_input(&self) -> bool {
        self.cols[2] > 0
    }

    /// out ← rows `rows` of step k's stacked matrix times the stacked inputs `segs` (state, input
    /// and, when present at this step, the known input), each lane with its own mode's entries
    /// (`lanes`). One sum per output entry, the columns in order, entries zero in the lane's mode
    /// skipped: term by term what [`lanes::gemm`] computes with the matrices one by one.
    #[inline(always)]
    pub(crate) fn product<const C: usize>(
        &self,
        k: usize,
        rows: Range<usize>,
        segs: &[&[Row]],
        lanes: &ModeLanes,
        out: &mut [Row],
    ) {
        debug_assert!(segs.iter().zip(&self.cols).all(|(s, &c)| s.len() == c) && out.len() == rows.len());
        let (off, per_mode) = self.steps[k];
        let size = self.rows * self.cols.iter().sum::<usize>();
        match (per_mode, lanes.uniform) {
            (false, _) => sums::<C, false>(&self.data[off..off + size], size, self.rows, rows, segs, &[], out),
            (true, Some(m)) => {
                let block = &self.data[off + m * size..off + (m + 1) * size];
                sums::<C, false>(block, size, self.rows, rows, segs, &[], out)
            }
            (true, None) => {
                let blocks = &self.data[off..off + self.modes * size];
                sums::<C, true>(blocks, size, self.rows, rows, segs, &lanes.masks, out)
            }
        }
    }
}

/// Per step, Lᵀ[−C, D] of the whitened innovation Lᵀν (module docs), W = L Lᵀ the step's NIS
/// weight; C and D those the engine's innovation uses, the plant's in its first mode.
struct Whiteners {
    nu: usize,
    /// (−LᵀC, LᵀD) per step, None at a step without a weight.
    rows: Vec<Option<(Mat, Mat)>>,
}

/// The whiteners of a filter in error coordinates with NIS weights `weights`: None where its state
/// does not estimate the plant's (ν = D w − C ε needs ε = s − x) or a weight has no Cholesky factor
/// (the engine then forms ν and νᵀWν itself).
fn whiteners(plant: &Plant, cols: [usize; 3], weights: &[Option<Arc<Mat>>]) -> Option<Whiteners> {
    if cols[0] != plant.nx() || cols[1] != plant.nw() || weights.len() != plant.steps() {
        return None;
    }
    let rows = weights
        .iter()
        .enumerate()
        .map(|(k, w)| match w {
            None => Some(None),
            Some(w) => {
                let lt = w.as_ref().clone().cholesky()?.l().transpose();
                Some(Some((-(&lt * plant.c_of(k, 0).as_ref()), &lt * plant.d_of(k, 0).as_ref())))
            }
        })
        .collect::<Option<Vec<_>>>()?;
    Some(Whiteners { nu: plant.ny(), rows })
}

impl Whiteners {
    /// Writes step k's rows from `first` into a column-major `block` of `nrows` rows (the known
    /// input's columns stay zero).
    fn write(&self, k: usize, nrows: usize, first: usize, block: &mut [f64]) {
        let Some((c, d)) = &self.rows[k] else { return };
        for (j0, m) in [(0, c), (c.ncols(), d)] {
            for j in 0..m.ncols() {
                let col = &mut block[(j0 + j) * nrows + first..(j0 + j) * nrows + first + self.nu];
                for (d, v) in col.iter_mut().zip(m.column(j).iter()) {
                    *d = *v;
                }
            }
        }
    }
}

/// The lanes' modes at the current step, as [`Stacked::product`] reads them.
pub(crate) struct ModeLanes {
    /// The mode of every active lane, when they share one.
    uniform: Option<usize>,
    /// Per mode, all ones in the lanes in it: a lane's entry is picked by bits, not by a branch.
    masks: Vec<[u64; LANES]>,
}

impl ModeLanes {
    pub(crate) fn new(modes: usize) -> Self {
        ModeLanes { uniform: Some(0), masks: vec![[0; LANES]; modes] }
    }

    pub(crate) fn update(&mut self, modes: &[u32; LANES], active: usize) {
        let m0 = modes[0];
        if self.masks.len() == 1 || modes[..active].iter().all(|&m| m == m0) {
            self.uniform = Some(m0 as usize);
            return;
        }
        self.uniform = None;
        for (m, mask) in self.masks.iter_mut().enumerate() {
            for (k, &l) in mask.iter_mut().zip(modes) {
                *k = if l as usize == m { u64::MAX } else { 0 };
            }
        }
    }
}

/// [`Stacked::product`]'s sums: one per output row `i` of `rows`, over the columns of `segs` in
/// order, each column's entry at `at` (column-major, `nrows` rows) times its lanes, skipped where
/// it is zero. With one block for every lane (`MIXED` false) that is `blocks`' entry; where the
/// lanes' modes differ (`MIXED`), an entry equal in every mode's block the same way, and another
/// one per lane, picked from its mode's block by the lane's mask and added only where it is not
/// zero.
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn sums<const C: usize, const MIXED: bool>(
    blocks: &[f64],
    size: usize,
    nrows: usize,
    rows: Range<usize>,
    segs: &[&[Row]],
    masks: &[[u64; LANES]],
    out: &mut [Row],
) {
    let modes = masks.len();
    for c in (0..LANES).step_by(C) {
        for (i, o) in rows.clone().zip(out.iter_mut()) {
            let mut acc = [0.0; C];
            let mut at = i;
            for seg in segs {
                for xj in seg.iter() {
                    let v0 = blocks[at];
                    if !MIXED || (1..modes).all(|m| blocks[m * size + at].to_bits() == v0.to_bits()) {
                        if v0 != 0.0 {
                            lanes::madd(v0, &xj[c..c + C], &mut acc);
                        }
                    } else {
                        // Every lane starts from mode 0's entry; each later mode's mask puts its own in.
                        let mut coef = [v0; C];
                        for (m, mask) in masks.iter().enumerate().skip(1) {
                            let vm = blocks[m * size + at].to_bits();
                            for (q, k) in coef.iter_mut().zip(&mask[c..c + C]) {
                                *q = f64::from_bits((vm & k) | (q.to_bits() & !k));
                            }
                        }
                        let x: &[f64; C] = xj[c..c + C].try_into().expect("C divides LANES");
                        for ((s, q), v) in acc.iter_mut().zip(&coef).zip(x) {
                            let t = *s + q * v;
                            *s = if *q != 0.0 { t } else { *s };
                        }
                    }
                    at += nrows;
                }
            }
            let o: &mut [f64; C] = (&mut o[c..c + C]).try_into().expect("C divides LANES");
            *o = acc;
        }
    }
}
