//! One run measuring each method against the parry3d baseline.
//!
//! Per frame every body is posed once (joint matrices, object poses), which
//! every side needs and is charged with. The baseline then skins every vertex
//! (parry's BVHs need them all), moves its meshes and finds its pairs
//! ([`ParryWorld`]). Each method runs [`Session::detect`] (refit on
//! demand, traversal, skinning only the vertices its narrow phase reads, the
//! narrow phase, every pair kind) on all of the world's threads and again on
//! one thread, which gives its parallel speed-up in the same run. The
//! baseline runs on the same threads before a method's all-thread run and on
//! one thread before its one-thread run, so each speed-up compares equal
//! threads (the one-thread baseline over the all-thread method is kept
//! beside them, labelled).
//!
//! Every run of a method comes right after a run of the baseline's frame,
//! and every run of the baseline after a method's: each side is measured
//! after the other's work, as an engine's frame runs after its other work.
//! (Two runs of a method back to back would time the second on caches and
//! branch history warm from the same frame: up to 65% faster on this machine,
//! `docs/performance.md`, "How a frame is measured".) Which of a method's
//! two runs goes first alternates from frame to frame; each side's time per
//! frame is the median over its runs.

use std::time::Instant;

use serde::Serialize;

use crate::scenario::Resolved;
use crate::session::{Session, SessionError};
use crate::truth::{ParryWorld, TruthError};
use cornertree::pipeline::Method;
use cornertree::world::StepContacts;

/// One method's measurement.
#[derive(Clone, Debug, Serialize)]
pub struct MethodBench {
    pub method: Method,
    /// Median wall time per frame (posing included) on all threads.
    pub ms_per_frame: f64,
    /// The same on one thread.
    pub ms_per_frame_one_thread: f64,
    /// `ms_per_frame_one_thread / ms_per_frame`.
    pub parallel_speedup: f64,
    /// parry on the same threads over this method on all threads: same
    /// threads against same threads.
    pub speedup_vs_parry_same_threads: f64,
    /// parry on one thread over this method on one thread.
    pub speedup_vs_parry_one_thread: f64,
    /// parry on one thread over this method on all threads (a pairing of
    /// unequal threads, kept for older reports).
    pub speedup_vs_parry: f64,
    /// Median work of the one-thread frames: every pass's time and the
    /// step's own, in milliseconds ([`StepContacts::work_ms`]).
    pub work_ms: f64,
    /// Median span of the one-thread frames: the longest chain of that work
    /// that must run one after another ([`StepContacts::span_ms`]).
    pub span_ms: f64,
    /// Median of work over span per frame: how many threads the frame could
    /// keep busy.
    pub available_parallelism: f64,
    pub operations_per_frame: f64,
    /// Median of the method's own skinning (the vertices it tested; summed
    /// over threads).
    pub skinning_ms_per_frame: f64,
    pub skinned_vertices_per_frame: f64,
    pub pairs_per_frame: f64,
    /// Frames whose pairs (any kind) differ from the baseline's.
    pub frames_with_other_pairs_than_parry: usize,
}

/// A run's measurement.
#[derive(Clone, Debug, Serialize)]
pub struct Bench {
    pub scenario: String,
    pub frames: usize,
    pub dedup: bool,
    /// Threads of the methods' frames and of the baseline's same-thread
    /// frames.
    pub threads: usize,
    pub characters: usize,
    pub objects: usize,
    pub environment_vertices: usize,
    /// Vertices of every character together.
    pub vertices: usize,
    /// The first character's gap to its surface, as asked (`placement.gap`).
    pub gap_metres: Option<f32>,
    /// The least signed distance of its vertices to that surface's plane
    /// over the clip (negative: that deep behind it).
    pub deepest_metres: Option<f32>,
    /// Median over the baseline's one-thread runs (one before each
    /// one-thread run of a method, posing included).
    pub parry_ms_per_frame: f64,
    /// Median over the baseline's runs on the methods' threads (one before
    /// each all-thread run of a method; posing, skinning, `update_vertices`
    /// and the body pairs on the pool).
    pub parry_ms_per_frame_same_threads: f64,
    /// Leaf pairs parry's traversals yielded per frame (mean).
    pub parry_candidates_per_frame: f64,
    /// Posing (joint matrices, object poses) on every thread, in each
    /// method's time (posed again before each run).
    pub pose_ms_per_frame: f64,
    /// Posing on one thread, in each method's one-thread time and the
    /// baseline's.
    pub pose_ms_per_frame_one_thread: f64,
    /// Skinning every vertex on one thread, in the baseline's time.
    pub skinning_all_ms_per_frame: f64,
    pub methods: Vec<MethodBench>,
}

