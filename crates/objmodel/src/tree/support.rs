//! The tree's support ([`crate::support`]): every demonstration's measurements of the support's
//! height are kept (those of a demonstration with a withheld edge are not used:
//! `tree/landing_edges.rs`); the height they agree on, if they do, gives each confirmed landing's face
//! observation its offset, and the face's offset σ holds the support's error once (it is
//! common to all its landings).

use super::{Tree, MATCH_ALPHA};
use crate::face::FaceSource;
use crate::support::SupportHeight;

impl Tree {
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
            for o in f
                .observations
                .iter_mut()
                .filter(|o| o.source == FaceSource::Landing)
            {
                let landing = landings.iter().find(|l| l.confirmed && l.taught(o));
                let (offset, var) = match (support, landing) {
                    (Some(s), Some(l)) => {
                        let (d, v) = s.offset_of(l);
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
                .any(|o| o.source == FaceSource::Landing && o.offset.is_some());
            if changed || from_landings {
                f.refit();
            }
            if let (Some(s), Some(sigma), true) = (support, f.offset_sigma_m, from_landings) {
                f.offset_sigma_m = Some((sigma * sigma + common_var(f, s.sigma_m)).sqrt());
            }
        }
    }
}

/// What the weighted mean of a face's offsets leaves out of its variance: the support's
/// height error `sigma_z` is one error common to every landing's offset, and does not average
/// out over them as the mean assumes. The mean `Σ wᵢ dᵢ / W` takes it in with the weight of the
/// landings, `W_L / W`; its variance counted `Σ_L wᵢ² σ_z² / W²` of it.
fn common_var(f: &super::Face, sigma_z: f64) -> f64 {
    let weights = f.observations.iter().filter_map(|o| {
        Some((
            o.source == FaceSource::Landing,
            1.0 / (o.offset_var? + 1e-12),
        ))
    });
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
