//! A face of the object in the tree: the weighted mean of its observations' normals and of
//! the offsets that are known (see the [tree documentation](super)).

use super::unlocated_offset::UnlocatedOffset;
use super::{angle, SYSTEMATIC_DIRECTION_RAD, SYSTEMATIC_POINT_M};
use crate::face::{FaceObservation, FaceSource, SUPPORT_LEVEL_SIGMA_RAD};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// A face of the object: the plane `{x : normal·x = offset}`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Face {
    /// Identifier, `f0`, `f1`, ...
    pub id: String,
    /// Unit normal (outward when `sign_known`).
    pub normal: Vector3<f64>,
    /// Offset \[m\], or null when the data do not determine it (a slide alone does not) or
    /// do not locate it ([`Face::offset_unlocated`]).
    pub offset: Option<f64>,
    /// Standard deviation of the offset \[m\].
    pub offset_sigma_m: Option<f64>,
    /// RMS standard deviation of the normal \[rad\].
    pub sigma_normal_rad: f64,
    /// Whether the normal is known to point out of the object.
    pub sign_known: bool,
    /// Names of the demonstrations that show this face.
    pub support: Vec<String>,
    /// Number of supporting demonstrations.
    pub n_support: usize,
    /// How many observations came from slides and from rests.
    pub evidence: Evidence,
    /// The per-demonstration observations.
    pub observations: Vec<FaceObservation>,
    /// The offset's estimate where its σ does not locate it well enough to be the face's
    /// (`offset` and `offset_sigma_m` are then null; `tree/unlocated.rs`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub offset_unlocated: Option<UnlocatedOffset>,
}

/// Counts of face observations by source.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct Evidence {
    /// From slides.
    pub slide: usize,
    /// From rests before or after topples, or on the support.
    pub rest: usize,
    /// From landings after flights, confirmed by another demonstration's ([`crate::landing`]).
    #[serde(default)]
    pub landing: usize,
}

impl Face {
    pub(super) fn new(id: String, obs: FaceObservation) -> Self {
        let mut f = Self {
            id,
            normal: obs.normal,
            offset: None,
            offset_sigma_m: None,
            sigma_normal_rad: 0.0,
            sign_known: obs.sign_known,
            support: Vec::new(),
            n_support: 0,
            evidence: Evidence::default(),
            observations: vec![obs],
            offset_unlocated: None,
        };
        f.refit();
        f
    }

    /// Recompute the estimate from the observations.
    pub(super) fn refit(&mut self) {
        // Reference sign: the most precise observation whose sign is known, else the most
        // precise. (The first one, as before, made the fusion depend on the order of the
        // demonstrations: a palm "slide" known to ±39°, 90° from the rests it matched within
        // that, came first, and the rests' normals were signed by their dot product with it,
        // one each way: Drake, a face 16° off.)
        let most_precise = |sign_known: bool| {
            self.observations
                .iter()
                .filter(|o| o.sign_known || !sign_known)
                .min_by(|a, b| a.sigma_normal().total_cmp(&b.sigma_normal()))
        };
        let reference = most_precise(true)
            .or_else(|| most_precise(false))
            .map_or(self.normal, |o| o.normal);
        let (mut sum, mut wsum, mut wsum2) = (Vector3::zeros(), 0.0, 0.0);
        // The known offsets, signed as the reference normal, with their weights.
        let mut offsets: Vec<(f64, f64)> = Vec::new();
        let mut evidence = Evidence::default();
        for o in &self.observations {
            let w = 1.0 / (o.sigma_normal().powi(2) + 1e-12);
            let n = if o.normal.dot(&reference) < 0.0 {
                -o.normal
            } else {
                o.normal
            };
            sum += n * w;
            wsum += w;
            wsum2 += w * w;
            if let (Some(d), Some(v)) = (o.offset, o.offset_var) {
                let d = if o.normal.dot(&reference) < 0.0 {
                    -d
                } else {
                    d
                };
                // Weighed by its own variance; the part common to the face's observations
                // (the contact's depth of the edge it came through) is added back below.
                let own = (v - o.offset_common_var).max(0.0);
                offsets.push((d, 1.0 / (own + 1e-12)));
            }
            match o.source {
                FaceSource::Slide => evidence.slide += 1,
                FaceSource::Rest => evidence.rest += 1,
                FaceSource::Landing => evidence.landing += 1,
            }
        }
        let n = sum.normalize();
        // Scatter of the normals about their mean, per axis, over the effective count.
        let n_eff = (wsum * wsum / wsum2).max(1.0);
        let scatter: f64 = self
            .observations
            .iter()
            .map(|o| {
                let w = 1.0 / (o.sigma_normal().powi(2) + 1e-12);
                let a = angle(&n, &o.normal);
                w * a.min(std::f64::consts::PI - a).powi(2)
            })
            .sum::<f64>()
            / wsum;
        self.normal = n;
        self.sigma_normal_rad =
            ((scatter / 2.0) / n_eff + 1.0 / wsum + self.common_level_var(wsum)).sqrt();
        self.sign_known = self.observations.iter().any(|o| o.sign_known);
        let off_w: f64 = offsets.iter().map(|(_, w)| w).sum();
        self.offset_unlocated = None;
        self.offset =
            (off_w > 0.0).then(|| offsets.iter().map(|(d, w)| d * w).sum::<f64>() / off_w);
        let common = self.offset_common_var();
        self.offset_sigma_m = self
            .offset
            .map(|mean| (birge_ratio(&offsets, mean) / off_w + common).sqrt());
        self.support = self.observations.iter().map(|o| o.demo.clone()).collect();
        self.support.sort();
        self.support.dedup();
        self.n_support = self.support.len();
        self.evidence = evidence;
    }

