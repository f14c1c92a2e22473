//! `run --ccd` recordings read back (docs/recordings.md, "Continuous
//! detection"): the continuous entities are there, their per-step counters
//! are the JSON report's, one swept sphere per touching pair, and nothing of
//! `cd/ccd` at steps without pairs.

mod common;

use std::path::Path;
use std::process::Command;

use common::Scratch;
use common::rrd::read_rrd;

#[test]
fn tunnel_recording_carries_the_continuous_steps_of_the_report() {
    let scratch = Scratch::new("ccd-recording");
    let (rrd, json) = (scratch.path("tunnel.rrd"), scratch.path("tunnel.json"));
    let o = Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .arg("run")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/tunnel.toml"))
        .args(["--method", "pruned-tri-tri", "--frames", "29", "--save"])
        .arg(&rrd)
        .arg("--json")
        .arg(&json)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let frames = report["frames"].as_array().unwrap();
    let r = read_rrd(&rrd);
    let paths = r.entity_paths();
    for p in [
        "cd/ccd/toi/characters/00_reacher",
        "cd/ccd/toi/objects/00_pole",
        "cd/ccd/toi/pairs",
        "cd/ccd/toi/pairs_other",
        "cd/ccd/swept_spheres",
        "stats/ccd/pairs",
        "stats/ccd/missed_by_discrete",
        "stats/ccd/recall",
    ] {
        assert!(paths.contains(p), "{p} missing from {paths:?}");
    }
    let pairs = r.scalars("stats/ccd/pairs");
    let missed = r.scalars("stats/ccd/missed_by_discrete");
    let recall = r.scalars("stats/ccd/recall");
    let swept = r.ellipsoids("cd/ccd/swept_spheres");
    let mut with_pairs = 0;
    for f in &frames[1..] {
        let c = &f["continuous"];
        let k = f["frame"].as_i64().unwrap();
        let n = c["pairs"].as_array().unwrap().len();
        assert_eq!(pairs[&k], n as f64, "frame {k}");
        assert_eq!(
            missed[&k],
            c["missed_by_discrete"].as_array().unwrap().len() as f64,
            "frame {k}"
        );
        assert_eq!(recall[&k], 1.0, "frame {k}");
        // One swept sphere per touching pair (its character leaf), and
        // none logged at a step without pairs.
        assert_eq!(swept.get(&k).map_or(0, Vec::len), n, "frame {k}");
        with_pairs += usize::from(n > 0);
    }
    assert!(
        with_pairs > 0 && pairs[&28] > 0.0,
        "the pole's step has pairs"
    );
}
