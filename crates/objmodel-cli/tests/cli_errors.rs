//! End-to-end tests of the `objmodel` binary: bad input gets a clear error naming file and line
//! (exit code 2, no panic), and the help texts.

#[allow(unused_imports)]
mod common;
#[allow(unused_imports)]
use common::*;
#[allow(unused_imports)]
use serde_json::Value;
#[allow(unused_imports)]
use std::path::{Path, PathBuf};

// ---------------------------------------------------------------------------------------------
// 1. bad input: a clear error naming the file and line, exit code 2, no panic

/// `objmodel classify FILE` must fail cleanly; its message must contain `FILE:LINE:` (or just
/// `FILE` for `line == None`) and every string in `expect`.
fn expect_bad(
    dir: &TempDir,
    name: &str,
    content: Option<&str>,
    line: Option<usize>,
    expect: &[&str],
) {
    let path = match content {
        Some(c) => dir.write(name, c),
        None => dir.join(name),
    };
    let r = run(&["classify".to_string(), s(&path)]).fails();
    let at = match line {
        Some(l) => format!("{}:{l}: ", path.display()),
        None => format!("{}", path.display()),
    };
    r.check(
        r.stderr.contains(&at),
        &format!("the message should name the place '{at}'"),
    );
    for e in expect {
        r.check(
            r.stderr.to_lowercase().contains(&e.to_lowercase()),
            &format!("the message should mention '{e}'"),
        );
    }
    r.check(
        r.stderr.trim_end().lines().count() == 1,
        "expected a one-line message",
    );
}

#[test]
fn bad_input_empty_file() {
    let d = TempDir::new("empty");
    expect_bad(&d, "empty.tum", Some(""), None, &["no", "poses"]);
    // only comments and blank lines: no poses either
    expect_bad(
        &d,
        "comments.tum",
        Some("# nothing here\n\n   \n# timestamp tx ty tz qx qy qz qw\n"),
        None,
        &["poses"],
    );
}

#[test]
fn bad_input_wrong_column_count() {
    let d = TempDir::new("columns");
    expect_bad(
        &d,
        "seven.tum",
        Some(&format!("# a comment\n{GOOD}0.5 0 0 0 0 0 1\n")),
        Some(7),
        &["expected 8 columns", "found 7"],
    );
    expect_bad(
        &d,
        "nine.tum",
        Some(&format!("{GOOD}0.5 0 0 0 0 0 0 1 9\n")),
        Some(6),
        &["expected 8 columns", "found 9"],
    );
    // commas without a header: hint at the CSV header
    expect_bad(
        &d,
        "commas.tum",
        Some("0,0,0,0,0,0,0,1\n"),
        Some(1),
        &["expected 8 columns", "header"],
    );
}

#[test]
fn bad_input_not_a_number() {
    let d = TempDir::new("nan-text");
    expect_bad(
        &d,
        "word.tum",
        Some(&format!("{GOOD}0.5 0 0 0.2x 0 0 0 1\n")),
        Some(6),
        &["column 4", "tz", "\"0.2x\"", "not a number"],
    );
}

#[test]
fn bad_input_nan_and_infinity() {
    let d = TempDir::new("nan");
    expect_bad(
        &d,
        "nan.tum",
        Some(&format!("{GOOD}0.5 0 NaN 0 0 0 0 1\n")),
        Some(6),
        &["ty", "NaN", "finite"],
    );
    expect_bad(
        &d,
        "inf.tum",
        Some(&format!("{GOOD}0.5 0 0 0 0 0 0 inf\n")),
        Some(6),
        &["qw", "infinite", "finite"],
    );
}

#[test]
fn bad_input_zero_quaternion() {
    let d = TempDir::new("zeroq");
    expect_bad(
        &d,
        "zero.tum",
        // (Every pose value zero is a frame where the tracker lost the object: a gap.)
        Some(&format!("{GOOD}0.5 0.1 0 0 0 0 0 0\n")),
        Some(6),
        &["quaternion", "zero"],
    );
}

