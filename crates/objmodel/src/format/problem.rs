//! What can be wrong with a line of a pose file, and the words for it.
//!
//! The checks (of values in `check.rs`, of TUM lines in `tum.rs`, of CSV lines and headers in
//! `csv.rs`) return a [`Problem`]: plain data about the line alone. The reader adds where the
//! line is ([`Context`]: line numbers, the text of a field) and turns the problem into a
//! `file:line: message` error with [`Problem::message`].

use super::date_time::looks_like_date_time;
use super::layout::{COLUMNS, CSV_NAMES, MAX_LINE, QUAT_NORM_TOLERANCE, TIME};

/// What is wrong with one line of a pose file.
#[derive(Clone, Debug, PartialEq)]
pub(crate) enum Problem {
    /// A TUM line with `found` fields instead of eight; `commas`: the line has commas (a CSV
    /// file without its header, most likely).
    TumColumns { found: usize, commas: bool },
    /// A CSV line with `found` fields where its header, on line `header_line`, has `expected`.
    CsvColumns {
        expected: usize,
        found: usize,
        header_line: usize,
    },
    /// Field `column` (1-based), which holds value `role` (an index into `COLUMNS`), is `text`,
    /// which is not a number.
    NotANumber {
        column: usize,
        role: usize,
        text: Vec<u8>,
    },
    /// Field `column` (1-based), the time, is `text`, which begins as a date-time does but
    /// does not read as one (`why`: `date_time.rs`).
    NotADateTime {
        column: usize,
        text: Vec<u8>,
        why: String,
    },
    /// The line is longer than `MAX_LINE` bytes.
    LineTooLong,
    /// A CSV header without a column for the values `missing` (indices into `COLUMNS`);
    /// `found` are its column names (lower case).
    MissingColumns {
        missing: Vec<usize>,
        found: Vec<String>,
    },
    /// A CSV header whose columns `first` and `second` (1-based), named `names`, both give
    /// value `role`.
    DoubledColumn {
        role: usize,
        first: usize,
        second: usize,
        names: [String; 2],
    },
    /// A CSV header's column `column` (1-based), named `name`, which gives value `role`,
    /// declares a unit that is none of that value's.
    UnknownUnit {
        column: usize,
        role: usize,
        name: String,
    },
    /// A CSV header's position columns, named `names`, declare different units.
    MixedUnits { names: [String; 2] },
    /// A motion-capture (OptiTrack Motive) export that cannot be read, and why.
    Motive(String),
    /// A rigid body was named for a file that is no Motive export.
    NotMotive(String),
    /// Value `role` is NaN (`nan`) or infinite.
    NotFinite { role: usize, nan: bool },
    /// The quaternion `q` (qx qy qz qw) is zero.
    ZeroQuaternion { q: [f64; 4] },
    /// The quaternion `q` (qx qy qz qw) has a norm that differs from 1 by more than
    /// `QUAT_NORM_TOLERANCE`.
    NormOff { q: [f64; 4], norm: f64 },
    /// The timestamp `t` is not after `prev_t`, the previous pose's.
    TimeNotIncreasing { t: f64, prev_t: f64 },
}

/// Where a [`Problem`] is: what its message needs beyond the line's values.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Context<'a> {
    /// Number of the line (1-based).
    pub(crate) line: usize,
    /// Line of the previous pose.
    pub(crate) prev_line: usize,
    /// The text of the field that a [`Problem::NotFinite`] names, if found.
    pub(crate) field: Option<&'a [u8]>,
}

