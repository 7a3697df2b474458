//! The object's shape from its learnt faces: the convex polyhedron that the faces' half-spaces
//! bound, in the object frame, with its vertices (the paper's "vertices may be derived from the
//! intersection of learnt edges", here of faces, which carry the edges' positions through
//! their offsets), the polygon of each face and the extents.
//!
//! Only faces whose outward normal and offset are known bound the shape: a face seen only in a
//! slide has no offset (a slide does not tell how far the face is from the tag). The shape is
//! closed when those half-spaces bound a finite region; when they do not, [`reconstruct`] says
//! towards which directions it is open, i.e. which faces have not been seen.
//!
//! Each vertex's standard deviation comes from its three faces' offsets and normals:
//! `x = A⁻¹ d` for the faces' normals (rows of `A`) and offsets `d`; a face's normal error
//! `δn ⟂ n` moves its plane at `x` by `δn · x`, so the vertex covariance is
//! `A⁻¹ diag(σ_d² + |x_⊥|² σ_n² / 2) A⁻ᵀ` (per axis of `δn`, hence the half), `x_⊥` the part of
//! `x` along the face.
//!
//! [`reconstruct_inferring`] closes a shape that the learnt faces leave open where a face was
//! never seen but its opposite was, under a stated assumption: the unseen face is parallel to
//! its opposite (as in a box) and the object's density is uniform along their common normal,
//! so that the centre of mass lies halfway between them. Such a face is marked
//! [`ShapeFace::inferred`] with the assumption; its offset's standard deviation is that of the
//! opposite face's and twice the CoM's (the distance is twice the CoM's height), and says
//! nothing of how wrong the assumption may be (a weight inside the object moves the face by
//! twice the weight's offset of the CoM).

mod box_fit;
mod inferred;
pub use box_fit::{box_fit, BoxFit, BOX_ANGLE_RAD};
pub use inferred::{opposite_id, reconstruct_inferring, OPPOSITE_RAD};

use nalgebra::{Matrix3, Vector3};
use serde::{Deserialize, Serialize};

/// How far \[m\] from the learnt faces the shape is searched: a half-space that leaves the
/// shape open meets this box instead, and that tells where a face is missing.
pub const SEARCH_HALF_WIDTH_M: f64 = 10.0;

/// A vertex lies on a face when it is within this distance \[m\] of its plane.
pub const ON_FACE_M: f64 = 1e-9;

/// One face of the shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ShapeFace {
    /// The tree's face id.
    pub id: String,
    /// Outward unit normal.
    pub normal: Vector3<f64>,
    /// Offset \[m\]: the plane is `normal · x = offset`.
    pub offset: f64,
    /// Indices into [`Shape::vertices`] of the face's corners, counter-clockwise seen from
    /// outside.
    pub polygon: Vec<usize>,
    /// Standard deviation of the offset \[m\].
    #[serde(default)]
    pub offset_sigma_m: f64,
    /// Standard deviation of the normal per axis \[rad\] (absent in older files: 0).
    #[serde(default)]
    pub normal_sigma_rad: f64,
    /// The assumption under which the face was inferred, for a face never seen (see
    /// [`reconstruct_inferring`]); absent for a face the data determine.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub inferred: Option<String>,
}

/// The reconstructed shape.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Shape {
    /// The faces that bound it.
    pub faces: Vec<ShapeFace>,
    /// Its corners \[m\], object frame.
    pub vertices: Vec<Vector3<f64>>,
    /// Standard deviation \[m\] of each vertex (RMS over the axes).
    pub vertex_sigma_m: Vec<f64>,
    /// Smallest and largest coordinates of the vertices \[m\].
    pub extents: [Vector3<f64>; 2],
    /// Faces of the tree that were left out, and why.
    pub left_out: Vec<(String, String)>,
    /// The assumptions the shape rests on beyond the data (one per inferred face); empty when
    /// the data determine every face.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub assumptions: Vec<String>,
}

impl Shape {
    /// How far \[m\] `point` lies outside the shape, and beyond which face: the largest
    /// `normal · point - offset` over the faces (negative inside). `None` without faces.
    pub fn outside(&self, point: &Vector3<f64>) -> Option<(f64, &ShapeFace)> {
        self.faces
            .iter()
            .map(|f| (f.normal.dot(point) - f.offset, f))
            .max_by(|a, b| a.0.total_cmp(&b.0))
    }
}

