//! `filterbench check`: the expectations of an experiment file (`[[expect]]`) evaluated on its
//! result tables, with one family-wise false-alarm rate split over every tested cell by Holm's
//! procedure and the power of every test stated (docs/checks.md); and `filterbench compare`, what
//! changed between two result folders (docs/regression-tests.md).

pub mod compare;
pub mod evaluate;
pub mod kind;
pub mod kinds;
pub mod output;
pub mod run;
pub mod stats;
pub mod tables;
