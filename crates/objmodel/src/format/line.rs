//! One line of a pose file, given what came before it: skipped (blank, comment, CSV header),
//! a pose, or an error that names the file, the line and the problem.
//!
//! [`State`] is what a reader knows between lines: the format (given, or decided at the first
//! non-comment line), the CSV header, and the [`Track`] of lines and the previous pose.

use super::check::{check_values, Track};
use super::csv::{has_separator, looks_like_header, trim, Header};
use super::detect::detect_format;
use super::layout::{Format, VALUES};
use super::motive::{is_motive_start, Preamble};
use super::problem::{Context, Problem};
use super::skipped::{is_copy, is_lost, SkippedSink};
use super::tum::{is_tum_header, scan_tum, tum_field, TumScan};
use crate::trajectory::StampedPose;
use crate::{Error, Result};
use std::path::PathBuf;

/// What a reader knows about the file's format so far.
#[derive(Debug)]
pub(crate) enum Mode {
    /// Format not known yet: decided by [`detect_format`] at the first non-comment line.
    Auto,
    /// TUM, whitespace-separated.
    Tum,
    /// CSV, header not seen yet.
    CsvHeader,
    /// CSV with its header.
    Csv(Header),
    /// An OptiTrack Motive export, before its column header.
    Motive(Preamble),
}

/// The values of a line in TUM order, `None` for a line to skip, or its problem.
type Values = std::result::Result<Option<[f64; VALUES]>, Problem>;

/// What a reader knows between lines.
pub(crate) struct State {
    /// The file name used in messages.
    pub(crate) file: PathBuf,
    pub(crate) mode: Mode,
    /// The line being read and the previous pose.
    pub(crate) track: Track,
    /// Line of the last pose decoded or returned.
    pub(crate) pose_line: usize,
    /// The last pose decoded or returned (the line `track.prev_line`), for a line that repeats
    /// it exactly; set by [`State::finish`] and, after a group of lines the fast path decoded,
    /// by its caller.
    pub(crate) last_pose: Option<StampedPose>,
    /// A commented-out CSV header (`#t,x,y,...`) seen before the first data line.
    pending: Option<Header>,
    /// The line that may be a units row (`Header::units_row`): the first after the CSV header
    /// that is not blank or a comment (0: none).
    units_line: usize,
    /// An error ended the reading.
    pub(crate) done: bool,
    /// The rigid body to read from a Motive export that holds several, where one is named.
    pub(crate) rigid_body: Option<String>,
    /// The lines skipped (`skipped.rs`): where the tracker lost the object, a last line cut
    /// short.
    pub(crate) skipped: SkippedSink,
}

impl State {
    /// Before the first line of `file` (a name for messages), in `mode`.
    pub(crate) fn new(file: PathBuf, mode: Mode) -> Self {
        State {
            file,
            mode,
            track: Track::new(),
            pose_line: 0,
            last_pose: None,
            pending: None,
            units_line: 0,
            done: false,
            rigid_body: None,
            skipped: SkippedSink::default(),
        }
    }

    /// The error for `problem` on the current line, whose text is `line`.
    #[cold]
    #[inline(never)]
    pub(crate) fn error(&self, problem: Problem, line: &[u8]) -> Error {
        let span = problem.role().and_then(|role| match &self.mode {
            Mode::Csv(h) => h.field(line, role),
            _ => tum_field(line, role),
        });
        let at = Context {
            line: self.track.line_no,
            prev_line: self.track.prev_line,
            field: span.map(|(a, b)| &line[a..b]),
        };
        Error::Parse {
            file: self.file.clone(),
            line: self.track.line_no,
            msg: problem.message(&at),
        }
    }

    /// The next line is longer than `MAX_LINE`: its error, which ends the reading.
    #[cold]
    pub(crate) fn too_long(&mut self) -> Option<Result<StampedPose>> {
        self.track.line_no += 1;
        self.done = true;
        Some(Err(self.error(Problem::LineTooLong, &[])))
    }

    /// Handle the next line (without its `\n`): `None` to skip it, else a pose or an error.
    pub(crate) fn handle(&mut self, mut line: &[u8]) -> Option<Result<StampedPose>> {
        self.track.line_no += 1;
        if self.track.line_no == 1 && line.starts_with(b"\xEF\xBB\xBF") {
            line = &line[3..];
        }
        if let [rest @ .., b'\r'] = line {
            line = rest;
        }
        let values = match &self.mode {
            Mode::Tum => return self.finish_tum(&scan_tum(line), line),
            Mode::Csv(_) if self.track.line_no == self.units_line => self.units_row(line),
            Mode::Csv(h) => h.values(line),
            Mode::Auto | Mode::CsvHeader => self.first_lines(line),
            Mode::Motive(_) => self.motive_line(line),
        };
        self.finish(values, line)
    }

    /// The item for a scanned TUM line (the current one).
    #[inline(always)]
    pub(crate) fn finish_tum(
        &mut self,
        scan: &TumScan,
        line: &[u8],
    ) -> Option<Result<StampedPose>> {
        let values = scan.values(line);
        self.finish(values, line)
    }

