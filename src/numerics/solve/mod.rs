//! Numerical building blocks for the design procedures: clarabel conic programs over symmetric
//! matrices ([`sdp`]), the certified S-procedure bound ([`slemma`]) and a maximizer of concave
//! functions on an interval ([`line`](mod@line)).

pub mod affine;
pub mod conic;
pub mod line;
pub mod sdp;
pub mod slemma;