    /// The variance \[m²\] common to the known offsets (the contact's depth of the edges they
    /// came through), which their number does not average down: its mean over them, a part of
    /// [`Self::offset_sigma_m`].
    pub(super) fn offset_common_var(&self) -> f64 {
        let common: Vec<f64> = self
            .observations
            .iter()
            .filter(|o| o.offset.is_some() && o.offset_var.is_some())
            .map(|o| o.offset_common_var)
            .collect();
        common.iter().sum::<f64>() / common.len().max(1) as f64
    }

    /// The face without the offsets that `demos` gave it: their observations' offsets came
    /// through those demonstrations' own edges (a topple's resting face passes through its
    /// edge, [`FaceObservation::from_rest`]), their normals from the rests (gravity), which
    /// are measurements of their own.
    pub(super) fn without_offsets_of(&self, demos: &[String]) -> Face {
        let mut f = self.clone();
        for o in f
            .observations
            .iter_mut()
            .filter(|o| demos.contains(&o.demo))
        {
            o.offset = None;
            o.offset_var = None;
            o.offset_common_var = 0.0;
        }
        f.refit();
        f
    }

    /// RMS standard deviation \[rad\] of the normal per axis without the support's level
    /// common to its gravity-taught observations ([`Self::sigma_normal_rad`] less
    /// `common_level_var`): what tells this face's normal from another face's taught in the same
    /// lab, where the common tilt tilts both alike (the centre of mass's planes weigh their
    /// resting faces by it, `tree/com.rs`).
    pub fn sigma_normal_own_rad(&self) -> f64 {
        let wsum: f64 = self
            .observations
            .iter()
            .map(|o| 1.0 / (o.sigma_normal().powi(2) + 1e-12))
            .sum();
        (self.sigma_normal_rad.powi(2) - self.common_level_var(wsum))
            .max(0.0)
            .sqrt()
    }

    /// Variance \[rad²\] per axis that the support's level adds to the weighted mean normal
    /// (of total weight `wsum`) beyond what its weights say. A normal taught by gravity (a rest,
    /// a landing) holds the level of the support and of the tracking frame against gravity,
    /// [`SUPPORT_LEVEL_SIGMA_RAD`] per axis, and its weight counts it as independent: the mean
    /// of `n` such normals would be known to `1/√n` of it. But a tilted table, or a tracker's
    /// world tilted from the gravity it was given, tilts them all alike: that part does not
    /// average down. Counted as common to them (full correlation, the worst case), it
    /// contributes `L² (W_g / W)²` to the mean's variance where the weights gave
    /// `L² Σ w_i² / W²` (`W_g` the gravity-taught observations' weight, `w_i` theirs): the
    /// difference is added. A face that rests alone taught is then known to the support's
    /// level, 1°, however many rests show it; one that slides taught too, to less.
    fn common_level_var(&self, wsum: f64) -> f64 {
        let level = SUPPORT_LEVEL_SIGMA_RAD * SUPPORT_LEVEL_SIGMA_RAD;
        let (mut w_g, mut w2_g) = (0.0, 0.0);
        for o in self
            .observations
            .iter()
            .filter(|o| matches!(o.source, FaceSource::Rest | FaceSource::Landing))
        {
            let w = 1.0 / (o.sigma_normal().powi(2) + 1e-12);
            w_g += w;
            w2_g += w * w;
        }
        (level * (w_g * w_g - w2_g) / (wsum * wsum)).max(0.0)
    }

