//! Simultaneous traversal of two sphere trees (paper §3, "Collision detection").
//!
//! Pairs of overlapping spheres are kept on an explicit stack held in a
//! reusable [`Workspace`], so a query allocates nothing once the stack has
//! grown to its working size. At a pair of inner nodes the one with the larger
//! radius is opened (ties open `a`); a leaf is never opened. Every sphere-sphere
//! test is counted and reported to both hierarchies ([`Hierarchy::tested`]);
//! pairs of overlapping leaves go to the narrow-phase callback.

use crate::geometry::Sphere;
use crate::geometry::leveled_box::{LeveledBox, leveled_boxes_meet};
use crate::prefetch::prefetch_at;

use super::node::{Node, NodeId, SphereTree};
use super::pass_marks::PassMarks;

/// A sphere tree as traversal sees it: fixed topology, and each node's sphere
/// for the current frame. A refitting hierarchy computes a sphere the first time
/// it is asked for it in a frame (on demand, §3 "Sphere update").
pub trait Hierarchy {
    /// The tree whose topology is walked.
    fn tree(&self) -> &SphereTree;
    /// Node `id`'s sphere for the current frame (a refitting hierarchy
    /// computes it on the first request).
    fn sphere(&mut self, id: NodeId) -> Sphere;
    /// Called once for every sphere-sphere test node `id`'s sphere takes part
    /// in, the root pair's included (a visit log; by default nothing, which
    /// compiles to nothing).
    #[inline]
    fn tested(&mut self, _id: NodeId) {}
    /// Asks the processor to start loading what [`Hierarchy::sphere`] will
    /// read for `id` (a hint: by default the node itself).
    #[inline]
    fn prefetch(&self, id: NodeId) {
        prefetch_at(self.tree().nodes(), id.index());
    }
    /// Time-stamp ticks spent refitting spheres so far, for a hierarchy
    /// that refits and times it (by default none).
    #[inline]
    fn refit_ticks(&self) -> u64 {
        0
    }
    /// Whether the nodes carry boxes ([`Hierarchy::node_box`]): where both
    /// hierarchies do, a pair whose spheres meet is dropped if their boxes
    /// do not.
    const BOXES: bool = false;
    /// Node `id`'s box this frame, in levels around its sphere (asked only
    /// after [`Hierarchy::sphere`] for `id`); by default the whole cube.
    #[inline]
    fn node_box(&mut self, _id: NodeId) -> LeveledBox {
        LeveledBox::CUBE
    }
    /// Whether this hierarchy's nodes have boxes now (with
    /// [`Hierarchy::BOXES`]: a tree whose rule keeps them).
    #[inline]
    fn has_boxes(&self) -> bool {
        Self::BOXES
    }
    /// Like [`Hierarchy::prefetch`] for what [`Hierarchy::node_box`] reads.
    #[inline]
    fn prefetch_box(&self, _id: NodeId) {}
}

impl Hierarchy for SphereTree {
    #[inline]
    fn tree(&self) -> &SphereTree {
        self
    }
    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.nodes[id.index()].sphere
    }
}

/// A pair of nodes waiting to be opened, with the spheres it was tested
/// with (so opening it asks neither hierarchy for them again: a sphere is
/// the same all pass long, and asking costs a refit check, a frame change
/// or a sweep).
#[derive(Clone, Copy, Debug)]
pub(super) struct Pending {
    pair: (NodeId, NodeId),
    spheres: (Sphere, Sphere),
}

/// Scratch space kept between queries.
#[derive(Clone, Debug, Default)]
pub struct Workspace {
    pub(super) stack: Vec<Pending>,
    /// Each stacked pair's key, for an ordered traversal ([`Order`]) only.
    keys: Vec<f32>,
    /// The nodes still to walk of a tree traversed against itself
    /// ([`super::self_traverse`]).
    pub(super) nodes: Vec<NodeId>,
}

impl Workspace {
    /// An empty workspace; its stack grows on the first queries.
    pub fn new() -> Self {
        Self::default()
    }

    /// Current stack capacity (for allocation tests): the smaller of the
    /// stack's and, once an ordered traversal has used them, its keys'.
    pub fn capacity(&self) -> usize {
        match self.keys.capacity() {
            0 => self.stack.capacity(),
            k => k.min(self.stack.capacity()),
        }
    }

