//! CSV lines: splitting a line into fields (comma separated, optional spaces around a field,
//! optional double quotes, `""` inside quotes, `#` outside quotes starting a comment), reading
//! the header ([`Header`]: which column holds which value; a units row after it (the first line
//! that is not blank or a comment), `s,mm,mm,mm,,,,`, declares units as a name's `x [mm]` does;
//! under a commented header, `#t,x,...`, a row whose fields are its columns' units) and the
//! values of a data line (an empty field past the header's columns, or a header's empty last
//! column missing, is a comma a logger ends its lines with).
//!
//! A header without a comma whose columns are separated by semicolons (`t;x;y;z;...`) makes
//! the file semicolon-separated, as a spreadsheet in a locale that writes decimal commas saves
//! it: then a comma inside a number is its decimal point (`0,5` is 0.5; `2026-12-07
//! 10:00:00,25` too, as ISO 8601 allows).
//!
//! The fields are split by hand rather than by the `csv` crate: that crate parses a stream, not
//! one line handed over by the reader, knows comments only at the start of a line, and keeps
//! the spaces before an opening quote (and then the quotes) in a field. Measured on 24807 lines
//! with commas of a corpus of good and spoiled files, with a persistent `csv::Reader` fed one
//! line at a time and comments cut off first, 2383 lines split differently (`" 1.5"` after a
//! space became a field with quotes, which is no number; `""` is unescaped), and it split the
//! 200001 lines of a CSV pose file in 43-56 ms against 12-16 ms here.

use super::date_time::{looks_like_date_time, seconds_since_epoch};
use super::layout::{
    column_name, column_role, column_unit, is_log_time, HEADER_STAMP, TIME, VALUES,
};
use super::length_unit::{time_unit_from_name, DeclaredUnits, LengthUnit};
use super::number::parse_f64;
use super::problem::Problem;

/// Role value of a column that is ignored.
const IGNORE: u8 = u8::MAX;

/// The longest field a units row holds \[bytes\] (`millimetres`, `[s]`).
const MAX_UNIT_NAME: usize = 16;

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

/// Splits a CSV line into fields: separated by `sep` (a comma, or a semicolon: see the module
/// documentation), optional spaces around fields, optional double quotes (`""` inside quotes is
/// a quote), and `#` outside quotes starts a comment.
struct Fields<'a> {
    s: &'a [u8],
    sep: u8,
    i: usize,
    done: bool,
}

