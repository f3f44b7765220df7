//! One block of `LANES` trials simulated together (docs/math.md §6): the plant
//! x\[k+1] = A_θ x + B_θ w + Σ_i ζ_i (A_i x + B_i w) + r, y = C_θ x + D_θ w + …, z = Cz x + Dz w + …
//! (seed 003 (3.1) for the factors, seed 001 (1) for the modes), and every filter on the same y
//! (common random numbers), s\[k+1] = Af s + Bf y + Gf r, ẑ = Cf s + Df y, or in error coordinates
//! ε\[k+1] = F ε + E w + R r, e = H ε + G w ([`crate::analysis::exact::error_form`]).
//! Each step is a few products of a matrix with the block's n × LANES lane matrices.

use crate::analysis::exact::ErrorForm;
use crate::numerics::linalg::Mat;
use crate::numerics::linop::LinOp;
use crate::sim::lanes::{self, LANES, Row};
use crate::sim::noise::LaneDraw;
use crate::sim::scenario::Scenario;
use crate::sim::stacked::ModeLanes;

/// Preallocated per-thread buffers: a block allocates nothing.
pub(crate) struct Workspace {
    pub draw: LaneDraw,
    pub(super) x: Vec<Row>,
    x_next: Vec<Row>,
    y: Vec<Row>,
    z: Vec<Row>,
    zhat: Vec<Row>,
    /// e = z − ẑ of the current filter and step.
    err: Vec<Row>,
    /// Each filter's state (or error state ε) at the current step.
    pub(super) s: Vec<Vec<Row>>,
    s_next: Vec<Vec<Row>>,
    /// A stacked filter's product ([`crate::sim::stacked`]): its next state, then its output.
    stacked_out: Vec<Vec<Row>>,
    /// The lanes' modes at the current step, for the stacked products.
    mode_lanes: ModeLanes,
    /// r\[k] in every lane.
    r: Vec<Row>,
    tmp: Vec<Row>,
    /// Two vectors' room (of the plant's state size or more) for the per-trial checks.
    pub(super) scratch: Vec<Row>,
    /// Input energy E_k of each lane so far (seed 002's per-trial checks).
    pub(super) energy: Row,
    /// The visits read z, ẑ and y (the sample trajectories): the plant is always simulated.
    outputs: bool,
}

impl Workspace {
    pub fn new(sc: &Scenario) -> Self {
        let p = sc.plant;
        let ns = sc.filters.iter().map(|r| r.ns()).max().unwrap_or(0);
        let wide = p.nx().max(p.ny()).max(p.nz()).max(p.nw()).max(ns);
        Workspace {
            draw: sc.sampler.lanes(),
            x: lanes::zeros(p.nx()),
            x_next: lanes::zeros(p.nx()),
            y: lanes::zeros(p.ny()),
            z: lanes::zeros(p.nz()),
            zhat: lanes::zeros(p.nz()),
            err: lanes::zeros(p.nz()),
            s: sc.filters.iter().map(|r| lanes::zeros(r.ns())).collect(),
            s_next: sc.filters.iter().map(|r| lanes::zeros(r.ns())).collect(),
            stacked_out: (0..sc.filters.len()).map(|f| lanes::zeros(sc.stacked(f).map_or(0, |st| st.rows()))).collect(),
            mode_lanes: ModeLanes::new(sc.ops.modes),
            r: lanes::zeros(p.nx()),
            tmp: lanes::zeros(wide),
            scratch: lanes::zeros(2 * wide),
            energy: [0.0; LANES],
            outputs: false,
        }
    }

    /// A workspace whose visits get z, ẑ and y ([`StepView::outputs`]) whatever the scenario needs.
    pub fn with_outputs(sc: &Scenario) -> Self {
        Workspace { outputs: true, ..Workspace::new(sc) }
    }
}

/// A matrix of the trial loop: a plant operator (dense or CSR) or a filter's dense gain.
#[derive(Clone, Copy)]
enum Op<'a> {
    Lin(&'a LinOp),
    Dense(&'a Mat),
}

impl Op<'_> {
    #[inline(always)]
    fn apply<const C: usize>(self, x: &[Row], add: bool, out: &mut [Row]) {
        match self {
            Op::Lin(op) => lanes::apply_in::<C>(op, x, add, out),
            Op::Dense(m) => lanes::gemm_in::<C>(m, x, add, out),
        }
    }
    fn addr(self) -> *const () {
        match self {
            Op::Lin(op) => op as *const LinOp as *const (),
            Op::Dense(m) => m as *const Mat as *const (),
        }
    }
}

