//! Compressed glTF files (`tests/compressed/`, made by `make.sh` there from
//! CesiumMan and the generated museum room with gltf-transform and gltfpack):
//! Draco (edgebreaker and sequential), meshopt (with quantization and its
//! filters) and quantization alone load as characters and static scenes, and
//! a scenario played on them gives the pairs it gives on the uncompressed
//! files, but for pairs whose distance in the other geometry is within how
//! far compression moved their vertices that frame (measured, and bounded by
//! the quantization step).

mod common;
use common::Scratch;
use common::glb::Glb;

use std::collections::{BTreeSet, HashMap};
use std::path::{Path, PathBuf};

use cornertree::geometry::{Point, Triangle};
use cornertree::io::{LoadError, load_character, load_static_mesh};
use cornertree_workbench::environment::museum;
use cornertree_workbench::scenario::{Resolved, Scenario, resolve};
use cornertree_workbench::session::Session;
use cornertree_workbench::truth::{Truth, triangle_distance};

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn compressed(name: &str) -> PathBuf {
    root().join("tests/compressed").join(name)
}

const CESIUM: [&str; 5] = [
    "cesium_draco.glb",
    "cesium_draco_sequential.glb",
    "cesium_meshopt.glb",
    "cesium_quantized.glb",
    "cesium_gltfpack.glb",
];
const ROOMS: [&str; 3] = ["room_draco.glb", "room_meshopt.glb", "room_gltfpack.glb"];

