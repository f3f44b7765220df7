//! A filter's worst case over deterministic disturbances bounded in energy (seed 000 §5, eq (36)
//! with time-varying weights W_k, and per-step bounds d\[k]ᵀ W_k d\[k] ≤ r_k as a set U of (33)):
//! the sequence that maximizes its summed error, that error, and a certified upper bound on it.
//!
//! For a linear filter the error is e = (random part, from x0 and the noises) + c + L d, with d the
//! stacked disturbance blocks (u, v, … of seed 000 eqs (33)–(36)) and c the error of x0's mean and
//! the known input; the random part is independent of d, so E J = J(K) + |c + L d|² − |c|², and the
//! worst case over the covariance sets × the disturbances splits into the sets' maximum of the
//! affine J(K) (the linear oracle, exact) plus the maximum of |c + L d|² − |c|² over the product of
//! the blocks' sets.
//!
//! In u\[k] = W_k^{½} d\[k] the error is |L T u|², T = blockdiag(W_k^{-½}). One block with the summed
//! bound alone: the maximum is r λmax((LT)ᵀLT), attained by the top eigenvector, a closed form.
//! Per-step bounds, or several blocks, make it a convex quadratic maximized over a product of balls,
//! which has no closed form (box-constrained cases are NP-hard); we take the best of a monotone
//! ascent u ← argmax_{u' ∈ U} ⟨M u, u'⟩ (the linear oracle is a water-filling in closed form per
//! block) from the top eigenvectors (and, with several blocks, from the blocks' own maximizers).
//! Seed 000's surrogate (eqs (38)–(39)) bounds one block, since d dᵀ ⪯ s·blockdiag(W_k⁻¹) on its
//! set, but not two: (u, v)(u, v)ᵀ has the cross terms u vᵀ that blockdiag(s_u W⁻¹, s_v T⁻¹) does
//! not dominate. The bound used instead is the S-procedure dual over the product, one multiplier
//! per constraint, made exactly feasible ([`slemma::quadratic_max_bound`]): a bound U on max
//! |L T u|² whatever the number of blocks, exact for one block with the summed bound alone. With
//! c ≠ 0 the cross term 2cᵀL d is bounded by 2|c|√U. When the ascent meets the bound (to 1e-9)
//! the value is the exact maximum.

use crate::error::Result;
use crate::filter::realization::Realization;
use crate::model::disturbance::{Disturbance, WMean, blocks};
use crate::model::plant::Plant;
use crate::numerics::linalg::{Mat, Vector, psd_factor, sym_eigen, top_eigen};
use crate::numerics::solve::slemma::{self, BallGroup};

/// The map L from one block's sequence (columns: step-major, then component) to the stacked
/// deterministic errors e\[k] over the steps that count: w\[k0] enters e\[k0] through G and the state
/// through E, then propagates through F.
fn response(plant: &Plant, real: &Realization, offset: usize, m: usize) -> Mat {
    let nz = plant.nz();
    let steps = plant.steps();
    let mut rows = vec![None; steps];
    let mut next = 0;
    for (k, r) in rows.iter_mut().enumerate() {
        if plant.counts(k) {
            *r = Some(next * nz);
            next += 1;
        }
    }
    let aug: Vec<_> = (0..steps).map(|k| crate::analysis::exact::augmented(plant, real, k, 0)).collect();
    let mut l = Mat::zeros(next * nz, steps * m);
    for k0 in 0..steps {
        for j in 0..m {
            let col = k0 * m + j;
            let unit_g = aug[k0].g.column(offset + j).into_owned();
            if let Some(r) = rows[k0] {
                l.view_mut((r, col), (nz, 1)).copy_from(&unit_g);
            }
            if k0 == plant.horizon {
                continue;
            }
            let mut xi = aug[k0].e.column(offset + j).into_owned();
            for k in k0 + 1..steps {
                if let Some(r) = rows[k] {
                    let e = &aug[k].h * &xi;
                    l.view_mut((r, col), (nz, 1)).copy_from(&e);
                }
                if k < plant.horizon {
                    xi = &aug[k].f * &xi;
                }
            }
        }
    }
    l
}

