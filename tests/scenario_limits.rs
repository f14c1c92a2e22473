//! Limits instead of exhaustion (issue #15): every scenario number outside
//! its documented range is refused at load in one line naming the file, the
//! line and column and the field; sizes past the run's memory budget are
//! refused before they are allocated, naming the value that drove them; and
//! `cornertree run` exits with status 1 on both.

mod common;
use common::glb::Glb;

use std::path::{Path, PathBuf};
use std::process::Command;
use std::time::{Duration, Instant};

use cornertree_workbench::scenario::budget::{self, cost};
use cornertree_workbench::scenario::{RunLimits, Scenario, load_scenario, resolve, resolve_with};

/// A small single-character scenario: `{GAP}` is the placement's gap.
const BASE: &str = "[character]
source = \"generated:humanoid?vertices=1000\"
clip = \"walk\"

[environment]
kind = \"living-room\"

[placement]
gap = { surface = \"south wall\", metres = {GAP} }
";

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("cornertree-limits-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir.join(name)
}

/// Writes `text` as `name`, loads and resolves it (default limits) and
/// returns the error, checked to be one line starting with the path.
fn refused(name: &str, text: &str) -> (PathBuf, String) {
    let path = scratch(name);
    std::fs::write(&path, text).unwrap();
    let e = load_scenario(&path)
        .and_then(|s| resolve(&s, path.parent().unwrap()))
        .err()
        .unwrap_or_else(|| panic!("{name} was accepted"))
        .to_string();
    assert!(!e.contains('\n'), "{e:?}");
    assert!(e.starts_with(&path.display().to_string()), "{e}");
    (path, e)
}

#[test]
fn a_gap_of_minus_1e30_is_refused_at_its_column() {
    let (path, e) = refused("gap.toml", &BASE.replace("{GAP}", "-1e30"));
    assert_eq!(
        e,
        format!(
            "{}:9:42: placement.gap.metres: must be finite metres within ±1e6, not -1e30",
            path.display()
        )
    );
    // The ends of the range are accepted (far from the wall, no contact).
    let path = scratch("gap_far.toml");
    std::fs::write(&path, BASE.replace("{GAP}", "-1e6")).unwrap();
    let r = resolve(&load_scenario(&path).unwrap(), path.parent().unwrap()).unwrap();
    assert!((r.first().gap.as_ref().unwrap().achieved + 1e6).abs() < 1.0);
}

#[test]
fn ten_to_the_twelve_frames_are_refused() {
    let (path, e) = refused(
        "frames.toml",
        &format!("frames = 1000000000000\n{}", BASE.replace("{GAP}", "0.01")),
    );
    assert_eq!(
        e,
        format!(
            "{}:1:10: frames: must be a whole number from 1 to 1000000, not 1000000000000",
            path.display()
        )
    );
}

#[test]
fn a_room_of_ten_to_the_ten_vertices_is_refused() {
    let text = BASE.replace("{GAP}", "0.01").replace(
        "kind = \"living-room\"",
        "kind = \"living-room\"\nvertices = 10000000000",
    );
    let (path, e) = refused("room.toml", &text);
    assert_eq!(
        e,
        format!(
            "{}:7:12: environment.vertices: must be a whole number from 1 to 20000000, not 10000000000",
            path.display()
        )
    );
}

#[test]
fn a_humanoid_of_ten_to_the_ten_vertices_is_refused() {
    let text = BASE
        .replace("{GAP}", "0.01")
        .replace("vertices=1000", "vertices=10000000000");
    let (path, e) = refused("humanoid.toml", &text);
    assert_eq!(
        e,
        format!(
            "{}:2:10: character.source: vertices must be a whole number from 500 to 2000000, not 10000000000",
            path.display()
        )
    );
}

#[test]
fn numbers_out_of_range_name_their_field() {
    let good = BASE.replace("{GAP}", "0.01");
    let cases: [(String, &str); 14] = [
        (
            format!("fps = 1e300\n{good}"),
            "1:7: fps: must be frames per second from 0.001 to 10000, not 1e300",
        ),
        (
            format!("fps = nan\n{good}"),
            "1:7: fps: must be frames per second from 0.001 to 10000, not NaN",
        ),
        (
            format!("threshold = 0\n{good}"),
            "1:13: threshold: must be metres from 1e-6 to 1e6, not 0",
        ),
        (
            format!("frames = 0\n{good}"),
            "1:10: frames: must be a whole number from 1 to 1000000, not 0",
        ),
        (
            format!("methods = [\"original\", \"original\"]\n{good}"),
            "1:11: methods: original is listed twice (methods[1])",
        ),
        (
            good.replace("metres = 0.01", "metres = 0.01, along = inf"),
            "9:56: placement.gap.along: must be finite metres within ±1e6, not inf",
        ),
        (
            good.replace("metres = 0.01", "metres = 0.01, yaw_degrees = -1e300"),
            "9:62: placement.gap.yaw_degrees: must be finite degrees within ±1e6, not -1e300",
        ),
        (
            good.replace(
                "gap = { surface = \"south wall\", metres = 0.01 }",
                "start = { translation = [0, 1e7, 0] }",
            ),
            "9:25: placement.start.translation: must be finite metres within ±1e6, not 1e7",
        ),
        (
            good.replace(
                "gap = { surface = \"south wall\", metres = 0.01 }",
                "path = { waypoints = [[0, 0, 0]], speed = 1e30 }",
            ),
            "9:43: placement.path.speed: must be positive m/s up to 1e6, not 1e30",
        ),
        (
            good.replace(
                "gap = { surface = \"south wall\", metres = 0.01 }",
                "path = { waypoints = [[0, 0, 0], [nan, 0, 0]] }",
            ),
            "9:22: placement.path.waypoints[1]: must be finite metres within ±1e6, not NaN",
        ),
        (
            good.replace(
                "kind = \"living-room\"",
                "kind = \"living-room\"\nsubdivide = [{ object = \"floor\", times = 17 }]",
            ),
            "7:42: environment.subdivide[0].times: must be a whole number from 0 to 16, not 17",
        ),
        (
            format!("{good}[recording]\nmesh_every = 0\n"),
            "11:14: recording.mesh_every: must be a whole number from 1 to 4294967295, not 0",
        ),
        (
            format!("ccd = true\nccd_substeps = 0\n{good}"),
            "2:16: ccd_substeps: must be a whole number from 1 to 65536, not 0",
        ),
        (
            format!("ccd_substeps = 100000\n{good}"),
            "1:16: ccd_substeps: must be a whole number from 1 to 65536, not 100000",
        ),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let (path, e) = refused(&format!("range{i}.toml"), text);
        assert_eq!(e, format!("{}:{want}", path.display()));
    }
}

#[test]
fn world_numbers_out_of_range_name_their_field() {
    let head = "[environment]\nkind = \"living-room\"\n[[characters]]\nname = \"a\"\nsource = \"generated:humanoid?vertices=1000\"\nplacement = { start = { translation = [1, 0, 1] } }\n";
    let cases = [
        (
            format!("{head}clip_offset = 1e300\n"),
            "7:15: characters[0].clip_offset: must be finite seconds within ±1e6, not 1e300",
        ),
        (
            format!(
                "{head}[[objects]]\nname = \"b\"\nkind = \"ball\"\nradius = 1e30\nmotion = {{ times = [0], positions = [[0, 0, 0]] }}\n"
            ),
            "10:10: objects[0].radius: must be positive metres up to 1e6, not 1e30",
        ),
        (
            format!(
                "{head}[[objects]]\nname = \"b\"\nkind = \"ball\"\nmotion = {{ times = [0, 1e300], positions = [[0, 0, 0], [1, 0, 0]] }}\n"
            ),
            "10:10: objects[0].motion.times: must be finite seconds within ±1e6, not 1e300",
        ),
        (
            format!(
                "{head}[[objects]]\nname = \"d\"\nkind = \"door\"\nmotion = {{ times = [0, 1], degrees = [0, 1e30] }}\n"
            ),
            "10:10: objects[0].motion.degrees: must be finite degrees within ±1e6, not 1e30",
        ),
        (
            format!(
                "{head}[[objects]]\nname = \"b\"\nkind = \"box\"\nsize = [1, -1, 1]\nmotion = {{ times = [0], positions = [[0, 0, 0]] }}\n"
            ),
            "10:8: objects[0].size: must be positive metres up to 1e6, not -1",
        ),
    ];
    for (i, (text, want)) in cases.iter().enumerate() {
        let e = Scenario::parse(text, Path::new("w.toml"))
            .err()
            .unwrap_or_else(|| panic!("case {i} was accepted"))
            .to_string();
        assert_eq!(e, format!("w.toml:{want}"), "case {i}");
    }
    // 257 characters, once past the old fixed cap, are read: the memory
    // budget bounds a scenario's characters now.
    let many = format!(
        "[environment]\nkind = \"living-room\"\n{}",
        (0..257)
            .map(|i| format!("[[characters]]\nname = \"c{i}\"\nsource = \"generated:humanoid?vertices=500\"\nplacement = {{ start = {{ translation = [1, 0, 1] }} }}\n"))
            .collect::<String>()
    );
    assert_eq!(
        Scenario::parse(&many, Path::new("w.toml"))
            .unwrap()
            .characters
            .len(),
        257
    );
}

/// A crowd past the memory budget is refused, naming it, before its
/// instances are built: the budget, not a fixed cap, bounds the count.
#[test]
fn a_crowd_past_the_budget_is_refused_naming_it() {
    let text = "[environment]\nkind = \"plaza\"\n[crowd]\nsource = \"generated:humanoid?vertices=10000\"\ncount = 200000\n";
    let start = Instant::now();
    let (_, e) = refused("big_crowd.toml", text);
    assert!(e.contains("200000 characters"), "{e}");
    assert!(e.contains(": crowd.count: "), "{e}");
    assert!(e.contains("over the run's memory budget"), "{e}");
    assert!(start.elapsed().as_secs() < 60, "{:?}", start.elapsed());
    // On a plaza of a given size, the instances themselves: refused at the
    // crowd's source once the budget is spent.
    let text = text.replace("kind = \"plaza\"", "kind = \"plaza\"\nsize = [10, 10]");
    let (_, e) = refused("big_crowd_sized.toml", &text);
    assert!(e.contains(": crowd.source: "), "{e}");
    assert!(e.contains("another instance of a character of"), "{e}");
}

/// Past the budget, the value that drove the size is named before anything
/// big is allocated.
#[test]
fn sizes_past_the_budget_are_refused_before_they_are_built() {
    // A 20,000,000-vertex room with every method's hierarchy.
    let text = BASE.replace("{GAP}", "0.01").replace(
        "kind = \"living-room\"",
        "kind = \"living-room\"\nvertices = 20000000",
    );
    let start = Instant::now();
    let (path, e) = refused("big_room.toml", &text);
    let v = 20_000_000usize;
    let methods = cornertree::pipeline::Method::ALL.len();
    let bytes = cost::ROOM_PER_VERTEX * v + budget::static_mesh_bytes(2 * v, methods, 1).unwrap();
    assert_eq!(
        e,
        format!(
            "{}: environment.vertices: a living room of 20000000 vertices with {methods} methods' hierarchies needs about {}, over the run's memory budget of 4.0 GiB (RunLimits::max_bytes, --memory-budget)",
            path.display(),
            budget::show_bytes(bytes)
        )
    );
    assert!(
        start.elapsed() < Duration::from_secs(5),
        "refused before building"
    );

    // A budget too small for the shipped crowd names the character that
    // crosses it.
    let crowd = Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/crowd.toml");
    let s = load_scenario(&crowd).unwrap();
    let e = resolve_with(
        &s,
        crowd.parent().unwrap(),
        &RunLimits {
            max_bytes: 800 << 20,
        },
    )
    .unwrap_err()
    .to_string();
    assert!(
        e.contains(": characters[") && e.contains(".source: a humanoid of 10000 vertices"),
        "{e}"
    );

    // A threshold so small that every triangle is divided to the level cap.
    let text = format!(
        "threshold = 1e-6\nmethods = [\"sphere-division\"]\n{}",
        BASE.replace("{GAP}", "0.01")
    );
    let (_, e) = refused("tiny_threshold.toml", &text);
    assert!(
        e.contains(": threshold: threshold = 1e-6 m: dividing the big triangles ("),
        "{e}"
    );
}

#[test]
fn the_cli_exits_with_status_1_and_one_line() {
    let run = |args: &[&str]| {
        let o = Command::new(env!("CARGO_BIN_EXE_cornertree"))
            .args(args)
            .output()
            .unwrap();
        (
            o.status.code(),
            String::from_utf8_lossy(&o.stderr).into_owned(),
        )
    };
    let path = scratch("cli_gap.toml");
    std::fs::write(&path, BASE.replace("{GAP}", "-1e30")).unwrap();
    let (code, err) = run(&["run", path.to_str().unwrap(), "--no-record"]);
    assert_eq!(code, Some(1));
    assert_eq!(
        err,
        format!(
            "error: {}:9:42: placement.gap.metres: must be finite metres within ±1e6, not -1e30\n",
            path.display()
        )
    );
    let good = scratch("cli_good.toml");
    std::fs::write(&good, BASE.replace("{GAP}", "0.01")).unwrap();
    let (code, err) = run(&[
        "run",
        good.to_str().unwrap(),
        "--no-record",
        "--frames",
        "1000000000000",
    ]);
    assert_eq!(code, Some(1));
    assert_eq!(
        err,
        "error: --frames: must be a whole number from 1 to 1000000, not 1000000000000\n"
    );
    let (code, err) = run(&[
        "run",
        good.to_str().unwrap(),
        "--no-record",
        "--memory-budget",
        "0.01",
    ]);
    assert_eq!(code, Some(1));
    assert!(
        err.starts_with(&format!(
            "error: {}: environment.kind: a living room of 133139 vertices",
            good.display()
        )) && err.ends_with(
            "over the run's memory budget of 10 MiB (RunLimits::max_bytes, --memory-budget)\n"
        ) && err.lines().count() == 1,
        "{err}"
    );
}

/// A character whose clip holds finite but absurd keyframes (1e30 m
/// translations) is refused at the first frame it reaches that far, not
/// played with overflowing distances.
#[test]
fn a_clip_posing_out_of_range_stops_the_run_in_one_line() {
    let cesium = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets/CesiumMan.glb");
    let mut glb = Glb::parse(std::fs::read(cesium).unwrap());
    let output = glb.channel_output(0, 0);
    for element in 0..glb.accessor(output)["count"].as_u64().unwrap() as usize {
        glb.set_float(output, element, 0, 1e30);
    }
    let character = scratch("huge_clip.glb");
    std::fs::write(&character, &glb.bytes).unwrap();
    let path = scratch("huge_clip.toml");
    std::fs::write(
        &path,
        format!(
            "frames = 3\n[character]\nsource = {:?}\n[environment]\nkind = \"museum\"\n[placement]\nstart = {{ translation = [2, 0, 1] }}\n",
            character.display().to_string()
        ),
    )
    .unwrap();
    let o = Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .args(["run", path.to_str().unwrap(), "--no-record"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    assert_eq!(o.status.code(), Some(1), "{err}");
    let prefix = format!(
        "error: {}: character \"character\": frame 0: its clip takes vertices up to ",
        path.display()
    );
    assert!(
        err.starts_with(&prefix)
            && err.ends_with(" m from the origin, beyond the 1e9 accepted for coordinates\n")
            && err.lines().count() == 1,
        "{err}"
    );
}
