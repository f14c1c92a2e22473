//! Continuous detection of a world over each frame step (issue 14; the
//! paper's future work, §7; docs/ccd.md, "Swept hierarchies").
//!
//! [`ContinuousWorld`] sits beside a [`World`] and reads it: the methods'
//! hierarchies (the characters' trees in their pipelines, the room's and the
//! objects' trees) and the pose of the current frame; it keeps the pose of
//! the previous frame and, per method and character, the refit states at
//! both ends ([`CharacterSweep`]). Over the step from frame `k − 1` to `k`
//! every vertex moves on a straight line between its positions at the two
//! frames (characters: skinned; objects: posed). Per method:
//!
//! 1. every character, in parallel: its swept tree against the room, the
//!    world broad phase on swept root spheres against every object swept
//!    along its motion, and the object passes;
//! 2. swept roots between characters, then each pair that meets (one after
//!    the other);
//! 3. the outcome: pairs with times of impact, sorted, and counters.
//!
//! Nothing is allocated per step once the buffers are sized
//! (`tests/no_alloc_ccd.rs`).

use std::time::Instant;

use nalgebra::{Isometry3, Vector3};
use rayon::prelude::*;

use crate::environment::RigidMotion;
use cornertree::character::PoseBuffers;
use cornertree::geometry::Sphere;
use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::geometry::ccd_sphere_plane::StillPlane;
use cornertree::pipeline::continuous::{
    Body, CharacterSweep, StepPose, detect_characters, room_planes,
};
use cornertree::pipeline::continuous_narrow::{CcdCounters, TimedPair};
use cornertree::pipeline::driver::FrameCounters;
use cornertree::sphere_tree::swept_rigid::RigidPath;
use cornertree::sphere_tree::traverse::LeafPair;
use cornertree::sphere_tree::{NodeId, Workspace};

use super::continuous_outcome::{ContinuousOutcome, Timed};
use super::motion::Motion;
use super::outcome::{CharacterPair, ObjectPair, RoomPair, add_counters};
use super::session::World;

/// Continuous detection beside a world.
pub struct ContinuousWorld {
    pub params: CcdParams,
    /// Each character posed at [`Self::prev_frame`] (joint and skin matrices).
    prev: Vec<PoseBuffers>,
    prev_poses: Vec<Isometry3<f32>>,
    prev_frame: Option<usize>,
    /// Each object's path over the step ending at `paths_frame`.
    paths: Vec<RigidPath>,
    paths_frame: Option<usize>,
    methods: Vec<MethodSweep>,
}

/// One method's continuous state.
struct MethodSweep {
    characters: Vec<CharacterSweep>,
    /// The planes of the room's big triangles (one per division).
    room_planes: Vec<StillPlane>,
    scratch: Vec<CharacterScratch>,
    /// The frame the characters' end states were refit for.
    last_end: Option<usize>,
    pair_leaves: Vec<LeafPair>,
    pair_workspace: Workspace,
    pair_out: Vec<TimedPair>,
    outcome: ContinuousOutcome,
}

#[derive(Default)]
struct CharacterScratch {
    root: Option<Sphere>,
    room: FrameCounters,
    objects: FrameCounters,
    ccd: CcdCounters,
    broad_phase_tests: u64,
    body_pairs: u64,
    room_pairs: Vec<TimedPair>,
    object_out: Vec<TimedPair>,
    object_pairs: Vec<Timed<ObjectPair>>,
}

