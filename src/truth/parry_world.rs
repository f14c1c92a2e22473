//! parry3d's answer for a whole world, written the way a Rust user of parry
//! would write it: the baseline `bench` and `scaling` time the methods
//! against.
//!
//! * The room is one `parry3d::shape::TriMesh` with its BVH, built once.
//! * Each character is a `TriMesh` built on its first pose and moved every
//!   frame with `TriMesh::update_vertices` (which refits its BVH); every
//!   vertex is skinned for it.
//! * Each moving object is a `TriMesh` whose vertices are set to the object's
//!   pose every frame (`update_vertices` from its rest positions, so poses do
//!   not accumulate rounding).
//! * Broad phase over the bodies: the meshes' root boxes (`local_aabb`), every
//!   two bodies; the room meets every character.
//! * For each body pair whose boxes overlap, `Bvh::leaf_pairs` gives the
//!   candidate triangle pairs and parry's `f32` `intersection_test`
//!   ([`parry_triangles_intersect`]) decides each.
//! * Scenes with `self_collision`: each character's BVH against itself,
//!   pairs sharing a welded corner dropped
//!   ([`self_leaf_pairs`](super::self_truth::self_leaf_pairs)), the same
//!   test.
//!
//! parry offers no parallel traversal of its own. On one thread it is
//! [`ParryWorld::update`] and [`ParryWorld::detect`]; on the caller's rayon
//! pool, as a user with cores to spare would write it, the characters'
//! `update_vertices` run side by side ([`ParryWorld::update_on_threads`]) and
//! so do the characters' body pairs, each character's pairs one task
//! ([`ParryWorld::detect_on_threads`]).

use nalgebra::Isometry3;
use parry3d::bounding_volume::BoundingVolume;
use parry3d::math::Vector as PVector;
use parry3d::partitioning::BvhNode;
use parry3d::shape::{TriMesh as ParryMesh, TriMeshFlags};

use super::TruthError;
use super::ground_truth::WorldPairs;
use super::parry_reference::parry_triangles_intersect;
use super::self_truth::{self_leaf_pairs, welded_when_self_collision};
use crate::scenario::Resolved;
use cornertree::character::PoseBuffers;
use cornertree::geometry::Point;
use cornertree::mesh::TriMesh;
use cornertree::world::{
    CharacterHandle, CharacterPair, ObjectHandle, ObjectPair, RoomHandle, RoomPair, SelfPair,
};

pub(crate) fn to_parry(p: &Point) -> PVector {
    PVector::new(p.x, p.y, p.z)
}

fn parry_mesh(mesh: &TriMesh, what: &'static str) -> Result<ParryMesh, TruthError> {
    let vertices = mesh.positions().iter().map(to_parry).collect();
    ParryMesh::new(vertices, mesh.indices().to_vec()).map_err(|_| TruthError::NoTriangles(what))
}

/// parry's pairs of every kind for the current frame of a world.
pub struct ParryWorld {
    room: ParryMesh,
    objects: Vec<ParryMesh>,
    object_rest: Vec<Vec<Point>>,
    character_indices: Vec<Vec<[u32; 3]>>,
    /// Per character, its triangles' welded corners, when the scene tests
    /// characters against themselves (empty otherwise).
    welded: Vec<Vec<[u32; 3]>>,
    /// Built on the first [`ParryWorld::update`].
    characters: Vec<Option<ParryMesh>>,
    /// This frame's pairs (parry's `f32` triangle test), sorted.
    pub pairs: WorldPairs,
    /// Leaf pairs the traversals yielded this frame.
    pub candidates: u64,
    /// Body pairs whose boxes overlapped this frame.
    pub body_pairs: u64,
}

