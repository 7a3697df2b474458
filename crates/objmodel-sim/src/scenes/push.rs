//! A kinematic fingertip that pushes a box along a straight horizontal line.
//!
//! A push is described in the box frame at the moment it starts: the finger moves along the
//! horizontal direction `e = Rz(δ) · s e_k` (box axis `k ∈ {x, y}`, sign `s`, small yaw error
//! `δ`) and meets the face with outward normal `-s e_k` at height `h` above the support and
//! lateral offset `l` along the other horizontal box axis from the face centre.

use super::Run;
use crate::spec::BoxSpec;
use crate::world::Body;
use crate::Result;
use nalgebra::{UnitQuaternion, Vector3};

/// Fingertip radius \[m\].
pub const FINGER_RADIUS: f64 = 0.006;
/// Fingertip friction (a smooth probe: it pushes along the face normal).
pub const FINGER_MU: f64 = 0.05;

/// How far past its balance a push turns the box before the finger lets go \[rad\]: 4°.
pub const TIP_PAST_BALANCE_RAD: f64 = 4.0 * (std::f64::consts::PI / 180.0);

/// The lowest push height \[m\] at which the finger still touches the pushed face of box axis
/// `axis` when the box has turned [`TIP_PAST_BALANCE_RAD`] past its balance angle
/// `φ = atan2(d, h_c)` (lever `d`, CoM height `h_c`): the face's bottom corner rises to
/// `w sin(φ + 4°)`, `w` the box's width along `axis`.
pub fn lowest_tipping_height(spec: &BoxSpec, axis: usize, d: f64, hc: f64) -> f64 {
    spec.dims[axis] * (d.atan2(hc) + TIP_PAST_BALANCE_RAD).sin() + FINGER_RADIUS + 0.003
}

/// A straight push.
#[derive(Debug, Clone, Copy)]
pub struct Push {
    /// Box axis pushed along (0 = x, 1 = y).
    pub axis: usize,
    /// Sign of the push along that axis.
    pub sign: f64,
    /// Height of the fingertip centre above the support \[m\].
    pub height: f64,
    /// Lateral offset from the face centre line \[m\].
    pub lateral: f64,
    /// Yaw error of the push direction \[rad\].
    pub yaw: f64,
    /// Finger speed \[m/s\].
    pub speed: f64,
}

/// The finger.
pub struct Finger {
    /// Its body.
    pub body: Body,
    /// Its current centre, world frame \[m\].
    pub pos: Vector3<f64>,
}

impl Push {
    /// World-frame start point (1.5 cm before the face) and unit direction of this push for the
    /// box's current pose in `run` (the support is the level table).
    pub fn line(&self, run: &Run, spec: &BoxSpec) -> (Vector3<f64>, Vector3<f64>) {
        self.line_up(run, spec, 2, 1.0)
    }

    /// [`Push::line`] for a box lying on any face: box axis `up` (0, 1, 2) with sign `up_sign`
    /// points up, `axis` is one of the two other (horizontal) axes, the lateral offset runs
    /// along the third, and the yaw error turns about `up`.
    pub fn line_up(
        &self,
        run: &Run,
        spec: &BoxSpec,
        up: usize,
        up_sign: f64,
    ) -> (Vector3<f64>, Vector3<f64>) {
        let s = run.samples.last().expect("a sample");
        let b = s.world_from_box;
        let h = spec.half_extents();
        let other = 3 - self.axis - up;
        let mut e_box = Vector3::zeros();
        e_box[self.axis] = self.sign;
        let mut up_axis = Vector3::zeros();
        up_axis[up] = up_sign;
        let e_box =
            UnitQuaternion::from_axis_angle(&nalgebra::Unit::new_unchecked(up_axis), self.yaw)
                * e_box;
        let mut contact = Vector3::zeros();
        contact[self.axis] = -self.sign * h[self.axis];
        contact[other] = self.lateral;
        // Express the direction and the contact point in the world, then fix the height above
        // the table, measured in the world (the box rests level).
        let mut e = b.rotation * e_box;
        e.z = 0.0;
        let e = e.normalize();
        let mut c = b * nalgebra::Point3::from(contact);
        c.z = self.height;
        (c.coords - e * (FINGER_RADIUS + 0.015), e)
    }
}

