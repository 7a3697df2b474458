//! Tracking noise: what a fiducial tracker adds to the true tag poses.
//!
//! For each frame:
//! * with probability `drop_prob` the frame is lost (not written);
//! * position: `p' = p + ε`, `ε ~ N(0, σ_p² I)` per world axis;
//! * orientation: `R' = R · exp([δ]×)`, `δ ~ N(0, σ_r² I)` per tag axis;
//! * or, for a camera that resolves depth and tilt worse than the image plane
//!   (`sight_ratio` k ≠ 1), in the axes of the line of sight `l` (camera to tag) and two axes
//!   across it: `ε` has σ_p across `l` and `k σ_p` along it, and `R' = exp([δ]×) · R` with `δ`
//!   (in the world) of `k σ_r` about the axes across `l` (tilts out of the image plane) and σ_r
//!   about `l` (the turn in the image);
//! * the Gaussian draws of consecutive frames are correlated with coefficient `correlation`
//!   (ρ, first-order autoregressive: `z_k = ρ z_{k−1} + √(1 − ρ²) w_k`, so each draw keeps
//!   its variance): a tracker that smooths its output; independent when ρ = 0;
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
use rand_distr::StandardNormal;
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
    /// How many times larger the noise is along the camera's line of sight (position) and in
    /// the tilts out of the image plane (orientation) than across it and in the image's own
    /// turn: 1 for noise alike on every axis.
    #[serde(default = "one")]
    pub sight_ratio: f64,
    /// Correlation of the Gaussian noise of consecutive frames (first-order autoregressive,
    /// each frame's variance unchanged): 0 for independent frames.
    #[serde(default)]
    pub correlation: f64,
}

