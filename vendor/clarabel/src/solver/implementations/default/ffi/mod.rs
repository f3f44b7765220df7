mod info;
mod settings;

pub use info::*;
pub use settings::*;