#[test]
fn bad_input_far_from_unit_quaternion() {
    let d = TempDir::new("farq");
    expect_bad(
        &d,
        "far.tum",
        Some(&format!("{GOOD}0.5 0 0 0 0 0 0 1.5\n")),
        Some(6),
        &["quaternion", "norm 1.5"],
    );
    expect_bad(
        &d,
        "small.tum",
        Some(&format!("{GOOD}0.5 0 0 0 0.5 0 0 0.5\n")),
        Some(6),
        &["quaternion", "norm"],
    );
    // a quaternion off by rounding is normalised, not rejected
    // (read: the object rests in it, which classify reports as nothing to learn)
    let ok = d.write("rounding.tum", &GOOD.replace(" 1\n", " 1.001\n"));
    let r = run(&["classify".to_string(), s(&ok)]).fails();
    r.check(
        r.stderr
            .contains("nothing to learn: no motion in its 5 frames"),
        "a norm within rounding should be read",
    );
}

#[test]
fn bad_input_timestamps_not_increasing() {
    let d = TempDir::new("time");
    expect_bad(
        &d,
        "repeat.tum",
        Some(&format!("{GOOD}0.4 0.1 0 0 0 0 0 1\n")),
        Some(6),
        &["timestamp", "repeats", "line 5", "strictly increase"],
    );
    expect_bad(
        &d,
        "back.tum",
        Some(&format!("{GOOD}0.25 0 0 0 0 0 0 1\n")),
        Some(6),
        &["timestamp 0.25", "goes back", "line 5", "strictly increase"],
    );
}

#[test]
fn bad_input_missing_file() {
    let d = TempDir::new("missing");
    expect_bad(&d, "does-not-exist.tum", None, None, &["no such file"]);
    // a named palm file that does not exist is reported by its name too
    let demo = d.write("demo.tum", GOOD);
    let palm = d.join("nopalm.tum");
    let r = run(&["classify".to_string(), s(&demo), "--palm".into(), s(&palm)]).fails();
    r.check(
        r.stderr.contains(&s(&palm)),
        "the message should name the missing palm file",
    );
}

#[test]
fn bad_input_csv() {
    let d = TempDir::new("csv");
    // a header without a qz column
    expect_bad(
        &d,
        "noqz.csv",
        Some("timestamp,tx,ty,tz,qx,qy,qw\n0,0,0,0,0,0,1\n"),
        Some(1),
        &["no column for qz"],
    );
    // a header without a timestamp (detected as CSV from the header, not the name)
    expect_bad(
        &d,
        "not",
        Some("x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,1\n"),
        Some(1),
        &["no column for timestamp"],
    );
    // a data row with a field missing
    expect_bad(
        &d,
        "short.csv",
        Some("t,x,y,z,qx,qy,qz,qw\n0,0,0,0,0,0,0,1\n0.1,0,0,0,0,0,1\n"),
        Some(3),
        &["expected 8 columns", "found 7"],
    );
    // a good CSV file (columns in another order, an extra column) is read
    let ok = d.write(
        "ok.csv",
        "qw,qx,qy,qz,frame,t,x,y,z\n1,0,0,0,a,0,0,0,0\n1,0,0,0,b,0.1,0,0,0\n1,0,0,0,c,0.2,0,0,0\n",
    );
    // (it is read: the object rests in it, which classify reports as nothing to learn)
    let r = run(&["classify".to_string(), s(&ok), "--json".into()]).fails();
    r.check(
        r.stderr
            .contains("nothing to learn: no motion in its 3 frames"),
        "a 3-line CSV should be read as 3 frames at rest",
    );
}

#[test]
fn bad_input_late_in_a_long_file() {
    // the error comes after many good lines (more than one parsing chunk): still its line
    let d = TempDir::new("long");
    let mut text = String::with_capacity(30 * 20_001);
    for i in 0..20_000 {
        text += &format!("{}.{:03} 0 0 0 0 0 0 1\n", i / 1000, i % 1000);
    }
    text += "25 0 0 0 0 0 0\n";
    expect_bad(
        &d,
        "long.tum",
        Some(&text),
        Some(20_001),
        &["expected 8 columns", "found 7"],
    );
}

/// Each part of an error message once: the file name is not repeated, nor the OS's message.
#[test]
fn error_messages_do_not_repeat_themselves() {
    let d = TempDir::new("repeat");
    for (name, content, needle) in [
        ("empty.tum", Some(""), "empty.tum"),
        ("nosuch.tum", None, "No such file"),
    ] {
        let path = match content {
            Some(c) => d.write(name, c),
            None => d.join(name),
        };
        let r = run(&["classify".to_string(), s(&path)]).fails();
        r.check(
            r.stderr.contains(needle),
            &format!("the message should contain '{needle}'"),
        );
        r.check(
            r.stderr.matches(needle).count() == 1,
            &format!("'{needle}' should appear once in the message"),
        );
    }
}