    /// Makes room for a stack of `n` entries (and their keys, once an
    /// ordered traversal has used them).
    pub fn reserve_to(&mut self, n: usize) {
        if self.stack.capacity() < n {
            self.stack.reserve_exact(n - self.stack.len());
        }
        if self.keys.capacity() > 0 && self.keys.capacity() < n {
            self.keys.reserve_exact(n - self.keys.len());
        }
    }

    /// Makes room for twice the deepest stack seen so far.
    pub fn reserve_headroom(&mut self) {
        let nodes = 2 * self.nodes.capacity();
        self.nodes.reserve(nodes.saturating_sub(self.nodes.len()));
        let want = 2 * self.stack.capacity();
        self.stack.reserve(want.saturating_sub(self.stack.len()));
        if self.keys.capacity() > 0 {
            self.keys.reserve(want.saturating_sub(self.keys.len()));
        }
    }
}

/// Counters of one traversal.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct TraversalStats {
    /// Sphere-sphere tests made (10 operations each in the paper's model).
    pub sphere_tests: u64,
    /// Overlapping leaf pairs handed to the narrow phase.
    pub leaf_pairs: u64,
    /// Box-box tests made, after a sphere test passed, where both
    /// hierarchies carry boxes ([`Hierarchy::BOXES`]).
    pub box_tests: u64,
    /// Deepest the stack went.
    pub max_stack: usize,
}

/// Two overlapping leaves.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub struct LeafPair {
    /// The leaf of the first tree (`a`).
    pub leaf_a: NodeId,
    /// The leaf of the second tree (`b`).
    pub leaf_b: NodeId,
    /// The primitive `leaf_a` bounds (a triangle index of `a`'s mesh).
    pub primitive_a: u32,
    /// The primitive `leaf_b` bounds (a triangle index of `b`'s mesh).
    pub primitive_b: u32,
}

/// Walks `a` and `b` together from their roots; calls `on_leaf_pair` for every
/// pair of overlapping leaves reached. Empty trees give no tests.
pub fn traverse<A, B, F>(
    a: &mut A,
    b: &mut B,
    ws: &mut Workspace,
    on_leaf_pair: F,
) -> TraversalStats
where
    A: Hierarchy + ?Sized,
    B: Hierarchy + ?Sized,
    F: FnMut(LeafPair),
{
    traverse_guarded(a, b, ws, |_, _| true, on_leaf_pair)
}

/// [`traverse`] with a `guard` on every pair pushed besides the sphere test:
/// `guard(j, s)` for a node `j` of `b` and the sphere `s` of the `a` node
/// paired with it; a pair is kept only if the guard says so. The guard is
/// asked after the sphere test passes, once per pair pushed (not for the
/// root pair).
pub fn traverse_guarded<A, B, G, F>(
    a: &mut A,
    b: &mut B,
    ws: &mut Workspace,
    guard: G,
    on_leaf_pair: F,
) -> TraversalStats
where
    A: Hierarchy + ?Sized,
    B: Hierarchy + ?Sized,
    G: FnMut(NodeId, &crate::geometry::Sphere) -> bool,
    F: FnMut(LeafPair),
{
    traverse_ordered(a, b, ws, &AsTested, guard, on_leaf_pair)
}

/// Both roots: where a traversal of two whole trees starts.
pub(crate) const ROOTS: (NodeId, NodeId) = (NodeId::ROOT, NodeId::ROOT);

/// The order in which a traversal opens the pairs pushed at one node, and
/// whether a pair is still worth opening when its turn comes: a ray's
/// nearest hit wants the spheres nearest its origin first, and a sphere
/// beyond the best hit found since it was pushed dropped unopened (so its
/// children are never refit). Only the order of the work changes, and the
/// pairs dropped are the ones `keep` rules out.
pub trait Order {
    /// Whether pairs are ordered at all (`false`: popped in the order they
    /// were tested, last first, and no key kept).
    const ORDERED: bool;
    /// The key of a pair whose `a` node has sphere `s`: smaller keys are
    /// opened first. Computed before the guard is asked (for a child of
    /// `a`, once it passes the sphere test; for the children of `b`, once
    /// for all of them): an order may rule a pair out here (a key `keep`
    /// refuses) and so spare the guard its own test.
    fn key(&self, s: &Sphere) -> f32;
    /// Whether a pair with `key` is still to be opened: asked before the
    /// pair is pushed and again when it is popped. Once `false` for a key,
    /// it must stay `false` for the rest of the traversal.
    fn keep(&self, key: f32) -> bool;
}

