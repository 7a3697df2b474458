//! The unit of a pose file's positions. The learner works in metres (gravity, the tracking
//! noise, every tolerance), but motion-capture software exports millimetres as often as metres
//! (OptiTrack's and Vicon's defaults), and a file read in the wrong unit gives a model a
//! thousand times too large, or none.
//!
//! Where the unit comes from, first found wins:
//!
//! 1. **declared** in a CSV header: a unit in brackets or parentheses after a position
//!    column's name (`x [mm]`, `Position X (millimeters)`, `p_RS_R_x [m]`), the same for
//!    the three; the timestamp's likewise (`Time (Seconds)`, `t [ns]`), which then replaces
//!    the guess by magnitude ([`super::detect_time_unit`]);
//! 2. **given** by the user for files that declare none (`--length-unit mm`,
//!    [`crate::classify::Config::length_unit`]);
//! 3. else metres, and the learner checks that the data look like metres
//!    (`crate::length_check`): a demonstration whose tracking noise or features are
//!    implausible in metres teaches nothing, and its report says which unit to give.

use super::time_unit::TimeUnit;
use crate::trajectory::StampedPose;
use serde::{Deserialize, Serialize};

/// A unit of length.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum LengthUnit {
    /// Metres.
    #[serde(rename = "m")]
    Metres,
    /// Centimetres.
    #[serde(rename = "cm")]
    Centimetres,
    /// Millimetres.
    #[serde(rename = "mm")]
    Millimetres,
}

impl LengthUnit {
    /// Metres per unit.
    pub fn metres(self) -> f64 {
        match self {
            LengthUnit::Metres => 1.0,
            LengthUnit::Centimetres => 1e-2,
            LengthUnit::Millimetres => 1e-3,
        }
    }

    /// Its symbol: `m`, `cm`, `mm`.
    pub fn symbol(self) -> &'static str {
        match self {
            LengthUnit::Metres => "m",
            LengthUnit::Centimetres => "cm",
            LengthUnit::Millimetres => "mm",
        }
    }

    /// The unit a name says (any case; symbol, or the name in British or American spelling,
    /// singular or plural), if it is one.
    pub fn from_name(name: &str) -> Option<LengthUnit> {
        let n = name.trim().to_ascii_lowercase();
        // A name in full may be plural; a symbol may not (`ms` is no length).
        let n = match n.strip_suffix('s') {
            Some(singular) if singular.len() > 2 => singular,
            _ => &n,
        };
        match n {
            "m" | "metre" | "meter" => Some(LengthUnit::Metres),
            "cm" | "centimetre" | "centimeter" => Some(LengthUnit::Centimetres),
            "mm" | "millimetre" | "millimeter" => Some(LengthUnit::Millimetres),
            _ => None,
        }
    }
}

impl std::str::FromStr for LengthUnit {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        LengthUnit::from_name(s)
            .ok_or_else(|| format!("unknown length unit {s:?}; expected m, cm or mm"))
    }
}

impl std::fmt::Display for LengthUnit {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.symbol())
    }
}

/// The unit a timestamp column's name declares (`s`, `sec`, `seconds`, `ms`, `us`, `µs`,
/// `ns`, and the names in full, any case), if it is one.
pub(crate) fn time_unit_from_name(name: &str) -> Option<TimeUnit> {
    match name.trim().to_lowercase().as_str() {
        "s" | "sec" | "secs" | "second" | "seconds" => Some(TimeUnit::Seconds),
        "ms" | "msec" | "millisecond" | "milliseconds" => Some(TimeUnit::Milliseconds),
        "us" | "µs" | "μs" | "usec" | "microsecond" | "microseconds" => {
            Some(TimeUnit::Microseconds)
        }
        "ns" | "nsec" | "nanosecond" | "nanoseconds" => Some(TimeUnit::Nanoseconds),
        _ => None,
    }
}

/// Convert `poses`' positions from `unit` to metres.
pub fn to_metres(poses: &mut [StampedPose], unit: LengthUnit) {
    if unit != LengthUnit::Metres {
        let k = unit.metres();
        poses
            .iter_mut()
            .for_each(|p| p.pose.translation.vector *= k);
    }
}

/// The units a pose file declares (a CSV header's); nothing for TUM files and CSV headers
/// without units.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct DeclaredUnits {
    /// The positions' unit.
    pub length: Option<LengthUnit>,
    /// The timestamps' unit.
    pub time: Option<TimeUnit>,
    /// Whether the file names its columns (a CSV header's, a Motive export's): the quaternion
    /// is then read by the names, whatever [`super::QuaternionOrder`] is given.
    pub named_columns: bool,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn length_names_in_every_spelling() {
        for (names, unit) in [
            (["m", "metre", "Meters", "METRES"], LengthUnit::Metres),
            (
                ["cm", "centimetre", "Centimeters", "CM"],
                LengthUnit::Centimetres,
            ),
            (
                ["mm", "millimetres", "Millimeters", " MM "],
                LengthUnit::Millimetres,
            ),
        ] {
            for n in names {
                assert_eq!(LengthUnit::from_name(n), Some(unit), "{n}");
                assert_eq!(n.parse::<LengthUnit>(), Ok(unit), "{n}");
            }
            // The symbol and the serialised name read back as the unit.
            assert_eq!(LengthUnit::from_name(unit.symbol()), Some(unit));
            let json = serde_json::to_string(&unit).unwrap();
            assert_eq!(json, format!("\"{}\"", unit.symbol()));
            assert_eq!(serde_json::from_str::<LengthUnit>(&json).unwrap(), unit);
        }
        for bad in ["", "s", "deg", "rad", "km", "inch", "ms", "mms"] {
            assert_eq!(LengthUnit::from_name(bad), None, "{bad}");
            assert!(bad
                .parse::<LengthUnit>()
                .unwrap_err()
                .contains("m, cm or mm"));
        }
        assert_eq!(LengthUnit::Millimetres.metres() * 1000.0, 1.0);
        assert_eq!(LengthUnit::Centimetres.metres() * 100.0, 1.0);
    }

    #[test]
    fn time_names_in_every_spelling() {
        for (names, unit) in [
            (vec!["s", "sec", "Seconds", "SECOND"], TimeUnit::Seconds),
            (vec!["ms", "msec", "milliseconds"], TimeUnit::Milliseconds),
            (
                vec!["us", "µs", "μs", "usec", "Microseconds"],
                TimeUnit::Microseconds,
            ),
            (
                vec!["ns", "nsec", "nanoseconds", "NS"],
                TimeUnit::Nanoseconds,
            ),
        ] {
            for n in names {
                assert_eq!(time_unit_from_name(n), Some(unit), "{n}");
            }
        }
        for bad in ["", "m", "mm", "min", "hours", "deg", "ss"] {
            assert_eq!(time_unit_from_name(bad), None, "{bad}");
        }
    }
}
