//! What one finished segment teaches: its edge line and face plane fitted over its blocks
//! ([`super::msac`]), the change-point trimming of the edge, whether a topple completed, the
//! labels and votes the fits give, and the edge observation (topple) or face (slide).

use super::block::{Block, Phase};
use super::lack_of_fit::{
    mean_inv_chord, systematic_direction_var, systematic_normal_var, systematic_point_var,
    PointSums,
};
use super::msac::{
    fit_line, fit_plane, line_inlier, plane_inlier, rotation_explains_translation, slide_normal,
    Thresholds,
};
use super::parts::{
    after_other_motion, direction_off_level, edge_on_support, edge_turns_too_little,
    face_off_level, part_end, RestPair,
};
use super::segments::MotionSegment;
use super::{Config, Kind, Label, Segment, Votes};
use crate::edge::EdgeObservation;
use crate::face::{FaceObservation, FaceSource};
use crate::geometry::{Line, LineChi2, LineStats, PlaneStats};
use nalgebra::Vector3;

/// Change-point trimming keeps at least this many blocks of a topple...
const MIN_KEPT_BLOCKS: usize = 3;
/// ... and at least this fraction of its frames: in a fast topple the object may pivot for
/// only a third of the frames in which it turns, and fly or slide for the rest.
const MIN_KEPT_FRACTION: f64 = 0.2;

/// Fewest frames with a measurable screw axis that a segment's edge line must explain for the
/// segment to be a topple. One frame always has some screw axis, so a fixed line is testable
/// only from the second frame on, and a glitch of two frames (two tag flips in a row, which
/// single-frame rejection does not catch) can agree with itself; a real topple tracked at 10 Hz
/// or more has many more.
pub const MIN_EDGE_FRAMES: f64 = 3.0;

/// Fewest slide frames whose plane of motion a slide's face must explain to be taught, for the
/// same reason as [`MIN_EDGE_FRAMES`]: one frame's motion always has some plane (eq. 5), so a
/// fixed plane is testable only from the second frame on, and two frames can agree with
/// themselves (in a noisy instrumented topple of the rapier dataset, a 2-frame "slide" of no
/// rotation taught a face 35° from any face of the box, at ±4.4°).
pub const MIN_FACE_FRAMES: f64 = 3.0;

/// Change-point trimming of a fitted edge: at the end of a topple the object may leave or slip
/// along its edge, and such frames, each within the noise, still bias the line as a group, all
/// the more because the last frames of a topple (largest rotation) weigh the most.
///
/// With `order` the line-inlier blocks in time order, every cut τ splits them into a before and
/// an after. Under a fixed edge both parts' weighted mean axis points agree, so
/// `T(τ) = |P (r̄_before - r̄_after)|² / (1/W_before + 1/W_after)` is χ²₂ (P projects normal to the
/// line, W are the summed point weights). The largest T over the cuts that keep at least
/// [`MIN_KEPT_BLOCKS`] blocks and [`MIN_KEPT_FRACTION`] of the frames is compared with the χ²₂ quantile at `alpha` divided by the number of cuts
/// (Bonferroni, for the scan); if significant, the frames after the cut are dropped and the
/// test repeated. The error of the reference pose is common to all frames and shifts each
/// frame's axis by about `σ_ref / (2 sin(θ/2))`, more for small rotations; its effect on the
/// difference, `σ_ref² (mean 1/c before - mean 1/c after)²`, is added to the variance, with
/// `σ_ref` \[m\] the reference's point-equivalent standard deviation. Returns the kept blocks.
fn trim_change_points(
    blocks: &[Block],
    order: &[usize],
    line: Line,
    alpha: f64,
    sigma_ref: f64,
) -> Vec<usize> {
    let mut kept: Vec<usize> = order.to_vec();
    let u = line.direction;
    let p_mat = nalgebra::Matrix3::identity() - u * u.transpose();
    // The sums the test needs, over all kept blocks (the prefix at the cut of the previous
    // pass: the same additions in the same order, so the same values).
    let mut total = PointSums::default();
    kept.iter().for_each(|&i| total.add(&blocks[i].line));
    while kept.len() >= 3 {
        let cuts = kept.len() - 1;
        let threshold = -2.0 * (alpha / cuts as f64).ln();
        let mut before = PointSums::default();
        let mut best: Option<(f64, usize, PointSums)> = None;
        for (k, &i) in kept.iter().enumerate().take(cuts) {
            before.add(&blocks[i].line);
            let (wb, wa) = (before.sw, total.sw - before.sw);
            if wb <= 0.0
                || wa <= 0.0
                || k + 1 < MIN_KEPT_BLOCKS
                || before.n < MIN_KEPT_FRACTION * total.n
            {
                continue;
            }
            let d = p_mat * (before.swr / wb - (total.swr - before.swr) / wa);
            let dc = before.sw_inv_chord / wb - (total.sw_inv_chord - before.sw_inv_chord) / wa;
            let t = d.norm_squared() / (1.0 / wb + 1.0 / wa + (sigma_ref * dc).powi(2));
            if t > threshold && best.is_none_or(|b| t > b.0) {
                best = Some((t, k + 1, before));
            }
        }
        let Some((_, n_before, sums)) = best else {
            break;
        };
        kept.truncate(n_before);
        total = sums;
    }
    kept
}

