//! Sphere hierarchies inside one big triangle (§5).
//!
//! - [`DivisionKind::Full`]: every sub-triangle whose longest edge exceeds the
//!   threshold splits in four (Fig. 2). Answered at the leaves by the
//!   triangle-triangle test this is the paper's *sphere division*; with the
//!   plane-sphere test it is the *quaternary tree* the paper argues against.
//! - [`DivisionKind::Corner`]: only sub-triangles with an edge on the original
//!   triangle's boundary split again; the central piece of every split is a
//!   leaf (Fig. 3). Level n holds 1, 4, 12, 36, 84, … spheres (Table 1).
//! - [`DivisionKind::Whole`] (ours): nothing splits; the division is one
//!   leaf, the whole triangle's sphere. With the plane and edge-plane guard
//!   of `undivided-pruned-tri-tri` it keeps the guard without the
//!   corner-tree's nodes (docs/results.md).
//!
//! Every node's sphere is the minimal sphere of its sub-triangle, grown by a few
//! `f32` ulps of the triangle's extent so that midpoint rounding can never leave
//! a sliver of the original triangle outside every leaf. Leaves point back to the
//! original triangle (their primitive).

use crate::geometry::enclosing::triangle_sphere;
use crate::geometry::{Real, Triangle};
use crate::mesh::TriangleId;
use crate::sphere_tree::{Node, NodeId, SphereTree};

use super::SubTriangle;

/// Which sub-triangles split again.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum DivisionKind {
    /// All of them (quaternary tree).
    Full,
    /// Only those with an edge on the original boundary (corner-tree).
    Corner,
    /// None (ours): one leaf, the whole triangle.
    Whole,
}

/// Default cap on levels, so a tiny threshold cannot exhaust memory
/// (a full tree of 10 levels has 349,525 nodes).
pub const MAX_LEVELS: usize = 10;

/// The hierarchy of one big triangle.
#[derive(Clone, Debug)]
pub struct Division {
    /// Which sub-triangles were allowed to split.
    pub kind: DivisionKind,
    /// The big triangle this hierarchy covers, in its mesh.
    pub original: TriangleId,
    /// Sub-triangle spheres, breadth first; leaves hold `original`.
    pub tree: SphereTree,
    /// The sub-triangle of every node.
    pub pieces: Vec<SubTriangle>,
    /// Whether [`MAX_LEVELS`] (or the given cap) stopped splitting early.
    pub capped: bool,
}

/// Why a division is malformed.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum DivisionError {
    /// A corner of a node's sub-triangle lies outside the node's sphere.
    #[error("node {node}: its sub-triangle sticks out of its sphere")]
    PieceOutside {
        /// The node, breadth-first index in the tree.
        node: u32,
    },
    /// An inner node's children do not cover its sub-triangle's area.
    #[error("node {node}: children's areas sum to {sum}, the piece has {area}")]
    ChildrenDoNotTile {
        /// The inner node, breadth-first index in the tree.
        node: u32,
        /// Sum of the children's areas.
        sum: f64,
        /// Area of the node's own sub-triangle.
        area: f64,
    },
    /// The leaves together do not cover the original triangle's area.
    #[error("leaves' areas sum to {sum}, the original triangle has {area}")]
    LeavesDoNotTile {
        /// Sum of the leaves' areas.
        sum: f64,
        /// Area of the original triangle.
        area: f64,
    },
    /// A leaf's primitive is not the original triangle.
    #[error("leaf {node} points to triangle {got}, not {expected}")]
    WrongPrimitive {
        /// The leaf, breadth-first index in the tree.
        node: u32,
        /// The triangle index the leaf holds.
        got: u32,
        /// The original triangle's index.
        expected: u32,
    },
}

impl Division {
    /// Builds the hierarchy of `t` (triangle `id` of its mesh): a piece splits
    /// while its longest edge exceeds `threshold` (and, for a corner-tree, it
    /// has a boundary edge), up to `max_levels` levels.
    pub fn build(
        t: &Triangle,
        id: TriangleId,
        kind: DivisionKind,
        threshold: Real,
        max_levels: usize,
    ) -> Self {
        let slack = slack(t);
        let mut pieces = vec![SubTriangle::whole(*t)];
        let mut level = vec![1usize];
        let mut nodes = Vec::new();
        let mut capped = false;
        let mut i = 0;
        while i < pieces.len() {
            let piece = pieces[i];
            let mut sphere = triangle_sphere(&piece.triangle);
            sphere.radius += slack;
            let wants = piece.triangle.longest_edge() > threshold
                && match kind {
                    DivisionKind::Full => true,
                    DivisionKind::Corner => piece.touches_boundary(),
                    DivisionKind::Whole => false,
                };
            if wants && level[i] >= max_levels {
                capped = true;
            }
            if wants && level[i] < max_levels {
                let first = NodeId(pieces.len() as u32);
                pieces.extend(piece.split());
                level.extend([level[i] + 1; 4]);
                nodes.push(Node::inner(sphere, first, 4));
            } else {
                nodes.push(Node::leaf(sphere, id.0));
            }
            i += 1;
        }
        Self {
            kind,
            original: id,
            tree: SphereTree::from_nodes(nodes),
            pieces,
            capped,
        }
    }

