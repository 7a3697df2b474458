//! Fuzz target `read_simd`: see `objmodel_fuzz::read_simd` (crates/objmodel/tests/fuzz_checks/mod.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| objmodel_fuzz::read_simd(data));
