//! The run budget's estimates against what building really takes (issue
//! #15): for shipped scenarios and variants where each kind of size
//! dominates (the room, divisions at a small threshold, a subdivided wall,
//! several characters, glTF bodies), the peak bytes allocated while
//! resolving, building every method's hierarchies, setting up the ground
//! truth and playing a frame — measured with a counting allocator — must not
//! exceed the estimate charged to the budget, and the estimate must stay
//! within a small factor of it.

#[path = "fuzz_gltf/alloc.rs"]
mod alloc;

use std::path::Path;
use std::sync::atomic::Ordering;

use alloc::{CURRENT, PEAK};
use cornertree_workbench::scenario::{RunLimits, Scenario, resolve_with};
use cornertree_workbench::session::Session;
use cornertree_workbench::truth::Truth;

#[global_allocator]
static GLOBAL: alloc::Tracking = alloc::Tracking;

/// Largest estimate accepted, as a multiple of the measured peak.
const MOST_OVER: f64 = 5.0;

/// Peak bytes of resolving `text` (as a file in `scenarios/`), building its
/// world on two threads, its ground truth and one frame; and the estimate.
fn measure(name: &str, text: &str) -> (usize, usize) {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(format!("{name}.toml"));
    let before = CURRENT.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let s = Scenario::parse(text, &path).unwrap();
    let r = resolve_with(&s, path.parent().unwrap(), &RunLimits::default()).unwrap();
    let estimate = r.estimated_bytes;
    let mut world = Session::new(r, 2).unwrap();
    world.pose(0);
    world.skin_all();
    let mut t = Truth::new(&world.scene).unwrap();
    t.update(&world.scene, &world.buffers, &world.object_poses)
        .unwrap();
    world.detect_all();
    drop(world);
    let peak = PEAK.load(Ordering::Relaxed) - before;
    (peak, estimate)
}

fn shipped(name: &str) -> String {
    std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenarios/{name}.toml")),
    )
    .unwrap()
}

/// `crowd.toml` with its eight walkers made from one source (seed 11): one
/// humanoid built and charged in full, seven more instances of it.
fn crowd_of_one_source() -> String {
    let mut text = shipped("crowd");
    for seed in 12..=18 {
        text = text.replace(&format!("seed={seed}\""), "seed=11\"");
    }
    assert_eq!(text.matches("seed=11\"").count(), 8);
    text
}

#[test]
fn estimates_cover_what_building_takes() {
    let touching = shipped("touching");
    let cases = [
        ("touching", touching.clone()),
        ("crowd", shipped("crowd")),
        ("door", shipped("door")),
        ("handshake", shipped("handshake")),
        ("cesium_man", shipped("cesium_man")),
        (
            // Divisions dominate.
            "touching",
            format!(
                "threshold = 0.03\nmethods = [\"sphere-division\", \"plane-sphere\"]\n{touching}"
            ),
        ),
        (
            // A subdivided wall.
            "touching",
            touching.replace(
                "kind = \"living-room\"",
                "kind = \"living-room\"\nsubdivide = [{ object = \"south wall\", times = 8 }]",
            ),
        ),
        (
            // The room dominates.
            "touching",
            format!(
                "methods = [\"pruned-tri-tri\"]\n{}",
                touching.replace(
                    "kind = \"living-room\"",
                    "kind = \"living-room\"\nvertices = 600000"
                )
            ),
        ),
        (
            // The character dominates.
            "touching",
            touching.replace("vertices=10000", "vertices=150000"),
        ),
        (
            // Instances of one source: eight walkers of one humanoid
            // (charged once in full, then per instance).
            "crowd",
            crowd_of_one_source(),
        ),
    ];
    let mut failures = Vec::new();
    for (i, (name, text)) in cases.iter().enumerate() {
        let (peak, estimate) = measure(name, text);
        let ratio = estimate as f64 / peak as f64;
        eprintln!(
            "case {i} ({name}): peak {:.1} MiB, estimate {:.1} MiB ({ratio:.2}×)",
            peak as f64 / 1048576.0,
            estimate as f64 / 1048576.0
        );
        if !(1.0..=MOST_OVER).contains(&ratio) {
            failures.push(format!("case {i} ({name}): estimate / peak = {ratio:.2}"));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}