/// A filter's worst deterministic disturbance: the mean squared error it adds Σ_k |e_mean\[k]|² (the
/// deterministic part of J, with x0's mean and the known input), the sequence, and certified upper
/// bounds on the maximum over all admissible sequences (module docs).
#[derive(Clone, Debug)]
pub struct Worst {
    pub value: f64,
    pub sequence: WMean,
    /// ≥ max Σ_k |e_mean\[k]|² over the admissible sequences: (|c| + √U)² with U the certified
    /// S-procedure bound on max |L d|² and |c|² the error of x0's mean and the known input alone.
    pub upper: f64,
    /// ≥ what the disturbances can add to E J over the sequences: U + 2|c|√U (the cross term
    /// 2 cᵀL d by Cauchy–Schwarz), so E J ≤ J(K) + `increase` for every admissible sequence.
    pub increase: f64,
    /// The S-procedure bound U with clarabel's report ([`slemma::CertifiedBound`]).
    pub certificate: slemma::CertifiedBound,
}

impl Worst {
    /// Whether `value` is the maximum (the upper bound is attained to 1e-9).
    pub fn exact(&self) -> bool {
        self.value >= self.upper * (1.0 - 1e-9)
    }
}

/// One block's worst sequence in u coordinates (steps × m entries).
struct BlockWorst {
    u: Vector,
    /// The sequence is T u · scale (the closed form scales the unit eigenvector by √r).
    scale: f64,
}

/// The linear oracle of the ascent: argmax ⟨g, u⟩ over |u_k|² ≤ r_k, Σ|u_k|² ≤ total. Each u_k
/// points along g_k with length t_k = min(√r_k, c |g_k|), c the water level that spends the total
/// (all caps when Σ r_k ≤ total): exact, by sorting the breakpoints √r_k/|g_k|.
fn oracle(g: &Vector, m: usize, r: &[f64], total: f64) -> Vector {
    let a: Vec<f64> = (0..r.len()).map(|k| g.rows(k * m, m).norm()).collect();
    let mut lengths: Vec<f64> = r.iter().map(|r| r.sqrt()).collect();
    if r.iter().sum::<f64>() > total {
        let mut order: Vec<usize> = (0..r.len()).filter(|&k| a[k] > 0.0).collect();
        order.sort_by(|&i, &j| (lengths[i] / a[i]).total_cmp(&(lengths[j] / a[j])));
        let (mut capped, mut free): (f64, f64) = (0.0, order.iter().map(|&k| a[k] * a[k]).sum());
        let mut level = 0.0;
        for (i, &k) in order.iter().enumerate() {
            let c = ((total - capped).max(0.0) / free).sqrt();
            level = c;
            if c <= lengths[k] / a[k] {
                break;
            }
            capped += r[k];
            free -= a[k] * a[k];
            if i + 1 == order.len() {
                level = f64::INFINITY;
            }
        }
        for k in 0..r.len() {
            lengths[k] = if a[k] > 0.0 { lengths[k].min(level * a[k]) } else { 0.0 };
        }
    }
    let mut u = Vector::zeros(g.len());
    for k in 0..r.len() {
        if a[k] > 0.0 {
            u.rows_mut(k * m, m).copy_from(&(g.rows(k * m, m) * (lengths[k] / a[k])));
        }
    }
    u
}

/// One block's set in its coordinates u (per-step caps r_k, ∞ without per-step bounds; the summed
/// bound, ∞ without), at `offset` in the stacked u of all blocks.
struct Caps {
    offset: usize,
    m: usize,
    r: Vec<f64>,
    total: f64,
}

impl Caps {
    fn len(&self) -> usize {
        self.r.len() * self.m
    }
}

/// The linear oracle over the product of the blocks' sets: it separates into one [`oracle`] per
/// block.
fn product_oracle(g: &Vector, caps: &[Caps]) -> Vector {
    let mut u = Vector::zeros(g.len());
    for c in caps {
        let part = oracle(&g.rows(c.offset, c.len()).into_owned(), c.m, &c.r, c.total);
        u.rows_mut(c.offset, c.len()).copy_from(&part);
    }
    u
}

