//! Matrices affine in the decision variables, c + Σ_k x_k M_k, for writing LMIs block by block as
//! they are printed (seed 003 (4.42)–(4.43)) and handing them to `Conic::psd`.

use std::collections::BTreeMap;

use super::conic::Conic;
use crate::numerics::linalg::{Mat, sym_unit, unit};

/// Hands out consecutive variable indices.
#[derive(Default)]
pub(crate) struct Vars {
    pub count: usize,
}

impl Vars {
    pub fn scalar(&mut self) -> usize {
        self.count += 1;
        self.count - 1
    }
    /// A symmetric d×d matrix variable (d(d+1)/2 scalars).
    pub fn symmetric(&mut self, d: usize) -> AffMat {
        let mut m = AffMat::zeros(d, d);
        for j in 0..d {
            for i in 0..=j {
                m.terms.insert(self.scalar(), sym_unit(d, i, j));
            }
        }
        m
    }
    /// A full r×c matrix variable, or its lower triangle only (the rest fixed at zero).
    pub fn matrix(&mut self, r: usize, c: usize, lower_only: bool) -> AffMat {
        let mut m = AffMat::zeros(r, c);
        for j in 0..c {
            for i in 0..r {
                if lower_only && i < j {
                    continue;
                }
                m.terms.insert(self.scalar(), unit(r, c, i, j));
            }
        }
        m
    }
}

/// c + Σ_k x_k M_k.
#[derive(Clone, Debug)]
pub(crate) struct AffMat {
    pub c: Mat,
    pub terms: BTreeMap<usize, Mat>,
}

impl AffMat {
    pub fn zeros(r: usize, c: usize) -> Self {
        AffMat { c: Mat::zeros(r, c), terms: BTreeMap::new() }
    }
    pub fn constant(c: Mat) -> Self {
        AffMat { c, terms: BTreeMap::new() }
    }
    /// x · M for one scalar variable x.
    pub(crate) fn scalar_times(var: usize, m: Mat) -> Self {
        let mut a = AffMat::zeros(m.nrows(), m.ncols());
        a.terms.insert(var, m);
        a
    }
    pub fn shape(&self) -> (usize, usize) {
        self.c.shape()
    }
    fn map(&self, f: impl Fn(&Mat) -> Mat) -> Self {
        AffMat { c: f(&self.c), terms: self.terms.iter().map(|(k, m)| (*k, f(m))).collect() }
    }
    /// self · R.
    pub(crate) fn rmul(&self, r: &Mat) -> Self {
        self.map(|m| m * r)
    }
    pub fn scale(&self, s: f64) -> Self {
        self.map(|m| m * s)
    }
    pub fn transpose(&self) -> Self {
        self.map(|m| m.transpose())
    }
    pub fn add(&self, o: &AffMat) -> Self {
        let mut out = self.clone();
        out.c += &o.c;
        for (k, m) in &o.terms {
            match out.terms.get_mut(k) {
                Some(x) => *x += m,
                None => {
                    out.terms.insert(*k, m.clone());
                }
            }
        }
        out
    }
    pub fn sub(&self, o: &AffMat) -> Self {
        self.add(&o.scale(-1.0))
    }
    /// The diagonal part (for the determinant bound [[Ψ, Z], [Zᵀ, Diag Z]]).
    pub(crate) fn diagonal(&self) -> Self {
        self.map(|m| Mat::from_diagonal(&m.diagonal()))
    }

    /// The symmetric block matrix whose lower blocks are `lower[i][j]` (j ≤ i; None is zero) with
    /// diagonal block sizes `sizes`; the upper blocks are the transposes.
    pub(crate) fn symmetric_blocks(sizes: &[usize], lower: &[Vec<Option<AffMat>>]) -> Self {
        let offs: Vec<usize> = sizes.iter().scan(0, |o, s| Some(std::mem::replace(o, *o + s))).collect();
        let d: usize = sizes.iter().sum();
        let mut out = AffMat::zeros(d, d);
        let place = |m: &Mat, out: &mut Mat, i: usize, j: usize| {
            out.view_mut((offs[i], offs[j]), (sizes[i], sizes[j])).copy_from(m);
            if i != j {
                out.view_mut((offs[j], offs[i]), (sizes[j], sizes[i])).copy_from(&m.transpose());
            }
        };
        for (i, row) in lower.iter().enumerate() {
            for (j, blk) in row.iter().enumerate().take(i + 1) {
                let Some(b) = blk else { continue };
                assert_eq!(b.shape(), (sizes[i], sizes[j]), "block ({i}, {j}) has the wrong size");
                place(&b.c, &mut out.c, i, j);
                for (k, m) in &b.terms {
                    let t = out.terms.entry(*k).or_insert_with(|| Mat::zeros(d, d));
                    place(m, t, i, j);
                }
            }
        }
        out
    }

    /// Adds self ⪰ 0 to the program.
    pub(crate) fn psd_into(&self, conic: &mut Conic) {
        let terms: Vec<(usize, Mat)> = self.terms.iter().map(|(k, m)| (*k, m.clone())).collect();
        conic.psd(&self.c, &terms);
    }

    /// The value at the solution x.
    pub fn value(&self, x: &[f64]) -> Mat {
        let mut v = self.c.clone();
        for (k, m) in &self.terms {
            v += m * x[*k];
        }
        v
    }

    /// [l r].
    pub(crate) fn hstack(l: &AffMat, r: &AffMat) -> AffMat {
        let (rows, c1) = l.shape();
        let c2 = r.shape().1;
        let place = |x: &Mat, y: &Mat| {
            let mut m = Mat::zeros(rows, c1 + c2);
            m.view_mut((0, 0), (rows, c1)).copy_from(x);
            m.view_mut((0, c1), (rows, c2)).copy_from(y);
            m
        };
        Self::combine(l, r, place, (rows, c1), (rows, c2))
    }

    /// [t; b].
    pub(crate) fn vstack(t: &AffMat, b: &AffMat) -> AffMat {
        let (r1, cols) = t.shape();
        let r2 = b.shape().0;
        let place = |x: &Mat, y: &Mat| {
            let mut m = Mat::zeros(r1 + r2, cols);
            m.view_mut((0, 0), (r1, cols)).copy_from(x);
            m.view_mut((r1, 0), (r2, cols)).copy_from(y);
            m
        };
        Self::combine(t, b, place, (r1, cols), (r2, cols))
    }

    fn combine(
        x: &AffMat,
        y: &AffMat,
        place: impl Fn(&Mat, &Mat) -> Mat,
        sx: (usize, usize),
        sy: (usize, usize),
    ) -> AffMat {
        let zx = Mat::zeros(sx.0, sx.1);
        let zy = Mat::zeros(sy.0, sy.1);
        let mut out = AffMat::constant(place(&x.c, &y.c));
        let keys: std::collections::BTreeSet<usize> = x.terms.keys().chain(y.terms.keys()).copied().collect();
        for k in keys {
            out.terms.insert(k, place(x.terms.get(&k).unwrap_or(&zx), y.terms.get(&k).unwrap_or(&zy)));
        }
        out
    }
}