/// out ← M_θ x (`add`: out + M_θ x), lane l using the matrix of its mode θ_l. One product when the
/// matrix does not depend on the mode, or every active lane is in the same mode and nothing is
/// added; otherwise one product per mode present, each kept (or added) where the lane is in that
/// mode. With `add`, out + (M_θ x) is then one sum whatever the other lanes' modes, so a lane's
/// result never depends on which lanes share its block.
#[allow(clippy::too_many_arguments)]
#[inline(always)]
fn by_mode<'a, const C: usize>(
    modes: &[u32; LANES],
    active: usize,
    n_modes: usize,
    op: impl Fn(usize) -> Op<'a>,
    x: &[Row],
    add: bool,
    out: &mut [Row],
    tmp: &mut [Row],
) {
    let first = op(0);
    if n_modes == 1 || (1..n_modes).all(|m| op(m).addr() == first.addr()) {
        return first.apply::<C>(x, add, out);
    }
    let m0 = modes[0];
    if !add && modes[..active].iter().all(|&m| m == m0) {
        return op(m0 as usize).apply::<C>(x, add, out);
    }
    let tmp = &mut tmp[..out.len()];
    for m in 0..n_modes {
        if modes[..active].contains(&(m as u32)) {
            op(m).apply::<C>(x, false, tmp);
            lanes::select(modes, m as u32, tmp, add, out);
        }
    }
}

/// Adds Σ_i ζ_i(k) M_i x to `out` for the matrix `which` (0 = A, …, 5 = Dz) of every factor.
#[inline(always)]
fn add_factors<const C: usize>(
    sc: &Scenario,
    which: usize,
    k: usize,
    zeta: &[Row],
    x: &[Row],
    out: &mut [Row],
    tmp: &mut [Row],
) {
    let ops = sc.ops;
    for (i, f) in ops.factors.iter().enumerate() {
        if let Some(op) = f[k][which] {
            let tmp = &mut tmp[..out.len()];
            lanes::apply_in::<C>(&ops.ops[op], x, false, tmp);
            lanes::add_scaled(&zeta[i], tmp, out);
        }
    }
}

/// The plant's side of step k: the truth, filter f's estimate of it, and the measurement.
pub(crate) struct Outputs<'a> {
    pub z: &'a [Row],
    pub zhat: &'a [Row],
    /// y\[k] (a filter's innovation in its own coordinates, [`crate::analysis::nees`]).
    pub y: &'a [Row],
}

/// What the engine shows of step k and filter f, over the block's lanes.
pub(crate) struct StepView<'a> {
    pub k: usize,
    pub f: usize,
    /// e = z − ẑ.
    pub e: &'a [Row],
    /// z, ẑ and y, None when the plant was not simulated (see [`simulate`]).
    pub outputs: Option<Outputs<'a>>,
    /// The lanes' input energy E_k before w\[k] (maintained only with per-trial checks).
    pub energy: &'a Row,
    /// θ\[k] per lane.
    pub modes: &'a [u32; LANES],
    /// w\[k] and the filter's state s\[k], or its error state ε = s − M x when
    /// `error_coordinates` (for the innovation, [`crate::analysis::nees`]).
    pub w: &'a [Row],
    pub s: &'a [Row],
    pub error_coordinates: bool,
    /// The innovation whitened by the step's NIS weight, Lᵀν with W = L Lᵀ, when the filter's
    /// product computes it ([`crate::sim::stacked`]; zero at a step without a weight).
    pub whitened: Option<&'a [Row]>,
}

/// Simulates trials first..first+active in the lanes of `ws` and calls `visit` for each step k and
/// filter f. A filter with an error form carries ε = s − M x instead of s and gets e from ε and w
/// directly; its ẑ is then z − e, for display only. When every filter has an error form, nothing
/// reads x\[N] ([`Scenario::errors_alone`]) and the workspace was not made
/// [`Workspace::with_outputs`], the plant's x, y and z are not simulated at all: the errors need
/// none of them, and are the same bits either way. Otherwise on return `ws` holds x\[N]; it always
/// holds every filter's final state.
pub(crate) fn simulate(sc: &Scenario, ws: &mut Workspace, first: u64, active: usize, visit: impl FnMut(StepView)) {
    match lanes::build() {
        // SAFETY: build() names only a build whose features the processor has.
        #[cfg(target_arch = "x86_64")]
        lanes::Build::Avx512 => unsafe { simulate_avx512(sc, ws, first, active, visit) },
        #[cfg(target_arch = "x86_64")]
        lanes::Build::Avx2 => unsafe { simulate_avx2(sc, ws, first, active, visit) },
        _ => simulate_lanes::<{ lanes::CHUNK }>(sc, ws, first, active, visit),
    }
}

