//! Other tools' files: CSV headers of EuRoC, motion-capture and ROS exports, TUM headers, and
//! OptiTrack Motive's CSV export.

use super::*;

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
    // (Semicolons separate a spreadsheet's fields where commas are decimal points: read, see
    // `lines.rs`.)
    let err = parse_error("s.csv", "t|x|y|z|qx|qy|qz|qw\n1|1|2|3|0|0|0|1\n", 1);
    assert!(err.contains("separated by '|'"), "{err}");
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
    assert!(
        e.contains("2 rigid bodies (box, palm): name the object's (--object NAME"),
        "{e}"
    );
    // A frame with part of the pose missing is no gap.
    let partial = ["0,0.0,0,0,0,1,100.5,-20,,0.0002,101,-20,300"];
    let e = msg(&motive("Millimeters", "Quaternion", &["box"], &partial), 8);
    assert!(e.contains("column 9 (tz) is empty"), "{e}");
}
