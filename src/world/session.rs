//! The frame loop of a world, as a library piece: [`World`] owns the
//! characters, the moving objects, the room and every chosen method's
//! hierarchies; [`World::step`] plays one frame through every method.
//!
//! Per method and frame:
//! 1. every character starts its frame (spheres and skinned vertices stale)
//!    and refits its root sphere;
//! 2. the broad phase between characters' root spheres lists the character
//!    pairs to traverse;
//! 3. every pass runs on the pool's threads ([`PassGraph`]): each
//!    character's pass against the room (exactly the one-character pipeline
//!    of `pipeline::driver`), the world broad phase against every object's
//!    root sphere at its pose and the pass against each object it meets;
//!    then its passes against the characters it meets, in any order, one
//!    at a time (each refits and skins both characters on demand). A pass
//!    starts as soon as its characters are free: no barrier between the
//!    room passes and the character pairs.
//!
//! Which thread runs what never changes a counter or a pair: a pass's tests
//! do not depend on which spheres were refit before it, and each sphere and
//! vertex is refit or skinned at most once a frame whichever pass asks
//! first. A character's own pass runs before its pairs, so the refits and
//! skinned vertices counted for the room and objects are the same on any
//! thread, and those counted for the character pairs add up to the rest.
//! Pairs are sorted at the end of the frame.

use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use nalgebra::Isometry3;
use rayon::prelude::*;

use crate::scenario::Resolved;
use cornertree::character::PoseBuffers;
use cornertree::geometry::Sphere;
use cornertree::io::limits::MAX_COORDINATE;
use cornertree::mesh::{EdgeDedup, dedup_edges};
use cornertree::pipeline::bodies::{CharacterPairScratch, detect_characters, sphere_in_frame};
use cornertree::pipeline::driver::{FrameCounters, Pipeline};
use cornertree::pipeline::{EnvironmentTree, Method};
use cornertree::sphere_tree::NodeId;

use super::outcome::{CharacterPair, MethodOutcome, ObjectPair, RoomPair, add_counters};
use super::pass_graph::PassGraph;
use super::pinning::pinned_pool;

/// A world being played.
pub struct World {
    /// The bodies, the room and the run's settings.
    pub scene: Resolved,
    pub methods: Vec<MethodWorld>,
    /// Each character posed and placed for the current frame (joint
    /// matrices; vertices only when [`World::skin_all`] was called).
    pub buffers: Vec<PoseBuffers>,
    /// Each object's pose (object frame → world) this frame.
    pub object_poses: Vec<Isometry3<f32>>,
    /// Milliseconds spent posing every character this frame.
    pub pose_ms: f64,
    /// Each character's bind vertices' largest distance from its origin.
    bind_reach: Vec<f32>,
    /// How far each character's vertices may reach from the origin this
    /// frame ([`PoseBuffers::reach`]).
    reach: Vec<f32>,
    /// A character posed beyond [`MAX_COORDINATE`] this frame, and how far
    /// (the frame is then not detected).
    out_of_range: Option<(usize, f32)>,
    /// The next frame to play.
    next: usize,
    pool: Arc<rayon::ThreadPool>,
    /// One thread, for [`World::detect_method_on_one_thread`].
    serial: rayon::ThreadPool,
    threads: usize,
}

/// One method's hierarchies and per-frame state in a world.
pub struct MethodWorld {
    pub method: Method,
    /// The room's hierarchy (shared by the characters' pipelines).
    pub room: Arc<EnvironmentTree>,
    /// Each object's hierarchy, in the object's frame.
    pub objects: Vec<EnvironmentTree>,
    /// One pipeline per character (its tree, refit state and the room).
    characters: Vec<Mutex<Pipeline>>,
    per_character: Vec<Mutex<CharacterScratch>>,
    object_roots: Vec<Option<Sphere>>,
    /// Character pairs whose roots met this frame, `(i, j)` with `i < j`.
    candidates: Vec<(u32, u32)>,
    pair_scratch: Vec<Mutex<PairScratch>>,
    /// The frame's passes and the order they may run in.
    graph: PassGraph,
    /// This frame's outcome.
    pub outcome: MethodOutcome,
}

