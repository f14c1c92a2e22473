//! The one pass skeleton: two bodies' hierarchies traversed together, then
//! every overlapping leaf pair answered (paper §3, "Collision detection"
//! and "Narrow phase").
//!
//! Every pass of a world is this loop: a character against the room, against
//! a moving object, against another character, discrete or swept over a
//! frame step. What differs is a policy, a [`Pass`]:
//!
//! 1. **traversal**: which hierarchies, which guard on the way down (the
//!    pruned methods' plane and edge planes, a swept pass's interpolated
//!    spheres), which leaves are grouped (a big triangle's division);
//! 2. **preparation** of the leaf pairs: the corners the leaf tests will
//!    read skinned (discrete), or nothing;
//! 3. **the leaf test** of each pair: the method's (triangle-triangle,
//!    Algorithm 1's plane-sphere test, or their continuous forms);
//! 4. **the hits' order**: sorted, repeats removed.
//!
//! [`run`] times the stages, counts the tests (the paper's operation model)
//! and what the pass refit and skinned, and sizes its buffers once: after
//! the first frame a pass allocates nothing.

use crate::sphere_tree::traverse::{LeafPair, TraversalStats};
use crate::sphere_tree::{PassMarks, Workspace};

use super::counters::{FrameCounters, ms_per_tick, ticks};
use super::prepared_triangles::PreparedTriangles;

/// What one traversal found and cost.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct Traversed {
    /// The traversal's own counters.
    pub(crate) stats: TraversalStats,
    /// Sphere tests a guard made besides the traversal's (a swept pass's
    /// interpolated spheres).
    pub(crate) guard_sphere_tests: u64,
    /// Plane-sphere tests a guard made on the way down.
    pub(crate) plane_tests: u64,
    /// Sphere-box tests a guard made on the way down.
    pub(crate) box_tests: u64,
    /// Time-stamp ticks spent refitting, when timed.
    pub(crate) refit_ticks: u64,
    /// Leaf tests a traversal made on the way (a ray's nearest-hit
    /// search), counted with the narrow phase's.
    pub(crate) leaf_tests: u64,
}

/// The leaf pairs of a traversal and the working memory of its tests, kept
/// from frame to frame.
#[derive(Clone, Debug, Default)]
pub(crate) struct PassScratch {
    pub(crate) workspace: Workspace,
    pub(crate) leaf_pairs: Vec<LeafPair>,
    /// The narrow phase's triangles prepared for the triangle-triangle
    /// test, one table per side.
    pub(crate) prepared: [PreparedTriangles; 2],
    warmed_up: bool,
}

impl PassScratch {
    /// The leaf pairs of the last pass, as traversal handed them over.
    pub(crate) fn leaf_pairs(&self) -> &[LeafPair] {
        &self.leaf_pairs
    }

    /// What the last pass needed: its leaf pairs and its deepest traversal
    /// stack (capacity).
    pub(crate) fn needed(&self) -> (usize, usize) {
        (self.leaf_pairs.len(), self.workspace.capacity())
    }

    /// Room for `leaf_pairs` leaf pairs and a traversal stack of `stack`;
    /// from now on sized by its owner alone (no headroom added after a
    /// first pass).
    pub(crate) fn reserve(&mut self, leaf_pairs: usize, stack: usize) {
        self.warmed_up = true;
        if self.leaf_pairs.capacity() < leaf_pairs {
            self.leaf_pairs
                .reserve_exact(leaf_pairs - self.leaf_pairs.len());
        }
        self.workspace.reserve_to(stack);
    }
}

/// A pass's marks: which (triangle, big triangle) pairs it has tested, which
/// character spheres it has descended against a big triangle (the methods
/// that test each pair once). Each pass starts them afresh, so they belong
/// to the thread running the pass, not to a character
/// (`world::marks_pool`).
#[derive(Clone, Debug, Default)]
pub(crate) struct PassMarksOf {
    /// Per character triangle, the last big triangle it was tested with.
    pub(crate) repeats: PassMarks,
    /// Per character node, the last big triangle it was descended against.
    pub(crate) groups: PassMarks,
    /// Big triangles' planes in the bind spaces of the joints that alone
    /// move the character triangles met with them.
    pub(crate) bind_planes: super::bind_planes::BindPlanes,
}

impl PassMarksOf {
    /// Room for characters of up to `triangles` triangles and `nodes` tree
    /// nodes (allocates only when it grows).
    pub(crate) fn grow_to(&mut self, triangles: usize, nodes: usize) {
        self.repeats.grow_to(triangles);
        self.groups.grow_to(nodes);
    }
}

/// A pass's policy (see the module doc).
pub(crate) trait Pass {
    /// What a colliding leaf pair gives.
    type Hit: Copy;

    /// Spheres refit and vertices skinned so far this frame by the pass's
    /// characters.
    fn work(&self) -> (u64, u64);

