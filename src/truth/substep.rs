//! The ground truth of continuous detection: the exact discrete oracle on
//! dense sub-steps of each frame step (docs/ccd.md, "Swept hierarchies").
//!
//! Over the step from frame `k − 1` to `k` every vertex moves on the
//! straight line between its two positions (characters: skinned; objects:
//! posed in `f32`, as every pass poses them). At each of `N + 1` sub-steps
//! `t = i / N` (`N = 256` by default) the corners are interpolated in `f64`
//! and every candidate pair is decided by `geometry::exact` (adaptive exact
//! predicates on the `f64` corners). Candidates are the pairs whose boxes
//! over the step overlap (each triangle's box of its six corners at both
//! ends, found with parry's BVH, `Bvh::leaf_pairs`): no contact at any `t`
//! can lie outside them. Nothing here shares code with the swept
//! hierarchies it checks.
//!
//! Every character triangle is considered, whether or not edge
//! de-duplication keeps it in the methods' trees.

use nalgebra::Isometry3;
use parry3d::bounding_volume::Aabb;
use parry3d::math::Vector as PVector;
use parry3d::partitioning::{Bvh, BvhBuildStrategy, BvhNode};
use serde::Serialize;

use super::self_truth::{share_a_corner, welded_when_self_collision};
use crate::scenario::Resolved;
use crate::session::Session;
use cornertree::geometry::Point;
use cornertree::geometry::exact::corners_intersect_exact;
use cornertree::mesh::TriMesh;
use cornertree::world::{
    CharacterHandle, CharacterPair, ObjectHandle, ObjectPair, RoomHandle, RoomPair, SelfPair,
};

/// A triangle's corners at both ends of a step (`f64`).
pub type MovingCorners = [[[f64; 3]; 3]; 2];

/// The bodies over one step: every character's skinned vertices and every
/// object's pose at both ends.
pub struct StepBodies<'a> {
    pub scene: &'a Resolved,
    pub start: Vec<&'a [Point]>,
    pub end: Vec<&'a [Point]>,
    pub object_start: &'a [Isometry3<f32>],
    pub object_end: &'a [Isometry3<f32>],
}

fn wide(p: &Point) -> [f64; 3] {
    [p.x as f64, p.y as f64, p.z as f64]
}

impl<'a> StepBodies<'a> {
    /// The step from the previous frame (each character's vertices and each
    /// object's pose then) to the session's current one.
    pub fn between(
        prev_positions: &'a [Vec<Point>],
        prev_poses: &'a [Isometry3<f32>],
        session: &'a Session,
    ) -> Self {
        StepBodies {
            scene: &session.scene,
            start: prev_positions.iter().map(Vec::as_slice).collect(),
            end: session
                .buffers
                .iter()
                .map(|b| b.positions.as_slice())
                .collect(),
            object_start: prev_poses,
            object_end: &session.object_poses,
        }
    }

    /// Character `c`'s triangle `t` at both ends.
    pub fn character_triangle(&self, c: usize, t: u32) -> MovingCorners {
        let idx = self.scene.characters[c].character.mesh.indices()[t as usize];
        [
            idx.map(|v| wide(&self.start[c][v as usize])),
            idx.map(|v| wide(&self.end[c][v as usize])),
        ]
    }

    /// Room triangle `t` (still).
    pub fn room_triangle(&self, t: u32) -> MovingCorners {
        let c = self.scene.environment.mesh.indices()[t as usize];
        let p = self.scene.environment.mesh.positions();
        let x = c.map(|v| wide(&p[v as usize]));
        [x, x]
    }

    /// Object `o`'s triangle `t` posed at both ends.
    pub fn object_triangle(&self, o: usize, t: u32) -> MovingCorners {
        let mesh = &self.scene.objects[o].mesh;
        let c = mesh.indices()[t as usize];
        let p = mesh.positions();
        let at = |pose: &Isometry3<f32>| c.map(|v| wide(&(pose * p[v as usize])));
        [at(&self.object_start[o]), at(&self.object_end[o])]
    }
}