#[derive(Default)]
struct CharacterScratch {
    root: Option<Sphere>,
    room: FrameCounters,
    objects: FrameCounters,
    broad_phase_tests: u64,
    body_pairs: u64,
    object_pairs: Vec<ObjectPair>,
    pairs: Vec<(u32, u32)>,
}

struct PairScratch {
    a: u32,
    b: u32,
    counters: FrameCounters,
    pairs: Vec<(u32, u32)>,
    scratch: CharacterPairScratch,
}

impl World {
    /// Builds every method's hierarchies for the scene, on `threads` threads
    /// (0: one per core).
    pub fn new(scene: Resolved, threads: usize) -> Result<Self, rayon::ThreadPoolBuildError> {
        let pool = Arc::new(pinned_pool(threads)?);
        let threads = pool.current_num_threads();
        let serial = rayon::ThreadPoolBuilder::new().num_threads(1).build()?;
        let dedups: Vec<EdgeDedup> = scene
            .characters
            .iter()
            .map(|a| {
                if scene.dedup {
                    dedup_edges(&a.character.mesh)
                } else {
                    EdgeDedup::keep_all(&a.character.mesh)
                }
            })
            .collect();
        let methods = pool.install(|| {
            scene
                .methods
                .par_iter()
                .map(|&m| MethodWorld::build(&scene, m, &dedups))
                .collect()
        });
        let buffers = scene
            .characters
            .iter()
            .map(|a| PoseBuffers::new(&a.character))
            .collect();
        let object_poses = vec![Isometry3::identity(); scene.objects.len()];
        let bind_reach: Vec<f32> = scene
            .characters
            .iter()
            .map(|a| {
                a.character
                    .mesh
                    .positions()
                    .iter()
                    .map(|p| p.coords.norm())
                    .fold(0.0, f32::max)
            })
            .collect();
        Ok(Self {
            scene,
            methods,
            buffers,
            object_poses,
            pose_ms: 0.0,
            reach: vec![0.0; bind_reach.len()],
            bind_reach,
            out_of_range: None,
            next: 0,
            pool,
            serial,
            threads,
        })
    }

    /// Threads the frames run on.
    pub fn threads(&self) -> usize {
        self.threads
    }

    /// Runs `f` on one of the world's threads, so that the frames it plays
    /// hand no job over to the pool: each [`World::step`] from outside the
    /// pool queues one, and rayon's queue allocates a block every few dozen
    /// jobs; inside, a frame allocates nothing once its buffers are sized
    /// (`tests/no_alloc.rs`).
    pub fn in_pool<R: Send>(&mut self, f: impl FnOnce(&mut World) -> R + Send) -> R {
        let pool = self.pool.clone();
        pool.install(|| f(self))
    }

    /// Runs later frames on `threads` threads (0: one per core).
    pub fn set_threads(&mut self, threads: usize) -> Result<(), rayon::ThreadPoolBuildError> {
        self.pool = Arc::new(pinned_pool(threads)?);
        self.threads = self.pool.current_num_threads();
        Ok(())
    }

    /// Frames in the scenario.
    pub fn frames(&self) -> usize {
        self.scene.frames
    }

    /// The frame [`World::step`] plays next.
    pub fn next_frame(&self) -> usize {
        self.next
    }

    /// Plays frame `k` from here on (frames are independent: any order works).
    pub fn seek(&mut self, k: usize) {
        self.next = k;
    }

    /// Poses every body for frame `k` (joint matrices and object poses),
    /// the characters side by side on the world's threads (their buffers
    /// are their own). A character whose pose takes a vertex beyond
    /// [`MAX_COORDINATE`] (a clip with absurd keyframes) is noted
    /// ([`World::out_of_range`]) and the frame is not detected: such
    /// coordinates overflow squared distances.
    pub fn pose(&mut self, k: usize) {
        self.pose_in(k, false);
    }

    /// Like [`World::pose`] on the calling thread alone (`bench` times a
    /// one-thread frame with a one-thread pose).
    pub fn pose_on_one_thread(&mut self, k: usize) {
        self.pose_in(k, true);
    }

