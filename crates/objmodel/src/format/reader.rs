//! The streaming pose reader: lines are taken straight out of the `BufRead` buffer (copied only
//! when a line straddles two buffer fills), split by hand and parsed without allocation. The
//! common TUM line (eight plain decimals) takes a faster path still, see [`tum_run`].

use super::check::not_a_number;
use super::csv::{self, Header};
use super::number::parse_f64;
#[cfg(target_arch = "x86_64")]
use super::simd::Shapes;
use super::tum::{scan_tum, scan_tum_fast, TumScan};
use super::{detect_format, Format};
use crate::trajectory::StampedPose;
use crate::{Error, Result};
use memchr::memchr;
use std::io::BufRead;
use std::path::PathBuf;

/// Column names in TUM order; also the roles a CSV column can have.
pub(crate) const COLUMNS: [&str; 8] = ["timestamp", "tx", "ty", "tz", "qx", "qy", "qz", "qw"];

/// Lines longer than this are rejected (keeps memory bounded on garbage input).
const MAX_LINE: usize = 1 << 20;

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
    st: State,
    /// Poses decoded ahead (from data already read), and their lines.
    batch: Vec<StampedPose>,
    lines: Vec<usize>,
    /// Next pose of `batch` to return.
    head: usize,
    /// An error that came after the poses in `batch`.
    pending_err: Option<Error>,
}

/// What the reader knows about the file so far.
#[derive(Debug)]
pub(super) enum Mode {
    /// Format not known yet: decided by [`detect_format`] at the first non-comment line.
    Auto,
    /// TUM, whitespace-separated.
    Tum,
    /// CSV, header not seen yet.
    CsvHeader,
    /// CSV with its header.
    Csv(Header),
}

/// Everything but the byte source, so that lines borrowed from the source can be parsed.
pub(super) struct State {
    pub(super) file: PathBuf,
    pub(super) mode: Mode,
    /// Lines read so far (= number of the line being handled, 1-based).
    pub(super) line_no: usize,
    /// Line of the last pose returned.
    pub(super) pose_line: usize,
    /// Time of the previous pose (-inf before the first).
    pub(super) prev_t: f64,
    /// Line of the previous pose.
    pub(super) prev_line: usize,
    /// A commented-out CSV header (`#t,x,y,...`) seen before the first data line.
    pending: Option<Header>,
    /// Part of a line that straddles two buffer fills.
    carry: Vec<u8>,
    /// The current line is longer than `MAX_LINE`: drop bytes until its end.
    overlong: bool,
    done: bool,
    /// The line shapes of the AVX2 scanner, once it runs.
    #[cfg(target_arch = "x86_64")]
    shapes: Option<Box<Shapes>>,
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

    /// A reader that decides the format with [`detect_format`] at the first non-comment line.
    pub(crate) fn detecting(reader: R, file: PathBuf) -> Self {
        Self::with_mode(reader, file, Mode::Auto)
    }

    fn with_mode(reader: R, file: PathBuf, mode: Mode) -> Self {
        let st = State {
            file,
            mode,
            line_no: 0,
            pose_line: 0,
            prev_t: f64::NEG_INFINITY,
            prev_line: 0,
            pending: None,
            carry: Vec::new(),
            overlong: false,
            done: false,
            #[cfg(target_arch = "x86_64")]
            shapes: None,
        };
        PoseReader {
            reader,
            st,
            batch: Vec::with_capacity(BATCH),
            lines: Vec::with_capacity(BATCH),
            head: 0,
            pending_err: None,
        }
    }

    /// Line number (1-based) of the last pose returned; 0 before the first.
    pub fn line(&self) -> usize {
        self.st.pose_line
    }

    /// Number of lines read so far.
    pub fn lines_read(&self) -> usize {
        self.st.line_no
    }

    /// The format, once known (always for [`PoseReader::new`]; after the first non-comment
    /// line for a reader from [`super::open`]).
    pub fn format(&self) -> Option<Format> {
        match self.st.mode {
            Mode::Auto => None,
            Mode::Tum => Some(Format::Tum),
            Mode::CsvHeader | Mode::Csv(_) => Some(Format::Csv),
        }
    }

    /// True once a CSV header line has been read.
    pub(crate) fn has_csv_header(&self) -> bool {
        matches!(self.st.mode, Mode::Csv(_))
    }

