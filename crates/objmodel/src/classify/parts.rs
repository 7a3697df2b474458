//! The parts of a segment and what each must show before it teaches: where a part ends
//! (`part_end`), whether it follows another motion without a rest between and so is not
//! measured from its own start (`after_other_motion`), whether its feature is level as a
//! contact on a level support is (`direction_off_level`, `face_off_level`), and whether a completed
//! topple's edge is on the support in both its rests (`edge_on_support`).

use super::block::Block;
use super::segments::MotionSegment;
use super::Label;
use crate::edge::{EdgeObservation, PointConstraint};
use crate::face::{FaceObservation, SUPPORT_LEVEL_SIGMA_RAD};
use crate::landing::{RestPlace, SUPPORT_FLATNESS_M};
use crate::noise::NoiseModel;
use nalgebra::{UnitQuaternion, Vector3};

/// Whether an edge's direction `u` (covariance `cov`) is not level: an edge a box topples
/// about lies in the face it rests on, and that face lies on a level support (a table, or a
/// palm in the palm's frame) to within [`SUPPORT_LEVEL_SIGMA_RAD`]. The edge's tilt from level
/// (its direction's component along "down" `d`) is tested against that and the direction's own
/// variance along `d`, χ²₁ at `alpha`. (The segment's fits only bound the tilt by
/// [`super::RobustConfig::max_axis_tilt_rad`], a search bound; a thrown box's flight from a
/// hand passed it with an "edge" 20° from level.) A topple's edge is tested with its
/// covariance before the split-half lack of fit of its axis (`classify::analysis`); a roll's
/// edge in the world ([`crate::roll`]) with its own.
pub(crate) fn direction_off_level(
    u: &Vector3<f64>,
    cov: &nalgebra::Matrix3<f64>,
    d: &Vector3<f64>,
    alpha: f64,
) -> Option<String> {
    let sin_tilt = u.dot(d).clamp(-1.0, 1.0);
    let var = d.dot(&(cov * d)) + SUPPORT_LEVEL_SIGMA_RAD.powi(2);
    let tilt = sin_tilt.asin();
    (tilt * tilt / var > crate::stats::chi2_threshold(1.0, alpha)).then(|| {
        format!(
            "its direction is {:.1}° from level (±{:.1}°), and {OFF_LEVEL}",
            tilt.abs().to_degrees(),
            var.sqrt().to_degrees()
        )
    })
}

/// The end of the reason an edge off level is not taught (`direction_off_level`); a part
/// withheld so is not scanned for rolls (`crate::roll`): its turn was about a line out of the
/// face it stood on (a box pivoting on a corner), and windows of it pass for rolls whose lines
/// are still off level, each by too little to fail alone (Drake: a roll 3.0° from level at
/// ±0.4° inside a topple 6.8° from level, 3.2° off the box's edge).
pub const OFF_LEVEL: &str = "an edge toppled about lies in the level face the object rests on";

/// Variance \[m²\] of the difference between a support's heights, as a contact on it sees them,
/// at two places `distance` \[m\] apart: its level across the distance
/// ([`SUPPORT_LEVEL_SIGMA_RAD`]: the tracking frame's "up" tilted from the support's normal),
/// its departure from a plane, which grows with the distance as its local slope allows (again
/// the level) up to its flatness ([`SUPPORT_FLATNESS_M`] per place), and the contact's own
/// wander in each of the two places (`contact_m`: a rounded edge, a soft contact; the
/// learner's edge tolerance). At one place only the contacts' wander remains.
pub fn height_difference_var(distance: f64, contact_m: f64) -> f64 {
    let level = (SUPPORT_LEVEL_SIGMA_RAD * distance).powi(2);
    level + level.min(2.0 * SUPPORT_FLATNESS_M.powi(2)) + 2.0 * contact_m.powi(2)
}

/// The start of the reason a completed topple's edge is not taught when it is off the support
/// (`edge_on_support`); a part withheld so is not scanned for rolls (`crate::roll`), whose
/// model is the same rotation about a fixed line, without the rests that refute it.
pub const OFF_SUPPORT: &str = "it is not on the support in both rests";

/// The rests before and after a motion, where the object's origin was and how it was turned
/// in each (`world_from_object`), and their frames: what [`edge_on_support`] tests an edge
/// against.
#[derive(Clone, Copy, Debug)]
pub(crate) struct RestPair {
    pub before: RestPlace,
    pub after: RestPlace,
    pub r_before: UnitQuaternion<f64>,
    pub r_after: UnitQuaternion<f64>,
    pub frames_before: f64,
    pub frames_after: f64,
}

