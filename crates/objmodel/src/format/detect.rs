//! Which format a pose file is in: from its name, else from its first non-comment line.

use super::csv::looks_like_header;
use super::layout::Format;
use std::path::Path;

/// True if `path` ends in `.csv` (any case).
pub(crate) fn has_csv_name(path: &Path) -> bool {
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("csv"))
}

/// Decide the format of `path` from its name and its first non-comment line: a `.csv`
/// extension (any case), or a first line with a comma and a field that has letters and is not a
/// number (a header such as `t,x,y,z,qx,qy,qz,qw`), means CSV; anything else is TUM.
pub fn detect_format(path: &Path, first_line: &str) -> Format {
    if has_csv_name(path) || looks_like_header(first_line.trim().as_bytes()) {
        Format::Csv
    } else {
        Format::Tum
    }
}