/// Whether a segment whose edge rotation about `line` ends with block `end` is a completed
/// topple: the object came to rest on a face adjacent to the one it started on, across that
/// edge. Then the frames after the rotation's end are its landing (it left the edge, fell and
/// settled), a consequence of the topple and not a motion of their own, and they do not vote.
///
/// An edge lies in both faces it joins, so both resting "down" directions (in the object
/// frame, from the rests before and after the segment) must be normal to the line within
/// `sin_tilt` (the sine of [`super::RobustConfig::max_axis_tilt_rad`], the bound the line
/// already met against the first face). The faces must differ by more than that angle, and the
/// down direction must have turned about the line against the rotation: a body turned by θ
/// about `u` sees a fixed direction turned by -θ, so `(d_before × d_after) · ω < 0` with ω the
/// largest rotation of the edge's last block.
fn completed_topple(line: &Line, end: &Block, seg: &MotionSegment, sin_tilt: f64) -> bool {
    let (Some(before), Some(after), Some((_, omega))) =
        (seg.rest_before, seg.rest_after, end.max_line)
    else {
        return false;
    };
    let u = line.direction;
    before.dot(&u).abs() <= sin_tilt
        && after.dot(&u).abs() <= sin_tilt
        && before.cross(&after).norm() > sin_tilt
        && before.cross(&after).dot(&omega) < 0.0
}

/// The edge observation from pooled per-frame line statistics and the frame of largest
/// rotation `(angle, line, ω)` (the paper's estimate; its ω also fixes the direction's sign).
pub(super) fn edge_observation(
    s: &LineStats,
    best: (f64, Line, Vector3<f64>),
    demo: &str,
) -> Option<EdgeObservation> {
    let (max_angle, best_line, omega) = best;
    let mean = s.mean()?.aligned_with(&omega);
    let (point_cov, direction_cov) = s.covariances(&mean);
    Some(EdgeObservation {
        demo: demo.to_string(),
        line: mean,
        point_cov,
        direction_cov,
        paper_line: Some(best_line.aligned_with(&omega)),
        frames: s.n as u64,
        max_angle,
        chi2_per_dof: s.chi2(&mean) / (5.0 * s.n).max(1.0),
        common_point_cov: nalgebra::Matrix3::zeros(),
    })
}

