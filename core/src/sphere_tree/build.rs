//! Sphere-tree construction (paper §3, after Quinlan and Kavan & Žára).
//!
//! 1. Binary tree, top down: a node's triangles are sorted by centroid along
//!    the axis where the centroids spread most and cut in two halves, so the two
//!    child spheres lie as far apart as possible; one triangle per leaf.
//! 2. Spheres: a leaf gets the minimal sphere of its triangle, an inner node
//!    the minimal sphere of its triangles' vertices, grown where needed to hold
//!    its children's spheres (nesting: see the module invariants).
//! 3. Collapse to an n-ary tree: a child whose radius is over
//!    `collapse_ratio` times its parent's is removed and its children move up,
//!    so traversal does not test nearly equal spheres twice.
//! 4. Breadth-first layout: children contiguous and after their parent.

use crate::geometry::enclosing::{grow_to_hold, points_sphere, triangle_sphere};
use crate::geometry::{Point, Sphere};
use crate::mesh::{TriMesh, TriangleId};

use super::node::SphereTree;

/// Construction settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BuildParams {
    /// A child whose radius exceeds this fraction of its parent's is
    /// collapsed into the parent (`1.0` or more keeps the binary tree).
    pub collapse_ratio: f32,
}

impl BuildParams {
    /// A wider, shallower tree: a child over 0.6 of its parent's radius is
    /// collapsed into it (fewer inner spheres to refit and test; our
    /// methods' character trees, `Method::character_build`).
    pub const WIDE: BuildParams = BuildParams {
        collapse_ratio: 0.6,
    };
}

impl Default for BuildParams {
    /// Collapse ratio 0.9 (ours; the paper says only "similar").
    fn default() -> Self {
        Self {
            collapse_ratio: 0.9,
        }
    }
}

/// Temporary binary node.
struct BinNode {
    sphere: Sphere,
    children: Option<[usize; 2]>,
    triangle: TriangleId,
}

/// Builds the tree over `triangles` of `mesh` (for example the triangles kept
/// after edge de-duplication). Leaves hold triangle indices of `mesh`.
/// An empty `triangles` gives an empty tree.
pub fn build_tree(mesh: &TriMesh, triangles: &[TriangleId], params: BuildParams) -> SphereTree {
    if triangles.is_empty() {
        return SphereTree::default();
    }
    let mut items: Vec<(TriangleId, Point)> = triangles
        .iter()
        .map(|&t| (t, mesh.triangle(t).centroid()))
        .collect();
    let mut bin = Vec::with_capacity(2 * items.len());
    let mut scratch = Vec::new();
    let root = build_binary(mesh, &mut items, &mut bin, &mut scratch);
    lay_out(&bin, root, params.collapse_ratio)
}

fn build_binary(
    mesh: &TriMesh,
    items: &mut [(TriangleId, Point)],
    bin: &mut Vec<BinNode>,
    scratch: &mut Vec<Point>,
) -> usize {
    if let [(t, _)] = items {
        bin.push(BinNode {
            sphere: triangle_sphere(&mesh.triangle(*t)),
            children: None,
            triangle: *t,
        });
        return bin.len() - 1;
    }
    // Sphere of all vertices first (scratch reused across the recursion).
    scratch.clear();
    scratch.extend(items.iter().flat_map(|(t, _)| mesh.triangle(*t).vertices()));
    let mut sphere = points_sphere(scratch);

    // Axis of greatest spread of the centroids.
    let (mut lo, mut hi) = (items[0].1, items[0].1);
    for (_, c) in items.iter() {
        lo = lo.inf(c);
        hi = hi.sup(c);
    }
    let spread = hi - lo;
    let axis = spread.imax();
    items.sort_unstable_by(|a, b| a.1[axis].total_cmp(&b.1[axis]).then(a.0.cmp(&b.0)));
    let mid = items.len() / 2;
    let (left, right) = items.split_at_mut(mid);
    let l = build_binary(mesh, left, bin, scratch);
    let r = build_binary(mesh, right, bin, scratch);

    // Nesting: grow the radius (centre kept) until both children fit.
    for child in [l, r] {
        grow_to_hold(&mut sphere, &bin[child].sphere);
    }
    bin.push(BinNode {
        sphere,
        children: Some([l, r]),
        triangle: TriangleId(u32::MAX),
    });
    bin.len() - 1
}

/// The children a binary node keeps after collapsing: a child over `ratio`
/// times the parent's radius is replaced by its own kept children.
fn collapsed_children(bin: &[BinNode], parent: usize, ratio: f32, out: &mut Vec<usize>) {
    let limit = bin[parent].sphere.radius * ratio;
    let mut pending: Vec<usize> = bin[parent].children.map(|c| c.to_vec()).unwrap_or_default();
    pending.reverse();
    while let Some(c) = pending.pop() {
        match bin[c].children {
            Some([a, b]) if bin[c].sphere.radius > limit => {
                pending.push(b);
                pending.push(a);
            }
            _ => out.push(c),
        }
    }
}

/// Breadth-first layout of the collapsed tree.
fn lay_out(bin: &[BinNode], root: usize, ratio: f32) -> SphereTree {
    let (tree, _) = SphereTree::breadth_first(root, |b, kids| {
        let node = &bin[b];
        match node.children {
            None => (node.sphere, Some(node.triangle.0)),
            Some(_) => {
                collapsed_children(bin, b, ratio, kids);
                (node.sphere, None)
            }
        }
    });
    tree
}