/// No order: the pairs of a node are opened last tested first, all of them.
pub struct AsTested;

impl Order for AsTested {
    const ORDERED: bool = false;
    #[inline(always)]
    fn key(&self, _: &Sphere) -> f32 {
        0.0
    }
    #[inline(always)]
    fn keep(&self, _: f32) -> bool {
        true
    }
}

/// [`traverse_guarded`] opening the pairs pushed at each node in `order`.
pub fn traverse_ordered<A, B, O, G, F>(
    a: &mut A,
    b: &mut B,
    ws: &mut Workspace,
    order: &O,
    guard: G,
    on_leaf_pair: F,
) -> TraversalStats
where
    A: Hierarchy + ?Sized,
    B: Hierarchy + ?Sized,
    O: Order,
    G: FnMut(NodeId, &crate::geometry::Sphere) -> bool,
    F: FnMut(LeafPair),
{
    let mut guard = guard;
    traverse_core(
        a,
        b,
        ws,
        ROOTS,
        None,
        |_| None,
        order,
        |_, j, s| guard(j, s),
        on_leaf_pair,
    )
}

/// Sorts the pairs stacked from `from` on by key, largest first (so the
/// smallest is popped first): a node's few children, by insertion.
#[inline]
fn sort_pushed(ws: &mut Workspace, from: usize) {
    for k in from + 1..ws.stack.len() {
        let (key, pair) = (ws.keys[k], ws.stack[k]);
        let mut m = k;
        while m > from && ws.keys[m - 1] < key {
            ws.keys[m] = ws.keys[m - 1];
            ws.stack[m] = ws.stack[m - 1];
            m -= 1;
        }
        ws.keys[m] = key;
        ws.stack[m] = pair;
    }
}