/// The median of `v` (the upper one of an even count; 0 when empty),
/// sorting `v`.
pub(super) fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

fn same_pairs(o: &StepContacts, parry: &ParryWorld) -> bool {
    o.room_pairs == parry.pairs.environment
        && o.object_pairs == parry.pairs.objects
        && o.character_pairs == parry.pairs.characters
        && o.self_pairs == parry.pairs.self_contact
}

/// Errors of a measurement.
#[derive(Debug, thiserror::Error)]
pub enum BenchError {
    #[error("{0}")]
    Session(#[from] SessionError),
    #[error("parry baseline: {0}")]
    Parry(#[from] TruthError),
}

/// Plays `frames` frames of `scene` (its methods, its de-duplication) on
/// `threads` threads (0: one per core) through every method and the parry3d
/// baseline, interleaved, and returns the medians. Calls `tick` after each
/// frame.
pub fn measure(
    scene: Resolved,
    name: &str,
    frames: usize,
    threads: usize,
    mut tick: impl FnMut(),
) -> Result<Bench, BenchError> {
    let mut world = Session::new(scene, threads)?;
    // Refit is timed with traversal: splitting it costs time.
    world.set_refit_timing(false);
    let mut parry = ParryWorld::new(&world.scene)?;
    let n = world.worlds().len();
    let mut pose_ms = Vec::with_capacity(frames * n);
    let mut pose_one_ms = Vec::with_capacity(frames * n.max(1));
    let mut skin_all_ms = Vec::with_capacity(frames * (2 * n).max(1));
    let mut parry_ms = Vec::with_capacity(frames * n.max(1));
    let mut parry_threads_ms = Vec::with_capacity(frames * n);
    let mut parry_candidates = 0u64;
    let mut all_ms = vec![Vec::with_capacity(frames); n];
    let mut one_ms = vec![Vec::with_capacity(frames); n];
    let mut skin_ms = vec![Vec::with_capacity(frames); n];
    let mut work_ms = vec![Vec::with_capacity(frames); n];
    let mut span_ms = vec![Vec::with_capacity(frames); n];
    let mut parallelism = vec![Vec::with_capacity(frames); n];
    let (mut ops, mut skinned, mut pairs) = (vec![0u64; n], vec![0u64; n], vec![0u64; n]);
    let mut differ = vec![0usize; n];
    // The baseline's frame `k`, posed on its one thread (its time, posing
    // included, and its skinning time recorded). Posing on the pool would
    // leave its threads spinning beside the baseline's frame.
    let mut parry_frame = |world: &mut Session, parry: &mut ParryWorld, k: usize| {
        world.pose_on_one_thread(k);
        let pose = world.pose_ms;
        let t0 = Instant::now();
        world.skin_all();
        skin_all_ms.push(t0.elapsed().as_secs_f64() * 1e3);
        parry.update(&world.buffers, &world.object_poses)?;
        parry.detect();
        parry_ms.push(pose + t0.elapsed().as_secs_f64() * 1e3);
        Ok::<f64, BenchError>(pose)
    };
    // The baseline's frame `k` on the session's threads: posing, skinning,
    // `update_vertices` and the body pairs on the pool.
    let mut parry_frame_on_threads = |world: &mut Session, parry: &mut ParryWorld, k: usize| {
        world.pose(k);
        let pose = world.pose_ms;
        let t0 = Instant::now();
        world.in_pool(|w| {
            w.skin_all_on_threads();
            parry.update_on_threads(&w.buffers, &w.object_poses)?;
            parry.detect_on_threads();
            Ok::<(), BenchError>(())
        })?;
        parry_threads_ms.push(pose + t0.elapsed().as_secs_f64() * 1e3);
        Ok::<(), BenchError>(())
    };
    for k in 0..frames {
        for i in 0..n {
            for one_thread in [k % 2 == 0, k % 2 != 0] {
                // The baseline on the threads the method's run is on.
                if one_thread {
                    parry_frame(&mut world, &mut parry, k)?;
                } else {
                    parry_frame_on_threads(&mut world, &mut parry, k)?;
                }
                // Posed again after the baseline's frame, as that frame
                // leaves the caches, on the threads the method runs on.
                if one_thread {
                    world.pose_on_one_thread(k);
                    pose_one_ms.push(world.pose_ms);
                    world.detect_on_one_thread(i);
                } else {
                    world.pose(k);
                    pose_ms.push(world.pose_ms);
                    world.detect(i);
                }
                let pose = world.pose_ms;
                let o = world.contacts(i);
                let ms = pose + world.detect_ms(i);
                if one_thread {
                    one_ms[i].push(ms);
                    work_ms[i].push(o.work_ms);
                    span_ms[i].push(o.span_ms);
                    parallelism[i].push(o.available_parallelism());
                } else {
                    all_ms[i].push(ms);
                    skin_ms[i].push(o.total.time.skinning_ms);
                }
            }
            let o = world.contacts(i);
            ops[i] += o.total.operations();
            skinned[i] += o.total.skinned_vertices;
            pairs[i] += o.total.pairs;
            if !same_pairs(o, &parry) {
                differ[i] += 1;
            }
        }
        // No method: the baseline still runs once a frame.
        if n == 0 {
            pose_one_ms.push(parry_frame(&mut world, &mut parry, k)?);
        }
        // The same candidates on every run of a frame: counted once.
        parry_candidates += parry.candidates;
        tick();
    }
    let per_frame = |x: u64| x as f64 / frames.max(1) as f64;
    let parry_median = median(&mut parry_ms);
    let parry_threads_median = median(&mut parry_threads_ms);
    let methods = (0..n)
        .map(|i| {
            let all = median(&mut all_ms[i]);
            let one = median(&mut one_ms[i]);
            let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
            MethodBench {
                method: world.world(i).method(),
                ms_per_frame: all,
                ms_per_frame_one_thread: one,
                parallel_speedup: ratio(one, all),
                speedup_vs_parry_same_threads: ratio(parry_threads_median, all),
                speedup_vs_parry_one_thread: ratio(parry_median, one),
                speedup_vs_parry: ratio(parry_median, all),
                work_ms: median(&mut work_ms[i]),
                span_ms: median(&mut span_ms[i]),
                available_parallelism: median(&mut parallelism[i]),
                operations_per_frame: per_frame(ops[i]),
                skinning_ms_per_frame: median(&mut skin_ms[i]),
                skinned_vertices_per_frame: per_frame(skinned[i]),
                pairs_per_frame: per_frame(pairs[i]),
                frames_with_other_pairs_than_parry: differ[i],
            }
        })
        .collect();
    let scene = &world.scene;
    Ok(Bench {
        scenario: name.to_string(),
        frames,
        dedup: scene.dedup,
        threads: world.threads(),
        characters: scene.characters.len(),
        objects: scene.objects.len(),
        environment_vertices: scene.environment.mesh.positions().len(),
        vertices: scene
            .characters
            .iter()
            .map(|a| a.character.mesh.positions().len())
            .sum(),
        gap_metres: scene
            .characters
            .first()
            .and_then(|a| a.gap.as_ref())
            .map(|g| g.metres),
        deepest_metres: scene
            .characters
            .first()
            .and_then(|a| a.gap.as_ref())
            .map(|g| g.achieved),
        parry_ms_per_frame: parry_median,
        parry_ms_per_frame_same_threads: parry_threads_median,
        parry_candidates_per_frame: per_frame(parry_candidates),
        pose_ms_per_frame: median(&mut pose_ms),
        pose_ms_per_frame_one_thread: median(&mut pose_one_ms),
        skinning_all_ms_per_frame: median(&mut skin_all_ms),
        methods,
    })
}