#[test]
fn compressed_characters_load_with_their_skeleton_and_clip() {
    let (plain, _) = load_character(&root().join("assets/CesiumMan.glb")).unwrap();
    for name in CESIUM {
        let (c, report) =
            load_character(&compressed(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(c.skeleton.len(), plain.skeleton.len(), "{name}");
        assert_eq!(
            c.mesh.triangle_count(),
            plain.mesh.triangle_count(),
            "{name}"
        );
        assert_eq!(c.influences.len(), c.mesh.vertex_count(), "{name}");
        assert_eq!(c.clips.len(), 1, "{name}");
        eprintln!(
            "{name}: {} vertices, clip {:.4} s to {:.4} s, {} channels",
            c.mesh.vertex_count(),
            c.clips[0].start(),
            c.clips[0].end(),
            c.clips[0].channels.len()
        );
        // gltfpack drops channels that hold their rest value.
        let channels = c.clips[0].channels.len();
        assert!(
            channels > 0 && channels <= plain.clips[0].channels.len(),
            "{name}"
        );
        assert!(report.skipped_channels.is_empty(), "{name}");
        assert!(
            report.notes.iter().any(|n| n.contains("is used and read")),
            "{name}: {:?}",
            report.notes
        );
    }
}

#[test]
fn compressed_rooms_load_every_triangle() {
    let plain = museum(0).mesh;
    for name in ROOMS {
        let (mesh, _) =
            load_static_mesh(&compressed(name)).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(mesh.triangle_count(), plain.triangle_count(), "{name}");
        // Every vertex lies within the quantization error of one of the
        // plain room's (14 bits over the room's 20 m: a step of 1.2 mm).
        let worst = largest_move(plain.positions(), mesh.positions());
        eprintln!(
            "{name}: {} vertices, largest move {:.3} mm",
            mesh.vertex_count(),
            worst * 1e3
        );
        assert!(worst <= ROOM_STEP, "{name}: a vertex moved {worst} m");
    }
}

/// The quantization step of the rooms' positions: 14 bits over the largest
/// extent (20 m), as gltf-transform and gltfpack quantize by default.
const ROOM_STEP: f32 = 20.0 / 16383.0;

/// For each point of `moved`, the nearest point of `original`: its index
/// and distance (a uniform grid of 1 cm cells, searched ring by ring; after
/// ring r every point within r cells has been seen).
fn nearest(original: &[Point], moved: &[Point]) -> Vec<(u32, f32)> {
    let cell = 0.01f32;
    let key = |p: &Point| {
        [
            (p.x / cell).floor() as i64,
            (p.y / cell).floor() as i64,
            (p.z / cell).floor() as i64,
        ]
    };
    let mut grid: HashMap<[i64; 3], Vec<u32>> = HashMap::new();
    for (i, p) in original.iter().enumerate() {
        grid.entry(key(p)).or_default().push(i as u32);
    }
    moved
        .iter()
        .map(|p| {
            let k = key(p);
            let mut best = (u32::MAX, f32::INFINITY);
            for r in 0..100i64 {
                for dx in -r..=r {
                    for dy in -r..=r {
                        for dz in -r..=r {
                            if dx.abs().max(dy.abs()).max(dz.abs()) != r {
                                continue;
                            }
                            for &i in grid
                                .get(&[k[0] + dx, k[1] + dy, k[2] + dz])
                                .into_iter()
                                .flatten()
                            {
                                let d = (original[i as usize] - p).norm();
                                if d < best.1 {
                                    best = (i, d);
                                }
                            }
                        }
                    }
                }
                if best.1 <= r as f32 * cell {
                    break;
                }
            }
            assert!(
                best.0 != u32::MAX,
                "no original vertex within a metre of {p:?}"
            );
            best
        })
        .collect()
}

fn largest_move(original: &[Point], moved: &[Point]) -> f32 {
    nearest(original, moved)
        .iter()
        .map(|n| n.1)
        .fold(0.0, f32::max)
}

#[test]
fn unsupported_required_extensions_are_still_refused_naming_them() {
    let bytes = std::fs::read(compressed("room_draco.glb")).unwrap();
    // Rename a supported extension in extensionsRequired (same length).
    let text = String::from_utf8_lossy(&bytes[20..]).into_owned();
    assert!(text.contains("KHR_"));
    let patched: Vec<u8> = replace_once(
        &bytes,
        b"\"extensionsRequired\":[\"KHR_",
        b"\"extensionsRequired\":[\"XYZ_",
    );
    let scratch = Scratch::new("unsupported");
    let path = scratch.write("unsupported.glb", patched);
    let error = load_static_mesh(&path).unwrap_err();
    let message = error.to_string();
    assert!(
        matches!(error, LoadError::UnsupportedExtension { .. }),
        "{message}"
    );
    assert!(message.contains("XYZ_"), "{message}");
    assert!(message.contains("KHR_draco_mesh_compression"), "{message}");
}

fn replace_once(bytes: &[u8], from: &[u8], to: &[u8]) -> Vec<u8> {
    assert_eq!(from.len(), to.len());
    let at = bytes
        .windows(from.len())
        .position(|w| w == from)
        .expect("pattern present");
    let mut out = bytes.to_vec();
    out[at..at + to.len()].copy_from_slice(to);
    out
}

/// CesiumMan walking in place in the museum room (`room`: a glTF file, or
/// `None` for the generated museum the compressed rooms were made from),
/// 10 cm from the south wall's plane (z = 0, which its arms and legs cross)
/// and 1 cm into the floor: contact every frame.
fn scenario(character: &Path, room: Option<&Path>) -> Resolved {
    let environment = match room {
        Some(room) => format!("kind = \"gltf\"\npath = {room:?}"),
        None => "kind = \"museum\"".to_owned(),
    };
    let text = format!(
        r#"frames = 20
fps = 10
methods = ["undivided-pruned-tri-tri"]
dedup = false

[character]
source = {character:?}

[environment]
{environment}

[placement]
start = {{ translation = [10.0, -0.01, 0.1], yaw_degrees = 90 }}
"#
    );
    let file = root().join("tests/compressed/scenario.toml");
    let scenario = Scenario::parse(&text, &file).unwrap();
    resolve(&scenario, root()).unwrap()
}

/// Per frame: the pairs (character triangle, room triangle) of the exact
/// reference and of the method, and the posed character and room.
struct Played {
    reference: Vec<BTreeSet<(u32, u32)>>,
    method: Vec<BTreeSet<(u32, u32)>>,
    character: Vec<Vec<Point>>,
    room: Vec<Point>,
    room_triangles: Vec<[u32; 3]>,
    character_triangles: Vec<[u32; 3]>,
}

fn play(r: Resolved) -> Played {
    let room = r.environment.mesh.positions().to_vec();
    let room_triangles = r.environment.mesh.indices().to_vec();
    let character_triangles = r.characters[0].character.mesh.indices().to_vec();
    let mut session = Session::new(r, 1).unwrap();
    let mut truth = Truth::new(&session.scene).unwrap();
    let mut played = Played {
        reference: Vec::new(),
        method: Vec::new(),
        character: Vec::new(),
        room,
        room_triangles,
        character_triangles,
    };
    for k in 0..session.frames() {
        session.pose(k);
        session.skin_all();
        truth
            .update(&session.scene, &session.buffers, &session.object_poses)
            .unwrap();
        session.detect_all();
        let pairs = |list: &mut dyn Iterator<Item = (u32, u32)>| list.collect::<BTreeSet<_>>();
        played.reference.push(pairs(
            &mut truth
                .exact
                .environment
                .iter()
                .map(|p| (p.triangle, p.room_triangle)),
        ));
        played.method.push(pairs(
            &mut session
                .contacts(0)
                .room_pairs
                .iter()
                .map(|p| (p.triangle, p.room_triangle)),
        ));
        played.character.push(session.buffers[0].positions.clone());
    }
    played
}

/// Maps each triangle of `moved` to the triangle of `original` whose corners
/// are the nearest original vertices of its corners (as a set); `None` where
/// no original triangle has those corners.
fn triangle_map(
    original: &[Point],
    original_triangles: &[[u32; 3]],
    moved: &[Point],
    moved_triangles: &[[u32; 3]],
) -> Vec<Option<u32>> {
    // Original vertices at one position are one vertex (seams, welds).
    let weld = |p: &Point| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let mut first: HashMap<[u32; 3], u32> = HashMap::new();
    let representative: Vec<u32> = original
        .iter()
        .enumerate()
        .map(|(i, p)| *first.entry(weld(p)).or_insert(i as u32))
        .collect();
    let key = |t: [u32; 3]| {
        let mut k = t.map(|v| representative[v as usize]);
        k.sort_unstable();
        k
    };
    let by_corners: HashMap<[u32; 3], u32> = original_triangles
        .iter()
        .enumerate()
        .map(|(i, t)| (key(*t), i as u32))
        .collect();
    let nearest = nearest(original, moved);
    moved_triangles
        .iter()
        .map(|t| {
            by_corners
                .get(&key(t.map(|v| nearest[v as usize].0)))
                .copied()
        })
        .collect()
}

fn triangle(points: &[Point], t: [u32; 3]) -> Triangle {
    Triangle::new(
        points[t[0] as usize],
        points[t[1] as usize],
        points[t[2] as usize],
    )
}

/// Plays the scenario on the plain files and on `character` + `room`; the
/// pairs must agree but for pairs within the frame's displacement bound.
fn same_pairs_as_uncompressed(plain: &Played, character: &str, room: &str) {
    let compressed_played = play(scenario(&compressed(character), Some(&compressed(room))));
    let c = &compressed_played;
    let room_map = triangle_map(
        &plain.room,
        &plain.room_triangles,
        &c.room,
        &c.room_triangles,
    );
    assert!(
        room_map.iter().all(Option::is_some),
        "{room}: every room triangle maps"
    );
    // The character's triangles map by its posed vertices at frame 0.
    let character_map = triangle_map(
        &plain.character[0],
        &plain.character_triangles,
        &c.character[0],
        &c.character_triangles,
    );
    let unmapped = character_map.iter().filter(|m| m.is_none()).count();
    assert_eq!(unmapped, 0, "{character}: {unmapped} triangles do not map");
    let room_moved = largest_move(&plain.room, &c.room);
    let matches = nearest(&plain.character[0], &c.character[0]);
    let (mut agreeing, mut flipped, mut worst_move) = (0usize, 0usize, 0.0f32);
    for k in 0..plain.reference.len() {
        // How far compression moved each character vertex this frame (the
        // vertex its frame-0 match is).
        let character_moved = c.character[k]
            .iter()
            .zip(&matches)
            .map(|(p, &(i, _))| (p - plain.character[k][i as usize]).norm())
            .fold(0.0f32, f32::max);
        worst_move = worst_move.max(character_moved);
        if std::env::var_os("COMPRESSED_LOG").is_some() {
            eprintln!(
                "{character} frame {k}: moved {:.3} mm",
                character_moved * 1e3
            );
        }
        let band = f64::from(character_moved + room_moved) + 1e-6;
        for (set_name, sets) in [
            ("reference", (&plain.reference, &c.reference)),
            ("method", (&plain.method, &c.method)),
        ] {
            let mapped: BTreeSet<(u32, u32)> = sets.1[k]
                .iter()
                .map(|&(a, b)| {
                    (
                        character_map[a as usize].unwrap(),
                        room_map[b as usize].unwrap(),
                    )
                })
                .collect();
            agreeing += mapped.intersection(&sets.0[k]).count();
            for &(a, b) in mapped.symmetric_difference(&sets.0[k]) {
                // A pair in one and not the other: within the band in the plain geometry.
                let d = triangle_distance(
                    &triangle(&plain.character[k], plain.character_triangles[a as usize]),
                    &triangle(&plain.room, plain.room_triangles[b as usize]),
                );
                assert!(
                    d <= band,
                    "{character} + {room}, frame {k}, {set_name}: pair ({a}, {b}) differs from the uncompressed run at distance {d} m, beyond the {band} m compression moved vertices"
                );
                flipped += 1;
            }
        }
    }
    eprintln!(
        "{character} + {room}: {agreeing} pairs agree, {flipped} differ within the band; vertices moved up to {:.3} mm (character) and {:.3} mm (room)",
        worst_move * 1e3,
        room_moved * 1e3
    );
    assert!(agreeing > 0, "the scenario must have contacts");
    // Quantization bound of the character: 14-bit positions over CesiumMan's
    // 1.5 m (0.1 mm), 8- to 16-bit weights and 16-bit rotations; 2 mm covers
    // every file here with room (the measured figures are printed above).
    assert!(
        worst_move <= 2e-3,
        "{character}: a vertex moved {worst_move} m"
    );
}

#[test]
fn a_scenario_on_compressed_files_gives_the_uncompressed_pairs() {
    let plain = play(scenario(&root().join("assets/CesiumMan.glb"), None));
    let contacts: usize = plain.reference.iter().map(BTreeSet::len).sum();
    assert!(contacts > 0, "the plain scenario must have contacts");
    for (character, room) in [
        ("cesium_draco.glb", "room_draco.glb"),
        ("cesium_draco_sequential.glb", "room_draco.glb"),
        ("cesium_meshopt.glb", "room_meshopt.glb"),
        ("cesium_quantized.glb", "room_meshopt.glb"),
        ("cesium_gltfpack.glb", "room_gltfpack.glb"),
    ] {
        same_pairs_as_uncompressed(&plain, character, room);
    }
}

/// `name` from `tests/compressed/` with part of buffer view `view`'s stream
/// set to 0xff (`part` gives, from the stream's length, where the damage
/// starts and how long it is); written to `scratch`.
fn damaged(
    scratch: &Scratch,
    name: &str,
    view: usize,
    part: impl Fn(usize) -> (usize, usize),
) -> PathBuf {
    let mut glb = Glb::parse(std::fs::read(compressed(name)).unwrap());
    let (offset, length) = glb.stream_range(view);
    let (skip, len) = part(length);
    glb.fill(offset + skip, len, 0xff);
    scratch.write(name, &glb.bytes)
}

/// Both loaders' errors on `path`, each checked to be one line that starts
/// with the file's path.
fn errors_of_both_loaders(path: &Path) -> [(LoadError, String); 2] {
    [
        load_character(path).map(|_| ()).unwrap_err(),
        load_static_mesh(path).map(|_| ()).unwrap_err(),
    ]
    .map(|error| {
        let message = error.to_string();
        eprintln!("{message}");
        assert!(!message.contains('\n'), "{message}");
        assert!(
            message.starts_with(&path.display().to_string()),
            "{message}"
        );
        (error, message)
    })
}

#[test]
fn a_damaged_draco_stream_is_one_line_naming_file_mesh_and_primitive() {
    let scratch = Scratch::new("damaged-draco");
    // View 2 holds the Draco stream (see the file's JSON); wipe its middle.
    let path = damaged(&scratch, "cesium_draco.glb", 2, |n| (16, n / 2));
    for (_, message) in errors_of_both_loaders(&path) {
        assert!(
            message.contains("mesh 0 \"Cesium_Man\" primitive 0"),
            "{message}"
        );
        assert!(message.contains("KHR_draco_mesh_compression"), "{message}");
    }
}

#[test]
fn a_damaged_meshopt_stream_is_one_line_naming_file_mesh_primitive_and_accessor() {
    let scratch = Scratch::new("damaged-meshopt");
    // gltfpack: POSITION is accessor 2 on buffer view 2; wipe its whole stream.
    let path = damaged(&scratch, "cesium_gltfpack.glb", 2, |n| (0, n));
    for (error, message) in errors_of_both_loaders(&path) {
        assert!(
            message.contains("mesh 0 primitive 0: accessor 2"),
            "{message}"
        );
        assert!(
            message.contains("buffer view 2: EXT_meshopt_compression"),
            "{message}"
        );
        assert!(
            matches!(error, LoadError::Accessor { accessor: 2, .. }),
            "{message}"
        );
    }
}

#[test]
fn a_draco_stream_over_the_load_budget_is_refused() {
    use cornertree::io::{LoadLimits, load_character_with};
    let path = compressed("cesium_draco.glb");
    // Budgets from what the file and its JSON take up to what the whole load
    // takes: one of them must run out while the Draco stream is decoded, and
    // say so.
    let fits = |max_bytes| load_character_with(&path, &LoadLimits { max_bytes }).is_ok();
    let (mut low, mut high) = (0usize, 64 << 20);
    assert!(fits(high));
    while high - low > 1 {
        let mid = (low + high) / 2;
        if fits(mid) { high = mid } else { low = mid }
    }
    let mut refused_in_draco = None;
    for max_bytes in (high / 2..high).step_by(1024) {
        if let Err(e) = load_character_with(&path, &LoadLimits { max_bytes }) {
            let message = e.to_string();
            if message.contains("KHR_draco_mesh_compression") {
                refused_in_draco = Some(message);
                break;
            }
        }
    }
    let message = refused_in_draco.expect("some budget runs out in the Draco decode");
    eprintln!("{message} (the whole load needs {high} bytes)");
    assert!(message.contains("primitive 0"), "{message}");
    assert!(
        message.contains("budget") || message.contains("ceiling"),
        "{message}"
    );
}
