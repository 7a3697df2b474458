//! Deterministic randomness for the crate's unit tests (one generator for all of them).

/// xorshift64*: the next pseudo-random number of the stream `state` (any non-zero seed).
pub(crate) fn next(state: &mut u64) -> u64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    state.wrapping_mul(0x2545_f491_4f6c_dd1d)
}

/// A pseudo-random number uniform in [0, 1), from the top 53 bits of [`next`].
pub(crate) fn unit(state: &mut u64) -> f64 {
    (next(state) >> 11) as f64 / (1u64 << 53) as f64
}
