//! Were the quaternions read in the order they were written? A TUM file says nothing of it, and
//! a file written `qw qx qy qz` (MuJoCo, Drake, transforms3d, pyquaternion) read as TUM's
//! `qx qy qz qw` is another rotation at every frame: its rests then teach faces that are not
//! on the object, with confidence.
//!
//! The motion tells, where it turns about an edge. Read in the wrong order, a rotation about a
//! fixed edge is no longer one: the strict model of Algorithm 1 explains those frames only in
//! the right order. So where a demonstration read as configured has moving frames that teach
//! no edge (general motion, a slide, a mode withheld), it is read again in the other order;
//! when that reading teaches an edge, located as the tree needs to teach it, over frames that
//! the first explains by no edge, and the first teaches no edge where the other reading finds
//! none, the demonstration teaches nothing and says which order to give ([`explains_more`]
//! says what counts). Slides are no evidence: a slide that does not turn is one in both orders
//! (its orientation is constant either way), and one that a reading does not teach, for
//! reasons of its own (a compound's slide at a camera's noise), the other may. A motion that
//! both orders explain alike (such a slide, a carry, a box upside down) leaves the two
//! undecided, and nothing is said here; learnt together with others, its rests may still show
//! the vertical only in the other order ([`super::gravity_check`]).
//!
//! Measured on the standard data set (1844 files: every kind and noise level, 40 tosses), each
//! demonstration learnt alone: as written, the same 378 edges and 1104 faces as without the
//! check (every one true); written w first and read as x y z w, 73 faces, all wrong, where
//! there were 203 (197 wrong).
//!
//! Only the robust method's classifications are checked (its tests are the strict ones; the
//! paper's method withholds the edge of the 10⁶-pose benchmark's topple, which does not start
//! from a rest, and reading that file twice doubled its time). Only files that do not name
//! their columns are read again (TUM; a CSV header names its columns, which decide), and not
//! standard input, which cannot be read twice; and poses in memory where the learner is told
//! they were read from quaternions in the configured order
//! ([`Learner::with_memory_quaternions`], the Python package's array rows).

use super::{Learner, Source};
use crate::classify::{Classification, Kind, Method};
use crate::edge::{max_sigmas, unlocated};
use crate::format::{PoseFile, QuaternionOrder};
use crate::trajectory::Demonstration;
use crate::tree::LOCATED_ALPHA;
use crate::Result;
use std::path::Path;

/// The time spans \[s\] over which `c` teaches an edge: its segments with one, its rolls
/// taught.
fn edge_spans(c: &Classification) -> impl Iterator<Item = (f64, f64)> + '_ {
    let segments = c
        .segments
        .iter()
        .filter(|s| s.edge.is_some())
        .map(|s| (s.t_start, s.t_end));
    let rolls = c
        .rolls
        .iter()
        .filter(|r| r.taught)
        .map(|r| (r.t_start, r.t_end));
    segments.chain(rolls)
}

/// Whether `c` has moving frames that teach no edge: a segment without one.
fn has_motion_without_edge(c: &Classification) -> bool {
    c.segments.iter().any(|s| s.edge.is_none())
}

