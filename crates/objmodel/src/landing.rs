//! Landings: the rests an object comes to after a free flight (a toss), and the face each
//! teaches once another landing confirms it.
//!
//! With gravity known, the face an object rests on on a support faces down
//! ([`FaceObservation::from_gravity`]). But a rest alone could be the object held still in a
//! hand, facing down anything; so a rest teaches its face only when a contact mode shows the
//! support (a slide or a topple leaves it or reaches it). A toss rarely shows one: it flies,
//! bounces and settles, and its last slide is too short to pass its test. Its final rest is
//! then a *landing*: a rest reached, in the same motion segment, after a flight (free fall:
//! nothing held the object then, [`crate::flight`]).
//!
//! A landing is still not proof of a support (a hand may catch the object), so it teaches its
//! face only when a landing of another demonstration agrees with it, in the object frame's
//! down *and* in the place: the same height above the poses' origin, where both rested.
//! An object resting on a flat support on one face comes to the same down and the same height
//! whatever the toss; a held object matches another held one in both only by chance (within a
//! few degrees and a few millimetres), and a polyhedron's faces differ by tens of degrees.
//! The test is a χ² (3 dof) of the difference, with the noise of both rests, the support's tilt
//! ([`crate::face::SUPPORT_LEVEL_SIGMA_RAD`] for each down, and across the distance between the
//! two places for the height) and its flatness ([`SUPPORT_FLATNESS_M`] for each height).
//!
//! A face is also a *discrete* rest: an object resting on a curved side (a cylinder, a bottle)
//! comes to rest at one height with any down along a circle, and two such rests may agree by
//! chance. So a landing teaches nothing while another landing at its height (χ²₁) has a down
//! that differs from its own (χ²₂) by less than [`crate::tree::SAME_FACE_RAD`] (20°, far less
//! than a polyhedron's faces differ by): its rests form a continuum, not a face.
//!
//! The tree keeps every landing ([`crate::tree::Tree::landings`]) and decides again over all
//! of them whenever one comes or goes, so that a later demonstration can confirm an earlier
//! one (or show it was on a curved side), whatever the order.

use crate::face::{FaceObservation, FaceSource, SUPPORT_LEVEL_SIGMA_RAD};
use crate::noise::NoiseModel;
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// Assumed standard deviation \[m\] of a support's height from a plane, between two places
/// (tables and floors are flat to about a millimetre).
pub const SUPPORT_FLATNESS_M: f64 = 1e-3;

pub use crate::rest_place::RestPlace;

/// A rest reached after a free flight, with what the face test needs.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Landing {
    /// The demonstration.
    pub demo: String,
    /// Down (unit) in the object frame over the rest: the outward normal of the face it rests
    /// on, if it rests on a support.
    pub down: Vector3<f64>,
    /// Standard deviation \[rad\] per axis of `down` from the tracking noise alone.
    pub sigma_down_rad: f64,
    /// Where it rested.
    pub place: RestPlace,
    /// Standard deviation \[m\] of the height from the tracking noise alone.
    pub sigma_height_m: f64,
    /// Frames of the rest.
    pub frames: u64,
    /// Whether a landing of another demonstration agrees with it: then it taught its face.
    #[serde(default)]
    pub confirmed: bool,
}

impl Landing {
    /// The landing of a rest of `frames` frames with `down` at `place`, under `noise`.
    pub fn new(
        demo: &str,
        down: &Vector3<f64>,
        place: RestPlace,
        frames: u64,
        noise: &NoiseModel,
    ) -> Self {
        let n = (frames.max(1)) as f64;
        Self {
            demo: demo.to_string(),
            down: down.normalize(),
            sigma_down_rad: noise.sigma_rotation / n.sqrt(),
            place,
            sigma_height_m: noise.sigma_position / n.sqrt(),
            frames,
            confirmed: false,
        }
    }

    /// χ² (3 dof) of the difference between two landings: their downs (2 dof,
    /// [`Landing::chi2_down`]) and their heights (1 dof, [`Landing::chi2_height`]), as the
    /// module documentation says.
    pub fn chi2(&self, other: &Landing) -> f64 {
        self.chi2_down(other) + self.chi2_height(other)
    }

    /// χ² (2 dof) of the difference between two landings' downs.
    pub fn chi2_down(&self, other: &Landing) -> f64 {
        let level = SUPPORT_LEVEL_SIGMA_RAD * SUPPORT_LEVEL_SIGMA_RAD;
        let var = self.sigma_down_rad.powi(2) + other.sigma_down_rad.powi(2) + 2.0 * level;
        self.angle_to(other).powi(2) / var
    }

    /// χ² (1 dof) of the difference between two landings' heights.
    pub fn chi2_height(&self, other: &Landing) -> f64 {
        let level = SUPPORT_LEVEL_SIGMA_RAD * SUPPORT_LEVEL_SIGMA_RAD;
        let apart = (self.place.across - other.place.across).norm();
        let var = self.sigma_height_m.powi(2)
            + other.sigma_height_m.powi(2)
            + 2.0 * SUPPORT_FLATNESS_M * SUPPORT_FLATNESS_M
            + level * apart * apart;
        (self.place.height - other.place.height).powi(2) / var
    }

    /// The angle \[rad\] between two landings' downs.
    pub fn angle_to(&self, other: &Landing) -> f64 {
        self.down
            .cross(&other.down)
            .norm()
            .atan2(self.down.dot(&other.down))
    }