impl RestPair {
    /// The pair, when both rests are known (gravity given) and of some length: a
    /// classification's first or last frames are called rest without the rest test (a file
    /// that starts or ends moving; the motion before a rest classified backwards,
    /// `crate::arrival`), and such a "rest" need not be on the support.
    fn new(
        places: (Option<RestPlace>, Option<RestPlace>),
        rotations: (Option<UnitQuaternion<f64>>, Option<UnitQuaternion<f64>>),
        frames: (f64, f64),
    ) -> Option<Self> {
        let window = crate::noise::SCATTER_WINDOW as f64;
        if frames.0 < window || frames.1 < window {
            return None;
        }
        Some(Self {
            before: places.0?,
            after: places.1?,
            r_before: rotations.0?,
            r_after: rotations.1?,
            frames_before: frames.0,
            frames_after: frames.1,
        })
    }

    /// The rests around a segment as the segmenter keeps it.
    pub(super) fn of_motion(seg: &MotionSegment) -> Option<Self> {
        Self::new(
            (seg.rest_before_place, seg.rest_after_place),
            (seg.rest_before_rotation, seg.rest_after_rotation),
            (seg.rest_before_frames, seg.rest_after_frames),
        )
    }

    /// The rests around a classified segment.
    pub(crate) fn of_segment(seg: &super::Segment) -> Option<Self> {
        Self::new(
            (seg.resting_place_before, seg.resting_place_after),
            (seg.resting_rotation_before, seg.resting_rotation_after),
            (
                seg.resting_frames_before as f64,
                seg.resting_frames_after as f64,
            ),
        )
    }
}

/// Whether a completed topple's edge lies on the support in both its rests, and what the rests
/// measure of it. An edge a box topples about lies on the support in the rest before (in the
/// face rested on) and in the rest after (in the next face, which meets the first at the
/// edge), and the support is the same: the edge's height along `up` must be the same in both
/// rests, within what the support and the contact allow between the places it touched
/// ([`height_difference_var`]), the rests' noise and the edge point's own covariance. A pushed
/// box whose edge slides on the table as it turns (about 0.25 mm per degree in MuJoCo, under a
/// finger that pushes it over) moves as a rotation about a line below the table: that line
/// passes every test of a rotation about a fixed line (at 120 Hz and 0.1 mm, one 10.7 mm off at
/// σ 0.7 mm), but its height differs between the rests by as much as it is off the edge. The
/// support is the table in the world, and the palm in the palm's frame (`up` is then the
/// palm's normal: the support's "down" taken where the palm was level).
///
/// The heights are compared where the edge touched the support in each rest: an edge toppled
/// about without slipping touches one place in both, and there only the contact's own wander
/// separates them ([`height_difference_var`]); at places apart, the support's level and
/// flatness too. (Compared at the object's two positions instead, 0.1-0.2 m apart, the
/// flatness of two places and the level across them let a MuJoCo push's edge 8.9 mm off pass.)
///
/// Where the edge passes, the rests measure its point along one direction to about the
/// contact's wander and the tracker's accuracy, often better than a short noisy fall does (at
/// 2 mm and 1°, 30 Hz, an edge point's σ is 1.6 mm in the median): the caller conditions the
/// edge on that measurement. On the standard data set at `noisy` this took the median edge
/// error per demonstration from 1.53 to 1.32 mm (`objmodel calibrate`), with no error beyond
/// 5σ.
///
/// Returns why the edge is not taught when the difference fails χ²₁ at `alpha`. Otherwise
/// the per-axis variance \[m²\] to add to the edge point's covariance (the difference's excess
/// over what the support, the rests and the edge's covariance explain: method of moments, zero
/// when it is within them, over the squared length of the direction it measures the point
/// along), and the measurement the rests make of the point: the difference is zero within the
/// support and the rests ([`EdgeObservation::condition_on`]). `None` where the rests are not
/// both long enough to tell.
pub(crate) fn edge_on_support(
    e: &EdgeObservation,
    rests: &RestPair,
    up: &Vector3<f64>,
    noise: &NoiseModel,
    contact_m: f64,
    alpha: f64,
) -> Result<Option<(f64, PointConstraint)>, String> {
    let (before, after) = (rests.before, rests.after);
    let p = e.line.point;
    let (r_before, r_after) = (
        rests.r_before.to_rotation_matrix(),
        rests.r_after.to_rotation_matrix(),
    );
    // The edge point's height in each rest is `place.height + up · (R p)`: the difference
    // measures the point along g.
    let g = (r_before.matrix() - r_after.matrix()).transpose() * up;
    let offset = before.height - after.height;
    let dh = offset + g.dot(&p);
    let per_frame = noise.sigma_position.powi(2) + (noise.sigma_rotation * p.norm()).powi(2);
    // A rest's mean pose is known to the tracker's accuracy, not its precision: the part of its
    // error that depends on the pose (a tag seen from another angle, a marker model) does not
    // average down over the rest's frames, and the two rests hold the object turned. It is
    // taken as large as the per-frame noise (the generators have none; a real tracker does).
    let rests = per_frame * (2.0 + 1.0 / rests.frames_before + 1.0 / rests.frames_after);
    // Where the edge touched the support in each rest (not where the object's origin was: an
    // edge toppled about without slipping touches the same place in both).
    let at = |place: &RestPlace, r: &nalgebra::Rotation3<f64>| r * p + place.position(&-up);
    let moved = at(&before, &r_before) - at(&after, &r_after);
    let distance = (moved - up * up.dot(&moved)).norm();
    let explained = height_difference_var(distance, contact_m) + rests;
    let var = explained + g.dot(&(e.point_cov * g));
    if dh * dh / var > crate::stats::chi2_threshold(1.0, alpha) {
        return Err(format!(
            "{OFF_SUPPORT}: its height in the rest after differs from that in the rest before \
             by {:.1} mm (±{:.1} mm), and an edge toppled about stays on the support (did it \
             slide or lift as the object turned?)",
            dh.abs() * 1e3,
            var.sqrt() * 1e3
        ));
    }
    let excess = ((dh * dh - var) / g.norm_squared().max(1e-12)).max(0.0);
    Ok(Some((
        excess,
        PointConstraint {
            g,
            offset,
            var: explained,
        },
    )))
}