/// Where `b` teaches a located edge over motion where `a` finds none (the first such segment's
/// time span \[s\]): the middle of one of `b`'s topple segments with a located edge lies in a segment of `a` without an edge that is
/// general motion, a slide, or a topple by fewer than half as many frames' votes, outside every
/// span over which `a` teaches an edge ([`edge_spans`]).
///
/// Not evidence: an edge located loosely (at a camera's noise, a slide that turns 21° read in
/// the wrong order passed as a rotation about a line 24 cm from the object, at ±6.6 mm); a
/// roll (a short turn: a slide of Drake's turning 89° at 0.2 mm, read in the wrong order, held
/// an 8.7° turn about a line taught as a roll); and a topple that `a` finds as well but does
/// not teach (a box turned upside down, a half turn about a horizontal axis, reads as another
/// half turn in the other order, and its topple as a topple about another edge: a topple of
/// Drake's, 220 frames' votes as read, its edge 3.7° from level and not taught, and 219 in the
/// other order, taught). A topple read in the wrong order that still votes topple does so in
/// few frames (12 against 194 in the right order, in a test below).
fn explains_more(b: &Classification, a: &Classification) -> Option<(f64, f64)> {
    let edges_of_a: Vec<(f64, f64)> = edge_spans(a).collect();
    let within = |t: f64, (t0, t1): (f64, f64)| t0 <= t && t <= t1;
    let located = max_sigmas(LOCATED_ALPHA);
    b.segments
        .iter()
        .filter(|s| {
            s.edge
                .as_ref()
                .is_some_and(|e| unlocated(e, located, "").is_none())
        })
        .find(|sb| {
            let middle = 0.5 * (sb.t_start + sb.t_end);
            let no_edge_in_a = a.segments.iter().any(|sa| {
                sa.edge.is_none()
                    && (sa.kind != Kind::Topple || 2 * sa.votes.topple < sb.votes.topple)
                    && within(middle, (sa.t_start, sa.t_end))
            });
            no_edge_in_a && !edges_of_a.iter().any(|&span| within(middle, span))
        })
        .map(|sb| (sb.t_start, sb.t_end))
}

/// Whether the object's poses in a pose file are read in the configured order: a file (not
/// standard input) that does not name its columns.
fn file_read_in_configured_order(object: &Path) -> bool {
    object.as_os_str() != "-"
        && PoseFile::whole(object)
            .read_first_declared(1)
            .is_ok_and(|(_, declared)| !declared.named_columns)
}

/// `demo` with every rotation, read in `order`, read in the other.
fn read_in_other_order(demo: &Demonstration, order: QuaternionOrder) -> Demonstration {
    let mut d = demo.clone();
    let poses = d.object.iter_mut().chain(d.palm.iter_mut().flatten());
    for p in poses {
        p.pose.rotation = order.read_in_other(&p.pose.rotation);
    }
    d
}

impl Learner {
    /// Whether the object's poses in `source` are read in the configured order: a pose file
    /// (not standard input) that does not name its columns, or poses in memory read so
    /// ([`Learner::with_memory_quaternions`]).
    pub(super) fn read_in_configured_order(&self, source: &Source) -> bool {
        match *source {
            Source::Files { object, .. } => file_read_in_configured_order(object),
            Source::Memory(_) => self.memory_quaternions,
            Source::Take { .. } | Source::Bag { .. } => false,
        }
    }

