//! The ground truth of a frame, for one character in a room or a whole
//! world, per pair kind: the exact oracle on parry's broad phase
//! ([`BodyPairTruth`], one per body pair) for every character against the
//! room, every character against every object, and every two characters;
//! parry's own answer beside it. Every command that scores a method reads
//! it: per kind (precision and recall), and per body pair in detail (false
//! positives with their distances, false negatives with their causes).
//!
//! * Against an object, the truth is taken in the object's frame: the
//!   character's skinned vertices are moved there by the inverse of the
//!   object's pose, as the methods move them.
//! * Two characters: the first one's posed mesh is the reference mesh of the
//!   frame (its BVH built anew each frame), the second one's is queried.
//! * Body pairs whose bounding boxes do not overlap have no pairs, and are
//!   not handed to parry.
//! * A character against itself (scenes with `self_collision`):
//!   [`SelfTruth`], its posed mesh's BVH against itself, neighbours
//!   dropped.

use nalgebra::Isometry3;
use serde::Serialize;

use super::self_truth::SelfTruth;
use super::{Accuracy, BodyPairTruth, MethodContext, MethodTruth, TruthError};
use crate::scenario::Resolved;
use cornertree::character::PoseBuffers;
use cornertree::geometry::{Point, bounds_of};
use cornertree::mesh::TriMesh;
use cornertree::world::{
    ByKind, CharacterHandle, CharacterPair, ObjectHandle, ObjectPair, RoomHandle, RoomPair,
    SelfPair, StepContacts,
};

/// This frame's pairs of every kind, sorted.
#[derive(Clone, Debug, Default, Serialize)]
pub struct WorldPairs {
    pub environment: Vec<RoomPair>,
    pub objects: Vec<ObjectPair>,
    pub characters: Vec<CharacterPair>,
    /// Each character against itself (scenes with `self_collision`).
    #[serde(rename = "self")]
    pub self_contact: Vec<SelfPair>,
}

/// The reference of the current frame.
pub struct Truth {
    room: Vec<BodyPairTruth>,
    /// `[character][object]`, built when first needed.
    objects: Vec<Vec<Option<BodyPairTruth>>>,
    /// Per character, against itself (empty when the scene does not ask).
    selves: Vec<SelfTruth>,
    moved: Vec<Point>,
    /// A method's pairs of one body pair, gathered for a detailed score.
    reported: Vec<(u32, u32)>,
    /// Exactly colliding pairs: the truth.
    pub exact: WorldPairs,
    /// parry's colliding pairs.
    pub parry: WorldPairs,
}

fn overlap(a: Option<(Point, Point)>, b: Option<(Point, Point)>) -> bool {
    match (a, b) {
        (Some((alo, ahi)), Some((blo, bhi))) => {
            (0..3).all(|i| alo[i] <= bhi[i] && blo[i] <= ahi[i])
        }
        _ => false,
    }
}

impl Truth {
    pub fn new(scene: &Resolved) -> Result<Self, TruthError> {
        let room = scene
            .characters
            .iter()
            .map(|a| BodyPairTruth::new(&scene.environment.mesh, a.character.mesh.indices()))
            .collect::<Result<_, _>>()?;
        Ok(Self {
            room,
            objects: scene
                .characters
                .iter()
                .map(|_| scene.objects.iter().map(|_| None).collect())
                .collect(),
            selves: if scene.self_collision {
                scene
                    .characters
                    .iter()
                    .map(|a| SelfTruth::new(&a.character.mesh))
                    .collect::<Result<_, _>>()?
            } else {
                Vec::new()
            },
            moved: Vec::new(),
            reported: Vec::new(),
            exact: WorldPairs::default(),
            parry: WorldPairs::default(),
        })
    }

