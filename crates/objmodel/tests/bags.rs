//! ROS 2 bags (MCAP) as demonstrations: bags written here (the `mcap` crate's writer, CDR
//! encoded by hand in `bag_fixture`) read through the learning pipeline: the poses a bag gives
//! are those it was written from, whatever the message type, compression, byte order or
//! arrival order. (The CDR decoder against hand-built bytes: `cdr.rs`.)

mod bag_fixture;

use bag_fixture::*;
use mcap::Compression;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use objmodel::classify::Kind;
use objmodel::format::bag::BagSelection;
use objmodel::learn::{Config, Learner, Source};
use objmodel::observation::Observation;
use objmodel::synth::{self, SynthBox, SynthNoise};
use objmodel::trajectory::StampedPose;
use objmodel::Demonstration;
use rand::{rngs::StdRng, SeedableRng};
use std::path::Path;

fn the_box() -> SynthBox {
    SynthBox::random(&mut StdRng::seed_from_u64(21))
}

fn instrumented(seed: u64) -> Demonstration {
    synth::instrumented_topple(&the_box(), 1, 0.2, &SynthNoise::REAL, 30.0, seed).demo
}

/// `world_from_camera`: a camera 1.2 m above the table, looking down and a little sideways.
fn world_from_camera() -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(0.4, -0.3, 1.2),
        UnitQuaternion::from_euler_angles(3.0, 0.2, 0.7),
    )
}

fn world_from_base() -> Isometry3<f64> {
    Isometry3::from_parts(
        Translation3::new(-0.2, 0.1, 0.05),
        UnitQuaternion::from_euler_angles(0.0, 0.0, 1.1),
    )
}

/// A bag as `apriltag_ros` and a robot write one: `/tf_static` with world -> camera and
/// world -> base_link; `/tf` with camera -> tag36h11:0 (the tag's detections, on the
/// camera's clock), base_link -> palm_link (the robot's, its stamps `palm_clock` s ahead) and
/// an unrelated joint; messages not quite in stamp order.
fn apriltag_bag(path: &Path, d: &Demonstration, palm_clock: f64, compression: Option<Compression>) {
    let (wc, wb) = (world_from_camera(), world_from_base());
    let mut msgs = vec![Msg {
        topic: "/tf_static".into(),
        schema: TF,
        log_time: d.object[0].t - 1.0,
        data: tf_message(
            true,
            &[
                (0.0, "world", "camera_optical", wc),
                (0.0, "world", "base_link", wb),
            ],
        ),
    }];
    for p in &d.object {
        let camera_from_tag = wc.inverse() * p.pose;
        msgs.push(Msg {
            topic: "/tf".into(),
            schema: TF,
            log_time: p.t + 0.03,
            data: tf_message(
                true,
                &[(p.t, "camera_optical", "tag36h11:0", camera_from_tag)],
            ),
        });
    }
    for p in d.palm.as_ref().unwrap() {
        let base_from_palm = wb.inverse() * p.pose;
        let joint = Isometry3::rotation(Vector3::z() * p.t.sin());
        msgs.push(Msg {
            topic: "/tf".into(),
            schema: TF,
            log_time: p.t + 0.001,
            data: tf_message(
                true,
                &[
                    (p.t + palm_clock, "base_link", "palm_link", base_from_palm),
                    (p.t + palm_clock, "base_link", "elbow", joint),
                ],
            ),
        });
    }
    msgs.sort_by(|a, b| a.log_time.total_cmp(&b.log_time));
    // Messages need not arrive in stamp order: swap neighbours now and then.
    for k in (10..msgs.len() - 1).step_by(17) {
        msgs.swap(k, k + 1);
    }
    write_bag(path, &msgs, compression);
}

fn selection(object: &str, palm: Option<&str>) -> BagSelection {
    BagSelection {
        object: object.into(),
        palm: palm.map(Into::into),
        ..Default::default()
    }
}

