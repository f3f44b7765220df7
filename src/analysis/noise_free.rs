//! The noise-free output of seed 003's Figs. 3–4 ("z(t) без шумов", drawn beside the noisy z(t)
//! and its estimates): what the plant's known input alone makes of z, the curve the noisy
//! trajectories scatter around.

use crate::model::plant::Plant;
use crate::numerics::linalg::{Mat, Vector};

/// z̄\[k] for k = 0..N (columns are steps) of seed 003 (5.1) with w ≡ 0: the mean dynamics driven by
/// the known input from E x(0), x̄\[k+1] = A\[k] x̄\[k] + r\[k], z̄\[k] = Cz\[k] x̄\[k]. This is E z\[k] for
/// zero-mean noise: the multiplicative factors of (3.1) have mean zero and are independent of
/// x\[k], and a dropout touches only the measurement. With Markov modes (seed 001) A depends on
/// θ\[k], so the mean is carried per mode, m_j\[k] = E[x\[k] 1{θ\[k] = j}] (the first moments of
/// seed 001 eq (10)): m_i\[k+1] = Σ_j Π_ji (A_j\[k] m_j\[k] + p_j(k) r\[k]), x̄ = Σ_j m_j. A scenario's
/// deterministic disturbance is not the known input and is left out. None when the plant has no
/// known input: then there is no reference beyond x(0)'s decaying mean.
pub(crate) fn noise_free_output(plant: &Plant) -> Option<Mat> {
    if plant.known_input.is_empty() {
        return None;
    }
    let (pi, probs) = (plant.transition(), plant.mode_probabilities());
    let q = pi.nrows();
    let mut m: Vec<Vector> = probs[0].iter().map(|p| &plant.x0_mean * *p).collect();
    let mut out = Mat::zeros(plant.nz(), plant.steps());
    for k in 0..plant.steps() {
        let mean = m.iter().fold(Vector::zeros(plant.nx()), |acc, mj| acc + mj);
        out.column_mut(k).copy_from(&(plant.cz_at(k) * mean));
        if k == plant.horizon {
            break;
        }
        let r = plant.r_at(k).cloned().unwrap_or_else(|| Vector::zeros(plant.nx()));
        let pushed: Vec<Vector> = (0..q).map(|j| plant.a_of(k, j) * &m[j] + &r * probs[k][j]).collect();
        m = (0..q).map(|i| (0..q).fold(Vector::zeros(plant.nx()), |acc, j| acc + &pushed[j] * pi[(j, i)])).collect();
    }
    Some(out)
}
