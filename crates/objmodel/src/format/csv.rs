//! CSV details: splitting a line into fields and reading the header.

use super::number::parse_f64;
use super::reader::COLUMNS;

/// Role value of a column that is ignored.
const IGNORE: u8 = u8::MAX;

/// Accepted header names (lower case) for each role, in TUM order.
const NAMES: [&[&str]; 8] = [
    &["timestamp", "t", "time"],
    &["tx", "x"],
    &["ty", "y"],
    &["tz", "z"],
    &["qx"],
    &["qy"],
    &["qz"],
    &["qw"],
];

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
pub(crate) struct Fields<'a> {
    s: &'a [u8],
    i: usize,
    done: bool,
}

impl<'a> Fields<'a> {
    pub(crate) fn new(s: &'a [u8]) -> Self {
        Fields {
            s,
            i: 0,
            done: false,
        }
    }

    /// True if the line has no fields at all (blank or comment only).
    pub(crate) fn is_blank(&self) -> bool {
        match self.s.iter().find(|&&b| !is_space(b)) {
            None => true,
            Some(&b) => b == b'#',
        }
    }

    /// Span `(start, end)` of the next field's content, trimmed and without quotes.
    #[inline]
    pub(crate) fn next_field(&mut self) -> Option<(usize, usize)> {
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
    cols: [usize; 8],
    /// Line the header is on.
    line: usize,
}

impl Header {
    /// Read a header line; the error names the missing (or doubled) columns.
    pub(crate) fn parse(s: &[u8], line: usize) -> Result<Header, String> {
        let mut roles = Vec::new();
        let mut cols = [usize::MAX; 8];
        let mut seen = Vec::new();
        let mut fields = Fields::new(s);
        while let Some((a, b)) = fields.next_field() {
            let name = String::from_utf8_lossy(&s[a..b]).to_ascii_lowercase();
            let col = roles.len();
            let role = NAMES
                .iter()
                .position(|names| names.contains(&name.as_str()));
            match role {
                Some(r) if cols[r] != usize::MAX => {
                    return Err(format!(
                        "CSV header: columns {} and {} both give {} (\"{}\" and \"{name}\")",
                        cols[r] + 1,
                        col + 1,
                        COLUMNS[r],
                        seen[cols[r]]
                    ));
                }
                Some(r) => {
                    cols[r] = col;
                    roles.push(r as u8);
                }
                None => roles.push(IGNORE),
            }
            seen.push(name);
        }
        let missing: Vec<&str> = (0..8)
            .filter(|&r| cols[r] == usize::MAX)
            .map(|r| COLUMNS[r])
            .collect();
        if !missing.is_empty() {
            let found = seen
                .iter()
                .map(|n| format!("\"{n}\""))
                .collect::<Vec<_>>()
                .join(", ");
            return Err(format!(
                "CSV header has no column for {} (accepted names: timestamp/t/time, tx/x, ty/y, \
                 tz/z, qx, qy, qz, qw, in any order, case-insensitive); found {found}",
                missing.join(", ")
            ));
        }
        Ok(Header { roles, cols, line })
    }

    /// Role of column `col`: an index into `COLUMNS`, or >= 8 for an ignored column.
    #[inline]
    pub(crate) fn role(&self, col: usize) -> usize {
        self.roles.get(col).map_or(IGNORE as usize, |&r| r as usize)
    }

    /// Column holding `role`.
    pub(crate) fn column_of(&self, role: usize) -> usize {
        self.cols[role]
    }

    /// Number of columns.
    pub(crate) fn columns(&self) -> usize {
        self.roles.len()
    }

    /// Line of the header.
    pub(crate) fn line(&self) -> usize {
        self.line
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
