//! Deterministic randomness for the crate's unit tests: `rand`'s `StdRng`, seeded.

use rand::{rngs::StdRng, Rng, SeedableRng};

/// A generator seeded with `seed`.
pub(crate) fn rng(seed: u64) -> StdRng {
    StdRng::seed_from_u64(seed)
}

/// The next pseudo-random number of `r`.
pub(crate) fn next(r: &mut StdRng) -> u64 {
    r.random()
}