impl Finger {
    /// Add a finger at `pos`.
    pub fn new(run: &mut Run, pos: Vector3<f64>) -> Finger {
        let body = run.world.add_finger(FINGER_RADIUS, FINGER_MU, &pos);
        Finger { body, pos }
    }

    /// Move in a straight line to `target` at `speed` \[m/s\], stepping the world, until there or
    /// until `stop(run)` holds. Returns whether `stop` ended the move.
    pub fn move_to(
        &mut self,
        run: &mut Run,
        target: Vector3<f64>,
        speed: f64,
        mut stop: impl FnMut(&Run) -> bool,
    ) -> Result<bool> {
        let dt = run.world.dt;
        loop {
            let d = target - self.pos;
            let n = d.norm();
            if n < 1e-9 {
                return Ok(false);
            }
            let stepl = (speed * dt).min(n);
            self.pos += d * (stepl / n);
            let pose = nalgebra::Isometry3::translation(self.pos.x, self.pos.y, self.pos.z);
            run.world.set_kinematic(self.body, &pose);
            run.step()?;
            if stop(run) {
                return Ok(true);
            }
        }
    }

    /// Push toward `target` at `speed` until the box, resting on the face whose outward normal
    /// in the box frame is `down`, has turned [`TIP_PAST_BALANCE_RAD`] past its balance angle
    /// `phi` \[rad\]. Returns whether it did before the finger reached `target`.
    pub fn tip_over(
        &mut self,
        run: &mut Run,
        target: Vector3<f64>,
        speed: f64,
        down: &Vector3<f64>,
        phi: f64,
    ) -> Result<bool> {
        let stop_at = phi + TIP_PAST_BALANCE_RAD;
        self.move_to(run, target, speed, |r| r.tilt(down) > stop_at)
    }

    /// Push to `target` at `speed`, a slide of the box resting on the face whose outward normal
    /// in the box frame is `down`. Returns the largest tilt of that face on the way \[rad\].
    pub fn slide_to(
        &mut self,
        run: &mut Run,
        target: Vector3<f64>,
        speed: f64,
        down: &Vector3<f64>,
    ) -> Result<f64> {
        let mut max_tilt: f64 = 0.0;
        self.move_to(run, target, speed, |r| {
            max_tilt = max_tilt.max(r.tilt(down));
            false
        })?;
        Ok(max_tilt)
    }

    /// Pull back 3 cm against the push direction `e`, out of the box's way.
    pub fn withdraw(&mut self, run: &mut Run, e: &Vector3<f64>) -> Result<()> {
        let back = self.pos - e * 0.03;
        self.move_to(run, back, 0.1, |_| false)?;
        Ok(())
    }

    /// Jump the (out of contact) finger to `pos` over one step.
    pub fn teleport(&mut self, run: &mut Run, pos: Vector3<f64>) -> Result<()> {
        self.pos = pos;
        let pose = nalgebra::Isometry3::translation(pos.x, pos.y, pos.z);
        run.world.set_kinematic(self.body, &pose);
        run.step()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn four_degrees_past_balance_is_four_degrees() {
        assert_eq!(TIP_PAST_BALANCE_RAD, 4f64.to_radians());
    }

    #[test]
    fn the_lowest_tipping_height_is_where_the_turned_face_s_corner_is() {
        // A 10 x 10 x 20 cm box, CoM centred, tipping over an x edge: φ = atan(5 / 10).
        let spec = BoxSpec::new("tall", [0.1, 0.1, 0.2], 0.6);
        let (d, hc) = super::super::edge_lever(&spec, 0, 1.0);
        let phi = (0.05f64 / 0.1).atan();
        assert!((d.atan2(hc) - phi).abs() < 1e-15);
        // The pushed face's bottom corner, turned by φ + 4° about the far edge, is
        // w sin(φ + 4°) above the table; the finger's centre must be its radius and 3 mm above.
        let h = lowest_tipping_height(&spec, 0, d, hc);
        let corner = 0.1 * (phi + 4f64.to_radians()).sin();
        assert!(
            (h - corner - FINGER_RADIUS - 0.003).abs() < 1e-15,
            "{h} {corner}"
        );
    }
}