fn with_offset(offset: f64) -> Learner {
    let mut c = Config::default();
    c.clocks.palm_time_offset_s = offset;
    Learner::new(c)
}

/// The learnt edges of two observations agree to `tol` (m, rad), and their kinds.
fn assert_same_edges(a: &Observation, b: &Observation, tol: f64) {
    let (ca, cb) = (&a.classification, &b.classification);
    assert_eq!(ca.kind, cb.kind);
    assert_eq!(ca.topples.len(), cb.topples.len());
    for (x, y) in ca.edges().zip(cb.edges()) {
        assert!((x.line.point - y.line.point).norm() < tol, "{x:?}\n{y:?}");
        assert!(
            x.line.direction.angle(&y.line.direction) < tol,
            "{x:?}\n{y:?}"
        );
    }
    for (x, y) in a.dynamics.iter().zip(&b.dynamics) {
        let (p, q) = (x.phi.unwrap(), y.phi.unwrap());
        assert!((p - q).abs() < tol, "phi {p} vs {q}");
    }
}

/// The case: `objmodel learn session.mcap --object tag36h11:0 --palm palm_link` on a
/// zstd-compressed apriltag_ros-style bag with the palm on its own clock gives the model of
/// the poses it was written from.
#[test]
fn apriltag_bag_with_the_palm_on_its_own_clock_learns_what_the_poses_teach() {
    let dir = tempfile::tempdir().unwrap();
    let d = instrumented(31);
    let truth = with_offset(0.0).observe(&Source::Memory(&d)).unwrap();
    assert_eq!(truth.classification.kind, Kind::Topple);
    for (name, compression) in [
        ("zstd.mcap", Some(Compression::Zstd)),
        ("lz4.mcap", Some(Compression::Lz4)),
        ("plain.mcap", None),
    ] {
        let path = dir.path().join(name);
        apriltag_bag(&path, &d, 0.25, compression);
        // To try the command line on it: OBJMODEL_KEEP_BAGS=DIR keeps a copy.
        if let Some(keep) = std::env::var_os("OBJMODEL_KEEP_BAGS") {
            std::fs::copy(&path, Path::new(&keep).join(name)).unwrap();
        }
        let sel = selection("tag36h11:0", Some("palm_link"));
        let source = Source::Bag {
            path: &path,
            selection: &sel,
        };
        let got = with_offset(-0.25).observe(&source).unwrap();
        assert_eq!(got.classification.name, name);
        assert_eq!(got.classification.frames, d.object.len() as u64);
        assert!(got.classification.instrumented);
        assert_same_edges(&got, &truth, 1e-6);
        // The same through `learn`, as the command line calls it.
        let mut tree = objmodel::tree::Tree::default();
        let reports = with_offset(-0.25).learn(&mut tree, &[source]).unwrap();
        assert_eq!(reports.len(), 1);
        // One edge, taught or (one demonstration at 1 mm and 30 Hz) held back as too loose.
        let edges: Vec<_> = tree.edge_estimates().collect();
        assert_eq!(edges.len(), 1);
        assert_eq!(edges[0].support, vec![name.to_string()]);
    }
}

#[test]
fn a_missing_topic_or_frame_is_an_error_that_lists_what_the_bag_holds() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.mcap");
    apriltag_bag(&path, &instrumented(32), 0.0, Some(Compression::Zstd));
    let learner = Learner::new(Config::default());
    for (object, palm, says) in [
        (
            "tag36h11:7",
            None,
            "no topic or tf frame 'tag36h11:7' for the object",
        ),
        (
            "tag36h11:0",
            Some("palm"),
            "no topic or tf frame 'palm' for the palm",
        ),
        ("/tf", None, "is a tf topic"),
        ("/camera/image_raw", None, "sensor_msgs/msg/Image"),
        ("world", None, "root of the tf tree"),
    ] {
        let sel = selection(object, palm);
        let e = learner
            .observe(&Source::Bag {
                path: &path,
                selection: &sel,
            })
            .unwrap_err()
            .to_string();
        assert!(e.contains(says), "{e}");
        for listed in [
            "tag36h11:0 <- camera_optical (",
            "palm_link <- base_link (",
            "camera_optical <- world (static)",
            "/camera/image_raw (sensor_msgs/msg/Image, 1 messages)",
        ] {
            assert!(e.contains(listed), "{listed} not in: {e}");
        }
    }
}

