//! Date-times in a CSV file's time column: loggers and data frames write the time of a pose as
//! a date and a time of day (pandas' `to_csv` of a `DatetimeIndex`: `2026-12-07
//! 10:00:00.123456`; RFC 3339: `2026-12-07T10:00:00.123456Z`, `...+01:00`) as often as in
//! seconds. Read here as seconds since the Unix epoch, by ISO 8601's rules (`T` or a space
//! between date and time, `Z` or an offset, or none: then UTC, since only the differences of
//! a demonstration's times matter; up to nanoseconds). A date without a time of day is no
//! time of a pose. TUM files keep the format's seconds.
//!
//! The seconds are an `f64`: about 0.2 µs apart at today's dates, well below any tracker's
//! frame period (as for the epoch seconds that TUM files hold).

use jiff::civil::DateTime;
use jiff::Timestamp;

/// Seconds since the Unix epoch of the date-time `field` (ISO 8601 / RFC 3339, see the module
/// documentation), or why it is none.
pub(crate) fn seconds_since_epoch(field: &[u8]) -> Result<f64, String> {
    let text = std::str::from_utf8(field).map_err(|_| "not UTF-8".to_string())?;
    let has_time = text.contains(['T', 't', ' ']);
    let instant = match text.parse::<Timestamp>() {
        Ok(t) => t,
        Err(with_offset) => {
            let civil = text.parse::<DateTime>().map_err(|e| match e.to_string() {
                // A Zulu time that does not read says why as an instant, not as a civil one.
                why if why.contains("Zulu") => with_offset.to_string(),
                why => why,
            })?;
            if !has_time {
                return Err("a date without a time of day".into());
            }
            civil
                .to_zoned(jiff::tz::TimeZone::UTC)
                .map_err(|e| e.to_string())?
                .timestamp()
        }
    };
    Ok(instant.as_second() as f64 + f64::from(instant.subsec_nanosecond()) * 1e-9)
}

/// Whether `field` looks like a date-time that is meant (four digits and a `-`, as ISO 8601's
/// dates begin), so that a message can say why it does not read.
pub(crate) fn looks_like_date_time(field: &[u8]) -> bool {
    field.len() > 4 && field[..4].iter().all(u8::is_ascii_digit) && field[4] == b'-'
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    /// 2026-12-07T10:00:00Z.
    const T0: f64 = 1_796_637_600.0;

    #[test]
    fn the_forms_loggers_write() {
        let cases = [
            ("2026-12-07T10:00:00Z", T0),
            ("2026-12-07t10:00:00z", T0),
            ("2026-12-07 10:00:00", T0),
            ("2026-12-07T10:00:00.25", T0 + 0.25),
            ("2026-12-07 10:00:00.123456", T0 + 0.123456),
            ("2026-12-07T10:00:00.123456789Z", T0 + 0.123456789),
            ("2026-12-07T11:00:00.5+01:00", T0 + 0.5),
            ("2026-12-07T05:00:00-0500", T0),
            ("2026-12-07T10:00:00,5Z", T0 + 0.5),
            ("20261207T100000Z", T0),
            ("1970-01-01T00:00:00Z", 0.0),
        ];
        for (text, want) in cases {
            let got =
                seconds_since_epoch(text.as_bytes()).unwrap_or_else(|e| panic!("{text}: {e}"));
            assert!((got - want).abs() < 1e-6, "{text}: {got} against {want}");
        }
    }

    #[test]
    fn what_is_no_time_of_a_pose_says_why() {
        for (text, why) in [
            ("2026-12-07", "without a time of day"),
            ("2026-13-07T10:00:00Z", "month"),
            ("2026-12-07T25:00:00", "hour"),
            ("2026-12-07T10:00:00.1234567891Z", "unparsed input"),
            ("1.5", "year"),
            ("", "year"),
        ] {
            let e = seconds_since_epoch(text.as_bytes()).expect_err(text);
            assert!(e.contains(why), "{text}: {e}");
        }
        assert!(looks_like_date_time(b"2026-13-07T10:00:00Z"));
        assert!(!looks_like_date_time(b"1796637600.5"));
        assert!(!looks_like_date_time(b"-1e3"));
    }

    proptest! {
        /// Any instant of this century, written as RFC 3339 with nanoseconds and any whole
        /// minute offset, reads back to within the `f64`'s resolution.
        #[test]
        fn written_instants_read_back(
            s in 946_684_800i64..4_102_444_800,
            ns in 0i32..1_000_000_000,
            offset_min in -12 * 60i32..14 * 60,
            space in any::<bool>(),
        ) {
            let t = Timestamp::new(s, ns).unwrap();
            let off = jiff::tz::Offset::from_seconds(offset_min * 60).unwrap();
            let mut text = t.to_zoned(jiff::tz::TimeZone::fixed(off)).strftime("%Y-%m-%dT%H:%M:%S.%f%:z").to_string();
            if space {
                text = text.replacen('T', " ", 1);
            }
            let got = seconds_since_epoch(text.as_bytes()).unwrap();
            let want = s as f64 + f64::from(ns) * 1e-9;
            prop_assert!((got - want).abs() <= 1e-6, "{} {} {}", text, got, want);
        }
    }
}
