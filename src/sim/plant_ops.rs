//! The plant's matrices as the Monte Carlo applies them, converted once per run.

use std::borrow::Cow;

use crate::model::plant::Plant;
use crate::numerics::linalg::Mat;
use crate::numerics::linop::LinOp;

/// The plant's matrices as [`LinOp`]s (sparse when large and mostly zero), each distinct matrix
/// converted once: A_θ\[k], B_θ\[k], C_θ\[k], D_θ\[k] per step and mode, Cz\[k], Dz\[k], and each
/// multiplicative factor's matrices per step.
pub struct PlantOps {
    pub(super) ops: Vec<LinOp>,
    pub(super) modes: usize,
    pub(super) a: Vec<usize>,
    pub(super) b: Vec<usize>,
    pub(super) c: Vec<usize>,
    pub(super) d: Vec<usize>,
    pub(super) cz: Vec<usize>,
    pub(super) dz: Vec<usize>,
    /// Per multiplicative factor i, per step k: its matrices [A_i, B_i, C_i, D_i, Cz_i, Dz_i](k),
    /// None where it does not enter (C_i, D_i also before the first measurement).
    pub(super) factors: Vec<Vec<[Option<usize>; 6]>>,
}

impl PlantOps {
    pub fn new(plant: &Plant) -> Self {
        let mut ops = Vec::new();
        // One operator per distinct matrix: the plant's own by address, the zero matrices of
        // steps without a measurement (made on request, so without a lasting address) by shape.
        let mut seen = std::collections::HashMap::<(*const Mat, usize, usize), usize>::new();
        let mut index = |m: Cow<'_, Mat>| {
            let key = match &m {
                Cow::Borrowed(b) => (*b as *const Mat, 0, 0),
                Cow::Owned(z) => (std::ptr::null(), z.nrows(), z.ncols()),
            };
            *seen.entry(key).or_insert_with(|| {
                ops.push(LinOp::new(&m));
                ops.len() - 1
            })
        };
        let modes = plant.n_modes();
        let (mut a, mut b, mut c, mut d, mut cz, mut dz) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new(), Vec::new());
        for k in 0..plant.steps() {
            cz.push(index(Cow::Borrowed(plant.cz_at(k))));
            dz.push(index(Cow::Borrowed(plant.dz_at(k))));
            for s in 0..modes {
                a.push(index(Cow::Borrowed(plant.a_of(k, s))));
                b.push(index(Cow::Borrowed(plant.b_of(k, s))));
                c.push(index(plant.c_of(k, s)));
                d.push(index(plant.d_of(k, s)));
            }
        }
        let factors = plant
            .factors
            .iter()
            .map(|f| {
                (0..plant.steps())
                    .map(|k| {
                        let measured = plant.measured(k);
                        let mut at = |m: &Option<crate::model::plant::Steps>, used: bool| {
                            m.as_ref().filter(|_| used).map(|s| index(Cow::Borrowed(s.at(k))))
                        };
                        [
                            at(&f.a, true),
                            at(&f.b, true),
                            at(&f.c, measured),
                            at(&f.d, measured),
                            at(&f.cz, true),
                            at(&f.dz, true),
                        ]
                    })
                    .collect()
            })
            .collect();
        PlantOps { ops, modes, a, b, c, d, cz, dz, factors }
    }
    pub(super) fn a(&self, k: usize, mode: usize) -> &LinOp {
        &self.ops[self.a[k * self.modes + mode]]
    }
    pub(super) fn b(&self, k: usize, mode: usize) -> &LinOp {
        &self.ops[self.b[k * self.modes + mode]]
    }
    pub(super) fn c(&self, k: usize, mode: usize) -> &LinOp {
        &self.ops[self.c[k * self.modes + mode]]
    }
    pub(super) fn d(&self, k: usize, mode: usize) -> &LinOp {
        &self.ops[self.d[k * self.modes + mode]]
    }
}
