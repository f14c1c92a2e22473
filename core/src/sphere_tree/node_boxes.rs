//! Each node of a static tree with the box of the geometry under it
//! ([`QuantizedBox`], six bytes a node, levels across the cube around the
//! node's own sphere; ours).
//!
//! A room never moves, so its nodes' boxes cost nothing to keep up. Where
//! its surfaces are flat and square to the axes (floors, walls, table tops,
//! shelves), a node's box is a thin slab where its sphere is a ball: a
//! character sphere near the surface overlaps the ball but not the slab.
//! Traversal asks the box after the sphere test passes
//! (`EnvironmentTree::box_may_meet`, in the discrete guard and, with a
//! swept sphere, in the continuous room pass's), so a pair whose character
//! sphere misses the box is dropped with everything under it.
//!
//! Built from the leaves up: a leaf's box is its triangle's, an inner
//! node's the union of its children's boxes as stored (so a child's clip to
//! its own cube carries up), each clipped to the node's cube and rounded
//! outward to levels. A leaf of a big triangle's division names the whole
//! big triangle; clipped to the leaf's cube, its box still holds the piece
//! of the triangle the leaf stands for (which lies in its sphere).

use crate::geometry::sphere_box::{QuantizedBox, sphere_meets_box};
use crate::geometry::{Point, Sphere};

use super::{NodeId, SphereTree};

/// The box of every node of one static tree (empty: no boxes, every
/// sphere may meet).
#[derive(Clone, Debug, Default)]
pub struct NodeBoxes {
    boxes: Vec<QuantizedBox>,
}

impl NodeBoxes {
    /// The boxes of `tree`'s nodes, given the corners of each leaf's
    /// primitive (`corners(primitive)`).
    pub fn build(tree: &SphereTree, corners: impl Fn(u32) -> [Point; 3]) -> Self {
        let nodes = tree.nodes();
        let mut boxes = vec![QuantizedBox::CUBE; nodes.len()];
        // Children are stored after their parent: a reverse sweep visits
        // them first.
        for i in (0..nodes.len()).rev() {
            let n = &nodes[i];
            let (mut min, mut max) = ([f64::INFINITY; 3], [f64::NEG_INFINITY; 3]);
            let mut grow = |lo: [f64; 3], hi: [f64; 3]| {
                for k in 0..3 {
                    min[k] = min[k].min(lo[k]);
                    max[k] = max[k].max(hi[k]);
                }
            };
            match n.primitive() {
                Some(p) => {
                    for q in corners(p) {
                        let q = [q.x, q.y, q.z].map(f64::from);
                        grow(q, q);
                    }
                }
                None => {
                    for c in n.children() {
                        let c = c as usize;
                        let (lo, hi) = boxes[c].bounds_as::<f64>(&nodes[c].sphere);
                        grow(lo, hi);
                    }
                }
            }
            boxes[i] = QuantizedBox::enclosing(min, max, &n.sphere);
        }
        Self { boxes }
    }

    /// Whether the sphere `s` may meet the geometry under node `id` of
    /// `tree` (the tree the boxes were built for): `false` only when `s`
    /// lies wholly outside the node's box. Without boxes, `true`.
    #[inline]
    pub fn may_meet(&self, tree: &SphereTree, id: NodeId, s: &Sphere) -> bool {
        match self.boxes.get(id.index()) {
            Some(b) => sphere_meets_box(s, b, &tree.node(id).sphere),
            None => true,
        }
    }

    /// Whether there are boxes at all.
    pub fn is_empty(&self) -> bool {
        self.boxes.is_empty()
    }

