//! The forward recursions of the module docs: per-mode raw moments, the mean-plus-Lyapunov
//! recursion, the modal (block-diagonal) fast path, and how many digits each result keeps.

use super::augmented::Augmented;
use super::exact_error::{Coordinates, ExactError, Resolution};
use crate::filter::realization::Realization;
use crate::model::plant::{Covariances, Plant};
use crate::numerics::linalg::{Mat, Vector, symmetrize};
use nalgebra::Matrix2;

use crate::numerics::linalg::weighted_sum;

/// What drives the recursion besides x0: white noise (covariance — one, or one per step when
/// [`Covariances::varying`] — and optional mean per step) or a joint input J with mean and raw
/// second moment over the whole horizon.
pub(super) enum Input<'a> {
    White { w: &'a [Mat], mean: Option<&'a Mat> },
    Joint { mean: &'a Vector, raw: &'a Mat },
}

/// W\[k] for [`Input::White`]: one matrix, or one per step when some block varies.
pub(super) fn white(plant: &Plant, cov: &Covariances) -> Vec<Mat> {
    if cov.varies() { (0..plant.steps()).map(|k| cov.w_at(k)).collect() } else { vec![cov.w()] }
}

/// Which step's noise w\[k] sits where in a joint input J = col(x0 − E x0, w\[0..N−1]) (w\[N] = 0) or
/// col(x0 − E x0, w\[0..N]): the offset of w\[k] in J, None when w\[k] = 0.
pub fn joint_offset(plant: &Plant, dim: usize, k: usize) -> Option<usize> {
    let (n, nw) = (plant.nx(), plant.nw());
    let with_last = dim == n + plant.steps() * nw;
    (k < plant.horizon || (k == plant.horizon && with_last)).then_some(n + k * nw)
}

/// The moments at k = 0 before the modes are mixed in: mean m, raw second moment Y and, for a joint
/// input, the cross moment Z = E\[ξ Jᵀ].
pub(super) struct Start {
    m: Vector,
    y: Mat,
    z: Option<Mat>,
}

impl Start {
    /// The moments of P ξ.
    pub(super) fn transformed(&self, p: &Mat) -> Start {
        Start { m: p * &self.m, y: symmetrize(&(p * &self.y * p.transpose())), z: self.z.as_ref().map(|z| p * z) }
    }
}

/// ξ\[0] = (x0, s0) in plant coordinates, with x0 = E x0 + x0_shift + δ, Cov δ = x0_cov.
pub(super) fn start(plant: &Plant, real: &Realization, x0_shift: &Vector, x0_cov: &Mat, input: &Input) -> Start {
    let (n, ns) = (plant.nx(), real.ns());
    let nxi = n + ns;
    let mut m0 = Vector::zeros(nxi);
    m0.rows_mut(0, n).copy_from(&(&plant.x0_mean + x0_shift));
    m0.rows_mut(n, ns).copy_from(&real.s0);
    let mut y0 = &m0 * m0.transpose();
    let mut top = y0.view_mut((0, 0), (n, n));
    top += x0_cov;
    let z0 = match input {
        Input::White { .. } => None,
        Input::Joint { mean, raw } => {
            let dj = mean.len();
            let mut z = Mat::zeros(nxi, dj);
            z.view_mut((0, 0), (n, dj)).copy_from(&(&plant.x0_mean * mean.transpose() + raw.rows(0, n)));
            z.view_mut((n, 0), (ns, dj)).copy_from(&(&real.s0 * mean.transpose()));
            Some(z)
        }
    };
    Start { m: m0, y: y0, z: z0 }
}

/// Σ_ab |A|_ab |B|_ab: the magnitude of ⟨A, B⟩'s terms.
pub(super) fn abs_dot(a: &Mat, b: &Mat) -> f64 {
    a.iter().zip(b.iter()).map(|(x, y)| (x * y).abs()).sum()
}

/// The per-mode raw-moment recursion of the module docs, in whatever coordinates `system` gives
/// the matrices of (the state dimension is the start's).
pub(super) fn propagate(
    plant: &Plant,
    start: &Start,
    input: &Input,
    system: &dyn Fn(usize) -> Vec<Augmented>,
) -> ExactError {
    propagate_outputs(plant, start, input, &[system]).pop().expect("one output")
}

