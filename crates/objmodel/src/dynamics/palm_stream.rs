//! The palm's poses for the tilt angles, without its tracker's glitches.
//!
//! The classifier judges the object's motion relative to the palm and drops the frames where
//! either tracker glitched; the recording keeps the palm's raw poses, so a flipped palm pose
//! would put a spike of tens of degrees into the palm's tilt ψ_palm, and through the smoothing
//! into the tilt at the onset. The palm stream is therefore cleaned with the same glitch test
//! as the object's ([`crate::clean::Cleaner`], same significance level), under the noise of
//! the demonstration.

use crate::classify::RobustConfig;
use crate::clean::{Cleaner, RawFrame};
use crate::noise::NoiseModel;
use crate::trajectory::StampedPose;
use nalgebra::Isometry3;

/// `palm` without the poses the glitch test rejects, for tracking noise `noise`.
pub(super) fn without_glitches(palm: &[StampedPose], noise: NoiseModel) -> Vec<StampedPose> {
    let n = noise.floored();
    let alpha = RobustConfig::default().outlier_alpha;
    let mut cleaner = Cleaner::new(n.sigma_rotation, n.sigma_position, alpha);
    let mut kept = Vec::with_capacity(palm.len());
    let mut take = |f: RawFrame, flipped: bool| {
        if !flipped {
            kept.push(StampedPose {
                t: f.t,
                pose: Isometry3::from_parts(f.p.into(), f.q),
            });
        }
    };
    for (index, p) in palm.iter().enumerate() {
        let f = RawFrame {
            index,
            t: p.t,
            q: p.pose.rotation,
            p: p.pose.translation.vector,
        };
        cleaner.push(f, &mut take);
    }
    cleaner.finish(&mut take);
    kept
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{UnitQuaternion, Vector3};
    use rand::{rngs::StdRng, Rng, SeedableRng};

    fn noise(sigma_rotation: f64) -> NoiseModel {
        NoiseModel {
            sigma_position: 1e-3,
            sigma_rotation,
        }
    }

    fn tilting_palm(n: usize, sigma: f64, rng: &mut StdRng) -> Vec<StampedPose> {
        (0..n)
            .map(|i| {
                let t = i as f64 / 30.0;
                let noise = Vector3::from_fn(|_, _| rng.random_range(-1.0..1.0) * sigma);
                let q = UnitQuaternion::from_scaled_axis(Vector3::x() * 0.05 * t + noise);
                StampedPose {
                    t,
                    pose: Isometry3::from_parts(Vector3::new(0.1, 0.0, 0.3).into(), q),
                }
            })
            .collect()
    }

    #[test]
    fn flipped_palm_poses_are_dropped_and_the_others_kept() {
        let mut rng = StdRng::seed_from_u64(7);
        let sigma = 0.3f64.to_radians();
        let mut palm = tilting_palm(200, sigma, &mut rng);
        // A tag's mirror solution: the orientation jumps by ~80° for one frame, or two.
        let flip = UnitQuaternion::from_scaled_axis(Vector3::new(1.0, 0.5, 0.0) * 1.2);
        for k in [40, 41, 120] {
            palm[k].pose.rotation = flip * palm[k].pose.rotation;
        }
        let kept = without_glitches(&palm, noise(sigma));
        let times: Vec<f64> = kept.iter().map(|p| p.t).collect();
        for k in [40, 41, 120] {
            assert!(!times.contains(&palm[k].t), "flip at {k} kept");
        }
        assert_eq!(kept.len(), palm.len() - 3);
        // Every kept pose is the input's, bit for bit (only the quaternion's sign may change).
        for p in &kept {
            let i = palm.iter().position(|q| q.t == p.t).unwrap();
            assert!(p.pose.rotation.angle_to(&palm[i].pose.rotation) < 1e-12);
            assert_eq!(p.pose.translation, palm[i].pose.translation);
        }
    }

    #[test]
    fn a_clean_palm_loses_nothing() {
        let mut rng = StdRng::seed_from_u64(8);
        let sigma = 0.1f64.to_radians();
        let palm = tilting_palm(300, sigma, &mut rng);
        assert_eq!(without_glitches(&palm, noise(sigma)).len(), palm.len());
    }
}
