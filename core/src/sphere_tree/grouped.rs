//! Traversal that descends each sphere of `a` once per *group* of `b`'s
//! leaves (the leaves of one big triangle's division, for example).
//!
//! In a big triangle's corner-tree many small leaves sit along its edges and
//! corners (§5), and every leaf names the same big triangle. A character
//! sphere overlapping `k` of those leaves is descended `k` times by
//! [`traverse_guarded`](super::traverse_guarded), with the same plane tests
//! each time, for leaf pairs that all end in the same triangle tests. Here,
//! the first time a sphere of `a` is paired with a leaf of group `g`, its
//! children are tested against the sphere of the whole group (which holds
//! every leaf of it) instead of that one leaf's, and the sphere is marked;
//! a later pair of the same sphere with another leaf of `g` is dropped. The
//! marked descent reaches every leaf of `a` the dropped pairs could have
//! reached, so no pair of primitives is lost; some may be reached twice (a
//! sphere first descended through an inner node of the group and again
//! through an ancestor), which the caller's repeat filter absorbs.
//!
//! **Leaves let through.** When a sphere of `a` paired with a group's leaf
//! is opened, its children that are leaves are handed on as leaf pairs
//! without a sphere, a test or the guard: the caller's exact test of the
//! leaf's primitive against the group's (the big triangle) answers for
//! them. Their spheres would be refit only to be tested against the
//! group's plane and edge planes, and in a character pressed into a wall
//! that refit costs more than the triangle tests it spares: 15 cm into
//! the living room's wall, 3,553 refits and 998 triangle tests a frame
//! became 1,742 and 1,758, and the frame 0.40 ms → 0.31 ms
//! (docs/performance-journal.md, "Leaves let through at big triangles").
//! A leaf of `a` may meet a leaf of the group no sphere test would have
//! paired it with; the exact test answers no, so no pair is added.
//!
//! **Twigs too.** A child that is a twig (a node whose children are all
//! leaves) hands its leaves on the same way, unrefit itself: once the
//! caller answers most such leaves from the big triangle's plane and edge
//! planes before preparing the character triangle (`pipeline::rigid_pass`),
//! a leaf costs less than the twig's refit and its plane and edge-plane
//! tests. 15 cm into the wall, refits 1,702 → 812 and triangle tests
//! 1,727 → 2,756 a frame (docs/performance-journal.md, "Twigs let through,
//! and a big triangle's answers before the test").

use super::node::NodeId;
use super::pass_marks::PassMarks;
use super::traverse::{
    AsTested, Hierarchy, LeafPair, ROOTS, TraversalStats, Workspace, traverse_core,
};
use crate::geometry::Sphere;

/// [`traverse_guarded`](super::traverse_guarded) where `group(j)` gives, for
/// a leaf `j` of `b` that belongs to a group, the group's index and a sphere
/// holding all of its leaves' primitives (see the module doc). `marks`
/// drops a sphere's later pairs with a group's other leaves; without them
/// (`None`: for groups of one leaf each, where no pair can come twice)
/// every pair is descended.
pub fn traverse_grouped<A, B, K, G, F>(
    a: &mut A,
    b: &mut B,
    ws: &mut Workspace,
    marks: Option<&mut PassMarks>,
    group: K,
    guard: G,
    on_leaf_pair: F,
) -> TraversalStats
where
    A: Hierarchy + ?Sized,
    B: Hierarchy + ?Sized,
    K: FnMut(NodeId) -> Option<(u32, Sphere)>,
    G: FnMut(NodeId, &Sphere) -> bool,
    F: FnMut(LeafPair),
{
    let mut guard = guard;
    traverse_core(
        a,
        b,
        ws,
        ROOTS,
        marks,
        group,
        &AsTested,
        |_, j, s| guard(j, s),
        on_leaf_pair,
    )
}

#[cfg(test)]
pub(super) mod tests {
    use std::cell::Cell;
    use std::collections::BTreeSet;

