//! The support: the height of the plane the object rests, topples and rolls on, in the frame
//! the poses are given in, and the face offsets it gives the landings.
//!
//! An edge the object turns about on the support lies on the support: the world line of a
//! roll ([`crate::roll`]) and the edge of a topple at the rest it starts from are at the
//! support's height. Each is a [`SupportObservation`]. Where at least two demonstrations
//! give one and they agree (χ² of their scatter about the weighted mean, with the support's
//! flatness and tilt, at [`crate::tree::MATCH_ALPHA`]), the support's height is known
//! ([`SupportHeight`]); where they disagree (the demonstrations came from several tables, or
//! trackers with other origins) it is not, and nothing is taken from it.
//!
//! A landing ([`crate::landing`]) rests on the support with the face it teaches: that face's
//! plane is at the support's height, so its offset is the landing's height above it,
//! `d = h − z` (the object frame's origin is `d` above the face it rests on).
//!
//! The user may know the support's height (a tracked table, a motion-capture frame whose
//! origin is on the floor): given ([`SupportObservation::given`], `objmodel learn
//! --support-height`), it is the support's height, whatever the edges measured.

use crate::face::SUPPORT_LEVEL_SIGMA_RAD;
use crate::landing::{Landing, SUPPORT_FLATNESS_M};
use nalgebra::Vector3;
use serde::{Deserialize, Serialize};

/// One demonstration's measurement of the support's height: an edge on the support.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SupportObservation {
    /// The demonstration.
    pub demo: String,
    /// Height \[m\] of the edge along −gravity, in the frame the poses are given in.
    pub height: f64,
    /// Its standard deviation \[m\]: the measurement's, with the contact's wander that the
    /// edge's σ holds (the support's flatness and tilt are added where observations meet).
    pub sigma_m: f64,
    /// Where it was across gravity \[m\].
    pub across: Vector3<f64>,
    /// What measured it: `"roll"` or `"topple"`; `"given"` for the user's
    /// ([`SupportObservation::given`]).
    pub from: String,
}

/// The demonstration name a given support's observation stands under.
pub const GIVEN: &str = "(given)";

impl SupportObservation {
    /// The support's height as the user gives it: `height` \[m\] along −gravity in the frame
    /// the poses are given in, known to `sigma_m` (how well the plane is known, its flatness
    /// and its level across where the object rests included). An error unless the height is
    /// finite and its σ finite and positive.
    pub fn given(height: f64, sigma_m: f64) -> crate::Result<Self> {
        if !(height.is_finite() && sigma_m.is_finite() && sigma_m > 0.0) {
            return Err(crate::Error::Data(format!(
                "a support's height must be finite and its σ positive, in metres (height \
                 {height}, σ {sigma_m})"
            )));
        }
        Ok(Self {
            demo: GIVEN.to_string(),
            height,
            sigma_m,
            across: Vector3::zeros(),
            from: "given".to_string(),
        })
    }

    /// Whether the user gave it.
    pub fn is_given(&self) -> bool {
        self.from == "given"
    }
}

/// The support's height, when the observations determine it.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct SupportHeight {
    /// Height \[m\] along −gravity, in the frame the poses are given in.
    pub height: f64,
    /// Its standard deviation \[m\] (the weighted mean's, the flatness and tilt included).
    pub sigma_m: f64,
    /// The mean place of the observations across gravity \[m\].
    pub across: Vector3<f64>,
    /// How many observations, and from how many demonstrations.
    pub observations: usize,
    /// Demonstrations.
    pub demos: usize,
    /// Whether it is the height the user gave ([`SupportObservation::given`]) rather than
    /// the demonstrations' measurements.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub given: bool,
}

/// Variance \[m²\] of a support's height between two places `apart` metres apart, beyond the
/// measurements' noise: its flatness at each and its tilt across the distance.
fn support_var(apart: f64) -> f64 {
    2.0 * SUPPORT_FLATNESS_M * SUPPORT_FLATNESS_M
        + (SUPPORT_LEVEL_SIGMA_RAD * apart) * (SUPPORT_LEVEL_SIGMA_RAD * apart)
}