    /// The file name used in messages.
    pub fn file(&self) -> &std::path::Path {
        &self.st.file
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
    /// Refill the batch (see [`step`]) and return the next item.
    #[inline(never)]
    fn refill(&mut self) -> Option<Result<StampedPose>> {
        self.batch.clear();
        self.lines.clear();
        self.head = 0;
        if let Some(e) = self.pending_err.take() {
            return Some(Err(e));
        }
        let (batch, lines) = (&mut self.batch, Some(&mut self.lines));
        let r = step(
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
            let r = step(
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

/// Read on: decode the complete lines already in the read buffer straight into `out` (at most
/// `limit` poses; lines into `lines`), or else read one line the slow way and return its item.
/// Returns `None` when poses were pushed (an error after them goes to `pending`) or at the end.
/// Never waits for more input once a pose is decoded, so a live stream on stdin is not delayed.
fn step<R: BufRead>(
    reader: &mut R,
    st: &mut State,
    pending: &mut Option<Error>,
    out: &mut Vec<StampedPose>,
    mut lines: Option<&mut Vec<usize>>,
    limit: usize,
) -> Option<Result<StampedPose>> {
    while !st.done {
        let buf = match reader.fill_buf() {
            Ok(b) => b,
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => continue,
            Err(source) => {
                st.done = true;
                return Some(Err(Error::Io {
                    file: st.file.clone(),
                    source,
                }));
            }
        };
        if buf.is_empty() {
            // End of input: a last line without '\n'.
            st.done = true;
            if st.carry.is_empty() && !st.overlong {
                return None;
            }
            return st.take_carry();
        }
        let whole_lines = st.carry.is_empty() && !st.overlong;
        if whole_lines && st.line_no > 0 {
            // Fast path: complete lines straight from the buffer.
            let mut off = 0;
            let mut err = None;
            let mut pushed = 0;
            while pushed < limit {
                let rest = &buf[off..];
                let (r, len) = if let Mode::Tum = st.mode {
                    let (used, n) = tum_run(st, rest, out, lines.as_deref_mut(), limit - pushed);
                    off += used;
                    pushed += n;
                    if pushed == limit {
                        break;
                    }
                    let rest = &buf[off..];
                    let scan = scan_tum(rest);
                    if scan.end == rest.len() {
                        break; // incomplete line
                    }
                    st.line_no += 1;
                    (st.finish_tum(&scan, &rest[..scan.end]), scan.end)
                } else {
                    let Some(e) = memchr(b'\n', rest) else { break };
                    (st.handle(&rest[..e]), e)
                };
                off += len + 1;
                match r {
                    Some(Ok(p)) => {
                        out.push(p);
                        pushed += 1;
                        if let Some(l) = lines.as_deref_mut() {
                            l.push(st.line_no);
                        }
                    }
                    Some(Err(e)) => {
                        err = Some(e);
                        break;
                    }
                    None => {}
                }
            }
            if off > 0 {
                reader.consume(off);
                if let Some(e) = err {
                    if pushed == 0 {
                        return Some(Err(e));
                    }
                    *pending = Some(e);
                }
                if pushed > 0 {
                    return None;
                }
                continue;
            }
        }
        // Slow path: the first line, or a line that straddles two buffer fills.
        let newline = memchr(b'\n', buf);
        if let (Some(i), true) = (newline, whole_lines) {
            let r = st.handle(&buf[..i]);
            reader.consume(i + 1);
            if r.is_some() {
                return r;
            }
            continue;
        }
        let take = newline.unwrap_or(buf.len());
        if !st.overlong {
            if st.carry.len() + take > MAX_LINE {
                st.overlong = true;
                st.carry = Vec::new();
            } else {
                st.carry.extend_from_slice(&buf[..take]);
            }
        }
        match newline {
            Some(i) => {
                reader.consume(i + 1);
                if let Some(r) = st.take_carry() {
                    return Some(r);
                }
            }
            None => reader.consume(take),
        }
    }
    None
}

/// Lines [`tum_run`] scans before it checks them.
const AHEAD: usize = 8;

/// Decode the common TUM lines at the start of `s` (see [`scan_tum_fast`]) straight into `out`
/// (at most `max`), until a line that is not common or fails a check: that one is left to the
/// general path, which makes its error. Returns the bytes consumed and the poses pushed.
///
/// Lines are scanned in groups of [`AHEAD`] and then checked and built in order. A line's
/// checks and pose end in a long chain of floating-point latencies (divisions, the square
/// root of the norm); right after its own scan they would hold up the CPU's in-order
/// retirement, while after the scan of a whole group the values are long ready and the chains
/// of several lines overlap. (Scanning ahead is free of effects: a line after a failed one is
/// simply scanned again by whoever reads on.)
#[inline(always)]
fn tum_run(
    st: &mut State,
    s: &[u8],
    out: &mut Vec<StampedPose>,
    lines: Option<&mut Vec<usize>>,
    max: usize,
) -> (usize, usize) {
    #[cfg(target_arch = "x86_64")]
    if super::simd::available() {
        let mut shapes = st.shapes.take().unwrap_or_default();
        // SAFETY: the processor runs AVX2, BMI1 and POPCNT code (checked just above).
        let r = unsafe { tum_run_avx2(st, &mut shapes, s, out, lines, max) };
        st.shapes = Some(shapes);
        return r;
    }
    tum_run_with(st, &mut ScalarLines, s, out, lines, max)
}

/// [`tum_run`] with the AVX2 line scanner ([`Shapes::scan`]), falling back to
/// [`scan_tum_fast`] for the lines it does not take.
///
/// # Safety
/// The processor must run AVX2, BMI1 and POPCNT code.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,bmi1,popcnt")]
unsafe fn tum_run_avx2(
    st: &mut State,
    shapes: &mut Shapes,
    s: &[u8],
    out: &mut Vec<StampedPose>,
    lines: Option<&mut Vec<usize>>,
    max: usize,
) -> (usize, usize) {
    tum_run_with(st, shapes, s, out, lines, max)
}

/// A line scanner for [`tum_run_with`]: [`scan_tum_fast`] or one that takes the same lines
/// with the same values (a type, not a closure, so that it is inlined into its caller's
/// target features).
trait LineScanner {
    /// The values and the `\n` of the common TUM line at the start of `s`, or `None`.
    ///
    /// # Safety
    /// The processor must run the code the scanner is built for.
    unsafe fn scan(&mut self, s: &[u8]) -> Option<([f64; 8], usize)>;
}

/// [`scan_tum_fast`], for every processor.
struct ScalarLines;

impl LineScanner for ScalarLines {
    #[inline(always)]
    unsafe fn scan(&mut self, s: &[u8]) -> Option<([f64; 8], usize)> {
        scan_tum_fast(s)
    }
}

/// [`Shapes::scan`], and [`scan_tum_fast`] for the lines it does not take.
#[cfg(target_arch = "x86_64")]
impl LineScanner for Shapes {
    #[inline(always)]
    unsafe fn scan(&mut self, s: &[u8]) -> Option<([f64; 8], usize)> {
        // SAFETY: passed on from the caller.
        match unsafe { Shapes::scan(self, s) } {
            Some(r) => Some(r),
            None => scan_tum_fast(s),
        }
    }
}

/// [`tum_run`] with the line scanner `scanner`, whose code this processor must run.
#[inline(always)]
fn tum_run_with<L: LineScanner>(
    st: &mut State,
    scanner: &mut L,
    s: &[u8],
    out: &mut Vec<StampedPose>,
    mut lines: Option<&mut Vec<usize>>,
    max: usize,
) -> (usize, usize) {
    let mut off = 0;
    let mut n = 0;
    let mut vals = [[0.0; 8]; AHEAD];
    let mut lens = [0; AHEAD];
    loop {
        // Scan a group of lines first ...
        let mut k = 0;
        let mut at = off;
        while k < AHEAD && n + k < max {
            // SAFETY: the caller checked that this processor runs `L`'s code.
            let Some((v, len)) = (unsafe { scanner.scan(&s[at..]) }) else {
                break;
            };
            vals[k] = v;
            lens[k] = len;
            at += len + 1;
            k += 1;
        }
        // ... then check them, in order.
        for q in 0..k {
            st.line_no += 1;
            // Finite by construction: m / 10^k with m <= 2^53 (see `scan_field`).
            let Some(p) = st.accept(&vals[q], true) else {
                st.line_no -= 1;
                return (off, n);
            };
            out.push(p);
            if let Some(l) = lines.as_deref_mut() {
                l.push(st.line_no);
            }
            off += lens[q] + 1;
            n += 1;
        }
        if k < AHEAD {
            return (off, n);
        }
    }
}

/// Outcome of one data line.
enum Parsed {
    /// Values in TUM order.
    Values([f64; 8]),
    /// Nothing to return (blank, comment, header).
    Skip,
}

impl State {
    pub(super) fn err(&self, msg: String) -> Error {
        Error::Parse {
            file: self.file.clone(),
            line: self.line_no,
            msg,
        }
    }

    /// Handle the carried (or over-long) line and reset the carry buffer.
    fn take_carry(&mut self) -> Option<Result<StampedPose>> {
        if std::mem::take(&mut self.overlong) {
            self.line_no += 1;
            self.done = true;
            return Some(Err(
                self.err(format!("line is longer than {MAX_LINE} bytes"))
            ));
        }
        let line = std::mem::take(&mut self.carry);
        let r = self.handle(&line);
        self.carry = line;
        self.carry.clear();
        r
    }

    /// Handle one line (without its `\n`): `None` to skip it, else a pose or an error.
    fn handle(&mut self, mut line: &[u8]) -> Option<Result<StampedPose>> {
        self.line_no += 1;
        if self.line_no == 1 && line.starts_with(b"\xEF\xBB\xBF") {
            line = &line[3..];
        }
        if let [rest @ .., b'\r'] = line {
            line = rest;
        }
        let parsed = match &self.mode {
            Mode::Tum => return self.finish_tum(&scan_tum(line), line),
            Mode::Csv(h) => self.parse_csv(line, h),
            Mode::Auto | Mode::CsvHeader => self.first_lines(line),
        };
        self.finish(parsed, line)
    }

    /// The iterator's item for a scanned TUM line.
    #[inline(always)]
    fn finish_tum(&mut self, scan: &TumScan, line: &[u8]) -> Option<Result<StampedPose>> {
        let parsed = self.check_tum(scan, line);
        self.finish(parsed, line)
    }

    /// The iterator's item for a parsed line; an error ends the iteration.
    #[inline(always)]
    fn finish(&mut self, parsed: Result<Parsed>, line: &[u8]) -> Option<Result<StampedPose>> {
        match parsed {
            Ok(Parsed::Skip) => None,
            Ok(Parsed::Values(v)) => {
                let r = self.pose(&v, line);
                self.done = r.is_err();
                Some(r)
            }
            Err(e) => {
                self.done = true;
                Some(Err(e))
            }
        }
    }

    /// Lines before the format (or the CSV header) is known.
    #[cold]
    fn first_lines(&mut self, line: &[u8]) -> Result<Parsed> {
        let body = csv::trim(line);
        if body.is_empty() {
            return Ok(Parsed::Skip);
        }
        if body[0] == b'#' {
            // Maybe a commented-out CSV header such as "#timestamp,x,y,z,...".
            if self.pending.is_none() && body.contains(&b',') {
                if let Ok(h) = Header::parse(&body[1..], self.line_no) {
                    self.pending = Some(h);
                }
            }
            return Ok(Parsed::Skip);
        }
        if let Mode::Auto = self.mode {
            let text = String::from_utf8_lossy(body);
            self.mode = match detect_format(&self.file, &text) {
                Format::Tum if !(self.pending.is_some() && body.contains(&b',')) => Mode::Tum,
                _ => Mode::CsvHeader,
            };
            if let Mode::Tum = self.mode {
                return self.check_tum(&scan_tum(line), line);
            }
        }
        // CSV: this line is the header, unless it is data and a commented header came before.
        if !csv::looks_like_header(body) {
            if let Some(h) = self.pending.take() {
                let r = self.parse_csv(line, &h);
                self.mode = Mode::Csv(h);
                return r;
            }
        }
        let h = Header::parse(body, self.line_no).map_err(|msg| self.err(msg))?;
        self.mode = Mode::Csv(h);
        Ok(Parsed::Skip)
    }

    /// Errors of a scanned TUM line: the column count first, then the first non-number.
    #[inline(always)]
    fn check_tum(&self, scan: &TumScan, s: &[u8]) -> Result<Parsed> {
        if scan.count == 8 && scan.bad.is_none() {
            return Ok(Parsed::Values(scan.vals));
        }
        if scan.count == 0 {
            return Ok(Parsed::Skip);
        }
        Err(self.tum_error(scan, s))
    }

    /// One CSV data line, with the columns given by the header.
    fn parse_csv(&self, s: &[u8], h: &Header) -> Result<Parsed> {
        let mut vals = [0.0; 8];
        let mut count = 0;
        let mut bad = None;
        let mut fields = csv::Fields::new(s);
        if fields.is_blank() {
            return Ok(Parsed::Skip);
        }
        while let Some((a, b)) = fields.next_field() {
            let role = h.role(count);
            if role < 8 {
                let f = &s[a..b];
                match parse_f64(f) {
                    Some(v) => vals[role] = v,
                    None if bad.is_none() => bad = Some((count, role, a, b)),
                    None => {}
                }
            }
            count += 1;
        }
        if count != h.columns() {
            return Err(self.err(format!(
                "expected {} columns (as in the CSV header on line {}), found {count}",
                h.columns(),
                h.line()
            )));
        }
        if let Some((col, role, a, b)) = bad {
            return Err(self.err(not_a_number(col + 1, role, &s[a..b])));
        }
        Ok(Parsed::Values(vals))
    }
}
