//! Algorithm 1: is a demonstration a topple (edge rotation), a slide (face slide) or general?
//!
//! Two implementations share the front end (parsing, relative motion, screws):
//!
//! * [`Method::Paper`]: the paper's Algorithm 1 as written. Frame i's screw of
//!   `g'(i) = g(0)⁻¹ g(i)` is compared with frame i-1's: `|pitch| < p_th`, axis angle `< l_th` and
//!   `|r| < r_palm` give *topple*; otherwise normal angle `< n_th` gives *slide*; a large pitch
//!   gives *general*. The demo is the most frequent label over moving frames.
//! * [`Method::Robust`] (default), which works at real tracking noise:
//!   1. the noise is estimated from the data ([`crate::noise`]); single-frame tag flips are
//!      rejected and quaternion signs made continuous ([`crate::clean`]);
//!   2. frames at rest do not vote: a χ²₆ test on the local velocity (least-squares slope of the
//!      pose over a window of [`RobustConfig::rest_window_s`]) separates rest from motion;
//!      motion between rests forms a *segment* whose reference pose is the mean of the rest
//!      before it (a better `g(0)` than one noisy frame);
//!   3. instead of comparing each frame with its noisy predecessor, each frame is tested against
//!      the segment's best *fixed line* (topple) and best *fixed plane of motion* (slide), found
//!      by MSAC over the frames (robust to the end of a topple, where the object leaves its edge)
//!      and refined by weighted least squares. Residuals are normalised by their variance
//!      propagated from the tracking noise (plus a small model tolerance), so one χ² level
//!      `alpha` replaces the hand-set angle thresholds;
//!   4. physics: a topple axis lies in the supporting face, so within
//!      [`RobustConfig::max_axis_tilt_rad`] of horizontal, and a slide's plane normal within the
//!      same angle of vertical, when the direction of gravity is known;
//!   5. the label of a frame is topple if it fits the line, else slide if it fits the plane, else
//!      general; the demonstration's kind is the most frequent label (ties: topple, slide);
//!   6. the frames after a completed topple's edge rotation (it ended at rest on the adjacent
//!      face across the edge) are its landing and do not vote (see `analysis::completed_topple`).
//!
//! The modules, in the order the data flows through them (each imports only modules above it;
//! `tests/import_circles.rs` checks that no two files import each other through any path):
//!
//! * `config`, `classification`: the configuration ([`Config`]) and the result
//!   ([`Classification`]) that every stage below uses;
//! * `sample`: a kept frame or the place of a rejected one, as the stages pass them on;
//! * `cleaning`: noise warm-up and tag-flip rejection per stream; `palm`: the motion relative
//!   to a tracked palm;
//! * `rotation_sum`, `rest_sums`, `rest`: the accumulated rotation and the windowed χ² rest
//!   test; `rest_test`: the test with its noise warm-up, and the verdicts it passes on;
//! * `frame_model`: a moving frame's motion and screw against its segment's reference, and its
//!   noise model; `rest_stats`: a rest's mean pose and drift;
//! * `block`: the sufficient statistics of a run of frames; `segments`: the motion segments;
//! * `msac`: the fixed-line and fixed-plane fits; `analysis`: what one segment teaches;
//!   `parts`: where a segment's parts end and what each must show to teach;
//!   `conclusion`: what the segments teach together (votes, topples by edge); `rest_faces`:
//!   what the rests teach (faces from gravity, landings, the support's height);
//! * `robust`, `paper`: the two methods, streaming; `analyzer`: the [`Analyzer`] that drives
//!   them; `files`: [`classify_files`].

mod analysis;
mod analyzer;
mod block;
mod classification;
pub(crate) mod cleaning;
mod conclusion;
mod config;
mod files;
pub(crate) mod frame_model;
mod lack_of_fit;
mod msac;
mod palm;
mod paper;
mod part_list;
pub(crate) mod parts;
mod rest;
mod rest_faces;
mod rest_stats;
mod rest_sums;
pub(crate) mod rest_test;
mod robust;
pub(crate) mod rotation_sum;
pub(crate) mod sample;
mod segments;

pub use analysis::{MIN_EDGE_FRAMES, MIN_FACE_FRAMES, UNKNOWN_VERTICAL};
pub use analyzer::Analyzer;
pub(crate) use classification::LargestRotation;
pub use classification::{Classification, Kind, Label, LabelRun, Part, Segment, Topple, Votes};
pub(crate) use conclusion::group_topples;
pub use config::{Config, Method, PaperThresholds, RobustConfig};
pub use files::classify_files;
pub(crate) use files::classify_files_recording;
pub(crate) use palm::SUPPORT_FRAMES;
pub use palm::{Clocks, DEFAULT_MAX_DT_S};
pub use parts::{height_difference_var, OFF_LEVEL, OFF_SUPPORT};

/// Classify a demonstration held in memory.
pub fn classify(demo: &crate::Demonstration, config: &Config) -> crate::Result<Classification> {
    let mut a = Analyzer::new(&demo.name, config, demo.palm.is_some());
    match &demo.palm {
        None => demo.object.iter().for_each(|p| a.push_object(p)),
        Some(palm) => {
            let (mut i, mut j) = (0, 0);
            while i < demo.object.len() || j < palm.len() {
                let take_palm =
                    j < palm.len() && (i >= demo.object.len() || palm[j].t <= demo.object[i].t);
                if take_palm {
                    a.push_palm(&palm[j]);
                    j += 1;
                } else {
                    a.push_object(&demo.object[i]);
                    i += 1;
                }
            }
        }
    }
    a.finish()
}
