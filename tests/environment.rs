//! Generated rooms (museum, living room) and static glTF scenes.

mod common;
use common::{Scratch, base64};

use std::path::PathBuf;
use std::sync::OnceLock;

use cornertree::geometry::Point;
use cornertree_workbench::environment::{
    Environment, LIVING_ROOM_VERTICES, MUSEUM_VERTICES, ObjectKind, SceneError, big_triangles,
    living_room, living_room_scaled, load_scene, museum, museum_scaled,
};

fn museum0() -> &'static Environment {
    static M: OnceLock<Environment> = OnceLock::new();
    M.get_or_init(|| museum(0))
}

fn living0() -> &'static Environment {
    static L: OnceLock<Environment> = OnceLock::new();
    L.get_or_init(|| living_room(0))
}

fn within_one_percent(got: usize, want: usize) -> bool {
    got.abs_diff(want) * 100 <= want
}

#[test]
fn vertex_counts_match_the_paper() {
    let m = museum0();
    let l = living0();
    for t in [0.5, 1.0, 2.0] {
        println!("{}", m.summary(t));
        println!("{}", l.summary(t));
    }
    assert!(
        within_one_percent(m.mesh.vertex_count(), MUSEUM_VERTICES),
        "{}",
        m.mesh.vertex_count()
    );
    assert!(
        within_one_percent(l.mesh.vertex_count(), LIVING_ROOM_VERTICES),
        "{}",
        l.mesh.vertex_count()
    );
    assert_eq!(m.mesh.vertex_count(), 9_482);
    assert_eq!(l.mesh.vertex_count(), 133_139);
    assert_eq!(
        m.mesh.bounds(),
        (Point::origin(), Point::new(20.0, 5.0, 12.0)),
        "inside the room"
    );
    assert_eq!(
        l.mesh.bounds(),
        (Point::origin(), Point::new(8.0, 2.7, 6.0)),
        "inside the room"
    );
}

#[test]
fn objects_are_contiguous_and_cover_the_mesh() {
    for env in [museum0(), living0()] {
        let (mut v, mut t) = (0, 0);
        for o in &env.objects {
            assert_eq!((o.vertices.start, o.triangles.start), (v, t), "{}", o.name);
            assert!(
                o.triangles.end > o.triangles.start,
                "{} has no triangles",
                o.name
            );
            for tri in &env.mesh.indices()[o.triangles.start as usize..o.triangles.end as usize] {
                assert!(
                    tri.iter().all(|i| o.vertices.contains(i)),
                    "{} uses another object's vertex",
                    o.name
                );
            }
            (v, t) = (o.vertices.end, o.triangles.end);
        }
        assert_eq!(
            (v as usize, t as usize),
            (env.mesh.vertex_count(), env.mesh.triangle_count())
        );
        // Every vertex is used.
        let mut used = vec![false; env.mesh.vertex_count()];
        env.mesh
            .indices()
            .iter()
            .flatten()
            .for_each(|&i| used[i as usize] = true);
        assert!(used.iter().all(|&u| u), "{}: unused vertices", env.name);
    }
}

#[test]
fn deterministic_in_the_seed() {
    let again = museum(0);
    assert_eq!(again.mesh.positions(), museum0().mesh.positions());
    assert_eq!(again.mesh.indices(), museum0().mesh.indices());
    let other = museum(1);
    assert_eq!(other.mesh.vertex_count(), MUSEUM_VERTICES);
    assert_eq!(
        other.mesh.bounds(),
        (Point::origin(), Point::new(20.0, 5.0, 12.0)),
        "inside the room"
    );
    assert_ne!(other.mesh.positions(), museum0().mesh.positions());

    let again = living_room(0);
    let bits = |e: &Environment| {
        e.mesh
            .positions()
            .iter()
            .flat_map(|p| p.iter().map(|c| c.to_bits()))
            .collect::<Vec<_>>()
    };
    assert_eq!(bits(&again), bits(living0()));
    assert_eq!(again.mesh.indices(), living0().mesh.indices());
    let other = living_room(7);
    assert_eq!(other.mesh.vertex_count(), LIVING_ROOM_VERTICES);
    assert_eq!(
        other.mesh.bounds(),
        (Point::origin(), Point::new(8.0, 2.7, 6.0)),
        "inside the room"
    );
    assert_ne!(bits(&other), bits(living0()));
}

