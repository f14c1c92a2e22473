//! Continuous detection through a world (issue 14, items 4–6).
//!
//! * On a small generated world (characters reaching into each other and
//!   into the museum's wall, a thin box flying through an arm, a character
//!   running through a thin panel between frames), the exact
//!   methods' continuous pairs are exactly those of a brute force over every
//!   triangle pair of every body pair (swept boxes, then the pipeline's own
//!   leaf test, `continuous_narrow::leaf_toi`): the swept hierarchies lose
//!   nothing (the leaf test itself is checked against sub-steps in
//!   `tests/ccd_props.rs`).
//! * `scenarios/tunnel.toml` through `run --ccd`: in one JSON report, full
//!   recall against the sub-stepped exact oracle on every step, and true
//!   contacts the same method's discrete frames miss at both ends.

use std::path::{Path, PathBuf};
use std::process::Command;

use cornertree::geometry::Point;
use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::geometry::ccd_triangles::MovingTriangle;
use cornertree::pipeline::Method;
use cornertree::pipeline::continuous_narrow::{CcdCounters, leaf_toi};
use cornertree::world::{CharacterPair, ObjectPair, RoomPair};
use cornertree_workbench::scenario::{Scenario, resolve};
use cornertree_workbench::session::Session;
use cornertree_workbench::truth::substep::{MovingCorners, StepBodies};

const SMALL_WORLD: &str = r#"
fps = 30
frames = 10
methods = ["original", "sphere-division", "pruned-tri-tri", "undivided-pruned-tri-tri"]
dedup = false

[environment]
kind = "museum"
seed = 0
vertices = 983

[[characters]]
name = "ada"
source = "generated:humanoid?vertices=700&seed=1"
clip = "reach"
clip_offset = 0.75
placement = { start = { translation = [4.27, 0, 2.3], yaw_degrees = 0 } }

[[characters]]
name = "ben"
source = "generated:humanoid?vertices=700&seed=1"
clip = "reach"
clip_offset = 0.55
placement = { start = { translation = [3.73, 0, 3.73], yaw_degrees = 180 } }

[[characters]]
name = "cat"
source = "generated:humanoid?vertices=600&seed=3"
clip = "walk"
# Half through the museum's south wall (z = 0), walking along it.
placement = { start = { translation = [8.0, 0, 0.05], yaw_degrees = 90 } }

[[characters]]
name = "dan"
source = "generated:humanoid?vertices=600&seed=4"
clip = "walk"
# Running along the corridor at 15 m/s (0.5 m a frame) through a still,
# thin panel between frames 3 and 4.
placement = { path = { waypoints = [[10.0, 0, 1.2], [16.0, 0, 1.2]], speed = 15 } }

[[objects]]
name = "door"
kind = "panel"
size = [2.0, 2.2]
motion = { times = [0], positions = [[11.8, 0, 2.2]], yaw_degrees = 90 }

[[objects]]
name = "pole"
kind = "box"
size = [0.02, 0.6, 0.02]
motion = { times = [0.05, 0.31667], positions = [[2.0, 1.1, 2.9], [6.0, 1.1, 2.9]] }
"#;

type Key = (u8, [u32; 4]);

fn corners(m: &MovingCorners) -> MovingTriangle<f64> {
    MovingTriangle {
        start: m[0],
        end: m[1],
    }
}

fn apart(a: &MovingCorners, b: &MovingCorners) -> bool {
    (0..3).any(|k| {
        let lo = |m: &MovingCorners| {
            m.iter()
                .flatten()
                .map(|p| p[k])
                .fold(f64::INFINITY, f64::min)
        };
        let hi = |m: &MovingCorners| {
            m.iter()
                .flatten()
                .map(|p| p[k])
                .fold(f64::NEG_INFINITY, f64::max)
        };
        hi(a) < lo(b) || hi(b) < lo(a)
    })
}

