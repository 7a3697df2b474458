//! Tests of the pose file formats: parsing, errors with line numbers, palm files, atomic writes.

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};
use objmodel::format::{self, Format, PoseReader, QUAT_NORM_TOLERANCE};
use objmodel::{Error, StampedPose};
use std::io::BufReader;
use std::path::{Path, PathBuf};

/// A fresh, empty directory (`tempfile`), kept on disk for the test's life: its files are
/// removed when the test process ends its use of them (the caller removes it, or the system's
/// temporary folder does).
fn tmpdir(tag: &str) -> PathBuf {
    tempfile::Builder::new()
        .prefix(&format!("objmodel-fmt-{tag}-"))
        .tempdir()
        .unwrap()
        .keep()
}

fn write(dir: &Path, name: &str, content: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, content).unwrap();
    p
}

/// Run `f` on a file `name` holding `content`, in a fresh directory.
fn with_file<T>(name: &str, content: &str, f: impl FnOnce(&Path) -> T) -> T {
    let dir = tmpdir("f");
    let r = f(&write(&dir, name, content));
    let _ = std::fs::remove_dir_all(&dir);
    r
}

/// Read `content` as file `name` and return the error's text, asserting it is at `line`.
fn parse_error(name: &str, content: &str, line: usize) -> String {
    with_file(name, content, |p| {
        let e = format::read_trajectory(p).expect_err(content);
        let (text, prefix) = (e.to_string(), format!("{}:{line}: ", p.display()));
        assert!(matches!(e, Error::Parse { .. }), "{text}");
        assert!(text.starts_with(&prefix), "expected {prefix:?} in {text:?}");
        text
    })
}

/// Read `content` as file `name` and return the whole-file error's text.
fn file_error(name: &str, content: &str) -> String {
    with_file(name, content, |p| {
        let e = format::read_trajectory(p).expect_err(content);
        assert!(matches!(e, Error::File { .. }), "{e}");
        e.to_string()
    })
}

fn read_str(name: &str, content: &str) -> Vec<StampedPose> {
    with_file(name, content, |p| {
        format::read_trajectory(p).unwrap_or_else(|e| panic!("{e}"))
    })
}

fn xyzw(p: &StampedPose) -> [f64; 4] {
    let q = p.pose.rotation.quaternion();
    [q.i, q.j, q.k, q.w]
}

fn xyz(p: &StampedPose) -> [f64; 3] {
    let t = p.pose.translation.vector;
    [t.x, t.y, t.z]
}

const LINE: &str = "0.5 1 2 3 0 0 0 1";

#[test]
fn tum_whitespace_comments_crlf() {
    let text = "# header comment\r\n\r\n  1.0\t2.0   3.0 4.0\t\t0 0 0 1   # trailing\r\n\
                #another\r\n\t \r\n2.5 -1 -2 -3 0.0 1.0 0.0 0.0\r\n3e0 1e-3 .5 5. +0 -0 0 -1";
    let poses = read_str("a.tum", text);
    assert_eq!(poses.len(), 3);
    assert_eq!(poses[0].t, 1.0);
    assert_eq!(xyz(&poses[0]), [2.0, 3.0, 4.0]);
    assert_eq!(xyzw(&poses[0]), [0.0, 0.0, 0.0, 1.0]);
    assert_eq!(xyz(&poses[1]), [-1.0, -2.0, -3.0]);
    assert_eq!(xyzw(&poses[1]), [0.0, 1.0, 0.0, 0.0]);
    assert_eq!(poses[2].t, 3.0);
    assert_eq!(xyz(&poses[2]), [1e-3, 0.5, 5.0]);
    // the sign of the quaternion is kept: w = -1 stays -1
    assert_eq!(xyzw(&poses[2])[3], -1.0);

    // line numbers of the poses, and a byte-order mark
    let bytes = format!("\u{feff}# c\n{LINE}\n\n1.5 0 0 0 0 0 0 1\n");
    let mut r = PoseReader::new(bytes.as_bytes(), "x.tum".into(), Format::Tum);
    assert_eq!(r.line(), 0);
    r.next().unwrap().unwrap();
    assert_eq!(r.line(), 2);
    r.next().unwrap().unwrap();
    assert_eq!(r.line(), 4);
    assert!(r.next().is_none());
}

