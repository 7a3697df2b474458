//! Robustness: random and mutated input never panics, and whatever is accepted is sane.

use super::layout::Format;
use super::mapped::{MIN_MAPPED_BYTES, WINDOW};
use super::reader::PoseReader;
use std::io::BufReader;

use crate::testing::next;

#[test]
fn random_input_never_panics() {
    let alphabet: &[u8] = b"0123456789012345678901234567890123456789 . . - + e E \t , , # \n\n\n\r\"qxtimez\xff\xef\xbb";
    let valid = b"t,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\n2 0 0 0 0 0 0 1\n3,1,2,3,0.5,0.5,0.5,0.5\n";
    let mut s = crate::testing::rng(7);
    let pick = |s: &mut rand::rngs::StdRng| alphabet[(next(s) % alphabet.len() as u64) as usize];
    for round in 0..3000 {
        let mut bytes: Vec<u8> = if round % 2 == 0 {
            (0..next(&mut s) % 300).map(|_| pick(&mut s)).collect()
        } else {
            valid.to_vec()
        };
        for _ in 0..next(&mut s) % 6 {
            let i = (next(&mut s) % (bytes.len() as u64 + 1)) as usize;
            let b = pick(&mut s);
            if i < bytes.len() && next(&mut s) & 1 == 0 {
                bytes[i] = b;
            } else {
                bytes.insert(i, b);
            }
        }
        for format in [Some(Format::Tum), Some(Format::Csv), None] {
            let cap = 1 + (next(&mut s) % 64) as usize;
            let src = BufReader::with_capacity(cap, &bytes[..]);
            let r = match format {
                Some(f) => PoseReader::new(src, "r".into(), f),
                None => PoseReader::detecting(src, "r".into()),
            };
            let mut prev = f64::NEG_INFINITY;
            for p in r.take(1000).flatten() {
                assert!(p.t.is_finite() && p.t > prev);
                assert!((p.pose.rotation.norm() - 1.0).abs() < 1e-12);
                prev = p.t;
            }
        }
    }
}

/// The fast path for common TUM lines gives just what the general path gives: the same poses
/// (bit for bit), line numbers and errors. With a 1-byte buffer every line straddles buffer
/// fills and takes the general path; larger buffers take the fast one, except near their ends.
#[test]
fn fast_and_general_paths_agree() {
    let mut s = crate::testing::rng(11);
    let unit = |s: &mut rand::rngs::StdRng| {
        let q: Vec<f64> = (0..4)
            .map(|_| (next(s) % 2_000_001) as f64 / 1e6 - 1.0)
            .collect();
        let n = q.iter().map(|x| x * x).sum::<f64>().sqrt().max(1e-3);
        q.iter().map(|x| x / n).collect::<Vec<f64>>()
    };
    for round in 0..400 {
        let mut text = String::from("# timestamp tx ty tz qx qy qz qw\n");
        let mut t = 1.7e9;
        for _ in 0..next(&mut s) % 300 {
            t += 0.008333;
            let q = unit(&mut s);
            let x = (next(&mut s) % 2_000_000) as f64 / 1e6 - 1.0;
            let mut f: Vec<String> = vec![format!("{t:.6}")];
            f.extend([x, -x, x / 3.0].iter().map(|v| format!("{v:.9}")));
            f.extend(q.iter().map(|v| format!("{v:.9}")));
            let mut sep = " ";
            let mut end = "\n";
            match next(&mut s) % 200 {
                0 => f[7] = format!("{:.9}", q[3] * 1.5 + 0.1), // norm
                1 => f[0] = format!("{:.6}", t - 1.0),          // time goes back
                2 => {
                    f.pop(); // 7 columns
                }
                3 => f[2] = "nan".into(),
                4 => f[5] = "abc".into(),
                5 => f[3] = format!("{x:e}"),
                6..=9 => sep = "\t",
                10..=13 => sep = "  ",
                14..=17 => end = "\r\n",
                18..=20 => end = " # comment\n",
                21..=23 => text.push_str("\n# a comment\n"),
                _ => {}
            }
            text.push_str(&f.join(sep));
            text.push_str(end);
        }
        if next(&mut s) % 4 == 1 {
            text.pop(); // no `\n` at the end
        }
        let bytes = text.into_bytes();
        let show = |r: crate::Result<crate::trajectory::StampedPose>, line: usize| match r {
            Ok(p) => {
                let (v, q) = (p.pose.translation.vector, p.pose.rotation.coords);
                let bits: Vec<u64> = [p.t, v.x, v.y, v.z, q.x, q.y, q.z, q.w]
                    .iter()
                    .map(|x| x.to_bits())
                    .collect();
                format!("{line} {bits:x?}")
            }
            Err(e) => format!("{line} {e}"),
        };
        let read = |cap: usize| {
            let src = BufReader::with_capacity(cap, &bytes[..]);
            let mut r = PoseReader::new(src, "f.tum".into(), Format::Tum);
            let mut items = Vec::new();
            while let Some(x) = r.next() {
                items.push(show(x, r.line()));
            }
            items.push(format!("{} lines", r.lines_read()));
            items
        };
        let general = read(1);
        for cap in [7, 300, 4096, 1 << 20] {
            assert_eq!(read(cap), general, "round {round}, buffer {cap}");
        }
        // Also the bulk path behind `read_trajectory`.
        let mut poses = Vec::new();
        let r = PoseReader::new(&bytes[..], "f.tum".into(), Format::Tum).read_into(&mut poses);
        let mut bulk: Vec<String> = poses.into_iter().map(|p| show(Ok(p), 0)).collect();
        let mut iter: Vec<String> = general
            .iter()
            .filter(|s| s.contains('['))
            .cloned()
            .collect();
        for x in iter.iter_mut() {
            *x = format!("0 {}", x.split_once(' ').unwrap().1);
        }
        if let Err(e) = r {
            bulk.push(e.to_string());
            let last = general[general.len() - 2]
                .split_once(' ')
                .unwrap()
                .1
                .to_string();
            iter.push(last);
        }
        assert_eq!(bulk, iter, "round {round}, read_into");
    }
}

