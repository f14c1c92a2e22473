//! After the first frame, a frame of the pipeline allocates nothing: posing,
//! skinning, on-demand refit, traversal (with or without its visit log) and
//! the narrow phase reuse their buffers (counted with a global allocator that
//! counts).

use std::alloc::{GlobalAlloc, Layout, System};
use std::path::Path;
use std::sync::atomic::{AtomicU64, Ordering};

use cornertree::character::PoseBuffers;
use cornertree::pipeline::Method;
use cornertree::pipeline::driver::Pipeline;
use cornertree::scenario::open_scenario;

struct Counting;

static ALLOCATIONS: AtomicU64 = AtomicU64::new(0);

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        ALLOCATIONS.fetch_add(1, Ordering::Relaxed);
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

#[test]
fn frames_after_the_first_allocate_nothing() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/touching.toml");
    let r = open_scenario(&path).unwrap();
    let options = r.pipeline_options(r.first());
    let env = &r.environment.mesh;
    // Every method, without and with the visit log a recorder turns on.
    let mut pipes: Vec<Pipeline> = Vec::new();
    for log in [false, true] {
        for m in Method::ALL {
            let mut p = Pipeline::new(&r.first().character, env, m, options);
            p.set_visit_log(log);
            pipes.push(p);
        }
    }
    let mut buffers = PoseBuffers::new(&r.first().character);
    let frames = 12;
    let mut per_frame = Vec::with_capacity(frames);
    for k in 0..frames {
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        r.first().pose_frame(&mut buffers, k);
        let mut pairs = 0;
        for p in &mut pipes {
            pairs += p.detect(&buffers, &r.first().character, env).pairs;
        }
        per_frame.push(ALLOCATIONS.load(Ordering::Relaxed) - before);
        assert!(pairs > 0, "frame {k} has contacts");
    }
    assert!(per_frame[0] > 0, "the first frame sizes the buffers");
    assert!(
        per_frame[1..].iter().all(|&n| n == 0),
        "allocations per frame: {per_frame:?}"
    );
}

/// A world's frames through [`cornertree::world::World`] on `threads`
/// threads, the loop inside the world's pool: once to size every buffer (pair lists grow to the most pairs a
/// frame has), then the same frames again, which must allocate nothing (the
/// rayon pool's job queues included). Returns the allocations of each frame
/// of both passes.
fn world_allocations(scenario: &str, frames: usize, threads: usize) -> (Vec<u64>, Vec<u64>) {
    use cornertree::world::World;
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join(scenario);
    let mut r = open_scenario(&path).unwrap();
    r.frames = frames;
    r.dedup = false;
    let mut world = World::new(r, threads).unwrap();
    let pass = |world: &mut World| {
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
    // The frame loop on one of the world's threads (`World::in_pool`).
    world.in_pool(|w| {
        let first = pass(w);
        let second = pass(w);
        (first, second)
    })
}

#[test]
fn world_frames_allocate_nothing_once_buffers_are_sized() {
    for (scenario, frames) in [
        ("scenarios/crowd.toml", 10),
        ("scenarios/door.toml", 20),
        ("scenarios/handshake.toml", 10),
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
