//! `objmodel view`: a learnt tree becomes the 3D page (with the demonstrations to play back,
//! palm files not counted as demonstrations) and, with `--figure`, the paper's Fig. 9a; a bad
//! model file is an error that names it. The page itself is tested in a browser by
//! objmodel-plot's tests/view.rs.

mod common;

use common::{run, s, synth, TempDir};

#[test]
fn view_writes_the_page_and_the_figure() {
    let d = TempDir::new("view");
    let mut files = synth("topple", &d.join("demos"), 2, 3, &[]);
    files.extend(synth("instrumented", &d.join("demos"), 1, 3, &[]));
    let model = d.join("box.json");
    let mut learn = vec!["learn".to_string()];
    learn.extend(files.iter().map(|f| s(f)));
    learn.extend(["-o".into(), s(&model)]);
    run(&learn).ok();
    let palm = files[2].with_file_name(
        files[2]
            .file_name()
            .unwrap()
            .to_string_lossy()
            .replace(".tum", ".palm.tum"),
    );
    assert!(palm.is_file(), "the instrumented demo has no palm file");
    let mut args = vec![
        "view".to_string(),
        s(&model),
        "-o".into(),
        s(&d.join("out/box.html")),
    ];
    args.push("--demos".into());
    args.extend(files.iter().chain([&palm]).map(|f| s(f)));
    args.extend(["--figure".into(), s(&d.join("out/fig9a"))]);
    let r = run(&args).ok();
    r.check(
        r.stderr.contains("3 demonstration(s)"),
        "palm file played as a demonstration",
    );
    let page = std::fs::read_to_string(d.join("out/box.html")).unwrap();
    r.check(
        page.contains("id=\"objmodel-data\""),
        "no model data in the page",
    );
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        r.check(page.contains(&name), &format!("{name} not in the page"));
    }
    let svg = std::fs::read_to_string(d.join("out/fig9a.svg")).unwrap();
    r.check(svg.contains("data-kind=\"edge\""), "Fig. 9a has no edge");
    r.check(d.join("out/fig9a.png").is_file(), "no Fig. 9a PNG");

    // Without -o, beside the model.
    run(&["view", &s(&model)]).ok();
    assert!(d.join("box.html").is_file());
}

#[test]
fn a_bad_model_is_an_error_naming_it() {
    let d = TempDir::new("view-bad");
    let bad = d.write("bad.json", "{\"schema\": \"something else\"}");
    let r = run(&["view", &s(&bad)]).fails();
    r.check(
        r.stderr.contains("bad.json"),
        "the error does not name the file",
    );
    r.check(
        !d.join("bad.html").exists(),
        "a page was written for a bad model",
    );
}
