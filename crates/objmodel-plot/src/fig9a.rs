//! The paper's Fig. 9a: the learnt object in an oblique orthographic view of its object frame
//! (z up on the page; from the azimuth and elevation, among a few, that keep the shape's
//! vertices furthest apart on the page, so that no edge is seen end-on), every part coloured by how it is known ([`Known`]): the shape's faces
//! lightly filled, edges (solid when learnt, dashed when inferred), vertices, the centre of mass,
//! the object frame's origin (green, as in the paper) and its axes, unknown face normals and
//! open directions as dashed arrows, and a legend with what is unknown.

use std::path::{Path, PathBuf};

use nalgebra::Vector3;

use crate::canvas::{Canvas, Shape2, Tag};
use crate::common::render_with_svg;
use crate::feature::{Feature, FeatureKind, Known};
use crate::fig9a_legend::{axes, legend};
use crate::fig9a_view::{View, HEIGHT, INK, LEFT, ORIGIN_GREEN, WIDTH};
use crate::model::ModelDrawing;
use crate::PlotError;

fn tag(f: &Feature, kind: &'static str) -> Tag {
    Tag {
        kind,
        id: f.id.clone(),
        known: f.known.name(),
        title: f.info.clone(),
    }
}

fn mean(points: &[[f64; 3]]) -> [f64; 3] {
    let s = points
        .iter()
        .fold([0.0; 3], |a, p| [a[0] + p[0], a[1] + p[1], a[2] + p[2]]);
    let n = points.len().max(1) as f64;
    [s[0] / n, s[1] / n, s[2] / n]
}

/// The unit normal of a polygon, by the right-hand rule.
fn normal(points: &[[f64; 3]]) -> Vector3<f64> {
    let p: Vec<Vector3<f64>> = points.iter().map(|x| Vector3::from(*x)).collect();
    (1..p.len().saturating_sub(1))
        .map(|i| (p[i] - p[0]).cross(&(p[i + 1] - p[0])))
        .sum::<Vector3<f64>>()
        .try_normalize(1e-300)
        .unwrap_or_else(Vector3::zeros)
}

