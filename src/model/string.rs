//! The vibrating string of seed 004 §§1–2 (docs/math.md §6): u_tt = c² u_ξξ + v on [0, L], fixed ends, at
//! rest at t = 0 by default, observed by m local averages of u with white measurement noise of a singular
//! intensity W_m, sampled every Δ.
//!
//! **Truth.** u = Σ_{k ≤ M} a_k(t) e_k(ξ), e_k = sqrt(2/L) sin(kπξ/L), and the forcing v is white in
//! time with a spatial covariance diagonal in the eigenfunctions, E\[(v, e_k)(v, e_l)] = q_k δ_kl δ(t),
//! q_k = q0 k^{−decay} (smooth: the modal intensities decay). Each mode is an oscillator
//! ä = −ω_k² a + v_k, ω_k = c kπ/L, discretized exactly: Φ_k = [[cos ωΔ, sin ωΔ/ω], [−ω sin ωΔ, cos ωΔ]]
//! and the integrated noise covariance
//! Q_k = q_k [[Δ/(2ω²) − sin 2ωΔ/(4ω³), sin² ωΔ/(2ω²)], [sin² ωΔ/(2ω²), Δ/2 + sin 2ωΔ/(4ω)]],
//! so the truth is exact at the sample times.
//!
//! **Measurements.** y_j\[k] = (1/h)∫_{s_j−h/2}^{s_j+h/2} u(ξ, t_k) dξ + w_j\[k], the sampled form of
//! continuous white noise of intensity W_m = G Gᵀ: cov w\[k] = W_m/Δ. With fewer noise sources than
//! sensors (G is m × r, r < m) W_m is singular: the problem seed 004 regularizes.
//!
//! **Projections on a growing family** (seed 004 (3), Lemmas 2–3, Theorem 2: r_m = the projections of
//! the observation on ρ₁ … ρ_m). `observation = "eigen"`: ρ_j = e_j; `"tiling"`: ρ_j = (m/L)·1 on
//! [(j−1)L/m, jL/m], m windows tiling [0, L]. Then the noise is the projection of one operator 𝒲 =
//! Σ_{k ≤ noise_rank} w0 k^{−noise_decay} e_k ⊗ e_k (degenerate: finitely many noisy modes), so
//! W_m,ij = (𝒲 ρ_i, ρ_j) = Σ_k w_k (ρ_i, e_k)(ρ_j, e_k), of rank ≤ noise_rank: singular once m
//! exceeds it, whatever m is — the family of seed 004's theorems, grown by `projections` = m.
//!
//! **Time-varying intensities** (seed 004's 𝒱(τ), 𝒲(τ)). q0 and w0 (for windows, the factor of
//! W_m = w0 G Gᵀ) may follow a time profile ([`crate::model::intensity`]): over step k the forcing
//! covariance is s_k Q and the measurement noise covariance r_k W_m/Δ, s_k and r_k the profiles'
//! means over the step; the truth carries them as B\[k] = [√s_k I, 0], D\[k] = [0, √r_k I] on the
//! unit-profile covariances.
//!
//! **Estimated.** z = u at chosen points ξ_p.

use serde::Deserialize;

use crate::error::{Error, Result};
use crate::model::intensity::Intensity;
use crate::model::plant::{Covariances, Plant, Steps};
use crate::numerics::linalg::{Mat, Vector, block_diag, from_rows, symmetrize};

