//! The kinds of `[[expect]]` entries, one file each, listed once in `kinds!` (docs/checks.md).

mod agrees;
mod baseline;
mod better;
mod consistent;
mod guarantee;

use super::kind::{Configured, build};
use crate::config::{Expectation, Experiment};
use crate::error::{Error, Result};

macro_rules! kinds {
    ($($k:ty),* $(,)?) => {
        /// Every kind's name, in the order the docs list them.
        pub const KINDS: &[&str] = &[$(<$k as super::kind::Kind>::NAME),*];

        /// Entry `i` of the experiment file with its kind's parameters read and checked.
        pub fn configure(i: usize, e: &Expectation, exp: &Experiment) -> Result<Box<dyn Configured>> {
            $(if e.kind == <$k as super::kind::Kind>::NAME {
                return build::<$k>(i, e, exp);
            })*
            Err(Error::invalid(
                format!("expect[{i}].kind"),
                format!("unknown kind `{}` (known: {})", e.kind, KINDS.join(", ")),
            ))
        }
    };
}

kinds!(
    agrees::AgreesWithExact,
    guarantee::WithinGuarantee,
    consistent::Consistent,
    better::Better,
    baseline::MatchesBaseline,
);
