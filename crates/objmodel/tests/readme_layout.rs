//! The README's layout table names every public module of the library: a reader finds each
//! concept there in one hop, and a module added without a word in the table fails here.

use std::path::Path;

/// The names of the `pub mod` declarations of `lib.rs`.
fn public_modules(lib: &str) -> Vec<String> {
    lib.lines()
        .filter_map(|l| l.trim().strip_prefix("pub mod "))
        .map(|rest| rest.trim_end_matches(';').trim().to_string())
        .collect()
}

/// The README's table row for the library crate.
fn library_row(readme: &str) -> &str {
    readme
        .lines()
        .find(|l| l.starts_with("| `crates/objmodel` |"))
        .expect("README.md has a layout table row for crates/objmodel")
}

#[test]
fn the_readme_layout_names_every_public_module() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let lib = std::fs::read_to_string(root.join("src/lib.rs")).unwrap();
    let readme = std::fs::read_to_string(root.join("../../README.md")).unwrap();
    let modules = public_modules(&lib);
    assert!(modules.len() > 20, "lib.rs declares {modules:?}");
    let row = library_row(&readme);
    let missing: Vec<&String> = modules
        .iter()
        .filter(|m| !row.contains(&format!("`{m}`")))
        .collect();
    assert!(
        missing.is_empty(),
        "README.md's layout row for crates/objmodel does not name {missing:?}"
    );
}

#[test]
fn a_module_missing_from_the_row_is_found() {
    let lib = "pub mod alpha;\nmod hidden;\npub mod beta;\n";
    assert_eq!(public_modules(lib), ["alpha", "beta"]);
    let readme = "# x\n| crate | what |\n| `crates/objmodel` | `alpha` and more |\n";
    let row = library_row(readme);
    assert!(row.contains("`alpha`") && !row.contains("`beta`"));
}
