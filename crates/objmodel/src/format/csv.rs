//! CSV lines: splitting a line into fields (comma separated, optional spaces around a field,
//! optional double quotes, `""` inside quotes, `#` outside quotes starting a comment), reading
//! the header ([`Header`]: which column holds which value) and the values of a data line.
//!
//! The fields are split by hand rather than by the `csv` crate: that crate parses a stream, not
//! one line handed over by the reader, knows comments only at the start of a line, and keeps
//! the spaces before an opening quote (and then the quotes) in a field. Measured on 24807 lines
//! with commas of a corpus of good and spoiled files, with a persistent `csv::Reader` fed one
//! line at a time and comments cut off first, 2383 lines split differently (`" 1.5"` after a
//! space became a field with quotes, which is no number; `""` is unescaped), and it split the
//! 200001 lines of a CSV pose file in 43-56 ms against 12-16 ms here.

use super::layout::{column_name, column_role, HEADER_STAMP, LOG_TIME, VALUES};
use super::number::parse_f64;
use super::problem::Problem;

/// Role value of a column that is ignored.
const IGNORE: u8 = u8::MAX;

/// Spaces and tabs (and a stray `\r`) around a field.
#[inline]
fn is_space(b: u8) -> bool {
    matches!(b, b' ' | b'\t' | b'\r')
}

/// `s` without leading and trailing spaces and tabs.
pub(crate) fn trim(s: &[u8]) -> &[u8] {
    let a = s.iter().position(|&b| !is_space(b)).unwrap_or(s.len());
    let b = s.iter().rposition(|&b| !is_space(b)).map_or(a, |p| p + 1);
    &s[a..b]
}

/// Splits a CSV line into fields: comma separated, optional spaces around fields, optional
/// double quotes (`""` inside quotes is a quote), and `#` outside quotes starts a comment.
struct Fields<'a> {
    s: &'a [u8],
    i: usize,
    done: bool,
}

impl<'a> Fields<'a> {
    fn new(s: &'a [u8]) -> Self {
        Fields {
            s,
            i: 0,
            done: false,
        }
    }

    /// True if the line has no fields at all (blank or comment only).
    fn is_blank(&self) -> bool {
        match self.s.iter().find(|&&b| !is_space(b)) {
            None => true,
            Some(&b) => b == b'#',
        }
    }

    /// Span `(start, end)` of the next field's content, trimmed and without quotes.
    #[inline]
    fn next_field(&mut self) -> Option<(usize, usize)> {
        if self.done {
            return None;
        }
        let s = self.s;
        let n = s.len();
        let mut i = self.i;
        while i < n && is_space(s[i]) {
            i += 1;
        }
        let (a, mut b);
        if i < n && s[i] == b'"' {
            a = i + 1;
            i += 1;
            loop {
                if i >= n {
                    b = n;
                    break;
                }
                if s[i] == b'"' {
                    if i + 1 < n && s[i + 1] == b'"' {
                        i += 2;
                        continue;
                    }
                    b = i;
                    i += 1;
                    break;
                }
                i += 1;
            }
            while i < n && s[i] != b',' && s[i] != b'#' {
                i += 1;
            }
        } else {
            a = i;
            while i < n && s[i] != b',' && s[i] != b'#' {
                i += 1;
            }
            b = i;
            while b > a && is_space(s[b - 1]) {
                b -= 1;
            }
        }
        if i < n && s[i] == b',' {
            self.i = i + 1;
        } else {
            self.done = true;
        }
        Some((a, b))
    }
}

/// A CSV header: which column holds which value.
#[derive(Debug, Clone)]
pub(crate) struct Header {
    /// Role (index into `COLUMNS`) of every column, or `IGNORE`.
    roles: Vec<u8>,
    /// Column of every role.
    cols: [usize; VALUES],
    /// Line the header is on.
    line: usize,
}

