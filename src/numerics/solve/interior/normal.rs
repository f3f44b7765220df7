//! The program's data by rows and the normal matrix Aᵀ W⁻¹ W⁻ᵀ A of [`super`]: its pattern, and its
//! values from the cones' scalings.

use clarabel::solver::SupportedConeT;

use rayon::prelude::*;

use super::cone::{Cone, Kind, SQ2, Scaling};

/// Cones per parallel task (a cone's work is a few microseconds, a task's start a fraction of one),
/// and the fixed runs of `step_to_boundary`.
pub(super) const CONES_PER_TASK: usize = 32;

/// Rows (or columns) of A per parallel task in Ax and Aᵀz.
const ROWS_PER_TASK: usize = 2048;

pub(super) struct Data {
    pub(super) m: usize,
    pub(super) n: usize,
    /// A by rows.
    pub(super) rp: Vec<usize>,
    pub(super) ci: Vec<usize>,
    pub(super) rv: Vec<f64>,
    /// A by columns (for Aᵀz).
    cp: Vec<usize>,
    ri: Vec<usize>,
    cv: Vec<f64>,
    pub(super) cones: Vec<Cone>,
    /// Σ of the cones' degrees (n for PSD(n), 1 for a second-order cone, 1 per nonnegative row).
    pub(super) degree: usize,
    /// The size a [`super::cone::Scratch`] needs: the largest PSD block or second-order cone.
    pub(super) largest: usize,
}

impl Data {
    pub(super) fn new(p: &Program, n: usize) -> Result<Data, String> {
        let m = p.b.len();
        let mut rp = vec![0usize; m + 1];
        for &r in p.rows {
            rp[r + 1] += 1;
        }
        for i in 0..m {
            rp[i + 1] += rp[i];
        }
        let mut at = rp.clone();
        let mut ci = vec![0; p.rows.len()];
        let mut rv = vec![0.0; p.rows.len()];
        for ((&r, &c), &v) in p.rows.iter().zip(p.cols).zip(p.vals) {
            ci[at[r]] = c;
            rv[at[r]] = v;
            at[r] += 1;
        }
        // By columns, each column's entries in row order.
        let mut cp = vec![0usize; n + 1];
        for &c in &ci {
            cp[c + 1] += 1;
        }
        for j in 0..n {
            cp[j + 1] += cp[j];
        }
        let (mut at, mut ri, mut cv) = (cp.clone(), vec![0; ci.len()], vec![0.0; ci.len()]);
        for r in 0..m {
            for k in rp[r]..rp[r + 1] {
                ri[at[ci[k]]] = r;
                cv[at[ci[k]]] = rv[k];
                at[ci[k]] += 1;
            }
        }
        let mut cones = Vec::new();
        let (mut off, mut degree) = (0, 0);
        for cone in p.cones {
            let (kind, dim, deg) = match *cone {
                SupportedConeT::NonnegativeConeT(d) => (Kind::Nonnegative, d, d),
                SupportedConeT::SecondOrderConeT(d) => (Kind::SecondOrder, d, 1),
                SupportedConeT::PSDTriangleConeT(d) => (Kind::Psd(d), d * (d + 1) / 2, d),
                ref other => return Err(format!("the own solver has no {other:?}")),
            };
            let mut coefs: Vec<(usize, Vec<(usize, usize, f64)>)> = Vec::new();
            if let Kind::Psd(d) = kind {
                let mut k = off;
                for j in 0..d {
                    for i in 0..=j {
                        for e in rp[k]..rp[k + 1] {
                            let a = if i == j { rv[e] } else { rv[e] / SQ2 };
                            match coefs.iter_mut().find(|(v, _)| *v == ci[e]) {
                                Some((_, l)) => l.push((i, j, a)),
                                None => coefs.push((ci[e], vec![(i, j, a)])),
                            }
                        }
                        k += 1;
                    }
                }
                coefs.sort_by_key(|(v, _)| *v);
            }
            cones.push(Cone { kind, rows: off..off + dim, coefs });
            off += dim;
            degree += deg;
        }
        let largest = cones
            .iter()
            .map(|c| match c.kind {
                Kind::Psd(k) => k,
                Kind::SecondOrder => c.rows.len(),
                Kind::Nonnegative => 0,
            })
            .max()
            .unwrap_or(0)
            .max(3);
        Ok(Data { m, n, rp, ci, rv, cp, ri, cv, cones, degree, largest })
    }

    /// Ax, rows in parallel (each row's sum in its own order).
    pub(super) fn ax(&self, x: &[f64], out: &mut [f64]) {
        out.par_iter_mut().enumerate().with_min_len(ROWS_PER_TASK).for_each(|(r, o)| {
            *o = (self.rp[r]..self.rp[r + 1]).map(|k| self.rv[k] * x[self.ci[k]]).sum();
        });
    }

