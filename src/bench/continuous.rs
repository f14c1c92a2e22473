//! `bench --ccd`: each method's continuous detection beside its discrete
//! frames, and against the naive alternative, discrete detection at `k`
//! sub-steps of every frame step (docs/ccd.md, "Cost").
//!
//! **Timing.** Per frame every body is posed once; then, per method and in
//! alternating order, the discrete frame ([`Session::detect`]) and the
//! continuous step ending at that frame ([`Session::sweep`]: both
//! ends refit on demand, the previous end's states reused). Frame 0 has no
//! step and is left out of both. Each side's time per frame is the median.
//!
//! **The naive alternative.** A sub-step at `t ∈ [0, 1]` of the step poses
//! every character with its skin matrices and base interpolated linearly
//! between the two frames: both skinning models are linear in the matrices,
//! so its vertices are the interpolated vertices (up to `f32` rounding), the
//! motion continuous detection assumes; objects are posed at the
//! interpolated isometry (exact for the translations of keyed paths). `k`
//! is the smallest number of sub-steps `i / k` (`i = 0..k`) whose discrete
//! pairs include, on every step, every contact the exact oracle finds on
//! the reference's sub-steps ([`SubstepTruth`]), which continuous detection
//! finds too. For an exact method, values of `k` that cannot do it (some
//! contact's run of touching reference sub-steps, widened by one sub-step
//! each way, holds no `i / k`) are skipped; the others (every `k` for a
//! plane-sphere method, whose plane test may report a pair before its
//! triangles touch) are tried in increasing order by running the method. The naive alternative then costs `k` discrete
//! detections a frame (the step's `i = 0` is the previous frame's `i = k`),
//! measured on the steps with contacts.

use std::time::Instant;

use nalgebra::{Isometry3, Matrix4};
use serde::Serialize;

use crate::scenario::Resolved;
use crate::session::{Session, SessionError};
use crate::truth::substep::{StepBodies, SubstepTruth};
use crate::truth::substep_score::StepPair;
use cornertree::character::PoseBuffers;
use cornertree::geometry::Point;
use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::pipeline::Method;
use cornertree::world::StepContacts;

use super::measure::median;

/// One method's continuous cost.
#[derive(Clone, Debug, Serialize)]
pub struct CcdMethodBench {
    pub method: Method,
    /// Median wall time per frame (posing included), discrete.
    pub discrete_ms_per_frame: f64,
    /// The same for the continuous step ending at the frame.
    pub continuous_ms_per_frame: f64,
    /// `continuous / discrete`.
    pub continuous_vs_discrete: f64,
    pub discrete_operations_per_frame: f64,
    pub continuous_operations_per_frame: f64,
    /// Triangle pairs tested per step by the CCD kernel (mean).
    pub kernel_tests_per_step: f64,
    pub discrete_pairs_per_frame: f64,
    pub continuous_pairs_per_step: f64,
    /// The naive alternative's sub-steps per frame step; `None` when no `k`
    /// up to the limit found every contact, or no step has contacts.
    pub substeps: Option<u32>,
    /// Its median time per frame step with contacts (`k` discrete
    /// detections, each sub-step's interpolated pose included).
    pub substeps_ms_per_frame: Option<f64>,
    /// `substeps_ms_per_frame / continuous_ms_per_frame`.
    pub substeps_vs_continuous: Option<f64>,
    /// Values of `k` run before the answer (the others were ruled out by
    /// the reference's contact runs).
    pub substeps_tried: Vec<u32>,
    /// The fewest sub-steps per step that find at least one contact of
    /// every body pair touching during a step (the event, not every pair).
    pub substeps_for_every_body_pair: Option<u32>,
    /// Reference contacts and touching body pairs found at `k = 1, 2, 4, …`
    /// sub-steps (over the steps with contacts).
    pub coverage: Vec<SubstepCoverage>,
}

/// What discrete detection at `substeps` sub-steps per step finds.
#[derive(Clone, Copy, Debug, Serialize)]
pub struct SubstepCoverage {
    pub substeps: u32,
    pub contacts: usize,
    pub body_pairs: usize,
}