/// Every pair of the step touching by the leaf test, with its time of
/// impact: character triangles in the trees (all, de-duplication off),
/// every room, object and other character triangle.
fn brute_force(bodies: &StepBodies<'_>, params: &CcdParams) -> Vec<(Key, f64)> {
    let scene = bodies.scene;
    let mut out = Vec::new();
    let mut c = CcdCounters::default();
    let mut test = |key: Key, a: &MovingCorners, b: &MovingCorners, still: bool| {
        if apart(a, b) {
            return;
        }
        if let Some(t) = leaf_toi(&corners(a), &corners(b), still, params, &mut c) {
            out.push((key, t));
        }
    };
    for (ci, a) in scene.characters.iter().enumerate() {
        let n = a.character.mesh.triangle_count() as u32;
        let tris: Vec<MovingCorners> = (0..n).map(|t| bodies.character_triangle(ci, t)).collect();
        for rt in 0..scene.environment.mesh.triangle_count() as u32 {
            let b = bodies.room_triangle(rt);
            for (t, ta) in tris.iter().enumerate() {
                test((0, [ci as u32, t as u32, rt, 0]), ta, &b, true);
            }
        }
        for (o, prop) in scene.objects.iter().enumerate() {
            for ot in 0..prop.mesh.triangle_count() as u32 {
                let b = bodies.object_triangle(o, ot);
                for (t, ta) in tris.iter().enumerate() {
                    test((1, [ci as u32, t as u32, o as u32, ot]), ta, &b, false);
                }
            }
        }
        for (cj, b) in scene.characters.iter().enumerate().skip(ci + 1) {
            for tb in 0..b.character.mesh.triangle_count() as u32 {
                let b = bodies.character_triangle(cj, tb);
                for (t, ta) in tris.iter().enumerate() {
                    test((2, [ci as u32, t as u32, cj as u32, tb]), ta, &b, false);
                }
            }
        }
    }
    out.sort_by_key(|x| x.0);
    out
}

fn keys(o: &cornertree::world::SweepContacts) -> Vec<(Key, f64)> {
    let room = |p: &RoomPair| (0, [p.character.0, p.triangle, p.room_triangle, 0]);
    let object = |p: &ObjectPair| {
        (
            1,
            [p.character.0, p.triangle, p.object.0, p.object_triangle],
        )
    };
    let chars = |p: &CharacterPair| (2, [p.a.0, p.triangle_a, p.b.0, p.triangle_b]);
    let mut v: Vec<(Key, f64)> = o
        .room_pairs
        .iter()
        .map(|p| (room(&p.pair), p.toi))
        .chain(o.object_pairs.iter().map(|p| (object(&p.pair), p.toi)))
        .chain(o.character_pairs.iter().map(|p| (chars(&p.pair), p.toi)))
        .collect();
    v.sort_by_key(|x| x.0);
    v
}

