//! Layer 1, numerics: dense linear algebra, linear operators, and the solvers (line search, conic
//! programs, SDPs) the designs and analyses call. Knows nothing about plants or filters.

pub mod accuracy;
pub mod linalg;
pub mod linop;
pub mod pd;
pub mod riccati;
pub mod solve;
