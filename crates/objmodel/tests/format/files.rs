//! Files: written and read back, streamed through small buffers, over-long lines however they
//! are read, palm files beside their object's, and atomic writes.

use super::*;
use std::io::BufReader;

#[test]
fn round_trip_write_read() {
    let mut rng = Rng::new(42);
    let poses: Vec<_> = (0..500)
        .map(|i| random_pose(&mut rng, 1.7e9 + i as f64 / 30.0))
        .collect();
    let dir = tmpdir("rt");
    let p = dir.path().join("traj.tum");
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

#[test]
fn palm_files() {
    let dir = tmpdir("palm");
    let obj = write(dir.path(), "push1.tum", LINE);
    assert_eq!(format::palm_path_for(&obj), None);
    let palm_csv = write(
        dir.path(),
        "push1.palm.csv",
        "t,x,y,z,qx,qy,qz,qw\n0.5,1,1,1,0,0,0,1\n",
    );
    assert_eq!(format::palm_path_for(&obj), Some(palm_csv.clone()));
    let palm = write(dir.path(), "push1.palm.tum", LINE);
    assert_eq!(format::palm_path_for(&obj), Some(palm.clone()));
    assert!(format::is_palm_file(&palm) && format::is_palm_file(Path::new("a/B.PALM.csv")));
    assert!(!format::is_palm_file(&obj) && !format::is_palm_file(Path::new("palm.tum")));
    assert_eq!(format::palm_path_for(&palm), None);
    let obj_csv = write(
        dir.path(),
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
    let lone = write(dir.path(), "lone.tum", LINE);
    assert!(format::read_demonstration(&lone, None)
        .unwrap()
        .palm
        .is_none());
    assert!(format::read_demonstration(&lone, Some(&dir.path().join("missing.tum"))).is_err());
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
    let p = write(dir.path(), "out.json", "old");
    format::write_atomic(&p, b"new").unwrap();
    assert_eq!(std::fs::read_to_string(&p).unwrap(), "new");
    assert_eq!(entries(dir.path()), ["out.json"]);

    // parent directory does not exist
    let missing = dir.path().join("no/such/dir/out.json");
    assert!(matches!(
        format::write_atomic(&missing, b"x"),
        Err(Error::Io { .. })
    ));
    assert_eq!(entries(dir.path()), ["out.json"]);

    // the target is a directory: rename fails, the temp file is removed
    let sub = dir.path().join("sub");
    std::fs::create_dir(&sub).unwrap();
    write(&sub, "keep", "k");
    assert!(format::write_atomic(&sub, b"x").is_err());
    assert_eq!(entries(dir.path()), ["out.json", "sub"]);
    assert_eq!(std::fs::read_to_string(sub.join("keep")).unwrap(), "k");

    // a directory that is not writable (meaningless when running as root)
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let ro = dir.path().join("ro");
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
}