/// The traversal behind [`traverse_guarded`],
/// [`super::grouped::traverse_grouped`] and
/// [`super::self_traverse::traverse_self`], from the pair `start` (node
/// `start.0` of `a`, `start.1` of `b`; [`ROOTS`] for two whole trees): a
/// leaf `j` of `b` for which `group(j)` names a group is met by the group's
/// sphere, and `a`'s leaves and twigs' leaves under it go to
/// `on_leaf_pair` without a sphere of their own (see [`super::grouped`]);
/// with `marks`, each sphere of `a` is descended once per group.
/// `guard(i, j, s)` is asked of every pair `(i, j)` pushed, with `s` the
/// sphere of `i`.
#[allow(clippy::too_many_arguments)]
pub(super) fn traverse_core<A, B, K, O, G, F>(
    a: &mut A,
    b: &mut B,
    ws: &mut Workspace,
    start: (NodeId, NodeId),
    mut marks: Option<&mut PassMarks>,
    mut group: K,
    order: &O,
    mut guard: G,
    mut on_leaf_pair: F,
) -> TraversalStats
where
    A: Hierarchy + ?Sized,
    B: Hierarchy + ?Sized,
    K: FnMut(NodeId) -> Option<(u32, Sphere)>,
    O: Order,
    G: FnMut(NodeId, NodeId, &Sphere) -> bool,
    F: FnMut(LeafPair),
{
    let mut stats = TraversalStats::default();
    if a.tree().is_empty() || b.tree().is_empty() {
        return stats;
    }
    if let Some(m) = marks.as_deref_mut() {
        m.begin_pass();
    }
    ws.stack.clear();
    ws.keys.clear();
    // Pairs met by their boxes too, where both sides keep boxes.
    let boxes = A::BOXES && B::BOXES && a.has_boxes() && b.has_boxes();
    stats.sphere_tests += 1;
    a.tested(start.0);
    b.tested(start.1);
    let spheres = (a.sphere(start.0), b.sphere(start.1));
    if spheres.0.overlaps(&spheres.1) {
        ws.stack.push(Pending {
            pair: start,
            spheres,
        });
        if O::ORDERED {
            ws.keys.push(f32::NEG_INFINITY);
        }
    }
    while let Some(Pending {
        pair: (i, j),
        spheres: (sa, sb),
    }) = ws.stack.pop()
    {
        if O::ORDERED && !order.keep(ws.keys.pop().unwrap_or(f32::NEG_INFINITY)) {
            continue;
        }
        let na: Node = *a.tree().node(i);
        let nb: Node = *b.tree().node(j);
        let grouped = if nb.is_leaf() {
            match group(j) {
                Some((g, _)) if marks.as_deref_mut().is_some_and(|m| !m.first_time(i.0, g)) => {
                    continue;
                }
                found => found,
            }
        } else {
            None
        };
        match (na.primitive(), nb.primitive()) {
            (Some(pa), Some(pb)) => {
                stats.leaf_pairs += 1;
                on_leaf_pair(LeafPair {
                    leaf_a: i,
                    leaf_b: j,
                    primitive_a: pa,
                    primitive_b: pb,
                });
            }
            _ => {
                // A group's leaf is met by the group's sphere.
                let sb = grouped.map_or(sb, |(_, s)| s);
                let open_a = nb.is_leaf() || (!na.is_leaf() && sa.radius >= sb.radius);
                let pushed_from = ws.stack.len();
                if open_a {
                    // A group's leaf lets `a`'s leaves and its twigs' leaves
                    // through unrefit (see `super::grouped`): no sphere, no
                    // test, no guard, and no mark (a leaf reached again for
                    // the group by another path meets the caller's repeat
                    // filter).
                    let through = grouped.and(nb.primitive());
                    for c in na.children() {
                        if let Some(pb) = through
                            && let Some(leaves) = leaves_let_through(a.tree(), NodeId(c))
                        {
                            for g in leaves {
                                if let Some(pa) = a.tree().node(NodeId(g)).primitive() {
                                    stats.leaf_pairs += 1;
                                    on_leaf_pair(LeafPair {
                                        leaf_a: NodeId(g),
                                        leaf_b: j,
                                        primitive_a: pa,
                                        primitive_b: pb,
                                    });
                                }
                            }
                            continue;
                        }
                        stats.sphere_tests += 1;
                        a.tested(NodeId(c));
                        b.tested(j);
                        let sc = a.sphere(NodeId(c));
                        if !sc.overlaps(&sb) {
                            continue;
                        }
                        if boxes {
                            stats.box_tests += 1;
                            if !leveled_boxes_meet(&a.node_box(NodeId(c)), &sc, &b.node_box(j), &sb)
                            {
                                continue;
                            }
                        }
                        let key = if O::ORDERED { order.key(&sc) } else { 0.0 };
                        if (!O::ORDERED || order.keep(key)) && guard(NodeId(c), j, &sc) {
                            ws.stack.push(Pending {
                                pair: (NodeId(c), j),
                                spheres: (sc, sb),
                            });
                            if O::ORDERED {
                                ws.keys.push(key);
                            }
                            prefetch_next(a, b, &marks, boxes, NodeId(c), j, sc.radius, sb.radius);
                        }
                    }
                } else {
                    // The pairs' `a` sphere is `sa` for every child.
                    let key = if O::ORDERED { order.key(&sa) } else { 0.0 };
                    for c in nb.children() {
                        stats.sphere_tests += 1;
                        a.tested(i);
                        b.tested(NodeId(c));
                        let sc = b.sphere(NodeId(c));
                        if sa.overlaps(&sc)
                            && (!boxes || {
                                stats.box_tests += 1;
                                leveled_boxes_meet(&a.node_box(i), &sa, &b.node_box(NodeId(c)), &sc)
                            })
                            && (!O::ORDERED || order.keep(key))
                            && guard(i, NodeId(c), &sa)
                        {
                            ws.stack.push(Pending {
                                pair: (i, NodeId(c)),
                                spheres: (sa, sc),
                            });
                            if O::ORDERED {
                                ws.keys.push(key);
                            }
                            prefetch_next(a, b, &marks, boxes, i, NodeId(c), sa.radius, sc.radius);
                        }
                    }
                }
                if O::ORDERED {
                    sort_pushed(ws, pushed_from);
                }
                stats.max_stack = stats.max_stack.max(ws.stack.len());
            }
        }
    }
    stats
}

/// The leaves node `id` hands on unrefit to a group's leaf: itself if it
/// is a leaf, its children if they all are (a twig); `None` otherwise.
#[inline]
fn leaves_let_through(tree: &SphereTree, id: NodeId) -> Option<std::ops::Range<u32>> {
    let n = tree.node(id);
    if n.is_leaf() {
        return Some(id.0..id.0 + 1);
    }
    n.is_twig().then(|| n.children())
}

