//! After its buffers are sized, a world's frame allocates nothing: every
//! character's passes, the object and character-character passes, rayon's
//! scheduling (the loop runs inside the world's pool). One test in this
//! binary, so no other test's allocations are counted.

use std::path::Path;
use std::sync::atomic::Ordering;

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::ALLOCATIONS;

use cornertree_workbench::scenario::open_scenario;

/// A world's frames through [`cornertree_workbench::session::Session`] on `threads`
/// threads, the loop inside the world's pool: once to size every buffer (pair lists grow to the most pairs a
/// frame has), then the same frames again, which must allocate nothing (the
/// rayon pool's job queues included). Returns the allocations of each frame
/// of both passes.
fn world_allocations(scenario: &str, frames: usize, threads: usize) -> (Vec<u64>, Vec<u64>) {
    use cornertree_workbench::scenario::{Scenario, resolve};
    use cornertree_workbench::session::Session;
    let mut r = match scenario.strip_prefix("plaza:") {
        // A plaza of this many 1,500-vertex humanoids, packed.
        Some(count) => {
            let text = format!(
                "[environment]\nkind = \"plaza\"\n[crowd]\n\
                 source = \"generated:humanoid?vertices=1500&seed=11\"\ncount = {count}\n\
                 clip = \"walk\"\nspacing = [0.45, 1.0]\n"
            );
            let s = Scenario::parse(&text, Path::new("plaza.toml")).unwrap();
            resolve(&s, Path::new(".")).unwrap()
        }
        None => open_scenario(&Path::new(env!("CARGO_MANIFEST_DIR")).join(scenario)).unwrap(),
    };
    r.frames = frames;
    r.dedup = false;
    let mut world = Session::new(r, threads).unwrap();
    let pass = |world: &mut Session| {
        world.seek(0);
        let mut per_frame = Vec::with_capacity(frames);
        loop {
            let before = ALLOCATIONS.load(Ordering::Relaxed);
            if world.step().is_none() {
                break;
            }
            per_frame.push(ALLOCATIONS.load(Ordering::Relaxed) - before);
        }
        per_frame
    };
    // The frame loop on one of the world's threads (`Session::in_pool`).
    world.in_pool(|w| {
        let first = pass(w);
        let second = pass(w);
        (first, second)
    })
}

fn world_frames_allocate_nothing_once_buffers_are_sized() {
    for (scenario, frames) in [
        ("scenarios/crowd.toml", 6),
        ("scenarios/door.toml", 12),
        ("scenarios/handshake.toml", 6),
        // 64 characters: the broad phase, the pass graph's heap and the
        // pair states of a crowd.
        ("plaza:64", 3),
        // Past the broad phase's every-pair threshold: its sweep.
        ("plaza:100", 2),
    ] {
        for threads in [1, 2] {
            let (first, second) = world_allocations(scenario, frames, threads);
            assert!(
                first[0] > 0,
                "{scenario}: the first frame sizes the buffers"
            );
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
    world_frames_allocate_nothing_once_buffers_are_sized();
    println!("world_frames_allocate_nothing_once_buffers_are_sized: ok");
}
