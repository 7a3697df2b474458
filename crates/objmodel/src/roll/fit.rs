//! The fixed-line model fitted to a window of poses: a rotation about one line, fixed both in
//! the world and in the object (a roll over an edge), measured without a reference pose.
//!
//! In a roll the points of the edge do not move, and the edge keeps its direction:
//!
//! ```text
//! R_k c_o + p_k = c_w        R_k u_o = u_w        (world_from_object_k = (R_k, p_k))
//! ```
//!
//! for every frame k, with `c_o`, `u_o` a point and the direction of the edge in the object
//! frame and `c_w`, `u_w` the same in the world. Each frame gives five equations (three for the
//! point, two for the unit direction) and no unknown of its own (its angle about the line is
//! its pose's), so nothing is measured relative to a reference pose: any frame of the roll
//! relates to any other by `world_from_object_j · world_from_object_i⁻¹`, a rotation about
//! the line. The unknowns are 10 (two points, two unit directions) less one gauge (sliding
//! both points along the line), so `n` frames leave `5n − 9` degrees of freedom.
//!
//! Frame k's residual `(R_k c_o + p_k − c_w, Eᵀ R_k u_o)` (E a basis normal to `u_w`) has,
//! for a pose error `(δp, δφ)` of covariance `diag(σ_p² I, σ_r² I)`, the covariance
//! `A diag(σ_p² I, σ_r² I) Aᵀ` with `A = [[I, −[c]×], [0, −Eᵀ[u_w]×]]`, `c = R_k c_o` (the
//! lever arm of a rotation error), plus the contact's own tolerance (a rounded edge, a soft
//! contact, micro-slip: [`crate::classify::RobustConfig::edge_tolerance_m`] and `_rad`) in
//! quadrature. The model is linear in `(c_o, c_w)` and, to first order, in the directions'
//! tangent steps, so a few Gauss-Newton steps from the screw axis of the window's first and
//! last frames ([`crate::screw::Screw`]) solve it; the gauge is fixed by the pseudo-inverse
//! (the step and the covariance have no component along it). The parameters' covariance is
//! that pseudo-inverse, so the edge's covariance is the noise model's, propagated.

use crate::edge::EdgeObservation;
use crate::flight::FlightFrame;
use crate::geometry::Line;
use crate::noise::NoiseModel;
use crate::screw::Screw;
use crate::se3::Twist;
use nalgebra::{
    Isometry3, Matrix2, Matrix3, Rotation3, SMatrix, SVector, Translation3, UnitQuaternion,
    Vector2, Vector3,
};

type M10 = SMatrix<f64, 10, 10>;
type V10 = SVector<f64, 10>;
type M5 = SMatrix<f64, 5, 5>;
type V5 = SVector<f64, 5>;
type M5x10 = SMatrix<f64, 5, 10>;

/// The fit's parameters: a point and the direction of the line in the object, and the same
/// in the world (`c_o`, `u_o`, `c_w`, `u_w`).
type Params = (Vector3<f64>, Vector3<f64>, Vector3<f64>, Vector3<f64>);

/// Gauss-Newton steps of a fit (from the screw's start, two or three reach the minimum to
/// within rounding; the rest guard against a poor start).
const ITERATIONS: usize = 6;

/// A Gauss-Newton step smaller than this in every parameter (\[m\] or \[rad\]) ends the fit:
/// 0.1 µm and 0.1 µrad, far below the smallest noise the tests assume
/// ([`crate::noise::MIN_SIGMA_POSITION_M`], [`crate::noise::MIN_SIGMA_ROTATION_RAD`]).
const CONVERGED: f64 = 1e-7;

/// The per-frame noise and the contact's tolerance, as the fit uses them.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollNoise {
    /// Tracking noise.
    pub noise: NoiseModel,
    /// How far \[m\] the contact point may wander, per axis.
    pub tolerance_m: f64,
    /// How far \[rad\] the contact's direction may wander, per axis.
    pub tolerance_rad: f64,
}

