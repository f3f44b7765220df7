//! Each generator reproduces its target: every distribution shape has exactly the scenario's
//! covariance (checked entrywise against the sample covariance of many draws, within 4.5σ of each
//! entry's own standard error), and the covariance choices land where they should in the set.

use filterbench::analysis::exact;
use filterbench::model::plant::Covariances;
use filterbench::model::shape::Shape;
use filterbench::model::uncertainty::{CovSet, SetShape};
use filterbench::pipeline;
use filterbench::sim::noise::NoiseSampler;

use crate::common;

/// Second moments of zero-mean vectors with, for every entry, the standard error of its estimate
/// (from the sample variance of the products).
struct Moments {
    m: usize,
    n: f64,
    sum: Vec<f64>,
    prod: Vec<f64>,
    prod2: Vec<f64>,
}

impl Moments {
    fn new(m: usize) -> Self {
        Moments { m, n: 0.0, sum: vec![0.0; m], prod: vec![0.0; m * m], prod2: vec![0.0; m * m] }
    }
    fn push(&mut self, v: impl Fn(usize) -> f64) {
        self.n += 1.0;
        for i in 0..self.m {
            self.sum[i] += v(i);
            for j in 0..self.m {
                let p = v(i) * v(j);
                self.prod[i * self.m + j] += p;
                self.prod2[i * self.m + j] += p * p;
            }
        }
    }
    /// Asserts the mean is 0 and the covariance is `target`, each entry within 4.5σ.
    fn check(&self, what: &str, target: &nalgebra::DMatrix<f64>) {
        let (m, n) = (self.m, self.n);
        for i in 0..m {
            let se = (target[(i, i)] / n).sqrt();
            assert!((self.sum[i] / n).abs() <= 4.5 * se, "{what}: mean of entry {i} = {}", self.sum[i] / n);
            for j in 0..m {
                let mean = self.prod[i * m + j] / n;
                let se = ((self.prod2[i * m + j] / n - mean * mean).max(0.0) / n).sqrt();
                let d = mean - target[(i, j)];
                // A product that never varies (Rademacher squares are exactly 1) must be exact.
                let ok = if se > 1e-12 { (d / se).abs() <= 4.5 } else { d.abs() <= 1e-9 };
                assert!(ok, "{what}: covariance ({i},{j}) = {mean} vs {} ({:.2}σ)", target[(i, j)], d / se);
            }
        }
    }
}

fn check_shape(shape: &Shape) {
    let exp = common::shapes("prediction");
    let cov = exp.nominal.clone();
    let sampler = NoiseSampler::new(&exp.plant, &cov, shape);
    let mut ws = sampler.workspace();
    let mut w = Moments::new(exp.plant.nw());
    let mut x0 = Moments::new(exp.plant.nx());
    for t in 0..20_000u64 {
        sampler.draw_trial(99, 3, t, &mut ws);
        x0.push(|i| ws.x0[i] - exp.plant.x0_mean[i]);
        for k in 0..ws.w.ncols() {
            w.push(|i| ws.w[(i, k)]);
        }
    }
    w.check(&format!("{shape:?}: w"), &cov.w());
    x0.check(&format!("{shape:?}: x0"), cov.x0());
}

#[test]
fn every_shape_has_the_target_covariance() {
    for shape in [
        Shape::Gaussian,
        Shape::Uniform,
        Shape::Laplace,
        Shape::StudentT { nu: 5.0 },
        Shape::Rademacher,
        Shape::Mixture { weight: 0.1, ratio: 4.0 },
    ] {
        check_shape(&shape);
    }
}

