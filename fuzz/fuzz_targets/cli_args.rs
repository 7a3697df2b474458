//! Fuzz target `cli_args`: see `objmodel_fuzz::cli_args` (crates/objmodel/tests/fuzz_checks/mod.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| objmodel_fuzz::cli_args(data));