    /// Computes the truth for the current frame: `buffers` skinned (every
    /// vertex), objects at `poses`.
    pub fn update(
        &mut self,
        scene: &Resolved,
        buffers: &[PoseBuffers],
        poses: &[Isometry3<f32>],
    ) -> Result<(), TruthError> {
        let (exact, parry) = (&mut self.exact, &mut self.parry);
        exact.environment.clear();
        parry.environment.clear();
        exact.objects.clear();
        parry.objects.clear();
        exact.characters.clear();
        parry.characters.clear();
        exact.self_contact.clear();
        parry.self_contact.clear();
        for (i, (t, b)) in self.selves.iter_mut().zip(buffers).enumerate() {
            t.update(&b.positions)?;
            let pair = |&(ta, tb): &(u32, u32)| SelfPair {
                character: CharacterHandle(i as u32),
                triangle_a: ta,
                triangle_b: tb,
            };
            exact.self_contact.extend(t.exact.iter().map(pair));
            parry.self_contact.extend(t.parry.iter().map(pair));
        }
        let boxes: Vec<_> = buffers
            .iter()
            .map(|b| bounds_of(b.positions.iter().copied()))
            .collect();
        for (i, (a, b)) in scene.characters.iter().zip(buffers).enumerate() {
            let indices = a.character.mesh.indices();
            let t = &mut self.room[i];
            t.update(&b.positions, indices, &scene.environment.mesh)?;
            let room = |&(c, e): &(u32, u32)| RoomPair {
                character: CharacterHandle(i as u32),
                triangle: c,
                room: RoomHandle(0),
                room_triangle: e,
            };
            exact.environment.extend(t.exact.iter().map(room));
            parry.environment.extend(t.parry.iter().map(room));
            for (o, (prop, pose)) in scene.objects.iter().zip(poses).enumerate() {
                let obox = bounds_of(prop.mesh.positions().iter().map(|p| pose * p));
                if !overlap(boxes[i], obox) {
                    continue;
                }
                let slot = &mut self.objects[i][o];
                if slot.is_none() {
                    *slot = Some(BodyPairTruth::new(&prop.mesh, indices)?);
                }
                let t = slot.as_mut().expect("just built");
                let inv = pose.inverse();
                self.moved.clear();
                self.moved.extend(b.positions.iter().map(|p| inv * p));
                t.update(&self.moved, indices, &prop.mesh)?;
                let pair = |&(c, e): &(u32, u32)| ObjectPair {
                    character: CharacterHandle(i as u32),
                    triangle: c,
                    object: ObjectHandle(o as u32),
                    object_triangle: e,
                };
                exact.objects.extend(t.exact.iter().map(pair));
                parry.objects.extend(t.parry.iter().map(pair));
            }
        }
        let n = scene.characters.len();
        for i in 0..n {
            for j in i + 1..n {
                if !overlap(boxes[i], boxes[j]) {
                    continue;
                }
                let (ai, aj) = (&scene.characters[i], &scene.characters[j]);
                let mesh_i = TriMesh::new(
                    buffers[i].positions.clone(),
                    ai.character.mesh.indices().to_vec(),
                )
                .map_err(|_| TruthError::NoTriangles("character"))?;
                let indices_j = aj.character.mesh.indices();
                let mut t = BodyPairTruth::new(&mesh_i, indices_j)?;
                t.update(&buffers[j].positions, indices_j, &mesh_i)?;
                // BodyPairTruth pairs are (queried triangle, reference triangle).
                let pair = |&(tj, ti): &(u32, u32)| CharacterPair {
                    a: CharacterHandle(i as u32),
                    triangle_a: ti,
                    b: CharacterHandle(j as u32),
                    triangle_b: tj,
                };
                exact.characters.extend(t.exact.iter().map(pair));
                parry.characters.extend(t.parry.iter().map(pair));
            }
        }
        for p in [&mut *exact, &mut *parry] {
            p.environment.sort_unstable();
            p.objects.sort_unstable();
            p.characters.sort_unstable();
            p.self_contact.sort_unstable();
        }
        Ok(())
    }

    /// A method's pairs against the truth, per kind.
    pub fn score(&self, outcome: &StepContacts) -> ByKind<Accuracy> {
        ByKind {
            environment: Accuracy::of_sorted(
                outcome.room_pairs.iter(),
                self.exact.environment.iter(),
            ),
            objects: Accuracy::of_sorted(outcome.object_pairs.iter(), self.exact.objects.iter()),
            characters: Accuracy::of_sorted(
                outcome.character_pairs.iter(),
                self.exact.characters.iter(),
            ),
            self_contact: Accuracy::of_sorted(
                outcome.self_pairs.iter(),
                self.exact.self_contact.iter(),
            ),
        }
    }

    /// Character `c`'s pairs with the room in `contacts`, scored in detail
    /// against the truth of its body pair: accuracy at three levels, false
    /// positives with their distances, false negatives with their causes,
    /// differences with parry's answer. `positions` are its skinned
    /// vertices this frame.
    pub fn room_detail(
        &mut self,
        c: usize,
        contacts: &StepContacts,
        scene: &Resolved,
        positions: &[Point],
        method: &MethodContext<'_>,
    ) -> Result<MethodTruth, TruthError> {
        self.reported.clear();
        self.reported.extend(
            contacts
                .room_contacts_of(CharacterHandle(c as u32))
                .iter()
                .map(|p| (p.triangle, p.room_triangle)),
        );
        let indices = scene.characters[c].character.mesh.indices();
        self.room[c].score(
            &self.reported,
            positions,
            indices,
            &scene.environment.mesh,
            method,
        )
    }

    /// Character `c`'s body pair with the room: its exact and parry pairs,
    /// parry's differences with the exact ones.
    pub fn room(&self, c: usize) -> &BodyPairTruth {
        &self.room[c]
    }

    /// Per kind, the exact pairs a character triangle of which `kept`
    /// (character index, triangle) says edge de-duplication removed: no
    /// method reports them (paper §4).
    pub fn removed_by_dedup(&self, kept: impl Fn(usize, u32) -> bool) -> ByKind<u64> {
        let e = &self.exact;
        let count = |it: &mut dyn Iterator<Item = bool>| it.filter(|&k| !k).count() as u64;
        ByKind {
            environment: count(
                &mut e
                    .environment
                    .iter()
                    .map(|p| kept(p.character.index(), p.triangle)),
            ),
            objects: count(
                &mut e
                    .objects
                    .iter()
                    .map(|p| kept(p.character.index(), p.triangle)),
            ),
            characters: count(
                &mut e
                    .characters
                    .iter()
                    .map(|p| kept(p.a.index(), p.triangle_a) && kept(p.b.index(), p.triangle_b)),
            ),
            self_contact: count(&mut e.self_contact.iter().map(|p| {
                kept(p.character.index(), p.triangle_a) && kept(p.character.index(), p.triangle_b)
            })),
        }
    }

    /// parry's pairs against the truth, per kind.
    pub fn parry_score(&self) -> ByKind<Accuracy> {
        ByKind {
            environment: Accuracy::of_sorted(
                self.parry.environment.iter(),
                self.exact.environment.iter(),
            ),
            objects: Accuracy::of_sorted(self.parry.objects.iter(), self.exact.objects.iter()),
            characters: Accuracy::of_sorted(
                self.parry.characters.iter(),
                self.exact.characters.iter(),
            ),
            self_contact: Accuracy::of_sorted(
                self.parry.self_contact.iter(),
                self.exact.self_contact.iter(),
            ),
        }
    }
}
