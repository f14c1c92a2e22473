//! What a pass costs: tests by kind (the paper's operation model, §6),
//! refits, skinned vertices, pairs, and milliseconds per stage.

use std::sync::OnceLock;
use std::sync::atomic::{AtomicU64, Ordering};
use std::time::Instant;

use crate::geometry::ops;

/// What one pass, or a sum of passes, cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FrameCounters {
    /// Sphere-sphere tests (10 operations each).
    pub sphere_sphere: u64,
    /// Triangle-triangle tests (96 operations each).
    pub tri_tri: u64,
    /// Plane-sphere tests (30 operations each).
    pub plane_sphere: u64,
    /// Sphere-box tests against a room's node boxes (34 operations each;
    /// ours, [`crate::geometry::sphere_box`]).
    pub sphere_box: u64,
    /// Box-box tests between two characters' posed node boxes, after their
    /// spheres met (30 operations each; ours,
    /// [`crate::geometry::leveled_box`]).
    pub box_box: u64,
    /// Character spheres refit.
    pub refits: u64,
    /// Distinct colliding pairs.
    pub pairs: u64,
    /// Character vertices skinned (corners of triangle-tested character
    /// triangles).
    pub skinned_vertices: u64,
    /// Milliseconds per stage.
    pub time: FrameTime,
}

/// Milliseconds spent per stage.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FrameTime {
    /// Joint matrices: clip sampling, world and skin matrices, placement (set
    /// by the caller, who poses once for every method).
    pub pose_ms: f64,
    /// The vertices the narrow phase reads.
    pub skinning_ms: f64,
    /// Character spheres refit (when timed apart from traversal).
    pub refit_ms: f64,
    /// Traversal of both trees.
    pub traversal_ms: f64,
    /// The leaf tests.
    pub narrow_ms: f64,
}

impl FrameTime {
    /// The sum of every stage.
    pub fn total_ms(&self) -> f64 {
        self.pose_ms + self.skinning_ms + self.refit_ms + self.traversal_ms + self.narrow_ms
    }
}

impl FrameCounters {
    /// Basic operations in the paper's model: `10·SS + 96·TT + 30·PS` (§6),
    /// plus our sphere-box tests' `34·SB` and box-box tests' `30·BB`.
    ///
    /// ```
    /// use cornertree::pipeline::FrameCounters;
    ///
    /// let c = FrameCounters { sphere_sphere: 200_000, tri_tri: 150_000, ..Default::default() };
    /// assert_eq!(c.operations(), 200_000 * 10 + 150_000 * 96);
    /// ```
    pub fn operations(&self) -> u64 {
        ops::SPHERE_SPHERE * self.sphere_sphere
            + ops::TRI_TRI * self.tri_tri
            + ops::PLANE_SPHERE * self.plane_sphere
            + ops::SPHERE_BOX * self.sphere_box
            + ops::BOX_BOX * self.box_box
    }

    /// Adds `b`'s tests, pairs, refits, skinned vertices and times.
    pub fn add(&mut self, b: &FrameCounters) {
        self.sphere_sphere += b.sphere_sphere;
        self.tri_tri += b.tri_tri;
        self.plane_sphere += b.plane_sphere;
        self.sphere_box += b.sphere_box;
        self.box_box += b.box_box;
        self.refits += b.refits;
        self.pairs += b.pairs;
        self.skinned_vertices += b.skinned_vertices;
        self.time.pose_ms += b.time.pose_ms;
        self.time.skinning_ms += b.time.skinning_ms;
        self.time.refit_ms += b.time.refit_ms;
        self.time.traversal_ms += b.time.traversal_ms;
        self.time.narrow_ms += b.time.narrow_ms;
    }
}

/// Milliseconds since `t0`, a [`ticks`] reading (0 should the counter
/// read lower than `t0`, as it could on a machine whose cores' counters
/// are not kept in step).
#[inline]
pub(crate) fn ms_since(t0: u64) -> f64 {
    ticks().saturating_sub(t0) as f64 * ms_per_tick()
}

/// Milliseconds a [`ticks`] unit lasts: measured against the system's
/// monotonic clock over the first 0.2 ms of its first use (a one-time
/// wait), then over all the time since, each time [`refine_tick_rate`] is
/// called. A pass reads the clock four to eight times; the time-stamp
/// counter is read in a few nanoseconds where `Instant::now` takes about
/// 23 ns here, a few per cent of a thousand-character frame of short passes
/// (docs/performance-journal.md, "Deep contact's narrow phase").
#[inline]
pub(crate) fn ms_per_tick() -> f64 {
    f64::from_bits(TICK_MS.load(Ordering::Relaxed)).max(tick_origin().2)
}

/// Measures [`ms_per_tick`] again over the time since the first use
/// (a step calls it once).
pub(crate) fn refine_tick_rate() {
    let (t0, k0, _) = *tick_origin();
    let (ms, k) = (t0.elapsed().as_secs_f64() * 1e3, ticks().saturating_sub(k0));
    if ms > 1.0 && k > 0 {
        TICK_MS.store((ms / k as f64).to_bits(), Ordering::Relaxed);
    }
}

/// The latest [`ms_per_tick`] measured over more than a millisecond (bits
/// of an `f64`; 0 before).
static TICK_MS: AtomicU64 = AtomicU64::new(0);

/// The clocks' first reading, and the rate measured over the first 0.2 ms.
fn tick_origin() -> &'static (Instant, u64, f64) {
    static ORIGIN: OnceLock<(Instant, u64, f64)> = OnceLock::new();
    ORIGIN.get_or_init(|| {
        let (t0, k0) = (Instant::now(), ticks());
        let mut ms = 0.0;
        while ms < 0.2 {
            ms = t0.elapsed().as_secs_f64() * 1e3;
        }
        let k = ticks().saturating_sub(k0).max(1);
        (t0, k0, ms / k as f64)
    })
}

/// The CPU's time-stamp counter (x86_64), or nanoseconds elsewhere: what
/// the refit timers of a traversal count.
#[inline]
pub(crate) fn ticks() -> u64 {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: RDTSC has no preconditions on x86_64.
        unsafe { std::arch::x86_64::_rdtsc() }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        static START: OnceLock<Instant> = OnceLock::new();
        START.get_or_init(Instant::now).elapsed().as_nanos() as u64
    }
}