    /// χ² (2 dof) of an observation's normal against this face, and whether offsets agree.
    pub(super) fn match_chi2(&self, o: &FaceObservation) -> f64 {
        let a = angle(&self.normal, &o.normal);
        // Signs: when both are known, opposite normals are different faces.
        let a = if self.sign_known && o.sign_known {
            a
        } else {
            a.min(std::f64::consts::PI - a)
        };
        let var = self.sigma_normal_rad.powi(2)
            + o.sigma_normal().powi(2)
            + SYSTEMATIC_DIRECTION_RAD.powi(2);
        let mut chi2 = a * a / var;
        if let (Some(d0), Some(d1), Some(v1)) = (self.offset, o.offset, o.offset_var) {
            let d1 = if self.normal.dot(&o.normal) < 0.0 {
                -d1
            } else {
                d1
            };
            let v = self.offset_sigma_m.unwrap_or(0.0).powi(2) + v1 + SYSTEMATIC_POINT_M.powi(2);
            chi2 += (d0 - d1).powi(2) / v;
        }
        chi2
    }
}

/// The Birge ratio of weighted values `(value, weight)` about their weighted `mean`:
/// `χ² / (N - 1)` when that exceeds 1, else 1. Offsets that scatter beyond their own sigmas (a
/// systematic error that differs between demonstrations, or two different faces within the
/// match gate) widen the mean's sigma by it; it never shrinks below the propagated one.
pub(super) fn birge_ratio(values: &[(f64, f64)], mean: f64) -> f64 {
    if values.len() < 2 {
        return 1.0;
    }
    let chi2: f64 = values.iter().map(|(d, w)| (d - mean).powi(2) * w).sum();
    (chi2 / (values.len() - 1) as f64).max(1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Matrix3;
    use rand::{rngs::StdRng, SeedableRng};
    use rand_distr::{Distribution, StandardNormal};

    fn rest(demo: &str, offset: f64, sigma: f64) -> FaceObservation {
        FaceObservation {
            demo: demo.into(),
            normal: Vector3::z(),
            normal_cov: Matrix3::identity() * 1e-6,
            offset: Some(offset),
            offset_var: Some(sigma * sigma),
            offset_common_var: 0.0,
            sign_known: true,
            source: FaceSource::Rest,
            frames: 30,
            rest_height: None,
        }
    }

    fn fused(obs: Vec<FaceObservation>) -> Face {
        let mut f = Face::new("f0".into(), obs[0].clone());
        f.observations = obs;
        f.refit();
        f
    }

    /// The fused normal does not depend on the order of the observations: a rough one (σ 39°)
    /// nearly normal to two precise ones, first or last, leaves their mean where they are.
    #[test]
    fn a_rough_first_observation_does_not_sign_the_precise_ones() {
        let with = |normal: Vector3<f64>, sigma: f64| FaceObservation {
            normal: normal.normalize(),
            normal_cov: Matrix3::identity() * sigma * sigma,
            ..rest("d", 0.0, 1e-3)
        };
        let rough = with(Vector3::new(-0.58, 0.09, -0.81), 39f64.to_radians());
        let a = with(Vector3::new(-0.154, -0.988, 0.0), 1f64.to_radians());
        let b = with(Vector3::new(-0.154, -0.988, 0.027), 1f64.to_radians());
        let truth = Vector3::new(-0.154, -0.988, 0.0135).normalize();
        for obs in [
            vec![rough.clone(), a.clone(), b.clone()],
            vec![a.clone(), b.clone(), rough.clone()],
            vec![b.clone(), rough.clone(), a.clone()],
        ] {
            let f = fused(obs);
            assert!(
                f.normal.angle(&truth) < 0.1f64.to_radians(),
                "{:?} is {:.1}° off",
                f.normal,
                f.normal.angle(&truth).to_degrees()
            );
        }
    }

    /// Offsets taught through edges share those edges' contact depth: each one's own variance
    /// weighs it, and the common part is added once to the mean's, not divided among them.
    /// Two agreeing offsets of own σ 0.2 mm and common σ 1 mm: σ² = 0.2²/2 + 1² mm².
    #[test]
    fn a_common_offset_error_does_not_average_down() {
        let (own, common) = (2e-4f64, 1e-3f64);
        let through_edge = |demo: &str, offset: f64| FaceObservation {
            offset_var: Some(own * own + common * common),
            offset_common_var: common * common,
            ..rest(demo, offset, 0.0)
        };
        let f = fused(vec![
            through_edge("a", 0.05),
            through_edge("b", 0.05 + 1e-4),
        ]);
        let expected = (own * own / 2.0 + common * common).sqrt();
        let sigma = f.offset_sigma_m.unwrap();
        assert!(
            (sigma - expected).abs() < 1e-3 * expected,
            "{sigma} against {expected}"
        );
        assert!((f.offset.unwrap() - 0.05005).abs() < 1e-12);
    }

    /// Offsets that agree within their sigmas keep the propagated sigma of their mean, and over
    /// many draws its error is honest (median |error|/σ near 0.674).
    #[test]
    fn agreeing_offsets_keep_the_propagated_sigma() {
        let mut rng = StdRng::seed_from_u64(3);
        let (truth, sigma) = (0.05, 4e-4);
        let mut z = Vec::new();
        for k in 0..400 {
            let n = 2 + k % 5;
            let obs: Vec<_> = (0..n)
                .map(|i| {
                    let e: f64 = StandardNormal.sample(&mut rng);
                    rest(&format!("d{i}"), truth + sigma * e, sigma)
                })
                .collect();
            let f = fused(obs);
            let s = f.offset_sigma_m.unwrap();
            assert!(s >= sigma / (n as f64).sqrt() * (1.0 - 1e-9));
            z.push(((f.offset.unwrap() - truth) / s).abs());
        }
        z.sort_by(f64::total_cmp);
        let median = z[z.len() / 2];
        assert!((0.5..0.8).contains(&median), "median |z| {median}");
    }

    /// Faces taught by gravity in one lab whose tracking frame is tilted from the gravity it
    /// was given (by a normal draw of 1° per axis, the support level the observations hold):
    /// every rest on the face sees the same tilt when the object rests on it the same way
    /// round, so their mean is off by the whole tilt however many rests there are. Its σ must
    /// say so: over many labs, the median |error|/σ of the 2-D normal error is near the
    /// honest 1.18 (counted as independent, the σ shrank as 1/√n and the median was
    /// 1.18 √n, 2.4 to 3.3 here), and no error exceeds 5 σ.
    #[test]
    fn a_tilt_common_to_rests_does_not_average_down() {
        let mut rng = StdRng::seed_from_u64(11);
        let level = SUPPORT_LEVEL_SIGMA_RAD;
        let mut z = Vec::new();
        for k in 0..400 {
            let n = 4 + k % 5;
            let (a, b): (f64, f64) = (
                StandardNormal.sample(&mut rng),
                StandardNormal.sample(&mut rng),
            );
            let tilt = Vector3::new(level * a, level * b, 0.0);
            let down = nalgebra::Rotation3::new(tilt) * Vector3::z();
            let obs: Vec<_> = (0..n)
                .map(|i| FaceObservation::from_gravity(&down, &format!("d{i}"), 40))
                .collect();
            let f = fused(obs);
            z.push(angle(&f.normal, &Vector3::z()) / f.sigma_normal_rad);
        }
        z.sort_by(f64::total_cmp);
        let median = z[z.len() / 2];
        assert!((0.95..1.4).contains(&median), "median |error|/σ {median}");
        assert!(z[z.len() - 1] < 5.0, "largest |error|/σ {}", z[z.len() - 1]);
    }

    /// The common level counts for the gravity-taught share of a face only: slides that
    /// determine the normal better keep it better known than the level.
    #[test]
    fn slides_keep_a_face_known_better_than_the_level() {
        let slide = FaceObservation {
            source: FaceSource::Slide,
            normal_cov: (Matrix3::identity() - Vector3::z() * Vector3::z().transpose()) * 1e-6,
            ..FaceObservation::from_gravity(&Vector3::z(), "s", 40)
        };
        let rests =
            (0..6).map(|i| FaceObservation::from_gravity(&Vector3::z(), &format!("r{i}"), 40));
        let f = fused(std::iter::repeat_n(slide, 3).chain(rests).collect());
        assert!(
            f.sigma_normal_rad < 0.1 * SUPPORT_LEVEL_SIGMA_RAD,
            "σ {}",
            f.sigma_normal_rad
        );
        let alone = fused(
            (0..6)
                .map(|i| FaceObservation::from_gravity(&Vector3::z(), &format!("r{i}"), 40))
                .collect(),
        );
        assert!(
            (alone.sigma_normal_rad - SUPPORT_LEVEL_SIGMA_RAD).abs()
                < 1e-3 * SUPPORT_LEVEL_SIGMA_RAD,
            "σ {}",
            alone.sigma_normal_rad
        );
    }

    /// Two offsets 10 mm apart, each known to 0.3 mm (two boxes' faces within the match gate):
    /// the mean's sigma covers their disagreement instead of claiming 0.2 mm.
    #[test]
    fn disagreeing_offsets_widen_the_sigma() {
        let f = fused(vec![rest("a", 0.045, 3e-4), rest("b", 0.055, 3e-4)]);
        let s = f.offset_sigma_m.unwrap();
        assert!((f.offset.unwrap() - 0.05).abs() < 1e-9);
        assert!(s > 4e-3, "σ {s}");
        assert!(s < 6e-3, "σ {s}");
    }
}
