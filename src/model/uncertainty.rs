//! Covariance uncertainty sets (seed 000 §2 and §6, docs/math.md §2): the elementwise box
//! {S : |S_ij − C_ij| ≤ h_ij}, the Frobenius ball {‖S − C‖_F ≤ ρ}, the Loewner interval
//! {L ⪯ S ⪯ U}, each optionally intersected with {S ⪰ 0}. A filter's error is affine in the
//! covariance, so everything asked of a set is a linear maximization: closed form for the plain box
//! (a sign pattern) and ball, a clarabel SDP otherwise.

use rand::Rng;
use rand_distr::{Distribution, StandardNormal, Uniform};

use crate::error::{Error, Result};
use crate::numerics::linalg::{Mat, PSD_TOL, frob_dot, is_psd, min_eigenvalue, psd_factor, symmetrize};
use crate::numerics::solve::sdp::{SymConstraints, max_linear};

#[derive(Clone, Debug)]
pub enum SetShape {
    /// Elementwise box: center ± half_width (half_width symmetric, non-negative).
    Box { center: Mat, half_width: Mat },
    /// Frobenius ball of symmetric matrices around center.
    Ball { center: Mat, radius: f64 },
    /// Loewner interval lower ⪯ S ⪯ upper.
    Loewner { lower: Mat, upper: Mat },
}

#[derive(Clone, Debug)]
pub struct CovSet {
    pub shape: SetShape,
    /// Intersected with the PSD cone (a real covariance must be PSD; seed 000's examples ignore it).
    pub psd: bool,
}

impl CovSet {
    /// Builds and checks a set: its parameters must be valid, it must not be empty, and it must
    /// contain the nominal covariance of its block. `key` names the set in errors.
    pub fn new(key: &str, shape: SetShape, psd: bool, nominal: &Mat) -> Result<Self> {
        let n = nominal.nrows();
        let sized = |name: &str, m: &Mat| {
            if m.shape() != (n, n) {
                return Err(Error::invalid(
                    format!("{key}.{name}"),
                    format!("expected a {n}×{n} matrix, found {}×{}", m.nrows(), m.ncols()),
                ));
            }
            if (m - m.transpose()).amax() > PSD_TOL * m.amax().max(1.0) {
                return Err(Error::invalid(format!("{key}.{name}"), "must be symmetric"));
            }
            Ok(())
        };
        let tol = 1e-12 * nominal.amax().max(1.0);
        match &shape {
            SetShape::Box { center, half_width } => {
                sized("center", center)?;
                sized("half_width", half_width)?;
                if half_width.iter().any(|v| *v < 0.0 || !v.is_finite()) {
                    return Err(Error::invalid(format!("{key}.half_width"), "half-widths must be finite and ≥ 0"));
                }
                if let Some(i) = (0..n * n).find(|&i| (nominal[i] - center[i]).abs() > half_width[i] + tol) {
                    return Err(Error::invalid(
                        key,
                        format!("the nominal covariance is outside its own box (entry ({}, {}))", i % n + 1, i / n + 1),
                    ));
                }
            }
            SetShape::Ball { center, radius } => {
                sized("center", center)?;
                if *radius < 0.0 || !radius.is_finite() {
                    return Err(Error::invalid(format!("{key}.radius"), "the radius must be finite and ≥ 0"));
                }
                let d = (nominal - center).norm();
                if d > radius + tol {
                    return Err(Error::invalid(
                        key,
                        format!(
                            "the nominal covariance is outside its own ball (‖nominal − center‖_F = {d:.6} > {radius})"
                        ),
                    ));
                }
            }
            SetShape::Loewner { lower, upper } => {
                sized("lower", lower)?;
                sized("upper", upper)?;
                let gap = min_eigenvalue(&(upper - lower));
                if gap < -PSD_TOL * upper.amax().max(1.0) {
                    return Err(Error::invalid(
                        key,
                        format!("the set is empty: upper − lower has a negative eigenvalue ({gap:.6e})"),
                    ));
                }
                if !is_psd(&(nominal - lower)) || !is_psd(&(upper - nominal)) {
                    return Err(Error::invalid(key, "the nominal covariance is outside its own Loewner interval"));
                }
            }
        }
        // The nominal covariance is PSD (checked when it was read) and in the set, so the set and
        // its PSD intersection are not empty.
        Ok(CovSet { shape, psd })
    }