impl Problem {
    /// The message for people, e.g. `expected 8 columns (timestamp tx ty tz qx qy qz qw),
    /// found 7` (without the `file:line: ` that the error adds).
    #[cold]
    pub(crate) fn message(&self, at: &Context) -> String {
        match self {
            Problem::TumColumns { found, commas } => {
                let mut msg =
                    format!("expected 8 columns (timestamp tx ty tz qx qy qz qw), found {found}");
                if *commas {
                    msg.push_str(
                        " (the line has commas: a CSV file needs a header line naming the \
                         columns, e.g. timestamp,tx,ty,tz,qx,qy,qz,qw)",
                    );
                }
                msg
            }
            Problem::CsvColumns {
                expected,
                found,
                header_line,
            } => format!(
                "expected {expected} columns (as in the CSV header on line {header_line}), \
                 found {found}"
            ),
            Problem::NotANumber { column, role, text } => {
                let name = COLUMNS[*role];
                if text.is_empty() {
                    format!("column {column} ({name}) is empty; expected a number")
                } else if *role == TIME && looks_like_date_time(text) {
                    format!(
                        "column {column} ({name}): {} is not a number (a TUM file's timestamps \
                         are seconds; a date-time is read from a CSV file's time column)",
                        quote(text)
                    )
                } else {
                    format!("column {column} ({name}): {} is not a number", quote(text))
                }
            }
            Problem::NotADateTime { column, text, why } => format!(
                "column {column} (timestamp): {} is neither a number of seconds nor a \
                 date-time that reads ({why}; ISO 8601 as 2026-12-07T10:00:00.25Z, with an \
                 offset or without one for UTC)",
                quote(text)
            ),
            Problem::LineTooLong => format!("line is longer than {MAX_LINE} bytes"),
            Problem::MissingColumns { missing, found } => {
                let missing: Vec<&str> = missing.iter().map(|&r| COLUMNS[r]).collect();
                // Ours and TUM's (the first three at most); the other tools' are in the README.
                let accepted: Vec<String> = CSV_NAMES
                    .iter()
                    .map(|n| n[..n.len().min(3)].join("/"))
                    .collect();
                // At most MAX_NAMES names, each shortened: a header line may be 1 MiB.
                let mut names: Vec<String> = found
                    .iter()
                    .take(MAX_NAMES)
                    .map(|n| quote(n.as_bytes()))
                    .collect();
                if found.len() > MAX_NAMES {
                    names.push(format!("... ({} columns)", found.len()));
                }
                // One field holding the whole header: another separator than the comma.
                let separator = match found.as_slice() {
                    [one] => [';', '\t', '|']
                        .into_iter()
                        .find(|c| one.contains(*c))
                        .map(|c| {
                            format!(
                                " (the header's columns are separated by {c:?}: a CSV file's \
                                 by commas)"
                            )
                        }),
                    _ => None,
                };
                format!(
                    "CSV header has no column for {} (accepted names: {}, in any order, \
                     case-insensitive; also EuRoC's, ROS messages' and motion-capture exports' \
                     names, with units in brackets or parentheses); found {}{}",
                    missing.join(", "),
                    accepted.join(", "),
                    names.join(", "),
                    separator.unwrap_or_default()
                )
            }
            Problem::DoubledColumn {
                role,
                first,
                second,
                names: [a, b],
            } => format!(
                "CSV header: columns {first} and {second} both give {} (\"{a}\" and \"{b}\")",
                COLUMNS[*role]
            ),
            Problem::UnknownUnit { column, role, name } => {
                let expected = if *role == 0 {
                    "a time: s, ms, us or ns"
                } else {
                    "a length: m, cm or mm"
                };
                format!(
                    "CSV header: column {column} (\"{name}\", {}) declares a unit that is not \
                     {expected}",
                    COLUMNS[*role]
                )
            }
            Problem::MixedUnits { names: [a, b] } => format!(
                "CSV header: the position columns declare different units (\"{a}\" and \
                 \"{b}\"); give them one"
            ),
            Problem::Motive(why) => format!("Motive export: {why}"),
            Problem::NotMotive(body) => format!(
                "a rigid body ({body:?}) was named, but this is no OptiTrack Motive export \
                 (whose first line is `Format Version,...`): only a Motive take holds several \
                 bodies (a bag's topics are named with --object too)"
            ),
            Problem::NotFinite { role, nan } => {
                let what = if *nan { "NaN" } else { "infinite" };
                let quoted = at
                    .field
                    .map(|f| format!(" ({})", quote(f)))
                    .unwrap_or_default();
                format!(
                    "{} is {what}{quoted}; every value must be a finite number",
                    COLUMNS[*role]
                )
            }
            Problem::ZeroQuaternion { q } => format!(
                "quaternion (qx qy qz qw) = {} is zero, which is no rotation",
                quaternion(q)
            ),
            Problem::NormOff { q, norm } => format!(
                "quaternion (qx qy qz qw) = {} has norm {}, which differs from 1 by more than \
                 the tolerance {QUAT_NORM_TOLERANCE}",
                quaternion(q),
                num(*norm)
            ),
            Problem::TimeNotIncreasing { t, prev_t } => {
                let how = if t == prev_t {
                    "repeats"
                } else {
                    "goes back from"
                };
                let (l, pl) = (at.line, at.prev_line);
                format!(
                    "timestamp {} on line {l} {how} timestamp {} on line {pl} \
                     (timestamps must strictly increase)",
                    num(*t),
                    num(*prev_t)
                )
            }
        }
    }

