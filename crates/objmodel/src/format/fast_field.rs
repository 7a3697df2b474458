//! The fields of the common TUM line, fast: [`scan_field`] reads a plain decimal
//! (`[+-]digits[.digits]`) in a few word-wide operations, for the scalar line scanner
//! (`fast_line.rs`); `simd.rs` shares its powers of ten and its limit.
//!
//! Speed code: it takes only numbers whose value one IEEE division gives exactly as
//! `str::parse` does (Clinger's fast path), and leaves every other field to the general path
//! (`tum.rs`, `fast_float2`).
//!
//! Why it stays in front of `fast_float2`: thread CPU time of `read_trajectory`, median of 9
//! interleaved runs, with the scalar line scanner and with every line it takes left to the
//! general path (`fast_float2` alone) instead:
//!
//! | file | with | `fast_float2` alone |
//! | --- | --- | --- |
//! | benchmark, 10⁶ poses, AVX2 | 63.9 ms | 63.9 ms |
//! | the same, AVX2 off (`fast::set_baseline_only`) | 79.8 ms | 150.4 ms |
//! | 3·10⁵ poses, trailing zeros stripped (shapes keep changing), AVX2 | 36.0 ms | 59.9 ms |
//!
//! On the benchmark file with AVX2 the lines go to `simd.rs` and this is idle; it is the
//! scanner of processors without AVX2 and of files whose line shapes keep changing.

/// Exact powers of ten representable as `f64` (10^0 ..= 10^22).
pub(crate) const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Largest integer up to which every integer is exactly representable as `f64`.
pub(crate) const MAX_EXACT: u64 = 1 << 53;

/// Eight bytes of `s` from `i` as a little-endian word (one load).
#[inline(always)]
fn load8(s: &[u8], i: usize) -> u64 {
    match s[i..].first_chunk::<8>() {
        Some(c) => u64::from_le_bytes(*c),
        None => panic!("load8: fewer than 8 bytes from {i}"),
    }
}

/// The value of eight decimal digits given as byte values 0..=9 (first digit in the lowest
/// byte), SWAR.
#[inline(always)]
fn parse_8digit_values(w: u64) -> u64 {
    const MASK: u64 = 0x0000_00FF_0000_00FF;
    const MUL1: u64 = 0x000F_4240_0000_0064; // 100 + (1000000 << 32)
    const MUL2: u64 = 0x0000_2710_0000_0001; // 1 + (10000 << 32)
    let w = w.wrapping_mul(10).wrapping_add(w >> 8); // pairs of digits
    let v1 = (w & MASK).wrapping_mul(MUL1);
    let v2 = ((w >> 16) & MASK).wrapping_mul(MUL2);
    u64::from(((v1.wrapping_add(v2)) >> 32) as u32)
}

/// `'0'` in every byte of a word.
const ZEROS: u64 = 0x3030_3030_3030_3030;

/// True if all eight bytes of `w` are ASCII digits.
///
/// A byte below `'0'` sets its high bit in `w - ZEROS`, a byte above `'9'` in `w + 0x46..`
/// (`'9' + 0x46 = 0x7F`), and a byte `>= 0x80` in one of the two. Carries and borrows start
/// only at non-digit bytes and only move upwards, so the lowest non-digit byte is always
/// flagged itself: no flag at all means eight digits.
#[inline(always)]
fn all_digits(w: u64) -> bool {
    (w.wrapping_add(0x4646_4646_4646_4646) | w.wrapping_sub(ZEROS)) & 0x8080_8080_8080_8080 == 0
}

/// [`all_digits`] for four bytes.
#[inline(always)]
fn all_digits4(w: u32) -> bool {
    (w.wrapping_add(0x4646_4646) | w.wrapping_sub(0x3030_3030)) & 0x8080_8080 == 0
}

/// The value of four ASCII digits (first digit in the lowest byte), SWAR as in
/// [`parse_8digit_values`]: pairs `10 * d0 + d1` and `10 * d2 + d3` land in bytes 0 and 2, one
/// multiplication by `(100 << 16) + 1` adds `100 * pair0 + pair1` into bits 16..32.
#[inline(always)]
fn parse_4digits(w: u32) -> u64 {
    let w = w.wrapping_sub(0x3030_3030);
    let w = w.wrapping_mul(10).wrapping_add(w >> 8);
    u64::from((w & 0x00FF_00FF).wrapping_mul((100 << 16) + 1) >> 16)
}

