//! Robustness: random and mutated input never panics, and whatever is accepted is sane.

use super::{Format, PoseReader};
use std::io::BufReader;

/// xorshift64*: deterministic test randomness.
fn next(state: &mut u64) -> u64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    state.wrapping_mul(0x2545_f491_4f6c_dd1d)
}

#[test]
fn random_input_never_panics() {
    let alphabet: &[u8] = b"0123456789012345678901234567890123456789 . . - + e E \t , , # \n\n\n\r\"qxtimez\xff\xef\xbb";
    let valid = b"t,x,y,z,qx,qy,qz,qw\n1,0,0,0,0,0,0,1\n2 0 0 0 0 0 0 1\n3,1,2,3,0.5,0.5,0.5,0.5\n";
    let mut s = 7u64;
    let pick = |s: &mut u64| alphabet[(next(s) % alphabet.len() as u64) as usize];
    for round in 0..3000 {
        let mut bytes: Vec<u8> = if round % 2 == 0 {
            (0..next(&mut s) % 300).map(|_| pick(&mut s)).collect()
        } else {
            valid.to_vec()
        };
        for _ in 0..next(&mut s) % 6 {
            let i = (next(&mut s) % (bytes.len() as u64 + 1)) as usize;
            let b = pick(&mut s);
            if i < bytes.len() && next(&mut s) & 1 == 0 {
                bytes[i] = b;
            } else {
                bytes.insert(i, b);
            }
        }
        for format in [Some(Format::Tum), Some(Format::Csv), None] {
            let cap = 1 + (next(&mut s) % 64) as usize;
            let src = BufReader::with_capacity(cap, &bytes[..]);
            let r = match format {
                Some(f) => PoseReader::new(src, "r".into(), f),
                None => PoseReader::detecting(src, "r".into()),
            };
            let mut prev = f64::NEG_INFINITY;
            for p in r.take(1000).flatten() {
                assert!(p.t.is_finite() && p.t > prev);
                assert!((p.pose.rotation.norm() - 1.0).abs() < 1e-12);
                prev = p.t;
            }
        }
    }
}