/// Corners at `t` of a step (`f64` interpolation).
pub fn corners_at(m: &MovingCorners, t: f64) -> [[f64; 3]; 3] {
    let mut out = [[0.0; 3]; 3];
    for (o, (a, b)) in out.iter_mut().zip(m[0].iter().zip(&m[1])) {
        for k in 0..3 {
            o[k] = a[k] + t * (b[k] - a[k]);
        }
    }
    out
}

fn boxes_apart(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> bool {
    (0..3).any(|k| {
        let lo = |t: &[[f64; 3]; 3]| t[0][k].min(t[1][k]).min(t[2][k]);
        let hi = |t: &[[f64; 3]; 3]| t[0][k].max(t[1][k]).max(t[2][k]);
        hi(a) < lo(b) || hi(b) < lo(a)
    })
}

/// Whether the two moving triangles touch at sub-step `t`.
pub fn touch_at(a: &MovingCorners, b: &MovingCorners, t: f64) -> bool {
    let (x, y) = (corners_at(a, t), corners_at(b, t));
    !boxes_apart(&x, &y) && corners_intersect_exact(&x, &y)
}

/// The first of `n + 1` sub-steps `i / n` at which the pair touches.
pub fn first_substep(a: &MovingCorners, b: &MovingCorners, n: u32) -> Option<u32> {
    (0..=n).find(|&i| touch_at(a, b, i as f64 / n as f64))
}

/// A pair of the step's reference, with the first sub-step it touches at.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Found<P> {
    #[serde(flatten)]
    pub pair: P,
    pub first_substep: u32,
}

/// The reference of one step.
pub struct SubstepTruth {
    pub substeps: u32,
    room: Bvh,
    /// Pairs of every kind touching at some sub-step, sorted.
    pub room_pairs: Vec<Found<RoomPair>>,
    pub object_pairs: Vec<Found<ObjectPair>>,
    pub character_pairs: Vec<Found<CharacterPair>>,
    /// Each character against itself (scenes with `self_collision`):
    /// pairs sharing a welded corner never count.
    pub self_pairs: Vec<Found<SelfPair>>,
    /// Per character, its triangles' welded corners, when the scene tests
    /// characters against themselves (empty otherwise).
    welded: Vec<Vec<[u32; 3]>>,
    /// Candidate pairs (boxes over the step overlap) decided this step.
    pub candidates: u64,
}