/// Bytes [`scan_field`] is given. It reads at most 36 (a sign or digit, 17 more integer
/// digits, the point, 16 fraction digits and the byte after them).
pub(crate) const FIELD_WINDOW: usize = 64;

/// Longest field [`scan_field`] takes: up to 19 bytes hold up to 19 digits, which cannot
/// overflow a `u64`.
const MAX_FIELD: usize = 19;

/// A plain decimal found by [`scan_field`]: its value is `mantissa / scale`, and that one IEEE
/// division is correctly rounded (both are exact doubles: `|mantissa| <= 2^53`, `scale = 10^k`
/// with `k <= 22`; Clinger's fast path).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Decimal {
    /// The digits as an integer, with the sign (`-0.0` for `-0`).
    pub(crate) mantissa: f64,
    /// `10^k` for `k` fraction digits.
    pub(crate) scale: f64,
    /// Length of the number in bytes.
    pub(crate) len: usize,
}

/// `m` followed by the eight digits in `w` (checked with [`all_digits`]).
#[inline(always)]
fn append_8digits(m: u64, w: u64) -> u64 {
    m.wrapping_mul(100_000_000)
        .wrapping_add(parse_8digit_values(w - ZEROS))
}

/// The end of a run of digits, byte by byte (at most 8) from `b[j]`, appended to `m`: the new
/// position and value. Part of [`scan_field`]'s hot loop, see there.
#[inline(always)]
fn digits_one_by_one(b: &[u8; FIELD_WINDOW], mut j: usize, mut m: u64) -> (usize, u64) {
    for _ in 0..8 {
        let d = u64::from(b[j]).wrapping_sub(u64::from(b'0'));
        if d > 9 {
            break;
        }
        m = m.wrapping_mul(10).wrapping_add(d);
        j += 1;
    }
    (j, m)
}

/// The plain decimal (`[+-]digits[.digits]`, at least one digit) at the start of `b`, for the
/// fields of a TUM line: its length and its value, exactly as `str::parse` gives it, or `None`
/// (then the caller takes the general path): for a number of more than [`MAX_FIELD`] bytes,
/// above `2^53`, or starting with the point (`.5`; `-.5` is taken).
///
/// `len` may stop short of the field (`1e5`, `1x`, more than 18 integer or 16 fraction
/// digits): the caller must check that a separator follows. This is the hot loop of reading a
/// TUM file, and written for an out-of-order CPU:
///
/// * Positions move only under branches, never by arithmetic on loaded bytes: the runs of
///   digits have the same lengths from line to line in a pose file, so the branches are
///   predicted and the CPU runs ahead to the next fields while the values are still being
///   computed. (Run lengths counted branch-free, e.g. from a bit mask, put a load and a few
///   operations between each field and the next, and that chain is slower.)
/// * For the same reason the first byte, a digit or a sign, is taken either way: the sign
///   changes the value, not where the digits are.
/// * Runs of eight (then four) digits are checked and converted with one load each
///   ([`all_digits`], [`parse_8digit_values`]); only the ends of runs and the integer part,
///   usually one digit, go byte by byte.
///
/// The division is left to the caller, which does eight at once.
#[inline(always)]
pub(crate) fn scan_field(b: &[u8; FIELD_WINDOW]) -> Option<Decimal> {
    let c = b[0];
    let neg = c == b'-';
    let d = c.wrapping_sub(b'0');
    let mut m = u64::from(d);
    if d > 9 {
        // A sign, followed by a digit (before or after the point).
        let digit_next =
            b[1].wrapping_sub(b'0') <= 9 || (b[1] == b'.' && b[2].wrapping_sub(b'0') <= 9);
        if !(neg || c == b'+') || !digit_next {
            return None;
        }
        m = 0;
    }
    // `b[0]` (a digit or the sign) is done; more integer digits follow from `b[1]`. Whether
    // `b[0]` was a sign only changes the value, not where the digits are.
    let mut j = 1;
    let d = b[1].wrapping_sub(b'0');
    if d <= 9 {
        m = m * 10 + u64::from(d);
        j = 2;
        let w = load8(b, j);
        if all_digits(w) {
            (j, m) = (j + 8, append_8digits(m, w));
        }
        (j, m) = digits_one_by_one(b, j, m);
    }
    let mut frac = 0;
    if b[j] == b'.' {
        j += 1;
        let f0 = j;
        let w = load8(b, j);
        if all_digits(w) {
            (j, m) = (j + 8, append_8digits(m, w));
        } else if all_digits4(w as u32) {
            m = m.wrapping_mul(10_000).wrapping_add(parse_4digits(w as u32));
            j += 4;
        }
        (j, m) = digits_one_by_one(b, j, m);
        frac = j - f0;
    }
    // At most 19 bytes: at most 19 digits, so `m` did not wrap, and `frac <= 22`. Up to 15
    // bytes, `m < 10^15 < 2^53` needs no test.
    if j > 15 && (j > MAX_FIELD || m > MAX_EXACT) {
        return None;
    }
    // `m as i64` is exact (m <= 2^53) and converts faster than from u64.
    let v = (m as i64) as f64;
    Some(Decimal {
        mantissa: if neg { -v } else { v },
        scale: POW10[frac],
        len: j,
    })
}

