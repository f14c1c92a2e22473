//! Recordings of worlds read back: every body, spheres per level, pairs and
//! counters per kind against the JSON report of the same run, and the same
//! counters as a run without a recording (the recorder changes no work).

mod common;

use std::path::Path;
use std::process::Command;

use common::Scratch;
use common::rrd::read_rrd;
use cornertree::world::PairKind;

fn run_ok(args: &[&str]) {
    let o = Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .args(args)
        .output()
        .unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
}

fn scenario(name: &str) -> String {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(name)
        .to_string_lossy()
        .into_owned()
}

fn frames_of(json: &Path) -> Vec<serde_json::Value> {
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).unwrap()).unwrap();
    v["frames"].as_array().unwrap().clone()
}

/// Records `name` for `frames` frames with one method; returns the recording
/// read back and the JSON frames of the same run.
fn record(
    scratch: &Scratch,
    name: &str,
    frames: usize,
) -> (common::rrd::Rrd, Vec<serde_json::Value>) {
    let rrd = scratch.path(&format!("{name}.rrd"));
    let json = scratch.path(&format!("{name}.json"));
    let frames = frames.to_string();
    run_ok(&[
        "run",
        &scenario(&format!("{name}.toml")),
        "--method",
        "pruned-tri-tri",
        "--no-dedup",
        "--frames",
        &frames,
        "--save",
        rrd.to_str().unwrap(),
        "--json",
        json.to_str().unwrap(),
    ]);
    (read_rrd(&rrd), frames_of(&json))
}

#[test]
fn handshake_recording_has_every_character_and_the_counters_per_kind() {
    let scratch = Scratch::new("world-rec-handshake");
    let frames = 6;
    let (rrd, report) = record(&scratch, "handshake", frames);
    assert_eq!(rrd.error, None, "the recording decodes to its end");
    assert!(rrd.has_blueprint);
    let paths = rrd.entity_paths();
    for p in [
        "world/environment/mesh",
        "world/characters/00_ada/mesh",
        "world/characters/00_ada/skeleton",
        "world/characters/00_ada/spheres/level_00",
        "world/characters/01_ben/mesh",
        "world/characters/01_ben/spheres/level_00",
        "cd/colliding/characters/bodies",
        "cd/colliding/environment/room",
        "cd/false_positive/characters/bodies",
        "cd/false_negative/characters/bodies",
        "stats/wall_ms",
        "stats/body_pairs",
        "frame_report",
        "info",
    ] {
        assert!(paths.contains(p), "{p} missing from {paths:?}");
    }
    assert_eq!(
        rrd.frames("world/characters/01_ben/skeleton"),
        (0..frames as i64).collect()
    );
    // Every kind's counters are the report's, frame by frame.
    for kind in PairKind::ALL {
        for counter in ["pairs", "sphere_sphere", "tri_tri", "operations"] {
            let logged = rrd.scalars(&format!("stats/by_kind/{counter}/{}", kind.name()));
            assert_eq!(logged.len(), frames, "{counter} {}", kind.name());
            for (k, f) in report.iter().enumerate() {
                let want = f["by_kind"][kind.name()][counter].as_f64().unwrap();
                assert_eq!(
                    logged[&(k as i64)],
                    want,
                    "frame {k} {counter} {}",
                    kind.name()
                );
            }
        }
        // Exact methods: precision and recall 1 on every frame.
        for what in ["precision", "recall"] {
            let logged = rrd.scalars(&format!("stats/accuracy/{}/{what}", kind.name()));
            assert!(logged.values().all(|&v| v == 1.0), "{what} {logged:?}");
        }
    }
}

#[test]
fn door_recording_moves_the_object_and_changes_no_counter() {
    let scratch = Scratch::new("world-rec-door");
    let frames = 5;
    let (rrd, report) = record(&scratch, "door", frames);
    assert_eq!(rrd.error, None);
    let paths = rrd.entity_paths();
    let object = paths
        .iter()
        .find(|p| p.starts_with("world/objects/") && p.matches('/').count() == 2)
        .unwrap_or_else(|| panic!("no object entity in {paths:?}"))
        .clone();
    assert!(paths.contains(&format!("{object}/mesh")), "{paths:?}");
    assert!(
        paths.contains(&format!("{object}/spheres/level_00")),
        "{paths:?}"
    );
    // Its pose goes in every frame.
    assert_eq!(rrd.frames(&object), (0..frames as i64).collect());
    // The same run without a recording counts the same.
    let json = scratch.path("door-plain.json");
    run_ok(&[
        "run",
        &scenario("door.toml"),
        "--method",
        "pruned-tri-tri",
        "--no-dedup",
        "--frames",
        &frames.to_string(),
        "--no-record",
        "--no-truth",
        "--json",
        json.to_str().unwrap(),
    ]);
    let plain = frames_of(&json);
    for (k, (a, b)) in report.iter().zip(&plain).enumerate() {
        assert_eq!(a["by_kind"], b["by_kind"], "frame {k}");
        assert_eq!(a["pairs_by_kind"], b["pairs_by_kind"], "frame {k}");
        assert_eq!(a["refits"], b["refits"], "frame {k}");
    }
}
