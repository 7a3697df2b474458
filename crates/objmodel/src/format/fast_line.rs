//! The common TUM line, fast and without SIMD: [`scan_tum_fast`] reads eight plain decimals
//! ([`scan_field`]) and their separators, unrolled. It reads what the general scanner
//! ([`scan_tum`]) reads, for the lines it takes; the others (and the last lines of a buffer)
//! are left to that one.
//!
//! Speed code: the scalar twin of the AVX2 scanner (`simd.rs`), which leaves it the lines it
//! does not take, and the line scanner of processors without AVX2.

use super::fast_field::{scan_field, Decimal, FIELD_WINDOW};
use super::tum::is_tum_space;
#[cfg(doc)]
use super::tum::scan_tum;

/// Bytes of a line [`scan_tum_fast`] reads: room for lines of up to about 190 bytes (the lines
/// of a pose file have about 100).
const LINE_WINDOW: usize = 256;

/// [`scan_tum`] for the common line: eight numbers that [`scan_field`] takes, separated by
/// spaces, tabs or stray `\r`s (fastest: one space), which may also come before the first and
/// after the last, and then the `\n`. Returns the values and the index of the `\n`: what
/// [`scan_tum`] finds for such a line (count 8, nothing bad), as [`scan_field`] gives the
/// value that `str::parse` (and so `fast_float2`) gives. `None` for any other line (blank,
/// comment, wrong, ...), which then takes [`scan_tum`], and when fewer than [`LINE_WINDOW`]
/// bytes are left (the last lines of a buffer).
///
/// The fields are unrolled, so their values stay in registers and each field's branches are
/// predicted on their own; the eight divisions come last, together (the compiler pairs them
/// into two-lane SIMD divisions, which are as correctly rounded as scalar ones).
#[inline(always)]
pub(crate) fn scan_tum_fast(s: &[u8]) -> Option<([f64; 8], usize)> {
    let line: &[u8; LINE_WINDOW] = s.first_chunk()?;
    let mut mantissa = [0.0; 8];
    let mut scale = [1.0; 8];
    let mut i = 0;
    // Field `k` at `i`, and the separator or line end after it; `i` moves past both.
    macro_rules! field {
        ($k:expr, $last:expr) => {{
            if i > LINE_WINDOW - FIELD_WINDOW {
                return None;
            }
            let mut b: &[u8; FIELD_WINDOW] = line[i..].first_chunk()?;
            let d = match scan_field(b) {
                Some(d) => d,
                None => {
                    // Not a number: more spaces, or the general path.
                    let (d, at) = field_after_space(line, i)?;
                    i = at;
                    b = line[i..].first_chunk()?;
                    d
                }
            };
            mantissa[$k] = d.mantissa;
            scale[$k] = d.scale;
            let next = b[d.len];
            let expected = if $last { b'\n' } else { b' ' };
            if next != expected && !other_space(next) {
                return None;
            }
            i += d.len + 1;
        }};
    }
    field!(0, false);
    field!(1, false);
    field!(2, false);
    field!(3, false);
    field!(4, false);
    field!(5, false);
    field!(6, false);
    field!(7, true);
    let end = if line[i - 1] == b'\n' {
        i - 1
    } else {
        newline_after_space(line, i - 1)?
    };
    Some((std::array::from_fn(|k| mantissa[k] / scale[k]), end))
}

/// For [`scan_tum_fast`]: the field after the run of spaces and tabs at `line[i..]`, and where
/// it starts; `None` if there is no such run, or no field that [`scan_field`] takes after it.
#[cold]
#[inline(never)]
fn field_after_space(line: &[u8; LINE_WINDOW], mut i: usize) -> Option<(Decimal, usize)> {
    if !is_tum_space(*line.get(i)?) {
        return None;
    }
    while is_tum_space(*line.get(i)?) {
        i += 1;
    }
    if i > LINE_WINDOW - FIELD_WINDOW {
        return None;
    }
    let d = scan_field(line[i..].first_chunk()?)?;
    Some((d, i))
}

/// [`is_tum_space`] for [`scan_tum_fast`] after a field, where a space (between fields) or the
/// `\n` (after the last) is the usual byte; a function of its own, so that the usual case
/// stays one comparison.
#[cold]
#[inline(never)]
fn other_space(b: u8) -> bool {
    is_tum_space(b)
}