fn aabb(points: impl Iterator<Item = [f64; 3]>) -> Aabb {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in points {
        for k in 0..3 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    // Outward to `f32` (interpolated corners stay within the corners' box
    // up to an `f64` rounding, far below an `f32` step).
    let down = |x: f64| (x as f32).next_down();
    let up = |x: f64| (x as f32).next_up();
    Aabb::new(
        PVector::new(down(lo[0]), down(lo[1]), down(lo[2])),
        PVector::new(up(hi[0]), up(hi[1]), up(hi[2])),
    )
}

fn swept_boxes(n: usize, corners: impl Fn(usize) -> MovingCorners) -> Vec<Aabb> {
    (0..n)
        .map(|t| {
            let m = corners(t);
            aabb(m[0].iter().chain(&m[1]).copied())
        })
        .collect()
}

fn mesh_boxes(mesh: &TriMesh) -> Vec<Aabb> {
    let p = mesh.positions();
    mesh.indices()
        .iter()
        .map(|c| aabb(c.iter().map(|&v| wide(&p[v as usize]))))
        .collect()
}

fn overlap(a: &BvhNode, b: &BvhNode) -> bool {
    a.intersects(b)
}

impl SubstepTruth {
    pub fn new(scene: &Resolved, substeps: u32) -> Self {
        Self {
            substeps: substeps.max(1),
            room: Bvh::from_leaves(
                BvhBuildStrategy::Binned,
                &mesh_boxes(&scene.environment.mesh),
            ),
            room_pairs: Vec::new(),
            object_pairs: Vec::new(),
            character_pairs: Vec::new(),
            self_pairs: Vec::new(),
            welded: welded_when_self_collision(scene),
            candidates: 0,
        }
    }

    /// Decides the step between the two poses of `bodies`.
    pub fn update(&mut self, bodies: &StepBodies<'_>) {
        let n = self.substeps;
        self.room_pairs.clear();
        self.object_pairs.clear();
        self.character_pairs.clear();
        self.self_pairs.clear();
        self.candidates = 0;
        let scene = bodies.scene;
        let characters: Vec<Bvh> = scene
            .characters
            .iter()
            .enumerate()
            .map(|(c, a)| {
                let boxes = swept_boxes(a.character.mesh.triangle_count(), |t| {
                    bodies.character_triangle(c, t as u32)
                });
                Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes)
            })
            .collect();
        let objects: Vec<Bvh> = scene
            .objects
            .iter()
            .enumerate()
            .map(|(o, prop)| {
                let boxes = swept_boxes(prop.mesh.triangle_count(), |t| {
                    bodies.object_triangle(o, t as u32)
                });
                Bvh::from_leaves(BvhBuildStrategy::Binned, &boxes)
            })
            .collect();
        let mut candidates = 0u64;
        for (c, cb) in characters.iter().enumerate() {
            if let Some(welded) = self.welded.get(c) {
                for (ta, tb) in cb.leaf_pairs(cb, overlap) {
                    // Each unordered pair once; neighbours never count.
                    let (wa, wb) = (&welded[ta as usize], &welded[tb as usize]);
                    if ta >= tb || share_a_corner(wa, wb) {
                        continue;
                    }
                    candidates += 1;
                    let a = bodies.character_triangle(c, ta);
                    let b = bodies.character_triangle(c, tb);
                    if let Some(i) = first_substep(&a, &b, n) {
                        self.self_pairs.push(Found {
                            pair: SelfPair {
                                character: CharacterHandle(c as u32),
                                triangle_a: ta,
                                triangle_b: tb,
                            },
                            first_substep: i,
                        });
                    }
                }
            }
            for (t, rt) in cb.leaf_pairs(&self.room, overlap) {
                candidates += 1;
                let a = bodies.character_triangle(c, t);
                let b = bodies.room_triangle(rt);
                if let Some(i) = first_substep(&a, &b, n) {
                    self.room_pairs.push(Found {
                        pair: RoomPair {
                            character: CharacterHandle(c as u32),
                            triangle: t,
                            room: RoomHandle(0),
                            room_triangle: rt,
                        },
                        first_substep: i,
                    });
                }
            }
            for (o, ob) in objects.iter().enumerate() {
                for (t, ot) in cb.leaf_pairs(ob, overlap) {
                    candidates += 1;
                    let a = bodies.character_triangle(c, t);
                    let b = bodies.object_triangle(o, ot);
                    if let Some(i) = first_substep(&a, &b, n) {
                        self.object_pairs.push(Found {
                            pair: ObjectPair {
                                character: CharacterHandle(c as u32),
                                triangle: t,
                                object: ObjectHandle(o as u32),
                                object_triangle: ot,
                            },
                            first_substep: i,
                        });
                    }
                }
            }
            for (d, db) in characters.iter().enumerate().skip(c + 1) {
                for (ta, tb) in cb.leaf_pairs(db, overlap) {
                    candidates += 1;
                    let a = bodies.character_triangle(c, ta);
                    let b = bodies.character_triangle(d, tb);
                    if let Some(i) = first_substep(&a, &b, n) {
                        self.character_pairs.push(Found {
                            pair: CharacterPair {
                                a: CharacterHandle(c as u32),
                                triangle_a: ta,
                                b: CharacterHandle(d as u32),
                                triangle_b: tb,
                            },
                            first_substep: i,
                        });
                    }
                }
            }
        }
        self.candidates = candidates;
        self.room_pairs.sort_unstable_by_key(|p| p.pair);
        self.room_pairs.dedup_by(|a, b| a.pair == b.pair);
        self.object_pairs.sort_unstable_by_key(|p| p.pair);
        self.object_pairs.dedup_by(|a, b| a.pair == b.pair);
        self.character_pairs.sort_unstable_by_key(|p| p.pair);
        self.character_pairs.dedup_by(|a, b| a.pair == b.pair);
        self.self_pairs.sort_unstable_by_key(|p| p.pair);
        self.self_pairs.dedup_by(|a, b| a.pair == b.pair);
    }

    /// Pairs of every kind.
    pub fn len(&self) -> usize {
        self.room_pairs.len()
            + self.object_pairs.len()
            + self.character_pairs.len()
            + self.self_pairs.len()
    }

    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}
