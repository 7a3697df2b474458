//! An AVX2 scanner for TUM lines that repeat a layout ([`Shapes`]): the same values as
//! [`super::fast_line::scan_tum_fast`] in about a third of the instructions.
//!
//! The scalar scanner walks each field byte by byte: about 70 instructions a field, most of
//! them finding where digits, points and signs are. In a pose file written by a program those
//! places repeat from line to line: a writer prints each column with a fixed number of digits,
//! so the lines differ only in their digits and in a few signs. The *shape* of a line is the
//! line with every digit replaced by `0` (`1.25 -0.5` → `0.00 -0.0`). For a shape seen before,
//! everything but the digits' values is known, and a line is read as:
//!
//! 1. **Match.** Four 32-byte loads; digits are replaced by `'0'` and the result compared with
//!    the shape's template up to and including its `\n` (bytes after it belong to the next
//!    line). The shape is found in a small table by a hash of where the digits are.
//! 2. **Digits.** The digits of each field (a *run*; a field longer than 16 bytes gives two,
//!    its integer and its fraction digits) are loaded into a 128-bit lane, `'0'` subtracted,
//!    and one byte shuffle (`pshufb`, its control computed once for the shape) drops sign and
//!    point and right-aligns the digits over zeros: two runs per 256-bit register. Three
//!    multiply-adds give each run as two eight-digit halves, joined as doubles (`10^8 hi + lo`,
//!    exact below 2^53), four runs at a time; a field of two runs is `int · 10^k + frac`.
//! 3. **Value.** As in [`super::fast_field::scan_field`]: with `m` the digits as an integer (at
//!    most 19 of them, `m <= 2^53`) and `k` fraction digits, `±m / 10^k` is one correctly
//!    rounded IEEE division of two exact doubles: the value `str::parse` gives.
//!
//! A line of a new shape is taken apart byte by byte once ([`Shape::new`]); a shape whose
//! fields this scanner does not take (exponents, `nan`, more or fewer than eight fields, more
//! than 19 digits, comments, ...) is remembered as such, and its lines go to the scalar
//! scanners, which also make the error messages. So do lines of 128 bytes or more, the last
//! lines of a buffer, and every line of a file whose shapes keep changing (see
//! [`Shapes::scan`]).

use super::fast_field::{MAX_EXACT, POW10};
use super::tum::tum_field;
use std::arch::x86_64::*;

/// Bytes from a line's start that [`Shapes::scan`] reads: 128 for the line and its `\n`, and
/// 16 more for the load of a run that starts near the line's end.
pub(super) const SIMD_WINDOW: usize = 144;

/// Bytes of a line (with its `\n`) that a shape covers.
const LINE: usize = 128;

/// Longest run of digits, with its point, that one lane takes \[bytes\].
const LANE: usize = 16;

/// Slots of the shape table (a power of two).
const SLOTS: usize = 64;

/// Whether this processor runs the scanner's code: AVX2 ([`crate::fast::avx2`], which tests
/// can turn off), BMI1 and POPCNT (checked once, then cached by `std`).
#[inline(always)]
pub(super) fn available() -> bool {
    crate::fast::avx2()
        && std::arch::is_x86_feature_detected!("bmi1")
        && std::arch::is_x86_feature_detected!("popcnt")
}

/// One shape of line: its template and what is known about its fields.
#[derive(Clone)]
struct Shape {
    /// The line with every digit replaced by `'0'`, up to its `\n`.
    template: [u8; LINE],
    /// The bytes of the template that a line must match, by 32-byte chunk: `0..=end`.
    need: [u32; 4],
    /// Whether lines of this shape are read here (else by the scalar scanners).
    taken: bool,
    /// Registers of two runs each: four for the first runs of the eight fields, and one or
    /// two more when fields have a second run.
    groups: usize,
    /// Where the low and the high lane of each register are loaded from (line offsets).
    load: [[usize; 2]; 6],
    /// The byte shuffle of each register (see the module documentation).
    ctl: [[u8; 32]; 6],
    /// Field `k`'s digits as an integer are `first[k] · mul[k] + second[k]`: `first` its run
    /// number `k`, `second` the run that [`Shape::pick`] picks from runs `8..12` (masked to
    /// zero by [`Shape::keep`] for a field of one run); `mul` is 1, or `10^(fraction digits)`
    /// for a field whose integer and fraction digits are two runs.
    mul: [f64; 8],
    /// For `_mm256_permutevar8x32_epi32` on runs `8..12` as doubles: field `k`'s second run
    /// is the double at `pick[k]` (32-bit elements `2 pick[k]` and `2 pick[k] + 1`).
    pick: [i32; 16],
    /// All ones for a field with a second run, else zero.
    keep: [u64; 8],
    /// `-1` or `1`.
    sign: [f64; 8],
    /// `10^(fraction digits)`.
    scale: [f64; 8],
}