impl ContinuousWorld {
    /// Continuous state for every method of `world`.
    pub fn new(world: &World, params: CcdParams) -> Self {
        let scene = &world.scene;
        let methods = world
            .methods
            .iter()
            .map(|mw| {
                let characters = mw
                    .character_pipelines()
                    .iter()
                    .zip(&scene.characters)
                    .map(|(p, a)| {
                        let p = p.lock().expect("no pass panicked");
                        CharacterSweep::new(&p.character_tree, &a.character)
                    })
                    .collect();
                MethodSweep {
                    characters,
                    room_planes: room_planes(&mw.room, &scene.environment.mesh),
                    scratch: scene
                        .characters
                        .iter()
                        .map(|_| CharacterScratch::default())
                        .collect(),
                    last_end: None,
                    pair_leaves: Vec::new(),
                    pair_workspace: Workspace::new(),
                    pair_out: Vec::new(),
                    outcome: ContinuousOutcome {
                        method: Some(mw.method),
                        ..Default::default()
                    },
                }
            })
            .collect();
        Self {
            params,
            prev: scene
                .characters
                .iter()
                .map(|a| PoseBuffers::new(&a.character))
                .collect(),
            prev_poses: vec![Isometry3::identity(); scene.objects.len()],
            prev_frame: None,
            paths: vec![RigidPath::still(Isometry3::identity()); scene.objects.len()],
            paths_frame: None,
            methods,
        }
    }

    /// Bytes [`ContinuousWorld::new`] and a step's reference
    /// (`truth::substep`) take beyond `world`, rounded up: per method and
    /// character, refit states, swept spheres and skinned vertices at both
    /// ends; per character, its previous pose and its triangles' boxes over
    /// a step. `None` past `usize`.
    pub fn estimated_bytes(world: &World) -> Option<usize> {
        let scene = &world.scene;
        let mut total = 0usize;
        for mw in &world.methods {
            for (p, a) in mw.character_pipelines().iter().zip(&scene.characters) {
                let nodes = p
                    .lock()
                    .expect("no pass panicked")
                    .character_tree
                    .tree
                    .len();
                let vertices = a.character.mesh.vertex_count();
                total = total
                    .checked_add(nodes.checked_mul(100)?)?
                    .checked_add(vertices.checked_mul(40)?)?;
            }
        }
        for a in &scene.characters {
            let (v, t) = (
                a.character.mesh.vertex_count(),
                a.character.mesh.triangle_count(),
            );
            total = total
                .checked_add(v.checked_mul(32)?)?
                .checked_add(t.checked_mul(200)?)?
                .checked_add(a.character.skeleton.len().checked_mul(400)?)?;
        }
        Some(total)
    }

    /// Method `m`'s outcome of the last step it detected.
    pub fn outcome(&self, m: usize) -> &ContinuousOutcome {
        &self.methods[m].outcome
    }

    /// Each character's pose at the start of the last step.
    pub fn start_poses(&self) -> &[PoseBuffers] {
        &self.prev
    }

    /// Each object's pose at the start of the last step.
    pub fn start_object_poses(&self) -> &[Isometry3<f32>] {
        &self.prev_poses
    }

    /// Each object's path over the last step.
    pub fn object_paths(&self) -> &[RigidPath] {
        &self.paths
    }

    /// Character `c`'s sweep state of method `m` (refit spheres at both
    /// ends of the last step).
    pub fn sweep(&self, m: usize, c: usize) -> &CharacterSweep {
        &self.methods[m].characters[c]
    }

    /// Detects the step from frame `k − 1` to `k` with method `m`; `world`
    /// is posed at frame `k` ([`World::pose`] or [`World::step`]). Frame 0
    /// has no step: its outcome is empty. Call [`Self::end_frame`] once
    /// every method has run.
    pub fn detect(&mut self, world: &mut World, k: usize, m: usize) {
        world.in_pool(|w| self.detect_in(w, k, m));
    }

    /// Every method of `world` over the step ending at frame `k`, then
    /// [`Self::end_frame`].
    pub fn detect_all(&mut self, world: &mut World, k: usize) {
        world.in_pool(|w| {
            for m in 0..self.methods.len() {
                self.detect_in(w, k, m);
            }
            self.end_frame(w, k);
        });
    }

