//! The sphere-tree validator: tests call it after every build and refit.

use crate::mesh::{TriMesh, TriangleId};

use super::node::SphereTree;

/// A broken invariant, naming the node.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum TreeError {
    /// A node's sphere has a non-finite centre or radius, or a negative radius.
    #[error("node {node}: sphere is not finite or has a negative radius")]
    InvalidSphere {
        /// The node's index.
        node: u32,
    },
    /// An inner node's children do not all come after it, or run past the
    /// last node.
    #[error("node {node}: children {first}..{end} are not all after it and inside the tree")]
    BadChildren {
        /// The inner node's index.
        node: u32,
        /// Its first child's index.
        first: u32,
        /// One past its last child's index.
        end: u32,
    },
    /// A node other than the root has no parent, or more than one.
    #[error("node {node} is reached from more than one parent, or never")]
    BadParent {
        /// The node's index.
        node: u32,
    },
    /// A leaf's primitive is not a triangle index of the mesh.
    #[error("leaf {node}: primitive {primitive} is not a triangle of the mesh")]
    BadPrimitive {
        /// The leaf's index.
        node: u32,
        /// The primitive it holds.
        primitive: u32,
    },
    /// A triangle of [`Checks::triangles`] is in no leaf or in several, or a
    /// triangle outside that list is in a leaf.
    #[error("triangle {triangle} is in {count} leaves, expected exactly one")]
    TriangleCount {
        /// The mesh triangle's index.
        triangle: u32,
        /// How many leaves hold it.
        count: u32,
    },
    /// A leaf triangle's corner lies outside its leaf's sphere or an
    /// ancestor's, beyond the tolerance.
    #[error(
        "leaf {leaf}: vertex {corner} of triangle {triangle} lies {excess} outside the sphere of node {node}"
    )]
    VertexOutside {
        /// The leaf's index.
        leaf: u32,
        /// The triangle it holds (mesh index).
        triangle: u32,
        /// Which corner of the triangle (0, 1 or 2).
        corner: usize,
        /// The node (the leaf or an ancestor) whose sphere misses the corner.
        node: u32,
        /// How far the corner lies beyond that sphere's radius, in model units.
        excess: f64,
    },
    /// A child's sphere is not inside its parent's (checked with
    /// [`Checks::nested`]).
    #[error("node {child} sticks out of its parent {parent} by {excess}")]
    NotNested {
        /// The parent's index.
        parent: u32,
        /// The child's index.
        child: u32,
        /// How far the child's sphere reaches beyond the parent's radius,
        /// in model units.
        excess: f64,
    },
}

/// What [`SphereTree::validate`] checks beyond the layout.
#[derive(Clone, Copy, Debug)]
pub struct Checks<'a> {
    /// Each triangle of this list must be in exactly one leaf.
    pub triangles: Option<&'a [TriangleId]>,
    /// Also require each child sphere inside its parent (true for built trees).
    pub nested: bool,
    /// Slack allowed beyond a radius, in model units.
    pub tolerance: f64,
}

impl SphereTree {
    /// Checks layout, leaf containment (every leaf triangle inside its sphere and
    /// the spheres of all its ancestors) and, as asked, coverage and nesting.
    pub fn validate(&self, mesh: &TriMesh, checks: Checks<'_>) -> Result<(), TreeError> {
        let n = self.nodes.len();
        let mut parent = vec![u32::MAX; n];
        for (i, node) in self.nodes.iter().enumerate() {
            if !node.sphere.is_valid() {
                return Err(TreeError::InvalidSphere { node: i as u32 });
            }
            let ch = node.children();
            if !ch.is_empty() && (ch.start as usize <= i || ch.end as usize > n) {
                return Err(TreeError::BadChildren {
                    node: i as u32,
                    first: ch.start,
                    end: ch.end,
                });
            }
            for c in ch {
                if parent[c as usize] != u32::MAX {
                    return Err(TreeError::BadParent { node: c });
                }
                parent[c as usize] = i as u32;
            }
            if let Some(p) = node.primitive()
                && p as usize >= mesh.triangle_count()
            {
                return Err(TreeError::BadPrimitive {
                    node: i as u32,
                    primitive: p,
                });
            }
        }
        if let Some(orphan) = (1..n).find(|&i| parent[i] == u32::MAX) {
            return Err(TreeError::BadParent {
                node: orphan as u32,
            });
        }
        if checks.nested {
            for (c, &pc) in parent.iter().enumerate().skip(1) {
                let (p, child) = (&self.nodes[pc as usize], &self.nodes[c]);
                if !p
                    .sphere
                    .contains_sphere(&child.sphere, checks.tolerance as f32)
                {
                    let d = crate::geometry::sphere::distance_f64(
                        &p.sphere.center,
                        &child.sphere.center,
                    );
                    let excess = d + child.sphere.radius as f64 - p.sphere.radius as f64;
                    return Err(TreeError::NotNested {
                        parent: pc,
                        child: c as u32,
                        excess,
                    });
                }
            }
        }
        // Leaf triangles inside the leaf and every ancestor.
        for (i, node) in self.nodes.iter().enumerate() {
            let Some(t) = node.primitive() else { continue };
            let tri = mesh.triangle(TriangleId(t));
            let mut a = i as u32;
            loop {
                let s = self.nodes[a as usize].sphere;
                for (corner, v) in tri.vertices().iter().enumerate() {
                    if !s.contains_point(v, checks.tolerance as f32) {
                        let d = crate::geometry::sphere::distance_f64(v, &s.center);
                        return Err(TreeError::VertexOutside {
                            leaf: i as u32,
                            triangle: t,
                            corner,
                            node: a,
                            excess: d - s.radius as f64,
                        });
                    }
                }
                if a == 0 {
                    break;
                }
                a = parent[a as usize];
            }
        }
        if let Some(list) = checks.triangles {
            let mut count = vec![0u32; mesh.triangle_count()];
            for p in self.nodes.iter().filter_map(|n| n.primitive()) {
                count[p as usize] += 1;
            }
            let mut expected = vec![0u32; mesh.triangle_count()];
            for t in list {
                expected[t.index()] += 1;
            }
            if let Some(t) = (0..count.len()).find(|&t| count[t] != expected[t].min(1)) {
                return Err(TreeError::TriangleCount {
                    triangle: t as u32,
                    count: count[t],
                });
            }
        }
        Ok(())
    }
}
