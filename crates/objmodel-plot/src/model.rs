//! What a picture of a learnt object shows, and how each part of it is known: the features of
//! an object description tree as drawable geometry in the object frame, shared by the paper's
//! Fig. 9a ([`crate::plot_model`]) and the 3D view ([`crate::view_page`]).
//!
//! How a part is known ([`Known`]):
//!
//! * **seen**: the demonstrations show it. A learnt edge (a topple about it), a face of the
//!   shape (rested on or slid on, with its offset from an edge in it), the centre of mass (the
//!   pendulums of topples), the object frame's origin (the tracked frame itself).
//! * **inferred**: derived from seen parts, never shown on its own. The shape's vertices (where
//!   three faces meet: the paper's "vertices may be derived from the intersection of learnt
//!   edges") and the shape's edges that no topple showed (where two seen faces meet).
//! * **unknown**: a face whose outward side or offset the data do not give (a slide alone does
//!   not give the offset), drawn as an arrow along its normal; a direction towards which the
//!   shape is open (no face facing it seen); a missing centre of mass (a note).
//! * **contradicted**: a feature the tree's consistency checks ([`Tree::contradictions`]) found
//!   at odds with the others beyond their uncertainty, or a face that does not bound the shape.
//!
//! A learnt edge is drawn as the part of its line that runs along the shape's edge it matches
//! (within three standard deviations of the edge, the shape's vertices and the tree's
//! per-demonstration systematic errors); an edge that matches none is drawn across the shape's
//! bounding sphere.

use crate::feature::{arr, mm, v3, Feature, FeatureKind, Known};
use crate::model_edges::shape_edges;
use nalgebra::Vector3;
use objmodel::shape::{reconstruct, Incomplete, Shape};
use objmodel::tree::{Face, Tree};
use serde::Serialize;
use std::collections::HashSet;

/// The learnt object as drawable parts.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ModelDrawing {
    /// Every part.
    pub features: Vec<Feature>,
    /// Centre of the region to show \[m\].
    pub centre: [f64; 3],
    /// Radius of the region to show \[m\].
    pub radius: f64,
    /// The closed shape's faces as half-spaces `normal · x <= offset`: `(normal, offset)`;
    /// empty when the faces close no shape.
    pub planes: Vec<([f64; 3], f64)>,
    /// Facts without geometry: what is unknown and why (no centre of mass, no closed shape).
    pub notes: Vec<String>,
}