/// Fit, label and summarise one motion segment; with it, a warning when the segment is general
/// only because of the given gravity (see [`gravity_warning`]).
#[allow(clippy::too_many_arguments)]
pub(super) fn analyse_segment(
    index: usize,
    instrumented: bool,
    seg: &MotionSegment,
    blocks: &mut [Block],
    config: &Config,
    alpha: f64,
    demo: &str,
) -> (Segment, Option<String>) {
    let idx: Vec<usize> = (0..blocks.len())
        .filter(|&i| blocks[i].segment == Some(index) && blocks[i].phase == Phase::Moving)
        .collect();
    let up = seg.down_ref.map(|d| -d);
    let (r_palm, sin_tilt, cos_tilt) = (
        config.paper.r_palm,
        config.robust.max_axis_tilt_rad.sin(),
        config.robust.max_axis_tilt_rad.cos(),
    );
    let valid_line = |l: &Line| {
        l.point.norm() <= r_palm && up.is_none_or(|u| l.direction.dot(&u).abs() <= sin_tilt)
    };
    let valid_plane = |n: &Vector3<f64>| up.is_none_or(|u| n.dot(&u).abs() >= cos_tilt);
    let mut th = Thresholds::new(alpha);
    // The fixed line and its inlier blocks in time order; a line that explains fewer than
    // MIN_EDGE_FRAMES frames is no line.
    let fitted = fit_line(blocks, &idx, valid_line, &mut th)
        .map(|l| {
            let lc = LineChi2::new(&l);
            let inliers: Vec<usize> = idx
                .iter()
                .copied()
                .filter(|&i| line_inlier(&blocks[i].line, &lc, &mut th))
                .collect();
            (l, inliers)
        })
        .filter(|(_, inliers)| {
            inliers.iter().map(|&i| blocks[i].line.n).sum::<f64>() >= MIN_EDGE_FRAMES
        });
    let mut line = fitted.as_ref().map(|(l, _)| *l);
    // The level-support prior: poses in the world frame (not instrumented) and gravity known.
    let level_down = seg.down_ref.filter(|_| !instrumented);
    let plane = fit_plane(blocks, &idx, valid_plane, level_down.as_ref(), &mut th);
    // Blocks cut off as "after (or before) the pure rotation": labelled general.
    let mut cut: std::collections::HashSet<usize> = std::collections::HashSet::new();
    // The last block of the pure edge rotation (after trimming), in time order.
    let mut rotation_end = fitted.as_ref().and_then(|(_, order)| order.last().copied());
    if let Some((l, order)) = fitted {
        let noise = config.robust.noise.unwrap_or(crate::noise::NoiseModel {
            sigma_position: 0.0,
            sigma_rotation: 0.0,
        });
        let sigma_ref = ((noise.sigma_position.powi(2)
            + (noise.sigma_rotation * l.point.norm()).powi(2))
            / seg.n_ref)
            .sqrt();
        let kept = trim_change_points(blocks, &order, l, alpha, sigma_ref);
        let mut s = LineStats::default();
        kept.iter().for_each(|&i| s.merge(&blocks[i].line));
        if let Some(trimmed) = s.mean().filter(|t| valid_line(t)) {
            rotation_end = kept.last().copied();
            let kept: std::collections::HashSet<usize> = kept.into_iter().collect();
            cut = order.into_iter().filter(|i| !kept.contains(i)).collect();
            line = Some(trimmed);
        }
    }

    let model = config
        .robust
        .noise
        .map(|n| super::frame_model::FrameModel::new(&n, &config.robust));
    let mut votes = Votes::default();
    let line_chi2 = line.map(|l| (l, LineChi2::new(&l)));
    for &i in &idx {
        let b = &blocks[i];
        let label = if b.significant == 0 {
            Label::Still
        } else if cut.contains(&i) {
            Label::General
        } else if line_chi2.is_some_and(|(l, lc)| {
            if b.line.n > 0.0 {
                line_inlier(&b.line, &lc, &mut th)
            } else {
                // Too little rotation to have an axis: consistent with the edge if its motion
                // lies in the plane normal to the edge and its translation is what a rotation
                // about the edge gives (a slide's pure translation across the edge is not).
                plane_inlier(&b.plane, &l.direction, &mut th)
                    && model.is_none_or(|m| {
                        rotation_explains_translation(&b.plane, &l, m.w_p, m.w_r, &mut th)
                    })
            }
        }) {
            Label::Topple
        } else if plane.is_some_and(|n| plane_inlier(&b.plane, &n, &mut th)) {
            Label::Slide
        } else {
            Label::General
        };
        blocks[i].label = label;
    }
    let completed = line
        .zip(rotation_end)
        .is_some_and(|(l, end)| completed_topple(&l, &blocks[end], seg, sin_tilt));
    if let Some(end) = rotation_end.filter(|_| completed) {
        for &i in &idx {
            if blocks[i].t0 > blocks[end].t1 && blocks[i].label == Label::General {
                blocks[i].label = Label::Landing;
            }
        }
    }
    for &i in &idx {
        if let Some(k) = blocks[i].label.vote() {
            votes.add(k, blocks[i].significant);
        }
    }
    let kind = votes.winner().unwrap_or(Kind::General);
    // Relative to a palm, "up" moves with it: the check is for poses in the world.
    let warning = match (kind, up) {
        (Kind::General, Some(up)) if !instrumented => {
            gravity_warning(blocks, &idx, &up, config, &mut th).map(|w| {
                format!(
                    "segment {index} ({:.2}-{:.2} s) is general under the given gravity, but \
                     {w}; if the tracker's world frame is not z-up, give its gravity (--gravity)",
                    seg.t_start, seg.t_end
                )
            })
        }
        _ => None,
    };
    let max_angle = idx.iter().map(|&i| blocks[i].max_angle).fold(0.0, f64::max);
    let blocks: &[Block] = blocks;
    let with_label = |l: Label| -> Vec<usize> {
        idx.iter()
            .copied()
            .filter(|&i| blocks[i].label == l)
            .collect()
    };
    // Each part teaches from its own frames only: the blocks of its label up to where
    // another motion takes over (see `part_end`).
    let on_plane =
        |b: &Block| plane.is_some_and(|n| plane_inlier(&b.plane, &n, &mut Thresholds::new(alpha)));
    let topple_end = part_end(blocks, &idx, |b| b.label == Label::Topple, MIN_EDGE_FRAMES);
    let slide_end = part_end(
        blocks,
        &idx,
        |b| b.label == Label::Slide || on_plane(b),
        MIN_FACE_FRAMES,
    );
    let topple_blocks: Vec<usize> = with_label(Label::Topple)
        .into_iter()
        .filter(|&i| blocks[i].t0 < topple_end)
        .collect();
    let slide_blocks: Vec<usize> = with_label(Label::Slide)
        .into_iter()
        .filter(|&i| blocks[i].t0 < slide_end)
        .collect();
    // A part is measured from the segment's reference pose, which is where the segment's
    // motion starts: a part that follows another mode of motion is not (see
    // `after_other_motion`).
    let topple_late = after_other_motion(blocks, &idx, Label::Topple, MIN_EDGE_FRAMES, |_| false);
    let slide_late = after_other_motion(blocks, &idx, Label::Slide, MIN_FACE_FRAMES, on_plane);
    let mut withheld = None;

    let mut topple_stats = LineStats::default();
    let mut topple_best: Option<super::LargestRotation> = None;
    if kind == Kind::Topple && topple_late.is_some() {
        withheld = topple_late.map(|w| format!("edge not taught: the topple {w}"));
    } else if kind == Kind::Topple {
        topple_blocks
            .iter()
            .for_each(|&i| topple_stats.merge(&blocks[i].line));
        topple_best = topple_blocks
            .iter()
            .filter_map(|&i| blocks[i].max_line.map(|(l, w)| (blocks[i].max_angle, l, w)))
            .max_by(|a, b| a.0.total_cmp(&b.0));
    }
    let mut edge = topple_best.and_then(|best| edge_observation(&topple_stats, best, demo));
    let mut topple_systematic_var = 0.0;
    let mut topple_systematic_direction_var = 0.0;
    // The edge direction's covariance without the split-half lack of fit of its axis, which the
    // level test uses. A pivot that slips turns the axis within the level plane (the edge
    // stays on the support); an axis that turns out of level as the object turns is no edge
    // on the support (the object twists as it tips, or pivots on a corner), and the drift
    // must not make an axis out of level pass for level: on Drake a push turned a box about a
    // line that went from 8° to 3.6° out of the face it stood on, the drift widened the edge's
    // σ to 2°, and its mean line, 6.3° from level, passed the test and taught an edge 6.4° off
    // the box's (`tests/corner_pivots.rs`). The taught edge keeps the drift in its σ.
    let mut level_cov = None;
    if let Some(e) = edge.as_mut() {
        let noise = config.robust.noise.unwrap_or(crate::noise::NoiseModel {
            sigma_position: 0.0,
            sigma_rotation: 0.0,
        });
        let sigma_ref = ((noise.sigma_position.powi(2)
            + (noise.sigma_rotation * e.line.point.norm()).powi(2))
            / seg.n_ref)
            .sqrt();
        // At least the contact's own wander (the model tolerance: a rounded edge, a soft
        // contact), which is one trajectory per demonstration and does not average down over
        // its frames; more where the split-half lack of fit shows the pivot moved more.
        // And the reference pose's own error, common to every frame.
        let inv_chord = mean_inv_chord(blocks, &topple_blocks);
        topple_systematic_var = systematic_point_var(blocks, &topple_blocks, &e.line, sigma_ref)
            .max(config.robust.edge_tolerance_m.powi(2))
            + (sigma_ref * inv_chord).powi(2);
        e.add_systematic_point_var(topple_systematic_var);
        let sigma_ref_rot = noise.sigma_rotation / seg.n_ref.sqrt();
        let reference_var = (sigma_ref_rot * inv_chord).powi(2);
        let drift_var = systematic_direction_var(blocks, &topple_blocks, &e.line, sigma_ref_rot);
        // The level test sees the direction without the drift of its axis: see `level_cov`.
        e.add_systematic_direction_var(reference_var);
        level_cov = Some(e.direction_cov);
        e.add_systematic_direction_var(drift_var);
        topple_systematic_direction_var = drift_var + reference_var;
    }
    // The part's own frames, after trimming and up to where another motion takes over, must
    // still be enough to test a fixed line (the segment's fit was tested with all of them).
    let too_few_frames = edge
        .as_ref()
        .filter(|_| topple_stats.n < MIN_EDGE_FRAMES)
        .map(|_| {
            format!(
                "its rotation about a fixed line holds {:.0} frames, fewer than the \
                 {MIN_EDGE_FRAMES} that test a fixed line (two frames agree with themselves)",
                topple_stats.n
            )
        });
    let turned_too_little = edge
        .as_ref()
        .and_then(|e| edge_turns_too_little(e, config.robust.edge_tolerance_m));
    let off_level = edge
        .as_ref()
        .zip(level_cov)
        .zip(seg.down_ref)
        .and_then(|((e, cov), d)| direction_off_level(&e.line.direction, &cov, &d, alpha));
    // A completed topple: the edge lies on the support (the table, or the palm in the palm's
    // frame) in both rests; where the rests leave it there, what they do not explain is the
    // edge's own error, and what they measure of it is used. "Down" in the poses' frame is
    // the one the rests' places were measured along.
    let mut off_support = None;
    let mut support_constraint = None;
    if let (Some(e), Some(down), Some(noise), true) = (
        edge.as_mut(),
        seg.down_ref.map(|d| seg.ref_q_inv.inverse() * d),
        config.robust.noise,
        completed,
    ) {
        let on_support = RestPair::of_motion(seg).map_or(Ok(None), |rests| {
            edge_on_support(
                e,
                &rests,
                &-down,
                &noise,
                config.robust.edge_tolerance_m,
                alpha,
            )
        });
        match on_support {
            Ok(Some((var, constraint))) => {
                e.add_systematic_point_var(var);
                topple_systematic_var += var;
                e.condition_on(&constraint);
                support_constraint = Some(constraint);
            }
            Ok(None) => {}
            Err(why) => off_support = Some(why),
        }
    }
    // The contact's depth along the support's normal at the middle of the turn: the bisector
    // of the faces rested on before and after (their outward normals are "down" in the
    // object's frame in each rest), or down at the reference turned by half the rotation.
    if let Some(e) = edge.as_mut() {
        let bisector = match (completed, seg.rest_before, seg.rest_after) {
            (true, Some(before), Some(after)) => Some(before + after),
            _ => seg.down_ref.map(|down| {
                nalgebra::Rotation3::new(e.line.direction * (-0.5 * e.max_angle)) * down
            }),
        };
        e.add_contact_depth_var(bisector, config.robust.contact_depth_m.powi(2));
    }
    // Without gravity a rotation about a fixed line is a topple about an edge or a slide that
    // turns about a fixed point (both are planar motions about one line; gravity says whether
    // the line is horizontal): in the world, no edge is taught. On the standard data set's
    // direct demonstrations at camera noise learnt without gravity, 20 of 99 edges were 3.5-42
    // cm off the box, each from a slide. Relative to a palm the box rests on the palm, which
    // turns it over, not about its normal.
    let unknown_vertical =
        (edge.is_some() && up.is_none() && !instrumented).then(|| UNKNOWN_VERTICAL.to_string());
    // An edge rotation that passed every test but turned too little to locate its edge is
    // still a contact mode measured from the rest: it shows the rest was on the support.
    let small_rotation = turned_too_little.is_some() && off_level.is_none();
    if let Some(w) = too_few_frames
        .or(turned_too_little)
        .or(off_level)
        .or(off_support)
        .or(unknown_vertical)
    {
        withheld = Some(format!("edge not taught: {w}"));
        edge = None;
        // Nor grouped into a topple of the demonstration.
        topple_best = None;
        topple_stats = LineStats::default();
    }

    if kind == Kind::Slide && slide_late.is_some() {
        withheld = slide_late
            .as_ref()
            .map(|w| format!("face not taught: the slide {w}"));
    }
    // Only a segment that votes slide teaches a face: a hand that carries an object level and
    // without tilting it moves it as a slide would, and the motion's majority is the evidence
    // that it was not carried (a toss's swing and flight pass for a slide in part).
    let face = (kind == Kind::Slide && slide_late.is_none()).then(|| {
        let mut s = PlaneStats::default();
        slide_blocks.iter().for_each(|&i| s.merge(&blocks[i].plane));
        let s = slide_normal(&s, level_down.as_ref());
        if s.n < MIN_FACE_FRAMES {
            return None;
        }
        let mut n = s.normal().map(|n| n.into_inner()).or(plane)?;
        if let Some(d) = seg.down_ref {
            if n.dot(&d) < 0.0 {
                n = -n;
            }
        }
        // The planar-motion model's lack of fit between the slide's halves, per axis.
        let systematic = systematic_normal_var(blocks, &slide_blocks, &n, level_down.as_ref());
        let across = nalgebra::Matrix3::identity() - n * n.transpose();
        Some(FaceObservation {
            demo: demo.to_string(),
            normal: n,
            normal_cov: s.normal_covariance(&n) + across * systematic,
            offset: None,
            offset_var: None,
            offset_common_var: 0.0,
            sign_known: seg.down_ref.is_some(),
            source: FaceSource::Slide,
            frames: s.n as u64,
            rest_height: None,
        })
    });

    let mut face = face.flatten();
    if let (Some(f), Some(d)) = (&face, seg.down_ref) {
        if let Some(w) = face_off_level(f, &d, alpha) {
            withheld = Some(format!("face not taught: {w}"));
            face = None;
        }
    }
    // The rests around the segment were on the support when a contact mode measured from them
    // leaves the rest before (it leads the segment: its features are taught) or reaches the
    // rest after (it lasts to the segment's end, landing aside). An edge rotation too small to
    // locate its edge shows that only relative to a palm, which is the support: in the world,
    // a hand that starts to swing a held object turns it about some line for a few degrees
    // too (on MuJoCo tosses from a still hold, two such 2-4° "topples" made the hold a
    // resting face, 34° and 49° off any face of the box).
    let rotation = edge.is_some() || (small_rotation && instrumented);
    let departs_from_support = seg.rest_before.is_some()
        && seg.rest_before_frames >= MIN_FACE_FRAMES
        && (face.is_some() || rotation);
    // As many frames of the rest after as of the rest before: a rest of two frames (a file
    // that ends as the object stops) does not say what the object came to rest on (a box that
    // tumbled off Drake's still, tilted palm onto the table, 45 cm from it, taught a face 11°
    // off beside its edge from the two frames of its rest on the table).
    let arrives_on_support = seg.rest_after.is_some()
        && seg.rest_after_frames >= MIN_FACE_FRAMES
        && ((face.is_some() && slide_end.is_infinite()) || (rotation && topple_end.is_infinite()));
    let segment = Segment {
        topple_stats,
        topple_best,
        topple_systematic_var,
        topple_systematic_direction_var,
        support_constraint,
        t_start: seg.t_start,
        t_end: seg.t_end,
        kind,
        votes,
        max_angle,
        edge,
        face,
        resting_normal_before: seg.rest_before,
        resting_normal_after: seg.rest_after,
        resting_frames_before: seg.rest_before_frames as u64,
        resting_frames_after: seg.rest_after_frames as u64,
        resting_place_before: seg.rest_before_place,
        resting_place_after: seg.rest_after_place,
        resting_rotation_before: seg.rest_before_rotation,
        resting_rotation_after: seg.rest_after_rotation,
        departs_from_support,
        arrives_on_support,
        withheld,
        remeasured: None,
        onset_frame: None,
        withheld_before_onset: None,
    };
    (segment, warning)
}

