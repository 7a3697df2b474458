//! Pose file formats: TUM (`timestamp tx ty tz qx qy qz qw`) and CSV with a header.
//!
//! * **TUM**: one pose per line, fields separated by any number of spaces or tabs, `#` starts
//!   a comment (whole line or trailing), blank lines are skipped, `\r\n` is accepted.
//! * **CSV**: a header line names the columns (case-insensitive, any order): `timestamp`
//!   (or `t`, `time`), `tx ty tz` (or `x y z`), `qx qy qz qw`; other columns are ignored.
//!   A unit in brackets or parentheses after a name (`x [mm]`, `Time (Seconds)`) is read:
//!   positions in m, cm or mm and stamps in s, ms, us or ns are converted to metres and
//!   seconds ([`LengthUnit`]).
//! * **OptiTrack Motive's CSV export** (`Format Version,1.23,...` and its rows of asset types,
//!   names and components): a rigid body's pose (the one, or the one named: [`PoseFile`]), in
//!   the export's `Length Units`; frames where the body was unseen are skipped (`motive.rs`).
//!   Fields are comma separated with optional spaces and optional double quotes. A commented
//!   header (`#timestamp,x,...`) is accepted too.
//!
//! In both the quaternion is in TUM order (x y z w) and a line gives `world_from_object`; a TUM
//! file written w x y z is read so where the user says ([`QuaternionOrder`]).
//! Values must be finite, the quaternion's norm within [`QUAT_NORM_TOLERANCE`] of 1 (it is then
//! normalised; its sign is kept) and timestamps strictly increasing; gaps are fine. A line
//! whose pose values are all `NaN`, all empty (CSV) or all zero is a frame where the tracker
//! lost the object: skipped as a gap and counted ([`SkippedLines`], [`PoseReader::skipped_lines`]);
//! so is a last line without its `\n` that does not read as a pose, after poses (a logger
//! stopped in the middle of it), and a line that repeats the one before exactly (its time and
//! pose: a logger that wrote it twice).
//!
//! Reading streams ([`PoseReader`], [`open`]); every error names the file, the line and the
//! problem, e.g. `demo.tum:17: expected 8 columns (timestamp tx ty tz qx qy qz qw), found 7`.
//!
//! The files, each importing only files above it in this list:
//!
//! * `layout.rs`: the column layout, the tolerances and limits, [`Format`];
//! * `number.rs`: [`parse_f64`];
//! * `problem.rs`: what can be wrong with a line, and its message;
//! * `check.rs`: the checks of a line's values, as pure functions;
//! * `time_unit.rs`: [`detect_time_unit`], stamps in ms, µs or ns recognised;
//! * `length_unit.rs`: [`LengthUnit`], [`DeclaredUnits`]: the units a CSV header declares;
//! * `quaternion_order.rs`: [`QuaternionOrder`], for TUM files written w x y z;
//! * `tum.rs`, `csv.rs`: the syntax of TUM and CSV lines, and CSV headers (with their units);
//! * `motive.rs`: OptiTrack Motive's CSV export (its preamble gives the CSV header);
//! * `detect.rs`: [`detect_format`];
//! * `date_time.rs`: a CSV time column's date-times (ISO 8601) as seconds;
//! * `skipped.rs`: [`SkippedLines`]: lines where the tracker lost the object (gaps), a last
//!   line cut short, lines written twice;
//! * `line.rs`: one line, given the ones before (format, header, previous pose);
//! * the fast path of TUM reading, speed code: `fast_field.rs` (plain decimals),
//!   `fast_line.rs` (the common line), `simd.rs` (the same with AVX2), `fast_run.rs` (groups
//!   of lines; the interface to the rest), `mapped.rs` (memory-mapped reading);
//! * `stream.rs`: lines out of a `BufRead`;
//! * `reader.rs`: [`PoseReader`];
//! * `files.rs`: [`open`], [`PoseFile`], [`read_trajectory`], [`read_demonstration`], palm files;
//! * `write.rs`: [`write_atomic`], [`write_tum`];
//! * `bag/`: ROS 2 bags (MCAP), [`bag::read_bag_demonstrations`].

pub mod bag;
mod check;
mod csv;
mod date_time;
mod detect;
mod fast_field;
mod fast_line;
mod fast_run;
mod files;
mod layout;
mod length_unit;
mod line;
mod mapped;
mod motive;
mod number;
mod problem;
#[cfg(test)]
mod props;
mod quaternion_order;
mod reader;
#[cfg(target_arch = "x86_64")]
mod simd;
mod skipped;
mod stream;
#[cfg(test)]
mod tests;
mod time_unit;
mod tum;
mod write;

pub use check::pose_from_values;
pub use detect::detect_format;
#[doc(hidden)]
pub use files::open_mapped;
pub use files::{
    declared_units, is_palm_file, open, palm_path_for, read_demonstration, read_first,
    read_first_declared, read_trajectory, PoseFile,
};
pub use layout::{Format, QUAT_NORM_TOLERANCE};
pub use length_unit::{to_metres, DeclaredUnits, LengthUnit};
pub use number::parse_f64;
pub use quaternion_order::QuaternionOrder;
pub use reader::PoseReader;
pub use skipped::{is_copy, is_lost, SkippedLines};
pub use time_unit::{
    conversion_warning, detect_time_unit, detect_time_unit_of, to_seconds, TimeUnit,
    TIME_UNIT_STAMPS,
};
pub use write::{write_atomic, write_tum};
