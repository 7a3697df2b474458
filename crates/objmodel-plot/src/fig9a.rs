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
use crate::fig9a_legend::{axes, legend};
use crate::model::{Feature, FeatureKind, Known, ModelDrawing};
use crate::PlotError;

/// Size of the figure (px).
const WIDTH: u32 = 1000;
const HEIGHT: u32 = 720;
/// The drawing's square: left edge, top edge and side (px); the legend is to its right.
pub(crate) const LEFT: f64 = 10.0;
pub(crate) const TOP: f64 = 50.0;
pub(crate) const SIDE: f64 = 660.0;
/// Azimuth and elevation of the direction towards the viewer in the object frame (degrees),
/// unless another view of [`View::choose`] shows the vertices much further apart.
const AZIMUTH_DEG: f64 = -58.0;
const ELEVATION_DEG: f64 = 26.0;
/// The object frame's origin: green, as in the paper.
pub(crate) const ORIGIN_GREEN: [u8; 3] = [44, 160, 44];
pub(crate) const INK: [u8; 3] = [30, 30, 30];

/// An orthographic view: page right, page up and towards the viewer, in the object frame.
pub(crate) struct View {
    pub(crate) right: Vector3<f64>,
    pub(crate) up: Vector3<f64>,
    toward: Vector3<f64>,
    centre: Vector3<f64>,
    scale: f64,
}

impl View {
    /// The view from azimuth `az_deg` and elevation `el_deg`.
    fn new(centre: Vector3<f64>, radius: f64, az_deg: f64, el_deg: f64) -> Self {
        let (az, el) = (az_deg.to_radians(), el_deg.to_radians());
        let toward = Vector3::new(el.cos() * az.cos(), el.cos() * az.sin(), el.sin());
        let right = Vector3::new(-az.sin(), az.cos(), 0.0);
        View {
            up: toward.cross(&right),
            right,
            toward,
            centre,
            scale: (SIDE / 2.0 - 40.0) / radius.max(1e-6),
        }
    }

    /// The default view, or, when it shows a face of the shape (outward `normals`) much more
    /// nearly edge-on than another view does (its smallest `|normal · toward|` below 0.8 of
    /// theirs), the view among azimuths every 15° and elevations 20°, 30°, 40° whose smallest
    /// `|normal · toward|` is largest: no face seen edge-on.
    fn choose(centre: Vector3<f64>, radius: f64, normals: &[Vector3<f64>]) -> Self {
        let open = |v: &View| {
            normals
                .iter()
                .map(|n| n.dot(&v.toward).abs())
                .fold(f64::INFINITY, f64::min)
        };
        let default = View::new(centre, radius, AZIMUTH_DEG, ELEVATION_DEG);
        let base = open(&default);
        let best = (0..24)
            .flat_map(|a| [20.0, 30.0, 40.0].map(|e| (a as f64 * 15.0 - 180.0, e)))
            .map(|(a, e)| View::new(centre, radius, a, e))
            .map(|v| (open(&v), v))
            .max_by(|a, b| a.0.total_cmp(&b.0));
        match best {
            Some((s, v)) if s.is_finite() && base < 0.8 * s => v,
            _ => default,
        }
    }

    /// Pixel position of the object-frame point `p`.
    fn px(&self, p: &[f64; 3]) -> (f64, f64) {
        let r = Vector3::from(*p) - self.centre;
        (
            LEFT + SIDE / 2.0 + self.scale * self.right.dot(&r),
            TOP + SIDE / 2.0 - self.scale * self.up.dot(&r),
        )
    }

    /// Whether the shape (half-spaces `planes`, `radius`) hides the object-frame point `p`: a
    /// step from it towards the viewer, of a twentieth of the radius, is inside every face.
    fn hidden(&self, planes: &[([f64; 3], f64)], radius: f64, p: &[f64; 3]) -> bool {
        let q = Vector3::from(*p) + self.toward * radius * 0.05;
        !planes.is_empty() && planes.iter().all(|(n, d)| Vector3::from(*n).dot(&q) < *d)
    }

    fn depth(&self, p: &[f64; 3]) -> f64 {
        self.toward.dot(&Vector3::from(*p))
    }
}

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
