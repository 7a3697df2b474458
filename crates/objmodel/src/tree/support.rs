//! The tree's support ([`crate::support`]): every demonstration's measurements of the support's
//! height are kept (those of a demonstration with a withheld edge are not used:
//! `tree/landing_edges.rs`); the height they agree on, if they do, gives each confirmed landing's face
//! observation its offset, and the face's offset σ holds the support's error once (it is
//! common to all its landings). A height the user gives ([`Tree::give_support`]) is kept with
//! the measurements and is the support's.

use super::{Tree, MATCH_ALPHA};
use crate::face::FaceSource;
use crate::support::{SupportHeight, SupportObservation};

impl Tree {
    /// Take `given` as the support's height ([`SupportObservation::given`]; it replaces one
    /// given before), and recompute what depends on it: the landings' face offsets, the shape.
    pub fn give_support(&mut self, given: SupportObservation) {
        self.supports.retain(|o| !o.is_given());
        self.supports.push(given);
        self.refit_whole();
    }

    /// Fuse the support's height from its observations, and give each face observation of a
    /// confirmed landing the offset it implies (none without a height).
    pub(super) fn refit_support(&mut self) {
        // A withheld edge's line is not on the support: its demonstration's measurements of
        // the support's height (the same lines) are left out with it.
        let withheld: Vec<&str> = self
            .withheld_edges
            .iter()
            .flat_map(|w| w.edge.observations.iter().map(|o| o.demo.as_str()))
            .collect();
        let kept: Vec<crate::support::SupportObservation> = self
            .supports
            .iter()
            .filter(|o| !withheld.contains(&o.demo.as_str()))
            .cloned()
            .collect();
        self.support = SupportHeight::fuse(&kept, MATCH_ALPHA);
        let (faces, landings, support) = (&mut self.faces, &self.landings, &self.support);
        for f in faces.iter_mut() {
            let mut changed = false;
            for o in f.observations.iter_mut().filter(|o| on_support(o)) {
                let landing = landings.iter().find(|l| l.confirmed && l.taught(o));
                let (offset, var) = match (support, landing, o.rest_height) {
                    (Some(s), Some(l), _) => {
                        let (d, v) = s.offset_of(l);
                        (Some(d), Some(v))
                    }
                    // A rest beside no flight or topple: only at a height the user gave
                    // (measured heights give the confirmed landings theirs alone).
                    (Some(s), None, Some(r)) if s.given => {
                        let (d, v) = s.offset_at(&r.place, r.sigma_m);
                        (Some(d), Some(v))
                    }
                    _ => (None, None),
                };
                changed |= o.offset != offset || o.offset_var != var;
                o.offset = offset;
                o.offset_var = var;
            }
            let from_landings = f
                .observations
                .iter()
                .any(|o| on_support(o) && o.offset.is_some());
            if changed || from_landings {
                f.refit();
            }
            if let (Some(s), Some(sigma), true) = (support, f.offset_sigma_m, from_landings) {
                f.offset_sigma_m = Some((sigma * sigma + common_var(f, s.sigma_m)).sqrt());
            }
        }
    }
}

/// Whether a face observation is a rest on the support, whose offset the support's height
/// gives: a landing's, or a rest's beside no topple with its place.
fn on_support(o: &crate::face::FaceObservation) -> bool {
    o.source == FaceSource::Landing || o.rest_height.is_some()
}

/// What the weighted mean of a face's offsets leaves out of its variance: the support's
/// height error `sigma_z` is one error common to every landing's offset, and does not average
/// out over them as the mean assumes. The mean `Σ wᵢ dᵢ / W` takes it in with the weight of the
/// landings, `W_L / W`; its variance counted `Σ_L wᵢ² σ_z² / W²` of it.
fn common_var(f: &super::Face, sigma_z: f64) -> f64 {
    let weights = f
        .observations
        .iter()
        .filter_map(|o| Some((on_support(o), 1.0 / (o.offset_var? + 1e-12))));
    let (mut w, mut w_l, mut w2_l) = (0.0, 0.0, 0.0);
    for (landing, wi) in weights {
        w += wi;
        if landing {
            w_l += wi;
            w2_l += wi * wi;
        }
    }
    if w <= 0.0 {
        return 0.0;
    }
    sigma_z * sigma_z * ((w_l / w).powi(2) - w2_l / (w * w)).max(0.0)
}
