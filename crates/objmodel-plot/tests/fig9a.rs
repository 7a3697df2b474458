//! The paper's Fig. 9a against the model it draws: the SVG's vertices are an orthographic,
//! equal-aspect, z-up projection of the shape's vertices, and the same projection puts the
//! centre of mass and every learnt edge where the tree has them; each part is coloured by how it
//! is known; the PNG shows the same picture.

mod model;

use model::{analytic_box, learnt_box, COM};
use nalgebra::{DMatrix, DVector, Vector3};
use objmodel::synth::SynthNoise;
use objmodel_plot::plot_model;
use std::collections::HashMap;

/// One SVG element: its name and attributes.
struct El {
    name: String,
    attrs: HashMap<String, String>,
}

impl El {
    fn f(&self, k: &str) -> f64 {
        self.attrs[k].parse().unwrap()
    }
    fn get(&self, k: &str) -> &str {
        self.attrs.get(k).map_or("", String::as_str)
    }
}

/// The elements of an SVG written as this crate writes it (double-quoted attributes).
fn elements(svg: &str) -> Vec<El> {
    let mut out = Vec::new();
    for chunk in svg.split('<').skip(1) {
        let tag = &chunk[..chunk.find('>').unwrap()];
        if tag.starts_with('/') {
            continue;
        }
        let name = tag.split_whitespace().next().unwrap().to_string();
        let mut attrs = HashMap::new();
        let mut rest = &tag[name.len()..];
        while let Some(eq) = rest.find("=\"") {
            let key = rest[..eq].trim().to_string();
            let after = &rest[eq + 2..];
            let end = after.find('"').unwrap();
            attrs.insert(key, after[..end].to_string());
            rest = &after[end + 1..];
        }
        out.push(El { name, attrs });
    }
    out
}

/// The affine map from object-frame points to pixels that fits `pairs` best (least squares),
/// as a 2x4 matrix, and its largest residual [px].
fn fit(pairs: &[(Vector3<f64>, (f64, f64))]) -> (DMatrix<f64>, f64) {
    let a = DMatrix::from_fn(
        pairs.len(),
        4,
        |i, j| if j < 3 { pairs[i].0[j] } else { 1.0 },
    );
    let mut m = DMatrix::zeros(2, 4);
    for k in 0..2 {
        let b = DVector::from_fn(pairs.len(), |i, _| {
            if k == 0 {
                pairs[i].1 .0
            } else {
                pairs[i].1 .1
            }
        });
        let x = a.clone().svd(true, true).solve(&b, 1e-12).unwrap();
        m.row_mut(k).copy_from(&x.transpose());
    }
    let worst = pairs
        .iter()
        .map(|(p, q)| {
            let r = project(&m, p);
            (r.0 - q.0).hypot(r.1 - q.1)
        })
        .fold(0.0, f64::max);
    (m, worst)
}

fn project(m: &DMatrix<f64>, p: &Vector3<f64>) -> (f64, f64) {
    let h = [p.x, p.y, p.z, 1.0];
    let r = |k: usize| (0..4).map(|j| m[(k, j)] * h[j]).sum::<f64>();
    (r(0), r(1))
}

fn draw(
    tree: &objmodel::tree::Tree,
    name: &str,
) -> (String, std::path::PathBuf, tempfile::TempDir) {
    let dir = tempfile::tempdir().unwrap();
    let (svg, png) = plot_model(tree, "learnt object", &dir.path().join(name)).unwrap();
    if let Some(keep) = std::env::var_os("OBJMODEL_PLOT_KEEP") {
        let keep = std::path::PathBuf::from(keep);
        std::fs::create_dir_all(&keep).unwrap();
        std::fs::copy(&svg, keep.join(format!("{name}.svg"))).unwrap();
        std::fs::copy(&png, keep.join(format!("{name}.png"))).unwrap();
    }
    (std::fs::read_to_string(&svg).unwrap(), png, dir)
}