/// For the pair `(i, j)` just pushed, with sphere radii `ra`, `rb`: prefetches
/// the children traversal will test when it pops the pair (the side it will
/// open, by the rule of [`traverse_guarded`]), their rest boxes where
/// `boxes` (both sides keep them), and `i`'s mark if the pop will look it
/// up (`j` a leaf, with marks).
#[inline(always)]
#[allow(clippy::too_many_arguments)]
fn prefetch_next<A, B>(
    a: &A,
    b: &B,
    marks: &Option<&mut PassMarks>,
    boxes: bool,
    i: NodeId,
    j: NodeId,
    ra: f32,
    rb: f32,
) where
    A: Hierarchy + ?Sized,
    B: Hierarchy + ?Sized,
{
    let (na, nb) = (a.tree().node(i), b.tree().node(j));
    let marks = marks.as_deref().filter(|_| nb.is_leaf());
    if let Some(m) = marks {
        m.prefetch(i.0);
    }
    if nb.is_leaf() || (!na.is_leaf() && ra >= rb) {
        for c in na.children() {
            a.prefetch(NodeId(c));
            if boxes {
                a.prefetch_box(NodeId(c));
            }
        }
        // The children's pairs with the leaf `j` will look their marks up
        // when popped, right after being pushed: too soon to load them then.
        if let (Some(m), Some(last)) = (marks, na.children().last()) {
            m.prefetch(na.children().start);
            m.prefetch(last);
        }
    } else {
        for c in nb.children() {
            b.prefetch(NodeId(c));
            if boxes {
                b.prefetch_box(NodeId(c));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use super::{Order, Workspace, traverse, traverse_ordered};
    use crate::geometry::Sphere;
    use crate::mesh::TriangleId;
    use crate::sphere_tree::grouped::tests::{soup, tree};

    /// Nodes by the least `x` of their sphere; those whose least `x` is
    /// beyond `limit` dropped.
    struct LeftFirst {
        limit: f32,
    }

    impl Order for LeftFirst {
        const ORDERED: bool = true;
        fn key(&self, s: &Sphere) -> f32 {
            s.center.x - s.radius
        }
        fn keep(&self, key: f32) -> bool {
            key <= self.limit
        }
    }

    /// Ordered, dropping nothing: the pairs and tests of plain traversal.
    /// Dropping nodes beyond a limit: exactly the plain pairs whose `a`
    /// triangle reaches below it are kept (a node's sphere holds its
    /// subtree's triangles), and fewer tests are made.
    #[test]
    fn ordering_changes_the_order_only_and_dropping_keeps_what_it_must() {
        for seed in 0..30u64 {
            let (ma, mb) = (soup(seed, 70, 1.0, 0.2), soup(seed + 500, 50, 1.0, 0.3));
            let (mut ta, mut tb) = (tree(&ma), tree(&mb));
            let mut ws = Workspace::new();
            let mut plain = BTreeSet::new();
            let plain_stats = traverse(&mut ta, &mut tb, &mut ws, |p| {
                plain.insert((p.primitive_a, p.primitive_b));
            });
            let every = LeftFirst {
                limit: f32::INFINITY,
            };
            let mut ordered = BTreeSet::new();
            let stats = traverse_ordered(
                &mut ta,
                &mut tb,
                &mut ws,
                &every,
                |_, _| true,
                |p| {
                    ordered.insert((p.primitive_a, p.primitive_b));
                },
            );
            assert_eq!(plain, ordered, "seed {seed}");
            assert_eq!(plain_stats.sphere_tests, stats.sphere_tests, "seed {seed}");

            let limit = 0.3;
            let mut kept = BTreeSet::new();
            let cut = traverse_ordered(
                &mut ta,
                &mut tb,
                &mut ws,
                &LeftFirst { limit },
                |_, _| true,
                |p| {
                    kept.insert((p.primitive_a, p.primitive_b));
                },
            );
            let left_of_limit = |t: u32| {
                let tri = ma.triangle(TriangleId(t));
                [tri.a, tri.b, tri.c].iter().any(|p| p.x <= limit)
            };
            for &(a, b) in &plain {
                if left_of_limit(a) {
                    assert!(kept.contains(&(a, b)), "seed {seed}: ({a}, {b}) dropped");
                }
            }
            assert!(kept.is_subset(&plain), "seed {seed}");
            assert!(cut.sphere_tests <= plain_stats.sphere_tests, "seed {seed}");
        }
    }
}