// ---------------------------------------------------------------------------------------------
// 6. help

#[test]
fn help_top_level_mentions_gravity() {
    let top = run(&["--help"]).ok();
    top.check(
        top.stdout.contains("classify") && top.stdout.contains("learn"),
        "top-level help should list the commands",
    );
    top.check(top.stdout.contains("--gravity"), "top-level help should mention --gravity (README: gravity must be given for camera-frame trackers)");
}

#[test]
fn help_classify_mentions_gravity() {
    let c = run(&["classify", "--help"]).ok();
    c.check(
        c.stdout.contains("--gravity"),
        "classify help should mention --gravity",
    );
    c.check(
        c.stdout.contains("--frames") && c.stdout.contains("--json"),
        "classify help should list --frames and --json",
    );
}

/// A contact's depth or tolerance is a length: a negative one is refused, naming the option;
/// zero (a rigid contact, a sharp edge) is accepted.
#[test]
fn a_negative_contact_depth_is_a_clear_error() {
    let d = TempDir::new("contact_depth");
    let demo = d.write("demo.tum", GOOD);
    for option in ["--contact-depth", "--edge-tolerance"] {
        let r = run(&["classify".to_string(), s(&demo), format!("{option}=-0.001")]).fails();
        r.check(
            r.stderr.contains(option) && r.stderr.contains("zero or positive"),
            "a negative length should be refused, naming the option",
        );
    }
    let r = run(&[
        "classify".to_string(),
        s(&demo),
        "--contact-depth".into(),
        "0".into(),
    ]);
    // (the file is read: it holds a rest only, which is its own error)
    r.check(
        !r.stderr.contains("--contact-depth"),
        "a contact depth of zero is accepted",
    );
}

#[test]
fn a_bad_tracking_noise_is_a_clear_error() {
    let d = TempDir::new("noise");
    let demo = d.write("demo.tum", GOOD);
    let classify = |extra: &[&str]| {
        let mut args = vec!["classify".to_string(), s(&demo)];
        args.extend(extra.iter().map(|a| a.to_string()));
        run(&args).fails()
    };
    for (option, other) in [
        ("--noise-position", "--noise-rotation"),
        ("--noise-rotation", "--noise-position"),
    ] {
        let r = classify(&[&format!("{other}=0.001"), &format!("{option}=-0.001")]);
        r.check(
            r.stderr.contains(option) && r.stderr.contains("zero or positive"),
            "a negative noise should be refused, naming the option",
        );
    }
    let r = classify(&[
        "--noise-position=0.001",
        "--noise-rotation=0.01",
        "--palm-noise-position=0.001",
    ]);
    r.check(
        r.stderr.contains("--palm-noise-rotation") && r.stderr.contains("give both"),
        "half a palm noise should be refused, naming the missing option",
    );
    let r = classify(&["--palm-noise-position=0.001", "--palm-noise-rotation=0.01"]);
    r.check(
        r.stderr.contains("--noise-position"),
        "a palm noise without the object's should be refused, naming what it needs",
    );
}

#[test]
fn bad_gravity_is_a_clear_error() {
    let d = TempDir::new("gravity");
    let demo = d.write("demo.tum", GOOD);
    let r = run(&[
        "classify".to_string(),
        s(&demo),
        "--gravity".into(),
        "0,0".into(),
    ])
    .fails();
    r.check(
        r.stderr.contains("--gravity"),
        "the message should name --gravity",
    );
    let r = run(&[
        "classify".to_string(),
        s(&demo),
        "--gravity".into(),
        "0,0,0".into(),
    ])
    .fails();
    r.check(
        r.stderr.contains("--gravity") && r.stderr.contains("zero"),
        "zero gravity should be refused",
    );
    // (accepted: the file is read, and the object rests in it)
    let r = run(&[
        "classify".to_string(),
        s(&demo),
        "--gravity".into(),
        "none".into(),
    ])
    .fails();
    r.check(
        r.stderr.contains("nothing to learn") && !r.stderr.contains("--gravity"),
        "--gravity none should be accepted",
    );
}