impl ModelDrawing {
    /// The drawable parts of `tree`. Its shape is the tree's own, or reconstructed from its
    /// faces when the file has none (an older file); its contradictions are those the file
    /// lists and those found now.
    pub fn from_tree(tree: &Tree) -> Self {
        let mut contradicted: HashSet<String> = HashSet::new();
        for c in tree.contradictions.iter().chain(&tree.contradictions()) {
            contradicted.extend(c.features.iter().cloned());
        }
        let status = |id: &str| {
            if contradicted.contains(id) {
                Known::Contradicted
            } else {
                Known::Seen
            }
        };
        let built = match &tree.shape {
            Some(s) => Ok(s.clone()),
            None => reconstruct(&tree.learnt_faces()),
        };
        let (centre, radius) = frame(tree, built.as_ref().ok());
        let mut features = Vec::new();
        let mut notes = Vec::new();
        if let Ok(shape) = &built {
            for sf in &shape.faces {
                let face = tree.faces.iter().find(|f| f.id == sf.id);
                features.push(Feature {
                    kind: FeatureKind::Face,
                    id: sf.id.clone(),
                    known: match (&sf.inferred, status(&sf.id)) {
                        (Some(_), Known::Seen) => Known::Inferred,
                        (_, k) => k,
                    },
                    points: sf
                        .polygon
                        .iter()
                        .map(|&i| arr(&shape.vertices[i]))
                        .collect(),
                    support: face.map(|f| f.n_support),
                    sigma_m: face.and_then(|f| f.offset_sigma_m),
                    info: match &sf.inferred {
                        Some(why) => format!("face {} inferred: {why}", sf.id),
                        None => face.map_or_else(
                            || format!("face {} of the shape (not in the tree's faces)", sf.id),
                            face_info,
                        ),
                    },
                });
            }
            features.extend(shape_edges(tree, shape, &status));
            for (i, v) in shape.vertices.iter().enumerate() {
                let faces: Vec<&str> = shape
                    .faces
                    .iter()
                    .filter(|f| f.polygon.contains(&i))
                    .map(|f| f.id.as_str())
                    .collect();
                let sigma = shape.vertex_sigma_m.get(i).copied();
                features.push(Feature {
                    kind: FeatureKind::Vertex,
                    id: format!("v{i}"),
                    known: Known::Inferred,
                    points: vec![arr(v)],
                    support: None,
                    sigma_m: sigma,
                    info: format!(
                        "vertex v{i}: {}\n± {} (from its faces' offsets and normals)\nwhere faces {} meet (derived, not demonstrated)",
                        v3(v),
                        sigma.map_or("?".into(), mm),
                        faces.join(", ")
                    ),
                });
            }
        } else {
            features.extend(shape_edges(tree, &empty_shape(centre, radius), &status));
        }
        let in_shape = |id: &str| {
            built
                .as_ref()
                .is_ok_and(|s| s.faces.iter().any(|f| f.id == id))
        };
        for f in tree.faces.iter().filter(|f| !in_shape(&f.id)) {
            features.push(loose_face(f, built.as_ref().ok(), centre, radius));
        }
        match &built {
            Err(Incomplete::Open { towards }) => {
                for (k, u) in towards.iter().enumerate() {
                    features.push(Feature {
                        kind: FeatureKind::Direction,
                        id: format!("open{k}"),
                        known: Known::Unknown,
                        points: vec![arr(&centre), arr(&(centre + u * radius * 0.9))],
                        support: None,
                        sigma_m: None,
                        info: format!(
                            "the shape is open towards [{:+.2}, {:+.2}, {:+.2}]: no face facing there has been seen",
                            u.x, u.y, u.z
                        ),
                    });
                }
                notes.push(format!(
                    "no closed shape: {}",
                    Incomplete::Open {
                        towards: towards.clone()
                    }
                ));
            }
            Err(e) => notes.push(format!("no closed shape: {e}")),
            Ok(_) => {}
        }
        match &tree.com {
            Some(com) => features.push(Feature {
                kind: FeatureKind::Com,
                id: "com".into(),
                known: status("com"),
                points: vec![arr(&com.point)],
                support: Some(com.pendulums),
                sigma_m: com.sigma_m.or(Some(com.rms_residual_m)),
                info: if com.pendulums > 0 {
                    format!(
                        "centre of mass: {}\nfrom {}; the pendulums' planes pass within {} (rms) \
                         of it",
                        v3(&com.point),
                        com.learnt_from(),
                        mm(com.rms_residual_m)
                    )
                } else {
                    format!(
                        "centre of mass: {}\nfrom {}",
                        v3(&com.point),
                        com.learnt_from()
                    )
                },
            }),
            None => notes.push(
                "centre of mass: unknown (it needs the pendulums of topples about at least two \
                 non-parallel edges, or tosses that spin in flight)"
                    .into(),
            ),
        }
        features.push(Feature {
            kind: FeatureKind::Origin,
            id: "origin".into(),
            known: Known::Seen,
            points: vec![[0.0; 3]],
            support: Some(tree.demos.len()),
            sigma_m: None,
            info: "object frame origin: the tracked frame (the tag), which every demonstration's poses give".into(),
        });
        ModelDrawing {
            features,
            centre: arr(&centre),
            radius,
            planes: built
                .as_ref()
                .map(|s| s.faces.iter().map(|f| (arr(&f.normal), f.offset)).collect())
                .unwrap_or_default(),
            notes,
        }
    }
}