/// Why no closed shape could be built.
#[derive(Clone, Debug, PartialEq)]
pub enum Incomplete {
    /// Fewer than four faces have a known outward normal and offset.
    TooFewFaces {
        /// How many there are.
        usable: usize,
    },
    /// The known faces leave the shape open towards these (unit) directions: no face facing
    /// them has been seen.
    Open {
        /// Directions in the object frame.
        towards: Vec<Vector3<f64>>,
    },
}

impl std::fmt::Display for Incomplete {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Incomplete::TooFewFaces { usable } => write!(
                f,
                "{usable} face(s) with a known outward normal and offset; a closed shape needs \
                 at least 4: demonstrate topples (each rests on two faces and gives their \
                 offsets through its edge)"
            ),
            Incomplete::Open { towards } => {
                write!(f, "the learnt faces leave the shape open towards")?;
                for (i, u) in towards.iter().enumerate() {
                    let sep = if i == 0 { " " } else { ", " };
                    write!(f, "{sep}[{:+.2}, {:+.2}, {:+.2}]", u.x, u.y, u.z)?;
                }
                write!(
                    f,
                    " (object frame): no face facing there has been seen; demonstrate a topple \
                     onto it or away from it (e.g. turn the object over and topple it), or, \
                     when the face opposite was seen, topples about three edges of different \
                     directions, whose centre of mass lets the face be inferred"
                )
            }
        }
    }
}

/// A half-space `n · x <= d` with the standard deviations of `d` \[m\] and of `n` \[rad\];
/// `id` is None for the search box.
struct HalfSpace {
    id: Option<String>,
    n: Vector3<f64>,
    d: f64,
    sigma_d: f64,
    sigma_n: f64,
}

/// A learnt face, as the shape needs it.
#[derive(Clone, Debug, PartialEq)]
pub struct LearntFace {
    /// Its id in the tree.
    pub id: String,
    /// Unit normal, outward when `outward`.
    pub normal: Vector3<f64>,
    /// Whether `normal` is known to point out of the object.
    pub outward: bool,
    /// Offset \[m\] (`normal · x = offset`), when known.
    pub offset: Option<f64>,
    /// Its standard deviation \[m\].
    pub offset_sigma_m: f64,
    /// RMS standard deviation of the normal \[rad\].
    pub normal_sigma_rad: f64,
}

/// The convex polyhedron of the faces with known outward normal and offset.
pub fn reconstruct(learnt: &[LearntFace]) -> Result<Shape, Incomplete> {
    let mut left_out = Vec::new();
    let mut planes: Vec<HalfSpace> = Vec::new();
    for f in learnt {
        match (f.outward, f.offset) {
            (true, Some(d)) => planes.push(HalfSpace {
                id: Some(f.id.clone()),
                n: f.normal,
                d,
                sigma_d: f.offset_sigma_m,
                sigma_n: f.normal_sigma_rad,
            }),
            (false, _) => left_out.push((f.id.clone(), "outward side unknown".to_string())),
            (true, None) => left_out.push((f.id.clone(), "offset unknown".to_string())),
        }
    }
    if planes.len() < 4 {
        return Err(Incomplete::TooFewFaces {
            usable: planes.len(),
        });
    }
    let learnt = planes.len();
    for axis in 0..3 {
        for sign in [1.0, -1.0] {
            let mut n = Vector3::zeros();
            n[axis] = sign;
            planes.push(HalfSpace {
                id: None,
                n,
                d: SEARCH_HALF_WIDTH_M,
                sigma_d: 0.0,
                sigma_n: 0.0,
            });
        }
    }
    let vertices = corners(&planes);
    let on = |v: &Vector3<f64>, p: &HalfSpace| (p.n.dot(v) - p.d).abs() <= ON_FACE_M;
    // A corner on the search box shows where the learnt faces do not close the shape.
    let mut open: Vec<Vector3<f64>> = Vec::new();
    for (v, _) in &vertices {
        if planes[learnt..].iter().any(|p| on(v, p)) {
            let u = v.normalize();
            if open.iter().all(|o| o.dot(&u) < 0.9) {
                open.push(u);
            }
        }
    }
    if !open.is_empty() {
        return Err(Incomplete::Open { towards: open });
    }
    let mut faces = Vec::new();
    for p in &planes[..learnt] {
        let id = p.id.clone().expect("a learnt face");
        let polygon: Vec<usize> = (0..vertices.len())
            .filter(|&i| on(&vertices[i].0, p))
            .collect();
        if polygon.len() < 3 {
            left_out.push((
                id,
                "does not bound the shape the other faces make (it lies outside it)".to_string(),
            ));
            continue;
        }
        faces.push(ShapeFace {
            id,
            normal: p.n,
            offset: p.d,
            polygon: counter_clockwise(polygon, &vertices, &p.n),
            offset_sigma_m: p.sigma_d,
            normal_sigma_rad: p.sigma_n,
            inferred: None,
        });
    }
    let mut min = Vector3::repeat(f64::INFINITY);
    let mut max = Vector3::repeat(f64::NEG_INFINITY);
    for (v, _) in &vertices {
        min = min.inf(v);
        max = max.sup(v);
    }
    Ok(Shape {
        faces,
        vertex_sigma_m: vertices.iter().map(|(_, s)| *s).collect(),
        vertices: vertices.into_iter().map(|(v, _)| v).collect(),
        extents: [min, max],
        left_out,
        assumptions: Vec::new(),
    })
}

