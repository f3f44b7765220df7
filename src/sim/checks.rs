//! Seed 002's per-trial promises, checked in lanes: the generalized H2 ellipsoid
//! e_z\[t]ᵀ Q\[t] e_z\[t] ≤ E_t at every step (Theorem 3.1 on (5.6)–(5.7)), as each error arrives, and
//! the H∞-λ ratio (Σ_{k<N} |e_z\[k]|² + e\[N]ᵀ S e\[N]) / E_N < bound ((5.9)–(5.10)) once the block
//! has ended. E_t is the input energy of the trial so far ([`crate::sim::block::Workspace`]).

use crate::filter::design::PerTrialBound;
use crate::sim::block::Workspace;
use crate::sim::lanes::{self, LANES, Row};
use crate::sim::mc_stats::FilterStats;
use crate::sim::scenario::Scenario;

/// The ellipsoid check of filter f at step k: e = e_z\[k], `energy` = E_k; a lane that breaks it
/// at any step is marked in `broke`.
pub fn ellipsoid(
    sc: &Scenario,
    f: usize,
    k: usize,
    e: &[Row],
    energy: &Row,
    active: usize,
    st: &mut FilterStats,
    broke: &mut Row,
) {
    let Some(Some(PerTrialBound::Ellipsoid { weights })) = sc.ratios.map(|rc| rc.bounds[f]) else { return };
    let Some(q) = weights.get(k) else { return };
    let mut v = [0.0; LANES];
    lanes::quadratic(q, e, &mut v);
    for l in 0..active {
        let ratio = v[l] / energy[l];
        st.max_ratio = st.max_ratio.max(ratio);
        // Equality is attained by the worst input: allow rounding only.
        if ratio > 1.0 + 1e-9 {
            broke[l] = 1.0;
        }
    }
}

/// The ratio check of filter f once the block has ended (`ws` holds x\[N], the final states and
/// E_N): `sums` holds Σ_{k<N} |e_z\[k]|² per lane, e = x − s, in error coordinates
/// x − s = (I − M) x − ε, = −ε for M = I.
pub(crate) fn terminal(sc: &Scenario, ws: &mut Workspace, f: usize, sums: &Row, active: usize, st: &mut FilterStats) {
    let Some(Some(PerTrialBound::Ratio { bound, terminal_weight })) = sc.ratios.map(|rc| rc.bounds[f]) else {
        return;
    };
    let nx = ws.x.len();
    let (e, mx) = ws.scratch.split_at_mut(nx);
    match sc.form(f) {
        None => e.copy_from_slice(&ws.x),
        Some(form) if form.identity => e.fill([0.0; LANES]),
        Some(form) => {
            let mx = &mut mx[..nx];
            lanes::gemm(&form.m, &ws.x, false, mx);
            lanes::difference(&ws.x, mx, e);
        }
    }
    lanes::subtract(&ws.s[f], e);
    let mut v = [0.0; LANES];
    lanes::quadratic(terminal_weight, e, &mut v);
    for l in 0..active {
        let ratio = (sums[l] + v[l]) / ws.energy[l];
        st.max_ratio = st.max_ratio.max(ratio);
        st.violations += (ratio >= *bound) as u64;
    }
}