/// [`propagate`] for several outputs of one state recursion: `systems[0]` gives the F, E (and
/// known-input) matrices the moments are carried with, and every system its own H and G, so each
/// output's error is what [`propagate`] returns for it alone, the same bits, for one pass over the
/// horizon (the NEES moments read nz(nz + 1)/2 projections of one error, `nees::error_moments`).
/// Every system must share `systems[0]`'s F, E and terms' F, E.
pub(super) fn propagate_outputs(
    plant: &Plant,
    start: &Start,
    input: &Input,
    systems: &[&dyn Fn(usize) -> Vec<Augmented>],
) -> Vec<ExactError> {
    let outputs = systems.len();
    let nw = plant.nw();
    let nxi = start.m.len();
    let probs = plant.mode_probabilities();
    let q = plant.n_modes();
    let transition = plant.transition();
    let mut m: Vec<Vector> = probs[0].iter().map(|p| &start.m * *p).collect();
    let mut y: Vec<Mat> = probs[0].iter().map(|p| &start.y * *p).collect();
    let mut z: Vec<Option<Mat>> = probs[0].iter().map(|p| start.z.as_ref().map(|z| z * *p)).collect();
    // Z = E[ξ Jᵀ] is read only at the columns of w[k] and later ones (ξ[k] meets w[k] at step k and
    // never an earlier w again), so it is carried from column `first` on, which moves up a step at a
    // time: the recursion then costs Σₖ (dim J − k·nw) instead of (N + 1)·dim J per mode. Each
    // column is the same bits either way (every product forms a column from that column alone);
    // at least KEPT columns are kept so that nalgebra's products take the same kernel as on the
    // whole matrix (it multiplies fewer than six columns in its own loops, not matrixmultiply's).
    const KEPT: usize = 6;
    let mut first = 0;
    let mut per_step = vec![Vec::with_capacity(plant.steps()); outputs];
    let mut per_mode = vec![vec![0.0; q]; outputs];
    let mut magnitudes = vec![Vec::with_capacity(plant.steps()); outputs];
    for k in 0..plant.steps() {
        let all: Vec<Vec<Augmented>> = systems.iter().map(|system| system(k)).collect();
        let augs = &all[0];
        // The moments of w[k]: mean μ and raw second moment R (zero when w[k] is not drawn).
        let (mu, rkk, off) = match input {
            Input::White { w, mean } => {
                let mu = mean.map_or_else(|| Vector::zeros(nw), |m| m.column(k).into_owned());
                let r = w.get(k).unwrap_or(&w[0]) + &mu * mu.transpose();
                (mu, r, None)
            }
            Input::Joint { mean, raw } => match joint_offset(plant, mean.len(), k) {
                Some(o) => (mean.rows(o, nw).into_owned(), raw.view((o, o), (nw, nw)).into_owned(), Some(o)),
                None => (Vector::zeros(nw), Mat::zeros(nw, nw), None),
            },
        };
        let r = plant.r_at(k);
        let mut mse = vec![0.0; outputs];
        let mut magnitude = vec![0.0; outputs];
        let mut next: Vec<(Vector, Mat, Option<Mat>)> = Vec::with_capacity(q);
        let counted = plant.counts(k);
        // The first column step k + 1 reads (w[k + 1]'s offset), never past the last KEPT.
        let next_first = match input {
            Input::Joint { mean, .. } => (plant.nx() + (k + 1) * nw).min(mean.len().saturating_sub(KEPT)).max(first),
            Input::White { .. } => 0,
        };
        for (j, a) in augs.iter().enumerate() {
            let pj = probs[k][j];
            // E[ξ w[k]ᵀ 1{θ = j}]: from the cross moment, or m_j μᵀ when w[k] is independent of ξ.
            let zk = match (&z[j], off) {
                (Some(zj), Some(o)) => zj.columns(o - first, nw).into_owned(),
                (Some(_), None) => Mat::zeros(nxi, nw),
                (None, _) => &m[j] * mu.transpose(),
            };
            // The mean matrices and each factor's term (module docs) add up in the second moment.
            for (o, out) in all.iter().enumerate() {
                let mut ej = 0.0;
                for t in out[j].with_terms() {
                    ej += (&t.h * &y[j] * t.h.transpose()).trace()
                        + 2.0 * (&t.h * &zk * t.g.transpose()).trace()
                        + pj * (&t.g * &rkk * t.g.transpose()).trace();
                    let (habs, gabs) = (t.h.abs(), t.g.abs());
                    magnitude[o] += abs_dot(&(habs.transpose() * &habs), &y[j])
                        + 2.0 * abs_dot(&(habs.transpose() * &gabs), &zk)
                        + pj * abs_dot(&(gabs.transpose() * &gabs), &rkk);
                }
                mse[o] += ej;
                if counted {
                    per_mode[o][j] += ej;
                }
            }
            if k == plant.horizon {
                continue;
            }
            let c = r.map_or_else(|| Vector::zeros(nxi), |r| &a.r_map * r);
            let v = &a.f * &m[j] + pj * (&a.e * &mu);
            let fze = &a.f * &zk * a.e.transpose();
            let mut yn = &a.f * &y[j] * a.f.transpose()
                + &fze
                + fze.transpose()
                + pj * (&a.e * &rkk * a.e.transpose())
                + &c * v.transpose()
                + &v * c.transpose()
                + pj * (&c * c.transpose());
            for t in &a.terms {
                let fze = &t.f * &zk * t.e.transpose();
                yn += &t.f * &y[j] * t.f.transpose() + &fze + fze.transpose() + pj * (&t.e * &rkk * t.e.transpose());
            }
            let zn = match (&z[j], input) {
                (Some(zj), Input::Joint { mean, raw }) => {
                    let cols = zj.ncols() - (next_first - first);
                    let mut zn = &a.f * zj.columns(next_first - first, cols)
                        + pj * (&c * mean.rows(next_first, cols).transpose());
                    if let Some(o) = off {
                        zn += pj * (&a.e * raw.view((o, next_first), (nw, cols)));
                    }
                    Some(zn)
                }
                _ => None,
            };
            next.push((v + pj * c, yn, zn));
        }
        for o in 0..outputs {
            per_step[o].push(mse[o]);
            magnitudes[o].push(magnitude[o]);
        }
        if k == plant.horizon {
            break;
        }
        first = next_first;
        // Mix by the chain: moments of θ[k+1] = i collect Π_ji times those of θ[k] = j.
        for i in 0..q {
            m[i] = (0..q).fold(Vector::zeros(nxi), |acc, j| acc + transition[(j, i)] * &next[j].0);
            y[i] = symmetrize(&weighted_sum(nxi, nxi, (0..q).map(|j| (transition[(j, i)], &next[j].1))));
            z[i] = next[0].2.as_ref().map(|z0| {
                let zj = |j: usize| next[j].2.as_ref().expect("every mode carries Z");
                weighted_sum(z0.nrows(), z0.ncols(), (0..q).map(|j| (transition[(j, i)], zj(j))))
            });
        }
    }
    per_step
        .into_iter()
        .zip(per_mode)
        .zip(&magnitudes)
        .map(|((per_step, per_mode), magnitudes)| {
            let total = per_step.iter().enumerate().filter(|(k, _)| plant.counts(*k)).map(|(_, v)| v).sum();
            let resolution = resolution(&per_step, magnitudes);
            ExactError { per_step, total, per_mode, resolution, coordinates: Coordinates::Plant, untracked: None }
        })
        .collect()
}

