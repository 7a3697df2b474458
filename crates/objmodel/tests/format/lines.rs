//! Lines: TUM and CSV syntax, headers, normalisation, and the errors that name file, line
//! and problem.

use super::*;

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
        ("demo.tum", format!("{h}2 1 0 0 0 0 0 0\n"), 4, vec!["is zero"]),
        ("demo.tum", format!("{h}2 0 0 0 0 0 0 1.02\n"), 4, vec!["norm 1.02", "tolerance 0.01"]),
        ("demo.tum", format!("{h}2 0 0 0 .5 .5 .5 .5\n3 0 0 0 0 0 0 .98\n"), 5, vec!["norm 0.98"]),
        ("demo.tum", format!("{h}1 0.1 0 0 0 0 0 1\n"), 4,
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
        ("e.csv", format!("{c}1,0,0,0.2,0,0,0,1,a\n"), 3, vec!["repeats timestamp 1 on line 2"]),
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

/// Frames where the tracker lost the object (every pose value NaN, empty or zero) are gaps:
/// skipped, counted with their lines, and they do not take part in the order of the times.
/// A line with only some values missing is still an error.
#[test]
fn lost_tracking_lines_are_gaps_and_counted() {
    let tum = "1 0.1 0.2 0.3 0 0 0 1\n2 nan nan nan nan nan nan nan\n\
               3 NaN NaN NaN NaN NaN NaN NaN\n# a comment between\n0.5 0 0 0 0 0 0 0\n\
               5 0.1 0.2 0.3 0 0 1 0\n6 nan nan nan nan nan nan nan\n\
               7 0.1 0.2 0.3 0 0 1 0\n";
    let csv = "t,x,y,z,qx,qy,qz,qw\n1,0.1,0.2,0.3,0,0,0,1\n2,,,,,,,\n3, , , , , , ,\n\
               0.5,nan,nan,nan,nan,nan,nan,nan\n5,0.1,0.2,0.3,0,0,1,0\n6,0,0,0,0,0,0,0\n\
               7,0.1,0.2,0.3,0,0,1,0\n";
    for (name, text, spans) in [
        ("lost.tum", tum, vec![(2, 3), (5, 5), (7, 7)]),
        ("lost.csv", csv, vec![(3, 5), (7, 7)]),
    ] {
        let format = if name.ends_with("csv") {
            Format::Csv
        } else {
            Format::Tum
        };
        let mut r = PoseReader::new(text.as_bytes(), name.into(), format);
        let poses: Vec<StampedPose> = r.by_ref().collect::<Result<_, _>>().unwrap();
        let times: Vec<f64> = poses.iter().map(|p| p.t).collect();
        assert_eq!(times, [1.0, 5.0, 7.0], "{name}");
        assert_eq!(xyz(&poses[1]), [0.1, 0.2, 0.3]);
        let lost = r.skipped_lines();
        assert_eq!(lost.spans, spans, "{name}");
        assert_eq!(lost.lines, 4, "{name}");
        let w = lost.warnings("object").remove(0);
        assert!(w.contains("lost it on 4 lines"), "{w}");
        // The whole-file reader skips them too.
        assert_eq!(read_str(name, text).len(), 3);
    }
    // Nothing lost: nothing counted.
    let mut r = PoseReader::new("1 0 0 0 0 0 0 1\n".as_bytes(), "ok.tum".into(), Format::Tum);
    assert!(r.next().unwrap().is_ok());
    assert_eq!(r.skipped_lines(), format::SkippedLines::default());
    // Some values missing or NaN, others not: errors, as before.
    let h = "t,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\n";
    let e = parse_error("p.csv", &format!("{h}2,0.1,,,,,,\n"), 3);
    assert!(e.contains("column 3 (ty) is empty"), "{e}");
    let e = parse_error("p.tum", "1 0 0 0 0 0 0 1\n2 nan nan nan 0 0 0 1\n", 2);
    assert!(e.contains("tx is NaN"), "{e}");
    // A lost line's time is not a pose's: the next pose may share it.
    let text = "1 0 0 0 0 0 0 1\n2 nan nan nan nan nan nan nan\n2 0 0 0 0 0 0 1\n";
    assert_eq!(read_str("p.tum", text).len(), 2);
}

/// A line written twice (the same time and pose: a logger that flushed a buffer twice) is no
/// second frame: left out and counted, wherever it falls (on the fast path's lines, after the
/// first line, after a lost line, at a buffer's edge), and the poses are those of the file
/// without the copies, bit for bit. The same time with another pose is still an error.
#[test]
fn a_line_written_twice_is_left_out_and_counted() {
    let mut rng = Rng::new(67);
    let lines: Vec<String> = (0..600)
        .map(|i| {
            let p = random_pose(&mut rng, 1_700_000_000.0 + i as f64 / 120.0);
            let (t, q) = (xyz(&p), xyzw(&p));
            format!(
                "{:.6} {:.9} {:.9} {:.9} {:.9} {:.9} {:.9} {:.9}",
                p.t, t[0], t[1], t[2], q[0], q[1], q[2], q[3]
            )
        })
        .collect();
    let clean = format!("# t x y z qx qy qz qw\n{}\n", lines.join("\n"));
    let want = read_str("clean.tum", &clean);
    for trial in 0..20 {
        // Copies of randomly chosen lines (some twice over), the first line's among them.
        let mut copied: Vec<usize> = (0..8).map(|_| rng.below(600) as usize).collect();
        copied.push(0);
        copied.sort();
        let mut text = String::from("# t x y z qx qy qz qw\n");
        let (mut first, mut n) = (None, 0);
        let mut line = 1;
        for (i, l) in lines.iter().enumerate() {
            text += l;
            text.push('\n');
            line += 1;
            let of = line;
            for _ in copied.iter().filter(|&&c| c == i) {
                text += l;
                text.push('\n');
                line += 1;
                first.get_or_insert((line, of));
                n += 1;
            }
        }
        assert_eq!(read_str("copies.tum", &text), want, "trial {trial}");
        let cap = [64, 200, 4096, 1 << 16][trial % 4];
        let src = std::io::BufReader::with_capacity(cap, text.as_bytes());
        let mut r = PoseReader::new(src, "copies.tum".into(), Format::Tum);
        let read: Vec<StampedPose> = r.by_ref().collect::<Result<_, _>>().unwrap();
        assert_eq!(read, want, "trial {trial}");
        let skipped = r.skipped_lines();
        assert_eq!((skipped.duplicates, skipped.first_duplicate), (n, first));
        assert_eq!(skipped.lines, 0);
    }
    // CSV, and a copy after a lost line between the two.
    let csv = "t,x,y,z,qx,qy,qz,qw\n1,0.1,0.2,0.3,0,0,0,1\n1,0.1,0.2,0.3,0,0,0,1\n\
               2,0.1,0.2,0.3,0,0,1,0\n3,,,,,,,\n2,0.1,0.2,0.3,0,0,1,0\n";
    let mut r = PoseReader::new(csv.as_bytes(), "c.csv".into(), Format::Csv);
    let read: Vec<StampedPose> = r.by_ref().collect::<Result<_, _>>().unwrap();
    assert_eq!(read.iter().map(|p| p.t).collect::<Vec<_>>(), [1.0, 2.0]);
    let skipped = r.skipped_lines();
    assert_eq!(
        (skipped.duplicates, skipped.first_duplicate),
        (2, Some((3, 2)))
    );
    assert_eq!(skipped.lines, 1);
    // A column the reader ignores (a frame number, a note) may differ: the pose is the same.
    let csv = "t,x,y,z,qx,qy,qz,qw,frame\n1,0,0,0,0,0,0,1,7\n1,0,0,0,0,0,0,1,8\n";
    let mut r = PoseReader::new(csv.as_bytes(), "c.csv".into(), Format::Csv);
    assert_eq!(r.by_ref().count(), 1);
    assert_eq!(r.skipped_lines().duplicates, 1);
    // The same time, another pose (even one that differs in the last digit, or only in the
    // quaternion's sign): an error, as before.
    let others = [
        "1.0 1 2 3 0 0 0.001 1",
        "1.0 1 2 3.000000001 0 0 0 1",
        "1 1 2 3 0 0 0 -1",
    ];
    for other in others {
        let e = parse_error("t.tum", &format!("1.0 1 2 3 0 0 0 1\n{other}\n"), 2);
        assert!(e.contains("repeats timestamp 1 on line 1"), "{e}");
    }
    // A copy of a line further back is no copy of the pose before: the time goes back.
    let text = "1 1 2 3 0 0 0 1\n2 1 2 3 0 0 0 1\n1 1 2 3 0 0 0 1\n";
    let e = parse_error("t.tum", text, 3);
    assert!(e.contains("goes back from"), "{e}");
}

/// A CSV time column written as date-times (pandas' `to_csv` of a `DatetimeIndex`, RFC 3339
/// with `Z` or an offset) reads as seconds since the Unix epoch: the same poses as the file
/// written in seconds, to the `f64`'s resolution at today's dates. A date-time that does not
/// read says why; a TUM file's times stay seconds.
#[test]
fn a_csv_time_column_of_date_times_reads_as_seconds() {
    let t0 = 1_796_637_600.0; // 2026-12-07T10:00:00Z
    let rows = [
        (0.0, "0.1,0.2,0.3,0,0,0,1"),
        (0.033333, "0.1,0.2,0.4,0,0,1,0"),
        (1.5, "0.2,0.2,0.4,0,0,0,1"),
    ];
    let seconds: String = rows
        .iter()
        .map(|(t, p)| format!("{},{p}\n", t0 + t))
        .collect();
    let want = read_str("s.csv", &format!("t,x,y,z,qx,qy,qz,qw\n{seconds}"));
    let forms: [fn(f64) -> String; 4] = [
        |t| format!("2026-12-07 10:00:{t:09.6}"),
        |t| format!("2026-12-07T10:00:{t:09.6}Z"),
        |t| format!("2026-12-07T11:00:{t:09.6}+01:00"),
        |t| format!("\"2026-12-07T10:00:{t:012.9}z\""),
    ];
    for (k, form) in forms.iter().enumerate() {
        let body: String = rows
            .iter()
            .map(|(t, p)| format!("{},{p}\n", form(*t)))
            .collect();
        // A header, a header in a comment (the first data line must not pass for one), and
        // a declared time unit, which a date-time does not take.
        for head in [
            "time,x,y,z,qx,qy,qz,qw\n",
            "#time,x,y,z,qx,qy,qz,qw\n",
            "time [ns],x,y,z,qx,qy,qz,qw\n",
        ] {
            let got = read_str("d.csv", &format!("{head}{body}"));
            assert_eq!(got.len(), want.len(), "{k} {head}");
            for (g, w) in got.iter().zip(&want) {
                assert!(
                    (g.t - w.t).abs() < 1e-6,
                    "{k} {head}: {} against {}",
                    g.t,
                    w.t
                );
                assert_eq!(
                    (g.pose.translation, g.pose.rotation.coords),
                    (w.pose.translation, w.pose.rotation.coords)
                );
            }
        }
    }
    // A lost frame's time may be a date-time too.
    let text =
        "time,x,y,z,qx,qy,qz,qw\n2026-12-07T10:00:00Z,0,0,0,0,0,0,1\n2026-12-07T10:00:01Z,,,,,,,\n";
    assert_eq!(read_str("l.csv", text).len(), 1);
    let h = "time,x,y,z,qx,qy,qz,qw\n";
    let e = parse_error(
        "m.csv",
        &format!("{h}2026-13-07T10:00:00Z,0,0,0,0,0,0,1\n"),
        2,
    );
    assert!(
        e.contains("is neither a number of seconds nor a date-time that reads"),
        "{e}"
    );
    assert!(e.contains("month"), "{e}");
    let e = parse_error("m.csv", &format!("{h}2026-12-07,0,0,0,0,0,0,1\n"), 2);
    assert!(e.contains("a date without a time of day"), "{e}");
    let e = parse_error("m.tum", "2026-12-07T10:00:00Z 0 0 0 0 0 0 1\n", 1);
    assert!(e.contains("a TUM file's timestamps are seconds"), "{e}");
    // Times still increase: a date-time before the one above it is out of order.
    let text =
        format!("{h}2026-12-07T10:00:01Z,0,0,0,0,0,0,1\n2026-12-07T10:00:00Z,0,0,0,0,0,0,1\n");
    let e = parse_error("o.csv", &text, 3);
    assert!(e.contains("goes back from"), "{e}");
}

/// What some exports and loggers add to a CSV file: a units row right after the header (its
/// units declared as a name's `x [mm]` declares them), and a comma that ends every line, or
/// only the header.
#[test]
fn a_units_row_and_trailing_commas() {
    let rows = "1,100,200,300,0,0,0,1\n2,100,200,400,0,0,1,0\n";
    let mm = read_str(
        "mm.csv",
        &format!("t [s],x [mm],y [mm],z [mm],qx,qy,qz,qw\n{rows}"),
    );
    for (head, units) in [
        ("t,x,y,z,qx,qy,qz,qw", "s,mm,mm,mm,,,,"),
        ("t,x,y,z,qx,qy,qz,qw", " [s] , [mm] ,(mm),\"mm\",-,-,-,-"),
        (
            "t,x,y,z,qx,qy,qz,qw,note",
            "seconds,millimetres,mm,mm,,,,,text",
        ),
        // The name's own unit stays; the row's fills in the others.
        ("t,x [mm],y,z,qx,qy,qz,qw", ",m,mm,mm,,,,"),
    ] {
        let rows = if head.ends_with("note") {
            rows.replace('\n', ",a\n")
        } else {
            rows.to_string()
        };
        let text = format!("{head}\n{units}\n{rows}");
        assert_eq!(read_str("u.csv", &text), mm, "{units}");
        let mut r = PoseReader::new(text.as_bytes(), "u.csv".into(), Format::Csv);
        assert_eq!(r.by_ref().count(), 2);
        assert_eq!(
            r.declared_units().length,
            Some(format::LengthUnit::Millimetres)
        );
    }
    // The units row after blank and comment lines; under a commented header; a commented
    // header followed by the header itself (names that are not units).
    for text in [
        format!("t,x,y,z,qx,qy,qz,qw\n\n# units:\ns,mm,mm,mm,,,,\n{rows}"),
        format!("#t,x,y,z,qx,qy,qz,qw\ns,mm,mm,mm,,,,\n{rows}"),
        format!("# t,x,y,z,qx,qy,qz,qw\n\n# units\ns,mm,mm,mm,,,,\n{rows}"),
    ] {
        assert_eq!(read_str("u.csv", &text), mm, "{text}");
    }
    let text = format!("#t,x,y,z,qx,qy,qz,qw\nt,x [mm],y [mm],z [mm],qx,qy,qz,qw\n{rows}");
    assert_eq!(read_str("u.csv", &text), mm);
    // A unit that is not its column's, and a units row that is data gone wrong.
    let e = parse_error(
        "u.csv",
        &format!("t,x,y,z,qx,qy,qz,qw\nframes,mm,mm,mm,,,,\n{rows}"),
        2,
    );
    assert!(
        e.contains("\"t [frames]\", timestamp) declares a unit that is not a time"),
        "{e}"
    );
    let e = parse_error(
        "u.csv",
        "t,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\ns,mm,mm,mm,,,,\n",
        3,
    );
    assert!(e.contains("\"s\" is not a number"), "{e}");
    // Trailing commas: on every line, on the data lines only, on the header only.
    let want = read_str(
        "c.csv",
        "t,x,y,z,qx,qy,qz,qw\n1,0.1,0.2,0.3,0,0,0,1\n2,0.1,0.2,0.4,0,0,0,1\n",
    );
    let data = ["1,0.1,0.2,0.3,0,0,0,1", "2,0.1,0.2,0.4,0,0,0,1"];
    for (head, end) in [(",", ","), ("", ","), (",", ""), ("", ", ")] {
        let text = format!(
            "t,x,y,z,qx,qy,qz,qw{head}\n{}{end}\n{}{end}\n",
            data[0], data[1]
        );
        assert_eq!(read_str("c.csv", &text), want, "{text:?}");
    }
    // One field too many that is not empty, or two empty ones: still an error.
    for extra in [",5", ",,"] {
        let text = format!("t,x,y,z,qx,qy,qz,qw\n{}{extra}\n", data[0]);
        let e = parse_error("c.csv", &text, 2);
        assert!(e.contains("expected 8 columns"), "{e}");
    }
}

/// A spreadsheet saved in a locale that writes decimal commas separates its fields by
/// semicolons: such a file (a header without commas) reads as its comma-separated twin, bit
/// for bit, with a units row, a commented header, date-times and a name without `.csv`; a field
/// with two commas, or a comma-separated file's decimal comma, is an error that names it.
#[test]
fn semicolons_and_decimal_commas() {
    let mut rng = Rng::new(68);
    let rows: Vec<[String; 8]> = (0..300)
        .map(|i| {
            let p = random_pose(&mut rng, 1_700_000_000.0 + i as f64 / 240.0);
            let (t, q) = (xyz(&p), xyzw(&p));
            let mut r = [p.t, t[0], t[1], t[2], q[0], q[1], q[2], q[3]].map(|v| format!("{v:.9}"));
            // Some values as integers, some in exponent notation.
            match i % 7 {
                0 => r[2] = format!("{}", t[1].round() as i64),
                1 => r[1] = format!("{:e}", t[0]),
                _ => {}
            }
            r
        })
        .collect();
    let lines = |sep: &str, comma: bool| -> String {
        rows.iter()
            .map(|r| {
                let r: Vec<String> = r
                    .iter()
                    .map(|v| {
                        if comma {
                            v.replace('.', ",")
                        } else {
                            v.clone()
                        }
                    })
                    .collect();
                r.join(sep) + "\n"
            })
            .collect()
    };
    let want = read_str(
        "w.csv",
        &format!("t,x,y,z,qx,qy,qz,qw\n{}", lines(",", false)),
    );
    assert_eq!(want.len(), rows.len());
    for (name, text) in [
        (
            "s.csv",
            format!("t;x;y;z;qx;qy;qz;qw\n{}", lines(";", true)),
        ),
        (
            "s.csv",
            format!("t;x;y;z;qx;qy;qz;qw\n{}", lines(";", false)),
        ),
        (
            "s.csv",
            format!(
                "t ; x ; y ; z ; qx ; qy ; qz ; qw ;\n{}",
                lines(" ; ", true)
            ),
        ),
        (
            "s.csv",
            format!("t;x;y;z;qx;qy;qz;qw\ns;m;m;m;;;;\n{}", lines(";", true)),
        ),
        (
            "s.txt",
            format!("t;x;y;z;qx;qy;qz;qw\n{}", lines(";", true)),
        ),
        (
            "s.txt",
            format!("#t;x;y;z;qx;qy;qz;qw\n{}", lines(";", true)),
        ),
    ] {
        let got = read_str(name, &text);
        assert_eq!(got, want, "{}", &text[..60]);
    }
    // Millimetres by a units row; a date-time with a decimal comma.
    let text = "t;x;y;z;qx;qy;qz;qw\ns;mm;mm;mm;;;;\n1,5;100;200,5;-300;0;0;0;1\n";
    let got = read_str("mm.csv", text);
    assert_eq!(xyz(&got[0]), [0.1, 0.2005, -0.3]);
    assert_eq!(got[0].t, 1.5);
    let text = "time;x;y;z;qx;qy;qz;qw\n2026-12-07 10:00:00,25;0;0;0;0;0;0;1\n";
    let got = read_str("d.csv", text);
    assert_eq!(got[0].t, 1_796_637_600.25);
    // Two commas in a field; a decimal comma where commas separate the fields.
    let e = parse_error("e.csv", "t;x;y;z;qx;qy;qz;qw\n1;0,1,5;0;0;0;0;0;1\n", 2);
    assert!(
        e.contains("column 2 (tx): \"0,1,5\" is not a number"),
        "{e}"
    );
    let e = parse_error("e.csv", "t,x,y,z,qx,qy,qz,qw\n1,0,5,0,0,0,0,0,1\n", 2);
    assert!(e.contains("expected 8 columns"), "{e}");
}

/// Headers that Python scripts and PlotJuggler write: a unit after an `_` (`time_s`, `x_mm`),
/// and PlotJuggler's `__time` with a topic's fields as paths (`/tag/pose/position/x`), timed
/// by the message's `header/stamp` where the file has one.
#[test]
fn unit_suffixes_and_plotjuggler_paths_name_columns() {
    let rows = [(1.0, [0.1, 0.2, 0.3]), (2.0, [0.1, 0.2, 0.4])];
    let want = read_str(
        "w.csv",
        &format!(
            "t,x,y,z,qx,qy,qz,qw\n{}",
            rows.iter()
                .map(|(t, p)| format!("{t},{},{},{},0,0,0,1\n", p[0], p[1], p[2]))
                .collect::<String>()
        ),
    );
    let pj = [
        "/tag/pose/position/x",
        "/tag/pose/position/y",
        "/tag/pose/position/z",
    ];
    let pq = [
        "/tag/pose/orientation/x",
        "/tag/pose/orientation/y",
        "/tag/pose/orientation/z",
    ];
    let pj = format!(
        "{},{},{}",
        pj.join(","),
        pq.join(","),
        "/tag/pose/orientation/w"
    );
    for (head, scale_t, scale_p, stamp) in [
        (
            "time_s,x_m,y_m,z_m,qx,qy,qz,qw".to_string(),
            1.0,
            1.0,
            false,
        ),
        (
            "t_ms,x_mm,y_mm,z_mm,qx,qy,qz,qw".to_string(),
            1e3,
            1e3,
            false,
        ),
        (
            "timestamp_ns,pos_x_mm,pos_y_mm,pos_z_mm,quat_x,quat_y,quat_z,quat_w".to_string(),
            1e9,
            1e3,
            false,
        ),
        (format!("__time,{pj}"), 1.0, 1.0, false),
        (format!("__time,/tag/header/stamp,{pj}"), 1.0, 1.0, true),
    ] {
        let body: String = rows
            .iter()
            .map(|(t, p)| {
                // The log time 0.05 s after the stamp: the stamp is the time, where there is one.
                let times = if stamp {
                    format!("{},{t}", t + 0.05)
                } else {
                    format!("{}", t * scale_t)
                };
                let [x, y, z] = p.map(|v| v * scale_p);
                format!("{times},{x},{y},{z},0,0,0,1\n")
            })
            .collect();
        let got = read_str("h.csv", &format!("{head}\n{body}"));
        assert_eq!(got.len(), 2, "{head}");
        for (g, w) in got.iter().zip(&want) {
            assert!((g.t - w.t).abs() < 1e-9, "{head}: {} {}", g.t, w.t);
            assert!(
                (g.pose.translation.vector - w.pose.translation.vector).norm() < 1e-12,
                "{head}"
            );
        }
    }
    // A name that is a known one whole is not split (`pos_x` is no `pos` in unit `x`), and a
    // unit after an `_` that is not the column's is the header's error.
    let e = parse_error("h.csv", "t,x_s,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\n", 1);
    assert!(
        e.contains("\"x_s\", tx) declares a unit that is not a length"),
        "{e}"
    );
}

/// A logger stopped in the middle of the last line: that line, without its `\n`, does not read
/// as a pose, and after poses it is left out and said, however the reader's buffer cuts the
/// file. Ended by a `\n`, or with no pose before it, it is an error as always.
#[test]
fn a_last_line_cut_short_is_left_out() {
    let poses = "1 0 0 0 0 0 0 1\n2 0.1 0 0 0 0 0 1\n";
    #[rustfmt::skip]
    let cases = [
        ("cut.tum", format!("{poses}3 0.1 0.2"), 2, 3, "found 3"),
        ("cut.tum", format!("# c\n{poses}3 0.1 0.2 0.3 0 0 0 0.7"), 2, 4, "norm 0.7"),
        ("cut.csv", "t,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\n2,0".into(), 1, 3, "found 2"),
    ];
    for (name, text, n, line, problem) in cases {
        let format = if name.ends_with("csv") {
            Format::Csv
        } else {
            Format::Tum
        };
        for cap in [1, 2, 7, 16, 64, 4096] {
            let src = std::io::BufReader::with_capacity(cap, text.as_bytes());
            let mut r = PoseReader::new(src, name.into(), format);
            let read: Vec<StampedPose> = r.by_ref().collect::<Result<_, _>>().unwrap();
            assert_eq!(read.len(), n, "{name} {cap}");
            let (at, why) = r.skipped_lines().cut_short.expect("said");
            assert_eq!(at, line, "{name} {cap}");
            assert!(why.contains(problem), "{why}");
        }
        let w = with_file(name, &text, |p| {
            let mut r = format::open(p).unwrap();
            r.by_ref().for_each(|p| assert!(p.is_ok()));
            r.skipped_lines().warnings("object")
        });
        assert_eq!(w.len(), 1);
        assert!(
            w[0].contains(&format!("line cut short (line {line}")),
            "{w:?}"
        );
        // With its end of line it is an error.
        parse_error(name, &format!("{text}\n"), line);
    }
    // No pose before it: an error.
    parse_error("one.tum", "1 0.1 0.2", 1);
    // A last line without its end of line that reads is a pose.
    assert_eq!(
        read_str("ok.tum", "1 0 0 0 0 0 0 1\n2 0 0 0 0 0 0 1").len(),
        2
    );
}

#[test]
fn files_without_poses() {
    assert!(file_error("e.tum", "").contains("empty"));
    assert!(file_error("e.tum", "# only\n\n  \n# comments\n").contains("no poses"));
    assert!(file_error("e.csv", "t,x,y,z,qx,qy,qz,qw\n").contains("header"));
    let lost = "1 nan nan nan nan nan nan nan\n2 0 0 0 0 0 0 0\n";
    let e = file_error("l.tum", lost);
    assert!(
        e.contains("every pose line is a frame where the tracker lost the object (2 lines"),
        "{e}"
    );
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
