//! Each figure from synthetic data: both files exist, the SVG holds the title and drawn lines,
//! the PNG decodes to the stated size with more than blank content.
//!
//! Set `OBJMODEL_PLOT_KEEP=DIR` to also keep the figures in DIR for viewing.

mod synthetic;

use std::path::{Path, PathBuf};

use objmodel_plot::{plot_angles, plot_side_view, plot_xy, Fig8, Outline, PlotError, SideView};

fn out_dir() -> (tempfile::TempDir, Option<PathBuf>) {
    let keep = std::env::var_os("OBJMODEL_PLOT_KEEP").map(PathBuf::from);
    (tempfile::tempdir().expect("temp dir"), keep)
}

/// Checks the pair of files and returns the PNG's (width, height).
fn check_pair(svg: &Path, png: &Path, title: &str, keep: &Option<PathBuf>) -> (u32, u32) {
    assert_eq!(svg.extension().unwrap(), "svg");
    assert_eq!(png.extension().unwrap(), "png");
    let text = std::fs::read_to_string(svg).expect("SVG readable");
    assert!(
        text.starts_with("<svg"),
        "not an SVG: {}",
        &text[..text.len().min(80)]
    );
    assert!(text.trim_end().ends_with("</svg>"));
    assert!(text.contains(title), "SVG lacks the title {title:?}");
    assert!(
        text.contains("<polyline") || text.contains("<path"),
        "SVG has no line"
    );

    let bytes = std::fs::read(png).expect("PNG readable");
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert!(
        bytes.len() > 10_000,
        "PNG suspiciously small: {} bytes",
        bytes.len()
    );
    let decoder = png::Decoder::new(std::io::Cursor::new(&bytes));
    let mut reader = decoder.read_info().expect("PNG header decodes");
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).expect("PNG data decodes");
    let pixels = &buf[..info.buffer_size()];
    let non_white = pixels
        .chunks(3)
        .filter(|p| p.iter().any(|&c| c < 200))
        .count();
    assert!(
        non_white > 5_000,
        "PNG nearly blank: {non_white} dark pixels"
    );
    // Red marks / coloured lines are present as colour, not only grey.
    let coloured = pixels
        .chunks(3)
        .filter(|p| p[0].abs_diff(p[2]) > 80)
        .count();
    assert!(coloured > 500, "PNG has almost no colour: {coloured}");

    // No temporary files are left behind.
    let dir = svg.parent().unwrap();
    let leftovers: Vec<_> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .filter(|e| e.file_name().to_string_lossy().ends_with(".tmp"))
        .collect();
    assert!(leftovers.is_empty(), "temporary files left: {leftovers:?}");

    if let Some(keep) = keep {
        std::fs::create_dir_all(keep).unwrap();
        for f in [svg, png] {
            std::fs::copy(f, keep.join(f.file_name().unwrap())).unwrap();
        }
    }
    (info.width, info.height)
}

#[test]
fn fig8_angles_svg_and_png() {
    let (dir, keep) = out_dir();
    let fig = synthetic::fig8();
    let (svg, png) = plot_angles(&fig, &dir.path().join("fig8")).unwrap();
    assert_eq!(svg, dir.path().join("fig8.svg"));
    assert_eq!(png, dir.path().join("fig8.png"));
    check_pair(&svg, &png, &fig.title, &keep);
    let text = std::fs::read_to_string(&svg).unwrap();
    for needle in [
        "time [s]",
        "angle [°]",
        "box angle relative to palm",
        "palm tilt",
        "onset",
        "φ = 20.00°",
        "ψe box",
    ] {
        assert!(text.contains(needle), "SVG lacks {needle:?}");
    }
    // Red marks.
    assert!(text.contains("#D62728"), "SVG lacks the red marks");
}

#[test]
fn fig8_rejects_mismatched_lengths_and_names_the_file() {
    let dir = tempfile::tempdir().unwrap();
    let mut fig = synthetic::fig8();
    fig.series[0].t.pop();
    let err = plot_angles(&fig, &dir.path().join("bad")).unwrap_err();
    assert!(matches!(err, PlotError::InvalidInput { .. }));
    let msg = err.to_string();
    assert!(
        msg.contains("bad") && msg.contains("box angle relative to palm"),
        "{msg}"
    );
    assert!(
        std::fs::read_dir(dir.path()).unwrap().next().is_none(),
        "nothing written"
    );
}

#[test]
fn fig8_without_data_still_draws() {
    let (dir, _) = out_dir();
    let fig = Fig8 {
        title: "empty".to_owned(),
        ..Fig8::default()
    };
    let (svg, png) = plot_angles(&fig, &dir.path().join("empty")).unwrap();
    assert!(svg.exists() && png.exists());
}

