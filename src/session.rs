//! A scenario played through its methods: one [`CollisionWorld`] per
//! method (the library's, one method each), all fed the same poses.
//!
//! [`Session`] poses every character (a clip sampled at the frame's time,
//! placed by the scenario) and object (its motion) once a frame, hands the
//! poses to every method's world and steps it. Comparing methods is the
//! workbench's job; a world knows one method. The ground truth, the
//! recorder, the JSON report, the frame dumps and the progress bar observe a
//! step's contacts and the worlds' state; none of them changes the measured
//! work.
//!
//! The session owns the thread pool its worlds step on (pinned to
//! processors, docs/performance-journal.md, "Pinned pool threads") and a pool of one
//! thread for one-thread measurements.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use nalgebra::Isometry3;

use cornertree::character::PoseBuffers;
use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::io::limits::MAX_COORDINATE;
use cornertree::mesh::{EdgeDedup, TriMesh, dedup_edges};
use cornertree::pipeline::Method;
use cornertree::world::pinning::pinned_pool;
use cornertree::world::{
    CharacterHandle, CharacterModel, CollisionWorld, ObjectHandle, RoomHandle, StepContacts,
    SweepContacts, WorldError,
};

use crate::scenario::Resolved;
use crate::scenario::motion::rigid_path;