/// A `bench --ccd` run.
#[derive(Clone, Debug, Serialize)]
pub struct CcdBench {
    pub scenario: String,
    pub frames: usize,
    pub threads: usize,
    pub dedup: bool,
    pub pose_ms_per_frame: f64,
    /// Sub-steps of the reference, and the most the naive search tries.
    pub reference_substeps: u32,
    pub max_substeps: u32,
    /// Steps whose reference found contacts, the contacts and the touching
    /// body pairs over the run.
    pub steps_with_contacts: usize,
    pub reference_contacts: usize,
    pub reference_body_pairs: usize,
    pub methods: Vec<CcdMethodBench>,
}

/// Poses every body of `world` at `t` of the step from `prev` (characters)
/// and `prev_poses` (objects) to `end` and `end_poses` (module doc).
pub fn pose_between(
    world: &mut Session,
    prev: &[PoseBuffers],
    prev_poses: &[Isometry3<f32>],
    end: &[PoseBuffers],
    end_poses: &[Isometry3<f32>],
    t: f32,
) {
    let lerp = |a: &Matrix4<f32>, b: &Matrix4<f32>| {
        let mut m = a * (1.0 - t) + b * t;
        // Exactly affine, as every skeleton matrix.
        m[(3, 0)] = 0.0;
        m[(3, 1)] = 0.0;
        m[(3, 2)] = 0.0;
        m[(3, 3)] = 1.0;
        m
    };
    for ((b, p), e) in world.buffers.iter_mut().zip(prev).zip(end) {
        for ((m, x), y) in b.skin.iter_mut().zip(&p.skin).zip(&e.skin) {
            *m = lerp(x, y);
        }
        b.base = lerp(&p.base, &e.base);
    }
    for ((q, a), b) in world.object_poses.iter_mut().zip(prev_poses).zip(end_poses) {
        *q = a.lerp_slerp(b, t);
    }
}

/// Every pair a discrete outcome reports, as [`StepPair`]s.
fn discrete_pairs(o: &StepContacts, out: &mut Vec<StepPair>) {
    out.extend(o.room_pairs.iter().map(|&p| StepPair::Environment(p)));
    out.extend(o.object_pairs.iter().map(|&p| StepPair::Objects(p)));
    out.extend(o.character_pairs.iter().map(|&p| StepPair::Characters(p)));
    out.extend(o.self_pairs.iter().map(|&p| StepPair::SelfContact(p)));
}

/// A step's reference contacts with their runs of touching sub-steps.
struct StepReference {
    prev: Vec<PoseBuffers>,
    prev_poses: Vec<Isometry3<f32>>,
    end: Vec<PoseBuffers>,
    end_poses: Vec<Isometry3<f32>>,
    /// Sorted contacts, and for each the sub-step runs `[a, b]` (of `n`).
    contacts: Vec<StepPair>,
    runs: Vec<Vec<(u32, u32)>>,
    /// Distinct body pairs among the contacts.
    body_pairs: usize,
}

/// The body pair of a pair: kind, character, other body.
fn body_pair(p: &StepPair) -> (u8, u32, u32) {
    match *p {
        StepPair::Environment(q) => (0, q.character.0, q.room.0),
        StepPair::Objects(q) => (1, q.character.0, q.object.0),
        StepPair::Characters(q) => (2, q.a.0, q.b.0),
        StepPair::SelfContact(q) => (3, q.character.0, q.character.0),
    }
}

/// Method `m`'s discrete pairs at the `k + 1` sub-steps `i / k` of step
/// `s`, sorted and distinct, into `found`; returns the milliseconds taken.
fn substep_pairs(
    world: &mut Session,
    m: usize,
    s: &StepReference,
    k: u32,
    found: &mut Vec<StepPair>,
) -> f64 {
    found.clear();
    let t0 = Instant::now();
    for sub in 0..=k {
        pose_between(
            world,
            &s.prev,
            &s.prev_poses,
            &s.end,
            &s.end_poses,
            sub as f32 / k as f32,
        );
        world.detect(m);
        discrete_pairs(world.contacts(m), found);
    }
    let ms = t0.elapsed().as_secs_f64() * 1e3;
    found.sort_unstable();
    found.dedup();
    ms
}

/// Whether `k` sub-steps can find every contact: each has some `i / k`
/// inside one of its runs widened by a reference sub-step each way (open).
fn may_find_all(step: &StepReference, n: u32, k: u32) -> bool {
    step.runs.iter().all(|runs| {
        runs.iter().any(|&(a, b)| {
            let (lo, hi) = ((a as f64 - 1.0) / n as f64, (b as f64 + 1.0) / n as f64);
            (0..=k).any(|i| {
                let t = i as f64 / k as f64;
                t > lo && t < hi
            })
        })
    })
}