#[test]
fn read_chunk_gives_the_iterators_poses_and_error() {
    // 300 lines with an error (a repeated timestamp) at line 201 (after the comment line).
    let mut text = String::from("# t x y z qx qy qz qw\n");
    for k in 0..300 {
        let t = if k == 200 { 199.0 } else { k as f64 };
        text.push_str(&format!("{t} {k}.5 0 0 0 0 0 1\n"));
    }
    let want: Vec<_> = PoseReader::new(text.as_bytes(), "f".into(), Format::Tum).collect();
    assert_eq!(want.len(), 201, "200 poses, then the error");
    let want_err = want[200].as_ref().unwrap_err().to_string();
    assert!(want_err.contains("line 202"), "{want_err}");
    let mut s = crate::testing::rng(3);
    for _ in 0..50 {
        let cap = 1 + (next(&mut s) % 200) as usize;
        let mut r = PoseReader::new(
            BufReader::with_capacity(cap, text.as_bytes()),
            "f".into(),
            Format::Tum,
        );
        let mut got = Vec::new();
        let err = loop {
            let limit = 1 + (next(&mut s) % 40) as usize;
            let before = got.len();
            match r.read_chunk(&mut got, limit) {
                Ok(more) => {
                    // A full chunk while there may be more, at most `limit` at the end.
                    if more {
                        assert_eq!(got.len() - before, limit);
                    } else {
                        assert!(got.len() - before <= limit);
                        break None;
                    }
                }
                Err(e) => break Some(e.to_string()),
            }
        };
        assert_eq!(err.as_deref(), Some(want_err.as_str()));
        assert_eq!(got.len(), 200);
        for (g, w) in got.iter().zip(&want) {
            assert_eq!(g, w.as_ref().unwrap());
        }
        let mut rest = Vec::new();
        assert!(!r.read_chunk(&mut rest, 10).unwrap() && rest.is_empty());
    }
}