    /// Remembers frame `k`'s pose (the world's, current) as the start of the
    /// next step. No allocation.
    pub fn end_frame(&mut self, world: &World, k: usize) {
        for (p, b) in self.prev.iter_mut().zip(&world.buffers) {
            p.skin.copy_from_slice(&b.skin);
            p.base = b.base;
        }
        self.prev_poses.copy_from_slice(&world.object_poses);
        self.prev_frame = Some(k);
    }

    /// Poses the previous frame if the last [`Self::end_frame`] was not it,
    /// and the objects' paths of the step.
    fn prepare(&mut self, world: &World, k: usize) {
        let scene = &world.scene;
        if self.prev_frame != Some(k - 1) {
            for (a, p) in scene.characters.iter().zip(&mut self.prev) {
                a.pose_frame(p, k - 1);
            }
            let t = scene.world_time(k - 1);
            for (o, p) in scene.objects.iter().zip(&mut self.prev_poses) {
                *p = o.motion.pose_at(t);
            }
            self.prev_frame = Some(k - 1);
        }
        if self.paths_frame != Some(k) {
            let (t0, t1) = (scene.world_time(k - 1), scene.world_time(k));
            for ((o, (path, from)), to) in scene
                .objects
                .iter()
                .zip(self.paths.iter_mut().zip(&self.prev_poses))
                .zip(&world.object_poses)
            {
                *path = rigid_path(&o.motion, t0, t1, *from, *to);
            }
            self.paths_frame = Some(k);
        }
    }