    /// `c`, the classification of `source` read in the configured quaternion order, withheld
    /// whole where the other order explains its motion better (see the module's doc), with
    /// the order to give.
    pub(super) fn order_checked(
        &self,
        source: &Source,
        mut c: Classification,
    ) -> Result<Classification> {
        if self.config.method != Method::Robust
            || !has_motion_without_edge(&c)
            || !self.read_in_configured_order(source)
        {
            return Ok(c);
        }
        let given = self.config.quaternion_order;
        let swapped = Learner {
            config: self.config.with_quaternion_order(given.other()),
            ..self.clone()
        };
        let b = match *source {
            Source::Memory(demo) => {
                let other = read_in_other_order(demo, given);
                swapped
                    .classify_recorded_in_order(&Source::Memory(&other))?
                    .0
            }
            _ => swapped.classify_recorded_in_order(source)?.0,
        };
        if let (Some((t0, t1)), None) = (explains_more(&b, &c), explains_more(&c, &b)) {
            c.withhold_all(&format!(
                "its quaternions look written in {} order: read so, it turns about an edge \
                 over {t0:.2}-{t1:.2} s, where read {}, as now, no edge explains that motion; \
                 give --quat-order {} (in Python, quat_order=\"{}\") if they are written so \
                 (TUM's own order is x y z w)",
                given.other().spelled(),
                given.spelled(),
                given.other(),
                given.other(),
            ));
        }
        Ok(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::classify::{classify, Config};
    use crate::synth::{self, SynthBox, SynthNoise, ToppleParams};
    use nalgebra::Vector3;
    use rand::{rngs::StdRng, SeedableRng};

    fn classified(demo: &crate::Demonstration) -> Classification {
        classify(demo, &Config::default()).expect("classified")
    }

    /// `demo` as a reader that takes `qw qx qy qz` for `qx qy qz qw` sees it.
    /// (Written w x y z, read x y z w: what a reader in w x y z order reads, read in the other;
    /// `QuaternionOrder::read_in_other` is tested against the components moved by hand.)
    fn read_w_first_as_x_first(demo: &crate::Demonstration) -> crate::Demonstration {
        read_in_other_order(demo, QuaternionOrder::Wxyz)
    }

    /// A topple tracked at motion-capture noise (0.3 mm, 0.1°, 120 Hz, with sign flips), whose
    /// edge is located well enough to teach.
    fn topple(b: &SynthBox, side: usize, seed: u64) -> crate::Demonstration {
        let p = ToppleParams {
            side,
            ..Default::default()
        };
        let mocap = SynthNoise {
            sigma_position: 3e-4,
            sigma_rotation: 0.1f64.to_radians(),
            ..SynthNoise::REAL
        };
        synth::topple(b, &p, &mocap, 120.0, seed).demo
    }

    #[test]
    fn a_topple_read_in_the_wrong_order_is_explained_better_the_right_way() {
        let mut rng = StdRng::seed_from_u64(11);
        for seed in 0..4 {
            let b = SynthBox::random(&mut rng);
            let demo = topple(&b, seed as usize, seed);
            let right = classified(&demo);
            assert_eq!(right.kind, Kind::Topple, "seed {seed}");
            let wrong = classified(&read_w_first_as_x_first(&demo));
            assert!(has_motion_without_edge(&wrong), "seed {seed}");
            let span = explains_more(&right, &wrong).expect("the right order explains more");
            assert!(right.segments.iter().any(|s| (s.t_start, s.t_end) == span));
            assert!(explains_more(&wrong, &right).is_none(), "seed {seed}");
        }
    }

    #[test]
    fn a_demonstration_does_not_explain_more_than_itself() {
        let b = SynthBox::new(Vector3::new(0.05, 0.04, 0.08), (0.0, 0.0), 0.2);
        let demo = topple(&b, 1, 7);
        let c = classified(&demo);
        assert!(explains_more(&c, &c).is_none());
        assert!(!has_motion_without_edge(&c));
    }

    /// Poses in memory read from quaternions written w first as x y z w are checked where the
    /// learner is told they were read from numbers ([`Learner::with_memory_quaternions`]);
    /// rotations given as such (the default) are not.
    #[test]
    fn poses_in_memory_read_from_numbers_in_the_wrong_order_teach_nothing() {
        let b = SynthBox::new(Vector3::new(0.05, 0.04, 0.08), (0.01, 0.0), 0.4);
        let demo = read_w_first_as_x_first(&topple(&b, 2, 5));
        let source = Source::Memory(&demo);
        let learner = Learner::new(Config::default());
        let as_given = learner.classify(&source).expect("classified");
        assert!(as_given.withheld.is_none());
        let read = learner.with_memory_quaternions();
        let checked = read.classify(&source).expect("classified");
        let why = checked.withheld.expect("withheld");
        assert!(why.contains("written in w x y z order"), "{why}");
        // Given as they were written, nothing is said.
        let right = topple(&b, 2, 5);
        let c = read.classify(&Source::Memory(&right)).expect("classified");
        assert!(c.withheld.is_none() && !c.topples.is_empty());
    }
}