/// Why a rotation about a fixed line in the world teaches no edge without gravity.
pub const UNKNOWN_VERTICAL: &str = "without gravity a rotation about a fixed line may be a slide \
     turning about a fixed point (give --gravity to tell)";

/// Fraction of a general segment's measurably moving frames that a line or plane fitted
/// without the gravity constraints must explain for [`gravity_warning`] to speak.
pub const WARN_EXPLAINED_FRACTION: f64 = 0.9;
/// Fewest measurably moving frames in a segment for [`gravity_warning`] to speak.
pub const WARN_MIN_FRAMES: u64 = 10;

/// For a general segment with gravity known: whether the motion would be a topple or a slide
/// but for the gravity constraints (a topple's axis within
/// [`super::RobustConfig::max_axis_tilt_rad`] of horizontal, a slide's normal as close to
/// vertical). The line and the plane are fitted again without them; a sentence for the user
/// when one explains nearly all ([`WARN_EXPLAINED_FRACTION`]) of at least [`WARN_MIN_FRAMES`]
/// measurably moving frames, as a real topple or slide does (a general motion's frames fit one
/// plane in part, by chance). A tracker in a camera frame with the default gravity (z up) gives
/// exactly this. A diagnostic only: nothing is relabelled.
fn gravity_warning(
    blocks: &[Block],
    idx: &[usize],
    up: &Vector3<f64>,
    config: &Config,
    th: &mut Thresholds,
) -> Option<String> {
    let total: u64 = idx.iter().map(|&i| blocks[i].significant).sum();
    if total < WARN_MIN_FRAMES {
        return None;
    }
    let enough = |n: u64| n as f64 >= WARN_EXPLAINED_FRACTION * total as f64;
    let explained = |inlier: &mut dyn FnMut(&Block) -> bool| -> u64 {
        idx.iter()
            .filter(|&&i| inlier(&blocks[i]))
            .map(|&i| blocks[i].significant)
            .sum()
    };
    let r_palm = config.paper.r_palm;
    let max_tilt = config.robust.max_axis_tilt_rad.to_degrees();
    if let Some(l) = fit_line(blocks, idx, |l| l.point.norm() <= r_palm, th) {
        let lc = LineChi2::new(&l);
        let n = explained(&mut |b: &Block| line_inlier(&b.line, &lc, th));
        let tilt = l
            .direction
            .dot(up)
            .abs()
            .clamp(0.0, 1.0)
            .asin()
            .to_degrees();
        if enough(n) && tilt > max_tilt {
            return Some(format!(
                "{:.0}% of its moving frames turn about one fixed line like a topple's edge, \
                 {tilt:.0}° from horizontal (an edge must be within {max_tilt:.0}°)",
                100.0 * n as f64 / total as f64
            ));
        }
    }
    let normal = fit_plane(blocks, idx, |_| true, None, th)?;
    let n = explained(&mut |b: &Block| plane_inlier(&b.plane, &normal, th));
    let tilt = normal.dot(up).abs().clamp(0.0, 1.0).acos().to_degrees();
    (enough(n) && tilt > max_tilt).then(|| {
        format!(
            "{:.0}% of its moving frames slide on one plane, its normal {tilt:.0}° from vertical \
             (a slide's must be within {max_tilt:.0}°)",
            100.0 * n as f64 / total as f64
        )
    })
}
