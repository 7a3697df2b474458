//! The model file: nothing to learn leaves it as it was, two learners at once both keep their
//! demonstrations, and files that are not trees (or are from a newer objmodel) are refused
//! with a clear error.

mod common;

use common::{run, s, synth, TempDir};
use std::process::Command;

fn demo_names(model: &std::path::Path) -> Vec<String> {
    common::read_json(model)["demos"]
        .as_array()
        .expect("demos")
        .iter()
        .map(|d| d["name"].as_str().unwrap().to_string())
        .collect()
}

#[test]
fn a_demonstration_without_motion_teaches_nothing() {
    let d = TempDir::new("nothing");
    let one = d.write("one.tum", "0 0.5 0 0.1 0 0 0 1\n");
    // classify: an error that names the file and says why
    let r = run(&["classify".to_string(), s(&one)]).fails();
    r.check(
        r.stderr.contains("one.tum") && r.stderr.contains("nothing to learn"),
        "the error should name the file and say there is nothing to learn",
    );
    // learn --into: the model stays byte for byte as it was
    let topples = synth("topple", &d.join("demos"), 1, 3, &[]);
    let model = d.join("box.json");
    run(&[
        "learn".to_string(),
        s(&topples[0]),
        "--into".into(),
        s(&model),
    ])
    .ok();
    let before = std::fs::read(&model).unwrap();
    let r = run(&["learn".to_string(), s(&one), "--into".into(), s(&model)]).ok();
    r.check(r.stderr.contains("nothing to learn"), "a warning says why");
    assert_eq!(std::fs::read(&model).unwrap(), before);
    // ... and a model that did not exist is not created
    let absent = d.join("absent.json");
    run(&["learn".to_string(), s(&one), "--into".into(), s(&absent)]).ok();
    assert!(!absent.exists());
}

/// Two `objmodel learn --into` processes on one model at once, several times: every
/// demonstration ends up in it.
#[test]
fn concurrent_learners_lose_nothing() {
    let d = TempDir::new("concurrent");
    let demos = synth("topple", &d.join("demos"), 6, 5, &[]);
    let model = d.join("box.json");
    for pair in demos.chunks(2) {
        let children: Vec<_> = pair
            .iter()
            .map(|demo| {
                Command::new(env!("CARGO_BIN_EXE_objmodel"))
                    .args(["learn", &s(demo), "--into", &s(&model)])
                    .output_async()
            })
            .collect();
        for c in children {
            let out = c.wait_with_output().unwrap();
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
        }
    }
    let mut names = demo_names(&model);
    names.sort();
    let mut expected: Vec<String> = demos
        .iter()
        .map(|p| p.file_name().unwrap().to_string_lossy().into_owned())
        .collect();
    expected.sort();
    assert_eq!(names, expected);
}

/// Spawning a child with its output piped, for running two at once.
trait OutputAsync {
    fn output_async(&mut self) -> std::process::Child;
}

impl OutputAsync for Command {
    fn output_async(&mut self) -> std::process::Child {
        self.stdout(std::process::Stdio::piped())
            .stderr(std::process::Stdio::piped())
            .spawn()
            .expect("spawn objmodel")
    }
}

#[test]
fn files_that_are_not_trees_are_refused_clearly() {
    let d = TempDir::new("not-a-tree");
    let demo = synth("topple", &d.join("demos"), 1, 7, &[]);
    let cases = [
        ("array.json", "[1, 2, 3]\n", "no \"schema\" field"),
        (
            "other.json",
            "{\"schema\": \"geojson\"}\n",
            "not an objmodel tree",
        ),
        (
            "newer.json",
            "{\"schema\": \"objmodel.tree\", \"version\": 99}\n",
            "newer objmodel",
        ),
        ("broken.json", "{\"schema\": ", "not valid JSON"),
    ];
    for (name, content, says) in cases {
        let model = d.write(name, content);
        let r = run(&["learn".to_string(), s(&demo[0]), "--into".into(), s(&model)]).fails();
        r.check(
            r.stderr.contains(name) && r.stderr.contains(says),
            &format!("{name}: the error should name the file and say '{says}'"),
        );
        assert_eq!(std::fs::read_to_string(&model).unwrap(), content);
    }
}

