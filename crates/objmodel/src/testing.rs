//! Deterministic randomness for `format`'s test generators, which copy and replay their
//! generator state (a `u64`); the other unit tests take theirs from `rand`.

/// xorshift64*: the next pseudo-random number of the stream `state` (any non-zero seed).
pub(crate) fn next(state: &mut u64) -> u64 {
    *state ^= *state >> 12;
    *state ^= *state << 25;
    *state ^= *state >> 27;
    state.wrapping_mul(0x2545_f491_4f6c_dd1d)
}