/// The best of the monotone ascents u ← argmax_{u' ∈ U} ⟨M u, u'⟩ from each feasible start: each
/// step does not decrease uᵀMu (convexity: f(u') ≥ f(u) + 2⟨Mu, u' − u⟩ ≥ f(u)). With `target`, an
/// upper bound on the maximum, it stops as soon as a value meets it (to [`MEETS`]): that value is
/// then the maximum, and further steps would only creep along rounding.
fn ascend(mm: &Mat, caps: &[Caps], starts: Vec<Vector>, target: Option<f64>) -> (f64, Vector) {
    let value = |u: &Vector| (u.transpose() * mm * u)[(0, 0)];
    let met = |f: f64| target.is_some_and(|t| f >= t * (1.0 - MEETS));
    let mut best: Option<(f64, Vector)> = None;
    for mut u in starts {
        let mut f = value(&u);
        for _ in 0..MAX_ASCENT {
            if met(f) {
                break;
            }
            let next = product_oracle(&(mm * &u), caps);
            let fn_ = value(&next);
            if fn_ <= f * (1.0 + 1e-15) {
                break;
            }
            (u, f) = (next, fn_);
        }
        if best.as_ref().is_none_or(|(bf, _)| f > *bf) {
            best = Some((f, u));
        }
        if met(f) {
            break;
        }
    }
    best.expect("at least one start")
}

/// The relative distance below the certified bound at which the ascent stops: the tolerance at
/// which [`Worst::exact`] calls the value the maximum (the bound's own accuracy, clarabel's 1e-10
/// and the certificate's margin, is not much finer; the ascent creeps the last digits at the
/// speed of a power iteration).
const MEETS: f64 = 1e-9;

/// Feasible starts from the top eigenvectors of M, each sent through the oracle.
fn eigen_starts(mm: &Mat, caps: &[Caps]) -> Result<Vec<Vector>> {
    let (_, vectors) = sym_eigen(mm)?;
    let n = mm.nrows();
    Ok((0..n.min(STARTS)).map(|i| product_oracle(&vectors.column(n - 1 - i).into_owned(), caps)).collect())
}

/// max uᵀ M u over the block's set (module docs): closed form with the summed bound alone, else the
/// best ascent from the top eigenvectors.
fn block_worst(mm: &Mat, m: usize, d: &Disturbance) -> Result<BlockWorst> {
    let Some(r) = &d.step_energy else {
        let (_, u) = top_eigen(mm)?;
        return Ok(BlockWorst { u, scale: d.energy.sqrt() });
    };
    let caps = [Caps { offset: 0, m, r: r.clone(), total: d.energy }];
    let (_, u) = ascend(mm, &caps, eigen_starts(mm, &caps)?, None);
    Ok(BlockWorst { u, scale: 1.0 })
}

/// Starts of the ascent: the top eigenvectors of (LT)ᵀLT.
const STARTS: usize = 8;
/// A cap on the ascent's iterations (each one increases the value; it stops when it does not).
const MAX_ASCENT: usize = 10_000;

/// One disturbance block's part of the problem: its offset in w, size m, bounds, and
/// T = blockdiag(W_k^{-½}), LT its response in u coordinates.
struct Part<'a> {
    offset: usize,
    m: usize,
    d: &'a Disturbance,
    t: Mat,
    lt: Mat,
}