#[test]
fn csv_reordered_and_extra_columns() {
    let text = "# made by a tracker\nqw, QX ,qy,qz,Time,frame,x,y,z,note\n\
                1,0,0,0,10.0,7,1.5,2.5,3.5,\"a, b\"\n\
                \"0\", 1 ,0,0,10.1,8,-1,-2,-3,x # comment\n";
    let poses = read_str("b.csv", text);
    assert_eq!(poses.len(), 2);
    assert_eq!(poses[0].t, 10.0);
    assert_eq!(xyz(&poses[0]), [1.5, 2.5, 3.5]);
    assert_eq!(xyzw(&poses[0]), [0.0, 0.0, 0.0, 1.0]);
    assert_eq!(poses[1].t, 10.1);
    assert_eq!(xyzw(&poses[1]), [1.0, 0.0, 0.0, 0.0]);

    // detected from the content without a .csv name; timestamp/tx names
    let text = "timestamp,tx,ty,tz,qx,qy,qz,qw\n1,2,3,4,0,0,0,1\n";
    let poses = read_str("c.txt", text);
    assert_eq!(xyz(&poses[0]), [2.0, 3.0, 4.0]);
    // a commented-out header
    let poses = read_str(
        "d.csv",
        "#t,x,y,z,qx,qy,qz,qw\n1,2,3,4,0,0,0,1\n2,2,3,4,0,0,0,1\n",
    );
    assert_eq!(poses.len(), 2);
    let poses = read_str("d.log", "#t,x,y,z,qx,qy,qz,qw\n1,2,3,4,0,0,0,1\n");
    assert_eq!(poses[0].t, 1.0);
}

/// Other tools' CSV headers: EuRoC/ASL ground truth (a commented header with units, stamps in
/// nanoseconds, declared, `w` first), a motion-capture export (units in parentheses, a frame column), and
/// a ROS message flattened to CSV (dotted paths, a text column). Each reads the same poses.
#[test]
fn csv_headers_of_other_tools() {
    let want = |poses: &[StampedPose]| {
        assert_eq!(poses.len(), 2);
        assert_eq!(xyz(&poses[1]), [1.5, -2.5, 3.5]);
        let q = xyzw(&poses[1]);
        let n = (0.5f64 * 0.5 * 4.0).sqrt();
        assert!(q.iter().all(|c| (c.abs() - 0.5 / n).abs() < 1e-12), "{q:?}");
    };
    let euroc = "#timestamp [ns],p_RS_R_x [m],p_RS_R_y [m],p_RS_R_z [m],q_RS_w [],q_RS_x [],\
                 q_RS_y [],q_RS_z []\n\
                 1403636579758555392,1,2,3,1,0,0,0\n\
                 1403636579763555584,1.5,-2.5,3.5,0.5,0.5,0.5,0.5\n";
    let poses = read_str("data.csv", euroc);
    want(&poses);
    // The header declares nanoseconds: read as seconds.
    assert_eq!(poses[0].t, 1403636579758555392.0 * 1e-9);
    let mocap = "Frame,Time (Seconds),X,Y,Z,qX,qY,qZ,qW\n\
                 0,0.000,1,2,3,0,0,0,1\n\
                 1,0.004,1.5,-2.5,3.5,0.5,0.5,0.5,0.5\n";
    let poses = read_str("take.csv", mocap);
    want(&poses);
    assert_eq!(poses[1].t, 0.004);
    let ros = "%time,field.header.seq,field.header.stamp,field.header.frame_id,\
               field.transform.translation.x,field.transform.translation.y,\
               field.transform.translation.z,field.transform.rotation.x,\
               field.transform.rotation.y,field.transform.rotation.z,field.transform.rotation.w\n\
               10.0,1,10.0,world,1,2,3,0,0,0,1\n\
               10.1,2,10.1,world,1.5,-2.5,3.5,0.5,0.5,0.5,0.5\n";
    let poses = read_str("tf.csv", ros);
    want(&poses);
    // The measurement's stamp, where the file has it, not the time it was logged.
    let logged = ros
        .replace("10.0,1,10.0,", "10.5,1,10.0,")
        .replace("10.1,2,10.1,", "10.52,2,10.1,");
    let poses = read_str("tf_logged_late.csv", &logged);
    want(&poses);
    assert_eq!((poses[0].t, poses[1].t), (10.0, 10.1));
    let unstamped = "%time,field.pose.position.x,field.pose.position.y,field.pose.position.z,\
                     field.pose.orientation.x,field.pose.orientation.y,field.pose.orientation.z,\
                     field.pose.orientation.w\n7,1,2,3,0,0,0,1\n7.1,1.5,-2.5,3.5,0.5,0.5,0.5,0.5\n";
    let poses = read_str("pose.csv", unstamped);
    want(&poses);
    assert_eq!(poses[1].t, 7.1);
    // Euler angles under a quaternion's names: no `w`, refused by name.
    let err = parse_error(
        "euler.csv",
        "t,x,y,z,rotation.x,rotation.y,rotation.z\n0,1,2,3,0.1,0.2,0.3\n",
        1,
    );
    assert!(err.contains("no column for qw"), "{err}");
}