/// The shapes of the lines seen so far, and the counts that decide whether to keep looking.
pub(super) struct Shapes {
    slots: Vec<Option<Shape>>,
    lines: usize,
    misses: usize,
}

impl Default for Shapes {
    fn default() -> Self {
        Self {
            slots: vec![None; SLOTS],
            lines: 0,
            misses: 0,
        }
    }
}

impl Shape {
    /// The shape of `line` (whose `\n` is at `end < 128`): taken when its bytes before the `\n`
    /// are eight fields `[+-]digits[.digits]` (at least one digit, at most 19, a field's part
    /// before or after the point at most 16 bytes when the field is longer than 16) separated
    /// by spaces, tabs or `\r`.
    fn new(line: &[u8; SIMD_WINDOW], end: usize) -> Shape {
        let mut template = [0u8; LINE];
        for (t, &b) in template.iter_mut().zip(&line[..=end]) {
            *t = if b.is_ascii_digit() { b'0' } else { b };
        }
        let mut need = [0u32; 4];
        for i in 0..=end {
            need[i / 32] |= 1 << (i % 32);
        }
        let mut shape = Shape {
            template,
            need,
            taken: false,
            groups: 4,
            load: [[0; 2]; 6],
            ctl: [[0x80; 32]; 6],
            mul: [1.0; 8],
            pick: [0; 16],
            keep: [0; 8],
            sign: [1.0; 8],
            scale: [1.0; 8],
        };
        shape.taken = shape.fields(&line[..end]).is_some();
        shape
    }

    /// Fill in the fields of `line` (without its `\n`); `None` if it is not a shape read here.
    /// Fields are split as [`tum_field`] splits them; a comment is left to the scalar scanners.
    fn fields(&mut self, line: &[u8]) -> Option<()> {
        let spans: Vec<(usize, usize)> = (0..9).map_while(|k| tum_field(line, k)).collect();
        if spans.len() != 8 || line.contains(&b'#') {
            return None;
        }
        let mut seconds = 0;
        for (k, &(a, i)) in spans.iter().enumerate() {
            let field = &line[a..i];
            let sg = usize::from(matches!(field[0], b'-' | b'+'));
            let body = &field[sg..];
            if !body.iter().all(|&b| b.is_ascii_digit() || b == b'.') {
                return None;
            }
            let dots: Vec<usize> = (0..body.len()).filter(|&j| body[j] == b'.').collect();
            let digits = body.len() - dots.len();
            if dots.len() > 1 || digits == 0 || digits > 19 {
                return None;
            }
            let d = dots.first().copied().unwrap_or(body.len());
            let frac = body.len() - d - dots.len();
            self.sign[k] = if field[0] == b'-' { -1.0 } else { 1.0 };
            self.scale[k] = POW10[frac];
            let start = a + sg;
            if body.len() <= LANE {
                self.run(k, start, body.len(), Some(d));
            } else {
                // The integer and the fraction digits in two runs, at most four such fields.
                if d > LANE || frac > LANE || dots.is_empty() || seconds == 4 {
                    return None;
                }
                self.run(k, start, d, None);
                self.run(8 + seconds, start + d + 1, frac, None);
                self.mul[k] = POW10[frac];
                self.pick[2 * k] = 2 * seconds as i32;
                self.pick[2 * k + 1] = 2 * seconds as i32 + 1;
                self.keep[k] = u64::MAX;
                seconds += 1;
            }
        }
        self.groups = 4 + seconds.div_ceil(2);
        // Lanes without a run: load them from anywhere (their shuffle is all zeros).
        for r in 8 + seconds..12 {
            self.load[r / 2][r % 2] = self.load[0][0];
        }
        Some(())
    }

    /// Run number `r`: `len` bytes at line offset `at`, all digits but the one at `dot` (if
    /// any). Sets its load and its shuffle.
    fn run(&mut self, r: usize, at: usize, len: usize, dot: Option<usize>) {
        let (g, hi) = (r / 2, r % 2);
        self.load[g][hi] = at;
        let digits: Vec<usize> = (0..len).filter(|&j| Some(j) != dot).collect();
        let ctl = &mut self.ctl[g][16 * hi..16 * hi + 16];
        for (slot, &j) in ctl[LANE - digits.len()..].iter_mut().zip(&digits) {
            *slot = j as u8;
        }
    }
}

