//! The fast path of TUM reading: the common lines at the start of a buffer are scanned (by the
//! AVX2 scanner of `simd.rs` where the processor runs it, and by the scalar one of
//! `fast_line.rs` for the lines that one leaves or on other processors), then checked and
//! built in groups.
//!
//! Speed code, behind a narrow interface: [`FastLines::decode`] takes bytes and the [`Track`],
//! and returns how many bytes and poses it took; the lines it leaves go to the general path,
//! which gives the same poses (bit for bit) and makes the errors.

use super::check::Track;
use super::fast_line::scan_tum_fast;
use super::layout::VALUES;
#[cfg(target_arch = "x86_64")]
use super::simd::{self, Shapes};
use crate::trajectory::StampedPose;

/// The fast line scanners of one reader, and what they learnt of the file (the line shapes of
/// the AVX2 scanner).
#[derive(Default)]
pub(crate) struct FastLines {
    /// The line shapes of the AVX2 scanner, once it runs.
    #[cfg(target_arch = "x86_64")]
    shapes: Option<Box<Shapes>>,
    /// Only the scalar scanner, whatever the processor runs (to compare the two).
    #[cfg_attr(not(target_arch = "x86_64"), allow(dead_code))]
    scalar_only: bool,
}

impl FastLines {
    /// Use only the scalar scanner from now on.
    pub(crate) fn scalar_only(&mut self) {
        self.scalar_only = true;
    }

    /// Decode the common TUM lines at the start of `s` straight into `out` (at most `max`;
    /// their line numbers into `lines`), until a line that is not common or fails a check:
    /// that one is left to the general path, which makes its error. `track` moves on by the
    /// lines taken. Returns the bytes consumed and the poses pushed.
    ///
    /// Lines are scanned in groups of [`AHEAD`] and then checked and built in order. A line's
    /// checks and pose end in a long chain of floating-point latencies (divisions, the square
    /// root of the norm); right after its own scan they would hold up the CPU's in-order
    /// retirement, while after the scan of a whole group the values are long ready and the
    /// chains of several lines overlap. (Scanning ahead is free of effects: a line after a
    /// failed one is simply scanned again by whoever reads on.)
    #[inline(always)]
    pub(crate) fn decode(
        &mut self,
        track: &mut Track,
        s: &[u8],
        out: &mut Vec<StampedPose>,
        lines: Option<&mut Vec<usize>>,
        max: usize,
    ) -> (usize, usize) {
        #[cfg(target_arch = "x86_64")]
        if !self.scalar_only && simd::available() {
            let mut shapes = self.shapes.take().unwrap_or_default();
            // SAFETY: the processor runs AVX2, BMI1 and POPCNT code (checked just above).
            let r = unsafe { run_avx2(track, &mut shapes, s, out, lines, max) };
            self.shapes = Some(shapes);
            return r;
        }
        run_with(track, &mut ScalarLines, s, out, lines, max)
    }
}

/// Lines [`FastLines::decode`] scans before it checks them.
const AHEAD: usize = 8;
/// How far ahead of a group of lines \[bytes\] their bytes are fetched ([`crate::fast::prefetch`]:
/// the processor's prefetchers stop at the end of each 4 KiB page), and how many: about a group
/// (8 lines of ~104 bytes in the benchmark's file). Parsing 10^6 poses in memory
/// (`examples/parse_bench`): 40 ms of CPU without, 28 ms with 2048 bytes ahead, flat from 1 to
/// 8 KiB, 32 ms at 16 KiB.
const PREFETCH_AHEAD: usize = 2048;
const PREFETCH_BYTES: usize = 1024;

/// [`run_with`] with the AVX2 line scanner ([`Shapes::scan`]), falling back to
/// [`scan_tum_fast`] for the lines it does not take.
///
/// # Safety
/// The processor must run AVX2, BMI1 and POPCNT code.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "avx2,bmi1,popcnt")]
unsafe fn run_avx2(
    track: &mut Track,
    shapes: &mut Shapes,
    s: &[u8],
    out: &mut Vec<StampedPose>,
    lines: Option<&mut Vec<usize>>,
    max: usize,
) -> (usize, usize) {
    run_with(track, shapes, s, out, lines, max)
}

/// A line scanner for [`run_with`]: [`scan_tum_fast`] or one that takes the same lines
/// with the same values (a type, not a closure, so that it is inlined into its caller's
/// target features).
trait LineScanner {
    /// The values and the `\n` of the common TUM line at the start of `s`, or `None`.
    ///
    /// # Safety
    /// The processor must run the code the scanner is built for.
    unsafe fn scan(&mut self, s: &[u8]) -> Option<([f64; VALUES], usize)>;
}

/// [`scan_tum_fast`], for every processor.
struct ScalarLines;

impl LineScanner for ScalarLines {
    #[inline(always)]
    unsafe fn scan(&mut self, s: &[u8]) -> Option<([f64; VALUES], usize)> {
        scan_tum_fast(s)
    }
}

/// [`Shapes::scan`], and [`scan_tum_fast`] for the lines it does not take.
#[cfg(target_arch = "x86_64")]
impl LineScanner for Shapes {
    #[inline(always)]
    unsafe fn scan(&mut self, s: &[u8]) -> Option<([f64; VALUES], usize)> {
        // SAFETY: passed on from the caller.
        match unsafe { Shapes::scan(self, s) } {
            Some(r) => Some(r),
            None => scan_tum_fast(s),
        }
    }
}

/// [`FastLines::decode`] with the line scanner `scanner`, whose code this processor must run.
#[inline(always)]
fn run_with<L: LineScanner>(
    track: &mut Track,
    scanner: &mut L,
    s: &[u8],
    out: &mut Vec<StampedPose>,
    mut lines: Option<&mut Vec<usize>>,
    max: usize,
) -> (usize, usize) {
    let mut off = 0;
    let mut n = 0;
    let mut vals = [[0.0; VALUES]; AHEAD];
    let mut lens = [0; AHEAD];
    loop {
        // Scan a group of lines first (the bytes a few groups on fetched meanwhile) ...
        crate::fast::prefetch(
            s.as_ptr().wrapping_add(off + PREFETCH_AHEAD),
            PREFETCH_BYTES,
        );
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
            track.line_no += 1;
            // Finite by construction: m / 10^k with m <= 2^53 (see `scan_field`).
            let Some(p) = track.accept(&vals[q], true) else {
                track.line_no -= 1;
                return (off, n);
            };
            out.push(p);
            if let Some(l) = lines.as_deref_mut() {
                l.push(track.line_no);
            }
            off += lens[q] + 1;
            n += 1;
        }
        if k < AHEAD {
            return (off, n);
        }
    }
}