    use super::traverse_grouped;
    use crate::geometry::enclosing::points_sphere;
    use crate::geometry::{Point, Sphere};
    use crate::mesh::{TriMesh, TriangleId};
    use crate::sphere_tree::PassMarks;
    use crate::sphere_tree::{
        BuildParams, Hierarchy, NodeId, SphereTree, Workspace, build_tree, traverse,
    };

    /// `n` random triangles of about `size` in a cube of side `spread`.
    pub(in crate::sphere_tree) fn soup(seed: u64, n: usize, spread: f32, size: f32) -> TriMesh {
        let mut next = crate::test_rng::unit_floats(seed.wrapping_mul(0x9e37_79b9_7f4a_7c15));
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        for t in 0..n as u32 {
            let c = [spread * next(), spread * next(), spread * next()];
            for _ in 0..3 {
                positions.push(Point::new(
                    c[0] + size * (next() - 0.5),
                    c[1] + size * (next() - 0.5),
                    c[2] + size * (next() - 0.5),
                ));
            }
            triangles.push([3 * t, 3 * t + 1, 3 * t + 2]);
        }
        TriMesh::new(positions, triangles).unwrap()
    }

    /// A tree over every triangle of `mesh`.
    pub(in crate::sphere_tree) fn tree(mesh: &TriMesh) -> SphereTree {
        let all: Vec<TriangleId> = (0..mesh.triangle_count() as u32).map(TriangleId).collect();
        build_tree(mesh, &all, BuildParams::default())
    }

    /// Against plain traversal of the same trees: every (primitive of `a`,
    /// group of `b`'s leaf) that plain traversal reaches is reached with
    /// groups too, whatever the grouping; and no leaf or twig of `a` is
    /// asked for its sphere to meet a group's leaf (they are let through).
    #[test]
    fn grouping_loses_no_pair() {
        for seed in 0..40u64 {
            let ma = soup(seed, 60, 1.0, 0.2);
            let mb = soup(seed + 1000, 80, 1.0, 0.3);
            let (mut ta, mut tb) = (tree(&ma), tree(&mb));
            // Groups: triangles of `b` by index modulo a seed-dependent count.
            let groups = 1 + (seed as u32 % 7);
            let group_of = |p: u32| p % groups;
            // Each group's sphere holds its leaves' spheres (as a division's
            // root sphere holds its nested leaves).
            let leaves: Vec<(u32, Sphere)> = tb
                .nodes()
                .iter()
                .filter_map(|n| n.primitive().map(|p| (p, n.sphere)))
                .collect();
            let spheres: Vec<Sphere> = (0..groups)
                .map(|g| {
                    let mine: Vec<Sphere> = leaves
                        .iter()
                        .filter(|(p, _)| group_of(*p) == g)
                        .map(|(_, s)| *s)
                        .collect();
                    let centres: Vec<Point> = mine.iter().map(|s| s.center).collect();
                    let mut s = points_sphere(&centres);
                    s.radius = mine
                        .iter()
                        .map(|l| (l.center - s.center).norm() + l.radius)
                        .fold(0.0, f32::max)
                        * (1.0 + 1e-5);
                    s
                })
                .collect();
            let mut ws = Workspace::new();
            let mut plain = BTreeSet::new();
            traverse(&mut ta, &mut tb, &mut ws, |p| {
                plain.insert((p.primitive_a, group_of(p.primitive_b)));
            });
            let mut grouped = BTreeSet::new();
            let mut marks = PassMarks::new(ta.len());
            let leaf_primitive = |j: NodeId| tb.node(j).primitive();
            let prims: Vec<Option<u32>> = (0..tb.len() as u32)
                .map(|j| leaf_primitive(NodeId(j)))
                .collect();
            // A leaf or a twig of `a` asked for its sphere to be tested
            // against a leaf of `b` (all of `b`'s leaves are grouped).
            // `traverse_core` tells `a`, then `b`, of each test, then asks
            // the side it opened for the child's sphere.
            let a_leaf = Cell::new(false);
            let both_leaves = Cell::new(false);
            let asked = Cell::new(0u64);
            let mut seen = LeavesTested {
                tree: &ta,
                twigs: true,
                on_test: |leaf| a_leaf.set(leaf),
                on_sphere: |leaf| asked.set(asked.get() + (leaf && both_leaves.get()) as u64),
            };
            let mut tb2 = LeavesTested {
                tree: &tb,
                twigs: false,
                on_test: |leaf| both_leaves.set(leaf && a_leaf.get()),
                on_sphere: |_| both_leaves.set(false),
            };
            traverse_grouped(
                &mut seen,
                &mut tb2,
                &mut ws,
                Some(&mut marks),
                |j| prims[j.index()].map(|p| (group_of(p), spheres[group_of(p) as usize])),
                |_, _| true,
                |p| {
                    grouped.insert((p.primitive_a, group_of(p.primitive_b)));
                },
            );
            let lost: Vec<_> = plain.difference(&grouped).collect();
            assert!(lost.is_empty(), "seed {seed}: lost {lost:?}");
            // Every leaf of `b` is in a group, so a leaf or a twig of `a` is
            // never asked for its sphere to meet one: it is let through.
            assert_eq!(
                asked.get(),
                0,
                "seed {seed}: leaves or twigs of `a` refit for a group"
            );
        }
    }

