//! FFI friendly versions of internal solver types

mod enums;
mod traits;
pub use enums::*;
pub use traits::*;