/// A fixed-line model fitted to a window of frames.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RollFit {
    /// The line in the object frame (point closest to the object's origin).
    pub object_line: Line,
    /// The line in the world (point closest to the world's origin).
    pub world_line: Line,
    /// Covariance of the object line's point, normal to the line \[m²\].
    pub point_cov: Matrix3<f64>,
    /// Covariance of the object line's direction \[rad²\].
    pub direction_cov: Matrix3<f64>,
    /// Covariance of the world line's direction \[rad²\].
    pub world_direction_cov: Matrix3<f64>,
    /// Covariance of the world line's point, normal to the line \[m²\].
    pub world_point_cov: Matrix3<f64>,
    /// χ² of the residuals.
    pub chi2: f64,
    /// Its degrees of freedom, `5n − 9`.
    pub dof: f64,
    /// The range of the frames' angles about the line \[rad\] (largest minus smallest), signed
    /// by the right-hand rule about `world_line.direction` (so that the last frame turned
    /// positively from the first).
    pub turn: f64,
    /// Frames fitted.
    pub frames: usize,
    /// A point of the edge in the object frame and where the fit puts it in the world (the
    /// lines' points above are each the closest to their frame's origin, not one point).
    pub matched: (Vector3<f64>, Vector3<f64>),
}

impl RollFit {
    /// The fit as an edge observation of the demonstration `demo` (its direction the one
    /// the object turned about, positively, as a topple's edge is given).
    pub fn edge(&self, demo: &str) -> EdgeObservation {
        EdgeObservation {
            demo: demo.to_string(),
            line: self.object_line,
            point_cov: self.point_cov,
            direction_cov: self.direction_cov,
            paper_line: None,
            frames: self.frames as u64,
            max_angle: self.turn.abs(),
            chi2_per_dof: self.chi2 / self.dof.max(1.0),
            common_point_cov: nalgebra::Matrix3::zeros(),
        }
    }
}

/// Two unit vectors normal to `u` and to each other.
fn basis(u: &Vector3<f64>) -> (Vector3<f64>, Vector3<f64>) {
    let a = if u.x.abs() < 0.9 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = u.cross(&a).normalize();
    (e1, u.cross(&e1))
}

fn basis_matrix(u: &Vector3<f64>) -> SMatrix<f64, 3, 2> {
    let (e1, e2) = basis(u);
    SMatrix::<f64, 3, 2>::from_columns(&[e1, e2])
}

/// The pose of a frame as an isometry.
pub(super) fn pose(f: &FlightFrame) -> Isometry3<f64> {
    let r = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(f.rotation));
    Isometry3::from_parts(Translation3::from(f.position), r)
}

/// The start of a fit: the screw axis of the relative motion from the first frame to the
/// last, `world_from_object_last · world_from_object_first⁻¹`, mapped into the object by the
/// first frame. `None` when that motion has no rotation.
fn start(frames: &[FlightFrame]) -> Option<Params> {
    let (a, b) = (frames.first()?, frames.last()?);
    let rel = pose(b) * pose(a).inverse();
    let s = Screw::from_twist(&Twist::log(&rel)).filter(|s| s.is_rotation())?;
    let u_w = s.direction.into_inner();
    let c_w = s.point;
    let u_o = a.rotation.transpose() * u_w;
    let c_o = a.rotation.transpose() * (c_w - a.position);
    Some((c_o, u_o, c_w, u_w))
}

/// Frame k's residual, its Jacobian in `(δc_o, δc_w, a, b)` (the directions' tangent steps in
/// the bases `bo`, `bw`) and its weight (the inverse covariance).
fn frame_terms(
    f: &FlightFrame,
    x: (&Vector3<f64>, &Vector3<f64>, &Vector3<f64>, &Vector3<f64>),
    bo: &SMatrix<f64, 3, 2>,
    bw: &SMatrix<f64, 3, 2>,
    n: &RollNoise,
) -> Option<(V5, M5x10, M5)> {
    let (c_o, u_o, c_w, u_w) = x;
    let r = &f.rotation;
    let c = r * c_o;
    let rp = c + f.position - c_w;
    let rd = bw.transpose() * (r * u_o);
    let mut res = V5::zeros();
    res.fixed_rows_mut::<3>(0).copy_from(&rp);
    res.fixed_rows_mut::<2>(3).copy_from(&rd);
    let mut j = M5x10::zeros();
    j.fixed_view_mut::<3, 3>(0, 0).copy_from(r);
    j.fixed_view_mut::<3, 3>(0, 3)
        .copy_from(&(-Matrix3::identity()));
    j.fixed_view_mut::<2, 2>(3, 6)
        .copy_from(&(bw.transpose() * r * bo));
    j.fixed_view_mut::<2, 2>(3, 8)
        .copy_from(&(-Matrix2::identity()));
    // Covariance: A diag(σp² I, σr² I) Aᵀ plus the tolerances.
    let (sp2, sr2) = (
        n.noise.sigma_position.powi(2),
        n.noise.sigma_rotation.powi(2),
    );
    let cx = c.cross_matrix();
    let ux = u_w.cross_matrix();
    let mut cov = M5::zeros();
    let pos = Matrix3::identity() * (sp2 + n.tolerance_m.powi(2)) + cx * cx.transpose() * sr2;
    let cross = cx * ux.transpose() * bw * sr2;
    let dir = bw.transpose() * ux * ux.transpose() * bw * sr2
        + Matrix2::identity() * n.tolerance_rad.powi(2);
    cov.fixed_view_mut::<3, 3>(0, 0).copy_from(&pos);
    cov.fixed_view_mut::<3, 2>(0, 3).copy_from(&cross);
    cov.fixed_view_mut::<2, 3>(3, 0)
        .copy_from(&cross.transpose());
    cov.fixed_view_mut::<2, 2>(3, 3).copy_from(&dir);
    let w = cov.try_inverse()?;
    Some((res, j, w))
}