    fn pose_in(&mut self, k: usize, one_thread: bool) {
        let World {
            scene,
            buffers,
            object_poses,
            bind_reach,
            reach,
            out_of_range,
            pool,
            ..
        } = self;
        let actors = &scene.characters;
        let parallel = !one_thread && actors.len() > 1 && pool.current_num_threads() > 1;
        let chunk = actors.len().div_ceil(pool.current_num_threads());
        let mut pose_all = || {
            let t0 = Instant::now();
            side_by_side(buffers, reach, parallel.then_some(chunk), |i, b, r| {
                actors[i].pose_frame(b, k);
                *r = b.reach(bind_reach[i]);
            });
            *out_of_range = reach
                .iter()
                .position(|r| !(r.is_finite() && *r <= MAX_COORDINATE))
                .map(|i| (i, reach[i]));
            let t = scene.world_time(k);
            for (o, p) in scene.objects.iter().zip(object_poses.iter_mut()) {
                *p = o.motion.pose_at(t);
            }
            t0.elapsed().as_secs_f64() * 1e3
        };
        self.pose_ms = if !parallel || pool.current_thread_index().is_some() {
            pose_all()
        } else {
            // As a frame's passes (see [`with_threads_awake`]): timed once
            // every thread is awake.
            let go = AtomicBool::new(false);
            let mut ms = 0.0;
            pool.install(|| {
                with_threads_awake(&go, || {
                    go.store(true, Ordering::Release);
                    ms = pose_all();
                })
            });
            ms
        };
    }

    /// Skins every vertex of every character for the current pose (for the
    /// ground truth, recordings and dumps; no method's work or time).
    pub fn skin_all(&mut self) {
        for (a, b) in self.scene.characters.iter().zip(&mut self.buffers) {
            b.skin_all(&a.character, a.skinning);
        }
    }

    /// Plays the next frame through every method; returns its index, or
    /// `None` past the last frame. Outcomes are in `methods[m].outcome`.
    pub fn step(&mut self) -> Option<usize> {
        let k = self.next;
        if k >= self.scene.frames {
            return None;
        }
        self.pose(k);
        self.detect_all();
        self.next = k + 1;
        Some(k)
    }

    /// Runs every method on the current pose.
    pub fn detect_all(&mut self) {
        for m in 0..self.methods.len() {
            self.detect_method(m);
        }
    }

    /// The first character posed out of range this frame, and how far its
    /// vertices may reach from the origin (see [`World::pose`]).
    pub fn out_of_range(&self) -> Option<(usize, f32)> {
        self.out_of_range
    }

    /// Runs method `m` (an index into `methods`) on the current pose (not
    /// when a character is posed out of range: the outcome is then empty).
    pub fn detect_method(&mut self, m: usize) {
        self.detect_method_in(m, false);
    }

    /// Like [`World::detect_method`] on one thread, whatever
    /// [`World::threads`] says (`bench` measures both in one run).
    pub fn detect_method_on_one_thread(&mut self, m: usize) {
        self.detect_method_in(m, true);
    }

    fn detect_method_in(&mut self, m: usize, one_thread: bool) {
        if self.out_of_range.is_some() {
            let mw = &mut self.methods[m];
            mw.outcome = MethodOutcome {
                method: Some(mw.method),
                ..MethodOutcome::default()
            };
            return;
        }
        let World {
            scene,
            methods,
            buffers,
            object_poses,
            pose_ms,
            pool,
            serial,
            ..
        } = self;
        let mw = &mut methods[m];
        let pool: &rayon::ThreadPool = if one_thread { serial } else { pool };
        // Inside the pool already (see [`World::in_pool`]): no job to hand
        // over to it. One character is one pass: it runs on the calling
        // thread, as handing it to a pool thread and back costs two thread
        // wake-ups (on this machine 0.30 ms of wall time per frame of
        // `touching.toml` against 0.16 ms of detection).
        if pool.current_thread_index().is_some() || mw.characters.len() <= 1 {
            mw.detect(scene, buffers, object_poses, None);
        } else {
            // Several characters: their passes may run side by side, on
            // threads awake from the start.
            let go = AtomicBool::new(false);
            pool.install(|| {
                with_threads_awake(&go, || mw.detect(scene, buffers, object_poses, Some(&go)))
            });
        }
        mw.outcome.total.time.pose_ms = *pose_ms;
    }

