pub(crate) mod atomic;
pub(crate) mod infbounds;
