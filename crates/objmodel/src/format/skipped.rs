//! Lines a reader skips that are neither blank nor comments, and why ([`SkippedLines`]), so
//! that the learner can say so:
//!
//! * **Frames where the tracker lost the object.** A motion-capture system that cannot see a
//!   body goes on writing its frames, with every pose value `NaN` (or empty, in a CSV export:
//!   pandas' `to_csv` and OptiTrack Motive both leave the cells blank) or zero (Vicon's
//!   occluded segments). Such a line is no pose and no error: the frame is a gap, as a frame
//!   the tracker dropped. A line with some values missing or `NaN` and others not is still an
//!   error: that is a broken file, not a tracker that lost sight.
//! * **A last line cut short.** A logger stopped in the middle of a line (killed, out of
//!   disk) leaves a last line without its `\n` that does not read as a pose. After poses it
//!   is left out, with its problem; elsewhere, or ended by a `\n`, a line that does not read
//!   is an error as always.
//! * **A line written twice.** A logger that flushes a buffer twice, or a tool that merged two
//!   copies of a log, repeats a line: the same time and the same pose (the columns a CSV
//!   reader ignores aside). The copy is no second frame and no contradiction; it is left out
//!   and counted. A line with the time of the one before and another pose is still an error
//!   (which of the two poses the tracker measured at that time, no reader can tell).

use super::layout::VALUES;
use crate::trajectory::StampedPose;
use std::sync::{Arc, Mutex};

/// Spans of lost lines kept for the message; lines past them are counted, not listed, so
/// that memory stays flat in the file's length.
const KEPT_SPANS: usize = 8;

/// Whether values in TUM order (`t tx ty tz qx qy qz qw`) are a frame where the tracker lost
/// the object: every pose value (all but the time) `NaN`, or every one exactly zero (a zero
/// quaternion is no rotation, so no tracker writes it for a pose it has).
pub fn is_lost(v: &[f64; VALUES]) -> bool {
    let pose = &v[1..];
    pose.iter().all(|x| x.is_nan()) || pose.iter().all(|&x| x == 0.0)
}

/// Whether pose `p` is a copy of pose `of`: the same time and the same coordinates, bit for bit
/// (coordinates, not rotations: `q` and `-q` are one rotation but two lines). What a line, or
/// a row of an array, written twice gives.
pub fn is_copy(p: &StampedPose, of: &StampedPose) -> bool {
    let coords = |p: &StampedPose| (p.t, p.pose.translation.vector, p.pose.rotation.coords);
    coords(p) == coords(of)
}

/// The lines of one file a reader skipped: where the tracker lost the object (how many, and
/// the first eight runs of consecutive lines), and a last line cut short.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct SkippedLines {
    /// Lines where the tracker lost the object, in all.
    pub lines: usize,
    /// Runs of consecutive such lines, first and last (1-based): the first eight.
    pub spans: Vec<(usize, usize)>,
    /// Runs in all.
    pub runs: usize,
    /// The last lost line.
    last: usize,
    /// The last line of the file, without its `\n`, that does not read as a pose: its number
    /// and the problem.
    pub cut_short: Option<(usize, String)>,
    /// Lines that repeat the pose line before them exactly (its time and its pose), in all.
    pub duplicates: usize,
    /// The first such line and the line it repeats (1-based).
    pub first_duplicate: Option<(usize, usize)>,
}

/// Where a reader on another thread counts the lines it skips, for the thread that reads its
/// poses.
pub(crate) type SkippedSink = Arc<Mutex<SkippedLines>>;

impl SkippedLines {
    /// Count line `line` (1-based, after every line counted before) as lost.
    pub(crate) fn record(&mut self, line: usize) {
        let continues = self.lines > 0 && self.last + 1 == line;
        self.lines += 1;
        self.last = line;
        if !continues {
            self.runs += 1;
            if self.spans.len() < KEPT_SPANS {
                self.spans.push((line, line));
            }
        } else if self.runs <= KEPT_SPANS {
            self.spans[self.runs - 1].1 = line;
        }
    }

    /// Count line `line` as a copy of line `of` (its time and pose exactly).
    pub(crate) fn record_duplicate(&mut self, line: usize, of: usize) {
        self.duplicates += 1;
        self.first_duplicate.get_or_insert((line, of));
    }

    /// What a learner says of the skipped lines of the `what` ("object", "palm") stream.
    pub fn warnings(&self, what: &str) -> Vec<String> {
        let mut said: Vec<String> = self.lost_warning(what).into_iter().collect();
        if let Some((line, of)) = self.first_duplicate {
            let n = self.duplicates;
            let (s, each) = if n == 1 {
                ("", "the copy")
            } else {
                ("s", "each copy")
            };
            said.push(format!(
                "the {what}'s file repeats {n} line{s} exactly (the first: line {line}, a copy \
                 of line {of}: the same time and pose, as a logger that wrote a line twice \
                 leaves): {each} left out, the frame kept once"
            ));
        }
        if let Some((line, problem)) = &self.cut_short {
            said.push(format!(
                "the {what}'s file ends in a line cut short (line {line}, without its end of \
                 line: a logger stopped in the middle of it?), which does not read as a pose \
                 ({problem}): left out"
            ));
        }
        said
    }