    /// Traverses both hierarchies, pushing the overlapping leaf pairs to
    /// `leaf_pairs` (empty on entry); with `TIMED`, counting the time-stamp
    /// ticks spent refitting ([`Pass::timed`] chooses).
    fn traverse<const TIMED: bool>(
        &mut self,
        ws: &mut Workspace,
        leaf_pairs: &mut Vec<LeafPair>,
    ) -> Traversed;

    /// Whether refit time is split from traversal time (two time-stamp
    /// reads per refit).
    fn timed(&self) -> bool {
        false
    }

    /// Whether the stages are timed (six clock reads a pass: nothing next
    /// to a contact pass, a tenth of a ray query's cost).
    fn times_stages(&self) -> bool {
        true
    }

    /// Gets ready what the leaf tests will read (timed as skinning).
    fn prepare(&mut self, _leaf_pairs: &[LeafPair]) {}

    /// Starts the narrow phase.
    fn begin_narrow(&mut self) {}

    /// The leaf test of `leaf_pairs[k]`, counted in `c`.
    fn test(
        &mut self,
        leaf_pairs: &[LeafPair],
        k: usize,
        prepared: &mut [PreparedTriangles; 2],
        c: &mut FrameCounters,
    ) -> Option<Self::Hit>;

    /// Puts the hits in their order (sorted, repeats removed).
    fn finish(hits: &mut Vec<Self::Hit>);
}

/// Sorts triangle pairs as [`slice::sort_unstable`] would, comparing each
/// pair as one 64-bit key (one comparison instead of two).
pub(crate) fn sort_pairs(hits: &mut [(u32, u32)]) {
    hits.sort_unstable_by_key(|&(a, b)| (u64::from(a) << 32) | u64::from(b));
}

/// Runs `pass`: traversal, preparation, the leaf test of every pair; fills
/// `hits` and returns what the pass cost. Refits and skinned vertices are
/// counted from the pass's start.
pub(crate) fn run<P: Pass>(
    pass: &mut P,
    scratch: &mut PassScratch,
    hits: &mut Vec<P::Hit>,
) -> FrameCounters {
    let mut c = FrameCounters::default();
    let (refits, skinned) = pass.work();
    // A hit list never used before (its slot's first pass).
    let first_use = hits.capacity() == 0;

    // Stage clocks: time-stamp counter readings, each stage's end the next
    // one's start.
    let clock = pass.times_stages();
    let now = || if clock { ticks() } else { 0 };
    let rate = if clock { ms_per_tick() } else { 0.0 };
    let ms = |from: u64, to: u64| to.saturating_sub(from) as f64 * rate;
    let t0 = now();
    scratch.leaf_pairs.clear();
    let (ws, leaf_pairs) = (&mut scratch.workspace, &mut scratch.leaf_pairs);
    let timed = pass.timed();
    let tr = if timed {
        pass.traverse::<true>(ws, leaf_pairs)
    } else {
        pass.traverse::<false>(ws, leaf_pairs)
    };
    let t1 = now();
    let elapsed = ms(t0, t1);
    if timed && clock {
        let total_ticks = t1.saturating_sub(t0).max(1);
        c.time.refit_ms = elapsed * (tr.refit_ticks as f64 / total_ticks as f64).min(1.0);
        c.time.traversal_ms = elapsed - c.time.refit_ms;
    } else {
        c.time.traversal_ms = elapsed;
    }
    c.sphere_sphere = tr.stats.sphere_tests + tr.guard_sphere_tests;
    c.plane_sphere = tr.plane_tests;
    c.sphere_box = tr.box_tests;
    c.box_box = tr.stats.box_tests;
    c.tri_tri = tr.leaf_tests;

    pass.prepare(&scratch.leaf_pairs);
    let t2 = now();
    c.time.skinning_ms = ms(t1, t2);

    hits.clear();
    pass.begin_narrow();
    let [a, b] = &mut scratch.prepared;
    a.clear();
    b.clear();
    for k in 0..scratch.leaf_pairs.len() {
        if let Some(hit) = pass.test(&scratch.leaf_pairs, k, &mut scratch.prepared, &mut c) {
            hits.push(hit);
        }
    }
    let found = hits.len();
    P::finish(hits);
    c.pairs = hits.len() as u64;
    let (refits_now, skinned_now) = pass.work();
    c.refits = refits_now - refits;
    c.skinned_vertices = skinned_now - skinned;
    // After the first frame, room for twice its work, so that later frames
    // of a similar pose do not grow the buffers (a pooled scratch is sized
    // by its pool instead, `world::pass_pool`; a hit list on its first
    // use).
    if !scratch.warmed_up {
        scratch.warmed_up = true;
        let n = scratch.leaf_pairs.len();
        scratch.leaf_pairs.reserve(n.max(64));
        scratch.workspace.reserve_headroom();
    }
    if first_use {
        hits.reserve((2 * found).max(64));
    }
    c.time.narrow_ms = ms(t2, now());
    c
}
