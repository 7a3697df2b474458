//! The tree's landings ([`crate::landing`]): every landing is kept, and whenever one comes or
//! goes, each is decided again over all of them: a landing teaches its face while a landing of
//! another demonstration agrees with it (χ², 3 dof, at [`MATCH_ALPHA`]) and no landing at its
//! height has a down less than [`SAME_FACE_RAD`] from its own that disagrees with it (a curved
//! side, not a face). A face observation comes and goes with its landing's confirmation.

use super::{Tree, MATCH_ALPHA, SAME_FACE_RAD};
use crate::landing::Landing;

impl Tree {
    /// Keep a demonstration's landings, and decide again every landing they may change.
    pub(super) fn add_landings(&mut self, landings: Vec<Landing>) {
        self.landings.extend(landings.iter().cloned());
        self.refit_landings(&landings);
    }

    /// Decide again ([`confirmed`]) every landing that the landings `changed` (added or
    /// removed) may change: those at a height a test could not tell from theirs. Each newly
    /// confirmed teaches its face, each no longer confirmed has its face observation taken
    /// back (and a face left without observations goes).
    pub(super) fn refit_landings(&mut self, changed: &[Landing]) {
        let gate3 = crate::stats::chi2_threshold(3.0, MATCH_ALPHA);
        let near: Vec<usize> = (0..self.landings.len())
            .filter(|&i| {
                changed
                    .iter()
                    .any(|c| self.landings[i].chi2_height(c) < gate3)
            })
            .collect();
        let now: Vec<(usize, bool)> = near
            .iter()
            .map(|&i| (i, confirmed(&self.landings, i)))
            .collect();
        let mut taken_back = false;
        for (i, c) in now {
            let was = self.landings[i].confirmed;
            self.landings[i].confirmed = c;
            if c && !was {
                self.add_face(self.landings[i].face());
            } else if was && !c {
                let landing = &self.landings[i];
                for f in &mut self.faces {
                    f.observations.retain(|o| !landing.taught(o));
                }
                taken_back = true;
            }
        }
        if taken_back {
            self.prune_faces();
        }
    }
}

/// Whether landing `i` of `all` teaches its face: a landing of another demonstration agrees
/// with it, and none at its height has a down within [`SAME_FACE_RAD`] that disagrees.
fn confirmed(all: &[Landing], i: usize) -> bool {
    let gate3 = crate::stats::chi2_threshold(3.0, MATCH_ALPHA);
    let gate2 = crate::stats::chi2_threshold(2.0, MATCH_ALPHA);
    let gate1 = crate::stats::chi2_threshold(1.0, MATCH_ALPHA);
    let l = &all[i];
    let agreed = all.iter().any(|o| o.demo != l.demo && l.chi2(o) < gate3);
    let continuum = all.iter().enumerate().any(|(j, o)| {
        j != i
            && l.chi2_height(o) < gate1
            && l.chi2_down(o) >= gate2
            && l.angle_to(o) < SAME_FACE_RAD
    });
    agreed && !continuum
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
    fn rests_along_a_curved_side_teach_no_face() {
        // A cylinder on its side: every rest at one height, its down anywhere on a circle.
        let mut t = Tree::default();
        t.add_landings(vec![landing("a", [0.0, 0.0, -1.0], 0.03, 0.0)]);
        t.add_landings(vec![landing("b", [0.01, 0.0, -1.0], 0.03, 0.1)]);
        assert_eq!(landing_faces(&t), 1, "two rests alone look like a face");
        // A third, 12 degrees round the side: the rests form a continuum, and the face goes.
        let (s, c) = 12f64.to_radians().sin_cos();
        t.add_landings(vec![landing("c", [s, 0.0, -c], 0.03, 0.2)]);
        assert_eq!(landing_faces(&t), 0, "{:?}", t.faces);
        assert!(t.landings.iter().all(|l| !l.confirmed));
        // Any order gives the same.
        let mut u = Tree::default();
        u.add_landings(vec![landing("c", [s, 0.0, -c], 0.03, 0.2)]);
        u.add_landings(vec![landing("b", [0.01, 0.0, -1.0], 0.03, 0.1)]);
        u.add_landings(vec![landing("a", [0.0, 0.0, -1.0], 0.03, 0.0)]);
        assert_eq!(landing_faces(&u), 0);
        // A box's next face (90 degrees away) at the same height does not block it.
        let mut v = Tree::default();
        v.add_landings(vec![landing("a", [0.0, 0.0, -1.0], 0.03, 0.0)]);
        v.add_landings(vec![landing("b", [0.01, 0.0, -1.0], 0.03, 0.1)]);
        v.add_landings(vec![landing("c", [1.0, 0.0, 0.0], 0.03, 0.2)]);
        assert_eq!(landing_faces(&v), 1);
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