#[test]
fn open_maps_a_large_file_and_reads_every_pose() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path();
    let path = dir.join("big.tum");
    // Enough lines to pass MIN_MAPPED_BYTES, so lines straddle several window boundaries.
    let mut text = String::from("# t x y z qx qy qz qw\n");
    let mut k = 0u64;
    while (text.len() as u64) < MIN_MAPPED_BYTES + WINDOW as u64 / 2 {
        let t = k as f64 / 30.0;
        text.push_str(&format!(
            "{t:.6} {:.6} -0.25 1.5 0 0 0.6 0.8\n",
            k as f64 * 1e-6
        ));
        k += 1;
    }
    std::fs::write(&path, &text).unwrap();
    let poses: Vec<_> = super::files::open(&path)
        .unwrap()
        .collect::<crate::Result<_>>()
        .unwrap();
    assert_eq!(poses.len() as u64, k);
    for (i, p) in poses.iter().enumerate() {
        assert!(
            (p.pose.translation.vector.x - i as f64 * 1e-6).abs() < 1e-9,
            "pose {i}"
        );
    }
}

/// The files of the module import one way: no file imports from `mod.rs`, and the imports
/// among the others (`use super::...` outside their tests) form no cycle.
#[test]
fn imports_go_one_way() {
    let files: &[(&str, &str)] = &[
        ("check", include_str!("check.rs")),
        ("csv", include_str!("csv.rs")),
        ("date_time", include_str!("date_time.rs")),
        ("detect", include_str!("detect.rs")),
        ("fast_field", include_str!("fast_field.rs")),
        ("fast_line", include_str!("fast_line.rs")),
        ("fast_run", include_str!("fast_run.rs")),
        ("files", include_str!("files.rs")),
        ("layout", include_str!("layout.rs")),
        ("length_unit", include_str!("length_unit.rs")),
        ("line", include_str!("line.rs")),
        ("mapped", include_str!("mapped.rs")),
        ("motive", include_str!("motive.rs")),
        ("number", include_str!("number.rs")),
        ("problem", include_str!("problem.rs")),
        ("reader", include_str!("reader.rs")),
        ("simd", include_str!("simd.rs")),
        ("skipped", include_str!("skipped.rs")),
        ("stream", include_str!("stream.rs")),
        ("time_unit", include_str!("time_unit.rs")),
        ("tum", include_str!("tum.rs")),
        ("write", include_str!("write.rs")),
    ];
    let names: Vec<&str> = files.iter().map(|f| f.0).collect();
    // What each file names as `super::NAME` in its code (comments and tests left out).
    let uses: Vec<Vec<usize>> = files
        .iter()
        .map(|(name, text)| {
            let code = text.split("#[cfg(test)]\nmod tests").next().unwrap();
            let mut to = Vec::new();
            for line in code.lines().filter(|l| !l.trim_start().starts_with("//")) {
                for (i, _) in line.match_indices("super::") {
                    let rest = &line[i + "super::".len()..];
                    let first: String = rest
                        .chars()
                        .take_while(|c| c.is_alphanumeric() || *c == '_')
                        .collect();
                    let listed: Vec<String> = if first.is_empty() && rest.starts_with('{') {
                        rest[1..]
                            .split(',')
                            .map(|s| s.trim().split("::").next().unwrap().to_string())
                            .collect()
                    } else {
                        vec![first]
                    };
                    for n in listed
                        .iter()
                        .filter(|n| !n.is_empty() && n.as_str() != "super")
                    {
                        let k = names.iter().position(|m| m == n);
                        assert!(
                            k.is_some(),
                            "{name}.rs uses super::{n}, which is not a sibling file"
                        );
                        to.extend(k);
                    }
                }
            }
            to
        })
        .collect();
    // Depth-first search for a cycle.
    fn visit(
        k: usize,
        uses: &[Vec<usize>],
        state: &mut [u8],
        path: &mut Vec<usize>,
    ) -> Option<Vec<usize>> {
        if state[k] == 2 {
            return None;
        }
        path.push(k);
        if state[k] == 1 {
            return Some(path.clone());
        }
        state[k] = 1;
        for &j in &uses[k] {
            if let Some(c) = visit(j, uses, state, path) {
                return Some(c);
            }
        }
        state[k] = 2;
        path.pop();
        None
    }
    let mut state = vec![0u8; files.len()];
    for k in 0..files.len() {
        let cycle = visit(k, &uses, &mut state, &mut Vec::new());
        let named: Option<Vec<&str>> = cycle.map(|c| c.iter().map(|&i| names[i]).collect());
        assert_eq!(named, None, "an import cycle");
    }
    // Every file is reached from somewhere but the top ones.
    assert!(uses[names.iter().position(|n| *n == "layout").unwrap()].is_empty());
}