impl ParryWorld {
    /// Builds the room's and the objects' meshes and BVHs.
    pub fn new(scene: &Resolved) -> Result<Self, TruthError> {
        Ok(Self {
            room: parry_mesh(&scene.environment.mesh, "environment")?,
            objects: scene
                .objects
                .iter()
                .map(|o| parry_mesh(&o.mesh, "object"))
                .collect::<Result<_, _>>()?,
            object_rest: scene
                .objects
                .iter()
                .map(|o| o.mesh.positions().to_vec())
                .collect(),
            character_indices: scene
                .characters
                .iter()
                .map(|a| a.character.mesh.indices().to_vec())
                .collect(),
            welded: welded_when_self_collision(scene),
            characters: scene.characters.iter().map(|_| None).collect(),
            pairs: WorldPairs::default(),
            candidates: 0,
            body_pairs: 0,
        })
    }

    /// Moves every body to this frame: characters' skinned vertices
    /// (`buffers[i].positions`, every vertex), objects to `poses`.
    pub fn update(
        &mut self,
        buffers: &[PoseBuffers],
        poses: &[Isometry3<f32>],
    ) -> Result<(), TruthError> {
        for ((slot, indices), b) in self
            .characters
            .iter_mut()
            .zip(&self.character_indices)
            .zip(buffers)
        {
            update_character(slot, indices, b)?;
        }
        self.update_objects(poses);
        Ok(())
    }

    /// [`Self::update`] with the characters side by side on the current
    /// rayon pool.
    pub fn update_on_threads(
        &mut self,
        buffers: &[PoseBuffers],
        poses: &[Isometry3<f32>],
    ) -> Result<(), TruthError> {
        use rayon::prelude::*;
        self.characters
            .par_iter_mut()
            .zip(&self.character_indices)
            .zip(buffers)
            .try_for_each(|((slot, indices), b)| update_character(slot, indices, b))?;
        self.update_objects(poses);
        Ok(())
    }

    fn update_objects(&mut self, poses: &[Isometry3<f32>]) {
        for ((mesh, rest), pose) in self.objects.iter_mut().zip(&self.object_rest).zip(poses) {
            mesh.update_vertices(|vs| {
                for (v, p) in vs.iter_mut().zip(rest) {
                    *v = to_parry(&(pose * p));
                }
            });
        }
    }

    /// The colliding pairs of every kind for the last [`Self::update`], by
    /// parry's `f32` triangle test, into [`Self::pairs`].
    pub fn detect(&mut self) {
        // Last frame's lists, emptied: one thread reuses them.
        let mut found = Found {
            pairs: std::mem::take(&mut self.pairs),
            ..Found::default()
        };
        found.pairs.environment.clear();
        found.pairs.objects.clear();
        found.pairs.characters.clear();
        found.pairs.self_contact.clear();
        for i in 0..self.characters.len() {
            self.detect_character(i, &mut found);
        }
        self.keep(found);
    }

    /// [`Self::detect`] on the current rayon pool: each character's body
    /// pairs (the room, the objects, the characters after it) one task.
    pub fn detect_on_threads(&mut self) {
        use rayon::prelude::*;
        let this = &*self;
        let found = (0..this.characters.len())
            .into_par_iter()
            .with_max_len(1)
            .fold(Found::default, |mut f, i| {
                this.detect_character(i, &mut f);
                f
            })
            .reduce(Found::default, Found::join);
        self.keep(found);
    }

    /// Keeps `found` as this frame's pairs, sorted.
    fn keep(&mut self, found: Found) {
        let Found {
            pairs,
            candidates,
            body_pairs,
        } = found;
        self.pairs = pairs;
        self.candidates = candidates;
        self.body_pairs = body_pairs;
        let p = &mut self.pairs;
        p.environment.sort_unstable();
        p.environment.dedup();
        p.objects.sort_unstable();
        p.objects.dedup();
        p.characters.sort_unstable();
        p.characters.dedup();
        p.self_contact.sort_unstable();
    }