    /// Times each sphere refit apart from the traversal (on by default;
    /// `bench` turns it off: the timers cost time).
    pub fn set_refit_timing(&mut self, on: bool) {
        for mw in &mut self.methods {
            for p in mw.pipelines() {
                p.set_refit_timing(on);
            }
        }
    }
}

impl MethodWorld {
    fn build(scene: &Resolved, method: Method, dedups: &[EdgeDedup]) -> Self {
        let build = cornertree::sphere_tree::BuildParams::default();
        let room = Arc::new(EnvironmentTree::build(
            &scene.environment.mesh,
            method,
            scene.threshold,
            build,
        ));
        let objects = scene
            .objects
            .iter()
            .map(|o| EnvironmentTree::build(&o.mesh, method, scene.threshold, build))
            .collect();
        let characters = scene
            .characters
            .iter()
            .zip(dedups)
            .map(|(a, d)| {
                Mutex::new(Pipeline::with_environment(
                    &a.character,
                    room.clone(),
                    method,
                    scene.pipeline_options(a),
                    d,
                ))
            })
            .collect();
        let n = scene.characters.len();
        Self {
            method,
            room,
            objects,
            characters,
            per_character: (0..n).map(|_| Mutex::default()).collect(),
            object_roots: vec![None; scene.objects.len()],
            candidates: Vec::new(),
            pair_scratch: Vec::new(),
            graph: PassGraph::new(n),
            outcome: MethodOutcome {
                method: Some(method),
                ..MethodOutcome::default()
            },
        }
    }

    /// Character `c`'s pipeline (its tree, refit state, room pairs).
    pub fn pipeline(&mut self, c: usize) -> &mut Pipeline {
        self.characters[c].get_mut().expect("no pass panicked")
    }

    /// Character `c`'s root sphere this frame (`None`: an empty tree).
    fn character_root(&mut self, c: usize) -> Option<Sphere> {
        self.per_character[c]
            .get_mut()
            .expect("no pass panicked")
            .root
    }

    /// Every character's pipeline behind its lock (for passes run beside
    /// the frame's, such as continuous detection, which read their trees).
    pub fn character_pipelines(&self) -> &[Mutex<Pipeline>] {
        &self.characters
    }

    /// Every character's pipeline, in order.
    pub fn pipelines(&mut self) -> impl Iterator<Item = &mut Pipeline> {
        self.characters
            .iter_mut()
            .map(|p| p.get_mut().expect("no pass panicked"))
    }

    /// Bytes of every hierarchy: the characters', the room's once, the objects'.
    pub fn hierarchy_bytes(&mut self) -> usize {
        let room = self.room.bytes();
        let objects: usize = self.objects.iter().map(EnvironmentTree::bytes).sum();
        let characters: usize = self
            .pipelines()
            .map(|p| p.character_tree.tree.bytes())
            .sum();
        room + objects + characters
    }

