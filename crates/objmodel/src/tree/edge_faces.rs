//! An edge is where two faces of the object meet: each edge's estimate conditioned on the
//! planes of the faces it joins: their normals as every rest on them measures them, their
//! offsets as the other demonstrations' edges do.
//!
//! A topple teaches its edge from the frames of one turn: at 30 Hz a fall of a fraction of a
//! second locates it to a few millimetres and degrees. The faces it joins are measured far
//! better: a face's normal by every rest on it (gravity in the object frame), its offset by
//! every edge in it (each topple's edge lies in the faces it rested on: `n · p = d`). An edge
//! `(p, u)` in a face `(n, d)` satisfies `n · u = 0` and `n · p = d`; those are two linear
//! measurements of the edge, with the face's uncertainty for noise, and each face the edge
//! joins gives them.
//!
//! The face is taken *without the offsets* of the edge's own demonstrations
//! ([`super::Face::without_offsets_of`]): those came through this very edge, and counting them
//! twice would shrink the σ for nothing. Their normals stay: a rest's normal is gravity in the
//! object frame, a measurement of its own. (When it was made normal to the edge, the edge's
//! own rests could not be used: at camera noise a fast palm topple taught an edge 5° off
//! from 3 frames, the face it landed on 5° off with it, and the rest that showed that face
//! right, 0.2° off, was never seen by the edge.) Conditioned on the rests and on what the
//! other demonstrations measure, the estimate is the joint one of the edge and its faces.
//!
//! The part of the point's covariance common to every edge of the object (the contact's depth,
//! [`crate::edge::EdgeObservation::add_contact_depth_var`]) is common to the faces' offsets
//! too, which came through other edges: it cancels in the test, and it does not average down,
//! so it is taken out before the update and added back after it.
//!
//! A face is used where the edge's own estimate lies in its plane within both uncertainties
//! and the per-demonstration systematic errors the tree allows an edge
//! ([`SYSTEMATIC_POINT_M`], [`SYSTEMATIC_DIRECTION_RAD`]: a pivot's micro-slip, a rounded
//! edge): χ² with one degree of freedom per measurement at [`MATCH_ALPHA`], the test of the
//! checks (`tree/checks.rs`, against the edge's own estimate, which [`super::Edge::observed`]
//! keeps). (Without the systematic errors, a box that Drake pivoted on a corner about a line
//! 3.7° out of the face it stood on, at σ 0.6°, was not conditioned on that face, passed the
//! checks with them, and stayed 3.7° off the box's edge; conditioned, it lies in the face.)
//! An edge that a face contradicts beyond them is withheld
//! ([`Tree::withhold_edges_out_of_their_faces`]).
//!
//! What uses which: the centre of mass, the matching of new observations and the checks use
//! the edge's own estimate ([`super::Edge::own`]): the conditioned edges share their faces'
//! errors, which those would count as independent; the edge's `point` and `direction`, which
//! plans, plots and other programs read, are the conditioned ones.

use super::{
    matrix, Edge, EdgeEstimate, Face, Tree, WithheldEdge, MATCH_ALPHA, SYSTEMATIC_DIRECTION_RAD,
    SYSTEMATIC_POINT_M,
};
use crate::stats::chi2_threshold;
use nalgebra::{Matrix3, Vector3};

/// A face as one measurement of an edge: its plane, its offset from the other demonstrations.
struct FacePlane {
    id: String,
    normal: Vector3<f64>,
    /// Variance \[rad²\] of the normal per axis.
    normal_var: f64,
    /// Offset \[m\] and the variance \[m²\] of its own part (without the common one).
    offset: Option<(f64, f64)>,
}

impl FacePlane {
    fn of(face: &Face, demos: &[String]) -> Self {
        let f = face.without_offsets_of(demos);
        let own_var = |s: f64| (s * s - f.offset_common_var()).max(0.0);
        Self {
            id: f.id.clone(),
            normal: f.normal,
            normal_var: f.sigma_normal_rad.powi(2),
            offset: f.offset.zip(f.offset_sigma_m.map(own_var)),
        }
    }
}

/// One scalar measurement `g · x = value` of a vector with covariance `cov`, of variance
/// `var`: its χ² and the Kalman update.
struct Measurement {
    g: Vector3<f64>,
    value: f64,
    var: f64,
}