/// For [`scan_tum_fast`]: the index of the `\n` after the spaces and tabs at `line[i..]`, or
/// `None` if something else comes first.
#[cold]
#[inline(never)]
fn newline_after_space(line: &[u8; LINE_WINDOW], mut i: usize) -> Option<usize> {
    while is_tum_space(*line.get(i)?) {
        i += 1;
    }
    (line[i] == b'\n').then_some(i)
}

#[cfg(test)]
mod tests {
    use super::super::tum::scan_tum;
    use super::*;

    use crate::testing::next;

    /// A field: what pose files hold (`%.6f`, `%.9f`, signs, ...), or with `any` also other
    /// numbers and things that are no number. True for a plain decimal of at most 15 bytes.
    fn random_field(r: &mut rand::rngs::StdRng, any: bool) -> (String, bool) {
        let x = (next(r) % 2_000_000_000) as f64 / 1e9 - 1.0;
        let kind = if any {
            next(r) % 16
        } else {
            [0, 6, 8, 9, 12][(next(r) % 5) as usize]
        };
        match kind {
            0..=5 => (format!("{x:.9}"), true),
            6 => (format!("{:.6}", 1.7e9 + x), true),
            7 => (format!("{x}"), false),
            8 => (format!("{:.3}", x * 1e4), true),
            9 => (format!("{:.0}", x * 1e3), true),
            10 => (format!("{x:.20}"), false),
            11 => (format!("{x:e}"), false),
            12 => (format!("+{:.2}", x.abs()), true),
            _ => {
                let odd = [
                    "nan", "-inf", ".5", "-.5", "5.", "-", "", "x1", "1,5", "0x1f", "#",
                ];
                (
                    odd[(next(r) % odd.len() as u64) as usize].to_string(),
                    false,
                )
            }
        }
    }

    /// `scan_tum_fast` finds what `scan_tum` finds, whenever it takes a line; and it takes
    /// the common lines.
    #[test]
    fn fast_scan_matches_scan_tum() {
        let mut r = crate::testing::rng(0x2545_f491_4f6c_dd1d);
        let (mut taken, mut common) = (0, 0);
        for round in 0..100_000 {
            let mut line = String::new();
            let mut plain = true;
            let any = next(&mut r) % 3 == 1;
            if next(&mut r) % 20 == 1 {
                line.push_str([" ", "\t", "  "][(next(&mut r) % 3) as usize]);
            }
            let fields = [8, 8, 8, 8, 8, 8, 7, 9][(next(&mut r) % 8) as usize];
            plain &= fields == 8;
            for k in 0..fields {
                if k > 0 {
                    let sep = [" ", " ", " ", " ", "\t", "  ", " \t", "\r"];
                    line.push_str(sep[(next(&mut r) % sep.len() as u64) as usize]);
                }
                let (f, ok) = random_field(&mut r, any);
                plain &= ok;
                line.push_str(&f);
            }
            match next(&mut r) % 24 {
                0 => line.push_str(" \r"),
                1 => line.push('\r'),
                2 => line.push_str("  "),
                3 => line.push_str(" # comment"),
                4 => line.push('#'),
                5 => {} // no line end
                _ => {}
            }
            if next(&mut r) % 24 != 5 {
                line.push('\n');
            }
            let mut buf = line.clone().into_bytes();
            // What follows: the next line, garbage, or nothing (the end of a buffer).
            let pad = [0, 10, 100, 300, 300, 300][(next(&mut r) % 6) as usize];
            buf.extend((0..pad).map(|_| b"0123456789 .-\n#xe\t"[(next(&mut r) % 18) as usize]));

            let slow = scan_tum(&buf);
            let Some((vals, end)) = scan_tum_fast(&buf) else {
                // A plain line (single spaces or tabs, one `\n`) with room to read is taken.
                let room = buf.len() >= LINE_WINDOW && line.len() < 150;
                let clean = !line.contains("  ") && !line.contains('\r') && !line.contains('#');
                let starts = !line.starts_with([' ', '\t']);
                assert!(
                    !(plain && room && clean && starts && line.ends_with('\n')),
                    "round {round}: {line:?} not taken"
                );
                continue;
            };
            assert_eq!((slow.count, slow.bad, slow.end), (8, None, end), "{line:?}");
            assert_eq!(
                vals.map(f64::to_bits),
                slow.vals.map(f64::to_bits),
                "{line:?}"
            );
            taken += 1;
            common += usize::from(plain);
        }
        assert!(taken > 10_000 && common > 5_000, "{taken} {common}");
    }
}
