//! The truth of one character against itself, and parry3d's answer: the
//! character's posed mesh as a parry `TriMesh` (its BVH built on the first
//! pose, refit after), the BVH's leaf pairs against itself as candidates,
//! pairs of a triangle with itself or with a neighbour (a shared welded
//! corner: the rule every method keeps) dropped, each remaining candidate
//! decided by the exact oracle (the truth) and by parry's `f64` test.
//!
//! parry 0.31 has no self-query of a triangle mesh: the BVH against itself
//! is what a parry3d user writes, and [`SelfTruth::parry_f32_pairs`] (its
//! `f32` triangle test) is the baseline `bench` times.

use parry3d::math::Vector as PVector;
use parry3d::partitioning::BvhNode;
use parry3d::shape::{TriMesh as ParryMesh, TriMeshFlags, Triangle as ParryTriangle};

use super::TruthError;
use super::parry_reference::{parry_f64_triangles_intersect, parry_triangles_intersect};
use cornertree::geometry::exact::{Contact, classify};
use cornertree::geometry::{Point, Triangle};
use cornertree::mesh::TriMesh;
use cornertree::mesh::dedup::weld_positions;

/// One character's self-contact truth, kept from frame to frame.
pub struct SelfTruth {
    indices: Vec<[u32; 3]>,
    /// Each triangle's corners, welded.
    welded: Vec<[u32; 3]>,
    mesh: Option<ParryMesh>,
    candidates: u64,
    /// Exactly touching pairs `(a, b)`, `a < b`, sorted: the truth.
    pub exact: Vec<(u32, u32)>,
    /// parry's touching pairs (its `f64` test), sorted.
    pub parry: Vec<(u32, u32)>,
}

impl SelfTruth {
    /// For a character of mesh `mesh` (its bind positions tell which
    /// corners weld).
    pub fn new(mesh: &TriMesh) -> Result<Self, TruthError> {
        if mesh.triangle_count() == 0 {
            return Err(TruthError::NoTriangles("character"));
        }
        Ok(Self {
            indices: mesh.indices().to_vec(),
            welded: welded_corners(mesh),
            mesh: None,
            candidates: 0,
            exact: Vec::new(),
            parry: Vec::new(),
        })
    }

    /// Moves parry's mesh to this frame's posed vertices (builds it on the
    /// first call, refits its BVH after) without deciding any pair.
    pub fn pose(&mut self, positions: &[Point]) -> Result<(), TruthError> {
        if let Some(v) = positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(TruthError::NonFinitePosition(v));
        }
        let to = |p: &Point| PVector::new(p.x, p.y, p.z);
        match &mut self.mesh {
            Some(m) => {
                if m.vertices().len() != positions.len() {
                    return Err(TruthError::VertexCountChanged {
                        expected: m.vertices().len(),
                        got: positions.len(),
                    });
                }
                m.update_vertices(|vs| {
                    for (v, p) in vs.iter_mut().zip(positions) {
                        *v = to(p);
                    }
                });
            }
            None => {
                for (triangle, tri) in self.indices.iter().enumerate() {
                    if let Some(&index) = tri.iter().find(|&&i| i as usize >= positions.len()) {
                        return Err(TruthError::IndexOutOfRange {
                            triangle,
                            index,
                            vertex_count: positions.len(),
                        });
                    }
                }
                self.mesh = Some(
                    ParryMesh::with_flags(
                        positions.iter().map(to).collect(),
                        self.indices.clone(),
                        TriMeshFlags::DEFORMABLE,
                    )
                    .map_err(|_| TruthError::NoTriangles("character"))?,
                );
            }
        }
        Ok(())
    }

    /// This frame's truth and parry's answer, from the posed vertices.
    pub fn update(&mut self, positions: &[Point]) -> Result<(), TruthError> {
        self.pose(positions)?;
        let mut exact = std::mem::take(&mut self.exact);
        let mut parry = std::mem::take(&mut self.parry);
        self.collect(&mut exact, |a, b| {
            classify(&from_parry(a), &from_parry(b)) != Contact::Disjoint
        });
        self.collect(&mut parry, parry_f64_triangles_intersect);
        (self.exact, self.parry) = (exact, parry);
        Ok(())
    }

    /// parry3d's answer with its `f32` triangle test, at the pose last
    /// given ([`Self::pose`]): the baseline `bench` times.
    pub fn parry_f32_pairs(&mut self, out: &mut Vec<(u32, u32)>) {
        self.collect(out, parry_triangles_intersect);
    }

    /// Candidates (the BVH's leaf pairs against itself, each unordered pair
    /// once, neighbours dropped), kept if `meets`; sorted.
    fn collect(
        &mut self,
        out: &mut Vec<(u32, u32)>,
        meets: impl Fn(&ParryTriangle, &ParryTriangle) -> bool,
    ) {
        out.clear();
        let Some(mesh) = &self.mesh else { return };
        self.candidates = self_leaf_pairs(mesh, &self.welded, |a, b| {
            if meets(&mesh.triangle(a), &mesh.triangle(b)) {
                out.push((a, b));
            }
        });
        out.sort_unstable();
        out.dedup();
    }

    /// Non-neighbouring candidate pairs of the last collection.
    pub fn candidates(&self) -> u64 {
        self.candidates
    }
}

/// Each triangle's corners of `mesh`, welded (equal positions, one id).
pub fn welded_corners(mesh: &TriMesh) -> Vec<[u32; 3]> {
    let weld = weld_positions(mesh);
    mesh.indices()
        .iter()
        .map(|t| t.map(|v| weld[v as usize]))
        .collect()
}

/// Per character of `scene`, its triangles' welded corners when the scene
/// tests characters against themselves; empty otherwise.
pub fn welded_when_self_collision(scene: &crate::scenario::Resolved) -> Vec<Vec<[u32; 3]>> {
    if !scene.self_collision {
        return Vec::new();
    }
    scene
        .characters
        .iter()
        .map(|a| welded_corners(&a.character.mesh))
        .collect()
}

/// Whether two triangles' welded corners share one: neighbours, never a
/// self contact.
#[inline]
pub fn share_a_corner(a: &[u32; 3], b: &[u32; 3]) -> bool {
    a.iter().any(|v| b.contains(v))
}

/// The candidates of a parry mesh against itself: its BVH's leaf pairs
/// against itself, each unordered pair once (`a < b`), pairs sharing a
/// welded corner (`welded`) dropped, each handed to `each`; returns how
/// many were.
pub fn self_leaf_pairs(
    mesh: &ParryMesh,
    welded: &[[u32; 3]],
    mut each: impl FnMut(u32, u32),
) -> u64 {
    let overlap = |a: &BvhNode, b: &BvhNode| a.intersects(b);
    let mut candidates = 0;
    for (a, b) in mesh.bvh().leaf_pairs(mesh.bvh(), overlap) {
        // Each unordered pair comes both ways: keep one.
        if a >= b {
            continue;
        }
        let (wa, wb) = (&welded[a as usize], &welded[b as usize]);
        if share_a_corner(wa, wb) {
            continue;
        }
        candidates += 1;
        each(a, b);
    }
    candidates
}

fn from_parry(t: &ParryTriangle) -> Triangle {
    let p = |v: PVector| Point::new(v.x, v.y, v.z);
    Triangle::new(p(t.a), p(t.b), p(t.c))
}
