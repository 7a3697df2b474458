//! OptiTrack Motive's CSV export (format versions 1.2x), as the software writes it:
//!
//! ```text
//! Format Version,1.23,Take Name,push 3,...,Rotation Type,Quaternion,Length Units,Millimeters,...
//!
//! ,Type,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Marker,...
//! ,Name,box,box,box,box,box,box,box,box,box:Marker1,...
//! ,ID,1,1,1,1,1,1,1,1,...
//! ,,Rotation,Rotation,Rotation,Rotation,Position,Position,Position,Mean Marker Error,Position,...
//! Frame,Time (Seconds),X,Y,Z,W,X,Y,Z,,X,...
//! 0,0.000000,0.0012,-0.0004,0.0021,0.9999,512.3,81.6,-240.9,0.21,...
//! ```
//!
//! The metadata line says the unit of the positions (`Length Units`) and how rotations are
//! written (`Rotation Type`: only quaternions are read). The rows above `Frame,...` say which
//! asset and which component each column holds. The pose is the one rigid body's: its
//! `Rotation` X Y Z W and `Position` X Y Z (a body's markers, and other markers, are ignored).
//! A take with several rigid bodies (an object and the palm that pushes it) is read one body at
//! a time, the one named ([`super::PoseFile::rigid_body`]); unnamed, it is refused with the
//! names it holds. A frame in which the body was not seen (every field of its pose empty) is a
//! gap, skipped and counted (`skipped.rs`); a partly empty one is an error. Motive's world is y-up unless
//! its up axis was set to z: learn such files with `--gravity 0,-1,0` (the gravity check says so).

use super::csv::{fields, Header};
use super::layout::QUAT;
use super::length_unit::LengthUnit;
use super::problem::Problem;

/// Whether `line` (trimmed) is the first line of a Motive export.
pub(crate) fn is_motive_start(line: &[u8]) -> bool {
    line.starts_with(b"Format Version,")
}

/// What a Motive export says before its column header (`Frame,Time (Seconds),...`).
#[derive(Debug)]
pub(crate) struct Preamble {
    /// The positions' unit.
    length: LengthUnit,
    /// The rows between the metadata and the column header, as fields.
    rows: Vec<Vec<String>>,
    /// The rigid body to read, where one is named.
    body: Option<String>,
}

impl Preamble {
    /// The preamble that the metadata line `line` starts, of an export whose rigid body `body`
    /// is to be read (where named).
    pub(crate) fn parse(line: &[u8], body: Option<&str>) -> Result<Preamble, Problem> {
        let f = fields(line, b',');
        let value = |key: &str| {
            f.iter()
                .position(|k| k.eq_ignore_ascii_case(key))
                .and_then(|i| f.get(i + 1))
        };
        if let Some(kind) = value("Rotation Type").filter(|k| !k.eq_ignore_ascii_case("Quaternion"))
        {
            return Err(Problem::Motive(format!(
                "rotations are written as {kind}: export them as quaternions (Rotation Type: \
                 Quaternion)"
            )));
        }
        let length = match value("Length Units") {
            None => LengthUnit::Metres,
            Some(u) => LengthUnit::from_name(u).ok_or_else(|| {
                Problem::Motive(format!(
                    "Length Units {u:?} is not a length this reads (m, cm or mm)"
                ))
            })?,
        };
        Ok(Preamble {
            length,
            rows: Vec::new(),
            body: body.map(str::to_string),
        })
    }

    /// Take line `line` of the preamble: a row describing the columns (kept), or, when it is
    /// the column header (`Frame,...`), the CSV header of the rigid body's pose (on line
    /// `line_no`).
    pub(crate) fn take(&mut self, line: &[u8], line_no: usize) -> Result<Option<Header>, Problem> {
        let f = fields(line, b',');
        if f.iter().all(|x| x.is_empty()) {
            return Ok(None);
        }
        if !f[0].eq_ignore_ascii_case("Frame") {
            self.rows.push(f);
            return Ok(None);
        }
        self.header(f, line_no).map(Some)
    }

    /// The header of the rigid body's pose, from the column header `axes`.
    fn header(&self, axes: Vec<String>, line_no: usize) -> Result<Header, Problem> {
        // The rows that name each column's asset type, asset and component: the one with a
        // `Rigid Body`, the one after it, and the last one before the column header.
        let type_row = self
            .rows
            .iter()
            .position(|r| r.iter().any(|x| x == "Rigid Body"))
            .ok_or_else(|| {
                Problem::Motive(
                    "no rigid body in the export (only markers?): export the object's rigid body"
                        .to_string(),
                )
            })?;
        let cell = |row: usize, col: usize| {
            self.rows
                .get(row)
                .and_then(|r| r.get(col))
                .map_or("", String::as_str)
        };
        let component_row = self.rows.len() - 1;
        let mut bodies: Vec<&str> = Vec::new();
        for col in (0..axes.len()).filter(|&c| cell(type_row, c) == "Rigid Body") {
            let name = cell(type_row + 1, col);
            if !bodies.contains(&name) {
                bodies.push(name);
            }
        }
        let chosen = match (self.body.as_deref(), bodies.as_slice()) {
            (Some(b), _) if bodies.contains(&b) => b,
            (Some(b), _) => {
                return Err(Problem::Motive(format!(
                    "no rigid body named {b:?}; the export holds {}",
                    bodies.join(", ")
                )))
            }
            (None, [one]) => *one,
            (None, _) => {
                return Err(Problem::Motive(format!(
                    "{} rigid bodies ({}): name the object's (--object NAME; and the palm's, \
                     --palm NAME, for an instrumented demonstration)",
                    bodies.len(),
                    bodies.join(", ")
                )))
            }
        };
        let rigid =
            |col: usize| cell(type_row, col) == "Rigid Body" && cell(type_row + 1, col) == chosen;
        let roles = axes
            .iter()
            .enumerate()
            .map(|(col, axis)| {
                if col > 0 && axis.eq_ignore_ascii_case("Time (Seconds)") {
                    return Some(0);
                }
                if !rigid(col) {
                    return None;
                }
                let k = ["X", "Y", "Z", "W"]
                    .iter()
                    .position(|a| axis.eq_ignore_ascii_case(a))?;
                match cell(component_row, col) {
                    "Position" if k < 3 => Some(1 + k),
                    "Rotation" => Some(QUAT + k),
                    _ => None,
                }
            })
            .collect();
        let names = (0..axes.len())
            .map(|col| {
                let what = [
                    cell(type_row + 1, col),
                    cell(component_row, col),
                    &axes[col],
                ];
                what.iter()
                    .filter(|x| !x.is_empty())
                    .copied()
                    .collect::<Vec<_>>()
                    .join(" ")
                    .to_ascii_lowercase()
            })
            .collect();
        Ok(Header::from_roles(names, roles, line_no, b',')?.with_length(self.length))
    }
}