/// Pose topics instead of tf, big-endian and little-endian, lz4: the object on a
/// PoseStamped topic in the camera frame (tf says where the camera is), the palm as
/// Odometry in the world frame; and PoseWithCovarianceStamped.
#[test]
fn pose_topics_of_every_type_give_the_same_poses() {
    let dir = tempfile::tempdir().unwrap();
    let d = instrumented(33);
    let truth = with_offset(0.0).observe(&Source::Memory(&d)).unwrap();
    let wc = world_from_camera();
    let mut msgs = vec![Msg {
        topic: "/tf_static".into(),
        schema: TF,
        log_time: 0.0,
        data: tf_message(false, &[(0.0, "world", "camera", wc)]),
    }];
    for p in &d.object {
        msgs.push(Msg {
            topic: "/tag_pose".into(),
            schema: POSE_STAMPED,
            log_time: p.t,
            data: pose_stamped(false, p.t, "camera", &(wc.inverse() * p.pose)),
        });
        msgs.push(Msg {
            topic: "/tag_pose_cov".into(),
            schema: POSE_COV,
            log_time: p.t,
            data: pose_with_covariance_stamped(true, p.t, "world", &p.pose),
        });
    }
    for p in d.palm.as_ref().unwrap() {
        msgs.push(Msg {
            topic: "/palm/odom".into(),
            schema: ODOMETRY,
            log_time: p.t,
            data: odometry(true, p.t, "world", "palm", &p.pose),
        });
    }
    let path = dir.path().join("topics.mcap");
    write_bag(&path, &msgs, Some(Compression::Lz4));
    for object in ["/tag_pose", "/tag_pose_cov"] {
        let sel = BagSelection {
            reference: Some("world".into()),
            ..selection(object, Some("/palm/odom"))
        };
        let got = with_offset(0.0)
            .observe(&Source::Bag {
                path: &path,
                selection: &sel,
            })
            .unwrap();
        assert_same_edges(&got, &truth, 1e-6);
    }
}

/// Lengthen the rest at the start or end of `poses` by `secs`: its first or last 15 poses
/// (half a second, inside the rest) repeated, on new stamps.
fn pad_rest(poses: &mut Vec<StampedPose>, secs: f64, at_end: bool) {
    let n = (secs * 30.0) as usize;
    let m = poses.len();
    let src: Vec<_> = if at_end {
        poses[m - 15..].to_vec()
    } else {
        poses[..15].to_vec()
    };
    if at_end {
        let last = poses[m - 1].t;
        for k in 0..n {
            poses.push(StampedPose::new(
                last + (k + 1) as f64 / 30.0,
                src[k % 15].pose,
            ));
        }
    } else {
        let first = poses[0].t;
        let mut pre: Vec<_> = (0..n)
            .map(|k| StampedPose::new(first - (n - k) as f64 / 30.0, src[k % 15].pose))
            .collect();
        pre.append(poses);
        *poses = pre;
    }
}

