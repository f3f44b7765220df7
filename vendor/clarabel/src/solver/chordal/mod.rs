// Julia version of chordal decomposition that was
// ported from COSMO has a lot of explicitly index loops.
// Allow in this module for the sake of easier porting
#![allow(clippy::needless_range_loop)]

type VertexSet = indexmap::IndexSet<usize>;

mod chordal_info;
mod decomp;
mod merge;
mod sparsity_pattern;
mod supernode_tree;

pub(crate) use chordal_info::*;
pub(crate) use merge::*;
pub(crate) use sparsity_pattern::*;
pub(crate) use supernode_tree::*;

// filterbench patch 6: the decomposition as a program transformation, for another solver.
mod program {
    use super::ChordalInfo;
    use crate::algebra::{CscMatrix, FloatT};
    use crate::solver::{DefaultSettings, DefaultVariables, SupportedConeT};

    /// clarabel's chordal decomposition of a conic program min qᵀx, s = b − Ax in the cones,
    /// exactly as the solver applies it to itself (the settings' merge method, compact or standard
    /// form), kept so that a solution of the decomposed program can be taken back.
    pub struct Decomposition<T: FloatT> {
        info: ChordalInfo<T>,
        settings: DefaultSettings<T>,
        /// The decomposed program's A: the original variables, then `added` new ones (cost zero).
        pub a: CscMatrix<T>,
        /// The decomposed program's b.
        pub b: Vec<T>,
        /// The decomposed program's cones.
        pub cones: Vec<SupportedConeT<T>>,
        /// How many variables the decomposition added.
        pub added: usize,
    }

    impl<T: FloatT> Decomposition<T> {
        /// None where clarabel would not decompose: no PSD cone larger than 3, or no cone whose
        /// sparsity splits it.
        pub fn new(
            a: &CscMatrix<T>,
            b: &[T],
            cones: &[SupportedConeT<T>],
            settings: DefaultSettings<T>,
        ) -> Option<Self> {
            if !cones.iter().any(|c| matches!(c, SupportedConeT::PSDTriangleConeT(d) if *d > 3)) {
                return None;
            }
            let mut info = ChordalInfo::new(a, b, cones, &settings);
            if !info.is_decomposed() {
                return None;
            }
            let p = CscMatrix::zeros((a.n, a.n));
            let q = vec![T::zero(); a.n];
            let (_, _, a_new, b_new, cones_new) = info.decomp_augment(&p, &q, a, b, &settings);
            let added = a_new.n - a.n;
            Some(Self { info, settings, a: a_new, b: b_new, cones: cones_new, added })
        }

        /// The original program's (x, s, z) from a point of the decomposed one (the dual completed
        /// to a PSD matrix where the settings ask for it).
        pub fn reverse(&self, x: &[T], s: &[T], z: &[T]) -> (Vec<T>, Vec<T>, Vec<T>) {
            let mut vars = DefaultVariables::<T>::new(x.len(), s.len());
            vars.x.copy_from_slice(x);
            vars.s.copy_from_slice(s);
            vars.z.copy_from_slice(z);
            let back = self.info.decomp_reverse(&vars, &self.cones, &self.settings);
            (back.x, back.s, back.z)
        }
    }
}
pub use program::Decomposition;