#[test]
fn the_drawing_is_a_projection_of_the_model() {
    let tree = analytic_box(true);
    let shape = tree.shape.as_ref().expect("the analytic box closes");
    let (svg, png, _dir) = draw(&tree, "analytic_box");
    let els = elements(&svg);
    let of = |kind: &'static str| els.iter().filter(move |e| e.get("data-kind") == kind);

    // Vertices: all eight, inferred, on one orthographic projection of the shape's corners.
    let pairs: Vec<(Vector3<f64>, (f64, f64))> = of("vertex")
        .map(|e| {
            let i: usize = e.get("data-id")[1..].parse().unwrap();
            assert_eq!(e.get("data-known"), "inferred");
            (shape.vertices[i], (e.f("cx"), e.f("cy")))
        })
        .collect();
    assert_eq!(pairs.len(), 8);
    let (m, worst) = fit(&pairs);
    assert!(
        worst < 0.02,
        "vertices are not an affine projection: {worst} px off"
    );
    let (r, u) = (
        m.fixed_view::<1, 3>(0, 0).transpose(),
        m.fixed_view::<1, 3>(1, 0).transpose(),
    );
    assert!(
        r.dot(&u).abs() < 1e-3 * r.norm_squared(),
        "not orthographic"
    );
    assert!(
        (r.norm() - u.norm()).abs() < 1e-3 * r.norm(),
        "unequal aspect"
    );
    let z = project(&m, &Vector3::z()).1 - project(&m, &Vector3::zeros()).1;
    assert!(z < 0.0, "the object frame's z does not point up the page");

    // The CoM, seen, where the same projection puts it; the origin likewise.
    let com: Vec<&El> = of("com").collect();
    assert_eq!(com.len(), 1);
    assert_eq!(com[0].get("data-known"), "seen");
    let want = project(&m, &Vector3::from(COM));
    let got = (com[0].f("cx"), com[0].f("cy"));
    assert!(
        (got.0 - want.0).hypot(got.1 - want.1) < 0.02,
        "CoM at {got:?}, want {want:?}"
    );
    let o = of("origin").next().unwrap();
    let want = project(&m, &Vector3::zeros());
    assert!((o.f("cx") - want.0).hypot(o.f("cy") - want.1) < 0.02);

    // Edges: twelve; the eight learnt ones seen, each on the projection of its line and as long
    // as the box's edge; the other four inferred.
    let edges: Vec<&El> = of("edge").collect();
    assert_eq!(edges.len(), 12);
    let mut seen = 0;
    for e in &edges {
        let (a, b) = ((e.f("x1"), e.f("y1")), (e.f("x2"), e.f("y2")));
        match tree.edges.iter().find(|x| x.id == e.get("data-id")) {
            Some(learnt) => {
                seen += 1;
                assert_eq!(e.get("data-known"), "seen");
                let p = project(&m, &learnt.point);
                let q = project(&m, &(learnt.point + learnt.direction));
                let (dx, dy) = (q.0 - p.0, q.1 - p.1);
                for end in [a, b] {
                    let off = ((end.0 - p.0) * dy - (end.1 - p.1) * dx).abs() / dx.hypot(dy);
                    assert!(off < 0.02, "{} drawn {off} px off its line", learnt.id);
                }
                let len = (b.0 - a.0).hypot(b.1 - a.1) / dx.hypot(dy);
                let box_len = shape.extents[1] - shape.extents[0];
                assert!(
                    box_len.iter().any(|l| (l - len).abs() < 1e-4),
                    "{} drawn {len} m long, box {box_len:?}",
                    learnt.id
                );
            }
            None => assert_eq!(e.get("data-known"), "inferred", "{}", e.get("data-id")),
        }
    }
    assert_eq!(seen, 8);
    let faces: Vec<&El> = of("face").collect();
    assert_eq!(faces.len(), 6);
    assert!(faces
        .iter()
        .all(|f| f.get("data-known") == "seen" && f.name == "polygon"));
    assert!(svg.contains("<title>centre of mass: "), "no hover text");

    // The PNG: the same size, and the CoM's colour (seen: blue) inside its circle.
    let decoder = png::Decoder::new(std::fs::File::open(&png).unwrap());
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size()];
    let info = reader.next_frame(&mut buf).unwrap();
    let at = |x: f64, y: f64| {
        let i = (y.round() as usize * info.width as usize + x.round() as usize) * 3;
        [buf[i], buf[i + 1], buf[i + 2]]
    };
    assert_eq!(
        at(got.0 + 4.0, got.1 + 4.0),
        objmodel_plot::Known::Seen.rgb()
    );
    let drawn = buf.chunks(3).filter(|p| p != &[255, 255, 255]).count();
    assert!(drawn > 20_000, "PNG nearly blank: {drawn} pixels drawn");
}