fn one() -> f64 {
    1.0
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
            sight_ratio: 1.0,
            correlation: 0.0,
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
            sight_ratio: 1.0,
            correlation: 0.0,
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
            sight_ratio: 1.0,
            correlation: 0.0,
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
            sight_ratio: 1.0,
            correlation: 0.0,
        }
    }

    /// A camera tracking a fiducial tag as a camera does: 0.7 mm across the line of sight and
    /// three times that (2.1 mm) along it, 0.3° in the image's own turn and three times that
    /// (0.9°) in the tilts out of the image plane, consecutive frames correlated at 0.5 (a
    /// smoothing tracker), 3% dropped frames, 5% sign flips, 1% mirror flips. A root mean
    /// square over the axes of 1.3 mm and 0.75° (the `real` preset: 1 mm, 0.5°); not alike on
    /// every axis nor independent between frames, as the learner's noise model assumes.
    pub fn camera() -> TrackerNoise {
        TrackerNoise {
            name: "camera".into(),
            sigma: NoiseModel {
                sigma_position: 0.0007,
                sigma_rotation: 0.3f64.to_radians(),
            },
            drop_prob: 0.03,
            sign_flip_prob: 0.05,
            mirror_prob: 0.01,
            camera: DEFAULT_CAMERA,
            sight_ratio: 3.0,
            correlation: 0.5,
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

    /// The preset called `name`, if any ([`TrackerNoise::PRESETS`], "mocap" or "camera").
    pub fn preset(name: &str) -> Option<TrackerNoise> {
        match name {
            "clean" => Some(Self::clean()),
            "real" => Some(Self::real()),
            "noisy" => Some(Self::noisy()),
            "mocap" => Some(Self::mocap()),
            "camera" => Some(Self::camera()),
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
            && (0.0..0.5).contains(&self.sigma.sigma_rotation)
            && (1.0..=10.0).contains(&self.sight_ratio)
            && (0.0..1.0).contains(&self.correlation);
        if !(sigmas_ok
            && ok_p(self.drop_prob)
            && ok_p(self.sign_flip_prob)
            && ok_p(self.mirror_prob))
        {
            return Err(crate::SimError::InvalidSpec(format!(
                "noise model '{}' out of range: sigmas must be below 0.1 m and 0.5 rad, probabilities in [0, 0.5], sight_ratio in [1, 10], correlation in [0, 1)",
                self.name
            )));
        }
        Ok(())
    }

    /// Apply this model to a clean trajectory of `world_from_tag` poses.
    pub fn apply(&self, clean: &[StampedPose], rng: &mut StdRng) -> Vec<StampedPose> {
        let (sigma_p, sigma_r) = (
            self.sigma.sigma_position.max(0.0),
            self.sigma.sigma_rotation.max(0.0),
        );
        let (rho, k) = (self.correlation, self.sight_ratio);
        let fresh = (1.0 - rho * rho).sqrt();
        let cam = Point3::from(self.camera);
        let (mut ze, mut zd) = (Vector3::zeros(), Vector3::zeros());
        let mut out = Vec::with_capacity(clean.len());
        for (i, exact) in clean.iter().enumerate() {
            // Draw every random number for every frame so that streams stay aligned.
            let drop = rng.random::<f64>() < self.drop_prob;
            let we = Vector3::new(normal(rng), normal(rng), normal(rng));
            let wd = Vector3::new(normal(rng), normal(rng), normal(rng));
            let mirror = rng.random::<f64>() < self.mirror_prob;
            let flip = rng.random::<f64>() < self.sign_flip_prob;
            (ze, zd) = if i == 0 || rho == 0.0 {
                (we, wd)
            } else {
                (ze * rho + we * fresh, zd * rho + wd * fresh)
            };
            if drop {
                continue;
            }
            let true_p = exact.pose.translation.vector;
            let (p, mut rot) = if k == 1.0 {
                (
                    true_p + ze * sigma_p,
                    exact.pose.rotation * UnitQuaternion::from_scaled_axis(zd * sigma_r),
                )
            } else {
                let [l, a, b] = sight_axes(&(Point3::from(true_p) - cam));
                let e = (a * ze.x + b * ze.y) * sigma_p + l * (ze.z * k * sigma_p);
                let d = (a * zd.x + b * zd.y) * (k * sigma_r) + l * (zd.z * sigma_r);
                (
                    true_p + e,
                    UnitQuaternion::from_scaled_axis(d) * exact.pose.rotation,
                )
            };
            let sight = Point3::from(p) - cam;
            if mirror && (rot * Vector3::z()).angle(&-sight) < MIRROR_MAX_VIEW {
                rot = mirror_about_sight(&rot, &sight);
            }
            if flip {
                rot = UnitQuaternion::new_unchecked(-rot.into_inner());
            }
            out.push(StampedPose {
                t: exact.t,
                pose: Isometry3::from_parts(Translation3::from(p), rot),
            });
        }
        out
    }
}

/// One standard normal draw (as `Normal::new(0, σ)` draws it before scaling by σ).
fn normal(rng: &mut StdRng) -> f64 {
    rng.sample(StandardNormal)
}

/// The unit line of sight `l` along `sight` (camera to tag) and two unit axes across it, `a`
/// level (normal to `l` and the world's z) and `b = l × a`; a line of sight straight down or
/// up takes `a` = x.
fn sight_axes(sight: &Vector3<f64>) -> [Vector3<f64>; 3] {
    let l = sight.normalize();
    let a = l
        .cross(&Vector3::z())
        .try_normalize(1e-9)
        .unwrap_or_else(Vector3::x);
    [l, a, l.cross(&a)]
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
    use rand::SeedableRng;

    /// A tag at rest at `p` seen by [`TrackerNoise::camera`] for `n` frames: the position
    /// errors and the orientation errors (world rotation vectors).
    fn camera_errors(
        p: Vector3<f64>,
        n: usize,
    ) -> (TrackerNoise, Vec<Vector3<f64>>, Vec<Vector3<f64>>) {
        let mut noise = TrackerNoise::camera();
        (noise.drop_prob, noise.sign_flip_prob, noise.mirror_prob) = (0.0, 0.0, 0.0);
        let rot = UnitQuaternion::from_euler_angles(0.3, -0.2, 1.0);
        let clean: Vec<StampedPose> = (0..n)
            .map(|k| StampedPose {
                t: k as f64 / 30.0,
                pose: Isometry3::from_parts(Translation3::from(p), rot),
            })
            .collect();
        let noisy = noise.apply(&clean, &mut StdRng::seed_from_u64(9));
        let e = noisy
            .iter()
            .map(|s| s.pose.translation.vector - p)
            .collect();
        let d = noisy
            .iter()
            .map(|s| (s.pose.rotation * rot.inverse()).scaled_axis())
            .collect();
        (noise, e, d)
    }

    /// The camera preset's noise has its σ across the line of sight, `sight_ratio` times that
    /// along it (and the reverse for the orientation: tilts out of the image plane are the
    /// larger), and consecutive frames correlated at `correlation` (each within its sampling
    /// error over 40 000 frames).
    #[test]
    fn camera_noise_is_larger_along_the_sight_and_correlated() {
        let p = Vector3::new(0.1, 0.05, 0.02);
        let n = 40_000;
        let (noise, e, d) = camera_errors(p, n);
        let [l, a, b] = sight_axes(&(Point3::from(p) - Point3::from(noise.camera)));
        let sd = |v: &[Vector3<f64>], u: &Vector3<f64>| {
            (v.iter().map(|x| x.dot(u).powi(2)).sum::<f64>() / v.len() as f64).sqrt()
        };
        let (sp, sr, k) = (
            noise.sigma.sigma_position,
            noise.sigma.sigma_rotation,
            noise.sight_ratio,
        );
        for (got, want) in [
            (sd(&e, &a), sp),
            (sd(&e, &b), sp),
            (sd(&e, &l), k * sp),
            (sd(&d, &a), k * sr),
            (sd(&d, &b), k * sr),
            (sd(&d, &l), sr),
        ] {
            // The sampling error of a σ from 40 000 correlated draws is about 0.6%.
            assert!((got / want - 1.0).abs() < 0.03, "{got} against {want}");
        }
        let lag1 = |v: &[Vector3<f64>], u: &Vector3<f64>| {
            let x: Vec<f64> = v.iter().map(|x| x.dot(u)).collect();
            let c: f64 = x.windows(2).map(|w| w[0] * w[1]).sum::<f64>() / (x.len() - 1) as f64;
            c / (x.iter().map(|x| x * x).sum::<f64>() / x.len() as f64)
        };
        for r in [lag1(&e, &a), lag1(&e, &l), lag1(&d, &b), lag1(&d, &l)] {
            assert!(
                (r - noise.correlation).abs() < 0.03,
                "lag-1 correlation {r}"
            );
        }
    }

    /// With `sight_ratio` 1 and no correlation, each frame's noise is σ times its own draws,
    /// independent of the others' (the presets' noise since the first data set).
    #[test]
    fn independent_noise_alike_on_every_axis() {
        let mut noise = TrackerNoise::real();
        (noise.drop_prob, noise.sign_flip_prob, noise.mirror_prob) = (0.0, 0.0, 0.0);
        let clean = vec![
            StampedPose {
                t: 0.0,
                pose: Isometry3::identity(),
            };
            2
        ];
        let noisy = noise.apply(&clean, &mut StdRng::seed_from_u64(3));
        let mut rng = StdRng::seed_from_u64(3);
        for s in &noisy {
            let _drop: f64 = rng.random();
            let e = Vector3::from_fn(|_, _| normal(&mut rng)) * noise.sigma.sigma_position;
            let d = Vector3::from_fn(|_, _| normal(&mut rng)) * noise.sigma.sigma_rotation;
            let (_mirror, _flip): (f64, f64) = (rng.random(), rng.random());
            assert_eq!(s.pose.translation.vector, e);
            assert!((s.pose.rotation.scaled_axis() - d).norm() < 1e-15);
        }
    }

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
