//! The CDR decoder of ROS 2 bags against messages built byte by byte, little- and big-endian:
//! alignment counted from the end of the encapsulation header, strings with their NUL, padding
//! to 8 before doubles.

use nalgebra::Vector3;
use objmodel::format::bag::messages::{decode, PoseType};

fn le_or_be(le: bool, f: f64) -> [u8; 8] {
    if le {
        f.to_le_bytes()
    } else {
        f.to_be_bytes()
    }
}

fn u32_bytes(le: bool, x: u32) -> [u8; 4] {
    if le {
        x.to_le_bytes()
    } else {
        x.to_be_bytes()
    }
}

/// A PoseStamped built byte by byte: encapsulation, stamp, frame, padding to 8, seven doubles.
fn hand_pose_stamped(le: bool) -> Vec<u8> {
    hand_pose_stamped_of(le, [0.5, -1.25, 2.0, 0.0, 0.0, 0.6, 0.8])
}

/// [`hand_pose_stamped`] with the seven doubles `pose`.
fn hand_pose_stamped_of(le: bool, pose: [f64; 7]) -> Vec<u8> {
    let mut b = vec![0, le as u8, 0, 0];
    b.extend(u32_bytes(le, 1_700_000_000)); // sec
    b.extend(u32_bytes(le, 250_000_000)); // nanosec
    b.extend(u32_bytes(le, 6)); // "world" and its NUL
    b.extend(b"world\0");
    assert_eq!(b.len() - 4, 18);
    b.extend([0; 6]); // to 24, a multiple of 8
    for v in pose {
        b.extend(le_or_be(le, v));
    }
    b
}

#[test]
fn cdr_pose_stamped_decodes_in_both_byte_orders() {
    for le in [true, false] {
        let bytes = hand_pose_stamped(le);
        let mut got = vec![];
        decode(PoseType::PoseStamped, &bytes, &mut |r| {
            got.push((r.t, r.parent.to_vec(), r.pose.unwrap()))
        })
        .unwrap();
        assert_eq!(got.len(), 1);
        let (t, frame, pose) = &got[0];
        assert_eq!(*t, 1_700_000_000.25);
        assert_eq!(frame, b"world");
        assert_eq!(pose.translation.vector, Vector3::new(0.5, -1.25, 2.0));
        let q = pose.rotation.coords;
        assert_eq!([q.x, q.y, q.z, q.w], [0.0, 0.0, 0.6, 0.8]);
        // Cut anywhere, it is an error, never a panic.
        for n in 0..bytes.len() {
            assert!(decode(PoseType::PoseStamped, &bytes[..n], &mut |_| {}).is_err());
        }
    }
}

/// A TFMessage of two transforms, built byte by byte (offsets after the header in comments).
fn hand_tf(le: bool) -> Vec<u8> {
    let mut b = vec![0, le as u8, 0, 0];
    b.extend(u32_bytes(le, 2)); // 0: two transforms
    for (k, child) in [b"tag36h11:0\0", b"tag36h11:1\0"].iter().enumerate() {
        b.extend(u32_bytes(le, 10 + k as u32)); // sec
        b.extend(u32_bytes(le, 0)); // nanosec
        b.extend(u32_bytes(le, 4));
        b.extend(b"cam\0");
        b.extend(u32_bytes(le, 11));
        b.extend(*child); // ends at 35, then 127
        b.extend(vec![0; if k == 0 { 5 } else { 1 }]); // to 40, then 128
        for v in [k as f64, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0] {
            b.extend(le_or_be(le, v));
        }
    }
    assert_eq!(b.len() - 4, 184);
    b
}

#[test]
fn cdr_tf_message_decodes_in_both_byte_orders() {
    for le in [true, false] {
        let bytes = hand_tf(le);
        let mut got = vec![];
        decode(PoseType::TfMessage, &bytes, &mut |r| {
            got.push((r.t, r.parent.to_vec(), r.child.to_vec(), r.pose.unwrap()))
        })
        .unwrap();
        assert_eq!(got.len(), 2);
        for (k, (t, parent, child, pose)) in got.iter().enumerate() {
            assert_eq!(*t, 10.0 + k as f64);
            assert_eq!(parent, b"cam");
            assert_eq!(child, format!("tag36h11:{k}").as_bytes());
            assert_eq!(pose.translation.vector, Vector3::new(k as f64, 0.0, 1.0));
            // x = 1: a half turn about x.
            assert!((pose.rotation.angle() - std::f64::consts::PI).abs() < 1e-12);
        }
    }
    // A bad quaternion is an error naming it.
    let mut bad = hand_pose_stamped(true);
    let n = bad.len();
    bad[n - 8..].copy_from_slice(&0.1f64.to_le_bytes());
    let e = decode(PoseType::PoseStamped, &bad, &mut |_| {}).unwrap_err();
    assert!(e.0.contains("quaternion"), "{e}");
}

/// A tracker that lost the object and published on: every value NaN, or zero, is no pose
/// (the reader counts it); some values NaN and others not is an error.
#[test]
fn a_lost_pose_is_none_and_a_broken_one_an_error() {
    let n = f64::NAN;
    for pose in [[n; 7], [0.0; 7]] {
        let mut got = vec![];
        decode(
            PoseType::PoseStamped,
            &hand_pose_stamped_of(true, pose),
            &mut |r| got.push(r.pose),
        )
        .unwrap();
        assert_eq!(got, [None]);
    }
    let broken = hand_pose_stamped_of(true, [0.5, n, 2.0, 0.0, 0.0, 0.6, 0.8]);
    let e = decode(PoseType::PoseStamped, &broken, &mut |_| {}).unwrap_err();
    assert!(e.0.contains("not finite"), "{e}");
}