/// Plays `frames` frames of `scene` on `threads` threads: discrete and
/// continuous per method, interleaved, then the naive alternative's search
/// up to `max_k` sub-steps. Calls `tick` after each frame of the timing
/// pass.
pub fn measure_ccd(
    scene: Resolved,
    name: &str,
    frames: usize,
    threads: usize,
    max_k: u32,
    mut tick: impl FnMut(),
) -> Result<CcdBench, SessionError> {
    let substeps = scene.ccd_substeps;
    let mut world = Session::new(scene, threads)?;
    world.set_refit_timing(false);
    world.enable_continuous(CcdParams::default());
    let mut truth = SubstepTruth::new(&world.scene, substeps);
    let n = world.worlds().len();
    // The previous frame's poses (the start of each step).
    let mut prev_buffers: Vec<PoseBuffers> = Vec::new();
    let mut prev_object_poses: Vec<Isometry3<f32>> = Vec::new();
    let mut pose_ms = Vec::with_capacity(frames);
    let mut disc_ms = vec![Vec::with_capacity(frames); n];
    let mut cont_ms = vec![Vec::with_capacity(frames); n];
    let (mut disc_ops, mut cont_ops) = (vec![0u64; n], vec![0u64; n]);
    let (mut disc_pairs, mut cont_pairs, mut kernel) =
        (vec![0u64; n], vec![0u64; n], vec![0u64; n]);
    let mut steps: Vec<StepReference> = Vec::new();
    let mut prev_positions: Vec<Vec<Point>> = Vec::new();
    let mut reference_contacts = 0;
    for k in 0..frames {
        world.pose(k);
        let pose = world.pose_ms;
        for i in 0..n {
            for continuous_first in [k % 2 == 0, k % 2 != 0] {
                if continuous_first {
                    let o = world.sweep(i, k)?;
                    if k > 0 {
                        cont_ms[i].push(pose + o.wall_ms);
                        cont_ops[i] += o.total.operations();
                        cont_pairs[i] += o.len() as u64;
                        kernel[i] += o.extra.kernel_tests;
                    }
                } else {
                    world.detect(i);
                    let o = world.contacts(i);
                    if k > 0 {
                        disc_ms[i].push(pose + world.detect_ms(i));
                        disc_ops[i] += o.total.operations();
                        disc_pairs[i] += o.total.pairs;
                    }
                }
            }
        }
        if k > 0 {
            pose_ms.push(pose);
        }
        // The reference of the step (not timed).
        world.skin_all();
        if k > 0 {
            let prev_poses = prev_buffers.clone();
            let bodies = StepBodies::between(&prev_positions, &prev_object_poses, &world);
            truth.update(&bodies);
            if !truth.is_empty() {
                let mut contacts: Vec<(StepPair, Vec<(u32, u32)>)> = Vec::new();
                let mut add = |pair: StepPair| {
                    let (a, b) = pair.corners(&bodies);
                    let mut runs: Vec<(u32, u32)> = Vec::new();
                    for s in 0..=substeps {
                        let t = s as f64 / substeps as f64;
                        if crate::truth::substep::touch_at(&a, &b, t) {
                            match runs.last_mut() {
                                Some(r) if r.1 + 1 == s => r.1 = s,
                                _ => runs.push((s, s)),
                            }
                        }
                    }
                    contacts.push((pair, runs));
                };
                truth
                    .room_pairs
                    .iter()
                    .for_each(|p| add(StepPair::Environment(p.pair)));
                truth
                    .object_pairs
                    .iter()
                    .for_each(|p| add(StepPair::Objects(p.pair)));
                truth
                    .character_pairs
                    .iter()
                    .for_each(|p| add(StepPair::Characters(p.pair)));
                truth
                    .self_pairs
                    .iter()
                    .for_each(|p| add(StepPair::SelfContact(p.pair)));
                contacts.sort_by_key(|c| c.0);
                reference_contacts += contacts.len();
                let mut bodies: Vec<(u8, u32, u32)> =
                    contacts.iter().map(|c| body_pair(&c.0)).collect();
                bodies.sort_unstable();
                bodies.dedup();
                steps.push(StepReference {
                    body_pairs: bodies.len(),
                    prev: prev_poses,
                    prev_poses: prev_object_poses.clone(),
                    end: world.buffers.clone(),
                    end_poses: world.object_poses.clone(),
                    runs: contacts.iter().map(|c| c.1.clone()).collect(),
                    contacts: contacts.into_iter().map(|c| c.0).collect(),
                });
            }
        }
        prev_positions = world.buffers.iter().map(|b| b.positions.clone()).collect();
        prev_buffers.clone_from(&world.buffers);
        prev_object_poses.clone_from(&world.object_poses);
        tick();
    }

    // The naive alternative, per method.
    let mut found: Vec<StepPair> = Vec::new();
    let mut methods = Vec::with_capacity(n);
    for i in 0..n {
        // Contacts and body pairs found at `k` sub-steps, over the steps.
        let tally = |world: &mut Session, k: u32, found: &mut Vec<StepPair>| {
            let (mut contacts, mut bodies, mut every) = (0, 0, true);
            for s in &steps {
                substep_pairs(world, i, s, k, found);
                let hit = s.contacts.iter().filter(|c| found.binary_search(c).is_ok());
                contacts += hit.clone().count();
                let mut seen: Vec<(u8, u32, u32)> = hit.map(body_pair).collect();
                seen.dedup();
                bodies += seen.len();
                every &= seen.len() == s.body_pairs;
            }
            (contacts, bodies, every)
        };
        let mut coverage = Vec::new();
        let mut k = 1;
        while k <= max_k && !steps.is_empty() {
            let (contacts, body_pairs, _) = tally(&mut world, k, &mut found);
            coverage.push(SubstepCoverage {
                substeps: k,
                contacts,
                body_pairs,
            });
            k *= 2;
        }
        let body_pair_k = if steps.is_empty() {
            None
        } else {
            (1..=max_k).find(|&k| tally(&mut world, k, &mut found).2)
        };
        let exact =
            world.world(i).method().big_leaf_test() == cornertree::pipeline::LeafTest::TriTri;
        let mut tried = Vec::new();
        let mut answer = None;
        for k in 1..=max_k {
            if steps.is_empty() {
                break;
            }
            // Only an exact method's pairs touch; a plane test may report
            // a pair earlier, so nothing is ruled out for it.
            if exact && !steps.iter().all(|s| may_find_all(s, substeps, k)) {
                continue;
            }
            tried.push(k);
            let mut times = Vec::new();
            let all = steps.iter().all(|s| {
                let ms = substep_pairs(&mut world, i, s, k, &mut found);
                times.push(ms * k as f64 / (k + 1) as f64);
                s.contacts.iter().all(|c| found.binary_search(c).is_ok())
            });
            if all {
                answer = Some((k, median(&mut times)));
                break;
            }
        }
        let disc = median(&mut disc_ms[i]);
        let cont = median(&mut cont_ms[i]);
        let per_step = |x: u64| x as f64 / frames.saturating_sub(1).max(1) as f64;
        let ratio = |a: f64, b: f64| if b > 0.0 { a / b } else { 0.0 };
        let naive_ms = answer.map(|(_, ms)| ms);
        methods.push(CcdMethodBench {
            method: world.world(i).method(),
            discrete_ms_per_frame: disc,
            continuous_ms_per_frame: cont,
            continuous_vs_discrete: ratio(cont, disc),
            discrete_operations_per_frame: per_step(disc_ops[i]),
            continuous_operations_per_frame: per_step(cont_ops[i]),
            kernel_tests_per_step: per_step(kernel[i]),
            discrete_pairs_per_frame: per_step(disc_pairs[i]),
            continuous_pairs_per_step: per_step(cont_pairs[i]),
            substeps: answer.map(|a| a.0),
            substeps_ms_per_frame: naive_ms,
            substeps_vs_continuous: naive_ms.map(|ms| ratio(ms, cont)),
            substeps_tried: tried,
            substeps_for_every_body_pair: body_pair_k,
            coverage,
        });
    }
    let scene = &world.scene;
    Ok(CcdBench {
        scenario: name.to_string(),
        frames,
        threads: world.threads(),
        dedup: scene.dedup,
        pose_ms_per_frame: median(&mut pose_ms),
        reference_substeps: substeps,
        max_substeps: max_k,
        steps_with_contacts: steps.len(),
        reference_contacts,
        reference_body_pairs: steps.iter().map(|s| s.body_pairs).sum(),
        methods,
    })
}