#[test]
fn big_and_small_triangles() {
    for env in [museum0(), living0()] {
        let big = big_triangles(&env.mesh, 2.0);
        assert!(
            big.len() >= 20,
            "{}: {} triangles longer than 2 m",
            env.name,
            big.len()
        );
        let small = env
            .mesh
            .iter_triangles()
            .filter(|(_, t)| t.longest_edge() < 0.2)
            .count();
        let fraction = small as f64 / env.mesh.triangle_count() as f64;
        assert!(
            fraction >= 0.9,
            "{}: only {:.3} of triangles shorter than 0.2 m",
            env.name,
            fraction
        );
        // The big ones include walls and the floor.
        let kinds: Vec<ObjectKind> = big
            .iter()
            .filter_map(|&id| env.object_of(id))
            .map(|o| o.kind)
            .collect();
        assert!(kinds.contains(&ObjectKind::Wall) && kinds.contains(&ObjectKind::Floor));
    }
}

#[test]
fn no_zero_area_triangles() {
    for env in [museum0(), living0()] {
        for (id, t) in env.mesh.iter_triangles() {
            let l = f64::from(t.longest_edge());
            let a = f64::from(t.area());
            // Not even a sliver: area at least 1e-4 of the squared longest edge.
            assert!(
                a > 1e-4 * l * l,
                "{}: triangle {} has area {a} for longest edge {l}",
                env.name,
                id.0
            );
            let [p, q, r] = env.mesh.indices()[id.index()];
            assert!(p != q && q != r && p != r);
        }
    }
}

#[test]
fn corridor_along_the_south_wall_is_free() {
    for (env, corridor) in [(museum0(), 2.5f32), (living0(), 1.3)] {
        for o in &env.objects {
            if matches!(
                o.kind,
                ObjectKind::Wall | ObjectKind::Floor | ObjectKind::Ceiling
            ) {
                continue;
            }
            let vs = &env.mesh.positions()[o.vertices.start as usize..o.vertices.end as usize];
            let zmin = vs.iter().map(|p| p.z).fold(f32::INFINITY, f32::min);
            assert!(
                zmin > corridor,
                "{}: {} reaches z = {zmin}",
                env.name,
                o.name
            );
        }
    }
}

#[test]
fn the_door_swings_rigidly() {
    for env in [museum0(), living0()] {
        let doors: Vec<_> = env.moving_objects().collect();
        assert_eq!(doors.len(), 1);
        let door = doors[0];
        assert_eq!(door.kind, ObjectKind::Door);
        let n = env.mesh.vertex_count();
        let mut a = vec![Point::origin(); n];
        let mut b = vec![Point::origin(); n];
        env.pose_at(0.0, &mut a);
        assert_eq!(a.as_slice(), env.mesh.positions(), "t = 0 is the rest pose");
        env.pose_at(1.3, &mut b);
        let range = door.vertices.start as usize..door.vertices.end as usize;
        for i in 0..n {
            if range.contains(&i) {
                assert!(
                    (a[i] - b[i]).norm() > 1e-3 || (a[i].x - 0.06).abs() < 1e-3,
                    "door vertex {i} did not move"
                );
            } else {
                assert_eq!(a[i], b[i], "static vertex {i} moved");
            }
        }
        let d = &range;
        for i in d.clone().step_by(7) {
            for j in d.clone().step_by(11) {
                let before = (a[i] - a[j]).norm();
                let after = (b[i] - b[j]).norm();
                assert!(
                    (before - after).abs() < 1e-4,
                    "door not rigid: {before} vs {after}"
                );
            }
        }
        // It opens into the room.
        assert!(b[range].iter().all(|p| p.x > -1e-3));
    }
}

