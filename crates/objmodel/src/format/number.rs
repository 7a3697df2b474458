//! Byte-level helpers for the pose readers: a correctly rounded fast path for plain decimals
//! (falling back to `fast_float2` for everything else) and a word-at-a-time newline search.

/// Exact powers of ten representable as `f64` (10^0 ..= 10^22).
const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Largest integer up to which every integer is exactly representable as `f64`.
const MAX_EXACT: u64 = 1 << 53;

/// Scan a plain decimal (`[+-]digits[.digits]`) starting at `s[start]`.
///
/// Returns `(value, end, exact)`: `end` is the index of the first byte that is not part of the
/// plain decimal. `exact` is true when `value` is correctly rounded: at least one digit, at
/// most 19, the digits form an integer `m <= 2^53` and there are at most 22 fraction digits,
/// so `±m` and `10^k` are exact doubles and one IEEE division rounds correctly (Clinger's fast
/// path). The caller must also check that `end` is the end of the field; otherwise (exponent,
/// stray characters, ...) it falls back to [`parse_f64`].
#[inline(always)]
pub(crate) fn scan_decimal(s: &[u8], start: usize) -> (f64, usize, bool) {
    let n = s.len();
    let mut i = start;
    let mut neg = false;
    if i < n && (s[i] == b'-' || s[i] == b'+') {
        neg = s[i] == b'-';
        i += 1;
    }
    let d0 = i;
    let mut m: u64 = 0;
    // Integer parts are short in pose files: byte by byte is fastest there.
    while i < n {
        let d = s[i].wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        m = m.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    let mut digits_seen = i - d0;
    let mut frac = 0;
    if i < n && s[i] == b'.' {
        i += 1;
        let (m2, e) = digits(s, i, m);
        m = m2;
        frac = e - i;
        i = e;
        digits_seen += frac;
    }
    let exact = digits_seen > 0 && digits_seen <= 19 && m <= MAX_EXACT && frac <= 22;
    // `m as i64` is exact when `exact` holds (m <= 2^53) and converts faster than from u64.
    let v = (m as i64) as f64 / POW10[if frac <= 22 { frac } else { 0 }];
    (if neg { -v } else { v }, i, exact)
}

/// Append the run of ASCII digits starting at `s[i]` to `m` (wrapping on overflow, which the
/// caller detects by counting digits). Returns the new `m` and the index after the run.
/// Whole groups of eight digits are taken at once; the rest byte by byte (branches on digits
/// predict well and let the CPU run ahead, where a branch-free digit count would not).
#[inline(always)]
fn digits(s: &[u8], mut i: usize, mut m: u64) -> (u64, usize) {
    let n = s.len();
    while i + 8 <= n {
        let w = load8(s, i);
        if digit_run(w) < 8 {
            break;
        }
        m = m
            .wrapping_mul(100_000_000)
            .wrapping_add(parse_8digit_values(w - 0x3030_3030_3030_3030));
        i += 8;
    }
    while i < n {
        let d = s[i].wrapping_sub(b'0');
        if d > 9 {
            break;
        }
        m = m.wrapping_mul(10).wrapping_add(u64::from(d));
        i += 1;
    }
    (m, i)
}

/// Number of leading (lowest) bytes of `w` that are ASCII digits, 0..=8.
#[inline(always)]
fn digit_run(w: u64) -> usize {
    // High bit set in bytes > '9' (a) or < '0' (b). Carries and borrows only move upwards and
    // only out of non-digit bytes, so the lowest flagged byte is always a true non-digit.
    let a = w.wrapping_add(0x4646_4646_4646_4646);
    let b = w.wrapping_sub(0x3030_3030_3030_3030);
    let mask = (a | b) & 0x8080_8080_8080_8080;
    (mask.trailing_zeros() / 8) as usize // 64 / 8 = 8 when there is none
}

/// Eight bytes of `s` from `i` as a little-endian word.
#[inline(always)]
fn load8(s: &[u8], i: usize) -> u64 {
    let c = &s[i..i + 8];
    u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]])
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

/// Parse a whole field as an `f64`, correctly rounded (the same result as
/// `str::parse::<f64>`). Returns `None` if the bytes are not a number. NaN and infinities are
/// accepted here (`"nan"`, `"inf"`); the readers reject them with their own message.
pub fn parse_f64(field: &[u8]) -> Option<f64> {
    let (v, end, exact) = scan_decimal(field, 0);
    if exact && end == field.len() {
        return Some(v);
    }
    fast_float2::parse::<f64, _>(field).ok()
}

/// Index of the first `\n` in `s`, eight bytes at a time.
#[inline]
pub(crate) fn find_newline(s: &[u8]) -> Option<usize> {
    const LO: u64 = 0x0101_0101_0101_0101;
    const HI: u64 = 0x8080_8080_8080_8080;
    const NL: u64 = LO * b'\n' as u64;
    let mut chunks = s.chunks_exact(8);
    let mut base = 0;
    for c in &mut chunks {
        let w = u64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]]) ^ NL;
        // The lowest flagged byte is always a true zero byte (borrows only propagate upwards).
        let z = w.wrapping_sub(LO) & !w & HI;
        if z != 0 {
            return Some(base + (z.trailing_zeros() / 8) as usize);
        }
        base += 8;
    }
    chunks
        .remainder()
        .iter()
        .position(|&b| b == b'\n')
        .map(|p| base + p)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn newline_search() {
        for len in 0..40 {
            for pos in 0..=len {
                let mut v = vec![b'a'; len];
                if pos < len {
                    v[pos] = b'\n';
                }
                // noise above the newline must not matter
                for b in v.iter_mut().skip(pos + 1) {
                    *b = 0x0b;
                }
                assert_eq!(find_newline(&v), if pos < len { Some(pos) } else { None });
            }
        }
    }

    #[test]
    fn plain_decimals() {
        for s in [
            "0.12345678",
            "0.123456789012",
            "99999999.99999999",
            "0.000000001",
        ] {
            assert_eq!(parse_f64(s.as_bytes()), s.parse::<f64>().ok(), "{s}");
        }
        for s in [
            "0",
            "-0",
            "1.",
            ".5",
            "+2.25",
            "1700000000.008333",
            "-0.000004363",
            "123",
        ] {
            assert_eq!(
                parse_f64(s.as_bytes()).map(f64::to_bits),
                s.parse::<f64>().ok().map(f64::to_bits),
                "{s}"
            );
        }
        for s in ["", ".", "-", "+", "1x", "1.2.3", "--1", "1e", "e5"] {
            assert_eq!(parse_f64(s.as_bytes()), None, "{s}");
        }
    }
}
