//! TUM lines: `timestamp tx ty tz qx qy qz qw`, separated by any spaces or tabs.

use super::number::{find_newline, parse_f64, scan_decimal};

/// A TUM line scanned up to its `\n` (or the end of the slice).
pub(super) struct TumScan {
    /// The first eight values.
    pub(super) vals: [f64; 8],
    /// Number of fields.
    pub(super) count: usize,
    /// First field that is not a number: (column, start, end).
    pub(super) bad: Option<(usize, usize, usize)>,
    /// Index of the `\n` ending the line, or the slice length if there is none.
    pub(super) end: usize,
}

/// Field separators of TUM (a stray `\r` counts as one).
#[inline(always)]
fn is_tum_space(b: u8) -> bool {
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
pub(super) fn scan_tum(s: &[u8]) -> TumScan {
    let n = s.len();
    let mut sc = TumScan {
        vals: [0.0; 8],
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
            i += find_newline(&s[i..]).unwrap_or(n - i);
            break;
        }
        let start = i;
        let (v, end, exact) = scan_decimal(s, i);
        i = end;
        let ok = exact && (i == n || ends_tum_field(s[i]));
        if !ok {
            while i < n && !ends_tum_field(s[i]) {
                i += 1;
            }
        }
        if sc.count < 8 {
            if ok {
                sc.vals[sc.count] = v;
            } else if let Some(v) = parse_f64(&s[start..i]) {
                sc.vals[sc.count] = v;
            } else if sc.bad.is_none() {
                sc.bad = Some((sc.count, start, i));
            }
        }
        sc.count += 1;
    }
    sc.end = i;
    sc
}

/// Span of the `k`-th whitespace-separated field of a TUM line.
pub(super) fn tum_field(s: &[u8], k: usize) -> Option<(usize, usize)> {
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
