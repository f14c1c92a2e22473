//! Ground truth end to end: `compare`, `run --dump-frame` read back with an
//! independent PLY parser and checked with the exact oracle, and the false
//! positives in recordings.

mod common;

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::process::Command;

use common::Scratch;
use common::rrd::read_rrd;
use cornertree::geometry::exact::{Contact, classify};
use cornertree::geometry::{Point, Triangle};
use ply_rs_bw::parser::Parser;
use ply_rs_bw::ply::{DefaultElement, Property};

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cornertree"))
}

fn scenario(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(name)
}

fn run_ok(args: &[&str]) -> String {
    let o = bin().args(args).output().unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn json(path: &Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

fn pairs(v: &serde_json::Value) -> BTreeSet<(u32, u32)> {
    v.as_array()
        .unwrap()
        .iter()
        .map(|p| (p[0].as_u64().unwrap() as u32, p[1].as_u64().unwrap() as u32))
        .collect()
}

fn run_of<'a>(report: &'a serde_json::Value, method: &str) -> &'a serde_json::Value {
    report["runs"]
        .as_array()
        .unwrap()
        .iter()
        .find(|r| r["method"] == method)
        .unwrap()
}

#[test]
fn touching_scenario_has_contacts_and_exact_methods_find_them_all() {
    let scratch = Scratch::new("truth-touching");
    let out = scratch.path("t.json");
    let frames = 12;
    let text = run_ok(&[
        "compare",
        scenario("touching.toml").to_str().unwrap(),
        "--frames",
        &frames.to_string(),
        "--no-dedup",
        "--json",
        out.to_str().unwrap(),
    ]);
    assert!(text.contains("Pairs precision / recall"), "{text}");
    let report = json(&out);
    let original = run_of(&report, "original");
    let with_contact = original["frames"]
        .as_array()
        .unwrap()
        .iter()
        .filter(|f| f["reference_pairs"].as_u64().unwrap() > 0)
        .count();
    assert!(
        2 * with_contact > frames,
        "contacts in most frames: {with_contact} of {frames}"
    );
    for method in [
        "original",
        "sphere-division",
        "pruned-tri-tri",
        "undivided-pruned-tri-tri",
    ] {
        for f in run_of(&report, method)["frames"].as_array().unwrap() {
            let a = &f["accuracy"]["pairs"];
            assert_eq!(a["fn"], 0, "{method} frame {}: no pair missed", f["frame"]);
            assert_eq!(
                a["fp"], 0,
                "{method} frame {}: no pair invented",
                f["frame"]
            );
            // Against parry: the same pairs, or touching cases only.
            for side in ["extra", "missed"] {
                let d = &f["vs_parry"][side];
                assert_eq!(d["true_error"], 0, "{method} {side}: {d}");
                assert_eq!(d["near_degenerate"], 0, "{method} {side}: {d}");
            }
            // And where they differ, parry differs from the exact answer by
            // as much (its own differences, classified and counted).
            assert_eq!(
                f["vs_parry"]["extra"], f["parry_vs_exact"]["missed"],
                "{method} frame {}",
                f["frame"]
            );
            assert_eq!(
                f["vs_parry"]["missed"], f["parry_vs_exact"]["extra"],
                "{method} frame {}",
                f["frame"]
            );
        }
    }
    // Plane-sphere leaves only add pairs (conservative): recall stays 1.
    for f in run_of(&report, "plane-sphere")["frames"]
        .as_array()
        .unwrap()
    {
        assert_eq!(f["accuracy"]["pairs"]["fn"], 0);
        for fp in f["false_positives"].as_array().unwrap() {
            assert!(fp["distance"].as_f64().unwrap() > 0.0);
        }
    }
}

