//! A face seen in one demonstration only that cuts into the shape of the faces seen in several
//! contradicts them: it is kept out of the shape, with the reason, until another demonstration
//! confirms it. (A wrong rest estimate, e.g. the attitude of a box still settling, gives such a
//! face: a plane a few degrees off a true face that cuts a corner off the object.)
//!
//! Two tests, each at [`CUT_SIGMAS`] standard deviations:
//! * it cuts: the confirmed faces close a shape (inferring as the shape does) and some corner
//!   of that shape lies beyond the face's plane by more than [`CUT_SIGMAS`] times the combined
//!   standard deviation of the face's offset and of that corner;
//! * it could not have held the object at rest: a face is learnt from a rest on it, and an
//!   object rests on a face only when its centre of mass lies above the face's polygon; one
//!   whose polygon in the shape leaves the CoM's projection outside by more than
//!   [`CUT_SIGMAS`] times the CoM's and the face offset's standard deviations is no face the
//!   object rested on. (A plane 10° off a true face cuts only millimetres deep, but leaves a
//!   sliver of a face at a corner that nothing can stand on. The corners' standard deviations
//!   are not counted: at such a sliver they come from nearly parallel planes, and are large
//!   exactly where the face is wrong.) A CoM outside the shape is itself the contradiction,
//!   and then no face is tested.

use super::Tree;
use crate::shape::{reconstruct_inferring, LearntFace, Shape};
use nalgebra::Vector3;

/// How many standard deviations a face must cut into the confirmed shape to contradict it.
pub const CUT_SIGMAS: f64 = 3.0;

impl Tree {
    /// The faces of `faces` (the tree's, as the shape takes them) seen in one demonstration
    /// that cut into the shape of those seen in several, each with the reason; `com` as
    /// [`crate::shape::reconstruct_inferring`] takes it.
    pub(super) fn unconfirmed_cuts(
        &self,
        faces: &[LearntFace],
        com: Option<(Vector3<f64>, f64)>,
    ) -> Vec<(String, String)> {
        let support = |id: &str| {
            self.faces
                .iter()
                .find(|f| f.id == id)
                .map_or(0, |f| f.n_support)
        };
        let confirmed: Vec<LearntFace> = faces
            .iter()
            .filter(|f| support(&f.id) >= 2)
            .cloned()
            .collect();
        let Ok(shape) = reconstruct_inferring(&confirmed, com) else {
            return Vec::new();
        };
        let mut out = Vec::new();
        for f in faces.iter().filter(|f| support(&f.id) < 2 && f.outward) {
            let Some(d) = f.offset else { continue };
            let cut = shape
                .vertices
                .iter()
                .zip(&shape.vertex_sigma_m)
                .map(|(v, s)| {
                    let sigma = (f.offset_sigma_m.powi(2) + s * s).sqrt();
                    (f.normal.dot(v) - d, sigma)
                })
                .filter(|(depth, sigma)| *depth > CUT_SIGMAS * sigma)
                .max_by(|a, b| a.0.total_cmp(&b.0));
            if let Some((depth, sigma)) = cut {
                out.push((
                    f.id.clone(),
                    format!(
                        "seen in one demonstration only, it cuts {:.1} mm (> {CUT_SIGMAS} x \
                         {:.1} mm) into the shape of the faces seen in several: kept out until \
                         another demonstration confirms it",
                        depth * 1e3,
                        sigma * 1e3
                    ),
                ));
            }
        }
        out
    }

    /// The faces of `shape` seen in one demonstration whose polygon leaves the projection of
    /// the centre of mass `com` (with its standard deviation) outside, each with the reason.
    pub(super) fn unstable_rests(
        &self,
        shape: &Shape,
        com: Option<(Vector3<f64>, f64)>,
    ) -> Vec<(String, String)> {
        let Some((c, sigma_c)) = com else {
            return Vec::new();
        };
        // A CoM outside the shape is what contradicts it (the tree's checks say so), not its
        // faces.
        if shape.outside(&c).is_some_and(|(d, _)| d > 0.0) {
            return Vec::new();
        }
        let once = |id: &str| self.faces.iter().any(|f| f.id == id && f.n_support < 2);
        let mut out = Vec::new();
        for f in shape
            .faces
            .iter()
            .filter(|f| f.inferred.is_none() && once(&f.id))
        {
            let p = c - f.normal * (f.normal.dot(&c) - f.offset);
            let corners: Vec<Vector3<f64>> = f.polygon.iter().map(|&i| shape.vertices[i]).collect();
            // Signed distance of p inside the polygon (counter-clockwise about the normal).
            let inside = (0..corners.len())
                .map(|i| {
                    let (a, b) = (corners[i], corners[(i + 1) % corners.len()]);
                    let m = f.normal.cross(&(b - a)).normalize();
                    m.dot(&(p - a))
                })
                .fold(f64::INFINITY, f64::min);
            let sigma = (sigma_c * sigma_c + f.offset_sigma_m * f.offset_sigma_m).sqrt();
            if inside < -CUT_SIGMAS * sigma {
                out.push((
                    f.id.clone(),
                    format!(
                        "seen in one demonstration only, as a face the object rested on, but the \
                         centre of mass lies {:.1} mm (> {CUT_SIGMAS} x {:.1} mm) beyond its \
                         polygon, where nothing rests: kept out until another demonstration \
                         confirms it",
                        -inside * 1e3,
                        sigma * 1e3
                    ),
                ));
            }
        }
        out
    }
}