/// Fit the fixed-line model to `frames` (time order, at least 3). `None` when the window's
/// motion has no rotation or the fit is singular.
pub fn fit(frames: &[FlightFrame], n: &RollNoise) -> Option<RollFit> {
    if frames.len() < 3 {
        return None;
    }
    let (mut c_o, mut u_o, mut c_w, mut u_w) = start(frames)?;
    let mut cov = M10::zeros();
    let mut chi2 = f64::INFINITY;
    for it in 0..=ITERATIONS {
        let (bo, bw) = (basis_matrix(&u_o), basis_matrix(&u_w));
        let mut nm = M10::zeros();
        let mut g = V10::zeros();
        let mut c2 = 0.0;
        for f in frames {
            let (r, j, w) = frame_terms(f, (&c_o, &u_o, &c_w, &u_w), &bo, &bw, n)?;
            let jw = j.transpose() * w;
            nm += jw * j;
            g += jw * r;
            c2 += (r.transpose() * w * r)[0];
        }
        // The gauge (both points along the line) is the normal matrix's null space: the
        // pseudo-inverse leaves it out of the step and of the covariance.
        let inv = nm.pseudo_inverse(1e-12 * nm.norm()).ok()?;
        chi2 = c2;
        cov = inv;
        if it == ITERATIONS {
            break;
        }
        let step = -(inv * g);
        c_o += step.fixed_rows::<3>(0);
        c_w += step.fixed_rows::<3>(3);
        u_o = (u_o + bo * Vector2::new(step[6], step[7])).normalize();
        u_w = (u_w + bw * Vector2::new(step[8], step[9])).normalize();
        if step.amax() < CONVERGED {
            // One more pass at the minimum gives its χ² and covariance.
            let (bo, bw) = (basis_matrix(&u_o), basis_matrix(&u_w));
            let mut nm = M10::zeros();
            let mut c2 = 0.0;
            for f in frames {
                let (r, j, w) = frame_terms(f, (&c_o, &u_o, &c_w, &u_w), &bo, &bw, n)?;
                nm += j.transpose() * w * j;
                c2 += (r.transpose() * w * r)[0];
            }
            chi2 = c2;
            cov = nm.pseudo_inverse(1e-12 * nm.norm()).ok()?;
            return Some(finish(frames, (c_o, u_o, c_w, u_w), &cov, chi2, (bo, bw)));
        }
    }
    let (bo, bw) = (basis_matrix(&u_o), basis_matrix(&u_w));
    Some(finish(frames, (c_o, u_o, c_w, u_w), &cov, chi2, (bo, bw)))
}