/// The region to show: the shape's bounding sphere, or, without a shape, the sphere about the
/// learnt features (edges' closest points, faces' planes, CoM, origin).
fn frame(tree: &Tree, shape: Option<&Shape>) -> (Vector3<f64>, f64) {
    if let Some(s) = shape {
        let centre = (s.extents[0] + s.extents[1]) / 2.0;
        return (
            centre,
            ((s.extents[1] - s.extents[0]).norm() / 2.0).max(1e-3),
        );
    }
    let mut pts = vec![Vector3::zeros()];
    pts.extend(tree.edges.iter().map(|e| e.point));
    pts.extend(
        tree.faces
            .iter()
            .filter_map(|f| f.offset.map(|d| f.normal * d)),
    );
    pts.extend(tree.com.iter().map(|c| c.point));
    let centre = pts.iter().sum::<Vector3<f64>>() / pts.len() as f64;
    let radius = pts.iter().map(|p| (p - centre).norm()).fold(0.05, f64::max);
    (centre, radius)
}

/// A shape with no faces, whose extents are the region shown: learnt edges are then drawn
/// across it.
fn empty_shape(centre: Vector3<f64>, radius: f64) -> Shape {
    let r = Vector3::repeat(radius / 3f64.sqrt());
    Shape {
        faces: Vec::new(),
        vertices: Vec::new(),
        vertex_sigma_m: Vec::new(),
        extents: [centre - r, centre + r],
        left_out: Vec::new(),
        assumptions: Vec::new(),
    }
}

/// Hover text of a tree face.
fn face_info(f: &Face) -> String {
    format!(
        "face {}: normal [{:+.3}, {:+.3}, {:+.3}]{} ± {:.2}°\noffset {}\n{} demonstration(s): {} slide, {} rest observation(s)",
        f.id,
        f.normal.x,
        f.normal.y,
        f.normal.z,
        if f.sign_known { " (outward)" } else { " (outward side unknown)" },
        f.sigma_normal_rad.to_degrees(),
        match (f.offset, f.offset_sigma_m) {
            (Some(d), Some(s)) => format!("{} ± {}", mm(d), mm(s)),
            (Some(d), None) => mm(d),
            _ => "unknown".into(),
        },
        f.n_support,
        f.evidence.slide,
        f.evidence.rest
    )
}

/// A tree face that is not a face of the shape: a square patch on its plane when its side and
/// offset are known (contradicted when a shape exists that it does not bound), otherwise an
/// arrow along its normal (unknown).
fn loose_face(f: &Face, shape: Option<&Shape>, centre: Vector3<f64>, radius: f64) -> Feature {
    let why = shape
        .and_then(|s| s.left_out.iter().find(|(id, _)| id == &f.id))
        .map(|(_, why)| why.clone());
    let mut info = face_info(f);
    if let Some(why) = &why {
        info += &format!("\nnot a face of the shape: {why}");
    }
    match (f.sign_known, f.offset) {
        (true, Some(d)) => {
            let n = f.normal;
            let c = centre + n * (d - n.dot(&centre));
            let u = n.cross(&if n.x.abs() < 0.9 {
                Vector3::x()
            } else {
                Vector3::y()
            });
            let u = u.normalize() * radius * 0.35;
            let w = n.cross(&u);
            Feature {
                kind: FeatureKind::Face,
                id: f.id.clone(),
                known: if shape.is_some() {
                    Known::Contradicted
                } else {
                    Known::Seen
                },
                points: [u + w, w - u, -u - w, u - w]
                    .iter()
                    .map(|x| arr(&(c + x)))
                    .collect(),
                support: Some(f.n_support),
                sigma_m: f.offset_sigma_m,
                info,
            }
        }
        _ => Feature {
            kind: FeatureKind::Direction,
            id: f.id.clone(),
            known: Known::Unknown,
            points: vec![arr(&centre), arr(&(centre + f.normal * radius * 0.9))],
            support: Some(f.n_support),
            sigma_m: None,
            info,
        },
    }
}