    fn detect_in(&mut self, world: &mut World, k: usize, m: usize) {
        let t_start = Instant::now();
        let method = world.methods[m].method;
        {
            let out = &mut self.methods[m].outcome;
            out.clear();
            out.method = Some(method);
        }
        if k == 0 || world.out_of_range().is_some() {
            return;
        }
        self.prepare(world, k);
        let params = self.params;
        let ContinuousWorld {
            prev,
            paths,
            methods,
            ..
        } = self;
        let ms = &mut methods[m];
        let continues = ms.last_end == Some(k - 1);
        ms.last_end = Some(k);
        let scene = &world.scene;
        let mw = &world.methods[m];
        let pipelines = mw.character_pipelines();
        let room = &*mw.room;
        let planes = &ms.room_planes[..];
        let objects = &mw.objects;
        let buffers = &world.buffers;
        let prev = &*prev;
        let paths = &*paths;
        // 1. Each character against the room and the objects.
        ms.characters
            .par_iter_mut()
            .zip(ms.scratch.par_iter_mut())
            .enumerate()
            .for_each(|(i, (sweep, s))| {
                let pipe = pipelines[i].lock().expect("no pass panicked");
                let body = body(scene, prev, buffers, i, &pipe.character_tree);
                sweep.begin_step(body.pose, continues);
                s.ccd = CcdCounters::default();
                s.room = sweep.detect_room(
                    &body,
                    room,
                    planes,
                    &scene.environment.mesh,
                    method,
                    &params,
                    &mut s.ccd,
                    &mut s.room_pairs,
                );
                s.root = sweep.root_sphere(&body);
                s.objects = FrameCounters::default();
                s.broad_phase_tests = 0;
                s.body_pairs = 0;
                s.object_pairs.clear();
                let Some(root) = s.root else { return };
                for (o, (tree, path)) in objects.iter().zip(paths).enumerate() {
                    if tree.tree.is_empty() {
                        continue;
                    }
                    s.broad_phase_tests += 1;
                    let oroot = path.sweep(&tree.tree.nodes()[NodeId::ROOT.index()].sphere);
                    if !root.overlaps(&oroot) {
                        continue;
                    }
                    s.body_pairs += 1;
                    let c = sweep.detect_object(
                        &body,
                        tree,
                        &scene.objects[o].mesh,
                        path,
                        &params,
                        &mut s.ccd,
                        &mut s.object_out,
                    );
                    add_counters(&mut s.objects, &c);
                    s.object_pairs.extend(s.object_out.iter().map(|p| Timed {
                        pair: ObjectPair {
                            character: i as u32,
                            triangle: p.a,
                            object: o as u32,
                            object_triangle: p.b,
                        },
                        toi: p.toi,
                        by_plane: p.by_plane,
                    }));
                }
            });

        // 2. Characters against each other.
        let out = &mut ms.outcome;
        out.frame = Some(k);
        let n = ms.characters.len();
        let mut char_tests = 0u64;
        let mut char_pairs = 0u64;
        for i in 0..n {
            let Some(ri) = ms.scratch[i].root else {
                continue;
            };
            for j in i + 1..n {
                let Some(rj) = ms.scratch[j].root else {
                    continue;
                };
                char_tests += 1;
                if !ri.overlaps(&rj) {
                    continue;
                }
                char_pairs += 1;
                let (lo, hi) = ms.characters.split_at_mut(j);
                let (sa, sb) = (&mut lo[i], &mut hi[0]);
                let pa = pipelines[i].lock().expect("no pass panicked");
                let pb = pipelines[j].lock().expect("no pass panicked");
                let c = detect_characters(
                    sa,
                    &body(scene, prev, buffers, i, &pa.character_tree),
                    sb,
                    &body(scene, prev, buffers, j, &pb.character_tree),
                    &params,
                    &mut ms.pair_leaves,
                    &mut ms.pair_workspace,
                    &mut out.ccd,
                    &mut ms.pair_out,
                );
                add_counters(&mut out.by_kind.characters, &c);
                out.character_pairs
                    .extend(ms.pair_out.iter().map(|p| Timed {
                        pair: CharacterPair {
                            a: i as u32,
                            triangle_a: p.a,
                            b: j as u32,
                            triangle_b: p.b,
                        },
                        toi: p.toi,
                        by_plane: false,
                    }));
            }
        }
        out.by_kind.characters.sphere_sphere += char_tests;

        // 3. The outcome, in a fixed order.
        out.broad_phase_tests = char_tests;
        out.body_pairs = char_pairs;
        let (mut refits, mut skinned) = (0, 0);
        for (i, (s, sweep)) in ms.scratch.iter().zip(&ms.characters).enumerate() {
            refits += sweep.refits();
            skinned += sweep.skinned();
            add_counters(&mut out.by_kind.environment, &s.room);
            add_counters(&mut out.by_kind.objects, &s.objects);
            out.by_kind.objects.sphere_sphere += s.broad_phase_tests;
            out.broad_phase_tests += s.broad_phase_tests;
            out.body_pairs += s.body_pairs;
            out.ccd.add(&s.ccd);
            out.object_pairs.extend_from_slice(&s.object_pairs);
            out.room_pairs.extend(s.room_pairs.iter().map(|p| Timed {
                pair: RoomPair {
                    character: i as u32,
                    triangle: p.a,
                    room_triangle: p.b,
                },
                toi: p.toi,
                by_plane: p.by_plane,
            }));
        }
        out.object_pairs.sort_unstable_by_key(|p| p.pair);
        out.character_pairs.sort_unstable_by_key(|p| p.pair);
        for kind in super::PairKind::ALL {
            add_counters(&mut out.total, out.by_kind.get(kind));
        }
        out.total.refits = refits;
        out.total.skinned_vertices = skinned;
        out.wall_ms = t_start.elapsed().as_secs_f64() * 1e3;
    }
}

/// Character `i` over the step, its tree `tree`.
fn body<'a>(
    scene: &'a crate::scenario::Resolved,
    prev: &'a [PoseBuffers],
    buffers: &'a [PoseBuffers],
    i: usize,
    tree: &'a cornertree::sphere_tree::character::CharacterTree,
) -> Body<'a> {
    let a = &scene.characters[i];
    Body {
        tree,
        character: &a.character,
        model: a.skinning,
        pose: StepPose {
            start: &prev[i],
            end: &buffers[i],
        },
    }
}