/// The `[string]` table of an experiment file.
#[derive(Deserialize, Clone, Debug)]
#[serde(deny_unknown_fields)]
pub(crate) struct StringFile {
    #[serde(default = "one")]
    pub length: f64,
    #[serde(default = "one")]
    pub speed: f64,
    pub duration: f64,
    pub dt: f64,
    /// M, the number of modes the truth is simulated with.
    pub truth_modes: usize,
    /// q0: a number or a time profile `{ times, values }` ([`Intensity`]).
    #[serde(default = "one_value")]
    pub forcing_intensity: toml::Value,
    #[serde(default = "four")]
    pub forcing_decay: f64,
    /// What the observation is projected on (module docs): `windows` (default: `sensors`,
    /// `sensor_width`, `noise_sources`), `eigen` or `tiling` (`projections`, `noise_*`).
    #[serde(default)]
    pub observation: ObservationKind,
    /// Centres s_j of the sensors' averaging windows.
    #[serde(default)]
    pub sensors: Vec<f64>,
    /// Width h of every window.
    pub sensor_width: Option<f64>,
    /// G (m × r): W_m = G Gᵀ.
    #[serde(default)]
    pub noise_sources: Vec<Vec<f64>>,
    /// m, the number of projections ρ₁ … ρ_m (`eigen`, `tiling`).
    pub projections: Option<usize>,
    /// w0 of 𝒲 = Σ_{k ≤ noise_rank} w0 k^{−noise_decay} e_k ⊗ e_k (`eigen`, `tiling`), or the
    /// factor of W_m = w0 G Gᵀ (`windows`, default 1): a number or a time profile ([`Intensity`]).
    pub noise_intensity: Option<toml::Value>,
    pub noise_decay: Option<f64>,
    pub noise_rank: Option<usize>,
    /// Points ξ_p where u is estimated.
    pub outputs: Vec<f64>,
    /// The random initial state (seed 004's covariance operators 𝒰₀ of u(0) and 𝒰₁ of u_t(0)),
    /// diagonal in the eigenfunctions: Var a_k(0) = initial_displacement · k^{−initial_decay},
    /// Var ȧ_k(0) = initial_velocity · k^{−initial_decay}. Zero (a string at rest) by default.
    #[serde(default)]
    pub initial_displacement: f64,
    #[serde(default)]
    pub initial_velocity: f64,
    #[serde(default = "four")]
    pub initial_decay: f64,
}

#[derive(Deserialize, Clone, Copy, PartialEq, Debug, Default)]
#[serde(rename_all = "snake_case")]
pub(crate) enum ObservationKind {
    #[default]
    Windows,
    Eigen,
    Tiling,
}

/// The functions ρ_j the observation is projected on.
#[derive(Clone, Debug, PartialEq)]
pub enum Observation {
    /// Averages over windows of width `width` centred at `centres` (ρ_j = 1/width on the window).
    Windows { centres: Vec<f64>, width: f64 },
    /// ρ_j = e_j, j = 1 … m.
    Eigen(usize),
}

impl Observation {
    /// (ρ_j, e_k) on [0, `length`]: the window average (1/h)∫ e_k, or δ_jk for eigenfunctions.
    pub(crate) fn inner(&self, length: f64, k: usize, j: usize) -> f64 {
        match self {
            Observation::Eigen(_) => (k == j + 1) as u8 as f64,
            Observation::Windows { centres, width } => {
                let a = k as f64 * std::f64::consts::PI / length;
                let (lo, hi) = (centres[j] - width / 2.0, centres[j] + width / 2.0);
                (2.0 / length).sqrt() * ((a * lo).cos() - (a * hi).cos()) / (a * width)
            }
        }
    }
}

fn one() -> f64 {
    1.0
}
fn one_value() -> toml::Value {
    toml::Value::Float(1.0)
}
fn four() -> f64 {
    4.0
}

/// The validated string model.
#[derive(Clone, Debug)]
pub struct StringModel {
    pub length: f64,
    pub speed: f64,
    pub dt: f64,
    pub truth_modes: usize,
    /// q0(τ): constant, or a profile whose step means scale the forcing ([`StringModel::forcing_scale`]).
    pub forcing: Intensity,
    pub forcing_decay: f64,
    pub observation: Observation,
    /// W_m, the measurement noise intensity (m × m, possibly singular); with a time profile w0(τ)
    /// it is the intensity at w0 = 1, scaled at step k by [`StringModel::noise_scale`].
    pub w_m: Mat,
    /// w0(τ) (module docs).
    pub noise: Intensity,
    pub outputs: Vec<f64>,
    pub initial_displacement: f64,
    pub initial_velocity: f64,
    pub initial_decay: f64,
}

