//! Scenario files: every shipped scenario loads and resolves, gap placements
//! achieve their gap (recomputed here from the south walls' known plane
//! `z = 0`), and bad files give one-line errors naming the file, the line and
//! the field.

use std::path::{Path, PathBuf};

use cornertree::character::PoseBuffers;
use cornertree::pipeline::Method;
use cornertree_workbench::scenario::{Placement, Resolved, ScenarioError, load_scenario, resolve};

fn shipped(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(name)
}

/// Minimum over every frame and vertex of the world z (the signed distance to
/// the south wall, whose plane is z = 0 with the room at z > 0), minimum world
/// y, and frames with some vertex at z < 0.
fn south_wall_extremes(r: &Resolved) -> (f64, f64, usize) {
    let mut buffers = PoseBuffers::new(&r.first().character);
    let (mut zmin, mut ymin, mut behind) = (f64::INFINITY, f64::INFINITY, 0);
    for k in 0..r.frames() {
        buffers.pose(&r.first().character, r.first().clip(), r.first().time_at(k));
        buffers.skin_all(&r.first().character, r.first().skinning);
        let iso = r.first().placement_at(k);
        let mut frame_zmin = f64::INFINITY;
        for p in &buffers.positions {
            let w = iso * p;
            frame_zmin = frame_zmin.min(w.z as f64);
            ymin = ymin.min(w.y as f64);
        }
        zmin = zmin.min(frame_zmin);
        behind += usize::from(frame_zmin < 0.0);
    }
    (zmin, ymin, behind)
}

fn check_gap(file: &str, expect_frames: Option<usize>) -> (Resolved, f64, usize) {
    let path = shipped(file);
    let s = load_scenario(&path).unwrap_or_else(|e| panic!("{e}"));
    let Placement::Gap(g) = &s.first_character().placement else {
        panic!("{file}: not a gap placement")
    };
    assert_eq!(g.surface, "south wall");
    let r = resolve(&s, path.parent().unwrap()).unwrap_or_else(|e| panic!("{e}"));
    if let Some(n) = expect_frames {
        assert_eq!(r.frames(), n, "{file}");
    }
    assert!(r.frames() > 1, "{file}: {} frames", r.frames());
    let (zmin, ymin, behind) = south_wall_extremes(&r);
    let report = r.first().gap.as_ref().expect("gap report");
    eprintln!(
        "{file}: {} vertices, {} frames; gap asked {} m, recomputed {zmin:.6} m (report {:.6} m, closest frame {}), \
         lowest y {ymin:.6}, frames behind the wall {behind}/{}",
        r.first().character.mesh.vertex_count(),
        r.frames(),
        g.metres,
        report.achieved,
        report.closest_frame,
        r.frames()
    );
    assert!(
        (zmin - g.metres as f64).abs() < 1e-4,
        "{file}: min distance {zmin} for a gap of {}",
        g.metres
    );
    assert!(
        (report.achieved as f64 - zmin).abs() < 1e-4,
        "{file}: report {} vs {zmin}",
        report.achieved
    );
    assert!(
        ymin.abs() < 1e-4,
        "{file}: feet at {ymin}, not on the floor"
    );
    assert!(
        (report.normal.z - 1.0).abs() < 1e-6 && report.offset.abs() < 1e-6,
        "{file}: plane {report:?}"
    );
    (r, zmin, behind)
}

#[test]
fn museum_paper_scale_keeps_5_mm() {
    let (r, _, behind) = check_gap("museum.toml", None);
    assert_eq!(r.first().character.mesh.vertex_count(), 44_345);
    assert_eq!(r.methods, Method::ALL.to_vec());
    assert_eq!(behind, 0);
    // Centred along the 20 m wall.
    let x = r.first().placement_at(0).translation.vector.x;
    assert!((5.0..15.0).contains(&x), "x = {x}");
}

