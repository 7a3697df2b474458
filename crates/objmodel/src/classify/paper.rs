//! The paper's Algorithm 1 and Algorithm 2, literally (see [`super::Method::Paper`]).
//!
//! Conventions where the paper leaves room (the same as `shared/bench/screw_numpy.py`): the
//! angle between axes or normals is the unsigned line angle; an undefined quantity (the axis
//! point of a pure translation, a normal from parallel velocities) fails its test; a frame
//! votes if it moved from g(0) by more than [`super::PaperThresholds::motion_rotation`] or
//! [`super::PaperThresholds::motion_translation`]; Algorithm 2 takes the frame of largest
//! rotation over all frames.

use super::sample::Sample;
use super::{Classification, Config, Kind, Label, LabelRun, Method, Segment, Votes};
use crate::edge::EdgeObservation;
use crate::face::{FaceObservation, FaceSource};
use crate::fast::avx2_or_baseline;
use crate::fast::twist4::FourMotions;
use crate::geometry::Line;
use crate::screw::{plane_normal, Screw};
use crate::se3::Twist;
use nalgebra::{Matrix3, UnitQuaternion, Vector3};

/// Algorithm 2's candidate: (θ \[rad\], axis point \[m\], unit axis direction, ω \[rad\]).
type Best = (f64, Vector3<f64>, Vector3<f64>, Vector3<f64>);

/// The reference pose `g(0)`: orientation, position \[m\], and "down" in its frame if known.
type Reference = (UnitQuaternion<f64>, Vector3<f64>, Option<Vector3<f64>>);

/// Label runs kept before the runs are coarsened ([`coarsen`]): a noisy slow turn changes label
/// every few frames (the benchmark's 10⁷-pose turn: ~10⁶ runs and, from them, ~10⁵ parts, which
/// took `learn --method paper` to 79 MB against 17-26 MB at 10⁶ poses), so the runs would grow
/// with the file. With this bound they take at most 1 MB, and `learn --method paper` peaks at
/// 20 MB at 10⁶ poses and 25 MB at 10⁷ (its tree unchanged); files whose labels change fewer
/// times keep every run (every file of the standard data set).
pub(super) const MAX_LABEL_RUNS: usize = 1 << 14;

/// Halve the number of label runs: each two neighbours become one run over both, with the label
/// of the one with more frames (the first on a tie), and neighbours of one label are joined.
/// The frames and times the runs cover are unchanged; only the labels of the shorter runs give
/// way.
fn coarsen(runs: &mut Vec<LabelRun>) {
    let mut out: Vec<LabelRun> = Vec::with_capacity(runs.len() / 2 + 1);
    for pair in runs.chunks(2) {
        let run = match pair {
            [a, b] => LabelRun {
                last: b.last,
                t_end: b.t_end,
                frames: a.frames + b.frames,
                label: if b.frames > a.frames {
                    b.label
                } else {
                    a.label
                },
                ..*a
            },
            [a] => *a,
            _ => unreachable!("chunks of two"),
        };
        match out.last_mut() {
            Some(prev) if prev.label == run.label => {
                prev.last = run.last;
                prev.t_end = run.t_end;
                prev.frames += run.frames;
            }
            _ => out.push(run),
        }
    }
    *runs = out;
}

/// Streaming state of the literal algorithm.
pub(super) struct PaperMethod {
    config: Config,
    reference: Option<Reference>,
    /// `g(0)⁻¹`'s rotation, kept to form `g(0)⁻¹ g(t)` per frame.
    reference_inv: UnitQuaternion<f64>,
    previous: Option<(Twist, Option<Screw>, Option<Vector3<f64>>)>,
    runs: Vec<LabelRun>,
    votes: Votes,
    /// The screw of largest rotation so far; its line is formed once, at the end.
    best: Option<Best>,
    normal_sum: Vector3<f64>,
    slide_frames: u64,
    t_range: Option<(f64, f64)>,
    /// Cosines of the axis and normal angle thresholds.
    cos_axis: f64,
    cos_normal: f64,
    /// Frames waiting for their logarithms, taken four at a time.
    pending: FourMotions,
}

impl PaperMethod {
    pub(super) fn new(config: &Config) -> Self {
        Self {
            config: *config,
            reference: None,
            reference_inv: UnitQuaternion::identity(),
            previous: None,
            runs: Vec::new(),
            votes: Votes::default(),
            best: None,
            normal_sum: Vector3::zeros(),
            slide_frames: 0,
            t_range: None,
            cos_axis: config.paper.axis_angle.cos(),
            cos_normal: config.paper.normal_angle.cos(),
            pending: FourMotions::default(),
        }
    }