impl SupportHeight {
    /// The support's height from `observations`: their mean weighted by their noise and the
    /// support's flatness, when at least two demonstrations give one and their scatter is
    /// what noise, flatness and tilt explain (χ² at `alpha`); `None` otherwise. A height the
    /// user gave ([`SupportObservation::given`]) is the support's, whatever was measured.
    pub fn fuse(observations: &[SupportObservation], alpha: f64) -> Option<Self> {
        // A height the user gave is the support's, alone: its σ is theirs.
        if let Some(g) = observations.iter().rev().find(|o| o.is_given()) {
            return Some(Self {
                height: g.height,
                sigma_m: g.sigma_m,
                across: g.across,
                observations: 1,
                demos: 0,
                given: true,
            });
        }
        let mut demos: Vec<&str> = observations.iter().map(|o| o.demo.as_str()).collect();
        demos.sort_unstable();
        demos.dedup();
        if demos.len() < 2 {
            return None;
        }
        let n = observations.len() as f64;
        let across = observations
            .iter()
            .fold(Vector3::zeros(), |s, o| s + o.across)
            / n;
        // Each observation's height about the plane's at the observations' mean place: its
        // noise, the flatness where it was, and a tilt across its distance from that place.
        let var = |o: &SupportObservation| {
            let apart = (o.across - across).norm();
            o.sigma_m * o.sigma_m
                + SUPPORT_FLATNESS_M * SUPPORT_FLATNESS_M
                + (SUPPORT_LEVEL_SIGMA_RAD * apart).powi(2)
        };
        let (mut sw, mut swh) = (0.0, 0.0);
        for o in observations {
            let w = 1.0 / var(o);
            sw += w;
            swh += w * o.height;
        }
        let height = swh / sw;
        let chi2: f64 = observations
            .iter()
            .map(|o| (o.height - height).powi(2) / var(o))
            .sum();
        if chi2 > crate::stats::chi2_threshold(n - 1.0, alpha) {
            return None;
        }
        Some(Self {
            height,
            sigma_m: (1.0 / sw).sqrt(),
            across,
            observations: observations.len(),
            demos: demos.len(),
            given: false,
        })
    }

    /// Whether the height `o` measured is this support's: their difference within their noise,
    /// and, for a measured support, its flatness and its tilt between their places (χ²₁ at
    /// `alpha`; a given height's σ holds those).
    pub fn holds(&self, o: &SupportObservation, alpha: f64) -> bool {
        let apart = (o.across - self.across).norm();
        let between = if self.given { 0.0 } else { support_var(apart) };
        let var = o.sigma_m.powi(2) + self.sigma_m.powi(2) + between;
        (o.height - self.height).powi(2) <= var * crate::stats::chi2_threshold(1.0, alpha)
    }

    /// The offset \[m\] of the face a landing rests on, and its variance: the landing's
    /// height above the support, with both their noise and the support's flatness and tilt
    /// between the landing's place and the observations' (a given height's σ holds them).
    pub fn offset_of(&self, landing: &Landing) -> (f64, f64) {
        self.offset_at(&landing.place, landing.sigma_height_m)
    }