    /// The value a problem of the values names (for [`Context::field`]), if it names one.
    pub(crate) fn role(&self) -> Option<usize> {
        match self {
            Problem::NotFinite { role, .. } => Some(*role),
            _ => None,
        }
    }
}

/// Column names a message about a CSV header lists at most.
const MAX_NAMES: usize = 16;

/// `(qx, qy, qz, qw)` for messages.
fn quaternion(q: &[f64; 4]) -> String {
    format!(
        "({}, {}, {}, {})",
        num(q[0]),
        num(q[1]),
        num(q[2]),
        num(q[3])
    )
}

/// A number for messages: plain (shortest round trip) unless very large or very small.
fn num(x: f64) -> String {
    let a = x.abs();
    if a != 0.0 && !(1e-5..1e16).contains(&a) {
        format!("{x:e}")
    } else {
        format!("{x}")
    }
}

/// `"text"`, shortened if long, for messages.
fn quote(field: &[u8]) -> String {
    let text = String::from_utf8_lossy(field);
    if text.chars().count() > 40 {
        format!("\"{}...\"", text.chars().take(40).collect::<String>())
    } else {
        format!("\"{text}\"")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The words of every problem, as the tests of the command line expect them.
    #[test]
    fn messages() {
        let at = Context {
            line: 6,
            prev_line: 5,
            field: Some(b"NaN"),
        };
        let say = |p: Problem| p.message(&at);
        assert_eq!(
            say(Problem::TumColumns {
                found: 1,
                commas: true
            }),
            "expected 8 columns (timestamp tx ty tz qx qy qz qw), found 1 (the line has commas: \
             a CSV file needs a header line naming the columns, e.g. \
             timestamp,tx,ty,tz,qx,qy,qz,qw)"
        );
        assert_eq!(
            say(Problem::NotFinite { role: 2, nan: true }),
            "ty is NaN (\"NaN\"); every value must be a finite number"
        );
        assert_eq!(
            say(Problem::MissingColumns {
                missing: vec![6],
                found: vec!["t".into(), "x".into()]
            }),
            "CSV header has no column for qz (accepted names: timestamp/t/time, tx/x/px, \
             ty/y/py, tz/z/pz, qx/q_x/quat_x, qy/q_y/quat_y, qz/q_z/quat_z, qw/q_w/quat_w, in \
             any order, case-insensitive; also EuRoC's, ROS messages' and motion-capture \
             exports' names, with units in brackets or parentheses); found \"t\", \"x\""
        );
        assert_eq!(
            say(Problem::TimeNotIncreasing {
                t: 0.25,
                prev_t: 0.4
            }),
            "timestamp 0.25 on line 6 goes back from timestamp 0.4 on line 5 (timestamps must \
             strictly increase)"
        );
        assert_eq!(
            say(Problem::NormOff {
                q: [0.0, 0.0, 0.0, 1.5],
                norm: 1.5
            }),
            "quaternion (qx qy qz qw) = (0, 0, 0, 1.5) has norm 1.5, which differs from 1 by \
             more than the tolerance 0.01"
        );
        assert_eq!(
            say(Problem::NotANumber {
                column: 70,
                role: 0,
                text: vec![b'x'; 50]
            }),
            format!(
                "column 70 (timestamp): \"{}...\" is not a number",
                "x".repeat(40)
            )
        );
        // A header of many (long) names: the first 16, shortened, and the count.
        let many = Problem::MissingColumns {
            missing: vec![0],
            found: (0..100_000).map(|k| format!("{k:0>50}")).collect(),
        };
        let m = say(many);
        assert!(m.len() < 1500, "{} bytes", m.len());
        assert!(
            m.ends_with(&format!(
                "found \"{}...\", {}... (100000 columns)",
                "0".repeat(40),
                format!("\"{}...\", ", "0".repeat(40)).repeat(15)
            )),
            "{m}"
        );
        assert_eq!(num(1e-7), "1e-7");
        assert_eq!(num(1.7e9), "1700000000");
    }
}