    /// The item for the values of the current line: the checked pose, nothing for a frame
    /// where the tracker lost the object or a copy of the line before (counted in `skipped`),
    /// or an error, which ends the reading.
    #[inline(always)]
    fn finish(&mut self, values: Values, line: &[u8]) -> Option<Result<StampedPose>> {
        let checked = match values {
            Ok(None) => return None,
            Ok(Some(v)) => self.track.check(&v).map_err(|problem| {
                let skip = is_lost(&v) || self.repeats_last_pose(&v, &problem);
                (problem, skip)
            }),
            Err(problem) => Err((problem, false)),
        };
        match checked {
            Ok(p) => {
                self.pose_line = self.track.line_no;
                self.last_pose = Some(p);
                Some(Ok(p))
            }
            Err((Problem::TimeNotIncreasing { .. }, true)) => {
                self.duplicate_line();
                None
            }
            Err((_, true)) => {
                self.lost_line();
                None
            }
            Err((problem, false)) => {
                self.done = true;
                Some(Err(self.error(problem, line)))
            }
        }
    }

    /// Whether values `v`, which failed the checks with `problem`, are the last pose again:
    /// its time, and a pose whose coordinates are the same bit for bit (the same values, read
    /// by the same rules on every path; columns the reader ignores aside).
    #[cold]
    #[inline(never)]
    fn repeats_last_pose(&self, v: &[f64; VALUES], problem: &Problem) -> bool {
        let Problem::TimeNotIncreasing { .. } = problem else {
            return false;
        };
        let (Ok(again), Some(last)) = (check_values(v, f64::NEG_INFINITY), self.last_pose) else {
            return false;
        };
        is_copy(&again, &last)
    }

    /// Count the current line as a copy of the last pose's line.
    #[cold]
    #[inline(never)]
    fn duplicate_line(&mut self) {
        let mut skipped = self.skipped.lock().unwrap_or_else(|e| e.into_inner());
        skipped.record_duplicate(self.track.line_no, self.track.prev_line);
    }

    /// Count the current line as one where the tracker lost the object.
    #[cold]
    #[inline(never)]
    fn lost_line(&mut self) {
        let mut skipped = self.skipped.lock().unwrap_or_else(|e| e.into_inner());
        skipped.record(self.track.line_no);
    }

    /// The file's last line, `line`, has no end of line and does not read as a pose
    /// (`problem`): left out, as cut short.
    #[cold]
    pub(crate) fn cut_short(&mut self, line: usize, problem: String) {
        let mut skipped = self.skipped.lock().unwrap_or_else(|e| e.into_inner());
        skipped.cut_short = Some((line, problem));
    }

    /// Lines before the format (or the CSV header) is known.
    #[cold]
    fn first_lines(&mut self, line: &[u8]) -> Values {
        let body = trim(line);
        if body.is_empty() {
            return Ok(None);
        }
        if body[0] == b'#' {
            // Maybe a commented-out CSV header such as "#timestamp,x,y,z,...".
            if self.pending.is_none() && has_separator(body) {
                if let Ok(h) = Header::parse(&body[1..], self.track.line_no) {
                    self.pending = Some(h);
                }
            }
            return Ok(None);
        }
        if let Mode::Auto = self.mode {
            let text = String::from_utf8_lossy(body);
            self.mode = match detect_format(&self.file, &text) {
                Format::Tum
                    if !self
                        .pending
                        .as_ref()
                        .is_some_and(|h| body.contains(&h.separator())) =>
                {
                    Mode::Tum
                }
                _ => Mode::CsvHeader,
            };
            if let Mode::Tum = self.mode {
                self.no_rigid_body()?;
                if is_tum_header(body) {
                    return Ok(None);
                }
                return scan_tum(line).values(line);
            }
        }
        // CSV: this line is the header, unless it is data or a units row and a commented header
        // came before.
        if let Some(h) = self.pending.as_ref() {
            // (A row of names that are not units is the header itself.)
            if let Some(Ok(h)) = h.units_row(body).map(|units| h.with_units_row(&units)) {
                self.pending = None;
                self.mode = Mode::Csv(h);
                return Ok(None);
            }
        }
        if !looks_like_header(body) {
            if let Some(h) = self.pending.take() {
                let values = h.values(line);
                self.mode = Mode::Csv(h);
                return values;
            }
        }
        if is_motive_start(body) {
            self.mode = Mode::Motive(Preamble::parse(body, self.rigid_body.as_deref())?);
            return Ok(None);
        }
        self.no_rigid_body()?;
        self.mode = Mode::Csv(Header::parse(body, self.track.line_no)?);
        self.units_line = self.track.line_no + 1;
        Ok(None)
    }

    /// The first line after the CSV header that is not blank or a comment: a units row
    /// (`s,mm,mm,mm,,,,`: `Header::units_row`), whose units the header then declares, or a data
    /// line.
    #[cold]
    fn units_row(&mut self, line: &[u8]) -> Values {
        let Mode::Csv(h) = &self.mode else {
            unreachable!("called in CSV mode")
        };
        if trim(line).first().is_none_or(|&b| b == b'#') {
            self.units_line += 1;
            return Ok(None);
        }
        let Some(units) = h.units_row(line) else {
            return h.values(line);
        };
        self.mode = Mode::Csv(h.with_units_row(&units)?);
        Ok(None)
    }

    /// The problem of a rigid body named for a file that is no Motive export, if one was.
    fn no_rigid_body(&self) -> std::result::Result<(), Problem> {
        match &self.rigid_body {
            Some(b) => Err(Problem::NotMotive(b.clone())),
            None => Ok(()),
        }
    }

    /// A line of a Motive export's preamble.
    #[cold]
    fn motive_line(&mut self, line: &[u8]) -> Values {
        let Mode::Motive(preamble) = &mut self.mode else {
            unreachable!("called in Motive mode")
        };
        if let Some(h) = preamble.take(line, self.track.line_no)? {
            self.mode = Mode::Csv(h);
        }
        Ok(None)
    }
}
