//! A joint input over the horizon drawn by a recursion instead of its dense factor (docs/math.md
//! §7; seed 003 §2): ξ = col(x0 − E x0, w\[0..N]) with x0 − E x0 = L0 u0 and
//!
//! ```text
//! w[k] = C(k) m[k] + D(k) u[k],   m[k+1] = A(k) m[k] + B(k) w[k],   m[0] = 0,
//! ```
//!
//! whose implied factor is block lower triangular. Two of seed 003's inputs have one: the AR(1)
//! colour of `anisotropy::coloured_covariance` (m = w\[k−1], C = ρI, D = √(1−ρ²) L_W after the
//! first step) and a filter's worst input at level a, Lemma 1's shaping filter
//! w = L(k) m + S(k)^½ v (`analysis::lemma1`). With D(k) the Cholesky factors, the implied factor
//! is the Cholesky factor of the input's covariance, so the recursion draws what the triangular
//! product draws, to rounding, at O(N n²) per trial instead of O(N² mw²): [`Shaping::matching`]
//! checks that against the factor before a run uses it.

use crate::numerics::linalg::Mat;
use crate::sim::lanes::{self, LANES, Row};

/// One step of the recursion.
#[derive(Clone, Debug)]
pub struct ShapeStep {
    pub a: Mat,
    pub b: Mat,
    pub c: Mat,
    pub d: Mat,
}

/// The recursion of a joint input: the initial state's factor, then one [`ShapeStep`] per step.
#[derive(Clone, Debug)]
pub struct Shaping {
    x0_half: Mat,
    steps: Vec<ShapeStep>,
}

/// How close the recursion's implied factor must be to the dense one, relative to its largest
/// entry: both are the Cholesky factor of one covariance, computed two ways (`aniso_dropout`, lw =
/// 402: 1.1e-16 for the AR(1) colour, 2.6–3.8e-15 for the six filters' worst inputs, Lemma 1's
/// recursion against the eigenvalues of Λ and a Cholesky factorization). A worst input so near
/// 1/λmax that the two computations part by more keeps the dense product.
const MATCH: f64 = 1e-9;

impl Shaping {
    pub fn new(x0_half: Mat, steps: Vec<ShapeStep>) -> Self {
        Shaping { x0_half, steps }
    }

    /// This recursion, scaled so that its implied factor has the dense `factor`'s size (the
    /// worst inputs are scaled to the nominal noise's power), if it then equals `factor` to
    /// `MATCH` (1e-9 of its largest entry); otherwise None, and the run keeps the product.
    pub fn matching(mut self, factor: &Mat) -> Option<Self> {
        let mut g = self.implied_factor();
        if g.shape() != factor.shape() || g.norm() == 0.0 {
            return None;
        }
        let n0 = self.x0_half.nrows();
        let horizon = |m: &Mat| m.rows(n0, m.nrows() - n0).norm();
        let scale = horizon(factor) / horizon(&g);
        if !scale.is_finite() {
            return None;
        }
        // Scaling the inputs' factors D scales the state and the output with them: C and the
        // dynamics stay, and the implied factor's horizon rows scale by the same number.
        for st in &mut self.steps {
            st.d *= scale;
        }
        g.rows_mut(n0, g.nrows() - n0).scale_mut(scale);
        ((&g - factor).amax() <= MATCH * factor.amax()).then_some(self)
    }

    /// The AR(1) colour of `analysis::anisotropy::coloured_covariance` over `steps` steps: the
    /// state is the last w, w\[0] = L_W u\[0] and w\[k] = ρ w\[k−1] + √(1−ρ²) L_W u\[k], with
    /// `w_half` = L_W the Cholesky factor of one step's covariance.
    pub fn ar1(x0_half: Mat, w_half: &Mat, rho: f64, steps: usize) -> Self {
        let nw = w_half.nrows();
        let steps = (0..steps)
            .map(|k| ShapeStep {
                a: Mat::zeros(nw, nw),
                b: Mat::identity(nw, nw),
                c: Mat::identity(nw, nw) * if k == 0 { 0.0 } else { rho },
                d: if k == 0 { w_half.clone() } else { w_half * (1.0 - rho * rho).sqrt() },
            })
            .collect();
        Shaping::new(x0_half, steps)
    }

    /// The state dimension of the recursion.
    pub(super) fn states(&self) -> usize {
        self.steps.first().map_or(0, |s| s.a.nrows())
    }

    /// The factor the recursion applies, column j its response to the unit input e_j.
    fn implied_factor(&self) -> Mat {
        let n0 = self.x0_half.nrows();
        let nw = self.steps.first().map_or(0, |s| s.d.nrows());
        let d = n0 + self.steps.len() * nw;
        let mut g = Mat::zeros(d, d);
        g.view_mut((0, 0), (n0, n0)).copy_from(&self.x0_half);
        let mut m = Mat::zeros(self.states(), d);
        for (k, st) in self.steps.iter().enumerate() {
            let lo = n0 + k * nw;
            let mut w = &st.c * &m;
            let mut dk = w.columns_mut(lo, nw);
            dk += &st.d;
            m = &st.a * &m + &st.b * &w;
            g.rows_mut(lo, nw).copy_from(&w);
        }
        g
    }

    /// ξ of every lane from its standardized draws `u`, step by step; `m` and `next` hold the
    /// recursion's state (preallocated, [`Shaping::states`] rows each).
    #[inline(always)]
    pub(super) fn map(&self, u: &[Row], xi: &mut [Row], m: &mut [Row], next: &mut [Row]) {
        let n0 = self.x0_half.nrows();
        lanes::gemm(&self.x0_half, &u[..n0], false, &mut xi[..n0]);
        m.fill([0.0; LANES]);
        let (mut m, mut next) = (m, next);
        for (k, st) in self.steps.iter().enumerate() {
            let nw = st.d.nrows();
            let (lo, hi) = (n0 + k * nw, n0 + (k + 1) * nw);
            let w = &mut xi[lo..hi];
            lanes::gemm(&st.d, &u[lo..hi], false, w);
            lanes::gemm(&st.c, m, true, w);
            lanes::gemm(&st.a, m, false, next);
            lanes::gemm(&st.b, w, true, next);
            std::mem::swap(&mut m, &mut next);
        }
    }
}
