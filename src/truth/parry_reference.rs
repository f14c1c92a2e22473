//! The colliding triangle pairs of a frame, answered by parry3d 0.31.
//!
//! [`ParryReference`] keeps two `parry3d::shape::TriMesh`es, each with the BVH
//! parry builds for it: the environment's, built once, and the character's,
//! built on the first [`ParryReference::update`] and afterwards moved with
//! `TriMesh::update_vertices`. Per frame, `Bvh::leaf_pairs` walks the two BVHs
//! together and yields the leaf pairs whose boxes overlap (the candidates);
//! each candidate is decided by parry's `query::intersection_test` on the two
//! triangles, both in world coordinates with identity poses, in parry's `f64`
//! build ([`ParryReference::pairs`]), or by our exact oracle
//! ([`ParryReference::exact_pairs`]).
//!
//! parry 0.31 has no public exact triangle-triangle test: for two triangles
//! its default dispatcher runs GJK on their support maps, which answers
//! "intersecting" once the origin is within its tolerance of the Minkowski
//! difference. In `f32` ([`parry_triangles_intersect`]) pairs that miss by
//! up to about 1e-5 at unit scale go either way, a thin triangle's pair can
//! be reported when millimetres apart, and so can a small triangle against a
//! big one (4.16 mm on `touching.toml`). The `f64` build
//! ([`parry_f64_triangles_intersect`]) agrees with the exact oracle on every
//! frame of every shipped scenario, so it is parry's answer here.
//!
//! [`brute_force_pairs`] is an independent reference for small inputs: every
//! pair through the exact oracle ([`cornertree::geometry::exact::classify`]).

use parry3d::math::{Pose, Vector as PVector};
use parry3d::partitioning::BvhNode;
use parry3d::query;
use parry3d::shape::{TriMesh as ParryMesh, TriMeshFlags, Triangle as ParryTriangle};

use super::TruthError;
use cornertree::geometry::exact::{Contact, classify};
use cornertree::geometry::{Point, Triangle};
use cornertree::mesh::{TriMesh, TriangleId};

fn to_parry(p: &Point) -> PVector {
    PVector::new(p.x, p.y, p.z)
}

/// parry's answer for one animated character against one static environment.
#[derive(Clone)]
pub struct ParryReference {
    environment: ParryMesh,
    character_indices: Vec<[u32; 3]>,
    /// Built on the first pose; `None` before.
    character: Option<ParryMesh>,
    candidates: usize,
}

impl std::fmt::Debug for ParryReference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ParryReference")
            .field("environment_triangles", &self.environment.num_triangles())
            .field("character_triangles", &self.character_indices.len())
            .field("posed", &self.character.is_some())
            .field("candidates", &self.candidates)
            .finish()
    }
}

impl ParryReference {
    /// Builds the environment's parry mesh and BVH. The character's mesh needs
    /// positions, so it is built by the first [`Self::update`].
    pub fn new(environment: &TriMesh, character_indices: &[[u32; 3]]) -> Result<Self, TruthError> {
        if character_indices.is_empty() {
            return Err(TruthError::NoTriangles("character"));
        }
        let vertices = environment.positions().iter().map(to_parry).collect();
        // `TriMesh::new` only fails on an empty index list (our `TriMesh`
        // already checked indices and positions).
        let environment = ParryMesh::new(vertices, environment.indices().to_vec())
            .map_err(|_| TruthError::NoTriangles("environment"))?;
        Ok(Self {
            environment,
            character_indices: character_indices.to_vec(),
            character: None,
            candidates: 0,
        })
    }

