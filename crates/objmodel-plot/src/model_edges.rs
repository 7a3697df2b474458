//! The edges of a drawing of the learnt object: the shape's edges (where two of its faces
//! meet), each matched to the learnt edge that lies along it, if any, and the learnt edges
//! that match none (see [`crate::model`]).

use crate::feature::{arr, mm, v3, Feature, FeatureKind, Known};
use nalgebra::Vector3;
use objmodel::shape::Shape;
use objmodel::tree::{Edge, Tree, SYSTEMATIC_DIRECTION_RAD, SYSTEMATIC_POINT_M};

/// The shape's edges and the learnt edges, as features; `status` says whether a tree feature
/// is seen or contradicted.
pub(crate) fn shape_edges(
    tree: &Tree,
    shape: &Shape,
    status: &dyn Fn(&str) -> Known,
) -> Vec<Feature> {
    // Each segment of the shape once, with the faces it joins.
    let mut segments: Vec<((usize, usize), Vec<&str>)> = Vec::new();
    for f in &shape.faces {
        let n = f.polygon.len();
        for k in 0..n {
            let (a, b) = (f.polygon[k], f.polygon[(k + 1) % n]);
            let key = (a.min(b), a.max(b));
            match segments.iter_mut().find(|(s, _)| *s == key) {
                Some((_, faces)) => faces.push(&f.id),
                None => segments.push((key, vec![&f.id])),
            }
        }
    }
    let mut out = Vec::new();
    let mut matched = vec![false; tree.edges.len()];
    for ((a, b), faces) in &segments {
        let (pa, pb) = (shape.vertices[*a], shape.vertices[*b]);
        let sigma_v = shape
            .vertex_sigma_m
            .get(*a)
            .copied()
            .unwrap_or(0.0)
            .max(shape.vertex_sigma_m.get(*b).copied().unwrap_or(0.0));
        let best = tree
            .edges
            .iter()
            .enumerate()
            .filter_map(|(i, e)| along(e, &pa, &pb, sigma_v).map(|d| (i, d)))
            .min_by(|x, y| x.1.total_cmp(&y.1));
        match best {
            Some((i, _)) => {
                matched[i] = true;
                let e = &tree.edges[i];
                let (qa, qb) = (foot(e, &pa), foot(e, &pb));
                out.push(learnt(e, status(&e.id), [qa, qb], None));
            }
            None => out.push(Feature {
                kind: FeatureKind::Edge,
                id: faces.join("|"),
                known: Known::Inferred,
                points: vec![arr(&pa), arr(&pb)],
                support: None,
                sigma_m: Some(sigma_v),
                info: format!(
                    "edge where faces {} meet ({} long)\nno topple about it was demonstrated: \
                     derived from the faces",
                    faces.join(" and "),
                    mm((pb - pa).norm())
                ),
            }),
        }
    }
    let centre = (shape.extents[0] + shape.extents[1]) / 2.0;
    let radius = (shape.extents[1] - shape.extents[0]).norm() / 2.0;
    for (e, _) in tree.edges.iter().zip(&matched).filter(|(_, m)| !**m) {
        let note = if shape.faces.is_empty() {
            None
        } else {
            Some("not along any edge of the reconstructed shape")
        };
        out.push(learnt(e, status(&e.id), across(e, &centre, radius), note));
    }
    out
}

/// The point of `e`'s line closest to `p`.
fn foot(e: &Edge, p: &Vector3<f64>) -> Vector3<f64> {
    e.point + e.direction * e.direction.dot(&(p - e.point))
}

/// How far (in standard deviations, the larger of position and direction) the segment
/// `a`–`b` lies from the learnt edge `e`, when within 3 of them.
fn along(e: &Edge, a: &Vector3<f64>, b: &Vector3<f64>, sigma_v: f64) -> Option<f64> {
    let s_pos = (e.sigma_point_m.powi(2) + sigma_v.powi(2) + SYSTEMATIC_POINT_M.powi(2)).sqrt();
    let s_dir = (e.sigma_direction_rad.powi(2) + SYSTEMATIC_DIRECTION_RAD.powi(2)).sqrt();
    let u = (b - a).normalize();
    let angle = u.cross(&e.direction).norm().asin();
    let dist = (a - foot(e, a)).norm().max((b - foot(e, b)).norm());
    let z = (dist / s_pos).max(angle / s_dir);
    (z <= 3.0).then_some(z)
}

/// The part of `e`'s line inside the sphere of `radius` about `centre`, at least as long as the
/// radius (a line that misses the sphere or grazes it gets that length about its point closest
/// to `centre`).
fn across(e: &Edge, centre: &Vector3<f64>, radius: f64) -> [Vector3<f64>; 2] {
    let closest = foot(e, centre);
    let d = (closest - centre).norm();
    let half = (radius * radius - d * d).max(0.0).sqrt().max(radius / 2.0);
    [closest - e.direction * half, closest + e.direction * half]
}

/// A learnt edge as a feature between `ends`.
fn learnt(e: &Edge, known: Known, ends: [Vector3<f64>; 2], note: Option<&str>) -> Feature {
    let mut info = format!(
        "edge {}: through {}, direction [{:+.3}, {:+.3}, {:+.3}]\n± {} across the line, ± {:.2}° in direction\n{} demonstration(s): {}",
        e.id,
        v3(&e.point),
        e.direction.x,
        e.direction.y,
        e.direction.z,
        mm(e.sigma_point_m),
        e.sigma_direction_rad.to_degrees(),
        e.n_support,
        e.support.join(", ")
    );
    if !e.faces.is_empty() {
        info += &format!("\njoins faces {}", e.faces.join(", "));
    }
    for p in &e.pendulums {
        info += &format!(
            "\npendulum: φ {} {}, from {} demonstration(s)",
            p.phi
                .map_or("unknown".into(), |x| format!("{:.2}°", x.to_degrees())),
            p.phi_sigma
                .map_or(String::new(), |x| format!("± {:.2}°", x.to_degrees())),
            p.support.len()
        );
    }
    if let Some(note) = note {
        info += &format!("\n{note}");
    }
    Feature {
        kind: FeatureKind::Edge,
        id: e.id.clone(),
        known,
        points: vec![arr(&ends[0]), arr(&ends[1])],
        support: Some(e.n_support),
        sigma_m: Some(e.sigma_point_m),
        info,
    }
}