    /// Aᵀz, columns in parallel from A by columns, each summed in row order: the same bits as
    /// scattering the rows in order.
    pub(super) fn atz(&self, z: &[f64], out: &mut [f64]) {
        out.par_iter_mut().enumerate().with_min_len(ROWS_PER_TASK).for_each(|(c, o)| {
            *o = (self.cp[c]..self.cp[c + 1]).fold(0.0, |acc, k| acc + self.cv[k] * z[self.ri[k]]);
        });
    }

    /// The variables each cone touches, for the normal matrix's pattern.
    pub(super) fn vars_of(&self, cone: &Cone) -> Vec<usize> {
        let mut v: Vec<usize> =
            cone.rows.clone().flat_map(|r| self.ci[self.rp[r]..self.rp[r + 1]].iter().copied()).collect();
        v.sort_unstable();
        v.dedup();
        v
    }
}

/// The normal matrix Aᵀ W⁻¹ W⁻ᵀ A: its upper triangle's pattern in CSC.
pub(super) struct Normal {
    pub(super) colptr: Vec<usize>,
    pub(super) rowval: Vec<usize>,
    /// Per cone, the entries of H its terms add to, in the order `assemble` visits them.
    pub(super) slots: Vec<Vec<usize>>,
    /// The same map read the other way (CSR over H's entries): entry k is the sum of the terms
    /// `sources[from[k]..from[k + 1]]`, listed in term order, that is cone after cone.
    from: Vec<usize>,
    sources: Vec<usize>,
}

impl Normal {
    pub(super) fn new(d: &Data) -> Normal {
        let mut sets: Vec<Vec<usize>> = (0..d.n).map(|j| vec![j]).collect();
        for cone in &d.cones {
            let groups: Vec<Vec<usize>> = match cone.kind {
                Kind::Nonnegative => cone.rows.clone().map(|r| d.ci[d.rp[r]..d.rp[r + 1]].to_vec()).collect(),
                _ => vec![d.vars_of(cone)],
            };
            for vs in groups {
                for &a in &vs {
                    for &b in &vs {
                        if a <= b {
                            sets[b].push(a);
                        }
                    }
                }
            }
        }
        let (mut colptr, mut rowval) = (vec![0], Vec::new());
        for set in sets.iter_mut() {
            set.sort_unstable();
            set.dedup();
            rowval.extend_from_slice(set);
            colptr.push(rowval.len());
        }
        let mut normal = Normal { colptr, rowval, slots: Vec::new(), from: Vec::new(), sources: Vec::new() };
        normal.slots = d.cones.iter().map(|c| normal.visit(d, c)).collect();
        let mut from = vec![0usize; normal.rowval.len() + 1];
        for &k in normal.slots.iter().flatten() {
            from[k + 1] += 1;
        }
        for k in 0..normal.rowval.len() {
            from[k + 1] += from[k];
        }
        let mut next = from.clone();
        let mut sources = vec![0; normal.terms()];
        for (t, &k) in normal.slots.iter().flatten().enumerate() {
            sources[next[k]] = t;
            next[k] += 1;
        }
        (normal.from, normal.sources) = (from, sources);
        normal
    }

    /// The entries of H one cone adds to, in `assemble`'s order.
    pub(super) fn visit(&self, d: &Data, cone: &Cone) -> Vec<usize> {
        let mut out = Vec::new();
        let mut pair = |r1: usize, r2: usize| {
            for k1 in d.rp[r1]..d.rp[r1 + 1] {
                for k2 in d.rp[r2]..d.rp[r2 + 1] {
                    if d.ci[k1] <= d.ci[k2] {
                        out.push(self.at(d.ci[k1], d.ci[k2]));
                    }
                }
            }
        };
        match cone.kind {
            Kind::Nonnegative => cone.rows.clone().for_each(|r| pair(r, r)),
            Kind::SecondOrder => {
                for ra in cone.rows.clone() {
                    for rb in cone.rows.clone() {
                        pair(ra, rb);
                    }
                }
            }
            Kind::Psd(_) => {
                for (jj, (vj, _)) in cone.coefs.iter().enumerate() {
                    for (vi, _) in &cone.coefs[..=jj] {
                        out.push(self.at(*vi, *vj));
                    }
                }
            }
        }
        out
    }

    pub(super) fn at(&self, i: usize, j: usize) -> usize {
        let (i, j) = if i <= j { (i, j) } else { (j, i) };
        let col = &self.rowval[self.colptr[j]..self.colptr[j + 1]];
        self.colptr[j] + col.binary_search(&i).expect("in the pattern")
    }