#[test]
fn living_room_paper_scale_keeps_5_mm() {
    let (r, _, behind) = check_gap("living_room.toml", None);
    assert_eq!(r.first().character.mesh.vertex_count(), 44_345);
    assert_eq!(behind, 0);
}

#[test]
fn cesium_man_keeps_1_cm() {
    let (_, _, behind) = check_gap("cesium_man.toml", None);
    assert_eq!(behind, 0);
}

#[test]
fn brainstem_keeps_1_cm_over_120_frames() {
    let (_, _, behind) = check_gap("brainstem.toml", Some(120));
    assert_eq!(behind, 0);
}

#[test]
fn touching_penetrates_most_frames() {
    let (r, _, behind) = check_gap("touching.toml", None);
    assert!(
        behind * 2 > r.frames(),
        "only {behind} of {} frames penetrate",
        r.frames()
    );
    assert_eq!(r.first().gap.as_ref().unwrap().penetrating_frames, behind);
}

#[test]
fn every_shipped_scenario_is_tested() {
    let mut names: Vec<String> = std::fs::read_dir(shipped(""))
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".toml"))
        .collect();
    names.sort();
    assert_eq!(
        names,
        [
            "brainstem.toml",
            "cesium_man.toml",
            // The worlds: tests/worlds.rs.
            "crowd.toml",
            "door.toml",
            "handshake.toml",
            "inside_furniture.toml",
            "living_room.toml",
            "museum.toml",
            // The plazas: tests/worlds.rs (shrunk to a few characters).
            "plaza_brushing.toml",
            "plaza_packed.toml",
            // Self-collision: tests/worlds.rs (and tests/self_contact.rs).
            "self_contact.toml",
            // Self-collision between frames: tests/ccd_world.rs.
            "self_swing.toml",
            "touching.toml",
            // Continuous detection: tests/ccd_world.rs, tests/ccd_recordings.rs.
            "tunnel.toml"
        ]
    );
}

// ---- Bad files. ----

const GOOD: &str = r#"# a small valid scenario
[character]
source = "generated:humanoid?vertices=1000"
clip = "walk"

[environment]
kind = "living-room"

[placement]
gap = { surface = "south wall", metres = 0.01 }
"#;

