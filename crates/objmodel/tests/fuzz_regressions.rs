//! The inputs the fuzz targets (`fuzz/`, nightly) found wrong, minimised, and their seed
//! corpora, run through the same checks on stable: every file of
//! `tests/fuzz_regressions/TARGET/` and of `fuzz/seeds/TARGET/` goes through the check of
//! `TARGET` (`tests/fuzz_checks/mod.rs`), which panics on a wrong result.

mod fuzz_checks;

use std::path::{Path, PathBuf};

/// The files of `dir`, sorted; none if it does not exist.
fn files(dir: &Path) -> Vec<PathBuf> {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return Vec::new();
    };
    let mut v: Vec<PathBuf> = entries.map(|e| e.unwrap().path()).collect();
    v.sort();
    v
}

/// Run `check` on every regression input and seed of `target`; returns how many there were.
fn run(target: &str, check: fn(&[u8])) -> (usize, usize) {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let found = files(&root.join("tests/fuzz_regressions").join(target));
    let seeds = files(&root.join("../../fuzz/seeds").join(target));
    for f in found.iter().chain(&seeds) {
        let data = std::fs::read(f).unwrap();
        let r = std::panic::catch_unwind(|| check(&data));
        assert!(r.is_ok(), "{target}: {} fails its check", f.display());
    }
    (found.len(), seeds.len())
}

#[test]
fn read_memory() {
    let (_, seeds) = run("read_memory", fuzz_checks::read_memory);
    assert!(seeds >= 20, "{seeds} seeds");
}

#[test]
fn read_mapped() {
    let (_, seeds) = run("read_mapped", fuzz_checks::read_mapped);
    assert!(seeds >= 20, "{seeds} seeds");
}

#[test]
fn read_simd() {
    let (_, seeds) = run("read_simd", fuzz_checks::read_simd);
    assert!(seeds >= 4, "{seeds} seeds");
}

/// A tree loaded and written again loads equal: serde_json read some numbers one unit in the
/// last place off (`4.197423004644176e-11`), so every `learn --into` moved them (fixed by its
/// `float_roundtrip` feature).
#[test]
fn tree_load() {
    let (found, seeds) = run("tree_load", fuzz_checks::tree_load);
    assert!(found >= 2 && seeds >= 3, "{found} found, {seeds} seeds");
}

#[test]
fn cli_args() {
    let (_, seeds) = run("cli_args", fuzz_checks::cli_args);
    assert!(seeds >= 10, "{seeds} seeds");
}