/// Builds the picture of `d`.
fn canvas(d: &ModelDrawing, title: &str) -> Canvas {
    let normals: Vec<Vector3<f64>> = d
        .features
        .iter()
        .filter(|f| f.kind == FeatureKind::Face)
        .map(|f| normal(&f.points))
        .collect();
    let view = View::choose(Vector3::from(d.centre), d.radius, &normals);
    let mut c = Canvas {
        width: WIDTH,
        height: HEIGHT,
        items: Vec::new(),
    };
    let text = |at, text: &str, colour, size, middle| Shape2::Text {
        at,
        text: text.to_string(),
        colour,
        size,
        middle,
    };
    c.push(
        text((LEFT + 10.0, 34.0), title, INK, 22.0, false),
        Tag::default(),
    );
    let of = |k: FeatureKind| d.features.iter().filter(move |f| f.kind == k);

    // Faces, back to front; those facing away lighter.
    let mut faces: Vec<&Feature> = of(FeatureKind::Face).collect();
    faces.sort_by(|a, b| {
        view.depth(&mean(&a.points))
            .total_cmp(&view.depth(&mean(&b.points)))
    });
    for f in &faces {
        let facing = normal(&f.points).dot(&view.toward) > 0.0;
        c.push(
            Shape2::Polygon {
                points: f.points.iter().map(|x| view.px(x)).collect(),
                fill: f.known.rgb(),
                opacity: if facing { 0.22 } else { 0.08 },
            },
            tag(f, "face"),
        );
    }
    // Unknown directions: dashed arrows.
    for f in of(FeatureKind::Direction) {
        let (a, b) = (view.px(&f.points[0]), view.px(&f.points[1]));
        c.push(
            Shape2::Line {
                a,
                b,
                colour: f.known.rgb(),
                width: 2.0,
                dashed: true,
            },
            tag(f, "direction"),
        );
        let (dx, dy) = (b.0 - a.0, b.1 - a.1);
        let len = (dx * dx + dy * dy).sqrt().max(1e-9);
        let (ux, uy) = (dx / len * 12.0, dy / len * 12.0);
        c.push(
            Shape2::Polygon {
                points: vec![
                    b,
                    (b.0 - ux - uy * 0.5, b.1 - uy + ux * 0.5),
                    (b.0 - ux + uy * 0.5, b.1 - uy - ux * 0.5),
                ],
                fill: f.known.rgb(),
                opacity: 1.0,
            },
            Tag::default(),
        );
        c.push(
            text(
                (b.0 + 6.0, b.1),
                &format!("{}?", f.id),
                f.known.rgb(),
                14.0,
                false,
            ),
            Tag::default(),
        );
    }
    // Edges: inferred first, learnt on top.
    let mut edges: Vec<&Feature> = of(FeatureKind::Edge).collect();
    edges.sort_by_key(|f| f.known != Known::Inferred);
    let hidden = |p: &[f64; 3]| view.hidden(&d.planes, d.radius, p);
    let faint = |c: [u8; 3], behind: bool| {
        if behind {
            c.map(|x| (f64::from(x) * 0.4 + 255.0 * 0.6) as u8)
        } else {
            c
        }
    };
    for f in &edges {
        let learnt = f.known != Known::Inferred;
        let (a, b) = (view.px(&f.points[0]), view.px(&f.points[1]));
        let behind = hidden(&mean(&f.points));
        c.push(
            Shape2::Line {
                a,
                b,
                colour: faint(f.known.rgb(), behind),
                width: if learnt && !behind {
                    4.0
                } else if learnt {
                    3.0
                } else {
                    2.0
                },
                dashed: !learnt,
            },
            tag(f, "edge"),
        );
        if learnt {
            let m = view.px(&mean(&f.points));
            c.push(
                text((m.0 + 5.0, m.1 - 4.0), &f.id, f.known.rgb(), 15.0, false),
                Tag::default(),
            );
        }
    }
    for f in &faces {
        let m = view.px(&mean(&f.points));
        c.push(
            text((m.0, m.1 + 5.0), &f.id, f.known.rgb(), 13.0, true),
            Tag::default(),
        );
    }
    for f in of(FeatureKind::Vertex) {
        c.push(
            Shape2::Circle {
                centre: view.px(&f.points[0]),
                r: 4.0,
                fill: faint(f.known.rgb(), hidden(&f.points[0])),
            },
            tag(f, "vertex"),
        );
    }
    for f in of(FeatureKind::Origin) {
        let o = view.px(&f.points[0]);
        c.push(
            Shape2::Circle {
                centre: o,
                r: 5.0,
                fill: ORIGIN_GREEN,
            },
            tag(f, "origin"),
        );
    }
    for f in of(FeatureKind::Com) {
        let p = view.px(&f.points[0]);
        c.push(
            Shape2::Circle {
                centre: p,
                r: 8.0,
                fill: f.known.rgb(),
            },
            tag(f, "com"),
        );
        for (dx, dy) in [(8.0, 0.0), (0.0, 8.0)] {
            c.push(
                Shape2::Line {
                    a: (p.0 - dx, p.1 - dy),
                    b: (p.0 + dx, p.1 + dy),
                    colour: [255, 255, 255],
                    width: 2.0,
                    dashed: false,
                },
                Tag::default(),
            );
        }
        c.push(
            text((p.0 + 11.0, p.1 - 8.0), "CoM", f.known.rgb(), 15.0, false),
            Tag::default(),
        );
    }
    axes(&mut c, &view);
    legend(&mut c, d);
    c
}

pub(crate) fn plot(
    d: &ModelDrawing,
    title: &str,
    base: &Path,
) -> Result<(PathBuf, PathBuf), PlotError> {
    let c = canvas(d, title);
    render_with_svg(base, &c, &c.svg())
}