/// An object's path over the step from world time `t0` to `t1`, posed
/// `from` and `to` at those times: the path length of its rotation axis's
/// point and the angle it turns, summed over the motion's pieces inside
/// the step (`sphere_tree::swept_rigid`).
pub fn rigid_path(
    motion: &Motion,
    t0: f32,
    t1: f32,
    from: Isometry3<f32>,
    to: Isometry3<f32>,
) -> RigidPath {
    let mut path = RigidPath {
        from,
        to,
        travel: 0.0,
        turn: 0.0,
        axis_point: Vector3::zeros(),
    };
    match motion {
        Motion::Periodic(RigidMotion::Hinge {
            pivot,
            open,
            period,
            ..
        }) => {
            path.axis_point = pivot.coords;
            path.turn = open.abs() as f64 * phase_variation(*period, t0, t1);
        }
        Motion::Periodic(RigidMotion::Slide { travel, period }) => {
            path.travel = travel.norm() as f64 * phase_variation(*period, t0, t1);
        }
        Motion::Waypoints {
            times,
            positions,
            yaw_degrees,
        } => {
            // Piecewise linear between keys: sum over the pieces in the step.
            let at = |t: f32| {
                keyed(times, t, |i, j, f| {
                    let p = positions[i].lerp(&positions[j], f);
                    let y = yaw_degrees[i] + (yaw_degrees[j] - yaw_degrees[i]) * f;
                    (p.cast::<f64>(), (y as f64).to_radians())
                })
            };
            let (mut p, mut y) = at(t0);
            for t in times
                .iter()
                .copied()
                .filter(|&t| t > t0 && t < t1)
                .chain([t1])
            {
                let (q, z) = at(t);
                path.travel += (q - p).norm();
                path.turn += (z - y).abs();
                (p, y) = (q, z);
            }
        }
        Motion::Hinge { times, degrees, .. } => {
            let at = |t: f32| {
                keyed(times, t, |i, j, f| {
                    ((degrees[i] + (degrees[j] - degrees[i]) * f) as f64).to_radians()
                })
            };
            let mut a = at(t0);
            for t in times
                .iter()
                .copied()
                .filter(|&t| t > t0 && t < t1)
                .chain([t1])
            {
                let b = at(t);
                path.turn += (b - a).abs();
                a = b;
            }
        }
    }
    // Rounding of the keys' interpolation in `f32`: a relative margin.
    path.travel *= 1.0 + 1e-5;
    path.turn *= 1.0 + 1e-5;
    path
}

/// A keyed value at time `t`: `value(i, j, f)` between keys `i` and `j` at
/// fraction `f` (held before the first key and after the last).
fn keyed<R>(times: &[f32], t: f32, value: impl Fn(usize, usize, f32) -> R) -> R {
    let last = times.len() - 1;
    if times.len() == 1 || t <= times[0] {
        return value(0, 0, 0.0);
    }
    if t >= times[last] {
        return value(last, last, 0.0);
    }
    let j = times.partition_point(|&k| k <= t).clamp(1, last);
    let i = j - 1;
    value(
        i,
        j,
        ((t - times[i]) / (times[j] - times[i])).clamp(0.0, 1.0),
    )
}

/// Total variation of `(1 − cos(2πt/P))/2` over `[t0, t1]`: it is monotone
/// between multiples of `P/2`.
fn phase_variation(period: f32, t0: f32, t1: f32) -> f64 {
    let p = period as f64;
    let phase = |t: f64| 0.5 * (1.0 - (std::f64::consts::TAU * t / p).cos());
    let (a, b) = (t0 as f64, t1 as f64);
    let mut sum = 0.0;
    let mut from = a;
    let mut k = (2.0 * a / p).floor() + 1.0;
    while k * p / 2.0 < b {
        let turn = k * p / 2.0;
        sum += (phase(turn) - phase(from)).abs();
        from = turn;
        k += 1.0;
    }
    sum + (phase(b) - phase(from)).abs()
}
