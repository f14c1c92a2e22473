//! One tree against itself: every pair of distinct leaves whose spheres
//! overlap, each once (self-collision of a character).
//!
//! No new traversal: a node's leaf pairs are those of each child alone plus
//! those across each pair of its children, `self(n) = Σ self(c) + Σ
//! cross(c_k, c_l)` for `k < l`. Each `cross` is the ordinary simultaneous
//! traversal ([`super::traverse()`]) started at the pair `(c_k, c_l)` instead
//! of the roots, both sides being views of the one hierarchy (its spheres
//! refit on demand once, whichever side asks). A pair of leaves has one
//! lowest common ancestor, so it is reached by one `cross` only, once.

use std::cell::RefCell;

use crate::geometry::Sphere;

use super::node::{NodeId, SphereTree};
use super::traverse::{AsTested, Hierarchy, LeafPair, TraversalStats, Workspace, traverse_core};

/// One side of a tree traversed against itself: its topology, and its
/// spheres through the hierarchy both sides share.
struct Shared<'t, 'h, H: ?Sized> {
    tree: &'t SphereTree,
    h: &'h RefCell<&'h mut H>,
}

impl<H: Hierarchy + ?Sized> Hierarchy for Shared<'_, '_, H> {
    #[inline]
    fn tree(&self) -> &SphereTree {
        self.tree
    }
    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.h.borrow_mut().sphere(id)
    }
    #[inline]
    fn tested(&mut self, id: NodeId) {
        self.h.borrow_mut().tested(id);
    }
    #[inline]
    fn prefetch(&self, id: NodeId) {
        self.h.borrow().prefetch(id);
    }
}

/// Walks `h` (whose topology is `tree`: the same tree, or a copy of its
/// topology, read while `h` lends its spheres) against itself: `on_leaf_pair(n,
/// p)` for every pair `p` of distinct overlapping leaves, reached across
/// two children of their lowest common ancestor `n` (`p.leaf_a` under the
/// lower child). `skip(n)` leaves node `n`'s own pairs out (none of them is
/// reached); `keep(n, i, j)` is asked of every pair `(i, j)` under two
/// children of `n` before its spheres are tested, and a pair it refuses is
/// not descended. Counters add up over every cross traversal.
pub fn traverse_self<H, S, K, F>(
    tree: &SphereTree,
    h: &mut H,
    ws: &mut Workspace,
    mut skip: S,
    mut keep: K,
    mut on_leaf_pair: F,
) -> TraversalStats
where
    H: Hierarchy + ?Sized,
    S: FnMut(NodeId) -> bool,
    K: FnMut(NodeId, NodeId, NodeId) -> bool,
    F: FnMut(NodeId, LeafPair),
{
    assert_eq!(
        tree.len(),
        h.tree().len(),
        "traverse_self: `tree` must be the hierarchy's topology"
    );
    let mut stats = TraversalStats::default();
    if tree.is_empty() {
        return stats;
    }
    let cell = RefCell::new(h);
    let (mut a, mut b) = (Shared { tree, h: &cell }, Shared { tree, h: &cell });
    ws.nodes.clear();
    ws.nodes.push(NodeId::ROOT);
    while let Some(n) = ws.nodes.pop() {
        let node = tree.node(n);
        if node.is_leaf() || skip(n) {
            continue;
        }
        let children = node.children();
        for k in children.clone() {
            for l in k + 1..children.end {
                let (ck, cl) = (NodeId(k), NodeId(l));
                if !keep(n, ck, cl) {
                    continue;
                }
                let s = traverse_core(
                    &mut a,
                    &mut b,
                    ws,
                    (ck, cl),
                    None,
                    |_| None,
                    &AsTested,
                    |i, j, _| keep(n, i, j),
                    |p| on_leaf_pair(n, p),
                );
                stats.sphere_tests += s.sphere_tests;
                stats.leaf_pairs += s.leaf_pairs;
                stats.max_stack = stats.max_stack.max(s.max_stack);
            }
        }
        for c in children {
            if !tree.node(NodeId(c)).is_leaf() {
                ws.nodes.push(NodeId(c));
            }
        }
    }
    stats
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use super::traverse_self;
    use crate::sphere_tree::Workspace;
    use crate::sphere_tree::grouped::tests::{soup, tree};

    /// Against brute force over every pair of leaves: the pairs whose leaf
    /// spheres overlap (in a nested tree every ancestor pair overlaps too),
    /// each once, with `leaf_a`'s primitive first in the walk's order.
    #[test]
    fn every_overlapping_leaf_pair_once() {
        for seed in 0..20u64 {
            let mesh = soup(seed, 90, 1.0, 0.25);
            let mut t = tree(&mesh);
            let leaves: Vec<_> = t
                .nodes()
                .iter()
                .filter(|n| n.is_leaf())
                .map(|n| (n.primitive().unwrap(), n.sphere))
                .collect();
            let mut brute = BTreeSet::new();
            for (x, (pa, sa)) in leaves.iter().enumerate() {
                for (pb, sb) in &leaves[x + 1..] {
                    if sa.overlaps(sb) {
                        brute.insert((*pa.min(pb), *pa.max(pb)));
                    }
                }
            }
            let mut found = Vec::new();
            // The topology is read while the tree lends its spheres.
            let topology = t.clone();
            let stats = traverse_self(
                &topology,
                &mut t,
                &mut Workspace::new(),
                |_| false,
                |_, _, _| true,
                |_, p| {
                    found.push((
                        p.primitive_a.min(p.primitive_b),
                        p.primitive_a.max(p.primitive_b),
                    ))
                },
            );
            let set: BTreeSet<_> = found.iter().copied().collect();
            assert_eq!(set.len(), found.len(), "seed {seed}: a pair twice");
            assert_eq!(set, brute, "seed {seed}");
            assert_eq!(stats.leaf_pairs as usize, found.len());
        }
    }
}
