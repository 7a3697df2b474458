//! Precision of the learnt trees per scene kind and noise level: each box's demonstrations of
//! one scene kind at one noise level learnt together into one tree, every edge and face of that
//! tree compared with the box's own (the bars of `bench/precision.py`: an edge within 3° and
//! 5 mm of an edge of the box, a face within 5° of a face, sign included when known, and its
//! offset, when known, within 5 mm), summed over the boxes.

use crate::truth::BoxFeatures;
use nalgebra::Vector3;
use objmodel::observation::Observation;
use objmodel::tree::{Edge, Face, Tree};
use serde::Serialize;
use std::collections::BTreeMap;

/// Largest angle \[deg\] between a true edge's direction and a learnt one's.
pub const EDGE_ANGLE_DEG: f64 = 3.0;
/// Largest distance \[m\] from the true edge's line to the learnt edge's point.
pub const EDGE_DISTANCE_M: f64 = 5e-3;
/// Largest angle \[deg\] between a true face's normal and a learnt one's.
pub const FACE_ANGLE_DEG: f64 = 5.0;
/// Largest error \[m\] of a learnt face's offset, when it has one.
pub const FACE_OFFSET_M: f64 = 5e-3;

/// The features learnt from one scene kind at one noise level, summed over the boxes.
#[derive(Clone, Debug, Default, Serialize)]
pub struct PrecisionRow {
    /// Scene kind (topple, instrumented, slide, general, compound, topple_slide, toss, session).
    pub scene: String,
    /// Noise preset.
    pub noise: String,
    /// Demonstrations.
    pub demos: usize,
    /// Edges learnt, and of them on the box.
    pub edges: usize,
    /// Edges on the box.
    pub edges_true: usize,
    /// Faces learnt.
    pub faces: usize,
    /// Faces of the box.
    pub faces_true: usize,
}

impl PrecisionRow {
    /// True features / features learnt, in percent (`None` if nothing was learnt).
    pub fn precision(&self) -> Option<f64> {
        let n = self.edges + self.faces;
        (n > 0).then(|| 100.0 * (self.edges_true + self.faces_true) as f64 / n as f64)
    }
}

fn v(a: [f64; 3]) -> Vector3<f64> {
    Vector3::new(a[0], a[1], a[2])
}

/// Whether a learnt edge is an edge of the box.
pub fn edge_is_true(e: &Edge, box_features: &BoxFeatures) -> bool {
    let u = e.direction.normalize();
    box_features.edges.iter().any(|t| {
        let (p, d) = (v(t.line.point), v(t.line.direction));
        let angle = u.cross(&d).norm().atan2(u.dot(&d).abs()).to_degrees();
        let off = e.point - p;
        let dist = (off - d * d.dot(&off)).norm();
        angle < EDGE_ANGLE_DEG && dist < EDGE_DISTANCE_M
    })
}

/// Whether a learnt face is a face of the box.
pub fn face_is_true(f: &Face, box_features: &BoxFeatures) -> bool {
    let n = f.normal.normalize();
    box_features.faces.iter().any(|t| {
        let tn = v(t.normal);
        let c = if f.sign_known {
            n.dot(&tn)
        } else {
            n.dot(&tn).abs()
        };
        let angle = n.cross(&tn).norm().atan2(c).to_degrees();
        let offset_ok = f
            .offset
            .is_none_or(|o| (o - t.offset).abs() < FACE_OFFSET_M);
        angle < FACE_ANGLE_DEG && offset_ok
    })
}

/// One row per (scene, noise) from the observations grouped by (scene, box, noise), each group
/// with its box's features: the group learnt into one tree and scored.
pub fn precision_rows(
    groups: &BTreeMap<(String, String, String), (Vec<Observation>, BoxFeatures)>,
) -> Vec<PrecisionRow> {
    let mut rows: BTreeMap<(String, String), PrecisionRow> = BTreeMap::new();
    for ((scene, _, noise), (observations, features)) in groups {
        let mut tree = Tree::default();
        for o in observations {
            if !o.teaches_nothing() {
                tree.add(o);
            }
        }
        let row = rows
            .entry((scene.clone(), noise.clone()))
            .or_insert_with(|| PrecisionRow {
                scene: scene.clone(),
                noise: noise.clone(),
                ..PrecisionRow::default()
            });
        row.demos += observations.len();
        row.edges += tree.edges.len();
        row.edges_true += tree
            .edges
            .iter()
            .filter(|e| edge_is_true(e, features))
            .count();
        row.faces += tree.faces.len();
        row.faces_true += tree
            .faces
            .iter()
            .filter(|f| face_is_true(f, features))
            .count();
    }
    rows.into_values().collect()
}

/// Noise levels from the least to the most noisy.
const NOISE_ORDER: [&str; 4] = ["clean", "mocap", "real", "noisy"];

/// The rows as a Markdown table, scenes in the order given (others after them).
pub fn markdown(rows: &[PrecisionRow], order: &[&str]) -> String {
    let mut s = String::from(
        "### Precision of the features learnt, per scene kind and noise level\n\n\
         Each box's demonstrations of one scene kind at one noise level learnt together into one \
         tree; every edge and face of the tree compared with the box's (an edge within 3° and \
         5 mm, a face within 5°, sign included when known, and its offset within 5 mm); summed \
         over the boxes. Precision = true features / features learnt.\n\n\
         | scene | noise | demos | edges true/learnt | faces true/learnt | precision |\n\
         |---|---|---|---|---|---|\n",
    );
    let rank = |scene: &str| {
        order
            .iter()
            .position(|o| *o == scene)
            .unwrap_or(order.len())
    };
    let noise_rank = |n: &str| {
        NOISE_ORDER
            .iter()
            .position(|o| *o == n)
            .unwrap_or(NOISE_ORDER.len())
    };
    let mut sorted: Vec<&PrecisionRow> = rows.iter().collect();
    sorted.sort_by(|a, b| {
        (rank(&a.scene), &a.scene, noise_rank(&a.noise), &a.noise).cmp(&(
            rank(&b.scene),
            &b.scene,
            noise_rank(&b.noise),
            &b.noise,
        ))
    });
    for r in sorted {
        s += &format!(
            "| {} | {} | {} | {}/{} | {}/{} | {} |\n",
            r.scene,
            r.noise,
            r.demos,
            r.edges_true,
            r.edges,
            r.faces_true,
            r.faces,
            r.precision().map_or("-".into(), |p| format!("{p:.0}%"))
        );
    }
    s
}
