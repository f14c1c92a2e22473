//! Compact sphere-tree storage.

use std::ops::Range;

use crate::geometry::Sphere;

/// Index of a node in its tree; the root is `NodeId(0)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct NodeId(pub u32);

impl NodeId {
    /// The root node, first in every tree.
    pub const ROOT: NodeId = NodeId(0);

    /// The id as an index into the tree's nodes.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// One sphere of the hierarchy: 24 bytes.
///
/// An inner node's children are `first .. first + count`; a leaf has
/// `count == 0` and `first` is the primitive it bounds (a triangle index).
/// The top bit of `count` marks a twig (an inner node whose children are
/// all leaves), set by [`SphereTree::from_nodes`], so that a traversal
/// knows a twig without reading its children.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Node {
    /// The sphere, in the coordinates of the mesh the tree was built over
    /// (bind space for a character, world for a room, the object's own frame
    /// for a rigid object).
    pub sphere: Sphere,
    first: u32,
    count: u32,
}

/// The bit of [`Node`]'s `count` that marks a twig.
const TWIG: u32 = 1 << 31;

impl Node {
    /// An inner node whose `child_count` (at least one) children are stored
    /// from `first_child` on.
    ///
    /// # Panics
    ///
    /// If `child_count` is 0, or 2³¹ or more (the top bit marks a twig).
    pub fn inner(sphere: Sphere, first_child: NodeId, child_count: u32) -> Self {
        assert!(child_count > 0 && child_count < TWIG);
        Self {
            sphere,
            first: first_child.0,
            count: child_count,
        }
    }

    /// A leaf bounding one primitive (a triangle index of the mesh).
    pub fn leaf(sphere: Sphere, primitive: u32) -> Self {
        Self {
            sphere,
            first: primitive,
            count: 0,
        }
    }

    /// Whether the node has no children (and so holds a primitive).
    #[inline]
    pub fn is_leaf(&self) -> bool {
        self.count == 0
    }

    /// The primitive of a leaf.
    #[inline]
    pub fn primitive(&self) -> Option<u32> {
        self.is_leaf().then_some(self.first)
    }

    /// Child ids (empty for a leaf).
    #[inline]
    pub fn children(&self) -> Range<u32> {
        if self.is_leaf() {
            0..0
        } else {
            self.first..self.first + (self.count & !TWIG)
        }
    }

    /// Number of children (0 for a leaf).
    #[inline]
    pub fn child_count(&self) -> u32 {
        self.count & !TWIG
    }

    /// Whether the node is inner and its children are all leaves (known
    /// once the node is in a [`SphereTree`]).
    #[inline]
    pub fn is_twig(&self) -> bool {
        self.count & TWIG != 0
    }
}

/// A sphere tree in breadth-first order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SphereTree {
    pub(crate) nodes: Vec<Node>,
}

impl SphereTree {
    /// Wraps nodes laid out as the module invariants require (see
    /// [`SphereTree::validate`]), and marks the twigs (see
    /// [`Node::is_twig`]).
    pub fn from_nodes(mut nodes: Vec<Node>) -> Self {
        for i in 0..nodes.len() {
            let n = nodes[i];
            let kids = n.children();
            let twig = !n.is_leaf()
                && (kids.end as usize) <= nodes.len()
                && nodes[kids.start as usize..kids.end as usize]
                    .iter()
                    .all(Node::is_leaf);
            nodes[i].count = if twig {
                n.count | TWIG
            } else {
                n.count & !TWIG
            };
        }
        Self { nodes }
    }

    /// Every node, root first, in breadth-first order.
    pub fn nodes(&self) -> &[Node] {
        &self.nodes
    }

    /// Spheres may be rewritten in place (refit); topology may not.
    pub fn spheres_mut(&mut self) -> impl Iterator<Item = &mut Sphere> {
        self.nodes.iter_mut().map(|n| &mut n.sphere)
    }

    /// Node `id` (panics if it is not in the tree).
    #[inline]
    pub fn node(&self, id: NodeId) -> &Node {
        &self.nodes[id.index()]
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.nodes.len()
    }