/// The worst step's digits lost. Each step is measured against its own value or a millionth of
/// the largest step's, whichever is larger: a step whose error is zero up to rounding (a
/// deterministic input the filter matches exactly) need not be resolved beyond the run's scale.
pub(super) fn resolution(per_step: &[f64], magnitudes: &[f64]) -> Resolution {
    let scale = per_step.iter().fold(0.0, |m: f64, v| m.max(v.abs()));
    let mut worst = Resolution { step: 0, digits_lost: 0.0 };
    for (k, (v, mag)) in per_step.iter().zip(magnitudes).enumerate() {
        // A value that is not finite stays so (f64::max would drop a NaN).
        let against = if v.is_finite() { v.abs().max(RESOLVE_FRACTION * scale) } else { *v };
        let lost = digits_lost(against, *mag);
        if lost > worst.digits_lost {
            worst = Resolution { step: k, digits_lost: lost };
        }
    }
    worst
}

/// See [`resolution`].
pub(super) const RESOLVE_FRACTION: f64 = 1e-6;

/// log10(magnitude of the terms / |result|), 0 when there is nothing to lose, capped at 17 (all
/// digits) when the result is zero but its terms are not; infinite when anything is not finite.
pub(super) fn digits_lost(result: f64, magnitude: f64) -> f64 {
    if !(result.is_finite() && magnitude.is_finite()) {
        return f64::INFINITY;
    }
    if magnitude <= 0.0 {
        return 0.0;
    }
    (magnitude / result.abs().max(magnitude * 1e-17)).log10().max(0.0)
}