#[cfg(test)]
mod tests {
    use super::super::number::tests::random_decimal;
    use super::*;

    /// `scan_field` (the number followed by other bytes) against `str::parse::<f64>`, bit for
    /// bit: what it takes is a number with the value `str::parse` gives, and it takes the
    /// whole number when a separator follows (what its caller checks).
    #[test]
    fn matches_std_bit_for_bit() {
        let mut state = crate::testing::rng(0x853c_49e6_748f_ea9b);
        let mut below = |n: u64| crate::testing::next(&mut state) % n;
        let followers = [
            b' ', b'\t', b'\r', b'\n', b'#', b'e', b'x', b'.', b'-', b'7', 0, 0xff,
        ];
        let mut seed = crate::testing::rng(0x2545_f491_4f6c_dd1d);
        let mut whole = 0;
        for _ in 0..300_000 {
            let s = random_decimal(&mut seed);
            let std = s.parse::<f64>().ok();
            // In a window, followed by a random byte and random filler.
            let mut b = [0u8; FIELD_WINDOW];
            for x in b.iter_mut() {
                *x = b" 0123456789.-+e\n"[below(16) as usize];
            }
            if s.len() >= FIELD_WINDOW {
                continue;
            }
            b[..s.len()].copy_from_slice(s.as_bytes());
            let follower = followers[below(followers.len() as u64) as usize];
            b[s.len()] = follower;
            let Some(d) = scan_field(&b) else { continue };
            let taken = std::str::from_utf8(&b[..d.len]).unwrap();
            let value = d.mantissa / d.scale;
            assert_eq!(
                Some(value.to_bits()),
                taken.parse::<f64>().ok().map(f64::to_bits),
                "{s:?} took {taken:?}"
            );
            let separator = |b: u8| matches!(b, b' ' | b'\t' | b'\r' | b'\n' | b'#');
            if separator(b[d.len]) && separator(follower) {
                assert_eq!(d.len, s.len(), "{s:?} took {taken:?}");
                assert_eq!(Some(value.to_bits()), std.map(f64::to_bits), "{s:?}");
                whole += 1;
            }
        }
        assert!(whole > 30_000, "{whole}");
    }

    #[test]
    fn scan_field_edges() {
        // As the caller uses it: the number must end at the separator.
        let field = |s: &str| {
            let mut b = [b' '; FIELD_WINDOW];
            b[..s.len()].copy_from_slice(s.as_bytes());
            scan_field(&b)
                .filter(|d| b[d.len] == b' ')
                .map(|d| (d.len, (d.mantissa / d.scale).to_bits()))
        };
        for s in [
            "0",
            "-0",
            "+0.5",
            "-.5",
            "5.",
            "-5.",
            "0.511458838",
            "-0.000067813",
            "1700000000.008333",
            "9007199254740992",
            "900719925474099.2",
            "-90071992547409.92",
            "-0.0000000000000001",
            "000000000000000001",
        ] {
            let std = s.parse::<f64>().unwrap().to_bits();
            assert_eq!(field(s), Some((s.len(), std)), "{s}");
        }
        // Beyond 2^53, more than 18 digits before or 16 after the point, more than 19 bytes,
        // no digit, a leading point, not a number: the general path.
        for s in [
            "9007199254740993",
            "90071992547409.93",
            "1234567890123456789",
            "0.00000000000000001",
            "0000000000000000001",
            "-",
            "+",
            "-.",
            ".5",
            ".",
            "nan",
            "inf",
            "e5",
            "1e5",
            "0x1",
        ] {
            assert_eq!(field(s), None, "{s}");
        }
    }
}
