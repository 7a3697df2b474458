//! The layout of a pose line and the limits of its values: what the other format files read
//! their constants from (this file imports none of them).
//!
//! A line holds eight values in TUM order, `timestamp tx ty tz qx qy qz qw`: the time, the
//! translation and the quaternion (x y z w) of `world_from_object`. Every value must be finite,
//! the quaternion's norm within [`QUAT_NORM_TOLERANCE`] of 1, and the timestamps strictly
//! increasing; there is no limit on the step between two timestamps (gaps are fine).

/// Which text format a file is in.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Format {
    /// `timestamp tx ty tz qx qy qz qw`, whitespace separated (TUM RGB-D benchmark).
    Tum,
    /// Comma separated with a header line naming the columns.
    Csv,
}

/// Number of values on a line.
pub(crate) const VALUES: usize = 8;

/// Column names in TUM order; also the roles a CSV column can have.
pub(crate) const COLUMNS: [&str; VALUES] = ["timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"];

/// Index of the timestamp in TUM order.
pub(crate) const TIME: usize = 0;

/// Index of the quaternion's first value (`qx`) in TUM order; `qx qy qz qw` follow.
pub(crate) const QUAT: usize = 4;

/// Accepted CSV header names (lower case) for each column, in TUM order.
pub(crate) const CSV_NAMES: [&[&str]; VALUES] = [
    &["timestamp", "t", "time"],
    &["tx", "x"],
    &["ty", "y"],
    &["tz", "z"],
    &["qx"],
    &["qy"],
    &["qz"],
    &["qw"],
];

/// A quaternion whose norm differs from 1 by more than this (relative) is rejected as corrupt;
/// smaller deviations (rounding in the file) are normalised silently.
pub const QUAT_NORM_TOLERANCE: f64 = 1e-2;

/// Lines longer than this \[bytes\] are rejected (keeps memory bounded on garbage input).
pub(crate) const MAX_LINE: usize = 1 << 20;
