//! After its buffers are sized, continuous detection of a world's frame
//! steps allocates nothing: the swept traversals against the room, moving
//! objects and other characters, the leaf tests and the CCD kernel, the
//! outcome, rayon's scheduling (the loop runs inside the world's pool).
//! One test in this binary, so no other test's allocations are counted.

use std::path::Path;
use std::sync::atomic::Ordering;

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::ALLOCATIONS;

use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::pipeline::Method;
use cornertree_workbench::scenario::open_scenario;
use cornertree_workbench::session::Session;

/// Every frame of `scenario` (its first `frames`) through the discrete
/// frame and every method's continuous step, twice: the first pass sizes
/// the buffers, the replay must allocate nothing. Returns the allocations
/// of each frame of both passes.
fn allocations(
    scenario: &str,
    frames: usize,
    methods: &[Method],
    threads: usize,
) -> (Vec<u64>, Vec<u64>) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(scenario);
    let mut r = open_scenario(&path).unwrap();
    r.frames = frames;
    r.dedup = false;
    r.methods = methods.to_vec();
    let mut world = Session::new(r, threads).unwrap();
    world.enable_continuous(CcdParams::default());
    world.in_pool(|w| {
        let mut pass = || {
            w.seek(0);
            let mut per_frame = Vec::with_capacity(frames);
            for k in 0..frames {
                let before = ALLOCATIONS.load(Ordering::Relaxed);
                w.step();
                for m in 0..w.worlds().len() {
                    w.sweep(m, k).unwrap();
                }
                per_frame.push(ALLOCATIONS.load(Ordering::Relaxed) - before);
            }
            per_frame
        };
        let first = pass();
        let second = pass();
        (first, second)
    })
}

fn continuous_steps_allocate_nothing_once_buffers_are_sized() {
    let all = Method::ALL;
    for (scenario, frames, methods) in [
        // Thin objects through a character between frames (contacts found
        // by the kernel), every method.
        ("scenarios/tunnel.toml", 34, &all[..]),
        // A swinging door (a rotating object) and two characters' hands.
        (
            "scenarios/door.toml",
            8,
            &[Method::PrunedTriTri, Method::PlaneSphere][..],
        ),
        ("scenarios/handshake.toml", 6, &[Method::PrunedTriTri][..]),
    ] {
        for threads in [1, 2] {
            let (first, second) = allocations(scenario, frames, methods, threads);
            assert!(first[1] > 0, "{scenario}: the first step sizes the buffers");
            assert!(
                second.iter().all(|&n| n == 0),
                "{scenario}, {threads} threads: allocations per frame on the replay: \
                 {second:?} (first pass {first:?})"
            );
        }
    }
}

/// Run without libtest's harness (`harness = false` in Cargo.toml): the
/// harness's own thread allocates when it prints that a test has run for
/// over a minute, and this binary's global allocator would count it inside
/// a measured frame.
fn main() {
    continuous_steps_allocate_nothing_once_buffers_are_sized();
    println!("continuous_steps_allocate_nothing_once_buffers_are_sized: ok");
}