/// The filter's worst disturbance ([`Worst`]). One block: the block's maximizer (module docs).
/// Several blocks: a joint ascent over the product of the blocks' sets, started from every sign
/// combination of the blocks' own maximizers and from the top eigenvectors of the joint form; it
/// is feasible and can fall short of the joint maximum (a convex quadratic over a product of sets).
/// In every case the upper bound is the certified S-procedure bound over the product
/// ([`slemma::quadratic_max_bound`], one multiplier per constraint: each block's summed bound and
/// each of its per-step bounds), which is the exact maximum for one block with the summed bound
/// alone, and otherwise meets the ascent where `exact()` says so.
pub fn worst(plant: &Plant, real: &Realization, dist: &[Option<Disturbance>]) -> Result<Option<Worst>> {
    let bl = blocks(plant, dist);
    if bl.is_empty() {
        return Ok(None);
    }
    if plant.random_matrices() {
        return Err(crate::error::Error::invalid(
            "disturbances",
            "the worst deterministic disturbance is computed for a plant with deterministic matrices (no dropouts, modes or multiplicative noise)",
        ));
    }
    let steps = plant.steps();
    let mut parts = Vec::new();
    for &(b, o, d) in &bl {
        let m = plant.noise_blocks[b].1;
        let l = response(plant, real, o, m);
        // d[k] = W_k^{-½} u[k]: maximize |L T u|² over the block's set in u.
        let mut t = Mat::zeros(steps * m, steps * m);
        for k in 0..steps {
            let winv_half = psd_factor(&d.weights[k].clone().try_inverse().expect("weight checked positive definite"));
            t.view_mut((k * m, k * m), (m, m)).copy_from(&winv_half);
        }
        let lt = &l * &t;
        parts.push(Part { offset: o, m, d, t, lt });
    }
    // The stacked u of all blocks, its form |A u|² and the product of the blocks' sets.
    let n: usize = parts.iter().map(|p| p.lt.ncols()).sum();
    let mut a = Mat::zeros(parts[0].lt.nrows(), n);
    let mut caps = Vec::new();
    let mut groups = Vec::new();
    let mut at = 0;
    for p in &parts {
        a.view_mut((0, at), p.lt.shape()).copy_from(&p.lt);
        let r = p.d.step_energy.clone();
        let total = p.d.energy.is_finite().then_some(p.d.energy);
        caps.push(Caps { offset: at, m: p.m, r: r.clone().unwrap_or(vec![f64::INFINITY; steps]), total: p.d.energy });
        groups.push(BallGroup { offset: at, size: p.m, steps, step: r, total });
        at += p.lt.ncols();
    }
    let certificate = slemma::quadratic_max_bound(&a, &groups, &crate::numerics::solve::conic::Tuning::default())
        .map_err(|e| {
            crate::error::Error::invalid("disturbances", format!("no certified bound on the worst disturbance: {e}"))
        })?;
    let mm = a.transpose() * &a;
    // Each block's own maximizer (scaled onto its set), stacked.
    let own: Vec<Vector> = parts
        .iter()
        .map(|p| block_worst(&(p.lt.transpose() * &p.lt), p.m, p.d).map(|bw| bw.u * bw.scale))
        .collect::<Result<_>>()?;
    let u = if parts.len() == 1 {
        own.into_iter().next().expect("one block")
    } else {
        let mut starts = eigen_starts(&mm, &caps)?;
        for signs in 0..(1u32 << own.len()) {
            let mut u = Vector::zeros(n);
            for (i, (o, c)) in own.iter().zip(&caps).enumerate() {
                let s = if signs >> i & 1 == 1 { -1.0 } else { 1.0 };
                u.rows_mut(c.offset, c.len()).copy_from(&(o * s));
            }
            starts.push(u);
        }
        ascend(&mm, &caps, starts, Some(certificate.value)).1
    };
    let mut sequence = Mat::zeros(plant.nw(), steps);
    for (p, c) in parts.iter().zip(&caps) {
        let seq = &p.t * u.rows(c.offset, c.len());
        for k in 0..steps {
            sequence.view_mut((p.offset, k), (p.m, 1)).copy_from(&seq.rows(k * p.m, p.m));
        }
    }
    let value = crate::analysis::exact::mean_error(plant, real, &sequence);
    let bound = certificate.value;
    let c = crate::analysis::exact::deterministic_error(plant, real).sqrt();
    let round_up = 1.0 + 4.0 * f64::EPSILON;
    let upper = ((c + bound.sqrt()).powi(2) * round_up).max(value);
    let increase = (bound + 2.0 * c * bound.sqrt()) * round_up;
    Ok(Some(Worst { value, sequence, upper, increase, certificate }))
}
