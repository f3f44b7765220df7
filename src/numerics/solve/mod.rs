//! Numerical building blocks for the design procedures: clarabel conic programs over symmetric
//! matrices ([`sdp`]), the project's own interior-point method for them ([`interior`]), the certified S-procedure bound ([`slemma`]) and a maximizer of concave
//! functions on an interval ([`line`](mod@line)).

pub mod affine;
pub mod conic;
pub mod interior;
pub mod line;
pub mod sdp;
pub mod slemma;