    /// Takes this frame's posed character vertices (same indexing as the
    /// character mesh).
    ///
    /// The first call builds the character's parry mesh and BVH
    /// (`TriMesh::with_flags`, binned build). Later calls write the positions
    /// in place through `TriMesh::update_vertices`, which in parry 0.31
    /// **refits** the BVH (each leaf box recomputed, then
    /// `Bvh::refit_without_opt`): the tree keeps the topology built for the
    /// first pose, only its boxes move. No allocation after the first call.
    pub fn update(&mut self, positions: &[Point]) -> Result<(), TruthError> {
        if let Some(v) = positions
            .iter()
            .position(|p| !p.iter().all(|c| c.is_finite()))
        {
            return Err(TruthError::NonFinitePosition(v));
        }
        match &mut self.character {
            Some(mesh) => {
                let expected = mesh.vertices().len();
                if positions.len() != expected {
                    return Err(TruthError::VertexCountChanged {
                        expected,
                        got: positions.len(),
                    });
                }
                mesh.update_vertices(|vs| {
                    for (v, p) in vs.iter_mut().zip(positions) {
                        *v = to_parry(p);
                    }
                });
            }
            None => {
                for (triangle, tri) in self.character_indices.iter().enumerate() {
                    if let Some(&index) = tri.iter().find(|&&i| i as usize >= positions.len()) {
                        return Err(TruthError::IndexOutOfRange {
                            triangle,
                            index,
                            vertex_count: positions.len(),
                        });
                    }
                }
                let vertices = positions.iter().map(to_parry).collect();
                // DEFORMABLE only tells parry's contact manifolds that the
                // vertices move; the BVH is the same either way.
                let mesh = ParryMesh::with_flags(
                    vertices,
                    self.character_indices.clone(),
                    TriMeshFlags::DEFORMABLE,
                )
                .map_err(|_| TruthError::NoTriangles("character"))?;
                self.character = Some(mesh);
            }
        }
        Ok(())
    }

    /// The colliding `(character triangle, environment triangle)` pairs of the
    /// last pose by parry's triangle-triangle test (`f64` build), sorted and distinct, into
    /// `out` (cleared first). Empty before the first [`Self::update`].
    ///
    /// `out` is reused by the caller; parry's `LeafPairs` iterator keeps its
    /// stack in a 32-entry `SmallVec`, which spills to the heap only for deep
    /// tree pairs.
    pub fn pairs(&mut self, out: &mut Vec<(u32, u32)>) {
        self.collect(out, parry_f64_triangles_intersect);
    }

    /// Like [`Self::pairs`] with parry3d's `f32` test
    /// ([`parry_triangles_intersect`]): what a parry3d user would write, the
    /// baseline of `cornertree bench`.
    pub fn pairs_f32(&mut self, out: &mut Vec<(u32, u32)>) {
        self.collect(out, parry_triangles_intersect);
    }

    /// Like [`Self::pairs`], but each candidate is decided by the exact oracle
    /// (`classify != Disjoint`) instead of parry's GJK: parry's broad phase
    /// with an exact narrow phase.
    pub fn exact_pairs(&mut self, out: &mut Vec<(u32, u32)>) {
        self.collect(out, |t1, t2| {
            classify(&from_parry(t1), &from_parry(t2)) != Contact::Disjoint
        });
    }

    /// Candidates from `Bvh::leaf_pairs` (boxes overlap), kept if `meets`.
    fn collect(
        &mut self,
        out: &mut Vec<(u32, u32)>,
        meets: impl Fn(&ParryTriangle, &ParryTriangle) -> bool,
    ) {
        out.clear();
        self.candidates = 0;
        let Some(character) = &self.character else {
            return;
        };
        let environment = &self.environment;
        let overlap = |a: &BvhNode, b: &BvhNode| a.intersects(b);
        let mut candidates = 0;
        for (c, e) in character.bvh().leaf_pairs(environment.bvh(), overlap) {
            candidates += 1;
            // Leaf data is the triangle's index (`TriMesh` builds its BVH from
            // the enumerated index buffer).
            if meets(&character.triangle(c), &environment.triangle(e)) {
                out.push((c, e));
            }
        }
        self.candidates = candidates;
        out.sort_unstable();
        out.dedup();
    }