#[test]
fn scaled_variants_meet_their_targets() {
    assert_eq!(
        museum_scaled(3, 20_000).unwrap().mesh.vertex_count(),
        20_000
    );
    assert_eq!(
        living_room_scaled(3, 10_000).unwrap().mesh.vertex_count(),
        10_000
    );
    assert!(museum_scaled(0, 10).is_err());
    let t = std::time::Instant::now();
    let big = living_room_scaled(5, 500_000).unwrap();
    assert_eq!(big.mesh.vertex_count(), 500_000);
    println!(
        "500k living room in {:?}: {}",
        t.elapsed(),
        big.summary(2.0)
    );
}

// ---------------------------------------------------------------------------
// Static glTF scenes.

/// A one-mesh glTF (data URI) with u32 indices, placed by a node translated by `(1, 2, 3)`.
fn write_gltf(
    scratch: &Scratch,
    name: &str,
    positions: &[[f32; 3]],
    indices: &[u32],
    mode: u32,
) -> PathBuf {
    let mut buffer: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|c| c.to_le_bytes())
        .collect();
    let pos_bytes = buffer.len();
    buffer.extend(indices.iter().flat_map(|i| i.to_le_bytes()));
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0, "translation": [1, 2, 3]}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}, "indices": 1, "mode": {mode}}}]}}],
  "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{data}"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": {pos_bytes}}},
                  {{"buffer": 0, "byteOffset": {pos_bytes}, "byteLength": {idx_bytes}}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": {count}, "type": "VEC3"}},
                {{"bufferView": 1, "componentType": 5125, "count": {icount}, "type": "SCALAR"}}]}}"#,
        len = buffer.len(),
        data = base64(&buffer),
        idx_bytes = buffer.len() - pos_bytes,
        count = positions.len(),
        icount = indices.len(),
    );
    let path = scratch.0.join(name);
    std::fs::write(&path, json).unwrap();
    path
}

const SQUARE_AND_LINE: [[f32; 3]; 6] = [
    [0., 0., 0.],
    [1., 0., 0.],
    [1., 1., 0.],
    [0., 1., 0.],
    [2., 0., 0.],
    [3., 0., 0.],
];

#[test]
fn scene_skips_degenerate_triangles() {
    let scratch = Scratch::new("degenerate");
    // Two good triangles, one collinear (zero area), one repeating an index.
    let path = write_gltf(
        &scratch,
        "room.gltf",
        &SQUARE_AND_LINE,
        &[0, 1, 2, 0, 4, 5, 0, 2, 3, 2, 2, 3],
        4,
    );
    let (env, report) = load_scene(&path).expect("loads");
    assert_eq!(env.mesh.triangle_count(), 2);
    assert_eq!(report.degenerate_removed, 2);
    assert_eq!(report.first_degenerate, vec![1, 3]);
    assert_eq!(env.objects.len(), 1);
    assert_eq!(env.objects[0].triangles, 0..2);
    assert_eq!(
        env.mesh.positions()[1],
        Point::new(2.0, 2.0, 3.0),
        "node transform applied"
    );
}

#[test]
fn scene_of_only_degenerate_triangles_is_an_error() {
    let scratch = Scratch::new("only-degenerate");
    let path = write_gltf(
        &scratch,
        "flat.gltf",
        &SQUARE_AND_LINE,
        &[0, 4, 5, 1, 1, 2],
        4,
    );
    let error = load_scene(&path).expect_err("nothing usable");
    let message = error.to_string();
    assert!(
        matches!(error, SceneError::OnlyDegenerate { removed: 2, .. }),
        "{message}"
    );
    assert!(
        message.contains("flat.gltf") && !message.contains('\n'),
        "{message}"
    );
}

#[test]
fn scene_without_triangles_is_an_error() {
    let scratch = Scratch::new("no-triangles");
    // A LINES primitive only.
    let path = write_gltf(&scratch, "lines.gltf", &SQUARE_AND_LINE, &[0, 1, 1, 2], 1);
    let error = load_scene(&path).expect_err("no triangles");
    let message = error.to_string();
    assert!(matches!(error, SceneError::Load(_)), "{message}");
    assert!(
        message.contains("lines.gltf")
            && message.contains("no triangles")
            && !message.contains('\n'),
        "{message}"
    );
}
