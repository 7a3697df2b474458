//! Classifying demonstrations straight from their files, streaming.

use super::cleaning::RotatingCleaner;
use super::{Analyzer, Classification, Config};
use crate::fast::handover::{push_cleaned_frames, CleanedFrames, ThreadedPoses};
use crate::format::{self, DeclaredUnits, LengthUnit, PoseFile, QuaternionOrder, TimeUnit};
use crate::recording::Recorder;
use crate::trajectory::StampedPose;
use crate::Result;
use std::path::Path;

/// The unit of a pose file's stamps, if `config` asks to recognise it and the file does
/// not declare it (`declared`; the reader converts a declared unit): from its `first`
/// [`format::TIME_UNIT_STAMPS`] poses, and the warning when it is not seconds.
fn stamp_unit(
    first: &[StampedPose],
    declared: DeclaredUnits,
    what: &str,
    config: &Config,
) -> (f64, Option<String>) {
    if !config.clocks.detect_time_unit || declared.time.is_some() {
        return (1.0, None);
    }
    match format::detect_time_unit_of(first) {
        TimeUnit::Seconds => (1.0, None),
        u => (u.seconds(), Some(format::conversion_warning(what, u))),
    }
}

/// The first poses of a pose file and the units it declares (none read from standard input,
/// which cannot be read twice; a bad line is reported by the reading proper, with its place
/// in the stream).
fn head(file: PoseFile) -> (Vec<StampedPose>, DeclaredUnits) {
    file.read_first_declared(format::TIME_UNIT_STAMPS)
        .unwrap_or_default()
}

/// The metres per unit of a pose file's positions as read (1 where the file declares its
/// unit: the reader converts it; else the unit `config` gives, if any), and the unit, where
/// it is known (declared or given).
fn position_unit(declared: DeclaredUnits, config: &Config) -> (f64, Option<LengthUnit>) {
    match (declared.length, config.length_unit) {
        (Some(u), _) => (1.0, Some(u)),
        (None, Some(u)) => (u.metres(), Some(u)),
        (None, None) => (1.0, None),
    }
}

/// The order in which a pose file's quaternions were written, read as x y z w: the one `config`
/// gives for a file that does not name its columns (TUM), else x y z w (the reader moved
/// named columns into it); and the warning where `config` gives one that the file's names
/// override.
fn quaternion_order(
    declared: DeclaredUnits,
    what: &str,
    config: &Config,
) -> (QuaternionOrder, Option<String>) {
    match config.quaternion_order {
        QuaternionOrder::Xyzw => (QuaternionOrder::Xyzw, None),
        given if declared.named_columns => (
            QuaternionOrder::Xyzw,
            Some(format!(
                "the {what}'s file names its columns: its quaternion is read by the names, \
                 not in the order given ({given})"
            )),
        ),
        given => (given, None),
    }
}

/// How one stream's poses, as read, become poses in seconds on the object's clock, metres and
/// x y z w quaternions: its stamp unit, length unit and quaternion order (what the file does
/// not declare and `config` recognises or gives), and its clock's offset.
struct Conversion {
    seconds: f64,
    offset_s: f64,
    metres: f64,
    order: QuaternionOrder,
}

impl Conversion {
    /// The conversion of the stream in `file` (`what`: "object" or "palm"), the warnings it
    /// gives, and its length unit where known; `offset_s` is added to its stamps.
    fn of(
        file: PoseFile,
        what: &str,
        offset_s: f64,
        config: &Config,
    ) -> (Self, Vec<String>, Option<LengthUnit>) {
        let (first, units) = head(file);
        let (seconds, stamp_warning) = stamp_unit(&first, units, what, config);
        let (metres, length) = position_unit(units, config);
        let (order, order_warning) = quaternion_order(units, what, config);
        let conversion = Self {
            seconds,
            offset_s,
            metres,
            order,
        };
        (
            conversion,
            stamp_warning.into_iter().chain(order_warning).collect(),
            length,
        )
    }

    /// Whether it leaves every pose as read.
    fn is_identity(&self) -> bool {
        self.seconds == 1.0
            && self.offset_s == 0.0
            && self.metres == 1.0
            && self.order == QuaternionOrder::Xyzw
    }

    fn apply(&self, mut p: StampedPose) -> StampedPose {
        p.t = p.t * self.seconds + self.offset_s;
        p.pose.translation.vector *= self.metres;
        p.pose.rotation = self.order.reorder(&p.pose.rotation);
        p
    }
}

/// Classify the demonstration in `object` (TUM or CSV), with `palm` as its palm trajectory
/// when instrumented. Both files are streamed in time order: memory does not grow with their
/// length. The demonstration's name is the object file's name.
pub fn classify_files(
    object: &Path,
    palm: Option<&Path>,
    config: &Config,
) -> Result<Classification> {
    classify_files_recording(
        PoseFile::whole(object),
        palm.map(PoseFile::whole),
        config,
        None,
    )
}