    fn label(&mut self, index: usize, t: f64, label: Label) {
        if let Some(r) = self.runs.last_mut() {
            if r.label == label {
                r.last = index;
                r.t_end = t;
                r.frames += 1;
                return;
            }
        }
        if self.runs.len() == MAX_LABEL_RUNS {
            coarsen(&mut self.runs);
        }
        self.runs.push(LabelRun {
            first: index,
            last: index,
            t_start: t,
            t_end: t,
            frames: 1,
            label,
            segment: Some(0),
        });
    }

    /// Push the next item; `down` is the unit "down" in the frame the poses are relative to.
    pub(super) fn push(&mut self, item: Sample, down: Option<Vector3<f64>>) {
        let Sample::Frame(f) = item else { return };
        if self.reference.is_none() {
            self.reference = Some((f.q, f.p, down.map(|d| f.q.inverse() * d)));
            self.reference_inv = f.q.inverse();
            self.t_range = Some((f.t, f.t));
        }
        let p0 = self.reference.map_or(f.p, |r| r.1);
        if let Some(r) = self.t_range.as_mut() {
            r.1 = f.t;
        }
        let q0_inv = self.reference_inv;
        let (q, t) = (q0_inv * f.q, q0_inv * (f.p - p0));
        if self.pending.push(f.index, f.t, &q, &t) {
            self.flush();
        }
    }

    /// Judge the pending frames.
    #[inline(never)]
    fn flush(&mut self) {
        avx2_or_baseline!(self.judge_pending())
    }

    /// The logarithms of the pending frames and their screws (eq. 1-3, as
    /// [`Twist::log_quat`] and [`Screw::from_twist`]), four at a time; then each frame is judged
    /// in order.
    #[inline(always)]
    fn judge_pending(&mut self) {
        let pending = std::mem::take(&mut self.pending);
        pending.twists_and_screws(
            #[inline(always)]
            |index, t, xi, screw| self.judge(index, t, xi, screw),
        );
    }

    /// Algorithm 1 for one frame: its twist `xi` of `g(0)⁻¹ g(t)` and screw, against the
    /// previous frame's.
    #[inline(always)]
    fn judge(&mut self, index: usize, t: f64, xi: Twist, screw: Option<Screw>) {
        let th = self.config.paper;
        let omega = xi.omega;
        // For a rotation the plane normal (eq. 5) is the screw's direction and θ its magnitude.
        let (theta, normal) = match &screw {
            Some(s) if s.is_rotation() => (s.magnitude, Some(s.direction.into_inner())),
            _ => (
                omega.norm(),
                plane_normal(&xi, self.previous.as_ref().map(|p| &p.0)).map(|n| n.into_inner()),
            ),
        };
        let moving = theta > th.motion_rotation
            || xi.v.norm_squared() > th.motion_translation * th.motion_translation;
        let label = match (&self.previous, &screw) {
            (Some((_, prev_screw, prev_normal)), Some(s)) => {
                if s.pitch.abs() < th.pitch {
                    // angle(a, b) < th as |a·b| > cos th for unit a, b (no atan2 per frame).
                    let same_axis = prev_screw
                        .is_some_and(|p| p.direction.dot(&s.direction).abs() > self.cos_axis);
                    let same_normal = matches!((prev_normal, &normal),
                        (Some(a), Some(b)) if a.dot(b).abs() > self.cos_normal);
                    if same_axis && s.point.norm_squared() < th.r_palm * th.r_palm {
                        Label::Topple
                    } else if same_normal {
                        Label::Slide
                    } else {
                        Label::Unlabelled
                    }
                } else {
                    Label::General
                }
            }
            _ => Label::Unlabelled,
        };
        let label = if moving { label } else { Label::Rest };
        if let Some(k) = label.vote() {
            self.votes.add(k, 1);
        }
        if label == Label::Slide {
            if let Some(n) = normal {
                let n = if n.dot(&self.normal_sum) < 0.0 { -n } else { n };
                self.normal_sum += n;
                self.slide_frames += 1;
            }
        }
        if let Some(s) = screw.filter(|s| s.is_rotation()) {
            if self.best.is_none_or(|b| theta > b.0) {
                self.best = Some((theta, s.point, s.direction.into_inner(), omega));
            }
        }
        self.label(index, t, label);
        self.previous = Some((xi, screw, normal));
    }