    /// The frame. `helpers_go`, when given, is set as the passes start
    /// (see [`with_threads_awake`]).
    fn detect(
        &mut self,
        scene: &Resolved,
        buffers: &[PoseBuffers],
        poses: &[Isometry3<f32>],
        helpers_go: Option<&AtomicBool>,
    ) {
        let t0 = Instant::now();
        // Objects' root spheres in the world.
        for ((root, tree), pose) in self.object_roots.iter_mut().zip(&self.objects).zip(poses) {
            *root = (!tree.tree.is_empty())
                .then(|| sphere_in_frame(&tree.tree.nodes()[NodeId::ROOT.index()].sphere, pose));
        }
        // 1. Each character's frame starts and its root sphere is refit (a
        //    few dozen spheres; the room pass counts them, from the frame's
        //    start, and would refit them first anyway), characters side by
        //    side on the pool's threads.
        if let Some(go) = helpers_go {
            go.store(true, Ordering::Release);
        }
        let threads = rayon::current_num_threads();
        let chunk = (threads > 1).then(|| self.characters.len().div_ceil(threads));
        side_by_side(
            &mut self.characters,
            &mut self.per_character,
            chunk,
            |i, pipe, s| {
                let pipe = pipe.get_mut().expect("no pass panicked");
                pipe.begin_frame(&buffers[i]);
                s.get_mut().expect("no pass panicked").root = pipe.root_sphere(&buffers[i]);
            },
        );

        // 2. The broad phase between characters' root spheres.
        let n = self.characters.len();
        let mut char_tests = 0u64;
        self.candidates.clear();
        for i in 0..n {
            let Some(ri) = self.character_root(i) else {
                continue;
            };
            for j in i + 1..n {
                let Some(rj) = self.character_root(j) else {
                    continue;
                };
                char_tests += 1;
                if ri.overlaps(&rj) {
                    self.candidates.push((i as u32, j as u32));
                }
            }
        }
        while self.pair_scratch.len() < self.candidates.len() {
            self.pair_scratch.push(Mutex::new(PairScratch {
                a: 0,
                b: 0,
                counters: FrameCounters::default(),
                pairs: Vec::new(),
                scratch: CharacterPairScratch::default(),
            }));
        }

        // 3. Every pass: each character against the room and the objects,
        //    then against the characters it meets; passes of different
        //    characters run in parallel.
        self.graph.set_pairs(self.candidates.iter().copied());
        let objects = &self.objects;
        let object_roots = &self.object_roots;
        let characters = &self.characters;
        let per_character = &self.per_character;
        let pair_scratch = &self.pair_scratch;
        self.graph.run(|t, pair| match pair {
            None => {
                let i = t;
                // A pass holds its characters alone: these locks are never
                // contended.
                let mut pipe = characters[i].lock().expect("no pass panicked");
                let mut s = per_character[i].lock().expect("no pass panicked");
                let s = &mut *s;
                let actor = &scene.characters[i];
                let b = &buffers[i];
                s.room = pipe.detect_room(b, &actor.character, &scene.environment.mesh);
                s.objects = FrameCounters::default();
                s.broad_phase_tests = 0;
                s.body_pairs = 0;
                s.object_pairs.clear();
                let Some(root) = s.root else { return };
                for (o, (tree, oroot)) in objects.iter().zip(object_roots).enumerate() {
                    let Some(oroot) = oroot else { continue };
                    s.broad_phase_tests += 1;
                    if !root.overlaps(oroot) {
                        continue;
                    }
                    s.body_pairs += 1;
                    let c = pipe.detect_object(
                        b,
                        &actor.character,
                        tree,
                        &scene.objects[o].mesh,
                        &poses[o],
                        &mut s.pairs,
                    );
                    add_counters(&mut s.objects, &c);
                    s.object_pairs
                        .extend(s.pairs.iter().map(|&(t, ot)| ObjectPair {
                            character: i as u32,
                            triangle: t,
                            object: o as u32,
                            object_triangle: ot,
                        }));
                }
            }
            Some((i, j)) => {
                let mut s = pair_scratch[t - n].lock().expect("no pass panicked");
                let s = &mut *s;
                let mut pa = characters[i as usize].lock().expect("no pass panicked");
                let mut pb = characters[j as usize].lock().expect("no pass panicked");
                s.a = i;
                s.b = j;
                let (ai, aj) = (&scene.characters[i as usize], &scene.characters[j as usize]);
                s.counters = detect_characters(
                    &mut pa,
                    &ai.character,
                    &buffers[i as usize],
                    &mut pb,
                    &aj.character,
                    &buffers[j as usize],
                    &mut s.scratch,
                    &mut s.pairs,
                );
            }
        });

        // 4. The outcome, in a fixed order.
        let out = &mut self.outcome;
        out.total = FrameCounters::default();
        out.by_kind = Default::default();
        out.room_pairs.clear();
        out.object_pairs.clear();
        out.character_pairs.clear();
        out.broad_phase_tests = char_tests;
        out.body_pairs = self.candidates.len() as u64;
        out.by_kind.characters.sphere_sphere += char_tests;
        // Refits and skinned vertices: each character's own count for the
        // frame (every pass adds to it once).
        let (mut refits, mut skinned) = (0, 0);
        for (i, (s, pipe)) in self
            .per_character
            .iter_mut()
            .zip(self.characters.iter_mut())
            .enumerate()
        {
            let pipe = pipe.get_mut().expect("no pass panicked");
            let s = s.get_mut().expect("no pass panicked");
            refits += pipe.refit_state().refits;
            skinned += pipe.skinned().skinned();
            add_counters(&mut out.by_kind.environment, &s.room);
            add_counters(&mut out.by_kind.objects, &s.objects);
            out.by_kind.objects.sphere_sphere += s.broad_phase_tests;
            out.broad_phase_tests += s.broad_phase_tests;
            out.body_pairs += s.body_pairs;
            out.object_pairs.extend_from_slice(&s.object_pairs);
            out.room_pairs
                .extend(pipe.pairs.iter().map(|&(t, rt)| RoomPair {
                    character: i as u32,
                    triangle: t,
                    room_triangle: rt,
                }));
        }
        for s in &mut self.pair_scratch[..self.candidates.len()] {
            let s = s.get_mut().expect("no pass panicked");
            add_counters(&mut out.by_kind.characters, &s.counters);
            out.character_pairs
                .extend(s.pairs.iter().map(|&(ta, tb)| CharacterPair {
                    a: s.a,
                    triangle_a: ta,
                    b: s.b,
                    triangle_b: tb,
                }));
        }
        out.object_pairs.sort_unstable();
        out.character_pairs.sort_unstable();
        for k in super::PairKind::ALL {
            add_counters(&mut out.total, out.by_kind.get(k));
        }
        out.total.refits = refits;
        out.total.skinned_vertices = skinned;
        out.wall_ms = t0.elapsed().as_secs_f64() * 1e3;
    }
}

