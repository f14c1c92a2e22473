//! After the first frame, a frame of the pipeline allocates nothing: posing,
//! skinning, on-demand refit, traversal (with or without its visit log) and
//! the narrow phase reuse their buffers (counted with a global allocator that
//! counts).

use std::path::Path;
use std::sync::atomic::Ordering;

use cornertree::character::PoseBuffers;
use cornertree::pipeline::Method;
use cornertree::pipeline::driver::Pipeline;
use cornertree_workbench::scenario::open_scenario;

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::ALLOCATIONS;

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