    pub(super) fn finish(
        mut self,
        name: &str,
        instrumented: bool,
        frames: u64,
    ) -> crate::Result<Classification> {
        if !self.pending.is_empty() {
            self.flush();
        }
        let kind = self.votes.winner().unwrap_or(Kind::General);
        let down = self.reference.and_then(|r| r.2);
        let edge = (kind == Kind::Topple)
            .then_some(self.best)
            .flatten()
            .map(|(theta, point, direction, _)| (theta, Line::through(point, direction)))
            .map(|(theta, line)| EdgeObservation {
                demo: name.to_string(),
                line,
                point_cov: Matrix3::zeros(),
                direction_cov: Matrix3::zeros(),
                paper_line: Some(line),
                frames: self.votes.topple,
                max_angle: theta,
                chi2_per_dof: f64::NAN,
                common_point_cov: nalgebra::Matrix3::zeros(),
            });
        let face = (kind == Kind::Slide && self.slide_frames > 0).then(|| {
            let mut n = self.normal_sum.normalize();
            if down.is_some_and(|d| n.dot(&d) < 0.0) {
                n = -n;
            }
            FaceObservation {
                demo: name.to_string(),
                normal: n,
                normal_cov: Matrix3::zeros(),
                offset: None,
                offset_var: None,
                offset_common_var: 0.0,
                sign_known: down.is_some(),
                source: FaceSource::Slide,
                frames: self.slide_frames,
                rest_height: None,
            }
        });
        let (t0, t1) = self.t_range.unwrap_or((0.0, 0.0));
        let paper_edge = edge.as_ref().map(|e| e.line);
        let mut c = Classification {
            name: name.to_string(),
            kind,
            method: Method::Paper,
            instrumented,
            frames,
            votes: self.votes,
            topples: edge
                .clone()
                .map(|e| super::Topple {
                    segments: vec![0],
                    edge: e,
                    resting_normal_before: down,
                    resting_normal_after: None,
                })
                .into_iter()
                .collect(),
            segments: vec![Segment {
                t_start: t0,
                t_end: t1,
                kind,
                votes: self.votes,
                max_angle: self.best.map_or(0.0, |b| b.0),
                edge,
                face,
                resting_normal_before: down,
                ..Default::default()
            }],
            labels: self.runs,
            paper_edge,
            ..Default::default()
        };
        c.fill_parts();
        Ok(c)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// However often the label changes, the runs stay within [`MAX_LABEL_RUNS`], cover every
    /// frame once and in order, and keep the label of the majority where one label dominates.
    #[test]
    fn label_runs_stay_bounded_and_cover_every_frame() {
        let mut m = PaperMethod::new(&Config::default());
        let n = 3 * MAX_LABEL_RUNS + 17;
        // Topple on two frames of three, slide on the third: a run change every frame or two.
        for i in 0..n {
            let label = if i % 3 == 2 {
                Label::Slide
            } else {
                Label::Topple
            };
            m.label(i, i as f64 * 0.01, label);
            assert!(
                m.runs.len() <= MAX_LABEL_RUNS,
                "{} runs at frame {i}",
                m.runs.len()
            );
        }
        let runs = &m.runs;
        assert!(runs.len() < n / 4, "{} runs", runs.len());
        assert_eq!(runs.iter().map(|r| r.frames).sum::<u64>(), n as u64);
        assert_eq!((runs[0].first, runs.last().unwrap().last), (0, n - 1));
        for w in runs.windows(2) {
            assert_eq!(w[1].first, w[0].last + 1);
            assert_eq!(w[1].t_start, w[1].first as f64 * 0.01);
            assert_ne!(w[0].label, w[1].label);
        }
        let topple: u64 = runs
            .iter()
            .filter(|r| r.label == Label::Topple)
            .map(|r| r.frames)
            .sum();
        assert!(topple as f64 > 0.6 * n as f64, "{topple} of {n}");
    }

    /// Files whose labels change fewer than [`MAX_LABEL_RUNS`] times keep every run.
    #[test]
    fn few_label_changes_keep_every_run() {
        let mut m = PaperMethod::new(&Config::default());
        for i in 0..1000 {
            m.label(
                i,
                i as f64,
                if (i / 10) % 2 == 0 {
                    Label::Topple
                } else {
                    Label::Slide
                },
            );
        }
        assert_eq!(m.runs.len(), 100);
        assert!(m.runs.iter().all(|r| r.frames == 10));
    }
}