impl Shapes {
    /// Whether the file's shapes keep changing, so that the table is no longer used (see
    /// [`Shapes::scan`]).
    #[inline(always)]
    fn given_up(&self) -> bool {
        self.lines >= 256 && self.misses * 16 > self.lines
    }

    /// The values of the TUM line at the start of `s` and the index of its `\n`, when its
    /// shape is one read here; `None` for every other line, and when fewer than
    /// [`SIMD_WINDOW`] bytes are left. Every line it takes is one that
    /// [`super::tum::scan_tum`] reads as eight numbers, with the same values, bit for bit.
    ///
    /// After 256 lines, if more than one line in 16 needed a new shape, the file's shapes keep
    /// changing (numbers printed with as many digits as they need, say): the table is then
    /// only a cost, and every further line is left to the scalar scanners.
    ///
    /// # Safety
    /// The processor must run AVX2, BMI1 and POPCNT code.
    #[inline]
    #[target_feature(enable = "avx2,bmi1,popcnt")]
    pub(super) unsafe fn scan(&mut self, s: &[u8]) -> Option<([f64; 8], usize)> {
        let window: &[u8; SIMD_WINDOW] = s.first_chunk()?;
        let p = window.as_ptr();
        let zero = _mm256_set1_epi8(b'0' as i8);
        let mut chunks = [_mm256_setzero_si256(); 4];
        let mut digits = 0u128;
        let mut newline = 0u128;
        for (k, c) in chunks.iter_mut().enumerate() {
            // SAFETY: bytes 32k..32k + 32 lie in the window.
            let v = unsafe { _mm256_loadu_si256(p.add(32 * k) as *const __m256i) };
            // Signed compares: bytes of 0x80 and above are negative, below '0'.
            let digit = _mm256_and_si256(
                _mm256_cmpgt_epi8(v, _mm256_set1_epi8(b'/' as i8)),
                _mm256_cmpgt_epi8(_mm256_set1_epi8(b':' as i8), v),
            );
            *c = _mm256_blendv_epi8(v, zero, digit);
            digits |= u128::from(_mm256_movemask_epi8(digit) as u32) << (32 * k);
            let nl = _mm256_cmpeq_epi8(v, _mm256_set1_epi8(b'\n' as i8));
            newline |= u128::from(_mm256_movemask_epi8(nl) as u32) << (32 * k);
        }
        if newline == 0 || self.given_up() {
            return None;
        }
        self.lines += 1;
        let end = newline.trailing_zeros() as usize;
        let slot = slot_of(digits, end);
        let matches = |shape: &Shape| {
            let mut differ = 0;
            for (k, c) in chunks.iter().enumerate() {
                // SAFETY: the template has 128 bytes.
                let t = unsafe { _mm256_loadu_si256(shape.template.as_ptr().add(32 * k).cast()) };
                let same = _mm256_movemask_epi8(_mm256_cmpeq_epi8(*c, t)) as u32;
                differ |= !same & shape.need[k];
            }
            differ == 0
        };
        let shape = match &self.slots[slot] {
            Some(shape) if matches(shape) => shape,
            _ => {
                self.misses += 1;
                self.slots[slot] = Some(Shape::new(window, end));
                self.slots[slot].as_ref()?
            }
        };
        if !shape.taken {
            return None;
        }
        // SAFETY: every run starts before the `\n` (at most byte 126), so its 16 bytes lie in
        // the window.
        unsafe { values(p, shape) }.map(|v| (v, end))
    }
}