/// The fit's result from its parameters and their covariance.
fn finish(
    frames: &[FlightFrame],
    (c_o, u_o, c_w, u_w): Params,
    cov: &M10,
    chi2: f64,
    (bo, bw): (SMatrix<f64, 3, 2>, SMatrix<f64, 3, 2>),
) -> RollFit {
    // The frames' angles about the line, from the first frame.
    let r0t = frames[0].rotation.transpose();
    let angles: Vec<f64> = frames
        .iter()
        .map(|f| {
            let q = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(
                f.rotation * r0t,
            ));
            crate::se3::so3_log(&q).dot(&u_w)
        })
        .collect();
    let (lo, hi) = angles
        .iter()
        .fold((0.0f64, 0.0f64), |(a, b), &x| (a.min(x), b.max(x)));
    let last = *angles.last().unwrap_or(&0.0);
    // The direction the object turned about, positively: flip the line if it turned back.
    let sign = if last >= 0.0 { 1.0 } else { -1.0 };
    let (u_o, u_w) = (u_o * sign, u_w * sign);
    // The object line's point closest to its origin, p* = c_o − u (u·c_o); its normal part
    // moves by P δc_o − (u·c_o) δu.
    let p_mat = Matrix3::identity() - u_o * u_o.transpose();
    let s = u_o.dot(&c_o);
    let mut jp = SMatrix::<f64, 3, 10>::zeros();
    jp.fixed_view_mut::<3, 3>(0, 0).copy_from(&p_mat);
    jp.fixed_view_mut::<3, 2>(0, 6).copy_from(&(-bo * s));
    let mut jd = SMatrix::<f64, 3, 10>::zeros();
    jd.fixed_view_mut::<3, 2>(0, 6).copy_from(&bo);
    let mut jw = SMatrix::<f64, 3, 10>::zeros();
    jw.fixed_view_mut::<3, 2>(0, 8).copy_from(&bw);
    // The world line's point closest to the world's origin, likewise.
    let pw_mat = Matrix3::identity() - u_w * u_w.transpose();
    let sw = u_w.dot(&c_w);
    let mut jwp = SMatrix::<f64, 3, 10>::zeros();
    jwp.fixed_view_mut::<3, 3>(0, 3).copy_from(&pw_mat);
    jwp.fixed_view_mut::<3, 2>(0, 8).copy_from(&(-bw * sw));
    RollFit {
        object_line: Line::through(c_o, u_o),
        world_line: Line::through(c_w, u_w),
        point_cov: jp * cov * jp.transpose(),
        direction_cov: jd * cov * jd.transpose(),
        world_direction_cov: jw * cov * jw.transpose(),
        world_point_cov: jwp * cov * jwp.transpose(),
        chi2,
        dof: 5.0 * frames.len() as f64 - 9.0,
        turn: sign * (hi - lo),
        frames: frames.len(),
        matched: (c_o, c_w),
    }
}

/// Frame `f`'s χ²₅ against a fit (its residual from the fitted lines, under its covariance):
/// how well the fit of the other frames explains it.
pub fn frame_chi2(fit: &RollFit, f: &FlightFrame, n: &RollNoise) -> f64 {
    let (c_o, c_w) = fit.matched;
    let (u_o, u_w) = (fit.object_line.direction, fit.world_line.direction);
    let (bo, bw) = (basis_matrix(&u_o), basis_matrix(&u_w));
    frame_terms(f, (&c_o, &u_o, &c_w, &u_w), &bo, &bw, n)
        .map_or(f64::INFINITY, |(r, _, w)| (r.transpose() * w * r)[0])
}

#[cfg(test)]
pub(crate) fn frames_about(
    line_point: Vector3<f64>,
    line_dir: Vector3<f64>,
    start: &Isometry3<f64>,
    angles: &[f64],
    dt: f64,
) -> Vec<FlightFrame> {
    angles
        .iter()
        .enumerate()
        .map(|(k, &a)| {
            let r = crate::se3::so3_exp(&(line_dir.normalize() * a));
            let about = Isometry3::from_parts(Translation3::from(line_point - r * line_point), r);
            let g = about * start;
            FlightFrame {
                t: k as f64 * dt,
                rotation: g.rotation.to_rotation_matrix().into_inner(),
                position: g.translation.vector,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn exact() -> RollNoise {
        RollNoise {
            noise: NoiseModel {
                sigma_position: 1e-4,
                sigma_rotation: 1e-3,
            },
            tolerance_m: 0.0,
            tolerance_rad: 0.0,
        }
    }

    /// A rotation about a known world line gives that line back, in the object frame and in
    /// the world, with χ² zero and the angle turned, whichever frame the window starts at.
    #[test]
    fn exact_rotation_gives_its_line() {
        let start = Isometry3::from_parts(
            Translation3::new(0.3, -0.1, 0.05),
            UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1),
        );
        let (q, u) = (
            Vector3::new(0.2, 0.1, 0.0),
            Vector3::new(1.0, 2.0, 0.0).normalize(),
        );
        let angles: Vec<f64> = (0..20).map(|k| 0.02 * k as f64).collect();
        let frames = frames_about(q, u, &start, &angles, 0.01);
        let f = fit(&frames, &exact()).unwrap();
        let truth_obj = Line::through(
            (start.inverse() * nalgebra::Point3::from(q)).coords,
            start.rotation.inverse() * u,
        );
        assert!(
            (f.object_line.direction - truth_obj.direction).norm() < 1e-9,
            "{f:?}"
        );
        assert!(
            (f.object_line.point - truth_obj.point).norm() < 1e-9,
            "{f:?}"
        );
        assert!((f.world_line.point - Line::through(q, u).point).norm() < 1e-9);
        assert!(f.chi2 < 1e-12, "{}", f.chi2);
        assert_eq!(f.dof, 91.0);
        assert!((f.turn - 0.38).abs() < 1e-9);
    }
}
