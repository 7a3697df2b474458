//! Fuzz target `tree_load`: see `objmodel_fuzz::tree_load` (crates/objmodel/tests/fuzz_checks/mod.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| objmodel_fuzz::tree_load(data));