    /// The face it teaches once confirmed: the face rested on, from gravity.
    pub fn face(&self) -> FaceObservation {
        FaceObservation {
            source: FaceSource::Landing,
            ..FaceObservation::from_gravity(&self.down, &self.demo, self.frames)
        }
    }

    /// Whether `o` is the face observation this landing taught ([`Landing::face`]).
    pub fn taught(&self, o: &FaceObservation) -> bool {
        // The fields `face` sets, compared without building the observation (its normal is
        // `from_gravity`'s, `down` normalised).
        o.source == FaceSource::Landing
            && o.demo == self.demo
            && o.frames == self.frames
            && o.normal == self.down.normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stats::chi2_threshold;
    use nalgebra::{Rotation3, Unit};
    use rand::{Rng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    /// A place's position is the one it was made from, for any down.
    #[test]
    fn a_place_gives_back_its_position() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        for _ in 0..100 {
            let v = |rng: &mut rand::rngs::StdRng| {
                Vector3::new(
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                    rng.random_range(-1.0..1.0),
                )
            };
            let (x, down) = (v(&mut rng), v(&mut rng).normalize());
            let place = RestPlace::new(&x, &down);
            assert!((place.position(&down) - x).norm() < 1e-12, "{x} {down}");
        }
    }

    fn noise() -> NoiseModel {
        NoiseModel {
            sigma_position: 1e-3,
            sigma_rotation: 0.5f64.to_radians(),
        }
    }

    /// A landing on the face with outward normal `down`, at `height` and `across`, its down
    /// and height disturbed as the model says (noise over 20 frames, a support tilted by
    /// `tilt` about a random horizontal axis, its flatness).
    fn landing(
        rng: &mut rand::rngs::StdRng,
        down: Vector3<f64>,
        height: f64,
        across: Vector3<f64>,
        tilt: f64,
    ) -> Landing {
        let frames = 20;
        let noise = noise();
        let unit = Normal::new(0.0, 1.0).unwrap();
        let axis = Unit::new_normalize(Vector3::new(unit.sample(rng), unit.sample(rng), 0.0));
        let noisy = Rotation3::from_axis_angle(&axis, tilt)
            * Rotation3::new(
                Vector3::new(unit.sample(rng), unit.sample(rng), unit.sample(rng))
                    * noise.sigma_rotation
                    / (frames as f64).sqrt(),
            );
        let h = height
            + unit.sample(rng) * SUPPORT_FLATNESS_M
            + unit.sample(rng) * noise.sigma_position / (frames as f64).sqrt();
        let place = RestPlace { height: h, across };
        Landing::new("d", &(noisy * down), place, frames, &noise)
    }

    #[test]
    fn a_place_splits_a_position_along_and_across_gravity() {
        let down = Vector3::new(0.0, 0.6, -0.8);
        let p = Vector3::new(1.0, 2.0, 3.0);
        let place = RestPlace::new(&p, &down);
        assert!((place.height - (-(1.2 - 2.4))).abs() < 1e-12);
        assert!(place.across.dot(&down).abs() < 1e-12);
        assert!((place.across - down * place.height - p).norm() < 1e-12);
    }

    #[test]
    fn rests_on_one_face_agree_and_other_faces_or_heights_do_not() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(7);
        let gate = chi2_threshold(3.0, 1e-4);
        let face = Vector3::new(0.0, 0.0, -1.0);
        let (mut agree, trials) = (0, 2000);
        for _ in 0..trials {
            let tilt = rng.random::<f64>() * SUPPORT_LEVEL_SIGMA_RAD;
            let x = Vector3::new(rng.random::<f64>() * 0.2, rng.random::<f64>() * 0.2, 0.0);
            let y = Vector3::new(rng.random::<f64>() * 0.2, rng.random::<f64>() * 0.2, 0.0);
            let a = landing(&mut rng, face, 0.05, x, tilt);
            let b = landing(&mut rng, face, 0.05, y, tilt);
            agree += usize::from(a.chi2(&b) < gate);
            // A face 20 degrees away, or the same down 30 mm higher (a hand, at most 0.28 m
            // away), never agrees.
            let turned = Rotation3::from_axis_angle(&Vector3::x_axis(), 0.35) * face;
            let c = landing(&mut rng, turned, 0.05, y, tilt);
            assert!(a.chi2(&c) > gate, "{}", a.chi2(&c));
            let d = landing(&mut rng, face, 0.08, y, tilt);
            assert!(a.chi2(&d) > gate, "{}", a.chi2(&d));
        }
        // At the test's level, nearly all true pairs agree.
        assert!(agree as f64 >= 0.999 * trials as f64, "{agree} of {trials}");
    }

    #[test]
    fn a_confirmed_landing_teaches_its_down_as_an_outward_normal() {
        let l = Landing::new(
            "toss",
            &Vector3::new(0.0, 0.0, -2.0),
            RestPlace::new(&Vector3::zeros(), &Vector3::new(0.0, 0.0, -1.0)),
            12,
            &noise(),
        );
        let f = l.face();
        assert_eq!(f.source, FaceSource::Landing);
        assert!(f.sign_known);
        assert!((f.normal - Vector3::new(0.0, 0.0, -1.0)).norm() < 1e-12);
        assert_eq!(f.demo, "toss");
    }
}