/// A whitespace-separated file whose first line names TUM's columns in TUM's order, uncommented
/// (spaces or tabs, other tools' names): a header. In another order it is no TUM header, and
/// the line is refused as before; a CSV header separated by semicolons is refused with a hint.
#[test]
fn a_first_line_naming_tums_columns_is_a_header() {
    for header in [
        "timestamp tx ty tz qx qy qz qw",
        "t\tx\ty\tz\tqx\tqy\tqz\tqw",
        "time[s]  px py pz  quat_x quat_y quat_z quat_w",
    ] {
        let text = format!("{header}\n1 1 2 3 0 0 0 1\n2 1.5 -2.5 3.5 0.5 0.5 0.5 0.5\n");
        let poses = read_str("h.txt", &text);
        assert_eq!(poses.len(), 2, "{header}");
        assert_eq!(xyz(&poses[1]), [1.5, -2.5, 3.5]);
    }
    let err = parse_error("o.txt", "t x y z qw qx qy qz\n1 1 2 3 1 0 0 0\n", 1);
    assert!(err.contains("is not a number"), "{err}");
    let err = parse_error("s.csv", "t;x;y;z;qx;qy;qz;qw\n1;1;2;3;0;0;0;1\n", 1);
    assert!(err.contains("separated by ';'"), "{err}");
}

#[test]
fn detect_format_rules() {
    let p = Path::new("x.tum");
    assert_eq!(
        format::detect_format(Path::new("x.CSV"), "1 2 3 4 5 6 7 8"),
        Format::Csv
    );
    assert_eq!(format::detect_format(p, "t,x,y,z,qx,qy,qz,qw"), Format::Csv);
    assert_eq!(format::detect_format(p, "1 2 3 4 0 0 0 1"), Format::Tum);
    assert_eq!(format::detect_format(p, "1,2,3,4,0,0,0,1e-3"), Format::Tum);
    assert_eq!(format::detect_format(p, "timestamp tx ty tz"), Format::Tum);
}

fn random_pose(rng: &mut Rng, t: f64) -> StampedPose {
    let axis = Vector3::new(rng.f64() - 0.5, rng.f64() - 0.5, rng.f64() - 0.5);
    let rot = UnitQuaternion::from_scaled_axis(axis * 6.0);
    let tr = Translation3::new(rng.f64() * 4.0 - 2.0, rng.f64() - 0.5, rng.f64() * 100.0);
    StampedPose::new(t, Isometry3::from_parts(tr, rot))
}