    /// Each leaf of `b` its own group and no marks (as for big triangles
    /// left whole): no pair of primitives is handed on twice, and every
    /// pair plain traversal reaches is handed on.
    #[test]
    fn one_leaf_groups_without_marks_repeat_and_lose_nothing() {
        for seed in 0..40u64 {
            let ma = soup(seed, 60, 1.0, 0.2);
            let mb = soup(seed + 2000, 80, 1.0, 0.3);
            let (mut ta, mut tb) = (tree(&ma), tree(&mb));
            let mut ws = Workspace::new();
            let mut plain = BTreeSet::new();
            traverse(&mut ta, &mut tb, &mut ws, |p| {
                plain.insert((p.primitive_a, p.primitive_b));
            });
            let groups: Vec<Option<(u32, Sphere)>> = tb
                .nodes()
                .iter()
                .map(|n| n.primitive().map(|p| (p, n.sphere)))
                .collect();
            let mut handed = Vec::new();
            traverse_grouped(
                &mut ta,
                &mut tb,
                &mut ws,
                None,
                |j| groups[j.index()],
                |_, _| true,
                |p| handed.push((p.primitive_a, p.primitive_b)),
            );
            let once: BTreeSet<(u32, u32)> = handed.iter().copied().collect();
            assert_eq!(
                once.len(),
                handed.len(),
                "seed {seed}: a pair handed on twice"
            );
            let lost: Vec<_> = plain.difference(&once).collect();
            assert!(lost.is_empty(), "seed {seed}: lost {lost:?}");
        }
    }

    /// `tree` as a hierarchy telling `on_test` of each sphere test its
    /// nodes take part in, and `on_sphere` of each sphere asked for:
    /// whether the node is a leaf, or (with `twigs`) a leaf or a twig (a
    /// node whose children are all leaves).
    struct LeavesTested<'a, T, S> {
        tree: &'a SphereTree,
        twigs: bool,
        on_test: T,
        on_sphere: S,
    }

    impl<T, S> LeavesTested<'_, T, S> {
        fn low(&self, id: NodeId) -> bool {
            let n = self.tree.node(id);
            n.is_leaf() || (self.twigs && n.children().all(|c| self.tree.node(NodeId(c)).is_leaf()))
        }
    }

    impl<T: FnMut(bool), S: FnMut(bool)> Hierarchy for LeavesTested<'_, T, S> {
        fn tree(&self) -> &SphereTree {
            self.tree
        }
        fn sphere(&mut self, id: NodeId) -> Sphere {
            let low = self.low(id);
            (self.on_sphere)(low);
            self.tree.node(id).sphere
        }
        fn tested(&mut self, id: NodeId) {
            let low = self.low(id);
            (self.on_test)(low);
        }
    }
}
