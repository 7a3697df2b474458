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

/// Accepted CSV header names (lower case) for each column, in TUM order, after
/// [`column_name`]: ours and TUM's, the EuRoC/ASL ground truth's (`p_RS_R_x [m]`,
/// `q_RS_w []`), a motion-capture export's (`Time (Seconds)`, `X`, `qX`) and a ROS message's
/// flattened to CSV (`%time`, `field.pose.position.x`, `field.pose.orientation.w`,
/// `field.transform.translation.x`, `field.transform.rotation.w`: a quaternion's `rotation`
/// needs its `w`, so Euler angles under those names are refused as a missing `qw`).
#[rustfmt::skip]
pub(crate) const CSV_NAMES: [&[&str]; VALUES] = [
    &["timestamp", "t", "time", "stamp", "header_stamp", "%time", "__time"],
    &["tx", "x", "px", "pos_x", "position_x", "translation_x", "p_rs_r_x"],
    &["ty", "y", "py", "pos_y", "position_y", "translation_y", "p_rs_r_y"],
    &["tz", "z", "pz", "pos_z", "position_z", "translation_z", "p_rs_r_z"],
    &["qx", "q_x", "quat_x", "orientation_x", "rotation_x", "q_rs_x"],
    &["qy", "q_y", "quat_y", "orientation_y", "rotation_y", "q_rs_y"],
    &["qz", "q_z", "quat_z", "orientation_z", "rotation_z", "q_rs_z"],
    &["qw", "q_w", "quat_w", "orientation_w", "rotation_w", "q_rs_w"],
];

/// The column (index in TUM order) a CSV header field names ([`column_name`], [`CSV_NAMES`]),
/// if any.
pub(crate) fn column_role(field: &str) -> Option<usize> {
    let name = column_name(field);
    CSV_NAMES
        .iter()
        .position(|names| names.contains(&name.as_str()))
}

/// A ROS message's stamp, flattened to CSV (`field.header.stamp`): the time of the measurement.
pub(crate) const HEADER_STAMP: &str = "header_stamp";
/// The time a ROS message was logged, flattened to CSV (`%time`; PlotJuggler's `__time`): a
/// timestamp only where the file has no [`HEADER_STAMP`] (the transport's delay and jitter
/// are in it).
pub(crate) fn is_log_time(name: &str) -> bool {
    matches!(name, "%time" | "__time")
}

/// Units a name may end in after an `_` (`time_s`, `x_mm`), where the rest is a name of
/// [`CSV_NAMES`].
const UNIT_SUFFIXES: [&str; 8] = ["s", "sec", "ms", "us", "ns", "m", "cm", "mm"];

/// A CSV header field as [`CSV_NAMES`] lists it: lower case, without a unit in brackets or
/// parentheses at its end (`Time (Seconds)`, `p_RS_R_x [m]`) or after an `_` (`x_mm`), and a
/// path reduced to its last two parts joined by `_` (a ROS message flattened to CSV,
/// `field.pose.position.x`, and PlotJuggler's `/tag/pose/position/x` are `position_x`).
pub(crate) fn column_name(field: &str) -> String {
    let mut name = field.trim().to_ascii_lowercase();
    for (open, close) in [('[', ']'), ('(', ')')] {
        if name.ends_with(close) {
            if let Some(at) = name.rfind(open) {
                name.truncate(at);
                name = name.trim_end().to_string();
            }
        }
    }
    let parts: Vec<&str> = name.split(['.', '/']).filter(|p| !p.is_empty()).collect();
    if parts.len() > 1 {
        name = parts[parts.len() - 2..].join("_");
    }
    match unit_suffix(&name) {
        Some((known, _)) => known.to_string(),
        None => name,
    }
}

/// A name that ends in a unit after an `_` (`time_s`, `x_mm`), where the rest is a name of
/// [`CSV_NAMES`] and the whole is none: the rest and the unit.
fn unit_suffix(name: &str) -> Option<(&str, &str)> {
    let known = |n: &str| CSV_NAMES.iter().any(|names| names.contains(&n));
    let (rest, unit) = name.rsplit_once('_')?;
    (UNIT_SUFFIXES.contains(&unit) && known(rest) && !known(name)).then_some((rest, unit))
}

/// The unit a CSV header field declares in brackets or parentheses at its end, lower case
/// (`X (Millimeters)`: `millimeters`), or after an `_` (`x_mm`), if any; empty brackets
/// (EuRoC's `q_RS_w []`) declare none.
pub(crate) fn column_unit(field: &str) -> Option<String> {
    let name = field.trim().to_lowercase();
    let bracketed = [('[', ']'), ('(', ')')]
        .into_iter()
        .find_map(|(open, close)| {
            let inner = name.strip_suffix(close)?;
            let unit = inner[inner.rfind(open)? + open.len_utf8()..].trim();
            (!unit.is_empty()).then(|| unit.to_string())
        });
    bracketed.or_else(|| unit_suffix(&name).map(|(_, unit)| unit.to_string()))
}

/// A quaternion whose norm differs from 1 by more than this (relative) is rejected as corrupt;
/// smaller deviations (rounding in the file) are normalised silently.
pub const QUAT_NORM_TOLERANCE: f64 = 1e-2;

/// Lines longer than this \[bytes\] are rejected (keeps memory bounded on garbage input).
pub(crate) const MAX_LINE: usize = 1 << 20;
