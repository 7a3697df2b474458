//! The streaming pose reader, [`PoseReader`]: an iterator of poses, or poses decoded in bulk
//! ([`PoseReader::read_chunk`]). Lines are taken straight out of the `BufRead` buffer (copied
//! only when a line straddles two buffer fills, `stream.rs`) and parsed without allocation
//! (`line.rs`; the common TUM line takes a faster path still, `fast_run.rs`).

use super::layout::Format;
use super::line::{Mode, State};
use super::skipped::{SkippedLines, SkippedSink};
use super::stream::Stream;
use crate::trajectory::StampedPose;
use crate::{Error, Result};
use std::io::BufRead;
use std::path::PathBuf;

/// Streaming reader of a pose file: an iterator of `Result<StampedPose>`.
///
/// Memory stays O(1) in the file length (the reader's buffer, at most one line that straddles
/// two buffer fills, and a batch of up to 128 poses decoded ahead from bytes already read: it
/// never waits for input it does not need, so it can follow a live stream on stdin). Comment
/// lines (`#`), trailing `# ...` comments and blank lines are skipped, `\r\n` is accepted.
/// After the first error the iterator ends (returns `None`), so
/// `collect::<Result<Vec<_>>>()` reports the first problem in the file.
pub struct PoseReader<R: BufRead> {
    reader: R,
    /// What is known between lines.
    st: State,
    /// Lines out of `reader`.
    stream: Stream,
    /// Poses decoded ahead (from data already read), and their lines.
    batch: Vec<StampedPose>,
    lines: Vec<usize>,
    /// Next pose of `batch` to return.
    head: usize,
    /// An error that came after the poses in `batch`.
    pending_err: Option<Error>,
}

impl<R: BufRead> PoseReader<R> {
    /// A reader of `format` data from `reader`; `file` is only used in error messages.
    /// For speed give it a large buffer, e.g. `BufReader::with_capacity(1 << 20, file)`.
    pub fn new(reader: R, file: PathBuf, format: Format) -> Self {
        let mode = match format {
            Format::Tum => Mode::Tum,
            Format::Csv => Mode::CsvHeader,
        };
        Self::with_mode(reader, file, mode)
    }

    /// A reader that decides the format with [`super::detect_format`] at the first non-comment
    /// line, as [`super::open`] does for a file not named `.csv`. An entry point for tests and
    /// fuzzing (`fuzz/`), not part of the supported interface.
    #[doc(hidden)]
    pub fn detecting(reader: R, file: PathBuf) -> Self {
        Self::with_mode(reader, file, Mode::Auto)
    }

    fn with_mode(reader: R, file: PathBuf, mode: Mode) -> Self {
        PoseReader {
            reader,
            st: State::new(file, mode),
            stream: Stream::default(),
            batch: Vec::with_capacity(BATCH),
            lines: Vec::with_capacity(BATCH),
            head: 0,
            pending_err: None,
        }
    }

    /// Read the rigid body `body` (where named) of an OptiTrack Motive take that holds
    /// several; a file that is no Motive export is then an error.
    pub(crate) fn with_rigid_body(mut self, body: Option<&str>) -> Self {
        self.st.rigid_body = body.map(str::to_string);
        self
    }

    /// Line number (1-based) of the last pose returned; 0 before the first.
    pub fn line(&self) -> usize {
        self.st.pose_line
    }

    /// The lines skipped so far that were neither blank nor comments ([`SkippedLines`]: where
    /// the tracker lost the object, a last line cut short); complete once the reader has
    /// returned its last pose.
    pub fn skipped_lines(&self) -> SkippedLines {
        let skipped = self.st.skipped.lock();
        skipped.unwrap_or_else(|e| e.into_inner()).clone()
    }

    /// A handle on [`PoseReader::skipped_lines`] that outlives the reader (read it after the
    /// last pose, e.g. on the thread the reader's poses are handed to).
    pub(crate) fn skipped_sink(&self) -> SkippedSink {
        self.st.skipped.clone()
    }

    /// Number of lines read so far.
    pub fn lines_read(&self) -> usize {
        self.st.track.line_no
    }

