//! TUM lines: `timestamp tx ty tz qx qy qz qw`, separated by any spaces or tabs, `#` starting
//! a comment. [`scan_tum`] reads any line, and [`TumScan::values`] gives its values or its
//! [`Problem`]. (The common line also has a fast path, see `fast_run.rs`.) A first line that
//! names the columns in that order, uncommented (`timestamp tx ty tz qx qy qz qw`, or with
//! other tools' names for them, [`is_tum_header`]), is a header, not a bad line.

use super::layout::{column_role, VALUES};
use super::number::parse_f64;
use super::problem::Problem;

/// Whether `line` names the eight columns in TUM order, separated by whitespace (each field
/// naming its column as a CSV header's would, [`column_role`]).
pub(crate) fn is_tum_header(line: &[u8]) -> bool {
    let text = String::from_utf8_lossy(line);
    let roles: Vec<Option<usize>> = text.split_ascii_whitespace().map(column_role).collect();
    roles.len() == VALUES && roles.iter().enumerate().all(|(k, r)| *r == Some(k))
}

/// A TUM line scanned up to its `\n` (or the end of the slice).
pub(crate) struct TumScan {
    /// The first eight values.
    pub(crate) vals: [f64; VALUES],
    /// Number of fields.
    pub(crate) count: usize,
    /// First field that is not a number: (column, start, end).
    pub(crate) bad: Option<(usize, usize, usize)>,
    /// Index of the `\n` ending the line, or the slice length if there is none.
    pub(crate) end: usize,
}

impl TumScan {
    /// The values of the scanned `line` (what was scanned, without its `\n`), `None` for a line
    /// without fields (blank or comment), or the problem: the column count first, then the
    /// first field that is not a number.
    #[inline(always)]
    pub(crate) fn values(&self, line: &[u8]) -> Result<Option<[f64; VALUES]>, Problem> {
        if self.count == VALUES && self.bad.is_none() {
            return Ok(Some(self.vals));
        }
        if self.count == 0 {
            return Ok(None);
        }
        Err(self.problem(line))
    }

    #[cold]
    fn problem(&self, line: &[u8]) -> Problem {
        if self.count != VALUES {
            return Problem::TumColumns {
                found: self.count,
                commas: line.contains(&b','),
            };
        }
        let (k, a, b) = self.bad.unwrap_or((0, 0, 0));
        Problem::NotANumber {
            column: k + 1,
            role: k,
            text: line[a..b].to_vec(),
        }
    }
}

/// Field separators of TUM (a stray `\r` counts as one).
#[inline(always)]
pub(crate) fn is_tum_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r')
}

/// Bytes that end a TUM field.
#[inline(always)]
fn ends_tum_field(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r' | b'\n' | b'#')
}

/// Scan `s` from its start as one TUM line (`timestamp tx ty tz qx qy qz qw`, any spaces or
/// tabs, `#` comments), up to the first `\n`.
#[inline(always)]
pub(crate) fn scan_tum(s: &[u8]) -> TumScan {
    let n = s.len();
    let mut sc = TumScan {
        vals: [0.0; VALUES],
        count: 0,
        bad: None,
        end: n,
    };
    let mut i = 0;
    loop {
        while i < n && is_tum_space(s[i]) {
            i += 1;
        }
        if i == n || s[i] == b'\n' {
            break;
        }
        if s[i] == b'#' {
            i += memchr::memchr(b'\n', &s[i..]).unwrap_or(n - i);
            break;
        }
        let start = i;
        while i < n && !ends_tum_field(s[i]) {
            i += 1;
        }
        if sc.count < VALUES {
            match parse_f64(&s[start..i]) {
                Some(v) => sc.vals[sc.count] = v,
                None if sc.bad.is_none() => sc.bad = Some((sc.count, start, i)),
                None => {}
            }
        }
        sc.count += 1;
    }
    sc.end = i;
    sc
}

/// Span of the `k`-th whitespace-separated field of a TUM line.
pub(crate) fn tum_field(s: &[u8], k: usize) -> Option<(usize, usize)> {
    let body = s.split(|&b| b == b'#').next().unwrap_or(s);
    let mut i = 0;
    let mut count = 0;
    while i < body.len() {
        while i < body.len() && is_tum_space(body[i]) {
            i += 1;
        }
        let a = i;
        while i < body.len() && !is_tum_space(body[i]) {
            i += 1;
        }
        if a < i {
            if count == k {
                return Some((a, i));
            }
            count += 1;
        }
    }
    None
}