/// Calls `f(i, &mut a[i], &mut b[i])` for every `i`; with `chunk`, on the
/// current pool in pieces of at least `chunk` items (rayon's indexed
/// iterators split by `join`: nothing is boxed, so nothing allocates).
fn side_by_side<A: Send, B: Send>(
    a: &mut [A],
    b: &mut [B],
    chunk: Option<usize>,
    f: impl Fn(usize, &mut A, &mut B) + Sync,
) {
    match chunk {
        Some(c) => a
            .par_iter_mut()
            .zip(b)
            .enumerate()
            .with_min_len(c)
            .for_each(|(i, (x, y))| f(i, x, y)),
        None => {
            for (i, (x, y)) in a.iter_mut().zip(b).enumerate() {
                f(i, x, y);
            }
        }
    }
}

/// Runs `frame` on the current thread once every other thread of the
/// current pool is running, each held in a spin until `frame` sets `go`
/// (when its passes start: they then take the passes' jobs at once).
///
/// A frame handed to a pool from outside starts on a thread that has just
/// woken, and its time starts there; without this, the other threads would
/// wake during the frame, and on a virtual machine a processor idle for a
/// few milliseconds takes 1–3 ms to wake (docs/performance.md, "All
/// cores"), longer than a crowd's frame. One thread's frame does not count
/// its wake-up either. If a thread has not come within 20 ms (a pool busy
/// elsewhere), the frame starts without it. Arriving is not enough: a
/// thread woken onto the frame's own processor waits there until the frame
/// ends, so the pool's threads are pinned apart ([`super::pinning`]).
fn with_threads_awake(go: &AtomicBool, frame: impl FnOnce() + Send) {
    let others = rayon::current_num_threads().saturating_sub(1);
    let arrived = AtomicUsize::new(0);
    // `go` is set however `frame` ends, so no helper spins on after it.
    struct Release<'a>(&'a AtomicBool);
    impl Drop for Release<'_> {
        fn drop(&mut self) {
            self.0.store(true, Ordering::Release);
        }
    }
    fn hold(n: usize, arrived: &AtomicUsize, go: &AtomicBool, run: impl FnOnce() + Send) {
        if n == 0 {
            run();
            return;
        }
        rayon::join(
            || hold(n - 1, arrived, go, run),
            || {
                arrived.fetch_add(1, Ordering::AcqRel);
                // Yielding now and then, in case it shares a processor
                // with the frame.
                let mut spins = 0u32;
                while !go.load(Ordering::Acquire) {
                    spins += 1;
                    if spins.is_multiple_of(64) {
                        std::thread::yield_now();
                    } else {
                        std::hint::spin_loop();
                    }
                }
            },
        );
    }
    hold(others, &arrived, go, || {
        let _release = Release(go);
        let deadline = Instant::now() + std::time::Duration::from_millis(20);
        while arrived.load(Ordering::Acquire) < others && Instant::now() < deadline {
            std::hint::spin_loop();
        }
        frame();
    });
}
