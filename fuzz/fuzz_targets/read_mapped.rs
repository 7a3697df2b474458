//! Fuzz target `read_mapped`: see `objmodel_fuzz::read_mapped` (crates/objmodel/tests/fuzz_checks/mod.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| objmodel_fuzz::read_mapped(data));
