//! Writing small ROS 2 bags for the tests: MCAP files (the `mcap` crate's writer) of messages
//! encoded here by hand in CDR, independently of the library's decoder.

#![allow(dead_code)]

use mcap::records::MessageHeader;
use mcap::{Compression, WriteOptions, Writer};
use nalgebra::Isometry3;
use std::collections::{BTreeMap, HashMap};
use std::io::BufWriter;
use std::path::Path;

/// A CDR message being written (XCDR1, little- or big-endian).
pub struct Cdr {
    out: Vec<u8>,
    le: bool,
}

impl Cdr {
    pub fn new(le: bool) -> Self {
        Self {
            out: vec![0, le as u8, 0, 0],
            le,
        }
    }
    fn align(&mut self, n: usize) {
        while !(self.out.len() - 4).is_multiple_of(n) {
            self.out.push(0);
        }
    }
    pub fn u32(&mut self, x: u32) -> &mut Self {
        self.align(4);
        let b = if self.le {
            x.to_le_bytes()
        } else {
            x.to_be_bytes()
        };
        self.out.extend_from_slice(&b);
        self
    }
    pub fn i32(&mut self, x: i32) -> &mut Self {
        self.u32(x as u32)
    }
    pub fn f64(&mut self, x: f64) -> &mut Self {
        self.align(8);
        let b = if self.le {
            x.to_le_bytes()
        } else {
            x.to_be_bytes()
        };
        self.out.extend_from_slice(&b);
        self
    }
    pub fn string(&mut self, s: &str) -> &mut Self {
        self.u32(s.len() as u32 + 1);
        self.out.extend_from_slice(s.as_bytes());
        self.out.push(0);
        self
    }
    /// `std_msgs/Header`.
    pub fn header(&mut self, t: f64, frame: &str) -> &mut Self {
        let (sec, nsec) = sec_nsec(t);
        self.i32(sec).u32(nsec).string(frame)
    }
    /// A `Pose` (or `Transform`): position, then quaternion x y z w.
    pub fn pose(&mut self, g: &Isometry3<f64>) -> &mut Self {
        let p = g.translation.vector;
        let q = g.rotation.coords; // x y z w
        for v in [p.x, p.y, p.z, q.x, q.y, q.z, q.w] {
            self.f64(v);
        }
        self
    }
    pub fn bytes(&self) -> Vec<u8> {
        self.out.clone()
    }
}

/// A stamp as (sec, nanosec).
pub fn sec_nsec(t: f64) -> (i32, u32) {
    let mut sec = t.floor();
    let mut nsec = ((t - sec) * 1e9).round();
    if nsec >= 1e9 {
        sec += 1.0;
        nsec -= 1e9;
    }
    (sec as i32, nsec as u32)
}

pub fn pose_stamped(le: bool, t: f64, frame: &str, g: &Isometry3<f64>) -> Vec<u8> {
    Cdr::new(le).header(t, frame).pose(g).bytes()
}

pub fn pose_with_covariance_stamped(le: bool, t: f64, frame: &str, g: &Isometry3<f64>) -> Vec<u8> {
    let mut c = Cdr::new(le);
    c.header(t, frame).pose(g);
    for k in 0..36 {
        c.f64(k as f64 * 0.01);
    }
    c.bytes()
}

pub fn odometry(le: bool, t: f64, frame: &str, child: &str, g: &Isometry3<f64>) -> Vec<u8> {
    let mut c = Cdr::new(le);
    c.header(t, frame).string(child).pose(g);
    for _ in 0..(36 + 6 + 36) {
        c.f64(0.5);
    }
    c.bytes()
}

/// A `tf2_msgs/TFMessage` of transforms (stamp, parent, child, parent_from_child).
pub fn tf_message(le: bool, transforms: &[(f64, &str, &str, Isometry3<f64>)]) -> Vec<u8> {
    let mut c = Cdr::new(le);
    c.u32(transforms.len() as u32);
    for (t, parent, child, g) in transforms {
        c.header(*t, parent).string(child).pose(g);
    }
    c.bytes()
}

/// Schema names.
pub const POSE_STAMPED: &str = "geometry_msgs/msg/PoseStamped";
pub const POSE_COV: &str = "geometry_msgs/msg/PoseWithCovarianceStamped";
pub const ODOMETRY: &str = "nav_msgs/msg/Odometry";
pub const TF: &str = "tf2_msgs/msg/TFMessage";

/// One message to write: topic, schema, log time [s], CDR bytes.
pub struct Msg {
    pub topic: String,
    pub schema: &'static str,
    pub log_time: f64,
    pub data: Vec<u8>,
}

/// Write `messages` (in the order given) to an MCAP bag at `path`.
pub fn write_bag(path: &Path, messages: &[Msg], compression: Option<Compression>) {
    let f = BufWriter::new(std::fs::File::create(path).unwrap());
    let mut w: Writer<_> = WriteOptions::new()
        .compression(compression)
        .profile("ros2")
        .chunk_size(Some(64 * 1024))
        .create(f)
        .unwrap();
    let mut schemas: HashMap<&str, u16> = HashMap::new();
    let mut channels: HashMap<String, u16> = HashMap::new();
    // An unrelated topic, as a real bag has.
    let img = w
        .add_schema("sensor_msgs/msg/Image", "ros2msg", b"")
        .unwrap();
    let img_ch = w
        .add_channel(img, "/camera/image_raw", "cdr", &BTreeMap::new())
        .unwrap();
    w.write_to_known_channel(
        &MessageHeader {
            channel_id: img_ch,
            sequence: 0,
            log_time: 1,
            publish_time: 1,
        },
        &[0, 1, 0, 0, 9, 9, 9, 9],
    )
    .unwrap();
    for (seq, m) in messages.iter().enumerate() {
        let sid = *schemas
            .entry(m.schema)
            .or_insert_with(|| w.add_schema(m.schema, "ros2msg", b"").unwrap());
        let cid = *channels.entry(m.topic.clone()).or_insert_with(|| {
            w.add_channel(sid, &m.topic, "cdr", &BTreeMap::new())
                .unwrap()
        });
        let ns = (m.log_time.max(0.0) * 1e9) as u64;
        w.write_to_known_channel(
            &MessageHeader {
                channel_id: cid,
                sequence: seq as u32,
                log_time: ns,
                publish_time: ns,
            },
            &m.data,
        )
        .unwrap();
    }
    w.finish().unwrap();
}