/// [`classify_files`] of the object's and the palm's poses in files (or rigid bodies of a
/// Motive take: [`PoseFile`]), handing every frame to `recorder` as well (for the dynamics, in
/// the same pass over the files).
pub(crate) fn classify_files_recording(
    object_file: PoseFile,
    palm: Option<PoseFile>,
    config: &Config,
    mut recorder: Option<&mut Recorder>,
) -> Result<Classification> {
    let object = object_file.path;
    let name = object
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| object.display().to_string());
    let mut a = Analyzer::new(&name, config, palm.is_some());
    let (object_conversion, mut warnings, mut length_unit) =
        Conversion::of(object_file, "object", 0.0, config);
    let object_poses = object_file.open()?;
    let mut skipped = vec![("object", object_poses.skipped_sink())];
    match palm {
        None if !object_conversion.is_identity() => {
            // Stamps not in seconds, positions not in metres or quaternions written w first:
            // converted on this thread (not the fast path's).
            for (i, p) in (0u64..).zip(ThreadedPoses::spawn(object_poses)) {
                let p = object_conversion.apply(p?);
                if let Some(r) = recorder.as_deref_mut() {
                    r.object(i, p.t, &p.pose.rotation, &p.pose.translation.vector);
                }
                a.push_object(&p);
            }
        }
        None => {
            // Robust: parsing, cleaning and the accumulated rotation on the background
            // thread; rest detection, segments and blocks on this one. Measured on 10^6 poses
            // (CPU per thread, medians of interleaved runs): the parsing thread ~57 ms, this
            // one ~57-59 ms, the mapping helper ~5 ms; with the rotation here instead, the
            // wall time did not improve; with the whole rest detection there (`ObjectRestTest`),
            // that thread is much the busier.
            if let Some(cleaner) = a.take_object_cleaner() {
                let front = RotatingCleaner::new(cleaner);
                let mut index = 0;
                CleanedFrames::spawn(object_poses, front).for_each_chunk(|chunk| {
                    if let Some(r) = recorder.as_deref_mut() {
                        let (first, end) = (index as u64, (index + chunk.len()) as u64);
                        let mut i = r.next_object_index(first);
                        while i < end {
                            let h = &chunk[(i - first) as usize];
                            r.object(i, h.t, &h.q, &h.p);
                            i = r.next_object_index(i + 1);
                        }
                    }
                    push_cleaned_frames(&mut a, chunk, &mut index)
                })?;
            } else {
                for (i, p) in (0u64..).zip(ThreadedPoses::spawn(object_poses)) {
                    let p = p?;
                    if let Some(r) = recorder.as_deref_mut() {
                        r.object(i, p.t, &p.pose.rotation, &p.pose.translation.vector);
                    }
                    a.push_object(&p);
                }
            }
        }
        Some(palm) => {
            let offset = config.clocks.palm_time_offset_s;
            let (palm_conversion, palm_warnings, palm_length) =
                Conversion::of(palm, "palm", offset, config);
            // The palm's stamp-unit warning before its quaternion-order one, as the object's.
            warnings.extend(palm_warnings);
            // Known only where both streams' units are.
            length_unit = length_unit.filter(|_| palm_length.is_some());
            let mut objects = ThreadedPoses::spawn(object_poses);
            let palm_poses = palm.open()?;
            skipped.push(("palm", palm_poses.skipped_sink()));
            let mut palms = ThreadedPoses::spawn(palm_poses);
            // Both on the object's clock, in seconds.
            let mut next_object = || {
                objects
                    .next()
                    .transpose()
                    .map(|o| o.map(|o| object_conversion.apply(o)))
            };
            let mut next_palm = || {
                palms
                    .next()
                    .transpose()
                    .map(|p| p.map(|p| palm_conversion.apply(p)))
            };
            let (mut o, mut p) = (next_object()?, next_palm()?);
            let mut index = 0u64;
            loop {
                let palm_first = match (&o, &p) {
                    (None, None) => break,
                    (Some(x), Some(y)) => y.t <= x.t,
                    (Some(_), None) => false,
                    (None, Some(_)) => true,
                };
                if palm_first {
                    let y = p.as_ref().expect("a palm pose");
                    if let Some(r) = recorder.as_deref_mut() {
                        r.palm(y);
                    }
                    a.push_palm(y);
                    p = next_palm()?;
                } else {
                    let x = o.as_ref().expect("an object pose");
                    if let Some(r) = recorder.as_deref_mut() {
                        r.object(index, x.t, &x.pose.rotation, &x.pose.translation.vector);
                    }
                    index += 1;
                    a.push_object(x);
                    o = next_object()?;
                }
            }
        }
    }
    let lost_only = skipped[0].1.lock().ok().and_then(|s| s.why_no_poses());
    let mut c = a.finish().map_err(|e| match e {
        crate::Error::Data(msg) => crate::Error::File {
            file: object.to_path_buf(),
            // (No frame at all: `Analyzer::finish`'s "no poses".)
            msg: match lost_only {
                Some(why) if msg.starts_with("no poses") => why,
                _ => msg,
            },
        },
        e => e,
    })?;
    // (Each reader has returned its last pose: its count is complete.)
    for (what, sink) in &skipped {
        let lines = sink.lock().unwrap_or_else(|e| e.into_inner());
        warnings.extend(lines.warnings(what));
        match *what {
            "object" => {
                c.lost_frames = lines.lines as u64;
                c.duplicate_lines = lines.duplicates as u64;
            }
            _ => {
                c.palm_lost_frames = lines.lines as u64;
                c.palm_duplicate_lines = lines.duplicates as u64;
            }
        }
    }
    c.warnings.splice(0..0, warnings);
    c.length_unit = length_unit;
    Ok(c)
}