impl StringModel {
    pub(crate) fn from_file(f: &StringFile) -> Result<Self> {
        let key = |k: &str| format!("string.{k}");
        let positive = |k: &str, v: f64| {
            if v > 0.0 && v.is_finite() { Ok(()) } else { Err(Error::invalid(key(k), format!("must be > 0, got {v}"))) }
        };
        positive("length", f.length)?;
        positive("speed", f.speed)?;
        positive("dt", f.dt)?;
        positive("duration", f.duration)?;
        let forcing = Intensity::parse(&key("forcing_intensity"), &f.forcing_intensity)?;
        if !f.forcing_decay.is_finite() {
            return Err(Error::invalid(key("forcing_decay"), format!("must be finite, got {}", f.forcing_decay)));
        }
        if !(f.initial_displacement >= 0.0
            && f.initial_velocity >= 0.0
            && f.initial_displacement.is_finite()
            && f.initial_velocity.is_finite()
            && f.initial_decay.is_finite())
        {
            return Err(Error::invalid(
                key("initial_displacement"),
                "initial_displacement and initial_velocity must be ≥ 0 (and initial_decay finite)",
            ));
        }
        if f.duration < f.dt {
            return Err(Error::invalid(key("duration"), "must be at least one step dt"));
        }
        if f.truth_modes == 0 {
            return Err(Error::invalid(key("truth_modes"), "at least one mode"));
        }
        let l = f.length;
        let (observation, w_m, noise) = observation(f)?;
        for (p, x) in f.outputs.iter().enumerate() {
            if !(*x >= 0.0 && *x <= l) {
                return Err(Error::invalid(format!("string.outputs[{p}]"), format!("{x} is outside [0, {l}]")));
            }
        }
        if f.outputs.is_empty() {
            return Err(Error::invalid(key("outputs"), "at least one point"));
        }
        Ok(StringModel {
            length: l,
            speed: f.speed,
            dt: f.dt,
            truth_modes: f.truth_modes,
            forcing,
            forcing_decay: f.forcing_decay,
            observation,
            w_m,
            noise,
            outputs: f.outputs.clone(),
            initial_displacement: f.initial_displacement,
            initial_velocity: f.initial_velocity,
            initial_decay: f.initial_decay,
        })
    }

    /// ω_k = c kπ/L.
    pub(crate) fn omega(&self, k: usize) -> f64 {
        self.speed * k as f64 * std::f64::consts::PI / self.length
    }
    /// q_k = q0 k^{−decay}, with q0 = 1 when q0 follows a time profile (then scaled per step by
    /// [`StringModel::forcing_scale`]).
    pub fn intensity(&self, k: usize) -> f64 {
        let q0 = match self.forcing {
            Intensity::Constant(q0) => q0,
            Intensity::Profile { .. } => 1.0,
        };
        q0 * (k as f64).powf(-self.forcing_decay)
    }
    /// The factor of the forcing intensity over step k: 1 for a constant q0 (already in
    /// [`StringModel::intensity`]), the profile's mean over the step otherwise (seed 004's 𝒱(τ)).
    pub fn forcing_scale(&self, k: usize) -> f64 {
        if self.forcing.varies() { self.forcing.step_mean(k, self.dt) } else { 1.0 }
    }
    /// The factor of W_m over step k: 1 for a constant w0 (already in W_m), the profile's mean over
    /// the step otherwise (seed 004's 𝒲(τ)).
    pub fn noise_scale(&self, k: usize) -> f64 {
        if self.noise.varies() { self.noise.step_mean(k, self.dt) } else { 1.0 }
    }
    /// Whether a forcing or noise intensity changes with time.
    pub fn varies(&self) -> bool {
        self.forcing.varies() || self.noise.varies()
    }
    /// (Var a_k(0), Var ȧ_k(0)): the modal variances of 𝒰₀ and 𝒰₁.
    pub fn initial(&self, k: usize) -> (f64, f64) {
        let decay = (k as f64).powf(-self.initial_decay);
        (self.initial_displacement * decay, self.initial_velocity * decay)
    }
    /// e_k(ξ).
    pub fn eigenfunction(&self, k: usize, xi: f64) -> f64 {
        (2.0 / self.length).sqrt() * (k as f64 * std::f64::consts::PI * xi / self.length).sin()
    }
    /// (ρ_j, e_k): see `Observation::inner`.
    pub fn observe(&self, k: usize, j: usize) -> f64 {
        self.observation.inner(self.length, k, j)
    }
    /// m, the number of observed projections.
    pub(crate) fn n_sensors(&self) -> usize {
        match &self.observation {
            Observation::Eigen(m) => *m,
            Observation::Windows { centres, .. } => centres.len(),
        }
    }

