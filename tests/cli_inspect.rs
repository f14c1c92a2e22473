//! `cornertree inspect` end to end: real assets, JSON keys, and bad input.

mod common;
use common::base64;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cornertree"))
}

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cornertree-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

fn inspect_json(path: &Path) -> serde_json::Value {
    let out = bin()
        .arg("inspect")
        .arg(path)
        .arg("--json")
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is one JSON object")
}

/// A failing run: non-zero exit, one line on stderr naming the file, no panic.
fn assert_clean_failure(out: &Output, file: &str, words: &[&str]) {
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        !out.status.success(),
        "expected failure, got success: {err}"
    );
    assert_eq!(out.status.code(), Some(1), "exit code; stderr: {err}");
    assert!(!err.contains("panicked"), "panic: {err}");
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "one line expected: {err}"
    );
    assert!(err.contains(file), "error does not name {file}: {err}");
    for w in words {
        assert!(
            err.to_lowercase().contains(&w.to_lowercase()),
            "error lacks {w:?}: {err}"
        );
    }
}

#[test]
fn inspect_real_assets() {
    for (name, triangles) in [("CesiumMan.glb", 4672), ("BrainStem.glb", 61666)] {
        let v = inspect_json(&asset(name));
        assert_eq!(v["triangles"], triangles, "{name}");
        let t = v["triangles"].as_u64().unwrap();
        let kept = v["triangles_after_dedup"].as_u64().unwrap();
        assert!(kept < t && kept * 2 >= t / 2, "{name}: {kept} of {t} kept");
        let levels: Vec<u64> = v["tree_levels"]
            .as_array()
            .unwrap()
            .iter()
            .map(|x| x.as_u64().unwrap())
            .collect();
        assert_eq!(levels[0], 1, "one root");
        assert_eq!(
            levels.iter().sum::<u64>(),
            v["tree_nodes"].as_u64().unwrap()
        );
        assert!(v["tree_bytes"].as_u64().unwrap() >= 24 * kept);
        assert!(v["vertices"].as_u64().unwrap() > 0);
        assert_eq!(v["valid"], true);
    }
    // Text form works too.
    let out = bin()
        .arg("inspect")
        .arg(asset("CesiumMan.glb"))
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("nodes per level"));
}

#[test]
fn no_dedup_keeps_every_triangle() {
    let out = bin()
        .arg("inspect")
        .arg(asset("CesiumMan.glb"))
        .args(["--json", "--no-dedup"])
        .output()
        .unwrap();
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["triangles_after_dedup"], v["triangles"]);
}

#[test]
fn missing_file() {
    let out = bin()
        .args(["inspect", "no/such/file.glb"])
        .output()
        .unwrap();
    assert_clean_failure(&out, "no/such/file.glb", &["no such file"]);
}

#[test]
fn not_gltf() {
    let p = scratch("not-a-model.glb");
    std::fs::write(&p, b"this is plain text, not a model\n").unwrap();
    let out = bin().arg("inspect").arg(&p).output().unwrap();
    assert_clean_failure(&out, "not-a-model.glb", &[]);
}

/// A glTF with one primitive of the given mode over three positions.
fn one_primitive_gltf(name: &str, positions: [[f32; 3]; 3], mode: u32) -> PathBuf {
    let mut bytes = Vec::new();
    for p in positions {
        for c in p {
            bytes.extend_from_slice(&c.to_le_bytes());
        }
    }
    let b64 = base64(&bytes);
    let (min, max) = ([-1.0, -1.0, -1.0], [1.0, 1.0, 1.0]);
    let json = format!(
        r#"{{"asset":{{"version":"2.0"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0}}],
"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"mode":{mode}}}]}}],
"accessors":[{{"bufferView":0,"componentType":5126,"count":3,"type":"VEC3","min":{min:?},"max":{max:?}}}],
"bufferViews":[{{"buffer":0,"byteLength":36}}],
"buffers":[{{"byteLength":36,"uri":"data:application/octet-stream;base64,{b64}"}}]}}"#
    );
    let p = scratch(name);
    std::fs::write(&p, json).unwrap();
    p
}

#[test]
fn a_valid_minimal_file_inspects() {
    let p = one_primitive_gltf(
        "ok.gltf",
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        4,
    );
    let v = inspect_json(&p);
    assert_eq!(v["triangles"], 1);
    assert_eq!(v["tree_levels"], serde_json::json!([1]));
}

#[test]
fn no_triangles() {
    // Mode 1 = LINES.
    let p = one_primitive_gltf(
        "lines.gltf",
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        1,
    );
    let out = bin().arg("inspect").arg(&p).output().unwrap();
    assert_clean_failure(&out, "lines.gltf", &["no triangles"]);
}

#[test]
fn nan_position() {
    let p = one_primitive_gltf(
        "nan.gltf",
        [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]],
        4,
    );
    let out = bin().arg("inspect").arg(&p).output().unwrap();
    assert_clean_failure(&out, "nan.gltf", &["vertex 1"]);
}

#[test]
fn animate_reports_refit_keys() {
    let out = bin()
        .arg("inspect")
        .arg(asset("CesiumMan.glb"))
        .args(["--animate", "--json", "--fps", "10", "--skinning", "paper"])
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert_eq!(v["joints"], 19);
    assert_eq!(v["clips"].as_array().unwrap().len(), 1);
    let r = &v["refit"];
    for key in ["frames", "violations", "tightness_mean", "tightness_max"] {
        assert!(r.get(key).is_some(), "refit.{key} missing: {r}");
    }
    assert_eq!(r["violations"], 0);
    assert!(r["frames"].as_u64().unwrap() >= 19, "about 2 s at 10 fps");
    let mean = r["tightness_mean"].as_f64().unwrap();
    assert!(
        (1.0..3.0).contains(&mean),
        "refit spheres are at least as large as minimal ones: {mean}"
    );
}

