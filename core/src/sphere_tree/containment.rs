//! Checking that refit spheres hold the deformed vertices they should.
//!
//! [`VertexSets`] lists, once per tree, the distinct vertices under every node
//! (those of the triangles in its subtree). A frame's check is then one pass
//! over those lists, comparing squared distances in `f64`, with one square root
//! per node for the worst excess.

use crate::geometry::{Point, Sphere};
use crate::mesh::TriMesh;

use super::node::SphereTree;

/// Distinct vertex ids under every node, flattened.
#[derive(Clone, Debug, Default)]
pub struct VertexSets {
    ids: Vec<u32>,
    ranges: Vec<(u32, u32)>,
}

/// Result of a containment check.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Containment {
    /// Vertex-in-sphere checks made.
    pub checks: u64,
    /// Vertices found further than radius + tolerance from a node's centre.
    pub violations: u64,
    /// Largest distance found beyond a radius (0 when none).
    pub worst_excess: f64,
}

impl VertexSets {
    /// Builds the sets bottom-up, merging children's sorted lists.
    pub fn new(tree: &SphereTree, mesh: &TriMesh) -> Self {
        let n = tree.len();
        let mut sets: Vec<Vec<u32>> = vec![Vec::new(); n];
        for i in (0..n).rev() {
            let node = &tree.nodes()[i];
            let mut v: Vec<u32> = match node.primitive() {
                Some(t) => mesh.indices()[t as usize].to_vec(),
                None => node
                    .children()
                    .flat_map(|c| sets[c as usize].iter().copied())
                    .collect(),
            };
            v.sort_unstable();
            v.dedup();
            sets[i] = v;
        }
        let mut ids = Vec::with_capacity(sets.iter().map(Vec::len).sum());
        let mut ranges = Vec::with_capacity(n);
        for s in sets {
            ranges.push((ids.len() as u32, (ids.len() + s.len()) as u32));
            ids.extend(s);
        }
        Self { ids, ranges }
    }

    /// Distinct vertices under node `i`.
    pub fn of(&self, i: usize) -> &[u32] {
        let (a, b) = self.ranges[i];
        &self.ids[a as usize..b as usize]
    }

    /// Checks every node's sphere against `positions` (`tolerance` in model
    /// units, may be 0). Squared distances are measured in `f64` from the
    /// `f32` coordinates (relative error about 10⁻¹⁶, where `f32` would round
    /// by 10⁻⁷ of a coordinate: a millimetre at 10 km).
    pub fn check(&self, spheres: &[Sphere], positions: &[Point], tolerance: f64) -> Containment {
        let mut out = Containment::default();
        for (i, s) in spheres.iter().enumerate() {
            let limit = s.radius as f64 + tolerance;
            let limit2 = limit * limit;
            let mut worst = 0.0f64;
            let mut worst_id = u32::MAX;
            for &v in self.of(i) {
                let d2 = distance2_f64(&positions[v as usize], &s.center);
                out.violations += (d2 > limit2) as u64;
                if d2 > worst {
                    worst = d2;
                    worst_id = v;
                }
            }
            out.checks += self.of(i).len() as u64;
            if worst_id != u32::MAX {
                out.worst_excess = out.worst_excess.max(worst.sqrt() - s.radius as f64);
            }
        }
        out
    }
}

/// Squared distance in `f64`.
#[inline]
fn distance2_f64(p: &Point, q: &Point) -> f64 {
    let d = |a: f32, b: f32| a as f64 - b as f64;
    let (x, y, z) = (d(p.x, q.x), d(p.y, q.y), d(p.z, q.z));
    x * x + y * y + z * z
}