    /// Bytes of the boxes.
    pub fn bytes(&self) -> usize {
        self.boxes.len() * std::mem::size_of::<QuantizedBox>()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Triangle;
    use crate::geometry::closest_point::point_triangle_distance;
    use crate::mesh::{TriMesh, TriangleId};
    use crate::sphere_tree::{BuildParams, build_tree};

    /// A floor of small squares, a table top above it and a slanted ramp:
    /// flat surfaces square to the axes and one that is not.
    fn room() -> TriMesh {
        let mut positions = Vec::new();
        let mut indices = Vec::new();
        let mut quad = |p: [Point; 4]| {
            let base = positions.len() as u32;
            positions.extend(p);
            indices.push([base, base + 1, base + 2]);
            indices.push([base, base + 2, base + 3]);
        };
        for i in 0..12 {
            for j in 0..12 {
                let (x, z) = (i as f32 * 0.25, j as f32 * 0.25);
                quad([
                    Point::new(x, 0.0, z),
                    Point::new(x + 0.25, 0.0, z),
                    Point::new(x + 0.25, 0.0, z + 0.25),
                    Point::new(x, 0.0, z + 0.25),
                ]);
                quad([
                    Point::new(x * 0.3 + 1.0, 0.75, z * 0.3 + 1.0),
                    Point::new(x * 0.3 + 1.075, 0.75, z * 0.3 + 1.0),
                    Point::new(x * 0.3 + 1.075, 0.75, z * 0.3 + 1.075),
                    Point::new(x * 0.3 + 1.0, 0.75, z * 0.3 + 1.075),
                ]);
                quad([
                    Point::new(x, 0.3 * x + 0.1, z + 4.0),
                    Point::new(x + 0.25, 0.3 * x + 0.175, z + 4.0),
                    Point::new(x + 0.25, 0.3 * x + 0.175, z + 4.25),
                    Point::new(x, 0.3 * x + 0.1, z + 4.25),
                ]);
            }
        }
        TriMesh::new(positions, indices).unwrap()
    }

    /// Against brute force over the triangles under each node: a sphere
    /// within reach of any of them is never dropped at that node, and most
    /// spheres near the surfaces that reach none are (the slabs are thin
    /// where the balls are not).
    #[test]
    fn a_node_drops_no_sphere_that_reaches_its_triangles() {
        let mesh = room();
        let all: Vec<TriangleId> = (0..mesh.triangle_count() as u32).map(TriangleId).collect();
        let tree = build_tree(&mesh, &all, BuildParams::default());
        let corners = |p: u32| {
            let t = mesh.triangle(TriangleId(p));
            [t.a, t.b, t.c]
        };
        let boxes = NodeBoxes::build(&tree, corners);
        assert_eq!(boxes.bytes(), 6 * tree.len());
        // The triangles under each node.
        let mut under: Vec<Vec<u32>> = vec![Vec::new(); tree.len()];
        for i in (0..tree.len()).rev() {
            let n = tree.nodes()[i];
            match n.primitive() {
                Some(p) => under[i].push(p),
                None => {
                    for c in n.children() {
                        let v = under[c as usize].clone();
                        under[i].extend(v);
                    }
                }
            }
        }
        let mut next = crate::test_rng::unit_floats(0x2545_f491_4f6c_dd1d);
        let (mut kept_reaching, mut missing, mut dropped) = (0u32, 0u32, 0u32);
        for (i, under_i) in under.iter().enumerate() {
            let node = tree.nodes()[i].sphere;
            for _ in 0..12 {
                // A sphere near the node's surface: inside its ball.
                let r = node.radius * (0.02 + 0.3 * next());
                let c = node.center
                    + (crate::geometry::Vector::new(next(), next(), next())
                        - crate::geometry::Vector::new(0.5, 0.5, 0.5))
                        * (2.0 * node.radius);
                let s = Sphere::new(c, r);
                if !s.overlaps(&node) {
                    continue;
                }
                let reaches = under_i.iter().any(|&p| {
                    let t: Triangle = mesh.triangle(TriangleId(p));
                    point_triangle_distance(&c.cast::<f64>(), &t) <= f64::from(r)
                });
                let keeps = boxes.may_meet(&tree, NodeId(i as u32), &s);
                if reaches {
                    assert!(keeps, "node {i} dropped {s:?}, which reaches a triangle");
                    kept_reaching += 1;
                } else {
                    missing += 1;
                    dropped += !keeps as u32;
                }
            }
        }
        assert!(
            kept_reaching > 1_000 && missing > 1_000,
            "{kept_reaching} {missing}"
        );
        assert!(
            dropped * 10 > missing * 6,
            "the boxes dropped only {dropped} of {missing} spheres that reach nothing"
        );
        assert!(NodeBoxes::default().may_meet(
            &tree,
            NodeId::ROOT,
            &Sphere::new(Point::origin(), 0.0)
        ));
    }
}
