//! A glTF character in the caller's own room: CesiumMan (a skinned glTF
//! character, CC BY 4.0, `assets/ATTRIBUTION.md`) loaded with the `gltf`
//! feature, its own walk clip sampled with the library's helper, and a room
//! the caller builds from triangles: a floor just above the character's
//! lowest point and a wall it walks through. Every step's contacts are
//! checked against an exact oracle.
//!
//! `cargo run -p cornertree --features gltf --example gltf_character_in_room [FILE.glb]`

use std::collections::BTreeSet;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use cornertree::character::{Character, PoseBuffers, SkinningModel};
use cornertree::geometry::exact::triangles_intersect_exact;
use cornertree::geometry::{Point, Triangle};
use cornertree::io::load_character;
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;
use cornertree::world::{CharacterModel, CollisionWorld};
use nalgebra::Isometry3;

/// Steps over one loop of the clip.
const STEPS: usize = 40;

/// The caller's room: a floor at height `floor` and a wall across `x = 0`,
/// two big triangles each.
fn room(floor: f32) -> TriMesh {
    let p = vec![
        Point::new(-5.0, floor, -5.0),
        Point::new(5.0, floor, -5.0),
        Point::new(5.0, floor, 5.0),
        Point::new(-5.0, floor, 5.0),
        Point::new(0.0, floor, -5.0),
        Point::new(0.0, floor + 3.0, -5.0),
        Point::new(0.0, floor + 3.0, 5.0),
        Point::new(0.0, floor, 5.0),
    ];
    let t = vec![[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7]];
    TriMesh::new(p, t).expect("a valid room")
}

/// Every pair of triangles decided with exact predicates.
fn oracle(c: &Character, p: &[Point], room: &TriMesh) -> BTreeSet<(u32, u32)> {
    let mut out = BTreeSet::new();
    for (t, [a, b, d]) in c.mesh.indices().iter().enumerate() {
        let ct = Triangle::new(p[*a as usize], p[*b as usize], p[*d as usize]);
        for (r, rt) in room.iter_triangles() {
            if triangles_intersect_exact(&ct, &rt) {
                out.insert((t as u32, r.0));
            }
        }
    }
    out
}

/// What a run saw.
#[derive(Debug, Default)]
struct Seen {
    steps_with_contact: usize,
    /// Pairs with the floor (room triangles 0 and 1) and the wall (2, 3).
    floor_pairs: usize,
    wall_pairs: usize,
}

/// Plays the character's first clip once through the room.
fn run(path: &Path) -> Result<Seen, Box<dyn std::error::Error>> {
    let (character, _report) = load_character(path)?;
    let character = Arc::new(character);
    let clip = character.clip(None)?;
    let (start, duration) = (clip.start(), clip.duration());
    let time = |k: usize| start + duration * k as f32 / STEPS as f32;
    // Where the character walks: from 0.8 m before the wall to 0.8 m past.
    let placement =
        |k: usize| Isometry3::translation(-0.8 + 1.6 * k as f32 / STEPS as f32, 0.0, 0.0);

    // The floor 1 cm above the lowest vertex of the first pose: the feet
    // touch it.
    let mut pose = PoseBuffers::new(&character);
    pose.pose(&character, Some(clip), time(0));
    pose.skin_all(&character, SkinningModel::Linear);
    let lowest = pose
        .positions
        .iter()
        .map(|p| p.y)
        .fold(f32::INFINITY, f32::min);
    let room = Arc::new(room(lowest + 0.01));

    let mut world = CollisionWorld::new(Method::PrunedTriTri);
    world.add_room(room.clone())?;
    let model = CharacterModel::deduplicated(character.clone(), SkinningModel::Linear)?;
    let kept: Vec<bool> = (0..character.mesh.triangle_count() as u32)
        .map(|t| model.kept().is_kept(cornertree::mesh::TriangleId(t)))
        .collect();
    let walker = world.add_character(Arc::new(model))?;

    let mut seen = Seen::default();
    for k in 0..STEPS {
        // The library's clip helper poses the joints; the world takes the
        // skin matrices.
        pose.pose(&character, Some(clip), time(k));
        pose.place(&placement(k).to_homogeneous());
        world.set_pose(walker, &pose)?;
        let contacts = world.step();
        let reported: BTreeSet<(u32, u32)> = contacts
            .room_contacts_of(walker)
            .iter()
            .map(|c| (c.triangle, c.room_triangle))
            .collect();
        // The oracle, on the triangles edge de-duplication keeps (§4: a
        // triangle whose edges kept neighbours carry is left out).
        pose.skin_all(&character, SkinningModel::Linear);
        let exact: BTreeSet<(u32, u32)> = oracle(&character, &pose.positions, &room)
            .into_iter()
            .filter(|&(t, _)| kept[t as usize])
            .collect();
        assert_eq!(reported, exact, "step {k}");
        seen.steps_with_contact += usize::from(!exact.is_empty());
        seen.floor_pairs += exact.iter().filter(|p| p.1 < 2).count();
        seen.wall_pairs += exact.iter().filter(|p| p.1 >= 2).count();
    }
    Ok(seen)
}

/// The bundled CesiumMan (in the repository's `assets/`, beside `core/`).
fn cesium_man() -> PathBuf {
    let core = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
    core.parent().unwrap_or(core).join("assets/CesiumMan.glb")
}

/// Plays `path` and checks what came out.
fn play(path: &Path) {
    let seen = run(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    println!(
        "{}: {STEPS} steps through the caller's room, {} with contact; {} pairs with the \
         floor, {} with the wall, each the exact oracle's",
        path.display(),
        seen.steps_with_contact,
        seen.floor_pairs,
        seen.wall_pairs
    );
    // The feet on the floor and the wall crossed.
    assert!(seen.floor_pairs > 0 && seen.wall_pairs > 0, "{seen:?}");
}

fn main() {
    let path = std::env::args()
        .nth(1)
        .map_or_else(cesium_man, PathBuf::from);
    play(&path);
}

#[test]
fn cesium_man_walks_through_the_callers_room() {
    play(&cesium_man());
}