impl Measurement {
    fn innovation(&self, x: &Vector3<f64>, cov: &Matrix3<f64>) -> (f64, f64) {
        (
            self.value - self.g.dot(x),
            self.g.dot(&(cov * self.g)) + self.var,
        )
    }

    /// χ² of the measurement against `x` of covariance `cov`, with `extra` \[unit²\] of
    /// systematic error.
    fn chi2(&self, x: &Vector3<f64>, cov: &Matrix3<f64>, extra: f64) -> f64 {
        let (r, s) = self.innovation(x, cov);
        r * r / (s + extra)
    }

    fn update(&self, x: &mut Vector3<f64>, cov: &mut Matrix3<f64>) {
        let (r, s) = self.innovation(x, cov);
        if s.is_nan() || s <= 0.0 {
            return;
        }
        let k = *cov * self.g / s;
        *x += k * r;
        let c = *cov - k * (cov.transpose() * self.g).transpose();
        *cov = (c + c.transpose()) * 0.5;
    }
}

/// The edge's measurements from the plane: its direction along it, its point on it (the
/// normal's error moves the plane at the point by its lever, the point's part along the face).
fn measurements(own: &EdgeEstimate, plane: &FacePlane) -> (Measurement, Option<Measurement>) {
    let n = plane.normal;
    let direction = Measurement {
        g: n,
        value: 0.0,
        var: plane.normal_var,
    };
    let point = plane.offset.map(|(d, var)| {
        let lever = (own.point - n * n.dot(&own.point)).norm_squared();
        Measurement {
            g: n,
            value: d,
            var: var + plane.normal_var * lever,
        }
    });
    (direction, point)
}

/// The edge's own estimate, with its point's covariance less the part common to every edge.
struct OwnEdge {
    estimate: EdgeEstimate,
    point_cov: Matrix3<f64>,
    direction_cov: Matrix3<f64>,
}

impl OwnEdge {
    fn of(e: &Edge) -> Self {
        let estimate = e.own();
        let point_cov = matrix(&estimate.point_cov) - e.common_point_cov();
        let direction_cov = matrix(&estimate.direction_cov);
        Self {
            estimate,
            point_cov,
            direction_cov,
        }
    }

    /// The plane's measurements of the edge, and whether it contradicts the edge: χ² of the
    /// direction along the plane and, where its offset is known, the point on it, above the
    /// threshold at [`MATCH_ALPHA`] (a NaN χ² fails too); with the χ² and its threshold.
    fn against(&self, plane: &FacePlane) -> (Measurement, Option<Measurement>, Verdict) {
        let own = &self.estimate;
        let (dir, pt) = measurements(own, plane);
        let chi2 = dir.chi2(
            &own.direction,
            &self.direction_cov,
            SYSTEMATIC_DIRECTION_RAD.powi(2),
        ) + pt.as_ref().map_or(0.0, |p| {
            p.chi2(&own.point, &self.point_cov, SYSTEMATIC_POINT_M.powi(2))
        });
        let dof = 1.0 + f64::from(u8::from(pt.is_some()));
        let limit = chi2_threshold(dof, MATCH_ALPHA);
        let verdict = Verdict {
            contradicts: chi2.is_nan() || chi2 > limit,
            chi2,
            limit,
        };
        (dir, pt, verdict)
    }
}

/// Whether a face's plane contradicts an edge, with the χ² and its threshold.
struct Verdict {
    contradicts: bool,
    chi2: f64,
    limit: f64,
}

/// The edge conditioned on the planes it lies in, and the ids of those used (see the module
/// documentation); `None` where none is used.
fn conditioned(e: &Edge, planes: &[FacePlane]) -> Option<(EdgeEstimate, Vec<String>)> {
    let own_edge = OwnEdge::of(e);
    let own = &own_edge.estimate;
    let common = e.common_point_cov();
    let mut used = Vec::new();
    let (mut point, mut point_cov) = (own.point, own_edge.point_cov);
    let (mut direction, mut direction_cov) = (own.direction, own_edge.direction_cov);
    for plane in planes {
        let (dir, pt, verdict) = own_edge.against(plane);
        if verdict.contradicts {
            continue;
        }
        dir.update(&mut direction, &mut direction_cov);
        if let Some(p) = pt {
            p.update(&mut point, &mut point_cov);
        }
        used.push(plane.id.clone());
    }
    if used.is_empty() {
        return None;
    }
    let u = direction.normalize();
    let across = Matrix3::identity() - u * u.transpose();
    let point_cov = across * (point_cov + common) * across;
    let direction_cov = across * direction_cov * across;
    let rows = super::rows;
    Some((
        EdgeEstimate {
            point: point - u * u.dot(&point),
            direction: u,
            point_cov: rows(&point_cov),
            direction_cov: rows(&direction_cov),
            sigma_point_m: (point_cov.trace() / 2.0).max(0.0).sqrt(),
            sigma_direction_rad: (direction_cov.trace() / 2.0).max(0.0).sqrt(),
        },
        used,
    ))
}

