//! Numbers in pose files: [`parse_f64`], correctly rounded by `fast_float2`.
//!
//! A hand-written parser of plain decimals used to stand in front of `fast_float2` here (and in
//! the general TUM scanner). It was removed: on the benchmark file (10⁶ poses) the parsing was
//! no faster with it (median thread CPU time of `read_trajectory` 60.0 ms with it and without
//! it, 10 interleaved runs each), because the lines of a pose file go through the line
//! scanners of the fast path (`simd.rs`, `fast_line.rs`) and reach this function only at the
//! ends of buffers, in CSV files and in lines those scanners leave.

/// Parse a whole field as an `f64`, correctly rounded (the same result as
/// `str::parse::<f64>`). Returns `None` if the bytes are not a number. NaN and infinities are
/// accepted here (`"nan"`, `"inf"`); the readers reject them with their own message.
#[inline]
pub fn parse_f64(field: &[u8]) -> Option<f64> {
    fast_float2::parse::<f64, _>(field).ok()
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Deterministic test randomness ([`crate::testing::next`]).
    struct Rng(rand::rngs::StdRng);

    impl Rng {
        fn below(&mut self, n: u64) -> u64 {
            crate::testing::next(&mut self.0) % n
        }

        fn digits(&mut self, n: usize, out: &mut String) {
            for _ in 0..n {
                out.push(char::from(b'0' + self.below(10) as u8));
            }
        }
    }

    /// A random decimal: sign or not, 0..=20 digits on each side of the point (or no point),
    /// leading zeros, and values next to 2^53.
    pub(crate) fn random_decimal(state: &mut rand::rngs::StdRng) -> String {
        let rng = &mut Rng(state.clone());
        let s = decimal(rng);
        *state = rng.0.clone();
        s
    }

    fn decimal(rng: &mut Rng) -> String {
        let mut s = String::new();
        match rng.below(8) {
            0..=2 => s.push('-'),
            3 => s.push('+'),
            _ => {}
        }
        if rng.below(8) == 0 {
            // Around 2^53 = 9007199254740992, with the point anywhere.
            let m = (1u64 << 53) - 3 + rng.below(7);
            let digits = m.to_string();
            let point = rng.below(digits.len() as u64 + 1) as usize;
            s.push_str(&digits[..point]);
            if point < digits.len() || rng.below(2) == 0 {
                s.push('.');
            }
            s.push_str(&digits[point..]);
            return s;
        }
        let int_len = [0, 1, 1, 1, 2, 3, 6, 10, 15, 16, 19, 20][rng.below(12) as usize];
        if rng.below(6) == 0 {
            let zeros = 1 + rng.below(8) as usize;
            s.push_str(&"0".repeat(zeros));
        }
        rng.digits(int_len, &mut s);
        if rng.below(6) != 0 {
            s.push('.');
            let frac_len = rng.below(21) as usize;
            rng.digits(frac_len, &mut s);
        }
        s
    }

    /// `parse_f64` against `str::parse::<f64>`, bit for bit.
    #[test]
    fn matches_std_bit_for_bit() {
        let mut state = crate::testing::rng(0x853c_49e6_748f_ea9b);
        for _ in 0..100_000 {
            let s = random_decimal(&mut state);
            assert_eq!(
                parse_f64(s.as_bytes()).map(f64::to_bits),
                s.parse::<f64>().ok().map(f64::to_bits),
                "{s:?}"
            );
        }
    }

    #[test]
    fn plain_decimals() {
        for s in [
            "0",
            "-0",
            "1.",
            ".5",
            "+2.25",
            "1700000000.008333",
            "-0.000004363",
            "123",
            "0.12345678",
            "0.123456789012",
            "99999999.99999999",
            "0.000000001",
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