/// The table slot of a line with digits where `digits` says (bytes after the `\n` at `end`
/// left out).
#[inline(always)]
fn slot_of(digits: u128, end: usize) -> usize {
    let digits = digits & ((1u128 << end) - 1);
    let h = (digits as u64 ^ end as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    let h = (h ^ (digits >> 64) as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    (h >> 58) as usize & (SLOTS - 1)
}

/// The runs of register `g` as 32-bit integers: `[hi, lo, hi, lo]` in each 128-bit lane, the
/// lane's digits being `10^8 hi + lo`.
///
/// # Safety
/// The 16 bytes at both of its load offsets must be readable from `p`.
#[inline(always)]
unsafe fn halves(p: *const u8, shape: &Shape, g: usize) -> __m256i {
    let [lo, hi] = shape.load[g];
    // SAFETY: by the caller; the control has 32 bytes.
    let (v, ctl) = unsafe {
        (
            _mm256_loadu2_m128i(p.add(hi).cast(), p.add(lo).cast()),
            _mm256_loadu_si256(shape.ctl[g].as_ptr().cast()),
        )
    };
    let d = _mm256_shuffle_epi8(_mm256_sub_epi8(v, _mm256_set1_epi8(b'0' as i8)), ctl);
    // Pairs: 10 * d[2i] + d[2i+1] (the more significant digit comes first in memory).
    let d = _mm256_maddubs_epi16(d, _mm256_set1_epi16(0x010A));
    // Groups of four: 100 * pair[2i] + pair[2i+1].
    let d = _mm256_madd_epi16(d, _mm256_set1_epi32(0x0001_0064));
    // Groups of eight: 10^4 * quad[2i] + quad[2i+1] (quads <= 9999 pack into 16 bits).
    let d = _mm256_packus_epi32(d, d);
    _mm256_madd_epi16(d, _mm256_set1_epi32(0x0001_2710))
}

/// Four runs (registers `g` and `g + 1`) as doubles: `10^8 hi + lo`, exact while the value is
/// below `2^53` (larger values are caught by the caller).
///
/// # Safety
/// The processor must run AVX2 code.
#[inline(always)]
unsafe fn four_runs(a: __m256i, b: __m256i) -> __m256d {
    // [a.r0, b.r0 | a.r1, b.r1] as (hi, lo) pairs, then all four hi and all four lo.
    let ab = _mm256_unpacklo_epi64(a, b);
    let v = _mm256_permutevar8x32_epi32(ab, _mm256_setr_epi32(0, 4, 2, 6, 1, 5, 3, 7));
    let hi = _mm256_cvtepi32_pd(_mm256_castsi256_si128(v));
    let lo = _mm256_cvtepi32_pd(_mm256_extracti128_si256::<1>(v));
    _mm256_add_pd(_mm256_mul_pd(hi, _mm256_set1_pd(1e8)), lo)
}

/// The eight values of a line of `shape` at `p`, or `None` if a field's digits exceed
/// `2^53 - 1` (then one division would not be exact; the scalar path takes the line).
///
/// # Safety
/// The 16 bytes at each of the shape's load offsets must be readable from `p`.
#[inline(always)]
unsafe fn values(p: *const u8, shape: &Shape) -> Option<[f64; 8]> {
    // SAFETY: passed on from the caller.
    let h = |g: usize| unsafe { halves(p, shape, g) };
    // SAFETY: the caller's processor runs AVX2 code.
    let four = |a, b| unsafe { four_runs(a, b) };
    let firsts = [four(h(0), h(1)), four(h(2), h(3))];
    let seconds = match shape.groups {
        4 => _mm256_setzero_pd(),
        5 => four(h(4), _mm256_setzero_si256()),
        _ => four(h(4), h(5)),
    };
    let seconds = _mm256_castpd_si256(seconds);
    let limit = _mm256_set1_pd(MAX_EXACT as f64);
    let mut out = [0.0; 8];
    let mut too_large = 0;
    for (half, first) in firsts.into_iter().enumerate() {
        let at = 4 * half;
        // SAFETY: every array read here has at least `at + 4` (or `2 at + 8`) elements.
        let (pick, keep, mul, sign, scale) = unsafe {
            (
                _mm256_loadu_si256(shape.pick.as_ptr().add(2 * at).cast()),
                _mm256_loadu_si256(shape.keep.as_ptr().add(at).cast()),
                _mm256_loadu_pd(shape.mul.as_ptr().add(at)),
                _mm256_loadu_pd(shape.sign.as_ptr().add(at)),
                _mm256_loadu_pd(shape.scale.as_ptr().add(at)),
            )
        };
        let second = _mm256_and_si256(_mm256_permutevar8x32_epi32(seconds, pick), keep);
        // Exact: each product and sum is an integer below 2^53 unless flagged here (rounding
        // is monotonic, so a true value of 2^53 or more never rounds below 2^53).
        let m = _mm256_add_pd(_mm256_mul_pd(first, mul), _mm256_castsi256_pd(second));
        too_large |= _mm256_movemask_pd(_mm256_cmp_pd::<_CMP_GE_OQ>(m, limit));
        let v = _mm256_div_pd(_mm256_mul_pd(m, sign), scale);
        // SAFETY: `out` has 8 elements.
        unsafe { _mm256_storeu_pd(out.as_mut_ptr().add(at), v) };
    }
    (too_large == 0).then_some(out)
}

#[cfg(test)]
#[path = "simd_tests.rs"]
mod tests;