/// `objmodel export`: a closed model gives MJCF and URDF files; an open one, or a mass that is
/// not a positive number, a clear error and no file.
#[test]
fn export_writes_simulation_models_or_says_what_is_missing() {
    use objmodel::learn::{Config, Learner, Source};
    use objmodel::synth::{self, SynthBox, SynthNoise};
    use rand::SeedableRng;
    let d = TempDir::new("export");
    let b = SynthBox::random(&mut rand::rngs::StdRng::seed_from_u64(4));
    let learner = Learner::new(Config::default());
    let mut tree = objmodel::tree::Tree::default();
    for (k, demo) in synth::topples_over_every_face(&b, &SynthNoise::REAL, 4)
        .iter()
        .enumerate()
    {
        learner
            .learn(&mut tree, &[Source::Memory(&demo.demo)])
            .unwrap();
        if k == 3 {
            // Four topples of the upright box: the top face is not known yet, and without a
            // centre of mass (with one, the top face would be inferred) nothing bounds it.
            let open = d.join("open.json");
            let mut no_com = tree.clone();
            no_com.com = None;
            no_com.save(&open).unwrap();
            let r = run(&[
                "export".to_string(),
                s(&open),
                "--mjcf".into(),
                s(&d.join("open.xml")),
                "--mass".into(),
                "0.6".into(),
            ])
            .fails();
            r.check(
                r.stderr.contains("open.json") && r.stderr.contains("open towards"),
                "the error should name the model and say where the shape is open",
            );
            assert!(!d.join("open.xml").exists());
        }
    }
    let model = d.join("box.json");
    tree.save(&model).unwrap();
    let (xml, urdf) = (d.join("box.xml"), d.join("box.urdf"));
    let r = run(&[
        "export".to_string(),
        s(&model),
        "--mjcf".into(),
        s(&xml),
        "--urdf".into(),
        s(&urdf),
        "--mass".into(),
        "0.6".into(),
    ])
    .ok();
    r.check(
        r.stderr.contains("mass: 0.6 kg"),
        "the notes say where each property came from",
    );
    let mjcf = std::fs::read_to_string(&xml).unwrap();
    assert!(
        mjcf.contains("<freejoint") && mjcf.contains("<inertial") && mjcf.contains("type=\"box\"")
    );
    let u = std::fs::read_to_string(&urdf).unwrap();
    assert!(u.contains("<robot") && u.contains("<inertial>") && u.contains("<box"));
    let r = run(&[
        "export".to_string(),
        s(&model),
        "--mjcf".into(),
        s(&d.join("bad.xml")),
        "--mass".into(),
        "-1".into(),
    ])
    .fails();
    r.check(r.stderr.contains("mass"), "a bad mass is named");
    assert!(!d.join("bad.xml").exists());

    // `objmodel simulate --model`: the learnt object (a squat box: it would slide on a tilted
    // palm before it toppled) slid on a table; the truth is in the model's frame (its CoM is
    // the model's).
    let sims = d.join("sims");
    let r = run(&[
        "simulate".to_string(),
        "slide".into(),
        "--model".into(),
        s(&model),
        "--mass".into(),
        "0.6".into(),
        "--json".into(),
        "-o".into(),
        s(&sims),
    ])
    .ok();
    let v: serde_json::Value = serde_json::from_str(&r.stdout).expect("JSON");
    let com: Vec<f64> = v["truth"]["com"]
        .as_array()
        .expect("truth.com")
        .iter()
        .map(|x| x.as_f64().unwrap())
        .collect();
    let want = tree.com.as_ref().expect("a CoM").point;
    assert!((nalgebra::Vector3::new(com[0], com[1], com[2]) - want).norm() < 1e-9);
    assert_eq!(v["truth"]["kind"], "slide");
    let r = run(&[
        "simulate".to_string(),
        "topple".into(),
        "--model".into(),
        s(&d.join("open.json")),
        "-o".into(),
        s(&sims),
    ])
    .fails();
    r.check(
        r.stderr.contains("open.json") && r.stderr.contains("no closed shape"),
        "simulating an open model names it and says why",
    );
}

/// The poses of a TUM file in a tracker frame whose y axis is the file's z (up): a quarter
/// turn about x (`tracker_from_world`), written as TUM.
fn to_y_up(from: &std::path::Path, to: &std::path::Path) {
    use nalgebra::{Isometry3, UnitQuaternion, Vector3};
    let tracker_from_world = Isometry3::from_parts(
        Default::default(),
        UnitQuaternion::from_axis_angle(&Vector3::x_axis(), -std::f64::consts::FRAC_PI_2),
    );
    let d = objmodel::format::read_demonstration(from, None).unwrap();
    let y_up = d.in_frame(&tracker_from_world);
    objmodel::format::write_tum(to, &y_up.object, "tracked with y up").unwrap();
}

/// Demonstrations tracked with y up and learnt with the default gravity (z up): `learn` fails,
/// says which gravity the demonstrations show, and leaves the model as it was.
#[test]
fn a_wrong_gravity_fails_and_leaves_the_model_as_it_was() {
    let d = TempDir::new("gravity");
    let mut demos = synth("slide", &d.join("demos"), 6, 7, &[]);
    demos.extend(synth("topple", &d.join("demos"), 6, 7, &[]));
    let model = d.join("box.json");
    run(&[
        "learn".to_string(),
        s(&demos[0]),
        "--into".into(),
        s(&model),
    ])
    .ok();
    let before = std::fs::read(&model).unwrap();
    std::fs::create_dir_all(d.join("y_up")).unwrap();
    let y_up: Vec<String> = demos
        .iter()
        .map(|f| {
            let to = d.join("y_up").join(f.file_name().unwrap());
            to_y_up(f, &to);
            s(&to)
        })
        .collect();
    let mut args = vec!["learn".to_string()];
    args.extend(y_up.iter().cloned());
    args.extend(["--into".to_string(), s(&model)]);
    let r = run(&args).fails();
    r.check(
        r.stderr
            .contains("not learnt, the gravity given contradicts the demonstrations")
            && r.stderr.contains("--gravity 0.000,-1.000,0.000"),
        "the error should say which gravity the demonstrations show",
    );
    assert_eq!(std::fs::read(&model).unwrap(), before);
    // Unchecked, they are learnt (with the wrong gravity: the user's call).
    let unchecked = d.join("unchecked.json");
    let mut a = args.clone();
    a.truncate(a.len() - 1);
    a.extend([s(&unchecked), "--no-gravity-check".to_string()]);
    run(&a).ok();
    assert!(unchecked.exists());
    // With that gravity they are learnt.
    args.extend(["--gravity".to_string(), "0,-1,0".into()]);
    run(&args).ok();
    assert_ne!(std::fs::read(&model).unwrap(), before);
}
