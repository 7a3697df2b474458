//! How fast a bag is read, against TUM on the same poses (a measurement, not a check).

mod bag_fixture;

use bag_fixture::*;
use mcap::Compression;
use nalgebra::{Isometry3, Translation3, UnitQuaternion};
use objmodel::format::bag::BagSelection;
use objmodel::trajectory::StampedPose;

/// Bag read speed against TUM on the same poses (`cargo test --release -p objmodel --test
/// bag_speed -- --ignored --nocapture`).
#[test]
#[ignore]
fn measure_bag_read_speed() {
    let dir = tempfile::tempdir().unwrap();
    let n = 200_000;
    let poses: Vec<StampedPose> = (0..n)
        .map(|k| {
            let t = 1.7e9 + k as f64 / 100.0;
            StampedPose::new(
                t,
                Isometry3::from_parts(
                    Translation3::new(t.sin(), 0.1, 0.2),
                    UnitQuaternion::from_euler_angles(0.1, k as f64 * 1e-4, 0.3),
                ),
            )
        })
        .collect();
    let tum = dir.path().join("p.tum");
    objmodel::format::write_tum(&tum, &poses, "speed").unwrap();
    let msgs: Vec<Msg> = poses
        .iter()
        .map(|p| Msg {
            topic: "/tf".into(),
            schema: TF,
            log_time: p.t - 1.7e9,
            data: tf_message(true, &[(p.t, "camera", "tag36h11:0", p.pose)]),
        })
        .collect();
    for (name, c) in [("zstd", Some(Compression::Zstd)), ("none", None)] {
        let bag = dir.path().join(format!("p_{name}.mcap"));
        write_bag(&bag, &msgs, c);
        let size = std::fs::metadata(&bag).unwrap().len();
        let best = |f: &dyn Fn() -> usize| {
            (0..5)
                .map(|_| {
                    let t = std::time::Instant::now();
                    assert_eq!(f(), n);
                    t.elapsed().as_secs_f64()
                })
                .fold(f64::INFINITY, f64::min)
        };
        let sel = BagSelection {
            object: "tag36h11:0".into(),
            ..Default::default()
        };
        let t_bag = best(&|| {
            objmodel::format::bag::read_bag_demonstrations(&bag, &sel, 0.0).unwrap()[0]
                .demo
                .object
                .len()
        });
        let t_read = best(&|| {
            let b = objmodel::format::bag::read_bag(&bag, &[]).unwrap();
            b.tf.edges()[0].poses.len()
        });
        let t_tum = best(&|| objmodel::format::read_trajectory(&tum).unwrap().len());
        eprintln!(
            "  of which reading and decoding the messages {:.0}%",
            100.0 * t_read / t_bag
        );
        eprintln!(
            "{n} poses: bag ({name}, {:.1} MB) {:.2} Mposes/s, TUM ({:.1} MB) {:.2} Mposes/s",
            size as f64 / 1e6,
            n as f64 / t_bag / 1e6,
            std::fs::metadata(&tum).unwrap().len() as f64 / 1e6,
            n as f64 / t_tum / 1e6
        );
    }
}