impl Header {
    /// Read header line `line`; the problem names the missing (or doubled) columns.
    pub(crate) fn parse(s: &[u8], line: usize) -> Result<Header, Problem> {
        let mut roles = Vec::new();
        let mut cols = [usize::MAX; VALUES];
        let mut seen = Vec::new();
        // A ROS message flattened to CSV has the time it was logged (`%time`) and the time it
        // was measured (`field.header.stamp`): the motion is in the second.
        let mut fields = Fields::new(s);
        let stamped = std::iter::from_fn(|| fields.next_field())
            .any(|(a, b)| column_name(&String::from_utf8_lossy(&s[a..b])) == HEADER_STAMP);
        let mut fields = Fields::new(s);
        while let Some((a, b)) = fields.next_field() {
            let name = String::from_utf8_lossy(&s[a..b]).to_ascii_lowercase();
            let col = roles.len();
            let role = column_role(&name).filter(|_| !(stamped && column_name(&name) == LOG_TIME));
            match role {
                Some(r) if cols[r] != usize::MAX => {
                    return Err(Problem::DoubledColumn {
                        role: r,
                        first: cols[r] + 1,
                        second: col + 1,
                        names: [std::mem::take(&mut seen[cols[r]]), name],
                    });
                }
                Some(r) => {
                    cols[r] = col;
                    roles.push(r as u8);
                }
                None => roles.push(IGNORE),
            }
            seen.push(name);
        }
        let missing: Vec<usize> = (0..VALUES).filter(|&r| cols[r] == usize::MAX).collect();
        if !missing.is_empty() {
            return Err(Problem::MissingColumns {
                missing,
                found: seen,
            });
        }
        Ok(Header { roles, cols, line })
    }

    /// Role of column `col`: an index into `COLUMNS`, or >= 8 for an ignored column.
    #[inline]
    fn role(&self, col: usize) -> usize {
        self.roles.get(col).map_or(IGNORE as usize, |&r| r as usize)
    }

    /// The values of data line `s` in TUM order, `None` for a line without fields (blank or
    /// comment), or the problem: the column count first, then the first field that is not a
    /// number.
    pub(crate) fn values(&self, s: &[u8]) -> Result<Option<[f64; VALUES]>, Problem> {
        let mut vals = [0.0; VALUES];
        let mut count = 0;
        let mut bad = None;
        let mut fields = Fields::new(s);
        if fields.is_blank() {
            return Ok(None);
        }
        while let Some((a, b)) = fields.next_field() {
            let role = self.role(count);
            if role < VALUES {
                match parse_f64(&s[a..b]) {
                    Some(v) => vals[role] = v,
                    None if bad.is_none() => bad = Some((count, role, a, b)),
                    None => {}
                }
            }
            count += 1;
        }
        if count != self.roles.len() {
            return Err(Problem::CsvColumns {
                expected: self.roles.len(),
                found: count,
                header_line: self.line,
            });
        }
        if let Some((col, role, a, b)) = bad {
            return Err(Problem::NotANumber {
                column: col + 1,
                role,
                text: s[a..b].to_vec(),
            });
        }
        Ok(Some(vals))
    }

    /// Span of the field of data line `s` that holds value `role`.
    pub(crate) fn field(&self, s: &[u8], role: usize) -> Option<(usize, usize)> {
        let mut f = Fields::new(s);
        (0..=self.cols[role]).filter_map(|_| f.next_field()).last()
    }
}

/// True if `line` looks like a CSV header: it has a comma, and a field with a letter that is
/// not a number (`1e-3`, `nan` and `inf` are numbers).
pub(crate) fn looks_like_header(line: &[u8]) -> bool {
    if !line.contains(&b',') {
        return false;
    }
    let mut f = Fields::new(line);
    while let Some((a, b)) = f.next_field() {
        let field = &line[a..b];
        if field.iter().any(u8::is_ascii_alphabetic) && parse_f64(field).is_none() {
            return true;
        }
    }
    false
}
