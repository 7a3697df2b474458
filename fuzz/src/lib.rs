//! The checks of the fuzz targets, shared with the regression tests that run on stable
//! (`crates/objmodel/tests/fuzz_regressions.rs`), which include the same file.

#[path = "../../crates/objmodel/tests/fuzz_checks/mod.rs"]
mod fuzz_checks;
pub use fuzz_checks::*;
