//! `cornertree run` end to end: report shape, determinism, bad scenarios.

use std::path::{Path, PathBuf};
use std::process::Command;

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cornertree"))
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cornertree-run-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn run_json(extra: &[&str], out: &Path) -> serde_json::Value {
    let o = bin()
        .arg("run")
        .arg(root().join("scenarios/cesium_man.toml"))
        .args(["--frames", "6", "--json"])
        .arg(out)
        .args(extra)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(
        stdout.contains("Sph-Sph tests") && stdout.contains("Operations"),
        "{stdout}"
    );
    serde_json::from_str(&std::fs::read_to_string(out).unwrap()).unwrap()
}

#[test]
fn one_method_report_has_the_documented_keys() {
    let rrd = scratch("one.rrd");
    let v = run_json(
        &[
            "--method",
            "sphere-division",
            "--save",
            rrd.to_str().unwrap(),
        ],
        &scratch("one.json"),
    );
    assert!(rrd.is_file(), "--save writes the recording");
    for key in ["scenario", "method", "hierarchy_bytes", "frames"] {
        assert!(v.get(key).is_some(), "{key} missing");
    }
    assert_eq!(v["method"], "sphere-division");
    let frames = v["frames"].as_array().unwrap();
    assert_eq!(frames.len(), 6);
    for f in frames {
        for key in [
            "sphere_sphere",
            "tri_tri",
            "plane_sphere",
            "operations",
            "refits",
            "time_ms",
            "pairs",
        ] {
            assert!(f.get(key).is_some(), "frame key {key} missing");
        }
        let ops = 10 * f["sphere_sphere"].as_u64().unwrap()
            + 96 * f["tri_tri"].as_u64().unwrap()
            + 30 * f["plane_sphere"].as_u64().unwrap();
        assert_eq!(f["operations"].as_u64().unwrap(), ops);
        assert!(f["sphere_sphere"].as_u64().unwrap() > 0);
    }
}

#[test]
fn same_scenario_same_counters_and_pairs() {
    let strip = |v: &serde_json::Value| -> Vec<serde_json::Value> {
        v["runs"]
            .as_array()
            .unwrap()
            .iter()
            .flat_map(|r| r["frames"].as_array().unwrap().clone())
            .map(|mut f| {
                for k in [
                    "time_ms",
                    "pose_ms",
                    "skinning_ms",
                    "refit_ms",
                    "traversal_ms",
                    "narrow_ms",
                ] {
                    f.as_object_mut().unwrap().remove(k);
                }
                f
            })
            .collect()
    };
    let a = run_json(&["--no-record"], &scratch("a.json"));
    let b = run_json(&["--no-record"], &scratch("b.json"));
    assert_eq!(
        a["runs"].as_array().unwrap().len(),
        cornertree::pipeline::Method::ALL.len(),
        "every method by default"
    );
    assert_eq!(strip(&a), strip(&b));
}

#[test]
fn bad_scenarios_fail_cleanly() {
    let good_rest = "[character]\nsource = \"generated:humanoid?vertices=2000\"\n[environment]\nkind = \"museum\"\n[placement]\nstart = { translation = [1.0, 0.0, 1.0] }\n";
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        ("syntax.toml", "frames = [\n".into(), vec!["syntax.toml:"]),
        (
            "unknown.toml",
            "colour = 3\n[character]\nsource = \"generated:humanoid\"\n".into(),
            vec!["unknown.toml:", "colour"],
        ),
        (
            "method.toml",
            format!("methods = [\"fastest\"]\n{good_rest}"),
            vec!["method.toml:", "fastest"],
        ),
        (
            "negative.toml",
            format!("frames = -3\n{good_rest}"),
            vec!["negative.toml:1:", "frames", "-3"],
        ),
        (
            "asset.toml",
            "[character]\nsource = \"no/such/character.glb\"\n[environment]\nkind = \"museum\"\n[placement]\nstart = { translation = [1.0, 0.0, 1.0] }\n".into(),
            vec!["asset.toml", "no/such/character.glb"],
        ),
    ];
    for (name, text, words) in cases {
        // Each case runs in an empty directory: a failed run must not leave a
        // recording behind (by default they go to ./recordings).
        let dir = scratch(&format!("bad-{name}"));
        std::fs::create_dir_all(&dir).unwrap();
        let p = dir.join(name);
        std::fs::write(&p, text).unwrap();
        let o = bin().arg("run").arg(&p).current_dir(&dir).output().unwrap();
        let err = String::from_utf8_lossy(&o.stderr);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{name}: one line: {err}");
        for w in words {
            assert!(err.contains(w), "{name}: {err} lacks {w}");
        }
        assert!(
            !dir.join("recordings").exists(),
            "{name}: a failed run left a recordings directory"
        );
    }
    let o = bin()
        .args(["run", "no/such/scenario.toml"])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("no/such/scenario.toml"));
}
