//! Layer 2, the model: the plant and its measurement pattern, the noise covariances and their
//! uncertainty sets, the noise shapes, known disturbances, and the string of seed 004.

pub mod choice;
pub mod disturbance;
pub mod intensity;
pub mod kind;
pub mod plant;
pub mod shape;
pub mod string;
pub mod uncertainty;