/// Below this many states the dense recursion costs nothing and the structure is not looked for.
pub(super) const MODAL_MIN_STATES: usize = 32;

/// Whether `m` is zero outside 2×2 blocks on its diagonal (a modal truth: independent oscillators).
pub(super) fn two_by_two_block_diagonal(m: &Mat) -> bool {
    m.nrows() % 2 == 0
        && m.iter().enumerate().all(|(idx, v)| *v == 0.0 || (idx % m.nrows()) / 2 == (idx / m.nrows()) / 2)
}

/// The recursion of [`propagate`] when A, cov x0 and B W Bᵀ are block diagonal in 2×2 blocks and
/// there are no modes, no means and no time-varying matrices (a modal truth, seed 004's string): the state covariance stays
/// block diagonal, so only its blocks P_b, the cross covariance X = E\[x sᵀ] and the filter's
/// S = E\[s sᵀ] are carried:
///
///     P_b' = A_b P_b A_bᵀ + (B W Bᵀ)_b,   X' = A X Afᵀ + A P (Bf C)ᵀ + B W Dᵀ Bfᵀ,
///     S' = Af S Afᵀ + Af Xᵀ (Bf C)ᵀ + (Bf C) X Afᵀ + (Bf C) P (Bf C)ᵀ + Bf D W Dᵀ Bfᵀ,
///
/// E|e|² = Σ_b tr(H_x,b P_b H_x,bᵀ) + 2 tr(H_x X H_sᵀ) + tr(H_s S H_sᵀ) + tr(G W Gᵀ), with
/// H_x = Cz − Df C, H_s = −Cf, G = Dz − Df D. The cost per step is linear in the number of modes
/// instead of cubic.
pub(super) fn propagate_modal(plant: &Plant, real: &Realization, x0_cov: &Mat, w: &Mat, bwb_full: &Mat) -> ExactError {
    let (nx, ns) = (plant.nx(), real.ns());
    let nb = nx / 2;
    // The blocks live on the stack (nalgebra's Matrix2): the string has 128 of them per step and
    // filter, and heap-allocated 2×2 matrices made this recursion most of galerkin_string's run.
    let blk = |m: &Mat, b: usize| -> Matrix2<f64> { m.fixed_view::<2, 2>(2 * b, 2 * b).into_owned() };
    let a: Vec<Matrix2<f64>> = (0..nb).map(|b| blk(plant.a_at(0), b)).collect();
    let bwb: Vec<Matrix2<f64>> = (0..nb).map(|b| blk(bwb_full, b)).collect();
    let mut p: Vec<Matrix2<f64>> = (0..nb).map(|b| blk(x0_cov, b)).collect();
    let mut x = Mat::zeros(nx, ns);
    let mut sm = Mat::zeros(ns, ns);
    // Block-diagonal products D·M for M with nx rows.
    let bd_mul = |d: &[Matrix2<f64>], m: &Mat| {
        let mut out = Mat::zeros(m.nrows(), m.ncols());
        for j in 0..m.ncols() {
            for (b, db) in d.iter().enumerate() {
                let (u, v) = (m[(2 * b, j)], m[(2 * b + 1, j)]);
                out[(2 * b, j)] = db[(0, 0)] * u + db[(0, 1)] * v;
                out[(2 * b + 1, j)] = db[(1, 0)] * u + db[(1, 1)] * v;
            }
        }
        out
    };
    // The plant is constant here (no time-varying matrices): every product of C, D and W that
    // does not involve the filter is formed once, so a step costs O(nx ns² + ns³) with no factor
    // of nw (the string's forcing has one component per truth mode).
    // D as measured (d_at(k) is zero before the first measurement, where these terms vanish).
    let d_measured = plant.d.at(0);
    let bwd_plant = plant.b_at(0) * w * d_measured.transpose();
    let dwd_plant = d_measured * w * d_measured.transpose();
    // tr(G W Gᵀ) with G = Dz − Df D, expanded so W (nw × nw) meets only the plant's matrices.
    let dz = plant.dz_at(0);
    let (zwz, dwz) = ((dz * w * dz.transpose()).trace(), d_measured * w * dz.transpose());
    let mut per_step = Vec::with_capacity(plant.steps());
    for k in 0..plant.steps() {
        let g = real.gains(k, 0);
        let c = &*plant.c_at(k);
        let hx = plant.cz_at(k) - &g.df * c;
        let hs = -&g.cf;
        let on = if plant.measured(k) { 1.0 } else { 0.0 };
        let gwg = zwz - 2.0 * on * (&g.df * &dwz).trace() + on * (&g.df * &dwd_plant * g.df.transpose()).trace();
        let mut mse = 2.0 * (&hx * &x * hs.transpose()).trace() + (&hs * &sm * hs.transpose()).trace() + gwg;
        // Σ_b tr(H_b P_b H_bᵀ), row by row: h P hᵀ for the 1×2 pieces h of each row of H_x.
        for (b, pb) in p.iter().enumerate() {
            for r in 0..hx.nrows() {
                let (h0, h1) = (hx[(r, 2 * b)], hx[(r, 2 * b + 1)]);
                mse += h0 * (pb[(0, 0)] * h0 + pb[(0, 1)] * h1) + h1 * (pb[(1, 0)] * h0 + pb[(1, 1)] * h1);
            }
        }
        per_step.push(mse);
        if k == plant.horizon {
            break;
        }
        // With Bf C = (Bf)(C): P Cᵀ (nx × ny) and Xᵀ Cᵀ (ns × ny) first, then the filter's Bf.
        let pct = bd_mul(&p, &c.transpose());
        let pgc = &pct * g.bf.transpose();
        let bwd = &bwd_plant * g.bf.transpose() * on;
        let dwd = &g.bf * &dwd_plant * g.bf.transpose() * on;
        let x_next = bd_mul(&a, &(&x * g.af.transpose() + &pgc)) + bwd;
        let xg = (x.transpose() * c.transpose()) * g.bf.transpose();
        let gpg = &g.bf * (c * &pct) * g.bf.transpose();
        let s_next = &g.af * &sm * g.af.transpose() + &g.af * &xg + xg.transpose() * g.af.transpose() + gpg + dwd;
        for b in 0..nb {
            let next = a[b] * p[b] * a[b].transpose() + bwb[b];
            p[b] = (next + next.transpose()) * 0.5;
        }
        x = x_next;
        sm = symmetrize(&s_next);
    }
    let total: f64 = per_step.iter().enumerate().filter(|(k, _)| plant.counts(*k)).map(|(_, v)| v).sum();
    // A stable modal truth (the string) is the only use: only overflow is looked for.
    let resolution = match per_step.iter().position(|v| !v.is_finite()) {
        Some(step) => Resolution { step, digits_lost: f64::INFINITY },
        None => Resolution { step: 0, digits_lost: 0.0 },
    };
    ExactError { per_step, total, per_mode: vec![total], resolution, coordinates: Coordinates::Plant, untracked: None }
}