    /// Whether `m` lies in the set (to rounding: 1e-9 relative), so that a promise made over the set
    /// holds for a scenario with this covariance.
    pub fn contains(&self, m: &Mat) -> bool {
        let tol = 1e-9 * m.amax().max(1.0);
        let inside = match &self.shape {
            SetShape::Box { center, half_width } => {
                m.shape() == center.shape()
                    && (m - center).iter().zip(half_width.iter()).all(|(d, h)| d.abs() <= h + tol)
            }
            SetShape::Ball { center, radius } => m.shape() == center.shape() && (m - center).norm() <= radius + tol,
            SetShape::Loewner { lower, upper } => {
                m.shape() == lower.shape()
                    && min_eigenvalue(&(m - lower)) >= -tol
                    && min_eigenvalue(&(upper - m)) >= -tol
            }
        };
        inside && (!self.psd || min_eigenvalue(m) >= -tol)
    }

    pub fn kind(&self) -> String {
        let k = match self.shape {
            SetShape::Box { .. } => "box",
            SetShape::Ball { .. } => "ball",
            SetShape::Loewner { .. } => "loewner",
        };
        if self.psd { format!("{k}∩psd") } else { k.to_string() }
    }

    /// The largest element in the Loewner order, when the set has one (seed 000 Theorem 1.2a: then
    /// the minimax filter is the Kalman filter at it): the upper end of a Loewner interval, the
    /// top diagonal of a box whose off-diagonal entries are fixed, the center of a ball of radius 0.
    pub fn largest(&self) -> Option<Mat> {
        match &self.shape {
            SetShape::Loewner { upper, .. } => Some(upper.clone()),
            SetShape::Box { center, half_width } => {
                let n = center.nrows();
                let fixed_off_diag = (0..n).all(|i| (0..n).all(|j| i == j || half_width[(i, j)] == 0.0));
                fixed_off_diag.then(|| center + Mat::from_diagonal(&half_width.diagonal()))
            }
            SetShape::Ball { center, radius } => (*radius == 0.0).then(|| center.clone()),
        }
    }

    fn constraints(&self) -> SymConstraints {
        let mut c = SymConstraints::default();
        match &self.shape {
            SetShape::Box { center, half_width } => c.bounds = Some((center - half_width, center + half_width)),
            SetShape::Ball { center, radius } => c.ball = Some((center.clone(), *radius)),
            SetShape::Loewner { lower, upper } => {
                c.lower = Some(lower.clone());
                c.upper = Some(upper.clone());
            }
        }
        c.psd = self.psd;
        c
    }

    /// argmax over the set of ⟨G, S⟩ for a symmetric G (seed 000 Algorithm 1, step 3). Plain box:
    /// the sign pattern C + h∘sign(G) (Examples 2–4); plain ball: C + ρ G/‖G‖_F (Example 2). With the
    /// PSD intersection the closed form is kept when it is PSD (it is then optimal on the smaller
    /// set too), otherwise, and for Loewner intervals, clarabel solves the SDP.
    pub fn argmax_linear(&self, g: &Mat) -> Result<Mat> {
        self.linear_max(g).map(|(s, _)| s)
    }

    /// [`CovSet::argmax_linear`] and a certified upper bound on max ⟨G, S⟩ over the set: the value
    /// itself where the maximizer has a closed form, the weak-duality bound of
    /// [`crate::numerics::solve::sdp::certified_upper`] where clarabel finds it (None where the
    /// closed form is exact).
    pub(crate) fn linear_max(&self, g: &Mat) -> Result<(Mat, Option<f64>)> {
        let closed = match &self.shape {
            SetShape::Box { center, half_width } => Some(center + half_width.zip_map(g, |h, v| h * signum0(v))),
            SetShape::Ball { center, radius } => {
                let norm = g.norm();
                Some(if norm == 0.0 { center.clone() } else { center + g * (radius / norm) })
            }
            SetShape::Loewner { .. } => None,
        };
        if let Some(s) = closed.filter(|s| !self.psd || is_psd(s)) {
            return Ok((s, None));
        }
        max_linear(g, g.nrows(), &self.constraints())
            .map(|r| (r.argmax, Some(r.upper)))
            .map_err(|e| Error::invalid(format!("{} set", self.kind()), format!("linear maximization failed: {e}")))
    }