#[test]
fn vertices_and_interior_points_lie_where_they_should() {
    use rand::SeedableRng;
    let center = nalgebra::DMatrix::from_row_slice(2, 2, &[1.0, 0.2, 0.2, 0.8]);
    let hw = nalgebra::DMatrix::from_row_slice(2, 2, &[0.1, 0.05, 0.05, 0.2]);
    let bx =
        CovSet::new("t", SetShape::Box { center: center.clone(), half_width: hw.clone() }, false, &center).unwrap();
    let ball = CovSet::new("t", SetShape::Ball { center: center.clone(), radius: 0.3 }, false, &center).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
    for _ in 0..100 {
        let v = bx.random_vertex(&mut rng).unwrap();
        let i = bx.random_interior(&mut rng).unwrap();
        assert_eq!(v, v.transpose());
        assert_eq!(i, i.transpose());
        for r in 0..2 {
            for c in 0..2 {
                assert!(((v[(r, c)] - center[(r, c)]).abs() - hw[(r, c)]).abs() < 1e-15, "vertex entry on the bound");
                assert!((i[(r, c)] - center[(r, c)]).abs() <= hw[(r, c)], "interior entry inside");
            }
        }
        let bv = ball.random_vertex(&mut rng).unwrap();
        let bi = ball.random_interior(&mut rng).unwrap();
        assert!(((&bv - &center).norm() - 0.3).abs() < 1e-12, "ball extreme point on the sphere");
        assert!((&bi - &center).norm() <= 0.3 + 1e-12, "ball interior point inside");
        assert_eq!(bv, bv.transpose());
    }
    // Loewner interval: vertices are lower + T^½ P T^½ with P a projection, interior points lie in
    // between; with the PSD intersection every draw is PSD.
    let lower = nalgebra::DMatrix::from_row_slice(2, 2, &[0.5, 0.1, 0.1, 0.4]);
    let upper = nalgebra::DMatrix::from_row_slice(2, 2, &[1.5, 0.3, 0.3, 1.2]);
    let lw =
        CovSet::new("t", SetShape::Loewner { lower: lower.clone(), upper: upper.clone() }, false, &center).unwrap();
    let min_eig = |m: &nalgebra::DMatrix<f64>| filterbench::numerics::linalg::min_eigenvalue(m);
    for _ in 0..100 {
        for s in [lw.random_vertex(&mut rng).unwrap(), lw.random_interior(&mut rng).unwrap()] {
            assert!(min_eig(&(&s - &lower)) >= -1e-12 && min_eig(&(&upper - &s)) >= -1e-12, "inside the interval");
        }
    }
    let psd_box = CovSet::new(
        "t",
        SetShape::Box { center: center.clone(), half_width: nalgebra::DMatrix::from_element(2, 2, 0.7) },
        true,
        &center,
    )
    .unwrap();
    for _ in 0..100 {
        assert!(min_eig(&psd_box.random_vertex(&mut rng).unwrap()) >= -1e-12);
        assert!(min_eig(&psd_box.random_interior(&mut rng).unwrap()) >= -1e-12);
    }
}

#[test]
fn worst_case_for_a_filter_beats_every_sampled_point_of_the_set() {
    use rand::SeedableRng;
    let exp = common::baseline(10);
    let filters = pipeline::design_all(&exp).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(5);
    for f in &filters {
        let real = &f.design.realization;
        let worst = f.worst.as_ref().expect("baseline has sets");
        let at_argmax = exact::error(&exp.plant, real, &worst.argmax).total;
        assert!(
            (at_argmax - worst.total).abs() <= 1e-9 * worst.total,
            "closed form {} vs recomputed {at_argmax}",
            worst.total
        );
        for _ in 0..200 {
            let mut cov: Covariances = exp.nominal.clone();
            for (i, s) in exp.sets.iter().enumerate() {
                if let Some(s) = s {
                    cov.blocks[i] = if rng.next_u32() & 1 == 0 {
                        s.random_vertex(&mut rng).unwrap()
                    } else {
                        s.random_interior(&mut rng).unwrap()
                    };
                }
            }
            let j = exact::error(&exp.plant, real, &cov).total;
            assert!(j <= worst.total * (1.0 + 1e-12), "a sampled point {j} exceeds the worst case {}", worst.total);
        }
    }
}
use rand::Rng as _;