    /// Checks that every sphere holds its piece, children tile their parent and
    /// leaves tile the original triangle (areas within `1e-6` relative), and
    /// that leaves point to the original.
    pub fn validate(&self) -> Result<(), DivisionError> {
        let area = |p: &SubTriangle| area_f64(&p.triangle);
        let total = area(&self.pieces[0]);
        let tol = 1e-6 * total.max(f64::MIN_POSITIVE);
        let mut leaves = 0.0;
        for (i, (node, piece)) in self.tree.nodes().iter().zip(&self.pieces).enumerate() {
            if !piece
                .triangle
                .vertices()
                .iter()
                .all(|v| node.sphere.contains_point(v, 0.0))
            {
                return Err(DivisionError::PieceOutside { node: i as u32 });
            }
            match node.primitive() {
                Some(p) if p != self.original.0 => {
                    return Err(DivisionError::WrongPrimitive {
                        node: i as u32,
                        got: p,
                        expected: self.original.0,
                    });
                }
                Some(_) => leaves += area(piece),
                None => {
                    let sum: f64 = node
                        .children()
                        .map(|c| area(&self.pieces[c as usize]))
                        .sum();
                    if (sum - area(piece)).abs() > tol {
                        return Err(DivisionError::ChildrenDoNotTile {
                            node: i as u32,
                            sum,
                            area: area(piece),
                        });
                    }
                }
            }
        }
        if (leaves - total).abs() > tol {
            return Err(DivisionError::LeavesDoNotTile {
                sum: leaves,
                area: total,
            });
        }
        Ok(())
    }

    /// Nodes per level, root first.
    pub fn nodes_per_level(&self) -> Vec<usize> {
        self.tree.nodes_per_level()
    }
}

/// A few ulps of the triangle's coordinate magnitude.
fn slack(t: &Triangle) -> Real {
    let m = t
        .vertices()
        .iter()
        .flat_map(|p| p.iter().map(|c| c.abs()))
        .fold(0.0, Real::max);
    4.0 * Real::EPSILON * (m + t.longest_edge())
}

fn area_f64(t: &Triangle) -> f64 {
    let w = |p: &crate::geometry::Point| p.coords.cast::<f64>();
    let (a, b, c) = (w(&t.a), w(&t.b), w(&t.c));
    0.5 * (b - a).cross(&(c - a)).norm()
}

/// Most nodes [`Division::build`] makes for a triangle whose longest edge is
/// `longest`, without building it (to bound memory before a build).
///
/// A split's four pieces are congruent to their parent halved, so every piece
/// of level `l` has longest edge `longest / 2^(l-1)`, and every piece of a
/// level splits or none does: the levels reached follow from the threshold.
/// A full division holds `4^(l-1)` nodes on level `l`. In a corner-tree a
/// piece with two boundary edges (`a`) splits into one such, two with one
/// boundary edge (`b`) and a central leaf; a `b` piece into two `b` pieces
/// and two leaves (Table 1: 1, 4, 12, 36, 84, …). Rounding of the midpoints
/// can only make an edge a few ulps longer: levels are counted as if the
/// threshold were a little smaller, so the count is never below the build's.
pub fn division_nodes(
    longest: Real,
    threshold: Real,
    kind: DivisionKind,
    max_levels: usize,
) -> u64 {
    let mut levels = 1;
    let mut edge = longest as f64;
    while levels < max_levels && edge > threshold as f64 * (1.0 - 1e-4) {
        levels += 1;
        edge *= 0.5;
    }
    match kind {
        DivisionKind::Whole => 1,
        DivisionKind::Full => (0..levels).map(|l| 4u64.pow(l as u32)).sum(),
        DivisionKind::Corner => {
            // Splitting pieces per level: the root, then `a + b`.
            let (mut a, mut b, mut nodes) = (0u64, 0u64, 1u64);
            for l in 1..levels {
                let splitting = if l == 1 { 1 } else { a + b };
                nodes += 4 * splitting;
                (a, b) = if l == 1 { (3, 0) } else { (a, 2 * a + 2 * b) };
            }
            nodes
        }
    }
}