/// A session of two topples with the box carried back between them (a lifted arc) is cut at
/// its rests into three demonstrations, BAG#1..3; the first and last teach the edges the two
/// topples teach alone.
#[test]
fn split_cuts_a_session_at_its_rests() {
    let b = the_box();
    let p = |side| synth::ToppleParams {
        side,
        ..Default::default()
    };
    let mut a = synth::topple(&b, &p(0), &SynthNoise::REAL, 30.0, 41).demo;
    let mut c = synth::topple(&b, &p(1), &SynthNoise::REAL, 30.0, 42).demo;
    pad_rest(&mut a.object, 1.5, true);
    let learner = Learner::new(Config::default());
    let alone = [&a, &c].map(|d| learner.observe(&Source::Memory(d)).unwrap());
    // c after a: 2 s of carrying from a's last pose to c's first, c shifted in time.
    let (from, t_end) = (a.object.last().unwrap().pose, a.object.last().unwrap().t);
    let shift = t_end + 2.0 + 1.5 - c.object[0].t;
    pad_rest(&mut c.object, 1.5, false);
    let to = c.object[0].pose;
    let mut session = a.object.clone();
    for k in 1..60 {
        let s = k as f64 / 60.0;
        let mut g = Isometry3::from_parts(
            from.translation
                .vector
                .lerp(&to.translation.vector, s)
                .into(),
            from.rotation.slerp(&to.rotation, s),
        );
        g.translation.vector.z += 0.15 * (std::f64::consts::PI * s).sin();
        session.push(StampedPose::new(t_end + 2.0 * s, g));
    }
    session.extend(
        c.object
            .iter()
            .map(|p| StampedPose::new(p.t + shift, p.pose)),
    );
    let msgs: Vec<Msg> = session
        .iter()
        .map(|p| Msg {
            topic: "/tf".into(),
            schema: TF,
            log_time: p.t,
            data: tf_message(true, &[(p.t, "world", "box", p.pose)]),
        })
        .collect();
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("session.mcap");
    write_bag(&path, &msgs, Some(Compression::Zstd));
    let sel = BagSelection {
        split_rest_s: Some(2.0),
        ..selection("box", None)
    };
    let parts = learner
        .observe_all(&Source::Bag {
            path: &path,
            selection: &sel,
        })
        .unwrap();
    let names: Vec<&str> = parts
        .iter()
        .map(|o| o.classification.name.as_str())
        .collect();
    assert_eq!(
        names,
        ["session.mcap#1", "session.mcap#2", "session.mcap#3"]
    );
    for (part, alone) in [(&parts[0], &alone[0]), (&parts[2], &alone[1])] {
        assert_eq!(part.classification.kind, Kind::Topple);
        let (x, y) = (
            part.classification.edges().next().unwrap(),
            alone.classification.edges().next().unwrap(),
        );
        assert!((x.line.point - y.line.point).norm() < 5e-3, "{x:?}\n{y:?}");
        assert!(x.line.direction.angle(&y.line.direction) < 2f64.to_radians());
    }
    // Without --split, one demonstration of the whole session.
    let whole = learner
        .observe_all(&Source::Bag {
            path: &path,
            selection: &selection("box", None),
        })
        .unwrap();
    assert_eq!(whole.len(), 1);
    assert_eq!(whole[0].classification.frames, session.len() as u64);
}