    /// Why a file without a single pose has none, where lines were skipped as lost.
    pub fn why_no_poses(&self) -> Option<String> {
        (self.lines > 0).then(|| {
            format!(
                "no poses: every pose line is a frame where the tracker lost the object ({} \
                 line{}, every pose value NaN, empty or zero)",
                self.lines,
                if self.lines == 1 { "" } else { "s" }
            )
        })
    }

    /// What a learner says of the lines where the tracker lost the object, if any.
    fn lost_warning(&self, what: &str) -> Option<String> {
        if self.lines == 0 {
            return None;
        }
        let mut at: Vec<String> = self
            .spans
            .iter()
            .map(|&(a, b)| {
                if a == b {
                    format!("{a}")
                } else {
                    format!("{a}-{b}")
                }
            })
            .collect();
        if self.runs > self.spans.len() {
            at.push(format!("and {} more runs", self.runs - self.spans.len()));
        }
        let (lines, runs) = (self.lines, self.runs);
        let s = |n: usize| if n == 1 { "" } else { "s" };
        Some(format!(
            "the {what}'s tracker lost it on {lines} line{} in {runs} run{} (line{} {}): every \
             pose value there is NaN, empty or zero; those frames are gaps, as frames not \
             recorded",
            s(lines),
            s(runs),
            s(lines),
            at.join(", ")
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn lost_values_are_all_nan_or_all_zero_and_only_those() {
        let n = f64::NAN;
        assert!(is_lost(&[1.0, n, n, n, n, n, n, n]));
        assert!(is_lost(&[1.0, 0.0, 0.0, -0.0, 0.0, 0.0, 0.0, 0.0]));
        // Some values missing and others not: a broken line, not a lost frame.
        assert!(!is_lost(&[1.0, 0.1, n, n, n, n, n, n]));
        assert!(!is_lost(&[1.0, n, n, n, 0.0, 0.0, 0.0, 1.0]));
        // A null pose is a pose (an identity rotation); held poses catch a tracker that
        // writes it while blind.
        assert!(!is_lost(&[1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0]));
        assert!(!is_lost(&[1.0, 0.0, 0.0, 0.0, n, 0.0, 0.0, 0.0]));
    }

    #[test]
    fn runs_are_merged_counted_and_kept_bounded() {
        let mut lost = SkippedLines::default();
        assert!(lost.warnings("object").is_empty());
        // Runs: 3-5, 9, then 20 single lines two apart.
        let lines: Vec<usize> = [3, 4, 5, 9]
            .into_iter()
            .chain((0..20).map(|k| 20 + 2 * k))
            .collect();
        for &l in &lines {
            lost.record(l);
        }
        assert_eq!(lost.lines, lines.len());
        assert_eq!(lost.runs, 22);
        assert_eq!(lost.spans.len(), KEPT_SPANS);
        assert_eq!(&lost.spans[..3], &[(3, 5), (9, 9), (20, 20)]);
        let w = lost.warnings("palm").remove(0);
        assert!(
            w.starts_with("the palm's tracker lost it on 24 lines in 22 runs"),
            "{w}"
        );
        assert!(
            w.contains("(lines 3-5, 9, 20, 22, 24, 26, 28, 30, and 14 more runs)"),
            "{w}"
        );
        // A run past the kept ones does not stretch the last kept span.
        let mut lost = SkippedLines::default();
        for k in 0..KEPT_SPANS {
            lost.record(10 * k + 1);
        }
        lost.record(500);
        lost.record(501);
        assert_eq!(lost.spans[KEPT_SPANS - 1], (71, 71));
        assert_eq!((lost.lines, lost.runs), (KEPT_SPANS + 2, KEPT_SPANS + 1));
    }

    #[test]
    fn duplicates_are_counted_and_the_first_named() {
        let mut lines = SkippedLines::default();
        lines.record_duplicate(48, 47);
        assert_eq!(
            lines.warnings("palm"),
            [
                "the palm's file repeats 1 line exactly (the first: line 48, a copy of line 47: \
              the same time and pose, as a logger that wrote a line twice leaves): the copy \
              left out, the frame kept once"
            ]
        );
        lines.record_duplicate(60, 58);
        lines.record_duplicate(61, 58);
        assert_eq!(
            (lines.duplicates, lines.first_duplicate),
            (3, Some((48, 47)))
        );
        let w = lines.warnings("object").remove(0);
        assert!(
            w.starts_with(
                "the object's file repeats 3 lines exactly (the first: line 48, a copy of line 47"
            ),
            "{w}"
        );
        assert!(
            w.ends_with("each copy left out, the frame kept once"),
            "{w}"
        );
        // Nothing to say of a file without copies or lost lines.
        assert!(SkippedLines::default().warnings("object").is_empty());
    }
}