#[test]
fn exact_methods_find_exactly_the_brute_force_pairs() {
    let s = Scenario::parse(SMALL_WORLD, Path::new("small_world.toml")).unwrap();
    let r = resolve(&s, Path::new(env!("CARGO_MANIFEST_DIR"))).unwrap();
    let mut world = Session::new(r, 2).unwrap();
    let params = CcdParams::default();
    world.enable_continuous(params);
    let mut prev: Vec<Vec<Point>> = Vec::new();
    let mut prev_poses = Vec::new();
    let mut seen = [0usize; 3];
    for k in 0..world.frames() {
        world.pose(k);
        world.skin_all();
        for m in 0..world.worlds().len() {
            world.sweep(m, k).unwrap();
        }
        if k > 0 {
            let bodies = StepBodies {
                scene: &world.scene,
                start: prev.iter().map(Vec::as_slice).collect(),
                end: world
                    .buffers
                    .iter()
                    .map(|b| b.positions.as_slice())
                    .collect(),
                object_start: &prev_poses,
                object_end: &world.object_poses,
            };
            let want = brute_force(&bodies, &params);
            for (kind, _) in &want {
                seen[kind.0 as usize] += 1;
            }
            for (m, method) in world.methods().enumerate() {
                let got = keys(world.world(m).sweep_contacts().unwrap());
                assert_eq!(
                    got.len(),
                    want.len(),
                    "step {k}, {method}: {} pairs, brute force {}",
                    got.len(),
                    want.len()
                );
                for (g, w) in got.iter().zip(&want) {
                    assert_eq!(g.0, w.0, "step {k}, {method}");
                    assert_eq!(g.1.to_bits(), w.1.to_bits(), "step {k}, {method}: {g:?}");
                }
            }
        }
        prev = world.buffers.iter().map(|b| b.positions.clone()).collect();
        prev_poses = world.object_poses.clone();
    }
    // The scene exercises every kind of pair.
    assert!(
        seen.iter().all(|&n| n > 0),
        "pairs per kind over the run: {seen:?}"
    );
    assert_eq!(
        world.methods().collect::<Vec<_>>(),
        [
            Method::Original,
            Method::SphereDivision,
            Method::PrunedTriTri,
            Method::UndividedPrunedTriTri
        ]
    );
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cornertree-ccd-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Plays scenario `name` with `args` (its continuous detection on) and
/// checks every step's recall against the sub-stepped reference is 1, no
/// pair only continuous detection found is beyond tolerance, and discrete
/// detection missed true contacts.
fn full_recall_and_discrete_misses_contacts(name: &str, args: &[&str]) {
    let json = scratch(&format!("{name}.json"));
    let o = Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .arg("run")
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join(format!("scenarios/{name}.toml")))
        .args(args)
        .args(["--no-record", "--json"])
        .arg(&json)
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    // One method's report is its run; several methods' report lists them.
    let runs = match report["runs"].as_array() {
        Some(runs) => runs.clone(),
        None => vec![report.clone()],
    };
    for run in &runs {
        let method = run["method"].as_str().unwrap();
        let frames = run["frames"].as_array().unwrap();
        assert!(frames[0].get("continuous").is_none(), "frame 0 has no step");
        let mut missed_true = 0;
        for f in &frames[1..] {
            let c = &f["continuous"];
            let r = &c["reference"];
            assert_eq!(r["recall"], 1.0, "{method}, step {}: {r}", c["step"]);
            assert!(r["missed"].as_array().unwrap().is_empty());
            // A pair discrete detection missed at both ends that is no
            // pair only continuous detection found is a reference contact.
            let only: Vec<&serde_json::Value> = r["only_continuous"]
                .as_array()
                .unwrap()
                .iter()
                .map(|x| &x["pair"])
                .collect();
            missed_true += c["missed_by_discrete"]
                .as_array()
                .unwrap()
                .iter()
                .filter(|p| !only.contains(p))
                .count();
            for x in r["only_continuous"].as_array().unwrap() {
                let class = x["class"].as_str().unwrap();
                assert_ne!(class, "beyond_tolerance", "{method}: {x}");
            }
        }
        assert!(
            missed_true > 0,
            "{method}: discrete detection missed no true contact"
        );
        let total = &run["continuous"];
        assert_eq!(total["reference"]["recall"], 1.0, "{total}");
        assert_eq!(total["reference"]["steps_below_full_recall"], 0);
        assert!(total["missed_by_discrete"].as_u64().unwrap() > 0);
    }
}

#[test]
fn tunnel_has_full_recall_and_discrete_misses_contacts() {
    full_recall_and_discrete_misses_contacts(
        "tunnel",
        &["--method", "pruned-tri-tri", "--method", "plane-sphere"],
    );
}

/// The humanoid's arm sweeps through its own chest between frames: every
/// self contact of the sub-stepped reference is found.
#[test]
fn arm_through_the_chest_has_full_recall_and_discrete_misses_contacts() {
    full_recall_and_discrete_misses_contacts(
        "self_swing",
        &[
            "--method",
            "undivided-pruned-tri-tri",
            "--no-dedup",
            "--frames",
            "10",
        ],
    );
}