    /// The format, once known (always for [`PoseReader::new`]; after the first non-comment
    /// line for a reader from [`super::open`]).
    pub fn format(&self) -> Option<Format> {
        match self.st.mode {
            Mode::Auto => None,
            Mode::Tum => Some(Format::Tum),
            Mode::CsvHeader | Mode::Csv(_) | Mode::Motive(_) => Some(Format::Csv),
        }
    }

    /// True once a CSV header line has been read.
    pub(crate) fn has_csv_header(&self) -> bool {
        matches!(self.st.mode, Mode::Csv(_))
    }

    /// The units the file declares (a CSV header's, once read: after the first pose).
    pub fn declared_units(&self) -> super::length_unit::DeclaredUnits {
        match &self.st.mode {
            Mode::Csv(h) => h.declared(),
            _ => Default::default(),
        }
    }

    /// The file name used in messages.
    pub fn file(&self) -> &std::path::Path {
        &self.st.file
    }

    /// Only the scalar line scanners from now on, whatever the processor runs: to compare the
    /// vectorised scanner with them. An entry point for tests and fuzzing (`fuzz/`), not part of
    /// the supported interface.
    #[doc(hidden)]
    pub fn scalar_only(mut self) -> Self {
        self.stream.fast.scalar_only();
        self
    }
}

/// Poses decoded per refill of [`PoseReader`]'s batch (only from data already buffered).
const BATCH: usize = 128;

impl<R: BufRead> Iterator for PoseReader<R> {
    type Item = Result<StampedPose>;

    #[inline]
    fn next(&mut self) -> Option<Self::Item> {
        if let Some(&p) = self.batch.get(self.head) {
            self.st.pose_line = self.lines[self.head];
            self.head += 1;
            return Some(Ok(p));
        }
        self.refill()
    }
}

impl<R: BufRead> PoseReader<R> {
    /// Refill the batch (see [`Stream::step`]) and return the next item.
    #[inline(never)]
    fn refill(&mut self) -> Option<Result<StampedPose>> {
        self.batch.clear();
        self.lines.clear();
        self.head = 0;
        if let Some(e) = self.pending_err.take() {
            return Some(Err(e));
        }
        let (batch, lines) = (&mut self.batch, Some(&mut self.lines));
        let r = self.stream.step(
            &mut self.reader,
            &mut self.st,
            &mut self.pending_err,
            batch,
            lines,
            BATCH,
        );
        if r.is_some() || self.batch.is_empty() {
            return r;
        }
        self.head = 1;
        self.st.pose_line = self.lines[0];
        Some(Ok(self.batch[0]))
    }

    /// Append all remaining poses to `out`: the same as collecting the iterator, but faster.
    pub(crate) fn read_into(&mut self, out: &mut Vec<StampedPose>) -> Result<()> {
        self.read_chunk(out, usize::MAX).map(|_| ())
    }

    /// Append up to `limit` more poses to `out` (`limit` ≥ 1), decoding straight into it:
    /// the same poses as the iterator, without the per-pose hand-over. Returns `Ok(false)` once
    /// the input is exhausted, `Ok(true)` if there may be more; after an error the poses before
    /// it are in `out` and the error is returned (the next call returns `Ok(false)`).
    pub fn read_chunk(&mut self, out: &mut Vec<StampedPose>, limit: usize) -> Result<bool> {
        let goal = out.len().saturating_add(limit.max(1));
        while out.len() < goal {
            if let Some(p) = self.next_if_batched() {
                out.push(p);
                continue;
            }
            if let Some(e) = self.pending_err.take() {
                return Err(e);
            }
            let before = out.len();
            let r = self.stream.step(
                &mut self.reader,
                &mut self.st,
                &mut self.pending_err,
                out,
                None,
                goal - before,
            );
            match r {
                Some(r) => out.push(r?),
                None if out.len() == before => return Ok(false),
                None => {}
            }
        }
        Ok(true)
    }

    /// The next pose of the batch, if there is one.
    fn next_if_batched(&mut self) -> Option<StampedPose> {
        let p = *self.batch.get(self.head)?;
        self.st.pose_line = self.lines[self.head];
        self.head += 1;
        Some(p)
    }
}