impl Tree {
    /// Withhold every edge that a face it joins contradicts, as the rests and the other
    /// demonstrations measure that face (the test [`Tree::condition_edges_on_faces`] leaves such
    /// a face out with; see the module documentation): whether any was withheld.
    ///
    /// An object turned about one of its edges rested before (and after) on a face that holds
    /// that edge. A fixed line of rotation out of such a face beyond the uncertainties and the
    /// systematic errors was no edge of it (a box pushed off its middle may pivot on a corner,
    /// or twist as it tips), or the face is not what the other demonstrations measure: the
    /// tree's checks reported it and kept the edge. Now the edge is withheld with the faces its
    /// topples taught ([`WithheldEdge`], as an edge off the landings' faces is) until the
    /// demonstrations change.
    pub(super) fn withhold_edges_out_of_their_faces(&mut self) -> bool {
        let mut out: Vec<(usize, String)> = Vec::new();
        for (i, e) in self.edges.iter().enumerate() {
            let own = OwnEdge::of(e);
            let off: Vec<String> = e
                .faces
                .iter()
                .filter_map(|id| self.faces.iter().find(|f| &f.id == id))
                .map(|f| FacePlane::of(f, &e.support))
                .filter_map(|plane| {
                    let (_, _, v) = own.against(&plane);
                    v.contradicts.then(|| {
                        let n = plane.normal;
                        let u = own.estimate.direction;
                        let along = match plane.offset {
                            Some((d, _)) => {
                                format!(
                                    ", {:.1} mm from it",
                                    (n.dot(&own.estimate.point) - d).abs() * 1e3
                                )
                            }
                            None => String::new(),
                        };
                        format!(
                            "{:.1}° out of face {}'s plane{along} (χ² {:.1} > {:.1})",
                            n.dot(&u).clamp(-1.0, 1.0).asin().abs().to_degrees(),
                            plane.id,
                            v.chi2,
                            v.limit
                        )
                    })
                })
                .collect();
            if !off.is_empty() {
                out.push((
                    i,
                    format!(
                        "edge {} is not in the faces it rested on, as the rests and the other \
                         demonstrations measure them: {}; a line of rotation out of the face \
                         the object stood on is no edge of it (a corner pivot, a twist); withheld",
                        e.id,
                        off.join(", ")
                    ),
                ));
            }
        }
        let mut faces_taken = false;
        for (i, why) in out.iter().rev() {
            let edge = self.edges.remove(*i);
            let faces = self.take_topple_faces(&edge);
            faces_taken |= !faces.is_empty();
            self.withheld_edges.push(WithheldEdge {
                edge,
                why: why.clone(),
                faces,
                unlocated: false,
            });
        }
        if faces_taken {
            self.prune_faces();
        }
        !out.is_empty()
    }

