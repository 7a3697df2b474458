//! An OptiTrack Motive take that holds the object and the palm as two rigid bodies (how a lab
//! records an instrumented demonstration) is read one body at a time, by name, and teaches
//! what the same poses in two files teach.

mod common;

use common::data;
use objmodel::format::{read_trajectory, PoseFile};
use objmodel::learn::{Config, Learner, Source};
use objmodel::observation::Observation;
use objmodel::trajectory::StampedPose;
use std::path::Path;

/// A take of `bodies` (name, poses) as Motive writes it, positions in `units` (`metres` per
/// unit): each body's columns (rotation X Y Z W, position X Y Z, mean marker error) and one
/// marker's, one row per stamp of any body, a body's fields empty at a stamp where it has no
/// pose (it was unseen). Numbers are written in their shortest exact form.
fn take(bodies: &[(&str, &[StampedPose])], units: &str, metres: f64) -> String {
    let mut head = [
        String::from(",Type"),
        String::from(",Name"),
        String::from(",ID"),
        String::from(","),
        String::from("Frame,Time (Seconds)"),
    ];
    for (k, (name, _)) in bodies.iter().enumerate() {
        head[0] += &",Rigid Body".repeat(8);
        head[0] += &",Rigid Body Marker".repeat(3);
        head[1] += &format!(",{name}").repeat(8);
        head[1] += &format!(",{name}:Marker1").repeat(3);
        head[2] += &format!(",{k}").repeat(11);
        head[3] += ",Rotation,Rotation,Rotation,Rotation,Position,Position,Position,";
        head[3] += "Mean Marker Error,Position,Position,Position";
        head[4] += ",X,Y,Z,W,X,Y,Z,,X,Y,Z";
    }
    let mut stamps: Vec<f64> = bodies
        .iter()
        .flat_map(|(_, poses)| poses.iter().map(|p| p.t))
        .collect();
    stamps.sort_by(f64::total_cmp);
    stamps.dedup();
    let mut text = format!(
        "Format Version,1.23,Take Name,push,Capture Frame Rate,30.000000,Rotation Type,\
         Quaternion,Length Units,{units},Coordinate Space,Global\n\n{}\n",
        head.join("\n")
    );
    for (frame, t) in stamps.iter().enumerate() {
        text += &format!("{frame},{t}");
        for (_, poses) in bodies {
            match poses.iter().find(|p| p.t == *t) {
                Some(p) => {
                    let (q, x) = (p.pose.rotation.coords, p.pose.translation.vector / metres);
                    text += &format!(
                        ",{},{},{},{},{},{},{},0.0002,{},{},{}",
                        q[0], q[1], q[2], q[3], x[0], x[1], x[2], x[0], x[1], x[2]
                    );
                }
                None => text += &",".repeat(11),
            }
        }
        text += "\n";
    }
    text
}

#[test]
fn a_take_of_object_and_palm_teaches_what_their_files_teach() {
    let name = "mujoco_palm_tilt_0.1mm";
    let (object_file, palm_file) = (
        data(&format!("{name}.tum")),
        data(&format!("{name}.palm.tum")),
    );
    let object = read_trajectory(&object_file).unwrap();
    let palm = read_trajectory(&palm_file).unwrap();
    // The object is unseen at some of the palm's stamps: its fields are empty there.
    assert!(object.len() < palm.len());
    let learner = Learner::new(Config::default());
    let from_files = learner
        .observe(&Source::Files {
            object: &object_file,
            palm: Some(&palm_file),
        })
        .unwrap();
    assert!(
        from_files.classification.edges().count() > 0,
        "{:?}",
        from_files.classification
    );
    let dir = tempfile::tempdir().unwrap();
    for (units, metres) in [("Meters", 1.0), ("Millimeters", 1e-3)] {
        // The palm's columns first: the order of the bodies does not matter.
        let path = dir.path().join(format!("take_{units}.csv"));
        let bodies = [("hand", &palm[..]), ("box", &object[..])];
        std::fs::write(&path, take(&bodies, units, metres)).unwrap();
        let from_take = learner
            .observe(&Source::Take {
                path: &path,
                object: "box",
                palm: Some("hand"),
            })
            .unwrap();
        assert_eq!(from_take.classification.name, format!("take_{units}.csv"));
        // The same model, to rounding (the quaternions are normalised again as read, and
        // millimetres converted).
        let (a, b) = (&from_take.classification, &from_files.classification);
        assert_eq!((a.kind, a.frames, &a.labels), (b.kind, b.frames, &b.labels));
        common::assert_same_edges(a, b, 1e-9);
        let phi = |o: &Observation| o.dynamics[0].phi.expect("φ");
        assert!((phi(&from_take) - phi(&from_files)).abs() < 1e-9);
    }
}

#[test]
fn a_take_names_its_rigid_bodies_and_a_file_that_is_none_says_so() {
    let dir = tempfile::tempdir().unwrap();
    let object = read_trajectory(&data("mujoco_palm_tilt_0.1mm.tum")).unwrap();
    let palm = read_trajectory(&data("mujoco_palm_tilt_0.1mm.palm.tum")).unwrap();
    let path = dir.path().join("take.csv");
    let bodies = [("box", &object[..10]), ("hand", &palm[..10])];
    std::fs::write(&path, take(&bodies, "Millimeters", 1e-3)).unwrap();
    let read = |body: Option<&str>| -> objmodel::Result<Vec<StampedPose>> {
        let file = PoseFile {
            path: &path,
            rigid_body: body,
        };
        file.open()?.collect()
    };
    // Each body's own poses, in metres.
    for (body, truth) in [("box", &object[..10]), ("hand", &palm[..10])] {
        let poses = read(Some(body)).unwrap();
        assert_eq!(poses.len(), truth.len(), "{body}");
        for (a, b) in poses.iter().zip(truth) {
            assert_eq!(a.t, b.t);
            assert!((a.pose.translation.vector - b.pose.translation.vector).norm() < 1e-12);
            assert!(a.pose.rotation.angle_to(&b.pose.rotation) < 1e-12);
        }
    }
    let err = |body: Option<&str>, path: &Path| {
        let file = PoseFile {
            path,
            rigid_body: body,
        };
        match file
            .open()
            .and_then(|r| r.collect::<objmodel::Result<Vec<_>>>())
        {
            Ok(_) => panic!("{} read with {body:?}", path.display()),
            Err(e) => e.to_string(),
        }
    };
    // Unnamed, several bodies are refused with their names and what to give.
    let e = err(None, &path);
    assert!(e.contains("take.csv:7:"), "{e}");
    assert!(e.contains("2 rigid bodies (box, hand)"), "{e}");
    assert!(e.contains("--object NAME"), "{e}");
    // A name the take does not hold.
    let e = err(Some("palm"), &path);
    assert!(e.contains("no rigid body named \"palm\""), "{e}");
    assert!(e.contains("holds box, hand"), "{e}");
    // A TUM file holds no rigid bodies.
    let e = err(Some("box"), &data("mujoco_palm_tilt_0.1mm.tum"));
    assert!(e.contains("mujoco_palm_tilt_0.1mm.tum:2:"), "{e}");
    assert!(e.contains("no OptiTrack Motive export"), "{e}");
    // Learnt, the error names the file.
    let learner = Learner::new(Config::default());
    let e = learner
        .observe(&Source::Take {
            path: &path,
            object: "crate",
            palm: None,
        })
        .unwrap_err()
        .to_string();
    assert!(e.contains("take.csv") && e.contains("\"crate\""), "{e}");
}
