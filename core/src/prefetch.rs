//! Cache prefetch hints.
//!
//! A frame's data is cold when the frame starts: the engine's other work
//! (skinning, rendering, another library, the other methods of a `bench`
//! run) has evicted it, and each node, rule, mark or vertex a frame reads
//! first comes from memory. Where the next reads are known a few steps
//! ahead (the children of a pair just pushed), asking for them early lets
//! their loads overlap (`docs/performance-journal.md`, "Cold caches and a
//! wider character tree"; the room pass's hints for the leaf pairs ahead
//! were taken out once most of its pairs were answered from bind corners:
//! "Room triangles answered from bind corners").

/// Starts loading the cache line of `p` (a hint; nothing on other
/// architectures).
#[inline(always)]
pub fn prefetch<T>(p: *const T) {
    #[cfg(target_arch = "x86_64")]
    // SAFETY: a prefetch is a hint that never faults, whatever the address.
    #[allow(unused_unsafe)]
    unsafe {
        use std::arch::x86_64::{_MM_HINT_T0, _mm_prefetch};
        _mm_prefetch::<_MM_HINT_T0>(p as *const i8);
    }
    #[cfg(not(target_arch = "x86_64"))]
    let _ = p;
}

/// Starts loading `slice[i]`'s cache line (a hint: an index out of bounds
/// loads nothing useful and does no harm).
#[inline(always)]
pub fn prefetch_at<T>(slice: &[T], i: usize) {
    prefetch(slice.as_ptr().wrapping_add(i));
}
