//! Tracking noise: what a fiducial tracker adds to the true tag poses.
//!
//! For each frame, independently:
//! * with probability `drop_prob` the frame is lost (not written);
//! * position: `p' = p + ε`, `ε ~ N(0, σ_p² I)` per world axis;
//! * orientation: `R' = R · exp([δ]×)`, `δ ~ N(0, σ_r² I)` per tag axis;
//! * with probability `mirror_prob` the planar-tag pose ambiguity strikes: the tag normal
//!   `n = R e_z` is reflected about the camera's line of sight `l` (unit, camera to tag),
//!   `n' = 2 (n·l) l − n`, and the orientation becomes `R' = Rot(n → n') · R`; the jump is
//!   `2 ∠(n, ±l)`, tens of degrees for a tag seen obliquely;
//! * with probability `sign_flip_prob` the quaternion is written as `−q` (the same rotation).

use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion, Vector3};
use objmodel::noise::NoiseModel;
use objmodel::StampedPose;
use rand::rngs::StdRng;
use rand::Rng;
use rand_distr::{Distribution, Normal};
use serde::{Deserialize, Serialize};

/// A simulated tracker's noise: the Gaussian noise of each pose (the library's
/// [`NoiseModel`], which the learner estimates from the data), and the tracker's failures.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct TrackerNoise {
    /// Preset name ("clean", "real", "noisy") or "custom".
    pub name: String,
    /// Position and orientation noise, standard deviations per axis.
    #[serde(flatten)]
    pub sigma: NoiseModel,
    /// Probability that a frame is dropped.
    pub drop_prob: f64,
    /// Probability that a frame's quaternion is written with the opposite sign.
    pub sign_flip_prob: f64,
    /// Probability that a frame shows the planar-tag mirror ambiguity.
    pub mirror_prob: f64,
    /// Camera position in the world \[m\] (it looks at the scene; only its position matters).
    pub camera: [f64; 3],
}

/// Largest viewing angle `α` at which a mirror flip can happen \[rad\] (50°).
pub const MIRROR_MAX_VIEW: f64 = 0.8727;

/// Default camera position: 70 cm in front of the scene and 45 cm up.
pub const DEFAULT_CAMERA: [f64; 3] = [0.0, -0.7, 0.45];

impl TrackerNoise {
    /// Exact poses.
    pub fn clean() -> TrackerNoise {
        TrackerNoise {
            name: "clean".into(),
            sigma: NoiseModel {
                sigma_position: 0.0,
                sigma_rotation: 0.0,
            },
            drop_prob: 0.0,
            sign_flip_prob: 0.0,
            mirror_prob: 0.0,
            camera: DEFAULT_CAMERA,
        }
    }

    /// A good fiducial tracker: 1 mm and 0.5° per axis, 3% dropped frames, 5% sign flips, 1%
    /// mirror flips.
    pub fn real() -> TrackerNoise {
        TrackerNoise {
            name: "real".into(),
            sigma: NoiseModel {
                sigma_position: 0.001,
                sigma_rotation: 0.5f64.to_radians(),
            },
            drop_prob: 0.03,
            sign_flip_prob: 0.05,
            mirror_prob: 0.01,
            camera: DEFAULT_CAMERA,
        }
    }

    /// A poor one: 2 mm and 1° per axis, 8% dropped frames, 15% sign flips, 3% mirror flips.
    pub fn noisy() -> TrackerNoise {
        TrackerNoise {
            name: "noisy".into(),
            sigma: NoiseModel {
                sigma_position: 0.002,
                sigma_rotation: 1f64.to_radians(),
            },
            drop_prob: 0.08,
            sign_flip_prob: 0.15,
            mirror_prob: 0.03,
            camera: DEFAULT_CAMERA,
        }
    }

    /// A marker-based motion-capture system (tracked at 100-250 Hz): 0.25 mm and 0.15° per axis,
    /// 0.5% dropped frames, 2% quaternion sign flips, no mirror flips (markers have no planar
    /// ambiguity). [`TrackerNoise::mocap_drawn`] draws the sigmas of one capture.
    pub fn mocap() -> TrackerNoise {
        TrackerNoise {
            name: "mocap".into(),
            sigma: NoiseModel {
                sigma_position: 0.00025,
                sigma_rotation: 0.15f64.to_radians(),
            },
            drop_prob: 0.005,
            sign_flip_prob: 0.02,
            mirror_prob: 0.0,
            camera: DEFAULT_CAMERA,
        }
    }