    /// H = Σ_cones A_cᵀ W_c⁻¹ W_c⁻ᵀ A_c. The cones' terms are formed in parallel into `terms` (one
    /// slice per cone, as long as its slots); each entry of H then sums its own terms in cone order,
    /// also in parallel, so the sums do not depend on the thread count (and are the bits of adding
    /// the cones' terms into H one cone after the other).
    pub(super) fn assemble(&self, d: &Data, sc: &[Scaling], terms: &mut [f64], vals: &mut [f64]) {
        let mut parts = split_mut(terms, self.slots.iter().map(Vec::len));
        d.cones
            .par_iter()
            .zip(sc)
            .zip(parts.par_iter_mut())
            .with_min_len(CONES_PER_TASK)
            .for_each(|((cone, s), out)| cone_terms(d, cone, s, out));
        drop(parts);
        let terms = &*terms;
        vals.par_iter_mut().enumerate().with_min_len(ROWS_PER_TASK).for_each(|(k, v)| {
            let mut acc = 0.0;
            for &t in &self.sources[self.from[k]..self.from[k + 1]] {
                acc += terms[t];
            }
            *v = acc;
        });
    }

    /// The length of `assemble`'s `terms`.
    pub(super) fn terms(&self) -> usize {
        self.slots.iter().map(Vec::len).sum()
    }
}

/// One cone's terms of A_cᵀ W_c⁻¹ W_c⁻ᵀ A_c, in [`Normal::visit`]'s order; for a PSD cone
/// H_ij = tr(A_i M A_j M), M = R⁻ᵀR⁻¹, from each coefficient matrix's nonzeros.
fn cone_terms(d: &Data, cone: &Cone, s: &Scaling, out: &mut [f64]) {
    let mut slot = out.iter_mut();
    let mut add = |v: f64| *slot.next().expect("visited in the same order") = v;
    let mut pair = |r1: usize, r2: usize, f: f64| {
        for k1 in d.rp[r1]..d.rp[r1 + 1] {
            for k2 in d.rp[r2]..d.rp[r2 + 1] {
                if d.ci[k1] <= d.ci[k2] {
                    add(f * d.rv[k1] * d.rv[k2]);
                }
            }
        }
    };
    match s {
        Scaling::Nonnegative(w) => {
            for (i, r) in cone.rows.clone().enumerate() {
                pair(r, r, 1.0 / (w[i] * w[i]));
            }
        }
        Scaling::SecondOrder(winv) => {
            // W⁻² by plain sums, not a dynamic product (whose kernel nalgebra picks by processor).
            let k = winv.nrows();
            for (a, ra) in cone.rows.clone().enumerate() {
                for (b, rb) in cone.rows.clone().enumerate() {
                    pair(ra, rb, (0..k).map(|c| winv[(a, c)] * winv[(c, b)]).sum());
                }
            }
        }
        Scaling::Psd { m: mm, .. } => {
            // tr(A_i M A_j M) entry by entry: with A = Σ a E_rs over the symmetric pairs
            // (r, s) of its nonzeros, tr(E_rs M E_tu M) = M_st M_ur — the products of
            // the two matrices' few nonzeros, never a dense M A_j M.
            let n = mm.nrows();
            let m = mm.as_slice();
            let at = |i: usize, j: usize| m[i + j * n];
            for (jj, (_, ej)) in cone.coefs.iter().enumerate() {
                for (_, ei) in &cone.coefs[..=jj] {
                    let mut acc = 0.0;
                    for &(r, s, a) in ei {
                        for &(t, u, b) in ej {
                            // Σ over (r,s),(s,r) and (t,u),(u,t), once for a diagonal entry.
                            let mut v = at(s, t) * at(u, r);
                            if t != u {
                                v += at(s, u) * at(t, r);
                            }
                            if r != s {
                                v += at(r, t) * at(u, s);
                                if t != u {
                                    v += at(r, u) * at(t, s);
                                }
                            }
                            acc += a * b * v;
                        }
                    }
                    add(acc);
                }
            }
        }
    }
}

/// Consecutive parts of v of the given lengths, for per-cone work in parallel.
pub(super) fn split_mut(v: &mut [f64], lens: impl Iterator<Item = usize>) -> Vec<&mut [f64]> {
    let mut rest = v;
    let mut out = Vec::new();
    for len in lens {
        let (head, tail) = std::mem::take(&mut rest).split_at_mut(len);
        out.push(head);
        rest = tail;
    }
    out
}

/// The program as `Conic` holds it: triplets of A, b and the cones in row order.
pub(crate) struct Program<'a> {
    pub rows: &'a [usize],
    pub cols: &'a [usize],
    pub vals: &'a [f64],
    pub b: &'a [f64],
    pub cones: &'a [SupportedConeT<f64>],
}
