//! `filterbench check` (docs/checks.md): the statistics core, the expectation kinds, the designed
//! error rates measured over many seeds, the command and its JUnit report.

mod stats;
