//! The unit of a pose file's timestamps. TUM stamps are seconds, but trackers and loggers also
//! write milliseconds, microseconds or nanoseconds (ROS's `header.stamp` as one integer);
//! every time-based test (rest windows, velocities) assumes seconds.
//!
//! The rule ([`detect_time_unit`]), on the first stamps of a stream:
//!
//! 1. **magnitude**: a first stamp that is a Unix time of the years 1980-2286 in one of the
//!    units (3.2e8-1e10 s, 3.2e11-1e13 ms, 3.2e14-1e16 µs, 3.2e17-1e19 ns) names the unit;
//! 2. else **spacing**: the median interval between the first frames is seconds if at most
//!    1 (1 Hz or faster), else milliseconds up to 1e3, microseconds up to 1e6, nanoseconds
//!    up to 1e9 (each: 1 Hz or faster in that unit); beyond, seconds (and the classifier warns
//!    that the frames are far apart).

use crate::trajectory::StampedPose;

/// A unit of timestamps.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TimeUnit {
    /// Seconds.
    Seconds,
    /// Milliseconds.
    Milliseconds,
    /// Microseconds.
    Microseconds,
    /// Nanoseconds.
    Nanoseconds,
}

impl TimeUnit {
    /// Seconds per unit.
    pub fn seconds(self) -> f64 {
        match self {
            TimeUnit::Seconds => 1.0,
            TimeUnit::Milliseconds => 1e-3,
            TimeUnit::Microseconds => 1e-6,
            TimeUnit::Nanoseconds => 1e-9,
        }
    }

    /// Its name.
    pub fn name(self) -> &'static str {
        match self {
            TimeUnit::Seconds => "seconds",
            TimeUnit::Milliseconds => "milliseconds",
            TimeUnit::Microseconds => "microseconds",
            TimeUnit::Nanoseconds => "nanoseconds",
        }
    }

    const ALL: [TimeUnit; 4] = [
        TimeUnit::Seconds,
        TimeUnit::Milliseconds,
        TimeUnit::Microseconds,
        TimeUnit::Nanoseconds,
    ];
}

/// Stamps looked at by [`detect_time_unit_of`].
pub const TIME_UNIT_STAMPS: usize = 64;

/// The unit of stamps `times` (the first [`TIME_UNIT_STAMPS`] of a stream, in order; see the
/// module's documentation). Seconds for fewer than two.
pub fn detect_time_unit(times: &[f64]) -> TimeUnit {
    let Some(&t0) = times.first() else {
        return TimeUnit::Seconds;
    };
    let epoch = |u: TimeUnit| {
        let s = t0.abs() * u.seconds();
        (3.2e8..1e10).contains(&s)
    };
    if let Some(u) = TimeUnit::ALL.into_iter().find(|&u| epoch(u)) {
        return u;
    }
    let mut dt: Vec<f64> = times.windows(2).map(|w| w[1] - w[0]).collect();
    if dt.is_empty() {
        return TimeUnit::Seconds;
    }
    dt.sort_by(f64::total_cmp);
    let median = dt[dt.len() / 2];
    TimeUnit::ALL
        .into_iter()
        .find(|u| median * u.seconds() <= 1.0)
        .filter(|_| median > 0.0)
        .unwrap_or(TimeUnit::Seconds)
}

/// The unit of `poses`' stamps ([`detect_time_unit`] on the first ones).
pub fn detect_time_unit_of(poses: &[StampedPose]) -> TimeUnit {
    let t: Vec<f64> = poses.iter().take(TIME_UNIT_STAMPS).map(|p| p.t).collect();
    detect_time_unit(&t)
}

/// The warning for stamps of `what` read in `unit` and converted to seconds.
pub fn conversion_warning(what: &str, unit: TimeUnit) -> String {
    format!(
        "the {what}'s timestamps look like {} (by their magnitude and spacing) and were \
         converted to seconds",
        unit.name()
    )
}

/// Convert `poses`' stamps from `unit` to seconds.
pub fn to_seconds(poses: &mut [StampedPose], unit: TimeUnit) {
    if unit != TimeUnit::Seconds {
        let k = unit.seconds();
        poses.iter_mut().for_each(|p| p.t *= k);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn stamps(t0: f64, hz: f64, unit: TimeUnit) -> Vec<f64> {
        (0..64)
            .map(|k| (t0 + k as f64 / hz) / unit.seconds())
            .collect()
    }

    #[test]
    fn units_are_told_by_magnitude_and_by_spacing() {
        for unit in TimeUnit::ALL {
            for hz in [10.0, 30.0, 120.0, 1000.0] {
                // Unix times: by magnitude, whatever the rate.
                assert_eq!(
                    detect_time_unit(&stamps(1.7e9, hz, unit)),
                    unit,
                    "{unit:?} {hz}"
                );
                // From zero: by spacing (below 1 kHz, where ms and s spacings overlap).
                if hz < 1000.0 {
                    assert_eq!(
                        detect_time_unit(&stamps(0.0, hz, unit)),
                        unit,
                        "{unit:?} {hz}"
                    );
                }
            }
        }
        // A slow stream in seconds from zero stays seconds; too few stamps are seconds.
        assert_eq!(
            detect_time_unit(&stamps(0.0, 1.5, TimeUnit::Seconds)),
            TimeUnit::Seconds
        );
        assert_eq!(detect_time_unit(&[]), TimeUnit::Seconds);
        assert_eq!(detect_time_unit(&[5.0]), TimeUnit::Seconds);
    }
}