    /// A random extreme point: a box corner (an independent random sign per upper-triangle entry),
    /// a point on the ball's sphere (uniform direction among symmetric matrices), or lower +
    /// T^½ P T^½ with P a random orthogonal projection (T = upper − lower) for a Loewner interval.
    /// With the PSD intersection, points that are not PSD are rejected and drawn again.
    pub fn random_vertex<R: Rng + ?Sized>(&self, rng: &mut R) -> Result<Mat> {
        self.sample(rng, true)
    }

    /// A random point of the set: uniform in the box or ball; lower + T^½ Q diag(u) Qᵀ T^½ with a
    /// random rotation Q and u uniform in [0, 1]ⁿ for a Loewner interval. PSD rejection as above.
    pub fn random_interior<R: Rng + ?Sized>(&self, rng: &mut R) -> Result<Mat> {
        self.sample(rng, false)
    }

    fn sample<R: Rng + ?Sized>(&self, rng: &mut R, extreme: bool) -> Result<Mat> {
        const TRIES: usize = 10_000;
        for _ in 0..TRIES {
            let s = self.sample_once(rng, extreme);
            if !self.psd || is_psd(&s) {
                return Ok(s);
            }
        }
        Err(Error::invalid(
            format!("{} set", self.kind()),
            format!("no PSD {} found in {TRIES} draws", if extreme { "extreme point" } else { "point" }),
        ))
    }

    fn sample_once<R: Rng + ?Sized>(&self, rng: &mut R, extreme: bool) -> Mat {
        let unit = Uniform::new(0.0, 1.0).expect("valid interval");
        match &self.shape {
            SetShape::Box { center, half_width } => {
                let n = center.nrows();
                let mut delta = Mat::zeros(n, n);
                for i in 0..n {
                    for j in i..n {
                        let t: f64 = if extreme { sign(rng) } else { 2.0 * unit.sample(rng) - 1.0 };
                        delta[(i, j)] = t * half_width[(i, j)];
                        delta[(j, i)] = delta[(i, j)];
                    }
                }
                center + delta
            }
            SetShape::Ball { center, radius } => {
                let n = center.nrows();
                let mut delta = Mat::zeros(n, n);
                for i in 0..n {
                    for j in i..n {
                        let g: f64 = StandardNormal.sample(rng);
                        // Off-diagonal coordinates count twice in ‖·‖_F: scale by 1/√2 so the
                        // direction is uniform on the sphere of symmetric matrices.
                        let v = if i == j { g } else { g / std::f64::consts::SQRT_2 };
                        delta[(i, j)] = v;
                        delta[(j, i)] = v;
                    }
                }
                let dim = (n * (n + 1) / 2) as f64;
                let r = if extreme { *radius } else { radius * unit.sample(rng).powf(1.0 / dim) };
                let norm = delta.norm();
                if norm > 0.0 {
                    delta *= r / norm;
                }
                center + delta
            }
            SetShape::Loewner { lower, upper } => {
                let n = lower.nrows();
                let t_half = psd_factor(&(upper - lower));
                let g = Mat::from_fn(n, n, |_, _| StandardNormal.sample(rng));
                let q = g.qr().q();
                let d = Mat::from_diagonal(&nalgebra::DVector::from_fn(n, |_, _| {
                    if extreme { (sign(rng) + 1.0) / 2.0 } else { unit.sample(rng) }
                }));
                symmetrize(&(lower + &t_half * q.clone() * d * q.transpose() * t_half.transpose()))
            }
        }
    }

    /// The maximum of ⟨G, S⟩ over the set (its certified upper bound, [`CovSet::linear_max`]) minus
    /// ⟨G, at⟩, and the maximizer: the gap term of seed 000 Algorithm 1, step 3, and the gain of a
    /// worst case over the set.
    pub(crate) fn linear_gain(&self, g: &Mat, at: &Mat) -> Result<(f64, Mat)> {
        let (s, upper) = self.linear_max(g)?;
        let gain = match upper {
            None => frob_dot(g, &(&s - at)),
            Some(upper) => upper - frob_dot(g, at),
        };
        Ok((gain, s))
    }
}

fn signum0(v: f64) -> f64 {
    if v > 0.0 {
        1.0
    } else if v < 0.0 {
        -1.0
    } else {
        0.0
    }
}

fn sign<R: Rng + ?Sized>(rng: &mut R) -> f64 {
    if rng.next_u32() & 1 == 0 { -1.0 } else { 1.0 }
}
