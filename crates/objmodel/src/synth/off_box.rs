//! How far a learnt feature is from the nearest true one of a [`SynthBox`]: what the tests
//! measure a learnt tree against.

use super::SynthBox;
use nalgebra::Vector3;

impl SynthBox {
    /// How far `(point, direction)` (tag frame) is from the nearest edge of the box: distance
    /// \[m\] and angle \[rad\], of the edge with the least distance among those within 3° of
    /// it (infinite where none is).
    pub fn off_edge(&self, point: &Vector3<f64>, direction: &Vector3<f64>) -> (f64, f64) {
        let p = (self.box_from_tag * nalgebra::Point3::from(*point)).coords;
        let u = (self.box_from_tag.rotation * direction).normalize();
        let mut best = (f64::INFINITY, f64::INFINITY);
        for axis in 0..3 {
            let angle = u[axis].abs().min(1.0).acos();
            let (j, k) = ((axis + 1) % 3, (axis + 2) % 3);
            for (sj, sk) in [(1.0, 1.0), (1.0, -1.0), (-1.0, 1.0), (-1.0, -1.0)] {
                let mut mid = Vector3::zeros();
                mid[j] = sj * self.half[j];
                mid[k] = sk * self.half[k];
                let d = mid - p;
                let dist = (d - u * d.dot(&u)).norm();
                if angle < 3f64.to_radians() && dist < best.0 {
                    best = (dist, angle);
                }
            }
        }
        best
    }

    /// How far the face `(normal, offset)` (tag frame, `normal · x = offset`) is from the nearest
    /// face of the box: angle \[rad\] and offset difference \[m\] (0 without an offset).
    /// Unless `signed` (the normal's sign known), a face and the one opposite are alike.
    pub fn off_face(&self, normal: &Vector3<f64>, offset: Option<f64>, signed: bool) -> (f64, f64) {
        let n = self.box_from_tag.rotation * normal;
        let mut best = (f64::INFINITY, f64::INFINITY);
        for axis in 0..3 {
            for s in [1.0, -1.0] {
                let mut e = Vector3::zeros();
                e[axis] = s;
                let c = if signed { n.dot(&e) } else { n.dot(&e).abs() };
                let angle = c.clamp(-1.0, 1.0).acos();
                let off = offset.map_or(0.0, |o| {
                    (o + n.dot(&self.box_from_tag.translation.vector) - self.half[axis]).abs()
                });
                if angle < best.0 {
                    best = (angle, off);
                }
            }
        }
        best
    }

    /// The features of `tree` that are not on the box, each described: an edge 5 mm or 3°
    /// from every edge of the box, a face 5° or 5 mm from every face (the tolerances of the
    /// precision tables, `bench/precision.py`).
    pub fn features_off(&self, tree: &crate::tree::Tree) -> Vec<String> {
        let edges = tree.edges.iter().filter_map(|e| {
            let (dist, angle) = self.off_edge(&e.point, &e.direction);
            (dist >= 5e-3 || angle >= 3f64.to_radians()).then(|| {
                format!(
                    "edge {} is {:.1} mm and {:.1}° from the box's (from {:?})",
                    e.id,
                    dist * 1e3,
                    angle.to_degrees(),
                    e.support
                )
            })
        });
        let faces = tree.faces.iter().filter_map(|f| {
            let (angle, off) = self.off_face(&f.normal, f.offset, f.sign_known);
            (angle >= 5f64.to_radians() || off >= 5e-3).then(|| {
                format!(
                    "face {} is {:.1}° and {:.1} mm from the box's (from {:?})",
                    f.id,
                    angle.to_degrees(),
                    off * 1e3,
                    f.support
                )
            })
        });
        edges.chain(faces).collect()
    }
}
