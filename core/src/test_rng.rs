//! A small deterministic generator for the unit tests (xorshift64).

/// Uniform `f32` values in `[0, 1)`, a fixed stream for each `seed` (made
/// odd, so never the generator's stuck zero state).
pub(crate) fn unit_floats(seed: u64) -> impl FnMut() -> f32 {
    let mut x = seed | 1;
    move || {
        x ^= x << 13;
        x ^= x >> 7;
        x ^= x << 17;
        (x >> 40) as f32 / (1u64 << 24) as f32
    }
}