    /// Whether the tree has no node (built over no triangle).
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty()
    }

    /// Number of leaves, one per primitive.
    pub fn leaf_count(&self) -> usize {
        self.nodes.iter().filter(|n| n.is_leaf()).count()
    }

    /// Bytes held by the hierarchy's nodes (the "Data" of the paper's Tables 2–3).
    pub fn bytes(&self) -> usize {
        self.nodes.len() * std::mem::size_of::<Node>()
    }

    /// Number of nodes on each level, root first.
    pub fn nodes_per_level(&self) -> Vec<usize> {
        let mut counts = Vec::new();
        let mut level = vec![0u32; self.nodes.len()];
        for (i, n) in self.nodes.iter().enumerate() {
            let l = level[i] as usize;
            if counts.len() <= l {
                counts.resize(l + 1, 0);
            }
            counts[l] += 1;
            for c in n.children() {
                level[c as usize] = level[i] + 1;
            }
        }
        counts
    }

    /// Lays a tree out breadth first from `root`. `visit(o, kids)` gives the
    /// sphere of `o` and, for a leaf, its primitive; for an inner node it pushes
    /// the children's origins into `kids` (given empty). Returns the tree and
    /// the origin of every node, in node order.
    pub(crate) fn breadth_first<O: Copy>(
        root: O,
        mut visit: impl FnMut(O, &mut Vec<O>) -> (Sphere, Option<u32>),
    ) -> (SphereTree, Vec<O>) {
        let mut order = vec![root];
        let mut nodes = Vec::new();
        let mut kids = Vec::new();
        let mut i = 0;
        while i < order.len() {
            kids.clear();
            let node = match visit(order[i], &mut kids) {
                (sphere, Some(primitive)) => Node::leaf(sphere, primitive),
                (sphere, None) => {
                    let first = NodeId(order.len() as u32);
                    order.extend_from_slice(&kids);
                    Node::inner(sphere, first, kids.len() as u32)
                }
            };
            nodes.push(node);
            i += 1;
        }
        (SphereTree::from_nodes(nodes), order)
    }

    /// Parent of every node (`u32::MAX` for the root).
    pub fn parents(&self) -> Vec<u32> {
        let mut p = vec![u32::MAX; self.nodes.len()];
        for (i, n) in self.nodes.iter().enumerate() {
            for c in n.children() {
                p[c as usize] = i as u32;
            }
        }
        p
    }

    /// Number of levels (a lone leaf has depth 1; an empty tree 0).
    pub fn depth(&self) -> usize {
        self.nodes_per_level().len()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn node_is_compact() {
        assert_eq!(std::mem::size_of::<Node>(), 24);
    }

    #[test]
    fn twigs_are_the_inner_nodes_whose_children_are_all_leaves() {
        let s = Sphere::new(crate::geometry::Point::origin(), 1.0);
        // 0 → {1, 2}; 1 → {3, 4} (a twig); 2 → {5} and 5 → {6} (2 is not a
        // twig, 5 is); 3, 4, 6 leaves.
        let tree = SphereTree::from_nodes(vec![
            Node::inner(s, NodeId(1), 2),
            Node::inner(s, NodeId(3), 2),
            Node::inner(s, NodeId(5), 1),
            Node::leaf(s, 0),
            Node::leaf(s, 1),
            Node::inner(s, NodeId(6), 1),
            Node::leaf(s, 2),
        ]);
        let twigs: Vec<bool> = tree.nodes().iter().map(Node::is_twig).collect();
        assert_eq!(twigs, [false, true, false, false, false, true, false]);
        // The mark changes neither the children nor their count.
        assert_eq!(tree.node(NodeId(1)).children(), 3..5);
        assert_eq!(tree.node(NodeId(1)).child_count(), 2);
        assert_eq!(tree.node(NodeId(5)).children(), 6..7);
        assert_eq!(tree.node(NodeId(0)).children(), 1..3);
    }
}