/// Farthest \[m\] the contact's own wander ([`super::RobustConfig::edge_tolerance_m`]) may
/// move the axis of an edge rotation's largest rotation for the rotation to locate its edge.
pub const EDGE_LOCATION_M: f64 = 2e-3;

/// Whether a turn by `angle` \[rad\] is too small to locate an edge when the contact wanders by
/// `tolerance_m` (the chord `2 sin(θ/2)` below `tolerance_m / EDGE_LOCATION_M`; see
/// [`edge_turns_too_little`]): the frames of a palm topple before its fall, which may creep.
pub(crate) fn turn_locates_no_edge(angle: f64, tolerance_m: f64) -> bool {
    2.0 * (0.5 * angle).sin() < tolerance_m / EDGE_LOCATION_M
}

/// Whether an edge rotation turned too little to locate its edge: a rotation by θ whose
/// contact point wanders by δ (a rounded edge, a soft contact, micro-slip) has its screw axis
/// moved by up to δ / (2 sin(θ/2)), and that must stay within [`EDGE_LOCATION_M`]: at
/// δ = 0.3 mm, θ ≥ 8.6°. The noise does not bound this: with precise poses a box lagging 0.4°
/// behind a tilting palm, creeping 1 mm down it, turns about a line 6 cm below the box, within
/// the noise of every frame. A topple turns tens of degrees.
pub(crate) fn edge_turns_too_little(e: &EdgeObservation, tolerance_m: f64) -> Option<String> {
    let shift = tolerance_m / (2.0 * (0.5 * e.max_angle).sin());
    (shift > EDGE_LOCATION_M).then(|| {
        format!(
            "it turns only {:.2}° about its line, and a contact that wanders by {:.1} mm moves \
             the axis of such a rotation by {:.0} mm",
            e.max_angle.to_degrees(),
            tolerance_m * 1e3,
            shift * 1e3
        )
    })
}

/// Whether a slide's face is not level: the plane of a slide on a level support is level,
/// so its normal is "down" `d` to within [`SUPPORT_LEVEL_SIGMA_RAD`] and its own covariance
/// (per axis), χ²₂ at `alpha`.
pub(super) fn face_off_level(f: &FaceObservation, d: &Vector3<f64>, alpha: f64) -> Option<String> {
    let angle = f.normal.cross(d).norm().atan2(f.normal.dot(d));
    let var = f.sigma_normal().powi(2) + SUPPORT_LEVEL_SIGMA_RAD.powi(2);
    (angle * angle / var > crate::stats::chi2_threshold(2.0, alpha)).then(|| {
        format!(
            "its normal is {:.1}° from vertical (±{:.1}°), and a slide on a level support moves \
             in a level plane",
            angle.to_degrees(),
            var.sqrt().to_degrees()
        )
    })
}