fn read_ply(path: &Path) -> (Vec<Point>, Vec<[u32; 3]>) {
    let mut f = std::fs::File::open(path).unwrap();
    let ply = Parser::<DefaultElement>::new().read_ply(&mut f).unwrap();
    let float = |p: &Property| match p {
        Property::Float(x) => *x,
        other => panic!("{other:?}"),
    };
    let verts = ply.payload["vertex"]
        .iter()
        .map(|v| Point::new(float(&v["x"]), float(&v["y"]), float(&v["z"])))
        .collect();
    let faces = ply.payload["face"]
        .iter()
        .map(|f| match &f["vertex_indices"] {
            Property::ListUInt(l) => [l[0], l[1], l[2]],
            other => panic!("{other:?}"),
        })
        .collect();
    (verts, faces)
}

#[test]
fn dumped_frame_checks_out_with_an_independent_reader_and_brute_force() {
    let scratch = Scratch::new("truth-dump");
    let dir = scratch.path("frame");
    run_ok(&[
        "run",
        scenario("touching.toml").to_str().unwrap(),
        "--frames",
        "4",
        "--method",
        "original",
        "--no-dedup",
        "--no-record",
        "--dump-frame",
        "3",
        dir.to_str().unwrap(),
    ]);
    let (av, af) = read_ply(&dir.join("avatar.ply"));
    let (ev, ef) = read_ply(&dir.join("environment.ply"));
    let p = json(&dir.join("pairs.json"));
    let reported = pairs(&p["reported"]);
    let reference = pairs(&p["reference"]);
    assert!(!reference.is_empty());
    let tri = |v: &[Point], f: &[[u32; 3]], i: u32| {
        let [a, b, c] = f[i as usize];
        Triangle::new(v[a as usize], v[b as usize], v[c as usize])
    };
    // Brute force over every pair whose boxes overlap, exact oracle.
    let bbox = |t: &Triangle| {
        let lo = t.a.coords.inf(&t.b.coords).inf(&t.c.coords);
        let hi = t.a.coords.sup(&t.b.coords).sup(&t.c.coords);
        (lo, hi)
    };
    let env_boxes: Vec<_> = (0..ef.len() as u32)
        .map(|e| bbox(&tri(&ev, &ef, e)))
        .collect();
    let mut brute = BTreeSet::new();
    for c in 0..af.len() as u32 {
        let tc = tri(&av, &af, c);
        let (lo, hi) = bbox(&tc);
        for (e, (elo, ehi)) in env_boxes.iter().enumerate() {
            let apart = (0..3).any(|k| hi[k] < elo[k] || ehi[k] < lo[k]);
            if !apart && classify(&tc, &tri(&ev, &ef, e as u32)) != Contact::Disjoint {
                brute.insert((c, e as u32));
            }
        }
    }
    assert_eq!(reference, brute, "the reference is the exact answer");
    assert_eq!(
        reported, brute,
        "original without de-duplication reports exactly it"
    );
}

#[test]
fn plane_sphere_false_positives_are_in_the_recording_with_distances() {
    let scratch = Scratch::new("truth-rec");
    let rrd = scratch.path("ps.rrd");
    let out = scratch.path("ps.json");
    run_ok(&[
        "run",
        scenario("cesium_man.toml").to_str().unwrap(),
        "--frames",
        "8",
        "--method",
        "plane-sphere",
        "--save",
        rrd.to_str().unwrap(),
        "--json",
        out.to_str().unwrap(),
    ]);
    let report = json(&out);
    let rec = read_rrd(&rrd);
    let labels = rerun::Points3D::descriptor_labels().component;
    let logged = rec.counts_per_frame("cd/false_positive/labels", labels);
    let mut total = 0;
    for f in report["frames"].as_array().unwrap() {
        let k = f["frame"].as_i64().unwrap();
        let n = f["false_positives"].as_array().unwrap().len();
        assert_eq!(logged.get(&k).copied().unwrap_or(0), n, "frame {k}");
        total += n;
    }
    assert!(
        total > 0,
        "cesium_man 1 cm from a wall gives plane-sphere false positives"
    );
    for p in [
        "cd/false_positive/environment/bodies",
        "cd/false_positive/environment/room",
        "cd/false_negative/environment/bodies",
        "stats/accuracy/pair_precision",
        "stats/reference_pairs",
    ] {
        assert!(rec.entity_paths().contains(p), "{p}");
    }
}