    /// The truth (M modes) as a plant on the horizon N = round(duration/Δ), with its covariances:
    /// state (a_1, ȧ_1, …, a_M, ȧ_M), noise blocks `process` (2M) and `measurement` (m).
    pub fn plant(&self, duration: f64) -> (Plant, Covariances) {
        let (mm, m, p) = (self.truth_modes, self.n_sensors(), self.outputs.len());
        let nx = 2 * mm;
        let dt = self.dt;
        let mut blocks_a = Vec::with_capacity(mm);
        let mut blocks_q = Vec::with_capacity(mm);
        for k in 1..=mm {
            let w = self.omega(k);
            let (s, c) = (w * dt).sin_cos();
            blocks_a.push(Mat::from_row_slice(2, 2, &[c, s / w, -w * s, c]));
            let q = self.intensity(k);
            let s2 = (2.0 * w * dt).sin();
            let cross = s * s / (2.0 * w * w);
            blocks_q.push(
                q * Mat::from_row_slice(
                    2,
                    2,
                    &[dt / (2.0 * w * w) - s2 / (4.0 * w * w * w), cross, cross, dt / 2.0 + s2 / (4.0 * w)],
                ),
            );
        }
        let a = block_diag(&blocks_a.iter().collect::<Vec<_>>());
        let q = block_diag(&blocks_q.iter().collect::<Vec<_>>());
        let c = Mat::from_fn(m, nx, |j, i| if i % 2 == 0 { self.observe(i / 2 + 1, j) } else { 0.0 });
        let cz =
            Mat::from_fn(p, nx, |o, i| if i % 2 == 0 { self.eigenfunction(i / 2 + 1, self.outputs[o]) } else { 0.0 });
        let horizon = ((duration / dt).round() as usize).max(1);
        let x0 = Mat::from_diagonal(&Vector::from_iterator(
            nx,
            (0..nx).map(|i| {
                let (d, v) = self.initial(i / 2 + 1);
                if i % 2 == 0 { d } else { v }
            }),
        ));
        let (mut plant, cov) = sampled(horizon, a, c, cz, q, &self.w_m / dt, x0);
        // Time-varying intensities: the noise blocks keep their unit-profile covariances and enter
        // through B[k] = [√s_k I, 0], D[k] = [0, √r_k I] (s_k, r_k the step means), so the sampler,
        // the Monte Carlo and the exact analysis see the same time-varying plant.
        if self.varies() {
            let steps = plant.steps();
            let scaled = |m: &Mat, forcing: f64, noise: f64| {
                let mut out = m.clone();
                out.columns_mut(0, nx).scale_mut(forcing.sqrt());
                out.columns_mut(nx, m.ncols() - nx).scale_mut(noise.sqrt());
                out
            };
            let (b, d) = (plant.b.at(0).clone(), plant.d.at(0).clone());
            plant.b = Steps::per_step((0..steps).map(|k| scaled(&b, self.forcing_scale(k), 1.0)).collect());
            plant.d = Steps::per_step((0..steps).map(|k| scaled(&d, 1.0, self.noise_scale(k))).collect());
        }
        (plant, cov)
    }
}