/// Where a part of a segment ends: the start time \[s\] of the first run of at least
/// `min_frames` measurably moving frames that the part's model does not explain (`member`
/// false) after the part has started (infinity if none). Shorter runs are within the per-frame
/// tests' false alarms (and tag flips), and the part goes on through them; a run as long as a
/// part needs to be a part is another motion, after which the part's model (measured from the
/// segment's reference) no longer holds even if frames fit it again by chance.
pub(super) fn part_end(
    blocks: &[Block],
    idx: &[usize],
    mut member: impl FnMut(&Block) -> bool,
    min_frames: f64,
) -> f64 {
    let (mut started, mut run, mut run_start) = (false, 0u64, f64::INFINITY);
    for &i in idx {
        let b = &blocks[i];
        if b.significant == 0 || matches!(b.label, Label::Landing) {
            continue;
        }
        if member(b) {
            started = true;
            run = 0;
        } else if started {
            if run == 0 {
                run_start = b.t0;
            }
            run += b.significant;
            if run as f64 >= min_frames {
                return run_start;
            }
        }
    }
    f64::INFINITY
}

/// Whether the frames labelled `label` in a segment follow another mode of motion: at least
/// `min_frames` measurably moving frames labelled otherwise (topple, slide or general) before
/// the first of them. Every frame's motion is measured from the segment's reference, the rest
/// before the segment; a topple that starts after a slide (a push that slides a box and then
/// tips it, no rest between) turns about its edge *after* the slide's displacement, so its
/// frames' screws relative to the reference are the slide composed with the rotation, whose
/// axes are not the edge (they sweep by about the slide's length over the rotation), and a
/// line fitted to a subset of them is a wrong edge. Likewise for a slide after a topple or a
/// flight. `min_frames` is the evidence a part needs to be a part ([`super::MIN_EDGE_FRAMES`],
/// [`super::MIN_FACE_FRAMES`]): fewer frames labelled otherwise are within the per-frame tests'
/// false alarms. Frames that the part's own model explains as well (`explained`: a slide's
/// first frames that a rotation about the edge explains too, and are labelled topple by the
/// labels' priority) are ambiguous and do not count. Returns what the part follows, for the
/// report.
pub(super) fn after_other_motion(
    blocks: &[Block],
    idx: &[usize],
    label: Label,
    min_frames: f64,
    mut explained: impl FnMut(&Block) -> bool,
) -> Option<String> {
    let first = idx.iter().position(|&i| blocks[i].label == label)?;
    let (mut frames, mut t) = (0u64, None);
    let mut kinds: Vec<&str> = Vec::new();
    for &i in &idx[..first] {
        let b = &blocks[i];
        if explained(b) {
            continue;
        }
        let name = match b.label {
            Label::Topple => "topple",
            Label::Slide => "slide",
            Label::General => "general motion",
            _ => continue,
        };
        frames += b.significant;
        t.get_or_insert(b.t0);
        if b.significant > 0 && !kinds.contains(&name) {
            kinds.push(name);
        }
    }
    (frames as f64 >= min_frames).then(|| {
        format!(
            "starts at {:.2} s after {frames} frames of {} from {:.2} s without a rest \
             between, so it is not measured from its own start",
            blocks[idx[first]].t0,
            kinds.join(" and "),
            t.unwrap_or(0.0)
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Line;
    use nalgebra::Matrix3;

    fn edge_turning(angle_deg: f64) -> EdgeObservation {
        EdgeObservation {
            demo: "t".into(),
            line: Line {
                point: Vector3::new(0.05, 0.0, -0.1),
                direction: Vector3::y(),
            },
            point_cov: Matrix3::identity() * 1e-8,
            direction_cov: Matrix3::identity() * 1e-6,
            paper_line: None,
            frames: 30,
            max_angle: angle_deg.to_radians(),
            chi2_per_dof: 1.0,
            common_point_cov: nalgebra::Matrix3::zeros(),
        }
    }

    /// The bound follows from the wander: at 0.3 mm, 2 sin(θ/2) ≥ 0.15, θ ≥ 8.6°; a creep's
    /// 0.4° fails, a topple's 40° passes, and a contact that wanders less needs less rotation.
    #[test]
    fn an_edge_must_turn_far_enough_to_be_located() {
        assert!(edge_turns_too_little(&edge_turning(0.4), 3e-4).is_some());
        assert!(edge_turns_too_little(&edge_turning(8.0), 3e-4).is_some());
        assert!(edge_turns_too_little(&edge_turning(9.0), 3e-4).is_none());
        assert!(edge_turns_too_little(&edge_turning(40.0), 3e-4).is_none());
        assert!(edge_turns_too_little(&edge_turning(4.0), 1e-4).is_none());
    }
}