/// Every point where three of the planes meet inside all the half-spaces, once, with its
/// standard deviation \[m\].
fn corners(planes: &[HalfSpace]) -> Vec<(Vector3<f64>, f64)> {
    let mut out: Vec<(Vector3<f64>, f64)> = Vec::new();
    let n = planes.len();
    for i in 0..n {
        for j in i + 1..n {
            for k in j + 1..n {
                let (a, b, c) = (&planes[i], &planes[j], &planes[k]);
                let m = Matrix3::from_rows(&[a.n.transpose(), b.n.transpose(), c.n.transpose()]);
                let Some(inv) = m.try_inverse() else {
                    continue;
                };
                if m.determinant().abs() < 1e-9 {
                    continue;
                }
                let x = inv * Vector3::new(a.d, b.d, c.d);
                if planes.iter().any(|p| p.n.dot(&x) > p.d + ON_FACE_M) {
                    continue;
                }
                if out.iter().any(|(v, _)| (v - x).norm() <= 1e-9) {
                    continue;
                }
                let var = |p: &HalfSpace| {
                    let along = (x - p.n * p.n.dot(&x)).norm_squared();
                    p.sigma_d * p.sigma_d + along * p.sigma_n * p.sigma_n / 2.0
                };
                let d = Matrix3::from_diagonal(&Vector3::new(var(a), var(b), var(c)));
                let cov = inv * d * inv.transpose();
                out.push((x, (cov.trace() / 3.0).sqrt()));
            }
        }
    }
    out
}

/// The face's corners ordered counter-clockwise about its outward normal.
fn counter_clockwise(
    mut polygon: Vec<usize>,
    vertices: &[(Vector3<f64>, f64)],
    normal: &Vector3<f64>,
) -> Vec<usize> {
    let centre =
        polygon.iter().map(|&i| vertices[i].0).sum::<Vector3<f64>>() / polygon.len() as f64;
    let u = (vertices[polygon[0]].0 - centre).normalize();
    let w = normal.cross(&u);
    let angle = |i: usize| {
        let r = vertices[i].0 - centre;
        w.dot(&r).atan2(u.dot(&r))
    };
    polygon.sort_by(|&a, &b| angle(a).total_cmp(&angle(b)));
    polygon
}

/// Faces of analytic boxes, for tests.
#[cfg(test)]
pub(crate) mod tests_support {
    use super::LearntFace;
    use nalgebra::{UnitQuaternion, Vector3};

    /// A face with 1 mm offset and 0.01 rad normal uncertainty.
    pub(crate) fn face(id: &str, normal: Vector3<f64>, offset: Option<f64>) -> LearntFace {
        LearntFace {
            id: id.to_string(),
            normal: normal.normalize(),
            outward: true,
            offset,
            offset_sigma_m: 1e-3,
            normal_sigma_rad: 0.01,
        }
    }

    /// The six faces of a box of `size` \[m\] centred at `centre`, turned by `rotation`.
    pub(crate) fn box_faces(
        centre: Vector3<f64>,
        rotation: &UnitQuaternion<f64>,
        size: &Vector3<f64>,
    ) -> Vec<LearntFace> {
        let mut faces = Vec::new();
        for axis in 0..3 {
            for sign in [1.0, -1.0] {
                let n = rotation * (Vector3::ith(axis, 1.0) * sign);
                let offset = n.dot(&centre) + size[axis] / 2.0;
                faces.push(face(&format!("f{}", faces.len()), n, Some(offset)));
            }
        }
        faces
    }
}