/// Why a session could not be built.
#[derive(Debug, thiserror::Error)]
pub enum SessionError {
    #[error("building the thread pool: {0}")]
    Threads(#[from] rayon::ThreadPoolBuildError),
    #[error("{0}")]
    World(#[from] WorldError),
}

/// A scenario's bodies in one collision world per method, posed together.
pub struct Session {
    /// The bodies, the room and the run's settings.
    pub scene: Resolved,
    /// One world per method of `scene.methods`, in that order.
    worlds: Vec<CollisionWorld>,
    /// `None` without methods (no world to hold it).
    room: Option<RoomHandle>,
    characters: Vec<CharacterHandle>,
    objects: Vec<ObjectHandle>,
    /// Each character posed and placed for the current frame (joint
    /// matrices; vertices only after [`Session::skin_all`]).
    pub buffers: Vec<PoseBuffers>,
    /// Each object's pose (object frame → world) this frame.
    pub object_poses: Vec<Isometry3<f32>>,
    /// Milliseconds spent posing every character this frame.
    pub pose_ms: f64,
    /// Per method: milliseconds of its last detection (handing it the poses
    /// and its step, threads awake).
    detect_ms: Vec<f64>,
    /// The frame the poses are for.
    posed: Option<usize>,
    /// Per method: the frame its last sweep ended at.
    swept: Vec<Option<usize>>,
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
    /// One thread, for [`Session::detect_on_one_thread`].
    serial: Arc<rayon::ThreadPool>,
    threads: usize,
}

impl Session {
    /// Builds every method's world for the scene, on `threads` threads (0:
    /// one per core).
    pub fn new(scene: Resolved, threads: usize) -> Result<Self, SessionError> {
        let pool = Arc::new(pinned_pool(threads)?);
        let threads = pool.current_num_threads();
        let serial = Arc::new(rayon::ThreadPoolBuilder::new().num_threads(1).build()?);
        // What every method's worlds share: the characters' models (edge
        // de-duplication done once per source and skinning model; actors of
        // one source are instances of one model, whose tree each world then
        // builds once), the room's and objects' meshes.
        let mut models: Vec<Arc<CharacterModel>> = Vec::with_capacity(scene.characters.len());
        for (i, a) in scene.characters.iter().enumerate() {
            let same = scene.characters[..i]
                .iter()
                .zip(&models)
                .find(|(b, _)| Arc::ptr_eq(&a.character, &b.character) && a.skinning == b.skinning);
            let model = match same {
                Some((_, m)) => m.clone(),
                None => {
                    let mesh = &a.character.mesh;
                    let kept = if scene.dedup {
                        dedup_edges(mesh)
                    } else {
                        EdgeDedup::keep_all(mesh)
                    };
                    Arc::new(CharacterModel::with_kept(
                        a.character.clone(),
                        a.skinning,
                        kept,
                    )?)
                }
            };
            models.push(model);
        }
        let room_mesh: Arc<TriMesh> = Arc::new(scene.environment.mesh.clone());
        let object_meshes: Vec<Arc<TriMesh>> = scene
            .objects
            .iter()
            .map(|o| Arc::new(o.mesh.clone()))
            .collect();
        let settings = scene.world_settings();
        let built: Vec<_> = pool.install(|| {
            use rayon::prelude::*;
            scene
                .methods
                .par_iter()
                .map(|&m| {
                    let mut w = CollisionWorld::with_settings(m, settings);
                    let room = w.add_room(room_mesh.clone())?;
                    let objects = object_meshes
                        .iter()
                        .map(|mesh| w.add_object(mesh.clone(), Isometry3::identity()))
                        .collect::<Result<Vec<_>, _>>()?;
                    let characters = models
                        .iter()
                        .map(|model| w.add_character(model.clone()))
                        .collect::<Result<Vec<_>, _>>()?;
                    Ok::<_, WorldError>((w, room, objects, characters))
                })
                .collect()
        });
        let mut worlds = Vec::with_capacity(built.len());
        let (mut room, mut objects, mut characters) = (None, Vec::new(), Vec::new());
        for b in built {
            let (w, r, o, c) = b?;
            worlds.push(w);
            (room, objects, characters) = (Some(r), o, c);
        }
        let buffers = scene
            .characters
            .iter()
            .map(|a| PoseBuffers::new(&a.character))
            .collect();
        let bind_reach: Vec<f32> = models.iter().map(|m| m.bind_reach()).collect();
        let n = worlds.len();
        Ok(Self {
            object_poses: vec![Isometry3::identity(); scene.objects.len()],
            scene,
            worlds,
            room,
            characters,
            objects,
            buffers,
            pose_ms: 0.0,
            detect_ms: vec![0.0; n],
            posed: None,
            swept: vec![None; n],
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

    /// Runs later frames on `threads` threads (0: one per core).
    pub fn set_threads(&mut self, threads: usize) -> Result<(), rayon::ThreadPoolBuildError> {
        self.pool = Arc::new(pinned_pool(threads)?);
        self.threads = self.pool.current_num_threads();
        Ok(())
    }

    /// Runs `f` on one of the session's threads, so that the frames it
    /// plays hand no job over to the pool: each [`Session::step`] from
    /// outside the pool queues one, and rayon's queue allocates a block
    /// every few dozen jobs; inside, a frame allocates nothing once its
    /// buffers are sized (`tests/no_alloc.rs`).
    pub fn in_pool<R: Send>(&mut self, f: impl FnOnce(&mut Session) -> R + Send) -> R {
        let pool = self.pool.clone();
        pool.install(|| f(self))
    }

    /// Frames in the scenario.
    pub fn frames(&self) -> usize {
        self.scene.frames
    }

    /// The frame [`Session::step`] plays next.
    pub fn next_frame(&self) -> usize {
        self.next
    }

    /// Plays frame `k` from here on (frames are independent: any order works).
    pub fn seek(&mut self, k: usize) {
        self.next = k;
    }

    /// The methods, one world each, in order.
    pub fn methods(&self) -> impl ExactSizeIterator<Item = Method> + '_ {
        self.worlds.iter().map(CollisionWorld::method)
    }

    /// Method `m`'s world.
    pub fn world(&self, m: usize) -> &CollisionWorld {
        &self.worlds[m]
    }

    /// Method `m`'s world, to change (settings, visit logs).
    pub fn world_mut(&mut self, m: usize) -> &mut CollisionWorld {
        &mut self.worlds[m]
    }

    /// Every method's world.
    pub fn worlds(&self) -> &[CollisionWorld] {
        &self.worlds
    }

    /// Method `m`'s contacts of its last step.
    pub fn contacts(&self, m: usize) -> &StepContacts {
        self.worlds[m].contacts()
    }

    /// The room's handle in every world (a session has a world per
    /// method; one without methods has no room to name).
    pub fn room(&self) -> RoomHandle {
        self.room.expect("a session with at least one method")
    }

    /// Character `i`'s handle in every world (the scenario's order).
    pub fn character(&self, i: usize) -> CharacterHandle {
        self.characters[i]
    }

    /// Object `o`'s handle in every world.
    pub fn object(&self, o: usize) -> ObjectHandle {
        self.objects[o]
    }

    /// Milliseconds of method `m`'s last detection: the poses handed to its
    /// world and its step, every thread awake.
    pub fn detect_ms(&self, m: usize) -> f64 {
        self.detect_ms[m]
    }

    /// Poses every body for frame `k` (joint matrices and object poses),
    /// the characters side by side on the session's threads (their buffers
    /// are their own). A character whose pose takes a vertex beyond
    /// [`MAX_COORDINATE`] (a clip with absurd keyframes) is noted
    /// ([`Session::out_of_range`]) and the frame is not detected.
    pub fn pose(&mut self, k: usize) {
        self.pose_in(k, false);
    }

    /// Like [`Session::pose`] on the calling thread alone (`bench` times a
    /// one-thread frame with a one-thread pose).
    pub fn pose_on_one_thread(&mut self, k: usize) {
        self.pose_in(k, true);
    }

    fn pose_in(&mut self, k: usize, one_thread: bool) {
        let Session {
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
        // As a frame's passes: timed once every thread is awake.
        self.pose_ms = if !parallel || pool.current_thread_index().is_some() {
            pose_all()
        } else {
            awake_on(pool, pose_all)
        };
        self.posed = Some(k);
    }

    /// Skins every vertex of every character for the current pose (for the
    /// ground truth, recordings and dumps; no method's work or time).
    pub fn skin_all(&mut self) {
        for (a, b) in self.scene.characters.iter().zip(&mut self.buffers) {
            b.skin_all(&a.character, a.skinning);
        }
    }

    /// [`Session::skin_all`] with the characters side by side on the
    /// session's threads (the baseline's same-thread frame; call it inside
    /// [`Session::in_pool`]).
    pub fn skin_all_on_threads(&mut self) {
        use rayon::prelude::*;
        self.scene
            .characters
            .par_iter()
            .zip(self.buffers.par_iter_mut())
            .for_each(|(a, b)| b.skin_all(&a.character, a.skinning));
    }

    /// The first character posed out of range this frame, and how far its
    /// vertices may reach from the origin (see [`Session::pose`]).
    pub fn out_of_range(&self) -> Option<(usize, f32)> {
        self.out_of_range
    }

    /// Plays the next frame through every method; returns its index, or
    /// `None` past the last frame. Contacts are in [`Session::contacts`].
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
        for m in 0..self.worlds.len() {
            self.detect(m);
        }
    }

    /// Runs method `m` on the current pose on the session's threads (not
    /// when a character is posed out of range: its contacts are then those
    /// of its last step).
    pub fn detect(&mut self, m: usize) {
        self.detect_in(m, false);
    }

    /// Like [`Session::detect`] on one thread, whatever
    /// [`Session::threads`] says (`bench` measures both in one run).
    pub fn detect_on_one_thread(&mut self, m: usize) {
        self.detect_in(m, true);
    }

    /// Hands the current poses to method `m`'s world (no step: queries
    /// then refit and skin on demand).
    pub fn hand_poses(&mut self, m: usize) {
        self.feed(m);
    }

    /// Hands the current poses to method `m`'s world.
    fn feed(&mut self, m: usize) {
        let w = &mut self.worlds[m];
        for (&h, b) in self.characters.iter().zip(&self.buffers) {
            w.set_pose(h, b)
                .expect("poses are checked by Session::pose");
        }
        for (&h, p) in self.objects.iter().zip(&self.object_poses) {
            w.set_object_pose(h, *p)
                .expect("motions give finite poses in range");
        }
    }

    fn detect_in(&mut self, m: usize, one_thread: bool) {
        if self.out_of_range.is_some() {
            return;
        }
        let pool = if one_thread { &self.serial } else { &self.pool }.clone();
        let one = self.characters.len() <= 1;
        let mut run = || {
            let t0 = Instant::now();
            self.feed(m);
            self.worlds[m].step();
            t0.elapsed().as_secs_f64() * 1e3
        };
        // Inside the pool already (see [`Session::in_pool`]): no job to
        // hand over to it. One character is one pass: it runs on the
        // calling thread, as handing it to a pool thread and back costs two
        // thread wake-ups.
        let ms = if pool.current_thread_index().is_some() || one {
            run()
        } else {
            // Several characters: their passes may run side by side, on
            // threads awake from the start.
            awake_on(&pool, run)
        };
        self.detect_ms[m] = ms;
    }

    /// Times each sphere refit apart from the traversal (on by default;
    /// `bench` turns it off: the timers cost time).
    pub fn set_refit_timing(&mut self, on: bool) {
        for w in &mut self.worlds {
            w.set_refit_timing(on);
        }
    }

    /// Turns continuous detection on in every method's world.
    pub fn enable_continuous(&mut self, params: CcdParams) {
        for w in &mut self.worlds {
            w.enable_continuous(params);
        }
    }

    /// Method `m`'s continuous detection over the step from frame `k − 1`
    /// to `k` (the session posed at `k`); frame 0 has no step. When `m`'s
    /// last sweep did not end at `k − 1`, frame `k − 1` is posed again and
    /// recorded as the step's start (untimed).
    pub fn sweep(&mut self, m: usize, k: usize) -> Result<&SweepContacts, WorldError> {
        if k > 0 && self.swept[m] != Some(k - 1) {
            // The step starts at `k − 1`: that pose recorded, nothing swept.
            let now = self.posed;
            self.pose_on_one_thread(k - 1);
            self.worlds[m].restart_sweep();
            self.sweep_posed(m, None)?;
            if let Some(now) = now {
                self.pose_on_one_thread(now);
            }
        } else if k == 0 {
            self.worlds[m].restart_sweep();
        }
        let paths = k.checked_sub(1).map(|prev| (prev, k));
        self.sweep_posed(m, paths)?;
        self.swept[m] = Some(k);
        Ok(self.worlds[m]
            .sweep_contacts()
            .expect("Session::sweep enables nothing: call enable_continuous"))
    }

    /// Sweeps method `m`'s world to the current poses; with `frames`
    /// `(from, to)`, each object's path between them from its motion.
    fn sweep_posed(&mut self, m: usize, frames: Option<(usize, usize)>) -> Result<(), WorldError> {
        self.feed(m);
        let pool = self.pool.clone();
        let Session {
            scene,
            worlds,
            objects,
            ..
        } = self;
        let w = &mut worlds[m];
        if let Some((from, to)) = frames {
            let (t0, t1) = (scene.world_time(from), scene.world_time(to));
            for (o, &h) in scene.objects.iter().zip(objects.iter()) {
                let path = rigid_path(
                    &o.motion,
                    t0,
                    t1,
                    o.motion.pose_at(t0),
                    o.motion.pose_at(t1),
                );
                w.set_object_path(h, path)?;
            }
        }
        pool.install(|| w.sweep().map(|_| ()))
    }

    /// Bytes of every method's hierarchies.
    pub fn hierarchy_bytes(&self, m: usize) -> usize {
        self.worlds[m].hierarchy_bytes()
    }

    /// Bytes continuous detection and a step's reference (`truth::substep`)
    /// take beyond the session, rounded up: per method and character, refit
    /// states, swept spheres and skinned vertices at both ends; per
    /// character, its previous pose and its triangles' boxes over a step.
    /// `None` past `usize`.
    pub fn continuous_estimated_bytes(&self) -> Option<usize> {
        let mut total = 0usize;
        for w in &self.worlds {
            for (&h, a) in self.characters.iter().zip(&self.scene.characters) {
                let nodes = w.character(h).ok()?.tree().tree.len();
                let vertices = a.character.mesh.vertex_count();
                total = total
                    .checked_add(nodes.checked_mul(100)?)?
                    .checked_add(vertices.checked_mul(40)?)?;
            }
        }
        for a in &self.scene.characters {
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
    use rayon::prelude::*;
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

/// Runs `timed` on `pool` with every thread of the pool awake
/// ([`with_threads_awake`]), the threads' work starting when it starts;
/// returns what it returns (its milliseconds).
fn awake_on(pool: &rayon::ThreadPool, timed: impl FnOnce() -> f64 + Send) -> f64 {
    let go = AtomicBool::new(false);
    let mut ms = 0.0;
    pool.install(|| {
        with_threads_awake(&go, || {
            go.store(true, Ordering::Release);
            ms = timed();
        })
    });
    ms
}

/// Runs `frame` on the current thread once every other thread of the
/// current pool is running, each held in a spin until `frame` sets `go`
/// (when its passes start: they then take the passes' jobs at once).
///
/// A frame handed to a pool from outside starts on a thread that has just
/// woken, and its time starts there; without this, the other threads would
/// wake during the frame, and on a virtual machine a processor idle for a
/// few milliseconds takes 1–3 ms to wake (docs/performance-journal.md, "All
/// cores"), longer than a crowd's frame. One thread's frame does not count
/// its wake-up either. If a thread has not come within 20 ms (a pool busy
/// elsewhere), the frame starts without it. Arriving is not enough: a
/// thread woken onto the frame's own processor waits there until the frame
/// ends, so the pool's threads are pinned apart
/// ([`cornertree::world::pinning`]).
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