    /// Leaf pairs parry's traversal reached (and tested) in the last
    /// [`Self::pairs`]. The few pairs at the top of the traversal are yielded
    /// without a box check, so this can exceed the box-overlapping pairs by
    /// a handful.
    pub fn candidates(&self) -> usize {
        self.candidates
    }

    /// The environment's parry mesh.
    pub fn environment(&self) -> &ParryMesh {
        &self.environment
    }

    /// The character's parry mesh, once posed.
    pub fn character(&self) -> Option<&ParryMesh> {
        self.character.as_ref()
    }
}

/// `parry3d::query::intersection_test` (the `f32` build) on two triangles
/// given in one frame (GJK on support maps; the default dispatcher always
/// answers a triangle pair, so `Unsupported` cannot occur and would read as
/// "no contact"). What a Rust user of parry3d would call; not the reference.
///
/// It is not exact on triangles of very different sizes. Measured on
/// `scenarios/touching.toml` with de-duplication off (32 frames): 10 pairs
/// reported that the exact oracle says are apart, up to 4.16 mm (frame 3: a
/// 1.5 cm character triangle and the 8 m wall triangle beside the one it
/// pierces; parry's own `query::distance` also gives 4.16 mm), and none
/// missed. Deciding by `query::distance == 0` instead is worse: 69 truly
/// intersecting pairs missed over the same frames.
pub fn parry_triangles_intersect(t1: &ParryTriangle, t2: &ParryTriangle) -> bool {
    matches!(
        query::intersection_test(&Pose::IDENTITY, t1, &Pose::IDENTITY, t2),
        Ok(r) if r.intersecting
    )
}

/// The same test in parry's `f64` build (`parry3d-f64`), on the triangles'
/// `f32` corners widened exactly to `f64`: parry's answer in
/// [`ParryReference::pairs`]. On every frame of every shipped scenario
/// (de-duplication off) it agrees with the exact oracle pair for pair, where
/// the `f32` test reported 10 pairs up to 4.16 mm apart on `touching.toml`.
pub fn parry_f64_triangles_intersect(t1: &ParryTriangle, t2: &ParryTriangle) -> bool {
    use parry3d_f64::math::{Pose as Pose64, Vector as V64};
    let w = |v: PVector| V64::new(v.x as f64, v.y as f64, v.z as f64);
    let tri = |t: &ParryTriangle| parry3d_f64::shape::Triangle::new(w(t.a), w(t.b), w(t.c));
    matches!(
        parry3d_f64::query::intersection_test(&Pose64::IDENTITY, &tri(t1), &Pose64::IDENTITY, &tri(t2)),
        Ok(r) if r.intersecting
    )
}

/// Parry's triangle as ours (the same `f32` corners).
fn from_parry(t: &ParryTriangle) -> Triangle {
    let p = |v: PVector| Point::new(v.x, v.y, v.z);
    Triangle::new(p(t.a), p(t.b), p(t.c))
}

/// A triangle of ours as parry's.
pub fn parry_triangle(t: &Triangle) -> ParryTriangle {
    ParryTriangle::new(to_parry(&t.a), to_parry(&t.b), to_parry(&t.c))
}

/// Every (character triangle, environment triangle) pair the exact oracle
/// says meets (`classify != Disjoint`), sorted. All `n × m` pairs are tested:
/// for small inputs in tests only. A character triangle with an index out of
/// range of `character` is skipped.
pub fn brute_force_pairs(
    character: &[Point],
    indices: &[[u32; 3]],
    env: &TriMesh,
) -> Vec<(u32, u32)> {
    let mut out = Vec::new();
    for (c, tri) in indices.iter().enumerate() {
        let corner = |k: usize| character.get(tri[k] as usize).copied();
        let (Some(a), Some(b), Some(d)) = (corner(0), corner(1), corner(2)) else {
            continue;
        };
        let tc = Triangle::new(a, b, d);
        for e in 0..env.triangle_count() as u32 {
            if classify(&tc, &env.triangle(TriangleId(e))) != Contact::Disjoint {
                out.push((c as u32, e));
            }
        }
    }
    out
}