#[cfg(test)]
mod tests {
    use super::tests_support::{box_faces as turned_box, face};
    use super::*;
    use nalgebra::UnitQuaternion;

    /// A box 0.2 x 0.1 x 0.3 m, centred at c, from its six faces.
    fn box_faces(c: Vector3<f64>) -> Vec<LearntFace> {
        turned_box(c, &UnitQuaternion::identity(), &Vector3::new(0.2, 0.1, 0.3))
    }

    #[test]
    fn a_box_from_its_six_faces() {
        let c = Vector3::new(0.02, -0.03, 0.1);
        let tree = box_faces(c);
        let s = reconstruct(&tree).unwrap();
        assert_eq!(s.vertices.len(), 8);
        assert_eq!(s.faces.len(), 6);
        assert!(s.faces.iter().all(|f| f.polygon.len() == 4));
        let half = Vector3::new(0.1, 0.05, 0.15);
        assert!((s.extents[0] - (c - half)).norm() < 1e-12);
        assert!((s.extents[1] - (c + half)).norm() < 1e-12);
        for v in &s.vertices {
            let r = v - c;
            for a in 0..3 {
                assert!((r[a].abs() - half[a]).abs() < 1e-12, "{v}");
            }
        }
        // Each polygon turns counter-clockwise about its outward normal.
        for f in &s.faces {
            let p: Vec<Vector3<f64>> = f.polygon.iter().map(|&i| s.vertices[i]).collect();
            let area = (0..p.len())
                .map(|i| p[i].cross(&p[(i + 1) % p.len()]))
                .sum::<Vector3<f64>>();
            assert!(area.dot(&f.normal) > 0.0, "{}", f.id);
        }
        // A corner's sigma: three perpendicular faces of 1 mm offsets, plus their tilt.
        assert!(s
            .vertex_sigma_m
            .iter()
            .all(|&x| x > 1e-3 / 3f64.sqrt() && x < 5e-3));
    }

    #[test]
    fn a_missing_face_leaves_it_open_towards_that_face() {
        let mut faces = box_faces(Vector3::zeros());
        faces.remove(0); // +x
        let tree = faces;
        match reconstruct(&tree) {
            Err(Incomplete::Open { towards }) => {
                assert!(towards.iter().all(|u| u.x > 0.9), "{towards:?}")
            }
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn faces_without_offset_or_side_are_left_out_and_counted() {
        let mut faces = box_faces(Vector3::zeros());
        faces[1].offset = None;
        faces[2].outward = false;
        let tree = faces;
        // Open towards -x and +y (and between them), nowhere else.
        match reconstruct(&tree) {
            Err(Incomplete::Open { towards }) => {
                assert!(
                    towards.iter().all(|u| u.x < -0.5 || u.y > 0.5),
                    "{towards:?}"
                );
                assert!(towards.iter().any(|u| u.x < -0.9), "{towards:?}");
                assert!(towards.iter().any(|u| u.y > 0.9), "{towards:?}");
            }
            other => panic!("{other:?}"),
        }
        let three = box_faces(Vector3::zeros())[..3].to_vec();
        assert_eq!(
            reconstruct(&three),
            Err(Incomplete::TooFewFaces { usable: 3 })
        );
    }

    /// A seventh face that lies outside the box (a wrong feature) does not bound it: it is left
    /// out, and says so.
    #[test]
    fn a_face_outside_the_shape_is_left_out() {
        let mut faces = box_faces(Vector3::zeros());
        faces.push(face("f6", Vector3::new(1.0, 1.0, 0.0), Some(0.5)));
        let tree = faces;
        let s = reconstruct(&tree).unwrap();
        assert_eq!(s.vertices.len(), 8);
        assert!(s.left_out.iter().any(|(id, _)| id == "f6"));
        // A face that cuts a corner off is a face of the shape.
        let mut faces = box_faces(Vector3::zeros());
        faces.push(face("f6", Vector3::new(1.0, 1.0, 0.0), Some(0.1)));
        let s = reconstruct(&faces).unwrap();
        assert_eq!(s.faces.len(), 7);
        assert_eq!(s.vertices.len(), 10);
    }
}