impl<'a> Fields<'a> {
    fn new(s: &'a [u8], sep: u8) -> Self {
        Fields {
            s,
            sep,
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
        let (s, sep) = (self.s, self.sep);
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
            while i < n && s[i] != sep && s[i] != b'#' {
                i += 1;
            }
        } else {
            a = i;
            while i < n && s[i] != sep && s[i] != b'#' {
                i += 1;
            }
            b = i;
            while b > a && is_space(s[b - 1]) {
                b -= 1;
            }
        }
        if i < n && s[i] == sep {
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
    /// What every value is multiplied by: the declared units' seconds and metres (1 where
    /// none is declared).
    scale: [f64; VALUES],
    /// The units the header declares.
    declared: DeclaredUnits,
    /// The column names (lower case), for a units row (`Header::with_units_row`).
    names: Vec<String>,
    /// What separates the fields ([`separator_of`] the header).
    sep: u8,
}

/// Whether `line` has a field separator: a comma, or a semicolon (see the module documentation).
pub(crate) fn has_separator(line: &[u8]) -> bool {
    line.contains(&b',') || line.contains(&b';')
}

/// What separates the fields of a CSV file whose header is `line`: a comma, unless the line has
/// none and has a semicolon (see the module documentation).
pub(crate) fn separator_of(line: &[u8]) -> u8 {
    if !line.contains(&b',') && line.contains(&b';') {
        b';'
    } else {
        b','
    }
}

impl Header {
    /// Read header line `line`; the problem names the missing (or doubled) columns.
    pub(crate) fn parse(s: &[u8], line: usize) -> Result<Header, Problem> {
        let sep = separator_of(s);
        let names: Vec<String> = fields(s, sep)
            .iter()
            .map(|f| f.to_ascii_lowercase())
            .collect();
        // A ROS message flattened to CSV has the time it was logged (`%time`) and the time it
        // was measured (`field.header.stamp`): the motion is in the second.
        let stamped = names.iter().any(|n| column_name(n) == HEADER_STAMP);
        let roles = names
            .iter()
            .map(|n| column_role(n).filter(|_| !(stamped && is_log_time(&column_name(n)))))
            .collect();
        Header::from_roles(names, roles, line, sep)
    }

    /// What separates the fields.
    pub(crate) fn separator(&self) -> u8 {
        self.sep
    }

    /// The header of columns `names` (as written, lower case) that give `roles` (an index into
    /// `COLUMNS`, or none), on line `line`, its fields separated by `sep`; the problem names the
    /// missing (or doubled) columns, or a unit that is not its column's.
    pub(crate) fn from_roles(
        mut names: Vec<String>,
        roles: Vec<Option<usize>>,
        line: usize,
        sep: u8,
    ) -> Result<Header, Problem> {
        let mut cols = [usize::MAX; VALUES];
        // (value, column, name) of every column that gives a value.
        let mut named = Vec::new();
        for (col, role) in roles.iter().enumerate() {
            match *role {
                Some(r) if cols[r] != usize::MAX => {
                    return Err(Problem::DoubledColumn {
                        role: r,
                        first: cols[r] + 1,
                        second: col + 1,
                        names: [
                            std::mem::take(&mut names[cols[r]]),
                            std::mem::take(&mut names[col]),
                        ],
                    });
                }
                Some(r) => {
                    cols[r] = col;
                    named.push((r, col, names[col].clone()));
                }
                None => {}
            }
        }
        let missing: Vec<usize> = (0..VALUES).filter(|&r| cols[r] == usize::MAX).collect();
        if !missing.is_empty() {
            return Err(Problem::MissingColumns {
                missing,
                found: names,
            });
        }
        let (scale, declared) = declared_units(&named)?;
        Ok(Header {
            roles: roles
                .iter()
                .map(|r| r.map_or(IGNORE, |r| r as u8))
                .collect(),
            cols,
            line,
            scale,
            declared,
            names,
            sep,
        })
    }

    /// The units of `s` if it is a units row: the line after the header in some exports
    /// (`s,mm,mm,mm,,,,`), a field per column, none of them a number or a date-time, none
    /// longer than a unit's name, not all empty.
    pub(crate) fn units_row(&self, s: &[u8]) -> Option<Vec<String>> {
        let units = fields(s, self.sep);
        // (A number or a date-time is what a time column's value may be.)
        let unit =
            |u: &String| u.len() <= MAX_UNIT_NAME && self.value(TIME, u.as_bytes()).is_none();
        let columns = self.columns_of(units.len(), units.last().is_some_and(String::is_empty));
        let is_row = columns && units.iter().all(unit) && units.iter().any(|u| !u.is_empty());
        is_row.then_some(units)
    }

    /// This header with the units of a units row declared, as a name's `x [mm]` declares
    /// them (a unit the column's name declares stays); the problem of a unit that is not its
    /// column's.
    pub(crate) fn with_units_row(&self, units: &[String]) -> Result<Header, Problem> {
        let names = self
            .names
            .iter()
            .zip(units.iter().chain(std::iter::repeat(&String::new())))
            .map(|(name, unit)| {
                let unit = unit.trim_matches(['[', ']', '(', ')']).trim();
                match unit.is_empty() || column_unit(name).is_some() {
                    true => name.clone(),
                    false => format!("{name} [{unit}]"),
                }
            })
            .collect();
        let roles = self
            .roles
            .iter()
            .map(|&r| (r != IGNORE).then_some(r as usize));
        Header::from_roles(names, roles.collect(), self.line, self.sep)
    }

    /// Whether a line of `count` fields (the last one empty: `last_empty`) has this header's
    /// columns: as many, or one more or one fewer where the one is an empty last field (a
    /// logger that ends every line, or only its header, with a comma).
    fn columns_of(&self, count: usize, last_empty: bool) -> bool {
        let n = self.roles.len();
        let header_ends_empty = self.names.last().is_some_and(String::is_empty);
        count == n || (count == n + 1 && last_empty) || (count + 1 == n && header_ends_empty)
    }

    /// This header with its positions in `unit` (declared elsewhere than in its columns, as a
    /// motion-capture export's metadata does).
    pub(crate) fn with_length(mut self, unit: LengthUnit) -> Header {
        self.declared.length = Some(unit);
        self.scale[1..4].fill(unit.metres());
        self
    }

    /// The units the header declares.
    pub(crate) fn declared(&self) -> DeclaredUnits {
        DeclaredUnits {
            named_columns: true,
            ..self.declared
        }
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
        let mut fields = Fields::new(s, self.sep);
        if fields.is_blank() {
            return Ok(None);
        }
        let mut last_empty = false;
        while let Some((a, b)) = fields.next_field() {
            let role = self.role(count);
            if role < VALUES {
                match self.value(role, &s[a..b]) {
                    Some(v) => vals[role] = v,
                    None if bad.is_none() => bad = Some((count, role, a, b)),
                    None => {}
                }
            }
            last_empty = a == b;
            count += 1;
        }
        if !self.columns_of(count, last_empty) {
            return Err(Problem::CsvColumns {
                expected: self.roles.len(),
                found: count,
                header_line: self.line,
            });
        }
        if let Some((col, role, a, b)) = bad {
            // Every position and rotation field empty: the tracker lost the object (`skipped.rs`).
            if let Some(t) = self.lost_frame_time(s) {
                let mut lost = [f64::NAN; VALUES];
                lost[TIME] = t;
                return Ok(Some(lost));
            }
            let text = s[a..b].to_vec();
            if role == TIME && looks_like_date_time(&text) {
                let why = seconds_since_epoch(&text).err().unwrap_or_default();
                return Err(Problem::NotADateTime {
                    column: col + 1,
                    text,
                    why,
                });
            }
            return Err(Problem::NotANumber {
                column: col + 1,
                role,
                text,
            });
        }
        Ok(Some(vals))
    }

    /// Value `role` of field `field`: a number in the column's unit, or a time written as a
    /// date-time (`date_time.rs`: seconds since the Unix epoch, whatever unit the header
    /// declares); `None` if it is neither.
    #[inline]
    fn value(&self, role: usize, field: &[u8]) -> Option<f64> {
        match parse_f64(field) {
            Some(v) => Some(v * self.scale[role]),
            None if self.sep == b';' && field.contains(&b',') => {
                self.value_with_decimal_comma(role, field)
            }
            None if role == TIME => date_time(field),
            None => None,
        }
    }

    /// [`Header::value`] of a field whose comma is its decimal point (a semicolon-separated
    /// file's: see the module documentation); `None` for one with more than one comma.
    #[cold]
    fn value_with_decimal_comma(&self, role: usize, field: &[u8]) -> Option<f64> {
        if field.iter().filter(|&&b| b == b',').count() != 1 {
            return None;
        }
        let dotted: Vec<u8> = field
            .iter()
            .map(|&b| if b == b',' { b'.' } else { b })
            .collect();
        self.value(role, &dotted)
    }

    /// The time of data line `s` if every field of it that holds a position or a rotation is
    /// empty and its time is a number.
    #[cold]
    fn lost_frame_time(&self, s: &[u8]) -> Option<f64> {
        let empty = (1..VALUES).all(|role| self.field(s, role).is_some_and(|(a, b)| a == b));
        let (a, b) = self.field(s, TIME).filter(|_| empty)?;
        self.value(TIME, &s[a..b])
    }

    /// Span of the field of data line `s` that holds value `role`.
    pub(crate) fn field(&self, s: &[u8], role: usize) -> Option<(usize, usize)> {
        let mut f = Fields::new(s, self.sep);
        (0..=self.cols[role]).filter_map(|_| f.next_field()).last()
    }
}

/// The units that the header columns `named` (value, column, name) declare
/// ([`column_unit`]), and the scale of every value they give: a timestamp's unit, and one
/// length for the positions (a position column without a unit takes the others'). A unit
/// that is not the value's, or two lengths, is a problem.
fn declared_units(
    named: &[(usize, usize, String)],
) -> Result<([f64; VALUES], DeclaredUnits), Problem> {
    let mut scale = [1.0; VALUES];
    let mut declared = DeclaredUnits::default();
    let mut length: Option<(LengthUnit, &String)> = None;
    for (role, col, name) in named {
        let Some(unit) = column_unit(name) else {
            continue;
        };
        let unknown = || Problem::UnknownUnit {
            column: col + 1,
            role: *role,
            name: name.clone(),
        };
        match role {
            0 => {
                let u = time_unit_from_name(&unit).ok_or_else(unknown)?;
                declared.time = Some(u);
                scale[0] = u.seconds();
            }
            1..=3 => {
                let u = LengthUnit::from_name(&unit).ok_or_else(unknown)?;
                match length {
                    Some((first, first_name)) if first != u => {
                        return Err(Problem::MixedUnits {
                            names: [first_name.clone(), name.clone()],
                        })
                    }
                    Some(_) => {}
                    None => length = Some((u, name)),
                }
            }
            // A quaternion's components have no unit, whatever a header says.
            _ => {}
        }
    }
    if let Some((u, _)) = length {
        declared.length = Some(u);
        scale[1..4].fill(u.metres());
    }
    Ok((scale, declared))
}

/// The fields of a CSV line separated by `sep`: trimmed, without quotes.
pub(crate) fn fields(line: &[u8], sep: u8) -> Vec<String> {
    let mut f = Fields::new(line, sep);
    std::iter::from_fn(|| f.next_field())
        .map(|(a, b)| String::from_utf8_lossy(&line[a..b]).into_owned())
        .collect()
}

/// The seconds since the Unix epoch of a field that is a date-time (`date_time.rs`), if it is
/// one.
#[cold]
fn date_time(field: &[u8]) -> Option<f64> {
    looks_like_date_time(field)
        .then(|| seconds_since_epoch(field).ok())
        .flatten()
}

/// True if `line` looks like a CSV header: it has a comma (or a semicolon: [`separator_of`]),
/// and a field with a letter that is not a number (`1e-3`, `nan` and `inf` are numbers) or a
/// date-time (`2026-12-07T10:00Z`).
pub(crate) fn looks_like_header(line: &[u8]) -> bool {
    if !has_separator(line) {
        return false;
    }
    let mut f = Fields::new(line, separator_of(line));
    while let Some((a, b)) = f.next_field() {
        let field = &line[a..b];
        let word = field.iter().any(u8::is_ascii_alphabetic);
        if word && parse_f64(field).is_none() && date_time(field).is_none() {
            return true;
        }
    }
    false
}

#[cfg(test)]
mod tests {
    use super::super::layout::Format;
    use super::super::reader::PoseReader;
    use super::super::TimeUnit;
    use super::*;
    use proptest::prelude::*;

    /// The poses of CSV text, and the units its header declares.
    fn read(
        text: &str,
    ) -> (
        crate::Result<Vec<crate::trajectory::StampedPose>>,
        DeclaredUnits,
    ) {
        let mut r = PoseReader::new(text.as_bytes(), "f.csv".into(), Format::Csv);
        let poses = r.by_ref().collect();
        (poses, r.declared_units())
    }

    const LENGTHS: [(&str, f64); 5] = [
        ("", 1.0),
        (" [m]", 1.0),
        (" (Meters)", 1.0),
        (" [cm]", 1e-2),
        (" (Millimeters)", 1e-3),
    ];
    const TIMES: [(&str, f64); 5] = [
        ("", 1.0),
        (" (Seconds)", 1.0),
        (" [ms]", 1e-3),
        (" [us]", 1e-6),
        (" [ns]", 1e-9),
    ];

    proptest! {
        /// A header's units scale what it gives, and only that: the positions by the length
        /// (a column without a unit takes the others'), the stamp by the time, never the
        /// quaternion.
        #[test]
        fn declared_units_scale_their_values(
            l in 0..LENGTHS.len(),
            tu in 0..TIMES.len(),
            bare in 0..3usize,
            t in 0.0..1e6f64,
            p in prop::array::uniform3(-1e4..1e4f64),
        ) {
            let (lu, lk) = LENGTHS[l];
            let (tname, tk) = TIMES[tu];
            let unit = |axis: usize| if axis == bare { "" } else { lu };
            let text = format!(
                "time{tname},x{},y{},z{},qx [],qy,qz,qw\n{t},{},{},{},0.6,0,0,0.8\n",
                unit(0), unit(1), unit(2), p[0], p[1], p[2]
            );
            let (poses, declared) = read(&text);
            let pose = poses.unwrap()[0];
            prop_assert_eq!(pose.t, t * tk);
            for (got, given) in pose.pose.translation.vector.iter().zip(p) {
                prop_assert_eq!(*got, given * lk);
            }
            prop_assert!((pose.pose.rotation.coords - nalgebra::Vector4::new(0.6, 0.0, 0.0, 0.8)).norm() < 1e-15);
            prop_assert_eq!(declared.length.map(LengthUnit::metres), (!lu.is_empty()).then_some(lk));
            prop_assert_eq!(declared.time.map(TimeUnit::seconds), (!tname.is_empty()).then_some(tk));
        }
    }

    #[test]
    fn units_that_are_not_the_columns_are_named() {
        let cases = [
            (
                "t,x [deg],y,z,qx,qy,qz,qw",
                "f.csv:1: CSV header: column 2 (\"x [deg]\", tx) declares a unit that is not a \
                 length: m, cm or mm",
            ),
            (
                "t (min),x,y,z,qx,qy,qz,qw",
                "f.csv:1: CSV header: column 1 (\"t (min)\", timestamp) declares a unit that is \
                 not a time: s, ms, us or ns",
            ),
            (
                "t,x [mm],y [mm],z [cm],qx,qy,qz,qw",
                "f.csv:1: CSV header: the position columns declare different units (\"x [mm]\" \
                 and \"z [cm]\"); give them one",
            ),
        ];
        for (header, want) in cases {
            let (poses, _) = read(&format!("{header}\n0,0,0,0,0,0,0,1\n"));
            assert_eq!(poses.unwrap_err().to_string(), want);
        }
        // A quaternion's "unit" is no problem, and declares no unit (the columns are named).
        let (poses, declared) = read("t,x,y,z,qx (unitless),qy [1],qz,qw\n0,0,0,0,0,0,0,1\n");
        assert_eq!(poses.unwrap().len(), 1);
        let named = DeclaredUnits {
            named_columns: true,
            ..Default::default()
        };
        assert_eq!(declared, named);
    }
}