#[test]
fn side_view_has_equal_aspect_panels() {
    let (dir, keep) = out_dir();
    let v = synthetic::side_view();
    let (svg, png) = plot_side_view(&v, &dir.path().join("fig5")).unwrap();
    let (w, h) = check_pair(&svg, &png, &v.title, &keep);
    assert!(w > h, "four panels side by side: {w}x{h}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<polygon"), "filled outlines");
    for needle in [
        "t = 2.300 s",
        "box",
        "palm",
        "horizontal [m]",
        "vertical [m]",
    ] {
        assert!(text.contains(needle), "SVG lacks {needle:?}");
    }
}

/// A square drawn alone must come out square in pixels (equal aspect), whatever the frame
/// count and data extent.
#[test]
fn side_view_square_stays_square() {
    let (dir, keep) = out_dir();
    for (n, name) in [(1usize, "square1"), (6, "square6")] {
        let frames = (0..n)
            .map(|i| {
                let s = 0.1;
                let x = i as f64 * 0.3; // spread so the shared range is wide, not square
                (
                    i as f64,
                    vec![Outline {
                        label: "square".to_owned(),
                        points: vec![[x, 0.0], [x + s, 0.0], [x + s, s], [x, s]],
                    }],
                )
            })
            .collect();
        let v = SideView {
            title: format!("square x{n}"),
            frames,
        };
        let (svg, png) = plot_side_view(&v, &dir.path().join(name)).unwrap();
        check_pair(&svg, &png, &v.title, &keep);
        // The first stroked ring in the SVG is the first square: compare its pixel extents.
        let text = std::fs::read_to_string(&svg).unwrap();
        let poly = text
            .split("<polygon")
            .nth(1)
            .and_then(|s| s.split("points=\"").nth(1))
            .and_then(|s| s.split('"').next())
            .expect("a polygon with points");
        let pts: Vec<(f64, f64)> = poly
            .split_whitespace()
            .map(|p| {
                let (x, y) = p.split_once(',').unwrap();
                (x.parse().unwrap(), y.parse().unwrap())
            })
            .collect();
        let ext = |f: fn(&(f64, f64)) -> f64| {
            let v: Vec<f64> = pts.iter().map(f).collect();
            v.iter().cloned().fold(f64::MIN, f64::max) - v.iter().cloned().fold(f64::MAX, f64::min)
        };
        let (pw, ph) = (ext(|p| p.0), ext(|p| p.1));
        assert!(pw > 10.0, "square visible: {pw} px");
        assert!(
            (pw - ph).abs() <= 2.0,
            "{n} frames: square drawn {pw} x {ph} px"
        );
    }
}

#[test]
fn side_view_without_frames_says_so() {
    let (dir, _) = out_dir();
    let v = SideView {
        title: "nothing".to_owned(),
        frames: vec![],
    };
    let (svg, _) = plot_side_view(&v, &dir.path().join("none")).unwrap();
    assert!(std::fs::read_to_string(svg).unwrap().contains("no frames"));
}

#[test]
fn xy_plot_with_gaps_and_new_folder() {
    let (dir, keep) = out_dir();
    let base = dir.path().join("nested/deeper/xy.v1");
    let (svg, png) = plot_xy(
        "Generic x-y plot",
        "x [m]",
        "y [m]",
        &synthetic::xy_series(),
        &base,
    )
    .unwrap();
    assert_eq!(svg, dir.path().join("nested/deeper/xy.v1.svg"));
    check_pair(&svg, &png, "Generic x-y plot", &keep);
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("cosine with a gap") && text.contains("x [m]"));
}

#[test]
fn overwrites_existing_files() {
    let (dir, _) = out_dir();
    let base = dir.path().join("again");
    std::fs::write(dir.path().join("again.svg"), "old").unwrap();
    let (svg, _) = plot_xy("second", "x", "y", &synthetic::xy_series(), &base).unwrap();
    assert!(std::fs::read_to_string(svg).unwrap().contains("second"));
}

#[test]
fn io_error_names_the_path() {
    let dir = tempfile::tempdir().unwrap();
    // A file where the folder should be.
    std::fs::write(dir.path().join("blocker"), "x").unwrap();
    let err = plot_xy("t", "x", "y", &[], &dir.path().join("blocker/fig")).unwrap_err();
    assert!(matches!(err, PlotError::Io { .. }), "{err:?}");
    assert!(err.to_string().contains("blocker"), "{err}");
}