    /// Condition every edge on the planes of the faces it joins (see the module
    /// documentation). The edges must hold their own estimates ([`Edge::refit`]).
    pub(super) fn condition_edges_on_faces(&mut self) {
        let faces = &self.faces;
        for e in &mut self.edges {
            let planes: Vec<FacePlane> = e
                .faces
                .iter()
                .filter_map(|id| faces.iter().find(|f| &f.id == id))
                .map(|f| FacePlane::of(f, &e.support))
                .collect();
            if let Some((estimate, used)) = conditioned(e, &planes) {
                e.observed = Some(e.own());
                e.point = estimate.point;
                e.direction = estimate.direction;
                e.point_cov = estimate.point_cov;
                e.direction_cov = estimate.direction_cov;
                e.sigma_point_m = estimate.sigma_point_m;
                e.sigma_direction_rad = estimate.sigma_direction_rad;
                e.conditioned_on = used;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::edge::EdgeObservation;
    use crate::geometry::Line;
    use rand::{rngs::StdRng, Rng, SeedableRng};
    use rand_distr::StandardNormal;

    /// The true edge: along z through (50, 30) mm, where the faces x = 50 mm and y = 30 mm meet.
    const X: f64 = 0.05;
    const Y: f64 = 0.03;

    fn across(u: &Vector3<f64>) -> Matrix3<f64> {
        Matrix3::identity() - u * u.transpose()
    }

    /// An edge observed at `point` along `direction`, σ `sp` \[m\] and `sd` \[rad\] per axis,
    /// with a common part of σ `sc` \[m\] per axis.
    fn edge(point: Vector3<f64>, direction: Vector3<f64>, sp: f64, sd: f64, sc: f64) -> Edge {
        let u = direction.normalize();
        let n = across(&u);
        let o = EdgeObservation {
            demo: "own".into(),
            line: Line {
                point: point - u * u.dot(&point),
                direction: u,
            },
            point_cov: n * (sp * sp + sc * sc),
            direction_cov: n * sd * sd,
            paper_line: None,
            frames: 10,
            max_angle: 1.5,
            chi2_per_dof: 1.0,
            common_point_cov: n * sc * sc,
        };
        Edge::new("e0".into(), o)
    }

    fn plane(id: &str, normal: Vector3<f64>, offset: f64, sd: f64, sn: f64) -> FacePlane {
        FacePlane {
            id: id.into(),
            normal: normal.normalize(),
            normal_var: sn * sn,
            offset: Some((offset, sd * sd)),
        }
    }

    fn gauss(rng: &mut StdRng) -> f64 {
        rng.sample(StandardNormal)
    }

    /// A vector normal to `n` with independent N(0, σ²) components on its two axes.
    fn tangent(rng: &mut StdRng, n: &Vector3<f64>, sigma: f64) -> Vector3<f64> {
        let [a, b] = crate::geometry::normal_axes(n);
        (a * gauss(rng) + b * gauss(rng)) * sigma
    }

    /// Squared Mahalanobis distance of `x` from `mean` in the plane normal to `u`.
    fn mahalanobis2(
        x: &Vector3<f64>,
        mean: &Vector3<f64>,
        cov: &[[f64; 3]; 3],
        u: &Vector3<f64>,
    ) -> f64 {
        let across = nalgebra::Matrix3x2::from_columns(&crate::geometry::normal_axes(u));
        let r = across.transpose() * (x - mean);
        let s = across.transpose() * matrix(cov) * across;
        r.dot(&(s.try_inverse().unwrap() * r))
    }

    /// Exact faces put the edge on their line, whatever its own error.
    #[test]
    fn exact_faces_put_the_edge_where_they_meet() {
        let e = edge(
            Vector3::new(X + 0.006, Y - 0.004, 0.0),
            Vector3::new(0.05, -0.03, 1.0),
            0.004,
            0.04,
            0.0,
        );
        let planes = [
            plane("fx", Vector3::x(), X, 1e-7, 1e-7),
            plane("fy", Vector3::y(), Y, 1e-7, 1e-7),
        ];
        let (c, used) = conditioned(&e, &planes).expect("both faces agree with the edge");
        assert_eq!(used, ["fx", "fy"]);
        assert!(
            (c.point - Vector3::new(X, Y, 0.0)).norm() < 1e-5,
            "{}",
            c.point
        );
        assert!(
            c.direction.cross(&Vector3::z()).norm() < 1e-5,
            "{}",
            c.direction
        );
        assert!(c.sigma_point_m < 1e-5 && c.sigma_direction_rad < 1e-5);
    }

    /// A face the edge's own estimate contradicts is not used, and without any the edge keeps
    /// its own estimate.
    #[test]
    fn a_contradicting_face_is_not_used() {
        let e = edge(Vector3::new(X, Y, 0.0), Vector3::z(), 0.001, 0.01, 0.0);
        let far = plane("far", Vector3::x(), X + 0.03, 3e-4, 0.01);
        assert!(conditioned(&e, &[far]).is_none());
        let near = plane("near", Vector3::y(), Y, 3e-4, 0.01);
        let far = plane("far", Vector3::x(), X + 0.03, 3e-4, 0.01);
        let (_, used) = conditioned(&e, &[far, near]).unwrap();
        assert_eq!(used, ["near"]);
    }

    /// A face measured well, which the edge leaves by less than the systematic error the
    /// tree allows a demonstration's edge (2°) but by several of its own σ, is used, and puts
    /// the edge in its plane: a box pivoted on a corner about a line 3.7° out of the face it
    /// stood on (Drake) left the tree's edge 3.7° off while this face was left out.
    #[test]
    fn a_face_within_the_systematic_errors_puts_the_edge_in_its_plane() {
        let tilt = 1.5_f64.to_radians();
        let u = Vector3::new(0.0, tilt.sin(), tilt.cos());
        let e = edge(Vector3::new(X, Y, 0.0), u, 0.001, 0.2_f64.to_radians(), 0.0);
        let face = plane("fy", Vector3::y(), Y, 3e-4, 0.1_f64.to_radians());
        let (c, used) = conditioned(&e, &[face]).expect("within the systematic errors");
        assert_eq!(used, ["fy"]);
        // The weighted update: 1.5° × 0.1² / (0.2² + 0.1²) = 0.3° left out of the face.
        let out = c.direction.dot(&Vector3::y()).asin().abs().to_degrees();
        assert!((out - 0.3).abs() < 0.01, "{out}° out of the face");
    }

    /// An edge that a face it rested on, as the other demonstrations measure it, contradicts
    /// beyond the uncertainties and the systematic errors is withheld, with the face's numbers
    /// in the reason and the faces its topple taught held back with it; the face stays. An edge
    /// in its face stays.
    #[test]
    fn an_edge_out_of_the_face_it_rested_on_is_withheld() {
        use crate::face::{FaceObservation, FaceSource};
        let mut tree = Tree::default();
        // The face y = Y, from two slides of other demonstrations (normal to 0.1° each).
        let face = |demo: &str| {
            let mut o = FaceObservation::from_gravity(&Vector3::y(), demo, 100);
            o.source = FaceSource::Slide;
            o.normal_cov = across(&Vector3::y()) * 0.1_f64.to_radians().powi(2);
            o.offset = Some(Y);
            o.offset_var = Some(1e-8);
            o
        };
        tree.faces.push(Face::new("f0".into(), face("slide 1")));
        tree.faces[0].observations.push(face("slide 2"));
        tree.faces[0].refit();
        let tilted = |deg: f64| {
            let t = deg.to_radians();
            Vector3::new(0.0, t.sin(), t.cos())
        };
        // 12° out of it at σ 0.3°: beyond the 2° of systematic error too.
        for (id, deg) in [("e0", 0.5), ("e1", 12.0)] {
            let mut e = edge(
                Vector3::new(X, Y, 0.0),
                tilted(deg),
                5e-4,
                0.3_f64.to_radians(),
                0.0,
            );
            e.id = id.into();
            e.observations[0].demo = format!("topple {id}");
            e.refit();
            e.faces.push("f0".into());
            tree.edges.push(e);
        }
        assert!(tree.withhold_edges_out_of_their_faces());
        let kept: Vec<&str> = tree.edges.iter().map(|e| e.id.as_str()).collect();
        assert_eq!(kept, ["e0"]);
        let w = &tree.withheld_edges[0];
        assert_eq!(w.edge.id, "e1");
        assert!(w.why.contains("12.0° out of face f0's plane"), "{}", w.why);
        assert_eq!(tree.faces.len(), 1);
        assert!(!tree.withhold_edges_out_of_their_faces());
    }

    /// A topple's own rests are measurements of the faces it joins: an edge 5° off (a fast
    /// topple seen in three frames, σ 1.8°) between two rests that show their faces exactly is
    /// put near their line, and its σ covers what is left. (With the resting faces made normal
    /// to the edge, the face it landed on tilted 5° with it, and the edge stayed 5° off.)
    #[test]
    fn an_edge_is_put_right_by_its_own_rests() {
        use crate::face::FaceObservation;
        let truth = Vector3::z();
        let off = 5f64.to_radians();
        let u = Vector3::new(off.sin() * 0.6, off.sin() * 0.8, off.cos());
        let o = edge(Vector3::new(X, Y, 0.0), u, 0.001, 1.8f64.to_radians(), 0.0).observations[0]
            .clone();
        let mut tree = Tree::default();
        let eid = tree.add_edge(o.clone());
        for down in [Vector3::x(), Vector3::y()] {
            let fid = tree.add_face(FaceObservation::from_rest(&down, &o));
            tree.edges[0].faces.push(fid);
        }
        tree.refit_whole();
        let e = tree.edges.iter().find(|e| e.id == eid).expect("kept");
        assert_eq!(e.conditioned_on.len(), 2, "{:?}", e.conditioned_on);
        let err = e.direction.cross(&truth).norm().asin();
        assert!(err < 1.5f64.to_radians(), "{}° off", err.to_degrees());
        let z2 = mahalanobis2(
            &(truth * e.direction.z.signum()),
            &e.direction,
            &e.direction_cov,
            &e.direction,
        );
        assert!(z2 < 9.0, "χ² {z2}");
        assert_eq!(tree.faces.len(), 2);
        for f in &tree.faces {
            let a = f.normal.dot(&truth).asin().abs().to_degrees();
            assert!(a < 0.01, "face {} {a}° off", f.id);
        }
    }

    /// The common part (the contact's depth) does not shrink: it is the edge's and the faces'
    /// alike, however well the faces are known.
    #[test]
    fn the_common_part_stays() {
        let sc = 0.001;
        let e = edge(Vector3::new(X, Y, 0.0), Vector3::z(), 0.003, 0.02, sc);
        let planes = [
            plane("fx", Vector3::x(), X, 1e-6, 1e-5),
            plane("fy", Vector3::y(), Y, 1e-6, 1e-5),
        ];
        let (c, _) = conditioned(&e, &planes).unwrap();
        let var_x = c.point_cov[0][0];
        assert!(
            (var_x - sc * sc).abs() < 0.05 * sc * sc,
            "{var_x} vs {}",
            sc * sc
        );
    }

    /// Against truth, over many draws: the edge's own error (3 mm, 2° per axis) and the
    /// faces' (0.5 mm, 0.5°), independent. The conditioned edge is closer to the truth than its
    /// own estimate, and its covariance says how close: its squared Mahalanobis errors average
    /// the two degrees of freedom, as χ²₂ does (and so does the direction's).
    #[test]
    fn the_conditioned_edge_is_nearer_and_its_sigma_honest() {
        let mut rng = StdRng::seed_from_u64(7);
        let (sp, sd, fo, fn_) = (0.003, 2f64.to_radians(), 5e-4, 0.5f64.to_radians());
        let truth = Vector3::new(X, Y, 0.0);
        let n = 2000;
        let (mut own_err, mut err, mut z2, mut z2_dir) = (0.0, 0.0, 0.0, 0.0);
        let mut used_both = 0;
        for _ in 0..n {
            let u = (Vector3::z() + tangent(&mut rng, &Vector3::z(), sd)).normalize();
            let p = truth + tangent(&mut rng, &Vector3::z(), sp);
            let e = edge(p, u, sp, sd, 0.0);
            let nx = (Vector3::x() + tangent(&mut rng, &Vector3::x(), fn_)).normalize();
            let ny = (Vector3::y() + tangent(&mut rng, &Vector3::y(), fn_)).normalize();
            // Each face's plane tilted about its point nearest the origin, as the model has it.
            let planes = [
                plane("fx", nx, X + fo * gauss(&mut rng), fo, fn_),
                plane("fy", ny, Y + fo * gauss(&mut rng), fo, fn_),
            ];
            let (c, used) = conditioned(&e, &planes).unwrap();
            used_both += usize::from(used.len() == 2);
            let on_line = |q: &Vector3<f64>, u: &Vector3<f64>| {
                let d = truth - q;
                (d - u * u.dot(&d)).norm()
            };
            own_err += on_line(&e.point, &e.direction);
            err += on_line(&c.point, &c.direction);
            // The truth's point on the conditioned line's normal plane.
            let t = truth - c.direction * c.direction.dot(&(truth - c.point));
            z2 += mahalanobis2(&t, &c.point, &c.point_cov, &c.direction);
            let true_u = Vector3::z() * c.direction.z.signum();
            z2_dir += mahalanobis2(&true_u, &c.direction, &c.direction_cov, &c.direction);
        }
        let nf = n as f64;
        assert!(used_both as f64 > 0.99 * nf, "{used_both}");
        assert!(
            err < 0.35 * own_err,
            "{} vs {} mm",
            err / nf * 1e3,
            own_err / nf * 1e3
        );
        assert!((z2 / nf - 2.0).abs() < 0.3, "point: mean χ² {}", z2 / nf);
        assert!(
            (z2_dir / nf - 2.0).abs() < 0.3,
            "direction: mean χ² {}",
            z2_dir / nf
        );
    }
}
