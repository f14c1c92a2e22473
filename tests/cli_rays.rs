//! `cornertree rays`: the documented JSON on a world of eight characters,
//! every first hit the exact reference's, a ray missing every root costing
//! one test per character, and a recording that holds the rays, their hits
//! and the spheres they refit.

use std::path::Path;
use std::process::Command;

#[path = "common/rrd.rs"]
#[allow(dead_code)]
mod rrd;

#[test]
fn rays_on_a_crowd_are_exact_and_recorded() {
    let dir = std::env::temp_dir().join(format!("cornertree-rays-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scenario = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/crowd.toml");
    let (json, rec) = (dir.join("rays.json"), dir.join("rays.rrd"));
    let o = Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .args([
            "rays",
            scenario.to_str().unwrap(),
            "--frames",
            "3",
            "--rays",
            "60",
        ])
        .arg("--json")
        .arg(&json)
        .arg("--save")
        .arg(&rec)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("first hits equal to the exact reference: 180 of 180"),
        "{stdout}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let n = |k: &str| v[k].as_u64().unwrap_or_else(|| panic!("{k} in {v}"));
    let f = |k: &str| v[k].as_f64().unwrap_or_else(|| panic!("{k} in {v}"));
    assert_eq!(n("characters"), 8);
    assert_eq!(n("rays"), 180);
    assert_eq!(n("hits_equal_reference"), 180);
    assert_eq!(n("parry_hits_equal_reference"), 180);
    assert!(n("hits") > 30, "{v}");
    assert!(f("ms_per_frame") > 0.0 && f("parry_ms_per_frame") > 0.0);
    assert!(
        (f("speedup_vs_parry") - f("parry_ms_per_frame") / f("ms_per_frame")).abs()
            < 1e-9 * f("speedup_vs_parry")
    );
    // Every ray tests each character's root once; one that misses them all
    // costs exactly that.
    assert_eq!(v["counters"]["root_tests"].as_u64().unwrap(), 180 * 8);
    let missing = n("rays_missing_every_root");
    assert!(missing > 0, "the fan passes over some heads: {v}");
    assert_eq!(n("root_tests_of_those"), missing * 8);
    assert_eq!(n("sphere_tests_of_those"), 0);

    let r = rrd::read_rrd(&rec);
    assert!(r.error.is_none(), "{:?}", r.error);
    assert!(r.has_blueprint);
    let paths = r.entity_paths();
    for p in [
        "world/rays/hit",
        "world/rays/missed",
        "world/rays/hit_points",
        "stats/rays_hit",
    ] {
        assert!(paths.contains(p), "{p} missing from {paths:?}");
    }
    assert!(
        paths.iter().any(|p| p.contains("refit_by_rays/level_")),
        "{paths:?}"
    );
    assert_eq!(r.frames("world/rays/hit_points").len(), 3);
    let hits: f64 = r.scalars("stats/rays_hit").values().sum();
    assert_eq!(hits as u64, n("hits"));
}
