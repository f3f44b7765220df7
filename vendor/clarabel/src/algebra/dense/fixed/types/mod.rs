mod square;
mod symmetric;

pub(crate) use square::*;
pub(crate) use symmetric::*;