fn temp_dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("cornertree-scenario-test-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `text` as `name` in a temp dir, loads and resolves it, expects an error.
fn error_of(name: &str, text: &str) -> (PathBuf, String) {
    let path = temp_dir().join(name);
    std::fs::write(&path, text).unwrap();
    let result: Result<_, ScenarioError> =
        load_scenario(&path).and_then(|s| resolve(&s, path.parent().unwrap()));
    let e = result.err().unwrap_or_else(|| panic!("{name}: loaded"));
    let msg = e.to_string();
    eprintln!("{msg}");
    assert!(!msg.contains('\n'), "{name}: not one line: {msg:?}");
    assert!(
        msg.starts_with(&path.display().to_string()),
        "{name}: file not named: {msg}"
    );
    (path, msg)
}

fn line_prefix(path: &Path, line: usize) -> String {
    format!("{}:{line}:", path.display())
}

#[test]
fn the_good_text_resolves() {
    let path = temp_dir().join("good.toml");
    std::fs::write(&path, GOOD).unwrap();
    let s = load_scenario(&path).unwrap();
    assert_eq!((s.fps, s.dedup, s.frames), (30.0, true, None));
    let r = resolve(&s, &temp_dir()).unwrap();
    assert!((r.first().gap.as_ref().unwrap().achieved - 0.01).abs() < 1e-4);
}

#[test]
fn syntax_error_names_the_line() {
    let text = GOOD.replace("clip = \"walk\"", "clip = \"walk");
    let (path, msg) = error_of("syntax.toml", &text);
    assert!(msg.starts_with(&line_prefix(&path, 4)), "{msg}");
}

#[test]
fn unknown_field_is_named() {
    let text = GOOD.replace("clip = \"walk\"", "clip = \"walk\"\ncolour = \"red\"");
    let (path, msg) = error_of("unknown_field.toml", &text);
    assert!(msg.starts_with(&line_prefix(&path, 5)), "{msg}");
    assert!(msg.contains("colour"), "{msg}");
}

#[test]
fn missing_asset_is_named() {
    let text = GOOD.replace("generated:humanoid?vertices=1000", "no/such/character.glb");
    let (path, msg) = error_of("missing_asset.toml", &text);
    assert!(msg.starts_with(&line_prefix(&path, 3)), "{msg}");
    assert!(
        msg.contains("character.source") && msg.contains("no/such/character.glb"),
        "{msg}"
    );

    let text = GOOD.replace(
        "kind = \"living-room\"",
        "kind = \"gltf\"\npath = \"rooms/none.glb\"",
    );
    let (path, msg) = error_of("missing_scene.toml", &text);
    assert!(msg.starts_with(&line_prefix(&path, 8)), "{msg}");
    assert!(
        msg.contains("environment.path") && msg.contains("rooms/none.glb"),
        "{msg}"
    );
}

#[test]
fn negative_frames_and_fps_are_refused() {
    let (path, msg) = error_of("frames.toml", &format!("frames = -3\n{GOOD}"));
    assert!(
        msg.starts_with(&line_prefix(&path, 1)) && msg.contains("frames") && msg.contains("-3"),
        "{msg}"
    );
    let (_, msg) = error_of("frames0.toml", &format!("frames = 0\n{GOOD}"));
    assert!(msg.contains("frames"), "{msg}");
    let (path, msg) = error_of("fps.toml", &format!("fps = -30\n{GOOD}"));
    assert!(
        msg.starts_with(&line_prefix(&path, 1)) && msg.contains("fps"),
        "{msg}"
    );
}

#[test]
fn unknown_method_lists_the_valid_ones() {
    let (path, msg) = error_of("method.toml", &format!("methods = [\"fastest\"]\n{GOOD}"));
    assert!(msg.starts_with(&line_prefix(&path, 1)), "{msg}");
    assert!(msg.contains("fastest"), "{msg}");
    for m in Method::ALL {
        assert!(msg.contains(m.name()), "{msg}");
    }
}

#[test]
fn self_culling_is_read_and_checked() {
    // Default: parts one joint moves; the key picks any set, even none.
    let path = temp_dir().join("self_culling.toml");
    for (line, rigid, cones) in [
        ("", true, false),
        ("self_culling = [\"normal-cones\"]\n", false, true),
        ("self_culling = [\"rigid\", \"normal-cones\"]\n", true, true),
        ("self_culling = []\n", false, false),
    ] {
        std::fs::write(&path, format!("self_collision = true\n{line}{GOOD}")).unwrap();
        let r = resolve(&load_scenario(&path).unwrap(), &temp_dir()).unwrap();
        let w = r.world_settings();
        assert_eq!(
            (
                w.self_collision,
                w.self_rigid_culling,
                w.self_normal_cone_culling
            ),
            (true, rigid, cones),
            "{line}"
        );
    }
    let (path, msg) = error_of(
        "self_culling_typo.toml",
        &format!("self_collision = true\nself_culling = [\"normal-cone\"]\n{GOOD}"),
    );
    assert!(msg.starts_with(&line_prefix(&path, 2)), "{msg}");
    assert!(
        msg.contains("normal-cone") && msg.contains("normal-cones") && msg.contains("rigid"),
        "{msg}"
    );
    let (path, msg) = error_of(
        "self_culling_alone.toml",
        &format!("self_culling = [\"rigid\"]\n{GOOD}"),
    );
    assert!(msg.starts_with(&line_prefix(&path, 1)), "{msg}");
    assert!(
        msg.contains("self_culling") && msg.contains("self_collision"),
        "{msg}"
    );
}

#[test]
fn unknown_surface_lists_objects() {
    let text = GOOD.replace("\"south wall\"", "\"souht wall\"");
    let (path, msg) = error_of("surface.toml", &text);
    assert!(msg.starts_with(&line_prefix(&path, 10)), "{msg}");
    assert!(
        msg.contains("placement.gap.surface") && msg.contains("souht wall"),
        "{msg}"
    );
    assert!(
        msg.contains("\"floor\"") || msg.contains("\"south wall\""),
        "{msg}"
    );
}

#[test]
fn placement_needs_exactly_one_kind() {
    let text = GOOD.replace(
        "gap = { surface = \"south wall\", metres = 0.01 }",
        "gap = { surface = \"south wall\", metres = 0.01 }\nstart = { translation = [1, 0, 1] }",
    );
    let (_, msg) = error_of("two_placements.toml", &text);
    assert!(
        msg.contains("placement") && msg.contains("exactly one"),
        "{msg}"
    );
}

#[test]
fn path_walks_facing_the_direction() {
    let text = GOOD.replace(
        "gap = { surface = \"south wall\", metres = 0.01 }",
        "path = { waypoints = [[1, 0, 1], [4, 0, 1], [4, 0, 3]], speed = 1.5 }",
    );
    let path = temp_dir().join("path.toml");
    std::fs::write(&path, text).unwrap();
    let r = resolve(&load_scenario(&path).unwrap(), &temp_dir()).unwrap();
    let actor = r.first();
    // The root joint (the pelvis) follows the path exactly: the walk clip's
    // own forward travel (about 1.35 m a stride) is taken out.
    let mut buffers = cornertree::character::PoseBuffers::new(&actor.character);
    let mut pelvis = |k: usize| {
        actor.pose_frame(&mut buffers, k);
        let m = buffers.world[0];
        nalgebra::Vector3::new(m[(0, 3)], 0.0, m[(2, 3)])
    };
    let p0 = pelvis(0);
    for k in [10, 30, 50] {
        // Frame k at 30 fps: 0.05·k m along the first leg (+X).
        let moved = pelvis(k) - p0;
        let along = nalgebra::Vector3::new(0.05 * k as f32, 0.0, 0.0);
        assert!((moved - along).norm() < 1e-4, "frame {k}: {moved}");
    }
    // Frame 30 faces +X.
    let iso = actor.placement_at(30);
    let forward = iso.rotation * nalgebra::Vector3::z();
    assert!(
        (forward - nalgebra::Vector3::x()).norm() < 1e-5,
        "{forward}"
    );
    // Frame 90: 4.5 m = 3 m + 1.5 m up the second leg, facing +Z; long after,
    // the end (the pelvis where the path says, less its rest offset, which
    // turns with the character).
    let rest = p0 - nalgebra::Vector3::new(1.0, 0.0, 1.0);
    let turned = nalgebra::Vector3::new(-rest.z, 0.0, rest.x);
    for (k, at, r) in [(90, [4.0, 2.5], turned), (1000, [4.0, 3.0], turned)] {
        let want = nalgebra::Vector3::new(at[0], 0.0, at[1]) + r;
        let got = pelvis(k);
        assert!((got - want).norm() < 1e-4, "frame {k}: {got} vs {want}");
    }
    let forward = actor.placement_at(90).rotation * nalgebra::Vector3::z();
    assert!(
        (forward - nalgebra::Vector3::z()).norm() < 1e-5,
        "{forward}"
    );
}

#[test]
fn environment_vertices_retessellates_the_generated_room() {
    let path = temp_dir().join("scaled.toml");
    let text = GOOD.replace(
        "kind = \"living-room\"",
        "kind = \"living-room\"\nvertices = 20000",
    );
    std::fs::write(&path, text).unwrap();
    let s = load_scenario(&path).unwrap();
    let r = resolve(&s, &temp_dir()).unwrap();
    assert_eq!(r.environment.mesh.positions().len(), 20_000);
    // Same layout: the placement rule still finds the south wall.
    assert!((r.first().gap.as_ref().unwrap().achieved - 0.01).abs() < 1e-4);

    // Bad sizes are named at their line; a glTF scene takes none.
    for (name, value) in [
        ("vertices_negative.toml", "-5"),
        ("vertices_zero.toml", "0"),
    ] {
        let text = GOOD.replace(
            "kind = \"living-room\"",
            &format!("kind = \"living-room\"\nvertices = {value}"),
        );
        let (path, msg) = error_of(name, &text);
        assert!(
            msg.starts_with(&line_prefix(&path, 8)) && msg.contains("environment.vertices"),
            "{msg}"
        );
    }
    let text = GOOD.replace(
        "kind = \"living-room\"",
        "kind = \"living-room\"\nvertices = 3",
    );
    let (_, msg) = error_of("vertices_few.toml", &text);
    assert!(msg.contains("environment.vertices"), "{msg}");
    let text = GOOD.replace(
        "kind = \"living-room\"",
        "kind = \"gltf\"\npath = \"room.glb\"\nvertices = 1000",
    );
    std::fs::write(temp_dir().join("room.glb"), b"").unwrap();
    let (_, msg) = error_of("vertices_gltf.toml", &text);
    assert!(msg.contains("environment.vertices"), "{msg}");
}

#[test]
fn gap_along_moves_the_character_along_the_wall() {
    let resolve_text = |name: &str, text: &str| {
        let path = temp_dir().join(name);
        std::fs::write(&path, text).unwrap();
        resolve(&load_scenario(&path).unwrap(), &temp_dir()).unwrap()
    };
    let centred = resolve_text("along0.toml", GOOD);
    let moved = resolve_text(
        "along.toml",
        &GOOD.replace("metres = 0.01 }", "metres = 0.01, along = -1.25 }"),
    );
    // The south wall's horizontal direction is +x (up × its normal +z).
    let d = moved.first().placement_at(0).translation.vector
        - centred.first().placement_at(0).translation.vector;
    assert!(
        (d.x + 1.25).abs() < 1e-4 && d.y.abs() < 1e-4 && d.z.abs() < 1e-4,
        "{d:?}"
    );
    assert!((moved.first().gap.as_ref().unwrap().achieved - 0.01).abs() < 1e-4);

    let (path, msg) = error_of(
        "along_nan.toml",
        &GOOD.replace("metres = 0.01 }", "metres = 0.01, along = nan }"),
    );
    assert!(
        msg.starts_with(&line_prefix(&path, 10)) && msg.contains("placement.gap.along"),
        "{msg}"
    );
}

#[test]
fn subdivide_splits_the_named_objects() {
    let path = temp_dir().join("split.toml");
    let text = GOOD.replace(
        "kind = \"living-room\"",
        "kind = \"living-room\"\nsubdivide = [{ object = \"south wall\", times = 3 }, { object = \"floor\", times = 1 }]",
    );
    std::fs::write(&path, text).unwrap();
    let r = resolve(&load_scenario(&path).unwrap(), &temp_dir()).unwrap();
    assert_eq!(
        r.environment.object("south wall").unwrap().triangles.len(),
        2 * 64
    );
    assert_eq!(
        r.environment.object("floor").unwrap().triangles.len(),
        2 * 4
    );
    // The wall's plane is unchanged, so the gap is kept.
    assert!((r.first().gap.as_ref().unwrap().achieved - 0.01).abs() < 1e-4);

    for (name, entry) in [
        ("split_unknown.toml", "{ object = \"no wall\", times = 1 }"),
        ("split_huge.toml", "{ object = \"floor\", times = 30 }"),
    ] {
        let text = GOOD.replace(
            "kind = \"living-room\"",
            &format!("kind = \"living-room\"\nsubdivide = [{entry}]"),
        );
        let (_, msg) = error_of(name, &text);
        assert!(msg.contains("environment.subdivide"), "{msg}");
    }
}