/// `inspect --animate --json` with extra arguments; the `refit` object.
fn animate_json(name: &str, args: &[&str]) -> serde_json::Value {
    let out = bin()
        .arg("inspect")
        .arg(asset(name))
        .args(["--animate", "--json"])
        .args(args)
        .output()
        .unwrap();
    assert!(
        out.status.success(),
        "{name}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    v["refit"].clone()
}

/// 10 km from the origin, where an f32 ulp is about a millimetre, refit
/// spheres still hold every skinned vertex, with no tolerance at all (the
/// same check as at the origin).
#[test]
fn animate_far_from_origin_keeps_every_vertex_inside() {
    let runs: [(&str, &str, &[&str]); 3] = [
        ("CesiumMan.glb", "linear", &["--fps", "10"]),
        ("CesiumMan.glb", "paper", &["--fps", "10"]),
        // 34k vertices: a few frames, tightness on the first only.
        (
            "BrainStem.glb",
            "linear",
            &["--fps", "2", "--sample-every", "1000000"],
        ),
    ];
    for (name, skinning, extra) in runs {
        let mut args = vec!["--offset", "10000,0,0", "--skinning", skinning];
        args.extend_from_slice(extra);
        let r = animate_json(name, &args);
        assert_eq!(
            r["offset"],
            serde_json::json!([10000.0, 0.0, 0.0]),
            "{name}"
        );
        assert!(r["checks"].as_u64().unwrap() > 0, "{name}");
        assert_eq!(r["tolerance"], 0.0, "{name} {skinning}");
        assert_eq!(
            r["violations"], 0,
            "{name} {skinning}: worst excess {}",
            r["worst_excess"]
        );
    }
}

#[test]
fn bad_offsets_are_rejected_by_the_parser() {
    for bad in [
        "1,2", "1,2,3,4", "1,x,3", "nan,0,0", "0,inf,0", "1e39,0,0", "",
    ] {
        let out = bin()
            .arg("inspect")
            .arg(asset("CesiumMan.glb"))
            .args(["--animate", "--json"])
            .arg(format!("--offset={bad}"))
            .output()
            .unwrap();
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{bad:?}: {err}");
        assert!(!err.contains("panicked"), "{bad:?}: {err}");
        let first = err.lines().next().unwrap_or("");
        assert!(
            first.contains("--offset") && first.contains("invalid value"),
            "{bad:?}: {err}"
        );
    }
    // A negative offset needs no `=`.
    let r = animate_json(
        "CesiumMan.glb",
        &[
            "--offset",
            "-3.5,0,2",
            "--fps",
            "2",
            "--sample-every",
            "1000000",
        ],
    );
    assert_eq!(r["offset"], serde_json::json!([-3.5, 0.0, 2.0]));
    assert_eq!(r["violations"], 0);
}

#[test]
fn unknown_clip_lists_the_clips() {
    let out = bin()
        .arg("inspect")
        .arg(asset("CesiumMan.glb"))
        .args(["--animate", "--clip", "dance"])
        .output()
        .unwrap();
    assert_clean_failure(
        &out,
        "CesiumMan.glb",
        &["no clip named \"dance\"", "animation 0"],
    );
}

#[test]
fn generated_humanoid_inspects_and_bad_specs_fail() {
    let v = inspect_json(Path::new("generated:humanoid?vertices=3000&seed=1"));
    assert_eq!(v["vertices"], 3000);
    let out = bin()
        .args(["inspect", "generated:humanoid?legs=3"])
        .output()
        .unwrap();
    assert!(!out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.contains("legs") && !err.contains("panicked"), "{err}");
}

#[test]
fn closed_stdout_is_not_a_panic() {
    use std::process::Stdio;
    let mut child = bin()
        .arg("inspect")
        .arg(asset("CesiumMan.glb"))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn damaged_glb_fails_inspect_in_one_line() {
    // A NaN keyframe: the issue's crash of `inspect --animate`.
    let mut glb = common::glb::Glb::parse(std::fs::read(asset("CesiumMan.glb")).unwrap());
    let output = glb.channel_output(0, 0);
    glb.set_float(output, 5, 0, f32::NAN);
    let path = scratch("nan-keyframe.glb");
    std::fs::write(&path, &glb.bytes).unwrap();
    let out = bin()
        .arg("inspect")
        .arg(&path)
        .arg("--animate")
        .output()
        .unwrap();
    assert_clean_failure(
        &out,
        "nan-keyframe.glb",
        &[
            "animation 0 channel 0",
            &format!("output accessor {output}"),
            "element 5, component 0 is NaN",
        ],
    );
    // A truncated download.
    let bytes = std::fs::read(asset("CesiumMan.glb")).unwrap();
    let path = scratch("cut.glb");
    std::fs::write(&path, &bytes[..bytes.len() / 2]).unwrap();
    for animate in [false, true] {
        let mut cmd = bin();
        cmd.arg("inspect").arg(&path);
        if animate {
            cmd.arg("--animate");
        }
        assert_clean_failure(&cmd.output().unwrap(), "cut.glb", &["not a glTF 2.0 file"]);
    }
}