    /// The [`TrackerNoise::mocap`] preset with the sigmas of one capture session drawn
    /// uniformly from 0.1-0.5 mm and 0.05-0.3° (the name stays "mocap").
    pub fn mocap_drawn<R: Rng>(rng: &mut R) -> TrackerNoise {
        let mut m = Self::mocap();
        m.sigma.sigma_position = rng.random_range(0.0001..0.0005);
        m.sigma.sigma_rotation = rng.random_range(0.05f64..0.3).to_radians();
        m
    }

    /// The preset called `name`, if any ([`TrackerNoise::PRESETS`] or "mocap").
    pub fn preset(name: &str) -> Option<TrackerNoise> {
        match name {
            "clean" => Some(Self::clean()),
            "real" => Some(Self::real()),
            "noisy" => Some(Self::noisy()),
            "mocap" => Some(Self::mocap()),
            _ => None,
        }
    }

    /// Names of the camera presets (the standard dataset's noise levels).
    pub const PRESETS: [&'static str; 3] = ["clean", "real", "noisy"];

    /// Motion-capture rates of the messy scenes \[Hz\]: 100-250 Hz rates that divide the
    /// 960 Hz physics rate, so every frame is an exact physics sample.
    pub const MOCAP_RATES: [f64; 4] = [120.0, 160.0, 192.0, 240.0];

    /// Check that every number is usable.
    pub fn validate(&self) -> crate::Result<()> {
        let ok_p = |p: f64| (0.0..=0.5).contains(&p);
        let sigmas_ok = (0.0..0.1).contains(&self.sigma.sigma_position)
            && (0.0..0.5).contains(&self.sigma.sigma_rotation);
        if !(sigmas_ok
            && ok_p(self.drop_prob)
            && ok_p(self.sign_flip_prob)
            && ok_p(self.mirror_prob))
        {
            return Err(crate::SimError::InvalidSpec(format!(
                "noise model '{}' out of range: sigmas must be below 0.1 m and 0.5 rad, probabilities in [0, 0.5]",
                self.name
            )));
        }
        Ok(())
    }

    /// Apply this model to a clean trajectory of `world_from_tag` poses.
    pub fn apply(&self, clean: &[StampedPose], rng: &mut StdRng) -> Vec<StampedPose> {
        let np = Normal::new(0.0, self.sigma.sigma_position.max(0.0)).expect("finite sigma");
        let nr = Normal::new(0.0, self.sigma.sigma_rotation.max(0.0)).expect("finite sigma");
        let cam = Point3::from(self.camera);
        let mut out = Vec::with_capacity(clean.len());
        for sp in clean {
            // Draw every random number for every frame so that streams stay aligned.
            let drop = rng.random::<f64>() < self.drop_prob;
            let e = Vector3::new(np.sample(rng), np.sample(rng), np.sample(rng));
            let d = Vector3::new(nr.sample(rng), nr.sample(rng), nr.sample(rng));
            let mirror = rng.random::<f64>() < self.mirror_prob;
            let flip = rng.random::<f64>() < self.sign_flip_prob;
            if drop {
                continue;
            }
            let mut rot = sp.pose.rotation * UnitQuaternion::from_scaled_axis(d);
            let p = sp.pose.translation.vector + e;
            let sight = Point3::from(p) - cam;
            if mirror && (rot * Vector3::z()).angle(&-sight) < MIRROR_MAX_VIEW {
                rot = mirror_about_sight(&rot, &sight);
            }
            if flip {
                rot = UnitQuaternion::new_unchecked(-rot.into_inner());
            }
            out.push(StampedPose {
                t: sp.t,
                pose: Isometry3::from_parts(Translation3::from(p), rot),
            });
        }
        out
    }
}

/// The mirror-ambiguous orientation of a planar tag seen along `sight` (camera to tag): its
/// normal `n = R e_z` reflected about the line of sight, `n' = 2 (n·l) l − n`, applied as the
/// shortest rotation from `n` to `n'`.
pub fn mirror_about_sight(rot: &UnitQuaternion<f64>, sight: &Vector3<f64>) -> UnitQuaternion<f64> {
    let l = sight.normalize();
    let n = rot * Vector3::z();
    let n2 = 2.0 * n.dot(&l) * l - n;
    match UnitQuaternion::rotation_between(&n, &n2) {
        Some(r) => r * rot,
        None => *rot,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirror_reflects_normal_about_sight_and_keeps_angle_to_it() {
        let rot = UnitQuaternion::from_euler_angles(0.3, -0.4, 0.2);
        let sight = Vector3::new(0.2, 1.0, -0.5);
        let m = mirror_about_sight(&rot, &sight);
        let (n, n2, l) = (rot * Vector3::z(), m * Vector3::z(), sight.normalize());
        assert!((n.dot(&l) - n2.dot(&l)).abs() < 1e-12);
        assert!(((n + n2) - 2.0 * n.dot(&l) * l).norm() < 1e-12);
    }
}