/// Table 1, counted on trees actually built over `t`: spheres on levels
/// 1..=`levels` for the corner-tree and the quaternary tree. The threshold is
/// chosen between the longest edges of levels `levels - 1` and `levels` so
/// both trees have exactly `levels` levels.
pub fn table1(t: &Triangle, levels: usize) -> (Vec<usize>, Vec<usize>) {
    assert!(levels >= 1);
    let l = t.longest_edge();
    // Longest edge of a level-k piece is l / 2^(k-1); split on levels < `levels`.
    let threshold = l / 2f32.powi(levels as i32 - 1) * 1.5;
    let corner = Division::build(t, TriangleId(0), DivisionKind::Corner, threshold, levels);
    let full = Division::build(t, TriangleId(0), DivisionKind::Full, threshold, levels);
    (corner.nodes_per_level(), full.nodes_per_level())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn t() -> Triangle {
        Triangle::new(
            Point::new(-2.0, 0.5, 1.0),
            Point::new(3.0, 0.0, 0.7),
            Point::new(0.4, 2.9, -1.3),
        )
    }

    #[test]
    fn table_1_by_construction() {
        let (corner, quaternary) = table1(&t(), 7);
        assert_eq!(corner, vec![1, 4, 12, 36, 84, 180, 372]);
        assert_eq!(quaternary, vec![1, 4, 16, 64, 256, 1024, 4096]);
    }

    #[test]
    fn divisions_validate() {
        for kind in [
            DivisionKind::Full,
            DivisionKind::Corner,
            DivisionKind::Whole,
        ] {
            let d = Division::build(&t(), TriangleId(7), kind, 0.3, MAX_LEVELS);
            d.validate().unwrap();
            assert!(!d.capped);
            assert!(
                d.pieces
                    .iter()
                    .zip(d.tree.nodes())
                    .all(|(p, n)| !n.is_leaf()
                        || p.triangle.longest_edge() <= 0.3
                        || kind != DivisionKind::Full)
            );
        }
        // A whole division is one leaf, the triangle, however big.
        let d = Division::build(&t(), TriangleId(7), DivisionKind::Whole, 1e-6, MAX_LEVELS);
        assert_eq!(d.tree.len(), 1);
        assert_eq!(d.tree.node(NodeId::ROOT).primitive(), Some(7));
        assert!(!d.capped);
        // A small triangle stays one leaf.
        let d = Division::build(&t(), TriangleId(0), DivisionKind::Full, 100.0, MAX_LEVELS);
        assert_eq!(d.tree.len(), 1);
        // A tiny threshold is capped.
        let d = Division::build(&t(), TriangleId(0), DivisionKind::Full, 1e-6, 4);
        assert!(d.capped);
        assert_eq!(d.nodes_per_level(), vec![1, 4, 16, 64]);
    }

    #[test]
    fn node_bound_matches_built_divisions() {
        use rand::{Rng, SeedableRng};
        let mut rng = rand::rngs::SmallRng::seed_from_u64(15);
        let (mut equal, mut cases) = (0, 0);
        for _ in 0..300 {
            let mut p = || {
                Point::new(
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-3.0..3.0),
                    rng.random_range(-3.0..3.0),
                )
            };
            let t = Triangle::new(p(), p(), p());
            if t.area() < 1e-3 {
                continue;
            }
            let threshold = rng.random_range(0.01..2.0f32);
            let levels = rng.random_range(1..=8);
            for kind in [
                DivisionKind::Full,
                DivisionKind::Corner,
                DivisionKind::Whole,
            ] {
                let built = Division::build(&t, TriangleId(0), kind, threshold, levels)
                    .tree
                    .len() as u64;
                let bound = division_nodes(t.longest_edge(), threshold, kind, levels);
                assert!(
                    bound >= built,
                    "{kind:?} {levels} levels: bound {bound} < built {built}"
                );
                cases += 1;
                equal += usize::from(bound == built);
            }
        }
        assert!(equal * 100 >= cases * 99, "{equal} of {cases} exact");
        assert_eq!(
            division_nodes(10.0, 1e-9, DivisionKind::Full, MAX_LEVELS),
            349_525
        );
        assert_eq!(
            division_nodes(10.0, 1e-9, DivisionKind::Corner, 7),
            1 + 4 + 12 + 36 + 84 + 180 + 372
        );
    }

    #[test]
    fn validator_catches_a_shrunk_sphere() {
        let mut d = Division::build(&t(), TriangleId(0), DivisionKind::Corner, 0.5, MAX_LEVELS);
        let mut nodes = d.tree.nodes().to_vec();
        nodes[5].sphere.radius *= 0.5;
        d.tree = SphereTree::from_nodes(nodes);
        assert_eq!(d.validate(), Err(DivisionError::PieceOutside { node: 5 }));
    }
}
