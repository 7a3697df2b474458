//! Property tests of reading whole files: lines as writers print them, now and then spoiled.
//! A good line reads as the values written; the first bad one gives its problem at its line;
//! and the vectorised, the scalar and the general TUM readers give the same poses (bit for
//! bit) and the same error.

use super::layout::{Format, COLUMNS};
use super::reader::PoseReader;
use crate::trajectory::StampedPose;
use proptest::prelude::*;
use std::io::BufReader;

/// How a writer prints a column: that many fraction digits, or (`None`) the shortest text
/// that reads back as the value.
type Digits = Option<usize>;

/// A writer: how it prints each column, and what separates the columns.
#[derive(Clone, Debug)]
struct Writer {
    digits: [Digits; 8],
    sep: &'static str,
}

/// What is done to a line.
#[derive(Clone, Debug)]
enum Spoil {
    None,
    /// Value `k` is `nan`, `inf` or `-inf`.
    NotFinite(usize, &'static str),
    /// The quaternion is multiplied by this (0, or far from 1).
    Norm(f64),
    /// The time repeats the previous one (`true`) or goes back.
    TimeBack(bool),
    /// A ninth value (`true`) or no `qw`.
    Columns(bool),
    /// Value `k` is no number.
    NotANumber(usize),
    /// Value `k` is written with an exponent, or (a translation) as an integer beyond 2^53:
    /// fine, but for the general path.
    Unusual(usize, bool),
    /// The line is a comment, or blank.
    Skipped(bool),
}

/// One line: the time step, the translation, a unit quaternion, and what is done to it.
#[derive(Clone, Debug)]
struct Line {
    dt: f64,
    xyz: [f64; 3],
    q: [f64; 4],
    spoil: Spoil,
}

fn writer() -> impl Strategy<Value = Writer> {
    let pos = prop_oneof![Just(None), (0..13usize).prop_map(Some)];
    let quat = prop_oneof![Just(None), (4..17usize).prop_map(Some)];
    (
        prop_oneof![Just(None), (6..10usize).prop_map(Some)],
        prop::array::uniform3(pos),
        prop::array::uniform4(quat),
        prop::sample::select(vec![" ", " ", "\t", "  ", " \t"]),
    )
        .prop_map(|(t, [x, y, z], [a, b, c, d], sep)| Writer {
            digits: [t, x, y, z, a, b, c, d],
            sep,
        })
}

fn spoil() -> impl Strategy<Value = Spoil> {
    prop_oneof![
        40 => Just(Spoil::None),
        1 => (0..8usize, prop::sample::select(vec!["nan", "inf", "-inf"]))
            .prop_map(|(k, s)| Spoil::NotFinite(k, s)),
        1 => prop::sample::select(vec![0.0, 0.5, 1.5]).prop_map(Spoil::Norm),
        1 => any::<bool>().prop_map(Spoil::TimeBack),
        1 => any::<bool>().prop_map(Spoil::Columns),
        1 => (0..8usize).prop_map(Spoil::NotANumber),
        2 => (0..8usize, any::<bool>()).prop_map(|(k, b)| Spoil::Unusual(k, b)),
        2 => any::<bool>().prop_map(Spoil::Skipped),
    ]
}

fn line(spoils: bool) -> impl Strategy<Value = Line> {
    let spoil = if spoils {
        spoil().boxed()
    } else {
        Just(Spoil::None).boxed()
    };
    (
        1e-3..10.0f64,
        prop::array::uniform3(-1e4..1e4f64),
        prop::array::uniform4(-1.0..1.0f64),
        spoil,
    )
        .prop_filter("a quaternion with a direction", |(_, _, q, _)| {
            q.iter().map(|a| a * a).sum::<f64>() > 1e-3
        })
        .prop_map(|(dt, xyz, q, spoil)| {
            let n = q.iter().map(|a| a * a).sum::<f64>().sqrt();
            Line {
                dt,
                xyz,
                q: q.map(|a| a / n),
                spoil,
            }
        })
}

/// `x` as `digits` says.
fn print(x: f64, digits: Digits) -> String {
    match digits {
        Some(d) => format!("{x:.d$}"),
        None => format!("{x}"),
    }
}

/// The text of `lines` as `w` writes them (CSV: comma separated after a header), each line's
/// fields, and the first error: its line and a part of its message.
fn text(
    w: &Writer,
    lines: &[Line],
    csv: bool,
) -> (String, Vec<Vec<String>>, Option<(usize, String)>) {
    let mut text = String::from(if csv {
        "t,x,y,z,qx,qy,qz,qw\n"
    } else {
        "# t x y z\n"
    });
    let (mut t, mut prev) = (1.7e9, None::<String>);
    let (mut rows, mut first) = (Vec::new(), None);
    for (i, l) in lines.iter().enumerate() {
        let number = i + 2;
        t += l.dt;
        let v = [
            t, l.xyz[0], l.xyz[1], l.xyz[2], l.q[0], l.q[1], l.q[2], l.q[3],
        ];
        let mut f: Vec<String> = (0..8).map(|k| print(v[k], w.digits[k])).collect();
        let mut problem = None;
        match &l.spoil {
            Spoil::None => {}
            Spoil::NotFinite(k, s) => {
                f[*k] = s.to_string();
                let what = if *s == "nan" { "NaN" } else { "infinite" };
                problem = Some(format!("{} is {what} (\"{s}\")", COLUMNS[*k]));
            }
            Spoil::Norm(m) => {
                for (k, x) in f.iter_mut().enumerate().skip(4) {
                    *x = print(v[k] * m, w.digits[k]);
                }
                let zero = f[4..].iter().all(|x| x.parse::<f64>() == Ok(0.0));
                problem = Some(if zero { "is zero" } else { "has norm" }.into());
            }
            Spoil::TimeBack(repeat) => {
                if let Some(p) = &prev {
                    f[0] = if *repeat {
                        p.clone()
                    } else {
                        "1600000000".into()
                    };
                    let how = if *repeat { "repeats" } else { "goes back from" };
                    problem = Some(format!("on line {number} {how} timestamp"));
                }
            }
            Spoil::Columns(more) => {
                if *more {
                    f.push("1".into());
                } else {
                    f.pop();
                }
                let found = if *more { 9 } else { 7 };
                problem = Some(if csv {
                    format!("expected 8 columns (as in the CSV header on line 1), found {found}")
                } else {
                    format!("expected 8 columns (timestamp tx ty tz qx qy qz qw), found {found}")
                });
            }
            Spoil::NotANumber(k) => {
                f[*k] = "x1".into();
                problem = Some(format!(
                    "column {} ({}): \"x1\" is not a number",
                    k + 1,
                    COLUMNS[*k]
                ));
            }
            Spoil::Unusual(k, exponent) => {
                f[*k] = if *exponent {
                    format!("{:e}", v[*k])
                } else if (1..4).contains(k) {
                    "9007199254740993".into()
                } else {
                    f[*k].clone()
                };
            }
            Spoil::Skipped(comment) => {
                f = if *comment {
                    vec!["# a comment".into()]
                } else {
                    vec![]
                };
            }
        }
        if let (None, Some(p)) = (&first, problem) {
            first = Some((number, p));
        }
        if f.len() == 8 {
            prev = Some(f[0].clone());
        }
        text += &f.join(if csv { "," } else { w.sep });
        text.push('\n');
        rows.push(f);
    }
    (text, rows, first)
}

/// Each item of a reader (the pose's bits and its line, or the error), and the lines read.
fn items(r: PoseReader<impl std::io::BufRead>) -> Vec<String> {
    let mut r = r;
    let mut items = Vec::new();
    while let Some(x) = r.next() {
        items.push(match x {
            Ok(p) => format!("{} {:x?}", r.line(), bits(&p)),
            Err(e) => e.to_string(),
        });
    }
    items.push(format!("{} lines", r.lines_read()));
    items
}

fn bits(p: &StampedPose) -> [u64; 8] {
    let (v, q) = (p.pose.translation.vector, p.pose.rotation.coords);
    [p.t, v.x, v.y, v.z, q.x, q.y, q.z, q.w].map(f64::to_bits)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(200))]

    /// Good lines read as the values written (the quaternion normalised), in TUM and CSV.
    #[test]
    fn good_lines_read_as_written(
        w in writer(),
        lines in prop::collection::vec(line(false), 1..60),
        csv in any::<bool>(),
    ) {
        let (text, rows, first) = text(&w, &lines, csv);
        prop_assert!(first.is_none());
        let format = if csv { Format::Csv } else { Format::Tum };
        let poses: Vec<StampedPose> = PoseReader::new(text.as_bytes(), "f".into(), format)
            .collect::<crate::Result<_>>()
            .unwrap();
        prop_assert_eq!(poses.len(), rows.len());
        for (p, f) in poses.iter().zip(&rows) {
            let v: Vec<f64> = f.iter().map(|s| s.parse().unwrap()).collect();
            let n = (v[4] * v[4] + v[5] * v[5] + v[6] * v[6] + v[7] * v[7]).sqrt();
            let want = [v[0], v[1], v[2], v[3], v[4] / n, v[5] / n, v[6] / n, v[7] / n];
            prop_assert_eq!(bits(p), want.map(f64::to_bits), "{:?}", f);
        }
    }

    /// The first bad line gives its problem, at its line, after the poses before it; the
    /// vectorised, scalar and general readers agree on every pose and on the error.
    #[test]
    fn readers_agree_and_name_the_first_problem(
        w in writer(),
        lines in prop::collection::vec(line(true), 1..300),
        csv in any::<bool>(),
    ) {
        let (text, _, first) = text(&w, &lines, csv);
        let bytes = text.as_bytes();
        let format = if csv { Format::Csv } else { Format::Tum };
        let fast = items(PoseReader::new(bytes, "f".into(), format));
        let scalar = items(PoseReader::new(bytes, "f".into(), format).scalar_only());
        let one_byte = BufReader::with_capacity(1, bytes);
        let general = items(PoseReader::new(one_byte, "f".into(), format));
        prop_assert_eq!(&fast, &scalar);
        prop_assert_eq!(&fast, &general);
        let last = fast.iter().rev().nth(1).map_or("", String::as_str);
        match first {
            Some((line, needle)) => {
                prop_assert!(last.starts_with(&format!("f:{line}: ")), "{} {}", last, needle);
                prop_assert!(last.contains(&needle), "{} {}", last, needle);
            }
            None => prop_assert!(!last.starts_with("f:"), "{}", last),
        }
    }
}