#[test]
fn unknown_and_contradicted_parts_say_so() {
    // Face f1 without offset: no closed shape; f1 an unknown direction, the shape open.
    let tree = analytic_box(false);
    assert!(tree.shape.is_none());
    let (svg, _png, _dir) = draw(&tree, "open_box");
    let els = elements(&svg);
    let f1: Vec<&El> = els.iter().filter(|e| e.get("data-id") == "f1").collect();
    assert_eq!(f1.len(), 1);
    assert_eq!(
        (f1[0].get("data-kind"), f1[0].get("data-known")),
        ("direction", "unknown")
    );
    assert!(els
        .iter()
        .any(|e| e.get("data-id").starts_with("open") && e.get("data-known") == "unknown"));
    assert_eq!(
        els.iter()
            .filter(|e| e.get("data-kind") == "vertex")
            .count(),
        0
    );
    assert_eq!(
        els.iter()
            .filter(|e| e.get("data-kind") == "edge" && e.get("data-known") == "seen")
            .count(),
        8
    );
    assert!(
        svg.contains("no closed shape"),
        "the note on the open shape is missing"
    );

    // A CoM outside the box: contradicted.
    let mut tree = analytic_box(true);
    tree.com.as_mut().unwrap().point = Vector3::new(0.3, 0.0, 0.0);
    let (svg, _png, _dir) = draw(&tree, "com_outside");
    let com = elements(&svg)
        .into_iter()
        .find(|e| e.get("data-kind") == "com")
        .unwrap();
    assert_eq!(com.get("data-known"), "contradicted");
}

/// A learnt box (noisy topples onto every face): every learnt edge lies along an edge of the
/// learnt shape, and is drawn as long as the true box's edge (within 5 mm).
#[test]
fn a_learnt_box_is_drawn_whole() {
    let (b, tree, _) = learnt_box(3, &SynthNoise::REAL);
    let (svg, _png, _dir) = draw(&tree, "learnt_box");
    let els = elements(&svg);
    assert_eq!(
        els.iter()
            .filter(|e| e.get("data-kind") == "vertex")
            .count(),
        8
    );
    assert_eq!(
        els.iter().filter(|e| e.get("data-kind") == "face").count(),
        6
    );
    let sizes: Vec<f64> = b.half.iter().map(|h| 2.0 * h).collect();
    for e in &tree.edges {
        let drawn: Vec<&El> = els.iter().filter(|x| x.get("data-id") == e.id).collect();
        assert_eq!(drawn.len(), 1, "{}", e.id);
        assert_eq!(drawn[0].get("data-known"), "seen");
        let title = &drawn[0].get("data-id");
        assert!(
            !svg.contains("not along any edge of the reconstructed shape"),
            "{title}"
        );
    }
    let dr = objmodel_plot::ModelDrawing::from_tree(&tree);
    for f in dr.features.iter().filter(|f| {
        f.kind == objmodel_plot::FeatureKind::Edge && f.known == objmodel_plot::Known::Seen
    }) {
        let (a, c) = (Vector3::from(f.points[0]), Vector3::from(f.points[1]));
        let len = (c - a).norm();
        assert!(
            sizes.iter().any(|s| (s - len).abs() < 5e-3),
            "{}: {len} m, box {sizes:?}",
            f.id
        );
    }
}