#[cfg(test)]
mod tests {
    use crate::shape::tests_support::box_faces;
    use crate::tree::{Face, Tree};
    use nalgebra::{UnitQuaternion, Vector3};

    fn face(f: crate::shape::LearntFace, n_support: usize) -> Face {
        Face {
            id: f.id,
            normal: f.normal,
            offset: f.offset,
            offset_sigma_m: Some(f.offset_sigma_m),
            sigma_normal_rad: f.normal_sigma_rad,
            sign_known: f.outward,
            support: vec![],
            n_support,
            evidence: Default::default(),
            observations: vec![],
            offset_unlocated: None,
        }
    }

    /// A box seen twice over, and a face seen once 10° off its top that cuts a corner off by a
    /// centimetre: the shape is the box, and says why the face is not in it. The same face
    /// seen twice is a face of the shape (a chamfer); a face seen once that lies on the box
    /// (its sixth face) is one too.
    #[test]
    fn a_face_seen_once_that_cuts_the_confirmed_shape_is_kept_out() {
        let size = Vector3::new(0.1, 0.08, 0.2);
        let faces = box_faces(Vector3::zeros(), &UnitQuaternion::identity(), &size);
        let top = Vector3::new(0.0, 0.17f64.sin(), 0.17f64.cos());
        let corner = Vector3::new(0.05, 0.04, 0.1);
        let mut cut = faces[0].clone();
        cut.id = "cut".into();
        cut.normal = top;
        cut.offset = Some(top.dot(&corner) - 0.01);
        for (n_cut, kept) in [(1, false), (2, true)] {
            let mut tree = Tree {
                faces: faces.iter().cloned().map(|f| face(f, 2)).collect(),
                ..Tree::default()
            };
            tree.faces.push(face(cut.clone(), n_cut));
            let shape = tree.reconstruct_shape().unwrap();
            assert_eq!(shape.faces.iter().any(|f| f.id == "cut"), kept);
            assert_eq!(shape.vertices.len(), if kept { 10 } else { 8 });
            assert_eq!(
                shape
                    .left_out
                    .iter()
                    .any(|(id, why)| id == "cut" && why.contains("one demonstration")),
                !kept
            );
        }
        let mut tree = Tree {
            faces: faces.iter().cloned().map(|f| face(f, 2)).collect(),
            ..Tree::default()
        };
        tree.faces[5].n_support = 1;
        assert_eq!(tree.reconstruct_shape().unwrap().faces.len(), 6);
    }

    /// A face seen once, 10° off the top towards a corner, cutting it only 2 mm deep (within its
    /// uncertainty): with the centre of mass known, its sliver of a face could hold nothing at
    /// rest, and it is kept out; without one, it stays.
    #[test]
    fn a_face_seen_once_that_could_hold_nothing_at_rest_is_kept_out() {
        let size = Vector3::new(0.1, 0.08, 0.2);
        let faces = box_faces(Vector3::zeros(), &UnitQuaternion::identity(), &size);
        let t = 0.17f64.sin() / 2f64.sqrt();
        let top = Vector3::new(t, t, 0.17f64.cos());
        let corner = Vector3::new(0.05, 0.04, 0.1);
        let mut sliver = faces[0].clone();
        sliver.id = "sliver".into();
        sliver.normal = top;
        sliver.offset = Some(top.dot(&corner) - 0.002);
        let mut tree = Tree {
            faces: faces.iter().cloned().map(|f| face(f, 2)).collect(),
            ..Tree::default()
        };
        tree.faces.push(face(sliver, 1));
        assert!(tree
            .reconstruct_shape()
            .unwrap()
            .faces
            .iter()
            .any(|f| f.id == "sliver"));
        tree.com = Some(crate::tree::CentreOfMass {
            point: Vector3::new(0.0, 0.0, -0.01),
            rms_residual_m: 0.002,
            pendulums: 3,
            covariance: None,
            sigma_m: None,
            chi2_per_dof: None,
            ..Default::default()
        });
        let shape = tree.reconstruct_shape().unwrap();
        assert_eq!(shape.faces.len(), 6);
        assert!(shape
            .left_out
            .iter()
            .any(|(id, why)| id == "sliver" && why.contains("nothing rests")));
        // A true face seen once holds the CoM above it: it stays.
        tree.faces.pop();
        tree.faces[4].n_support = 1;
        assert_eq!(tree.reconstruct_shape().unwrap().faces.len(), 6);
    }
}