    /// The offset \[m\] of the face a rest at `place` rests on, its height known to
    /// `sigma_m`, and the offset's variance ([`Self::offset_of`]).
    pub fn offset_at(&self, place: &crate::landing::RestPlace, sigma_m: f64) -> (f64, f64) {
        let apart = (place.across - self.across).norm();
        let between = if self.given { 0.0 } else { support_var(apart) };
        let var = sigma_m.powi(2) + self.sigma_m.powi(2) + between;
        (place.height - self.height, var)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::landing::RestPlace;
    use crate::noise::NoiseModel;
    use rand::{Rng, SeedableRng};
    use rand_distr::{Distribution, Normal};

    fn obs(demo: &str, height: f64, x: f64) -> SupportObservation {
        SupportObservation {
            demo: demo.to_string(),
            height,
            sigma_m: 2e-4,
            across: Vector3::new(x, 0.0, 0.0),
            from: "roll".to_string(),
        }
    }

    #[test]
    fn two_demonstrations_that_agree_fix_the_height_and_one_does_not() {
        assert!(SupportHeight::fuse(&[obs("a", 0.0, 0.0)], 1e-4).is_none());
        // Two edges of one demonstration are still one demonstration.
        assert!(SupportHeight::fuse(&[obs("a", 0.0, 0.0), obs("a", 0.0, 0.1)], 1e-4).is_none());
        let s = SupportHeight::fuse(&[obs("a", 0.001, 0.0), obs("b", -0.001, 0.2)], 1e-4)
            .expect("agree");
        assert!(s.height.abs() < 1e-9, "{}", s.height);
        assert_eq!((s.observations, s.demos), (2, 2));
        assert!((s.across.x - 0.1).abs() < 1e-12);
        // Two tables 5 cm apart in height are no one support.
        assert!(SupportHeight::fuse(&[obs("a", 0.0, 0.0), obs("b", 0.05, 0.1)], 1e-4).is_none());
    }

    /// A height within the noise, flatness and level of a measured support holds; 19 mm above
    /// it (a brick spinning on a corner, its line taken for an edge on the table) does not; a
    /// given height's σ is all there is.
    #[test]
    fn a_height_holds_within_the_supports_uncertainty_only() {
        let s = SupportHeight::fuse(&[obs("a", 0.0005, 0.0), obs("b", -0.0005, 0.2)], 1e-4)
            .expect("agree");
        assert!(s.holds(&obs("c", 0.002, 0.1), 1e-4));
        assert!(!s.holds(&obs("c", 0.019, 0.1), 1e-4));
        let given =
            SupportHeight::fuse(&[SupportObservation::given(0.0, 1e-4).unwrap()], 1e-4).unwrap();
        assert!(given.holds(&obs("c", 0.0003, 0.0), 1e-4));
        assert!(!given.holds(&obs("c", 0.002, 0.0), 1e-4));
    }

    /// A 16-frame landing on its −z face at `height`, at `across`, under 1 mm of noise.
    fn landing_at(height: f64, across: Vector3<f64>) -> Landing {
        let noise = NoiseModel {
            sigma_position: 1e-3,
            sigma_rotation: 0.01,
        };
        let place = RestPlace { height, across };
        Landing::new("c", &Vector3::new(0.0, 0.0, -1.0), place, 16, &noise)
    }

    #[test]
    fn a_landing_is_its_face_offset_above_the_support() {
        let s = SupportHeight::fuse(&[obs("a", 0.7, 0.0), obs("b", 0.7, 0.0)], 1e-4).unwrap();
        let l = landing_at(0.735, Vector3::new(0.3, 0.4, 0.0));
        let (d, var) = s.offset_of(&l);
        assert!((d - 0.035).abs() < 1e-12);
        // Noise of both, flatness at two places, and a 1° tilt over the 0.5 m between them.
        let tilt = (SUPPORT_LEVEL_SIGMA_RAD * 0.5).powi(2);
        let expected = 1e-6 / 16.0 + s.sigma_m.powi(2) + 2.0 * SUPPORT_FLATNESS_M.powi(2) + tilt;
        assert!((var / expected - 1.0).abs() < 1e-9, "{var} vs {expected}");
    }

    #[test]
    fn a_given_height_must_be_finite_and_its_sigma_positive() {
        for (h, s) in [
            (f64::NAN, 1e-3),
            (f64::INFINITY, 1e-3),
            (0.0, 0.0),
            (0.0, -1e-3),
            (0.0, f64::NAN),
            (0.0, f64::INFINITY),
        ] {
            let e = SupportObservation::given(h, s).unwrap_err().to_string();
            assert!(e.contains("must be finite"), "{h} {s}: {e}");
        }
        assert!(SupportObservation::given(-0.3, 1e-6).is_ok());
    }

    #[test]
    fn a_given_height_is_the_supports_alone_and_its_sigma_is_the_offsets() {
        // Alone, and beside two demonstrations that measured another height.
        let given = SupportObservation::given(0.01, 1e-3).unwrap();
        let s = SupportHeight::fuse(std::slice::from_ref(&given), 1e-4).expect("given");
        assert!(s.given && s.height == 0.01 && s.sigma_m == 1e-3);
        let all = [obs("a", 0.0, 0.0), given.clone(), obs("b", 0.0, 0.2)];
        assert_eq!(SupportHeight::fuse(&all, 1e-4), Some(s.clone()));
        let l = landing_at(0.06, Vector3::new(3.0, 4.0, 0.0));
        let (d, var) = s.offset_of(&l);
        assert!((d - 0.05).abs() < 1e-12);
        // No tilt over the 5 m from the origin: the given σ holds the plane's level.
        assert!((var - (1e-6 / 16.0 + 1e-6)).abs() < 1e-15, "{var}");
    }

    /// The fused height's σ is honest: over many supports measured as the model says (noise,
    /// flatness at each place), the median |error|/σ is near 0.67 and none exceeds 5.
    #[test]
    fn the_fused_height_sigma_is_honest() {
        let mut rng = rand::rngs::StdRng::seed_from_u64(3);
        let unit = Normal::new(0.0, 1.0).unwrap();
        let mut z = Vec::new();
        for _ in 0..2000 {
            let n = rng.random_range(2..8);
            let all: Vec<SupportObservation> = (0..n)
                .map(|k| {
                    let sigma = 1e-4 * (1.0 + 4.0 * rng.random::<f64>());
                    SupportObservation {
                        demo: format!("d{k}"),
                        height: unit.sample(&mut rng) * sigma
                            + unit.sample(&mut rng) * SUPPORT_FLATNESS_M,
                        sigma_m: sigma,
                        across: Vector3::zeros(),
                        from: "topple".to_string(),
                    }
                })
                .collect();
            if let Some(s) = SupportHeight::fuse(&all, 1e-4) {
                z.push(s.height.abs() / s.sigma_m);
            }
        }
        z.sort_by(f64::total_cmp);
        let median = z[z.len() / 2];
        assert!(z.len() > 1990, "{} fused", z.len());
        assert!((0.5..0.85).contains(&median), "median {median}");
        assert!(z.last().unwrap() < &5.0, "max {}", z.last().unwrap());
    }
}
