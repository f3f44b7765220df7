//! Double-double arithmetic (a value is hi + lo, |lo| ≤ ulp(hi)/2: about 106 bits, unit roundoff
//! ≈ 2⁻¹⁰⁴ ≈ 5e-32; Dekker 1971, Hida–Li–Bailey 2001), enough for an independent check of the
//! Galerkin filter's Kalman recursion in f64: the same recursion carried with 32 digits, its
//! Cholesky solve included, so that its rounding is ~10¹⁶ times smaller than f64's.

use filterbench::numerics::linalg::Mat;

#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Dd {
    pub hi: f64,
    pub lo: f64,
}

fn two_sum(a: f64, b: f64) -> (f64, f64) {
    let s = a + b;
    let bb = s - a;
    (s, (a - (s - bb)) + (b - bb))
}

fn quick_two_sum(a: f64, b: f64) -> Dd {
    let s = a + b;
    Dd { hi: s, lo: b - (s - a) }
}

impl Dd {
    pub fn from(x: f64) -> Self {
        Dd { hi: x, lo: 0.0 }
    }
    pub fn add(self, b: Dd) -> Dd {
        let (s, e) = two_sum(self.hi, b.hi);
        let (t, f) = two_sum(self.lo, b.lo);
        let r = quick_two_sum(s, e + t);
        quick_two_sum(r.hi, r.lo + f)
    }
    pub fn neg(self) -> Dd {
        Dd { hi: -self.hi, lo: -self.lo }
    }
    pub fn sub(self, b: Dd) -> Dd {
        self.add(b.neg())
    }
    pub fn mul(self, b: Dd) -> Dd {
        let p = self.hi * b.hi;
        let e = self.hi.mul_add(b.hi, -p);
        quick_two_sum(p, e + (self.hi * b.lo + self.lo * b.hi))
    }
    pub fn div(self, b: Dd) -> Dd {
        let q1 = self.hi / b.hi;
        let r = self.sub(b.mul(Dd::from(q1)));
        let q2 = r.hi / b.hi;
        let r = r.sub(b.mul(Dd::from(q2)));
        let q3 = r.hi / b.hi;
        let q = quick_two_sum(q1, q2);
        q.add(Dd::from(q3))
    }
    pub fn sqrt(self) -> Dd {
        let x = self.hi.sqrt();
        let xx = Dd::from(x).mul(Dd::from(x));
        Dd::from(x).add(self.sub(xx).div(Dd::from(2.0 * x)))
    }
    pub fn to_f64(self) -> f64 {
        self.hi + self.lo
    }
}

/// A dense row-major double-double matrix.
#[derive(Clone, Debug)]
pub struct DMat {
    pub r: usize,
    pub c: usize,
    v: Vec<Dd>,
}

impl DMat {
    pub fn zeros(r: usize, c: usize) -> Self {
        DMat { r, c, v: vec![Dd::default(); r * c] }
    }
    pub fn from(m: &Mat) -> Self {
        let mut out = DMat::zeros(m.nrows(), m.ncols());
        for i in 0..m.nrows() {
            for j in 0..m.ncols() {
                out.v[i * out.c + j] = Dd::from(m[(i, j)]);
            }
        }
        out
    }
    pub fn to_mat(&self) -> Mat {
        Mat::from_fn(self.r, self.c, |i, j| self.at(i, j).to_f64())
    }
    pub fn at(&self, i: usize, j: usize) -> Dd {
        self.v[i * self.c + j]
    }
    fn set(&mut self, i: usize, j: usize, x: Dd) {
        self.v[i * self.c + j] = x;
    }
    pub fn t(&self) -> DMat {
        let mut out = DMat::zeros(self.c, self.r);
        for i in 0..self.r {
            for j in 0..self.c {
                out.set(j, i, self.at(i, j));
            }
        }
        out
    }
    pub fn mul(&self, b: &DMat) -> DMat {
        assert_eq!(self.c, b.r);
        let mut out = DMat::zeros(self.r, b.c);
        for i in 0..self.r {
            for k in 0..self.c {
                let a = self.at(i, k);
                if a.hi == 0.0 {
                    continue;
                }
                for j in 0..b.c {
                    let x = out.at(i, j).add(a.mul(b.at(k, j)));
                    out.set(i, j, x);
                }
            }
        }
        out
    }
    pub fn add(&self, b: &DMat) -> DMat {
        DMat { r: self.r, c: self.c, v: self.v.iter().zip(&b.v).map(|(x, y)| x.add(*y)).collect() }
    }
    pub fn sub(&self, b: &DMat) -> DMat {
        DMat { r: self.r, c: self.c, v: self.v.iter().zip(&b.v).map(|(x, y)| x.sub(*y)).collect() }
    }
    pub fn symmetrize(&self) -> DMat {
        let mut out = self.clone();
        for i in 0..self.r {
            for j in 0..self.c {
                out.set(i, j, self.at(i, j).add(self.at(j, i)).mul(Dd::from(0.5)));
            }
        }
        out
    }
    /// N S⁻¹ for a symmetric positive definite S, by Cholesky S = L Lᵀ (panics if S is not
    /// positive definite in double-double).
    pub fn right_solve(n: &DMat, s: &DMat) -> DMat {
        let m = s.r;
        let mut l = DMat::zeros(m, m);
        for j in 0..m {
            let mut d = s.at(j, j);
            for k in 0..j {
                d = d.sub(l.at(j, k).mul(l.at(j, k)));
            }
            assert!(d.hi > 0.0, "S is not positive definite in double-double");
            let djj = d.sqrt();
            l.set(j, j, djj);
            for i in j + 1..m {
                let mut x = s.at(i, j);
                for k in 0..j {
                    x = x.sub(l.at(i, k).mul(l.at(j, k)));
                }
                l.set(i, j, x.div(djj));
            }
        }
        // X S = N ⇔ S Xᵀ = Nᵀ: forward then backward substitution on each column of Nᵀ.
        let mut x = n.t();
        for col in 0..x.c {
            for i in 0..m {
                let mut v = x.at(i, col);
                for k in 0..i {
                    v = v.sub(l.at(i, k).mul(x.at(k, col)));
                }
                x.set(i, col, v.div(l.at(i, i)));
            }
            for i in (0..m).rev() {
                let mut v = x.at(i, col);
                for k in i + 1..m {
                    v = v.sub(l.at(k, i).mul(x.at(k, col)));
                }
                x.set(i, col, v.div(l.at(i, i)));
            }
        }
        x.t()
    }
}
