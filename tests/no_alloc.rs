//! After the first frame, a frame of the pipeline allocates nothing: posing,
//! skinning, on-demand refit, traversal (with or without its visit log) and
//! the narrow phase reuse their buffers (counted with a global allocator that
//! counts).

use std::path::Path;
use std::sync::atomic::Ordering;

use cornertree::pipeline::Method;
use cornertree_workbench::scenario::open_scenario;
use cornertree_workbench::session::Session;

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::ALLOCATIONS;

fn frames_after_the_first_allocate_nothing() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/touching.toml");
    let mut r = open_scenario(&path).unwrap();
    r.methods = Method::ALL.to_vec();
    // Every method, without and with the visit log a recorder turns on.
    let mut sessions: Vec<Session> = [false, true]
        .into_iter()
        .map(|log| {
            let mut s = Session::new(r.clone(), 1).unwrap();
            for m in 0..s.worlds().len() {
                s.world_mut(m).set_visit_log(log);
            }
            s
        })
        .collect();
    let frames = 12;
    let mut per_frame = Vec::with_capacity(frames);
    for k in 0..frames {
        let before = ALLOCATIONS.load(Ordering::Relaxed);
        let mut pairs = 0;
        for s in &mut sessions {
            s.pose(k);
            s.detect_all();
            pairs += (0..s.worlds().len())
                .map(|m| s.contacts(m).total.pairs)
                .sum::<u64>();
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

/// Run without libtest's harness (`harness = false` in Cargo.toml): the
/// harness's own thread allocates when it prints that a test has run for
/// over a minute, and this binary's global allocator would count it inside
/// a measured frame.
fn main() {
    frames_after_the_first_allocate_nothing();
    println!("frames_after_the_first_allocate_nothing: ok");
}