/// [`simulate`] compiled for AVX-512: eight lanes per instruction, the same bits.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx512f,avx512vl,avx512dq,avx512bw,avx2")]
unsafe fn simulate_avx512(sc: &Scenario, ws: &mut Workspace, first: u64, active: usize, visit: impl FnMut(StepView)) {
    simulate_lanes::<{ lanes::WIDE_CHUNK }>(sc, ws, first, active, visit)
}

/// [`simulate`] compiled for AVX2: four lanes per instruction instead of SSE2's two. Rust never
/// fuses a·b + c, so each lane's arithmetic, and every figure, is the same bits either way.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2")]
unsafe fn simulate_avx2(sc: &Scenario, ws: &mut Workspace, first: u64, active: usize, visit: impl FnMut(StepView)) {
    simulate_lanes::<{ lanes::CHUNK }>(sc, ws, first, active, visit)
}

#[inline(always)]
fn simulate_lanes<const C: usize>(
    sc: &Scenario,
    ws: &mut Workspace,
    first: u64,
    active: usize,
    mut visit: impl FnMut(StepView),
) {
    let plant = ws.outputs || !sc.errors_alone();
    let p = sc.plant;
    let ops = sc.ops;
    let nm = ops.modes;
    sc.sampler.start(sc.seed, sc.index, first, active, &mut ws.draw);
    ws.x.copy_from_slice(&ws.draw.x0);
    if let Some(rc) = sc.ratios {
        let e0 = &mut ws.scratch[..p.nx()];
        e0.copy_from_slice(&ws.x);
        lanes::add_vector(-1.0, p.x0_mean.as_slice(), e0);
        lanes::quadratic(&rc.x0_weight, e0, &mut ws.energy);
    }
    for (f, (s, r)) in ws.s.iter_mut().zip(sc.filters).enumerate() {
        for (row, &v) in s.iter_mut().zip(r.s0.iter()) {
            *row = [v; LANES];
        }
        if let Some(form) = sc.form(f) {
            let t = &mut ws.tmp[..s.len()];
            lanes::gemm(&form.m, &ws.x, false, t);
            lanes::subtract(t, s);
        }
    }
    for k in 0..p.steps() {
        sc.sampler.step(k, &mut ws.draw);
        ws.mode_lanes.update(&ws.draw.modes, active);
        let (draw, modes) = (&ws.draw, &ws.draw.modes);
        let w = &draw.w;
        if plant {
            by_mode::<C>(modes, active, nm, |m| Op::Lin(ops.c(k, m)), &ws.x, false, &mut ws.y, &mut ws.tmp);
            by_mode::<C>(modes, active, nm, |m| Op::Lin(ops.d(k, m)), w, true, &mut ws.y, &mut ws.tmp);
            lanes::apply_in::<C>(&ops.ops[ops.cz[k]], &ws.x, false, &mut ws.z);
            lanes::apply_in::<C>(&ops.ops[ops.dz[k]], w, true, &mut ws.z);
        }
        if plant && !ops.factors.is_empty() {
            let zeta = &draw.zeta;
            add_factors::<C>(sc, 2, k, zeta, &ws.x, &mut ws.y, &mut ws.tmp);
            add_factors::<C>(sc, 3, k, zeta, w, &mut ws.y, &mut ws.tmp);
            add_factors::<C>(sc, 4, k, zeta, &ws.x, &mut ws.z, &mut ws.tmp);
            add_factors::<C>(sc, 5, k, zeta, w, &mut ws.z, &mut ws.tmp);
        }
        let r = p.r_at(k);
        if let Some(r) = r {
            for (row, &v) in ws.r.iter_mut().zip(r.iter()) {
                *row = [v; LANES];
            }
        }
        for (f, real) in sc.filters.iter().enumerate() {
            let form: Option<&ErrorForm> = sc.form(f);
            if let Some(st) = sc.stacked(f) {
                let (ns, input) = (st.ns(), if form.is_some() { w } else { &ws.y });
                let segs: [&[Row]; 3] = [&ws.s[f], input, &ws.r];
                let used = if r.is_some() && st.has_known_input() { 3 } else { 2 };
                // The last step's next state is never used (nor are its gains Af, Bf, Gf).
                let rows = if k < p.horizon { 0..st.rows() } else { ns..st.rows() };
                let out = &mut ws.stacked_out[f];
                st.product::<C>(k, rows.clone(), &segs[..used], &ws.mode_lanes, &mut out[rows]);
                let output = &out[st.output()];
                let whitened = st.whitened().map(|r| &out[r]);
                let (e, zhat) = match form {
                    None => {
                        lanes::difference(&ws.z, output, &mut ws.err);
                        (&ws.err[..], output)
                    }
                    Some(_) => {
                        if plant {
                            lanes::difference(&ws.z, output, &mut ws.zhat);
                        }
                        (output, &ws.zhat[..])
                    }
                };
                visit(StepView {
                    k,
                    f,
                    e,
                    outputs: plant.then_some(Outputs { z: &ws.z, zhat, y: &ws.y }),
                    energy: &ws.energy,
                    modes,
                    w,
                    s: &ws.s[f],
                    error_coordinates: form.is_some(),
                    whitened,
                });
                if k < p.horizon {
                    ws.s[f].copy_from_slice(&out[..ns]);
                }
                continue;
            }
            let s = &ws.s[f];
            match form {
                None => {
                    let g = |m| real.gains(k, m);
                    by_mode::<C>(modes, active, nm, |m| Op::Dense(&g(m).cf), s, false, &mut ws.zhat, &mut ws.tmp);
                    by_mode::<C>(modes, active, nm, |m| Op::Dense(&g(m).df), &ws.y, true, &mut ws.zhat, &mut ws.tmp);
                    lanes::difference(&ws.z, &ws.zhat, &mut ws.err);
                }
                Some(fm) => {
                    let a = |m: usize| &fm.steps[k][m];
                    by_mode::<C>(modes, active, nm, |m| Op::Dense(&a(m).h), s, false, &mut ws.err, &mut ws.tmp);
                    by_mode::<C>(modes, active, nm, |m| Op::Dense(&a(m).g), w, true, &mut ws.err, &mut ws.tmp);
                    if plant {
                        lanes::difference(&ws.z, &ws.err, &mut ws.zhat);
                    }
                }
            }
            let error_coordinates = form.is_some();
            visit(StepView {
                k,
                f,
                e: &ws.err,
                outputs: plant.then_some(Outputs { z: &ws.z, zhat: &ws.zhat, y: &ws.y }),
                energy: &ws.energy,
                modes,
                w,
                s,
                error_coordinates,
                whitened: None,
            });
            if k < p.horizon {
                let next = &mut ws.s_next[f];
                match form {
                    None => {
                        let g = |m| real.gains(k, m);
                        by_mode::<C>(modes, active, nm, |m| Op::Dense(&g(m).af), s, false, next, &mut ws.tmp);
                        by_mode::<C>(modes, active, nm, |m| Op::Dense(&g(m).bf), &ws.y, true, next, &mut ws.tmp);
                        if r.is_some() {
                            by_mode::<C>(modes, active, nm, |m| Op::Dense(&g(m).gf), &ws.r, true, next, &mut ws.tmp);
                        }
                    }
                    Some(fm) => {
                        let a = |m: usize| &fm.steps[k][m];
                        by_mode::<C>(modes, active, nm, |m| Op::Dense(&a(m).f), s, false, next, &mut ws.tmp);
                        by_mode::<C>(modes, active, nm, |m| Op::Dense(&a(m).e), w, true, next, &mut ws.tmp);
                        if r.is_some() {
                            by_mode::<C>(modes, active, nm, |m| Op::Dense(&a(m).r_map), &ws.r, true, next, &mut ws.tmp);
                        }
                    }
                }
                std::mem::swap(&mut ws.s[f], &mut ws.s_next[f]);
            }
        }
        if plant && k < p.horizon {
            by_mode::<C>(modes, active, nm, |m| Op::Lin(ops.a(k, m)), &ws.x, false, &mut ws.x_next, &mut ws.tmp);
            by_mode::<C>(modes, active, nm, |m| Op::Lin(ops.b(k, m)), w, true, &mut ws.x_next, &mut ws.tmp);
            if !ops.factors.is_empty() {
                add_factors::<C>(sc, 0, k, &draw.zeta, &ws.x, &mut ws.x_next, &mut ws.tmp);
                add_factors::<C>(sc, 1, k, &draw.zeta, w, &mut ws.x_next, &mut ws.tmp);
            }
            if let Some(r) = r {
                lanes::add_vector(1.0, r.as_slice(), &mut ws.x_next);
            }
            std::mem::swap(&mut ws.x, &mut ws.x_next);
            if let Some(rc) = sc.ratios {
                let mut q = [0.0; LANES];
                lanes::quadratic(&rc.w_weight, w, &mut q);
                for (e, q) in ws.energy.iter_mut().zip(&q) {
                    *e += q;
                }
            }
        }
    }
}
