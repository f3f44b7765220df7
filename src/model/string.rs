//! The vibrating string of seed 004 §§1–2 (SPEC §6): u_tt = c² u_ξξ + v on [0, L], fixed ends, at
//! rest at t = 0, observed by m local averages of u with white measurement noise of a singular
//! intensity W_m, sampled every Δ.
//!
//! **Truth.** u = Σ_{k ≤ M} a_k(t) e_k(ξ), e_k = sqrt(2/L) sin(kπξ/L), and the forcing v is white in
//! time with a spatial covariance diagonal in the eigenfunctions, E[(v, e_k)(v, e_l)] = q_k δ_kl δ(t),
//! q_k = q0 k^{−decay} (smooth: the modal intensities decay). Each mode is an oscillator
//! ä = −ω_k² a + v_k, ω_k = c kπ/L, discretized exactly: Φ_k = [[cos ωΔ, sin ωΔ/ω], [−ω sin ωΔ, cos ωΔ]]
//! and the integrated noise covariance
//! Q_k = q_k [[Δ/(2ω²) − sin 2ωΔ/(4ω³), sin² ωΔ/(2ω²)], [sin² ωΔ/(2ω²), Δ/2 + sin 2ωΔ/(4ω)]],
//! so the truth is exact at the sample times.
//!
//! **Measurements.** y_j[k] = (1/h)∫_{s_j−h/2}^{s_j+h/2} u(ξ, t_k) dξ + w_j[k], the sampled form of
//! continuous white noise of intensity W_m = G Gᵀ: cov w[k] = W_m/Δ. With fewer noise sources than
//! sensors (G is m × r, r < m) W_m is singular: the problem seed 004 regularizes.
//!
//! **Estimated.** z = u at chosen points ξ_p.

use serde::Deserialize;

use crate::error::{Error, Result};
use crate::model::plant::{Covariances, Plant};
use crate::numerics::linalg::{Mat, Vector, block_diag, from_rows};

/// The `[string]` table of an experiment file.
#[derive(Deserialize, Clone, Debug)]
#[serde(deny_unknown_fields)]
pub struct StringFile {
    #[serde(default = "one")]
    pub length: f64,
    #[serde(default = "one")]
    pub speed: f64,
    pub duration: f64,
    pub dt: f64,
    /// M, the number of modes the truth is simulated with.
    pub truth_modes: usize,
    #[serde(default = "one")]
    pub forcing_intensity: f64,
    #[serde(default = "four")]
    pub forcing_decay: f64,
    /// Centres s_j of the sensors' averaging windows.
    pub sensors: Vec<f64>,
    /// Width h of every window.
    pub sensor_width: f64,
    /// G (m × r): W_m = G Gᵀ.
    pub noise_sources: Vec<Vec<f64>>,
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

fn one() -> f64 {
    1.0
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
    pub forcing_intensity: f64,
    pub forcing_decay: f64,
    pub sensors: Vec<f64>,
    pub sensor_width: f64,
    /// W_m, the measurement noise intensity (m × m, possibly singular).
    pub w_m: Mat,
    pub outputs: Vec<f64>,
    pub initial_displacement: f64,
    pub initial_velocity: f64,
    pub initial_decay: f64,
}

impl StringModel {
    pub fn from_file(f: &StringFile) -> Result<Self> {
        let key = |k: &str| format!("string.{k}");
        let positive = |k: &str, v: f64| {
            if v > 0.0 && v.is_finite() { Ok(()) } else { Err(Error::invalid(key(k), format!("must be > 0, got {v}"))) }
        };
        positive("length", f.length)?;
        positive("speed", f.speed)?;
        positive("dt", f.dt)?;
        positive("duration", f.duration)?;
        positive("sensor_width", f.sensor_width)?;
        if !(f.forcing_intensity >= 0.0 && f.forcing_decay.is_finite()) {
            return Err(Error::invalid(key("forcing_intensity"), "must be ≥ 0 (and forcing_decay finite)"));
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
        if f.sensors.is_empty() {
            return Err(Error::invalid(key("sensors"), "at least one sensor"));
        }
        for (j, s) in f.sensors.iter().enumerate() {
            if !(s - f.sensor_width / 2.0 >= 0.0 && s + f.sensor_width / 2.0 <= l) {
                return Err(Error::invalid(
                    format!("string.sensors[{j}]"),
                    format!(
                        "the window [{}, {}] leaves the string [0, {l}]",
                        s - f.sensor_width / 2.0,
                        s + f.sensor_width / 2.0
                    ),
                ));
            }
        }
        for (p, x) in f.outputs.iter().enumerate() {
            if !(*x >= 0.0 && *x <= l) {
                return Err(Error::invalid(format!("string.outputs[{p}]"), format!("{x} is outside [0, {l}]")));
            }
        }
        if f.outputs.is_empty() {
            return Err(Error::invalid(key("outputs"), "at least one point"));
        }
        let m = f.sensors.len();
        let cols = f.noise_sources.first().map_or(0, Vec::len);
        let g = from_rows(&key("noise_sources"), &f.noise_sources, Some((m, cols)))?;
        Ok(StringModel {
            length: l,
            speed: f.speed,
            dt: f.dt,
            truth_modes: f.truth_modes,
            forcing_intensity: f.forcing_intensity,
            forcing_decay: f.forcing_decay,
            sensors: f.sensors.clone(),
            sensor_width: f.sensor_width,
            w_m: &g * g.transpose(),
            outputs: f.outputs.clone(),
            initial_displacement: f.initial_displacement,
            initial_velocity: f.initial_velocity,
            initial_decay: f.initial_decay,
        })
    }

    /// ω_k = c kπ/L.
    pub fn omega(&self, k: usize) -> f64 {
        self.speed * k as f64 * std::f64::consts::PI / self.length
    }
    /// q_k = q0 k^{−decay}.
    pub fn intensity(&self, k: usize) -> f64 {
        self.forcing_intensity * (k as f64).powf(-self.forcing_decay)
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
    /// (1/h)∫ e_k over sensor j's window.
    pub fn sensor_average(&self, k: usize, j: usize) -> f64 {
        let a = k as f64 * std::f64::consts::PI / self.length;
        let (lo, hi) = (self.sensors[j] - self.sensor_width / 2.0, self.sensors[j] + self.sensor_width / 2.0);
        (2.0 / self.length).sqrt() * ((a * lo).cos() - (a * hi).cos()) / (a * self.sensor_width)
    }
    pub fn n_sensors(&self) -> usize {
        self.sensors.len()
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
        let c = Mat::from_fn(m, nx, |j, i| if i % 2 == 0 { self.sensor_average(i / 2 + 1, j) } else { 0.0 });
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
        sampled(horizon, a, c, cz, q, &self.w_m / dt, x0)
    }
}

/// x[k+1] = A x + w_p, y = C x + w_m, z = Cz x with w_p ~ (0, Q), w_m ~ (0, R) and x0 ~ (0, X0)
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