/// A tracker that lost the object and published on (every value NaN, or zero): those
/// messages are left out, as frames not recorded, and said; the rest learns what the poses
/// without them teach.
#[test]
fn poses_a_lost_tracker_published_are_left_out_and_said() {
    let dir = tempfile::tempdir().unwrap();
    let d = instrumented(34);
    let nan = f64::NAN;
    let blind = [
        Isometry3::from_parts(
            Translation3::new(nan, nan, nan),
            UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(nan, nan, nan, nan)),
        ),
        Isometry3::from_parts(
            Translation3::new(0.0, 0.0, 0.0),
            UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(0.0, 0.0, 0.0, 0.0)),
        ),
    ];
    // Lost in the rest before the tilt (frames 20-25) and once more later (frame 70).
    let lost = |k: usize| (20..26).contains(&k) || k == 70;
    let mut msgs = Vec::new();
    for (k, p) in d.object.iter().enumerate() {
        let pose = if lost(k) { blind[k % 2] } else { p.pose };
        msgs.push(Msg {
            topic: "/tag_pose".into(),
            schema: POSE_STAMPED,
            log_time: p.t,
            data: pose_stamped(true, p.t, "world", &pose),
        });
    }
    for p in d.palm.as_ref().unwrap() {
        msgs.push(Msg {
            topic: "/palm".into(),
            schema: POSE_STAMPED,
            log_time: p.t,
            data: pose_stamped(true, p.t, "world", &p.pose),
        });
    }
    let path = dir.path().join("lost.mcap");
    write_bag(&path, &msgs, Some(Compression::Zstd));
    let sel = BagSelection {
        reference: Some("world".into()),
        ..selection("/tag_pose", Some("/palm"))
    };
    let got = with_offset(0.0)
        .observe_all(&Source::Bag {
            path: &path,
            selection: &sel,
        })
        .unwrap();
    assert_eq!(got.len(), 1);
    let said = &got[0].classification.warnings;
    assert!(
        said.iter().any(|w| w.starts_with(
            "7 object poses had every value NaN or zero (the tracker lost it) and were left out"
        )),
        "{said:?}"
    );
    let mut without = d.clone();
    without.object = (d.object.iter().enumerate())
        .filter(|(k, _)| !lost(*k))
        .map(|(_, p)| *p)
        .collect();
    let truth = with_offset(0.0).observe(&Source::Memory(&without)).unwrap();
    assert!(truth.classification.edges().count() > 0);
    assert_same_edges(&got[0], &truth, 1e-6);
}

/// On tf, a transform a lost tracker published (every value NaN or zero) is counted for its
/// own frame: the object's poses say how many of theirs were lost, not how many of another
/// frame's (an unrelated joint's).
#[test]
fn lost_transforms_on_tf_are_counted_for_their_frame() {
    let dir = tempfile::tempdir().unwrap();
    let d = instrumented(35);
    let wc = world_from_camera();
    let nan = f64::NAN;
    let blind = Isometry3::from_parts(
        Translation3::new(nan, nan, nan),
        UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(nan, nan, nan, nan)),
    );
    let mut msgs = vec![Msg {
        topic: "/tf_static".into(),
        schema: TF,
        log_time: d.object[0].t - 1.0,
        data: tf_message(true, &[(0.0, "world", "camera_optical", wc)]),
    }];
    for (k, p) in d.object.iter().enumerate() {
        // The tag lost in 3 frames; the joint, published with it, in 9.
        let tag = if (30..33).contains(&k) {
            blind
        } else {
            wc.inverse() * p.pose
        };
        let joint = if k % 10 == 5 {
            blind
        } else {
            Isometry3::rotation(Vector3::z() * p.t.sin())
        };
        msgs.push(Msg {
            topic: "/tf".into(),
            schema: TF,
            log_time: p.t + 0.01,
            data: tf_message(
                true,
                &[
                    (p.t, "camera_optical", "tag36h11:0", tag),
                    (p.t, "world", "elbow", joint),
                ],
            ),
        });
    }
    let path = dir.path().join("tf_lost.mcap");
    write_bag(&path, &msgs, Some(Compression::Zstd));
    let sel = BagSelection {
        reference: Some("world".into()),
        ..selection("tag36h11:0", None)
    };
    let got = with_offset(0.0)
        .observe_all(&Source::Bag {
            path: &path,
            selection: &sel,
        })
        .unwrap();
    let said = &got[0].classification.warnings;
    let lost: Vec<&String> = said
        .iter()
        .filter(|w| w.contains("the tracker lost it"))
        .collect();
    assert_eq!(lost.len(), 1, "{said:?}");
    assert!(
        lost[0].starts_with("3 object poses had every value NaN or zero"),
        "{said:?}"
    );
    assert!(d.object.len() / 10 > 3);
}