    /// Character `i` against the room, itself (when the scene asks), every
    /// object and every character after it, into `out`.
    fn detect_character(&self, i: usize, out: &mut Found) {
        let Self {
            room,
            objects,
            characters,
            ..
        } = self;
        let Some(c) = &characters[i] else { return };
        let Found {
            pairs,
            candidates,
            body_pairs,
        } = out;
        let cbox = c.local_aabb();
        let h = CharacterHandle(i as u32);
        *body_pairs += 1;
        *candidates += touching(c, room, |t, rt| {
            pairs.environment.push(RoomPair {
                character: h,
                triangle: t,
                room: RoomHandle(0),
                room_triangle: rt,
            })
        });
        if let Some(welded) = self.welded.get(i) {
            *candidates += self_leaf_pairs(c, welded, |ta, tb| {
                if parry_triangles_intersect(&c.triangle(ta), &c.triangle(tb)) {
                    pairs.self_contact.push(SelfPair {
                        character: h,
                        triangle_a: ta,
                        triangle_b: tb,
                    });
                }
            });
        }
        for (o, obj) in objects.iter().enumerate() {
            if cbox.intersects(&obj.local_aabb()) {
                *body_pairs += 1;
                *candidates += touching(c, obj, |t, ot| {
                    pairs.objects.push(ObjectPair {
                        character: h,
                        triangle: t,
                        object: ObjectHandle(o as u32),
                        object_triangle: ot,
                    })
                });
            }
        }
        for (j, d) in characters.iter().enumerate().skip(i + 1) {
            let Some(d) = d else { continue };
            if cbox.intersects(&d.local_aabb()) {
                *body_pairs += 1;
                *candidates += touching(c, d, |ta, tb| {
                    pairs.characters.push(CharacterPair {
                        a: h,
                        triangle_a: ta,
                        b: CharacterHandle(j as u32),
                        triangle_b: tb,
                    })
                });
            }
        }
    }
}

/// The leaf pairs of `a`'s and `b`'s BVHs whose triangles parry's test
/// says intersect, each handed to `hit`; returns the leaf pairs tested.
fn touching(a: &ParryMesh, b: &ParryMesh, mut hit: impl FnMut(u32, u32)) -> u64 {
    let mut tested = 0;
    let overlap = |x: &BvhNode, y: &BvhNode| x.intersects(y);
    for (ta, tb) in a.bvh().leaf_pairs(b.bvh(), overlap) {
        tested += 1;
        if parry_triangles_intersect(&a.triangle(ta), &b.triangle(tb)) {
            hit(ta, tb);
        }
    }
    tested
}

/// Character `slot`'s mesh moved to `b`'s skinned vertices (built on the
/// first call).
pub(crate) fn update_character(
    slot: &mut Option<ParryMesh>,
    indices: &[[u32; 3]],
    b: &PoseBuffers,
) -> Result<(), TruthError> {
    let positions = &b.positions;
    if let Some(v) = positions
        .iter()
        .position(|p| !p.iter().all(|c| c.is_finite()))
    {
        return Err(TruthError::NonFinitePosition(v));
    }
    match slot {
        Some(mesh) => mesh.update_vertices(|vs| {
            for (v, p) in vs.iter_mut().zip(positions) {
                *v = to_parry(p);
            }
        }),
        None => {
            let vertices = positions.iter().map(to_parry).collect();
            *slot = Some(
                ParryMesh::with_flags(vertices, indices.to_vec(), TriMeshFlags::DEFORMABLE)
                    .map_err(|_| TruthError::NoTriangles("character"))?,
            );
        }
    }
    Ok(())
}

/// What some characters' body pairs found (one thread's share).
#[derive(Default)]
struct Found {
    pairs: WorldPairs,
    candidates: u64,
    body_pairs: u64,
}

impl Found {
    fn join(mut self, other: Found) -> Found {
        self.pairs.environment.extend(other.pairs.environment);
        self.pairs.objects.extend(other.pairs.objects);
        self.pairs.characters.extend(other.pairs.characters);
        self.pairs.self_contact.extend(other.pairs.self_contact);
        self.candidates += other.candidates;
        self.body_pairs += other.body_pairs;
        self
    }
}