/// The projections ρ_j and W_m of a `[string]` table (module docs), each error naming its key.
fn observation(f: &StringFile) -> Result<(Observation, Mat, Intensity)> {
    let key = |k: &str| format!("string.{k}");
    let l = f.length;
    let projected = [("projections", f.projections.is_some())]
        .into_iter()
        .chain([("noise_decay", f.noise_decay.is_some()), ("noise_rank", f.noise_rank.is_some())]);
    let noise = match &f.noise_intensity {
        Some(v) => Some(Intensity::parse(&key("noise_intensity"), v)?),
        None => None,
    };
    let windowed = [("sensors", !f.sensors.is_empty()), ("sensor_width", f.sensor_width.is_some())]
        .into_iter()
        .chain([("noise_sources", !f.noise_sources.is_empty())]);
    let (stray, kind) = if f.observation == ObservationKind::Windows {
        (projected.collect::<Vec<_>>(), "\"eigen\" or \"tiling\"")
    } else {
        (windowed.collect::<Vec<_>>(), "\"windows\"")
    };
    if let Some((k, _)) = stray.iter().find(|(_, given)| *given) {
        return Err(Error::invalid(key(k), format!("only with observation = {kind}")));
    }
    if f.observation == ObservationKind::Windows {
        let width = f.sensor_width.ok_or_else(|| Error::invalid(key("sensor_width"), "missing"))?;
        if !(width > 0.0 && width.is_finite()) {
            return Err(Error::invalid(key("sensor_width"), format!("must be > 0, got {width}")));
        }
        if f.sensors.is_empty() {
            return Err(Error::invalid(key("sensors"), "at least one sensor"));
        }
        for (j, s) in f.sensors.iter().enumerate() {
            if !(s - width / 2.0 >= 0.0 && s + width / 2.0 <= l) {
                return Err(Error::invalid(
                    format!("string.sensors[{j}]"),
                    format!("the window [{}, {}] leaves the string [0, {l}]", s - width / 2.0, s + width / 2.0),
                ));
            }
        }
        let cols = f.noise_sources.first().map_or(0, Vec::len);
        let g = from_rows(&key("noise_sources"), &f.noise_sources, Some((f.sensors.len(), cols)))?;
        // W_m = w0 G Gᵀ; w0 = 1 (and G Gᵀ exactly) unless given as a constant.
        let noise = noise.unwrap_or(Intensity::Constant(1.0));
        let w_m = match noise {
            Intensity::Constant(w0) if w0 != 1.0 => w0 * (&g * g.transpose()),
            _ => &g * g.transpose(),
        };
        return Ok((Observation::Windows { centres: f.sensors.clone(), width }, w_m, noise));
    }
    let m = f.projections.ok_or_else(|| Error::invalid(key("projections"), "missing: the number m of projections"))?;
    if m == 0 {
        return Err(Error::invalid(key("projections"), "at least one projection"));
    }
    if f.observation == ObservationKind::Eigen && m > f.truth_modes {
        return Err(Error::invalid(
            key("projections"),
            format!("{m} eigenfunction projections but the truth has only {} modes", f.truth_modes),
        ));
    }
    let noise = noise.ok_or_else(|| Error::invalid(key("noise_intensity"), "missing"))?;
    // A constant w0 inside R as always; a profile's per-step factor scales W_m at w0 = 1.
    let w0 = match noise {
        Intensity::Constant(w0) => w0,
        Intensity::Profile { .. } => 1.0,
    };
    let decay = f.noise_decay.unwrap_or(0.0);
    let rank =
        f.noise_rank.ok_or_else(|| Error::invalid(key("noise_rank"), "missing: the number of noisy modes of 𝒲"))?;
    if !decay.is_finite() {
        return Err(Error::invalid(key("noise_decay"), format!("must be finite, got {decay}")));
    }
    let obs = match f.observation {
        ObservationKind::Eigen => Observation::Eigen(m),
        _ => Observation::Windows {
            centres: (0..m).map(|j| (j as f64 + 0.5) * l / m as f64).collect(),
            width: l / m as f64,
        },
    };
    // R_jk = (ρ_j, e_k) for the noisy modes k ≤ rank, W_m = R diag(w_k) Rᵀ.
    let r = Mat::from_fn(m, rank, |j, k| obs.inner(l, k + 1, j) * (w0 * ((k + 1) as f64).powf(-decay)).sqrt());
    Ok((obs, symmetrize(&(&r * r.transpose())), noise))
}

/// x\[k+1] = A x + w_p, y = C x + w_m, z = Cz x with w_p ~ (0, Q), w_m ~ (0, R) and x0 ~ (0, X0)
/// independent (X0 = 0: a string at rest): the sampled form of the truth and of every Galerkin
/// model, with noise blocks `process` and `measurement`.
pub fn sampled(horizon: usize, a: Mat, c: Mat, cz: Mat, q: Mat, r: Mat, x0: Mat) -> (Plant, Covariances) {
    let (nx, m, p) = (a.nrows(), c.nrows(), cz.nrows());
    let mut b = Mat::zeros(nx, nx + m);
    b.view_mut((0, 0), (nx, nx)).fill_with_identity();
    let mut d = Mat::zeros(m, nx + m);
    d.view_mut((0, nx), (m, m)).fill_with_identity();
    let plant = Plant::new(
        horizon,
        a,
        b,
        c,
        d,
        cz,
        Mat::zeros(p, nx + m),
        Vector::zeros(nx),
        0,
        Vec::new(),
        vec![("process".into(), nx), ("measurement".into(), m)],
    );
    (plant, Covariances::new(vec![x0, q, r]))
}
