//! The tree's landings ([`crate::landing`]): every landing is kept, and a landing teaches its
//! face once a landing of another demonstration agrees with it (χ², 3 dof, at
//! [`MATCH_ALPHA`]); the face observation goes when the last landing that agreed does.

use super::{Tree, MATCH_ALPHA};
use crate::face::FaceSource;
use crate::landing::Landing;

impl Tree {
    /// Keep a demonstration's landings; each that another demonstration's agrees with, and
    /// each earlier one that it is the first to agree with, teaches its face.
    pub(super) fn add_landings(&mut self, landings: Vec<Landing>) {
        let gate = crate::stats::chi2_threshold(3.0, MATCH_ALPHA);
        for mut new in landings {
            let mut confirmed_now = Vec::new();
            for (i, old) in self.landings.iter_mut().enumerate() {
                if old.demo != new.demo && old.chi2(&new) < gate {
                    new.confirmed = true;
                    if !old.confirmed {
                        old.confirmed = true;
                        confirmed_now.push(i);
                    }
                }
            }
            if new.confirmed {
                confirmed_now.push(self.landings.len());
            }
            self.landings.push(new);
            for i in confirmed_now {
                self.add_face(self.landings[i].face());
            }
        }
    }

    /// After the landings of a removed demonstration are gone: each landing that no other
    /// demonstration's agrees with any more no longer teaches its face.
    pub(super) fn reconfirm_landings(&mut self) {
        let gate = crate::stats::chi2_threshold(3.0, MATCH_ALPHA);
        for i in 0..self.landings.len() {
            let l = &self.landings[i];
            let agreed = self
                .landings
                .iter()
                .any(|o| o.demo != l.demo && o.chi2(l) < gate);
            if l.confirmed && !agreed {
                let taught = l.face();
                for f in &mut self.faces {
                    f.observations.retain(|o| {
                        !(o.source == FaceSource::Landing
                            && o.demo == taught.demo
                            && o.frames == taught.frames
                            && o.normal == taught.normal)
                    });
                }
                self.landings[i].confirmed = false;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::landing::RestPlace;
    use crate::noise::NoiseModel;
    use nalgebra::Vector3;

    fn landing(demo: &str, down: [f64; 3], height: f64, x: f64) -> Landing {
        let noise = NoiseModel {
            sigma_position: 1e-3,
            sigma_rotation: 0.5f64.to_radians(),
        };
        let place = RestPlace {
            height,
            across: Vector3::new(x, 0.0, 0.0),
        };
        Landing::new(demo, &Vector3::from(down), place, 20, &noise)
    }

    fn landing_faces(t: &Tree) -> usize {
        t.faces.iter().filter(|f| f.evidence.landing > 0).count()
    }

    #[test]
    fn a_landing_teaches_its_face_only_when_another_demonstration_agrees() {
        let mut t = Tree::default();
        t.add_landings(vec![landing("a", [0.0, 0.0, -1.0], 0.05, 0.0)]);
        assert_eq!(landing_faces(&t), 0, "alone");
        // The same demonstration again, a later rest: no confirmation.
        t.add_landings(vec![landing("a", [0.0, 0.0, -1.0], 0.05, 0.1)]);
        assert_eq!(landing_faces(&t), 0, "one demonstration");
        // Another demonstration, the same down 30 mm higher (held, not on the support).
        t.add_landings(vec![landing("b", [0.0, 0.0, -1.0], 0.08, 0.1)]);
        assert_eq!(landing_faces(&t), 0, "another height");
        // Another demonstration, another face at the same height.
        t.add_landings(vec![landing("c", [0.0, 1.0, 0.0], 0.05, 0.1)]);
        assert_eq!(landing_faces(&t), 0, "another down");
        // Agreement: both of a's landings and the new one teach one face.
        t.add_landings(vec![landing("d", [0.002, 0.0, -1.0], 0.0505, 0.2)]);
        assert_eq!(landing_faces(&t), 1);
        assert_eq!(t.faces[0].observations.len(), 3);
        assert_eq!(t.faces[0].evidence.landing, 3);
        assert!(t.faces[0].sign_known);
        assert!(t.faces[0].normal.z < -0.999);
    }

    #[test]
    fn removing_the_demonstration_that_agreed_takes_the_face_back() {
        let mut t = Tree::default();
        t.add_landings(vec![landing("a", [0.0, 0.0, -1.0], 0.05, 0.0)]);
        t.add_landings(vec![landing("b", [0.0, 0.0, -1.0], 0.05, 0.1)]);
        assert_eq!(landing_faces(&t), 1);
        t.remove_demo("b");
        assert!(t.faces.is_empty(), "{:?}", t.faces);
        assert_eq!(t.landings.len(), 1);
        assert!(!t.landings[0].confirmed);
        // Back again: the same tree as before, whichever order.
        t.add_landings(vec![landing("b", [0.0, 0.0, -1.0], 0.05, 0.1)]);
        let mut u = Tree::default();
        u.add_landings(vec![landing("b", [0.0, 0.0, -1.0], 0.05, 0.1)]);
        u.add_landings(vec![landing("a", [0.0, 0.0, -1.0], 0.05, 0.0)]);
        assert_eq!(landing_faces(&t), 1);
        assert!((t.faces[0].normal - u.faces[0].normal).norm() < 1e-12);
        assert_eq!(t.faces[0].n_support, u.faces[0].n_support);
    }
}