#[test]
fn round_trip_write_read() {
    let mut rng = Rng::new(42);
    let poses: Vec<_> = (0..500)
        .map(|i| random_pose(&mut rng, 1.7e9 + i as f64 / 30.0))
        .collect();
    let dir = tmpdir("rt");
    let p = dir.join("traj.tum");
    format::write_tum(&p, &poses, "round trip\nsecond line").unwrap();
    let back = format::read_trajectory(&p).unwrap();
    assert_eq!(back.len(), poses.len());
    for (a, b) in poses.iter().zip(&back) {
        assert!((a.t - b.t).abs() < 1e-6);
        for (x, y) in xyz(a).iter().zip(xyz(b)) {
            assert!((x - y).abs() <= 1e-9, "{x} {y}");
        }
        for (x, y) in xyzw(a).iter().zip(xyzw(b)) {
            assert!((x - y).abs() <= 1e-9, "{x} {y}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn slightly_non_unit_quaternion_is_normalised() {
    let poses = read_str("n.tum", "1 0 0 0 0 0 0.6 0.803\n2 0 0 0 0 0 0 -0.995\n");
    let q = xyzw(&poses[0]);
    let n = q.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!((n - 1.0).abs() < 1e-15);
    assert!((q[2] / q[3] - 0.6 / 0.803).abs() < 1e-15);
    // normalised, sign kept
    assert_eq!(xyzw(&poses[1]), [0.0, 0.0, 0.0, -1.0]);
}

#[test]
fn errors_name_file_line_and_problem() {
    let h = "# comment\n1 0 0 0 0 0 0 1\n\n";
    let c = "t,x,y,z,qx,qy,qz,qw,extra\n1,0,0,0,0,0,0,1,a\n";
    let long = format!("{LINE}\n1 {}\n", "0 ".repeat(700_000));
    #[rustfmt::skip]
    let cases: Vec<(&str, String, usize, Vec<&str>)> = vec![
        ("demo.tum", format!("{h}2 0 0 0 0 0 1\n"), 4,
         vec!["expected 8 columns (timestamp tx ty tz qx qy qz qw), found 7"]),
        ("demo.tum", format!("{h}2 0 0 0 0 0 0 1 9\n"), 4, vec!["found 9"]),
        ("demo.tum", format!("{h}2,0,0,0,0,0,0,1\n"), 4, vec!["found 1", "header"]),
        ("demo.tum", format!("{h}2 0 0 0 0.5x 0 0 1\n"), 4,
         vec!["column 5 (qx): \"0.5x\" is not a number"]),
        ("demo.tum", format!("{h}2 0 nan 0 0 0 0 1\n"), 4, vec!["ty is NaN (\"nan\")"]),
        ("demo.tum", format!("{h}2 0 0 -inf 0 0 0 1\n"), 4, vec!["tz is infinite (\"-inf\")"]),
        ("demo.tum", format!("{h}2 0 0 0 0 1e999 0 1\n"), 4, vec!["qy is infinite"]),
        ("demo.tum", format!("{h}2 0 0 0 0 0 0 0\n"), 4, vec!["is zero"]),
        ("demo.tum", format!("{h}2 0 0 0 0 0 0 1.02\n"), 4, vec!["norm 1.02", "tolerance 0.01"]),
        ("demo.tum", format!("{h}2 0 0 0 .5 .5 .5 .5\n3 0 0 0 0 0 0 .98\n"), 5, vec!["norm 0.98"]),
        ("demo.tum", format!("{h}1 0 0 0 0 0 0 1\n"), 4,
         vec!["timestamp 1 on line 4 repeats timestamp 1 on line 2"]),
        ("demo.tum", format!("{h}5 0 0 0 0 0 0 1\n4.5 0 0 0 0 0 0 1\n"), 5,
         vec!["timestamp 4.5 on line 5 goes back from timestamp 5 on line 4"]),
        ("long.tum", long, 2, vec!["longer than"]),
        ("bin.tum", "\u{0}\u{1}\u{7f}\u{ff} \u{2603} 1 2\n".into(), 1, vec!["found 4"]),
        ("e.csv", "t,x,y,z,qx,qy,qz\n1,0,0,0,0,0,0\n".into(), 1, vec!["no column for qw"]),
        ("e.csv", "# c\ntime,tx,ty,tz,qw\n".into(), 2, vec!["no column for qx, qy, qz"]),
        ("e.csv", "t,x,tx,y,z,qx,qy,qz,qw\n".into(), 1, vec!["both give tx"]),
        ("e.csv", "1,0,0,0,0,0,0,1\n".into(), 1, vec!["no column for"]),
        ("e.csv", format!("{c}2,0,0,0,0,0,0,1\n"), 3,
         vec!["expected 9 columns (as in the CSV header on line 1), found 8"]),
        ("e.csv", format!("{c}2,0,0,0,0,0,zero,1,b\n"), 3,
         vec!["column 7 (qz): \"zero\" is not a number"]),
        ("e.csv", format!("{c}2,0,,0,0,0,0,1,b\n"), 3, vec!["column 3 (ty) is empty"]),
        ("e.csv", format!("{c}2,0,0,0,0,0,0,NaN,b\n"), 3, vec!["qw is NaN"]),
        ("e.csv", format!("{c}1,0,0,0,0,0,0,1,b\n"), 3, vec!["repeats timestamp 1 on line 2"]),
    ];
    for (name, content, line, needles) in &cases {
        let e = parse_error(name, content, *line);
        for needle in needles {
            assert!(e.contains(needle), "{needle:?} not in {e:?}");
        }
    }
    assert_eq!(QUAT_NORM_TOLERANCE, 0.01);
    // within the tolerance, gaps in time and absurd positions are all fine
    read_str("ok.tum", "1 0 0 0 0 0 0 1.0099\n2 0 0 0 0 0 0 0.9901\n");
    read_str("gap.tum", "1 -1e6 0 0 0 0 0 1\n1000 1e9 -5 0 0 0 0 1\n");
}

#[test]
fn files_without_poses() {
    assert!(file_error("e.tum", "").contains("empty"));
    assert!(file_error("e.tum", "# only\n\n  \n# comments\n").contains("no poses"));
    assert!(file_error("e.csv", "t,x,y,z,qx,qy,qz,qw\n").contains("header"));
    let e = format::read_trajectory(Path::new("/nonexistent/dir/x.tum")).unwrap_err();
    assert!(
        matches!(e, Error::Io { .. }) && e.to_string().contains("x.tum"),
        "{e}"
    );
    assert!(format::read_trajectory(&std::env::temp_dir()).is_err());
}

#[test]
fn iterator_stops_after_an_error() {
    let text = format!("{LINE}\n1 0 0 0 0 0 0 1\nbad\n3 0 0 0 0 0 0 1\n");
    let mut r = PoseReader::new(text.as_bytes(), "s.tum".into(), Format::Tum);
    assert!(r.next().unwrap().is_ok());
    assert!(r.next().unwrap().is_ok());
    let e = r.next().unwrap().unwrap_err().to_string();
    assert!(e.starts_with("s.tum:3: "), "{e}");
    assert!(r.next().is_none());
}

/// A reader that produces `n` TUM lines lazily, in odd-sized pieces.
struct Lines {
    i: usize,
    n: usize,
    pending: Vec<u8>,
}

impl std::io::Read for Lines {
    fn read(&mut self, buf: &mut [u8]) -> std::io::Result<usize> {
        while self.pending.len() < 100 && self.i < self.n {
            let i = self.i as f64;
            let line = if self.i % 97 == 5 {
                "# comment here\n\n".to_string()
            } else {
                format!(
                    "{:.6}\t{:.9} {:.9} {} 0 0 {:.9} {:.9}\r\n",
                    i / 30.0,
                    i.sin(),
                    -i,
                    i * 1e-3,
                    (i * 0.01).sin(),
                    (i * 0.01).cos()
                )
            };
            self.pending.extend_from_slice(line.as_bytes());
            self.i += 1;
        }
        let k = buf.len().min(self.pending.len()).min(1 + self.i % 37);
        buf[..k].copy_from_slice(&self.pending[..k]);
        self.pending.drain(..k);
        Ok(k)
    }
}

#[test]
fn streaming_with_small_buffers_matches() {
    let n = 20_000;
    let mut all = Vec::new();
    std::io::Read::read_to_end(
        &mut Lines {
            i: 0,
            n,
            pending: Vec::new(),
        },
        &mut all,
    )
    .unwrap();
    let big: Vec<_> = PoseReader::new(&all[..], "big".into(), Format::Tum)
        .collect::<Result<_, _>>()
        .unwrap();
    for cap in [1, 7, 64, 4096] {
        let src = BufReader::with_capacity(
            cap,
            Lines {
                i: 0,
                n,
                pending: Vec::new(),
            },
        );
        let mut r = PoseReader::new(src, "small".into(), Format::Tum);
        let mut k = 0;
        for p in r.by_ref() {
            assert_eq!(p.unwrap(), big[k], "capacity {cap}, pose {k}");
            k += 1;
        }
        assert_eq!(k, big.len());
    }
    assert!(big.len() > 19_000);
}

#[test]
fn palm_files() {
    let dir = tmpdir("palm");
    let obj = write(&dir, "push1.tum", LINE);
    assert_eq!(format::palm_path_for(&obj), None);
    let palm_csv = write(
        &dir,
        "push1.palm.csv",
        "t,x,y,z,qx,qy,qz,qw\n0.5,1,1,1,0,0,0,1\n",
    );
    assert_eq!(format::palm_path_for(&obj), Some(palm_csv.clone()));
    let palm = write(&dir, "push1.palm.tum", LINE);
    assert_eq!(format::palm_path_for(&obj), Some(palm.clone()));
    assert!(format::is_palm_file(&palm) && format::is_palm_file(Path::new("a/B.PALM.csv")));
    assert!(!format::is_palm_file(&obj) && !format::is_palm_file(Path::new("palm.tum")));
    assert_eq!(format::palm_path_for(&palm), None);
    let obj_csv = write(
        &dir,
        "push1.csv",
        "t,x,y,z,qx,qy,qz,qw\n0.5,1,1,1,0,0,0,1\n",
    );
    assert_eq!(format::palm_path_for(&obj_csv), Some(palm_csv.clone()));

    let demo = format::read_demonstration(&obj, None).unwrap();
    assert_eq!(demo.name, "push1");
    assert_eq!(demo.object.len(), 1);
    assert_eq!(demo.palm.as_ref().map(Vec::len), Some(1));
    let demo = format::read_demonstration(&obj, Some(&palm_csv)).unwrap();
    assert_eq!(xyz(&demo.palm.unwrap()[0]), [1.0, 1.0, 1.0]);
    let lone = write(&dir, "lone.tum", LINE);
    assert!(format::read_demonstration(&lone, None)
        .unwrap()
        .palm
        .is_none());
    assert!(format::read_demonstration(&lone, Some(&dir.join("missing.tum"))).is_err());
    let _ = std::fs::remove_dir_all(&dir);
}

fn entries(dir: &Path) -> Vec<String> {
    let mut v: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn write_atomic_keeps_old_file_on_failure() {
    let dir = tmpdir("atomic");
    let p = write(&dir, "out.json", "old");
    format::write_atomic(&p, b"new").unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
    assert_eq!(entries(&dir), ["out.json"]);

    // parent directory does not exist
    let missing = dir.join("no/such/dir/out.json");
    assert!(matches!(
        format::write_atomic(&missing, b"x"),
        Err(Error::Io { .. })
    ));
    assert_eq!(entries(&dir), ["out.json"]);

    // the target is a directory: rename fails, the temp file is removed
    let sub = dir.join("sub");
    std::fs::create_dir(&sub).unwrap();
    write(&sub, "keep", "k");
    assert!(format::write_atomic(&sub, b"x").is_err());
    assert_eq!(entries(&dir), ["out.json", "sub"]);
    assert_eq!(std::fs::read_to_string(sub.join("keep")).unwrap(), "k");

    // a directory that is not writable (meaningless when running as root)
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let ro = dir.join("ro");
        std::fs::create_dir(&ro).unwrap();
        let target = write(&ro, "model.json", "old model");
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o555)).unwrap();
        let can_write = std::fs::File::create(ro.join("probe")).is_ok();
        if !can_write {
            assert!(format::write_atomic(&target, b"new model").is_err());
            assert_eq!(std::fs::read_to_string(&target).unwrap(), "old model");
            assert_eq!(entries(&ro), ["model.json"]);
        }
        std::fs::set_permissions(&ro, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Deterministic test randomness (`rand`'s `StdRng`, seeded).
struct Rng(rand::rngs::StdRng);

impl Rng {
    fn new(seed: u64) -> Self {
        Rng(<rand::rngs::StdRng as rand::SeedableRng>::seed_from_u64(
            seed,
        ))
    }
    fn below(&mut self, n: u64) -> u64 {
        rand::Rng::random_range(&mut self.0, 0..n)
    }
    fn f64(&mut self) -> f64 {
        rand::Rng::random::<f64>(&mut self.0)
    }
    fn digits(&mut self, n: u64) -> String {
        (0..n)
            .map(|_| char::from(b'0' + self.below(10) as u8))
            .collect()
    }
}

/// A random decimal string: sign, integer and fraction digits of many lengths, sometimes an
/// exponent, sometimes something that is not a number.
fn random_decimal(rng: &mut Rng) -> String {
    let mut s = String::new();
    match rng.below(4) {
        0 => s.push('-'),
        1 if rng.below(4) == 0 => s.push('+'),
        _ => {}
    }
    let int_len = [0, 1, 1, 2, 3, 10, 16, 19, 20, 25][rng.below(10) as usize];
    s.push_str(&rng.digits(int_len));
    if rng.below(5) != 0 {
        s.push('.');
        let frac_len = [0, 1, 3, 6, 9, 9, 12, 15, 17, 22, 23, 30][rng.below(12) as usize];
        s.push_str(&rng.digits(frac_len));
    }
    if rng.below(6) == 0 {
        s.push(['e', 'E'][rng.below(2) as usize]);
        if rng.below(2) == 0 {
            s.push('-');
        }
        let e = rng.below(330);
        s.push_str(&e.to_string());
    }
    if rng.below(50) == 0 {
        s.insert(
            rng.below(s.len() as u64 + 1) as usize,
            ['x', '.', '-', 'e'][rng.below(4) as usize],
        );
    }
    s
}

#[test]
fn float_parsing_matches_std_exactly() {
    let mut rng = Rng::new(0x9e37_79b9_7f4a_7c15);
    let mut checked = 0;
    for _ in 0..20_000 {
        let s = random_decimal(&mut rng);
        let ours = format::parse_f64(s.as_bytes());
        let std = s.parse::<f64>().ok();
        assert_eq!(ours.map(f64::to_bits), std.map(f64::to_bits), "{s:?}");
        checked += usize::from(std.is_some());
    }
    assert!(checked > 15_000);
    for s in [
        "inf",
        "-inf",
        "+infinity",
        "NaN",
        "1e308",
        "1e309",
        "2.2250738585072014e-308",
        "9007199254740993",
        "9007199254740992.5",
        "0.1",
        "1700000000.008333",
        "4.9406564584124654e-324",
        "00000000000000000000001.5",
    ] {
        let (a, b) = (format::parse_f64(s.as_bytes()), s.parse::<f64>().ok());
        assert!(
            a.map(f64::to_bits) == b.map(f64::to_bits)
                || a.unwrap().is_nan() && b.unwrap().is_nan(),
            "{s}"
        );
    }

    // and through the reader, as TUM and CSV fields
    let mut tum = String::new();
    let mut csv = String::from("t,x,y,z,qx,qy,qz,qw\n");
    let mut expected = Vec::new();
    let mut i = 0;
    while expected.len() < 3000 {
        let f: Vec<String> = (0..3).map(|_| random_decimal(&mut rng)).collect();
        let v: Vec<f64> = f.iter().filter_map(|s| s.parse::<f64>().ok()).collect();
        if v.len() < 3 || v.iter().any(|x| !x.is_finite()) {
            continue;
        }
        i += 1;
        tum.push_str(&format!("{i} {} {} {} 0 0 0 1\n", f[0], f[1], f[2]));
        csv.push_str(&format!("{i}, {} ,{},{},0,0,0,1\n", f[0], f[1], f[2]));
        expected.push([v[0], v[1], v[2]]);
    }
    for (name, text) in [("f.tum", &tum), ("f.csv", &csv)] {
        let poses = read_str(name, text);
        assert_eq!(poses.len(), expected.len());
        for (p, e) in poses.iter().zip(&expected) {
            assert_eq!(xyz(p).map(f64::to_bits), e.map(f64::to_bits));
        }
    }
}

/// A line longer than the limit (1 MiB) is the same error however it is read: through the
/// 1 MiB read buffer (where it straddles two fills), memory-mapped (where it lies whole in a
/// 2 MiB window), from memory, and as a comment or as columns, TUM or CSV. Before, a long
/// line that lay whole in the buffer was read like any other (a pose with a 1.5 MB comment,
/// or "found 700001 columns" after many allocations), so the result depended on the buffer.
#[test]
fn an_over_long_line_is_an_error_however_it_is_read() {
    let lines = [
        format!("# c\n{LINE}\n1 0 0 0 0 0 0 1 # {}\n", "x".repeat(1_500_000)),
        format!("# c\n{LINE}\n1 {}\n", "0 ".repeat(700_000)),
        format!("{LINE}\n{}\n2 0 0 0 0 0 0 1\n", " ".repeat(1_048_577)),
    ];
    let csv = format!("t,x,y,z,qx,qy,qz,qw\n{}\n", ",".repeat(1_500_000));
    let cases = [
        ("l.tum", &lines[0], 3),
        ("l.tum", &lines[1], 3),
        ("l.tum", &lines[2], 2),
        ("l.csv", &csv, 2),
    ];
    for (name, text, line) in cases {
        let want = format!("line is longer than {} bytes", 1 << 20);
        let e = parse_error(name, text, line);
        assert!(e.ends_with(&format!(":{line}: {want}")), "{e}");
        let mapped = with_file(name, text, |p| {
            let r: Result<Vec<StampedPose>, Error> = format::open_mapped(p).unwrap().collect();
            r.unwrap_err().to_string()
        });
        assert!(mapped.ends_with(&format!(":{line}: {want}")), "{mapped}");
        let format = if name.ends_with(".csv") {
            Format::Csv
        } else {
            Format::Tum
        };
        for cap in [text.len(), 4096, 1] {
            let src = BufReader::with_capacity(cap, text.as_bytes());
            let r: Result<Vec<StampedPose>, Error> =
                PoseReader::new(src, "m".into(), format).collect();
            let e = r.unwrap_err().to_string();
            assert_eq!(e, format!("m:{line}: {want}"), "buffer of {cap} bytes");
        }
    }
}

/// An OptiTrack Motive export: `rows` data lines after the preamble, with `units` and
/// `bodies` (each a rigid body with one marker), the first body's columns first.
fn motive(units: &str, rotation: &str, bodies: &[&str], rows: &[&str]) -> String {
    let mut types = String::from(",Type");
    let mut names = String::from(",Name");
    let mut ids = String::from(",ID");
    let mut comps = String::from(",");
    let mut axes = String::from("Frame,Time (Seconds)");
    for (k, b) in bodies.iter().enumerate() {
        types += &",Rigid Body".repeat(8);
        types += &",Rigid Body Marker".repeat(3);
        names += &format!(",{b}").repeat(8);
        names += &format!(",{b}:Marker1").repeat(3);
        ids += &format!(",{k}").repeat(11);
        comps +=
            ",Rotation,Rotation,Rotation,Rotation,Position,Position,Position,Mean Marker Error";
        comps += ",Position,Position,Position";
        axes += ",X,Y,Z,W,X,Y,Z,,X,Y,Z";
    }
    format!(
        "Format Version,1.23,Take Name,Take 1,Take Notes,,Capture Frame Rate,120.000000,\
         Rotation Type,{rotation},Length Units,{units},Coordinate Space,Global\r\n\r\n\
         {types}\r\n{names}\r\n{ids}\r\n{comps}\r\n{axes}\r\n{}\r\n",
        rows.join("\r\n")
    )
}

/// Motive's CSV export: the rigid body's pose in the export's unit, in metres; frames where it
/// was unseen skipped; its markers and the mean marker error ignored; what cannot be read is
/// named.
#[test]
fn motive_exports() {
    let rows = [
        "0,0.000000,0,0,0,1,100.5,-20,300,0.0002,101,-20,300",
        "1,0.008333,,,,,,,,,,,",
        "2,0.016667,0.5,0.5,0.5,0.5,101.5,-21,301,0.0002,102,-21,301",
    ];
    for (units, k) in [
        ("Millimeters", 1e-3),
        ("Centimeters", 1e-2),
        ("Meters", 1.0),
    ] {
        let text = motive(units, "Quaternion", &["box"], &rows);
        let poses = read_str("take.csv", &text);
        assert_eq!(poses.len(), 2, "{units}");
        assert_eq!(poses[1].t, 0.016667);
        assert_eq!(xyz(&poses[0]), [100.5 * k, -20.0 * k, 300.0 * k]);
        assert_eq!(xyzw(&poses[1]), [0.5, 0.5, 0.5, 0.5]);
        let declared = with_file("take.csv", &text, format::declared_units);
        assert_eq!(declared.length.map(|u| u.metres()), Some(k));
    }
    // Without the .csv name, from its content.
    let poses = read_str(
        "take.txt",
        &motive("Millimeters", "Quaternion", &["box"], &rows),
    );
    assert_eq!(poses.len(), 2);
    let msg = |text: &str, line: usize| parse_error("take.csv", text, line);
    let e = msg(&motive("Millimeters", "XYZ", &["box"], &rows), 1);
    assert!(
        e.contains("Motive export: rotations are written as XYZ"),
        "{e}"
    );
    let e = msg(&motive("Inches", "Quaternion", &["box"], &rows), 1);
    assert!(e.contains("Length Units \"Inches\""), "{e}");
    let two = motive(
        "Millimeters",
        "Quaternion",
        &["box", "palm"],
        &["0,0,0,0,0,1,1,2,3,0,1,2,3,0,0,0,1,1,2,3,0,1,2,3"],
    );
    let e = msg(&two, 7);
    assert!(e.contains("2 rigid bodies (box, palm)"), "{e}");
    // A frame with part of the pose missing is no gap.
    let partial = ["0,0.0,0,0,0,1,100.5,-20,,0.0002,101,-20,300"];
    let e = msg(&motive("Millimeters", "Quaternion", &["box"], &partial), 8);
    assert!(e.contains("column 9 (tz) is empty"), "{e}");
}
