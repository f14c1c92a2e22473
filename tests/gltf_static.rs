//! Static glTF loading: the two bundled assets, and small hand-built files for
//! every error and conversion path.

mod common;
use common::{Scratch, base64};

use std::path::{Path, PathBuf};

use cornertree::io::{LoadError, load_static_mesh};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
}

#[test]
fn cesium_man_loads_whole() {
    let (mesh, report) = load_static_mesh(&asset("CesiumMan.glb")).expect("CesiumMan.glb loads");
    assert_eq!(mesh.vertex_count(), 3_273);
    assert_eq!(mesh.triangle_count(), 4_672);
    assert_eq!((report.vertices, report.triangles), (3_273, 4_672));
    assert_eq!(
        (report.meshes, report.distinct_meshes, report.primitives),
        (1, 1, 1)
    );
    assert_eq!(report.skinned_instances, 1);
    assert_eq!(report.scene, Some(0));
    assert_eq!(report.nodes_visited, 22);
    assert!(report.skipped.is_empty());
    assert!(mesh.size() > 0.0);
}

#[test]
fn brain_stem_loads_whole() {
    let (mesh, report) = load_static_mesh(&asset("BrainStem.glb")).expect("BrainStem.glb loads");
    assert_eq!(mesh.triangle_count(), 61_666);
    assert_eq!(mesh.vertex_count(), 34_239);
    assert_eq!(report.primitives, 59);
    assert_eq!((report.meshes, report.distinct_meshes), (1, 1));
    assert!(report.skipped.is_empty());
}

// ---------------------------------------------------------------------------
// Hand-built files.

/// One mesh, one primitive, placed by the nodes in `nodes` (JSON array body);
/// positions and u32 indices in one buffer, as a data URI unless `bin` names
/// an external file to write it to.
struct Spec<'a> {
    positions: &'a [[f32; 3]],
    indices: Option<&'a [u32]>,
    mode: u32,
    nodes: &'a str,
    bin: Option<&'a str>,
}

impl Default for Spec<'_> {
    fn default() -> Self {
        Self {
            positions: &[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
            indices: Some(&[0, 1, 2]),
            mode: 4,
            nodes: r#"{"mesh": 0}"#,
            bin: None,
        }
    }
}

fn write_gltf(scratch: &Scratch, name: &str, spec: &Spec<'_>) -> PathBuf {
    let mut buffer = Vec::new();
    for p in spec.positions {
        for c in p {
            buffer.extend_from_slice(&c.to_le_bytes());
        }
    }
    let position_bytes = buffer.len();
    for i in spec.indices.unwrap_or(&[]) {
        buffer.extend_from_slice(&i.to_le_bytes());
    }
    let index_bytes = buffer.len() - position_bytes;
    let uri = match spec.bin {
        Some(bin) => {
            scratch.write(bin, &buffer);
            bin.to_owned()
        }
        None => format!("data:application/octet-stream;base64,{}", base64(&buffer)),
    };
    let (indices_attr, index_view, index_accessor) = match spec.indices {
        Some(indices) => (
            r#", "indices": 1"#.to_owned(),
            format!(
                r#", {{"buffer": 0, "byteOffset": {position_bytes}, "byteLength": {index_bytes}}}"#
            ),
            format!(
                r#", {{"bufferView": 1, "componentType": 5125, "count": {}, "type": "SCALAR"}}"#,
                indices.len()
            ),
        ),
        None => (String::new(), String::new(), String::new()),
    };
    let node_count = spec.nodes.matches('{').count();
    let roots: Vec<String> = (0..node_count).map(|i| i.to_string()).collect();
    let json = format!(
        r#"{{
  "asset": {{"version": "2.0"}},
  "scene": 0,
  "scenes": [{{"nodes": [{roots}]}}],
  "nodes": [{nodes}],
  "meshes": [{{"name": "thing", "primitives": [{{"attributes": {{"POSITION": 0}}{indices_attr}, "mode": {mode}}}]}}],
  "buffers": [{{"byteLength": {len}, "uri": "{uri}"}}],
  "bufferViews": [{{"buffer": 0, "byteOffset": 0, "byteLength": {position_bytes}}}{index_view}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": {count}, "type": "VEC3",
                 "min": [0, 0, 0], "max": [1, 1, 1]}}{index_accessor}]
}}"#,
        roots = roots.join(", "),
        nodes = spec.nodes,
        mode = spec.mode,
        len = buffer.len(),
        count = spec.positions.len(),
    );
    scratch.write(name, json.as_bytes())
}

/// Loading fails; the message is one line naming the file and containing every word.
fn expect_error(path: &Path, words: &[&str]) -> LoadError {
    let error = match load_static_mesh(path) {
        Ok((mesh, _)) => panic!(
            "{} loaded ({} triangles) but should fail",
            path.display(),
            mesh.triangle_count()
        ),
        Err(e) => e,
    };
    let message = error.to_string();
    assert!(!message.contains('\n'), "multi-line message: {message}");
    let file = path.file_name().unwrap().to_str().unwrap();
    assert!(
        message.contains(file),
        "message does not name {file}: {message}"
    );
    for word in words {
        assert!(message.contains(word), "message lacks {word:?}: {message}");
    }
    assert_eq!(error.path(), path);
    error
}

#[test]
fn missing_file_is_an_io_error() {
    let scratch = Scratch::new("missing");
    let path = scratch.0.join("nowhere.glb");
    let error = expect_error(&path, &["cannot read"]);
    assert!(matches!(error, LoadError::Io { .. }));
}

#[test]
fn random_bytes_and_text_are_not_gltf() {
    let scratch = Scratch::new("not-gltf");
    let noise: Vec<u8> = (0u32..4096)
        .map(|i| (i.wrapping_mul(2_654_435_761) >> 13) as u8)
        .collect();
    let path = scratch.write("noise.glb", &noise);
    assert!(matches!(
        expect_error(&path, &["not a glTF"]),
        LoadError::NotGltf { .. }
    ));

    let path = scratch.write("notes.gltf", b"just some notes\nabout a model\n");
    assert!(matches!(
        expect_error(&path, &["not a glTF"]),
        LoadError::NotGltf { .. }
    ));

    // Valid JSON, but not glTF.
    let path = scratch.write("object.gltf", br#"{"hello": "world"}"#);
    assert!(matches!(
        expect_error(&path, &["not a glTF"]),
        LoadError::NotGltf { .. }
    ));

    // GLB magic with a corrupt header and a truncated body.
    let path = scratch.write("header.glb", b"glTF\x02\x00\x00\x00\x04\x00\x00\x00");
    assert!(matches!(
        expect_error(&path, &["not a glTF"]),
        LoadError::NotGltf { .. }
    ));
    let path = scratch.write("short.glb", b"glTF\x02\x00\x00\x00\xff\xff\x00\x00JSON");
    assert!(matches!(
        expect_error(&path, &["not a glTF"]),
        LoadError::NotGltf { .. }
    ));
}

#[test]
fn only_lines_means_no_triangles() {
    let scratch = Scratch::new("lines");
    let path = write_gltf(
        &scratch,
        "lines.gltf",
        &Spec {
            indices: Some(&[0, 1, 1, 2]),
            mode: 1,
            ..Spec::default()
        },
    );
    let error = expect_error(
        &path,
        &["no triangles", "1 non-triangle primitive(s) skipped"],
    );
    assert!(matches!(
        error,
        LoadError::NoTriangles {
            primitives: 0,
            skipped: 1,
            ..
        }
    ));
}

#[test]
fn lines_next_to_triangles_are_skipped_and_reported() {
    let scratch = Scratch::new("mixed");
    let buffer: Vec<u8> = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
        .collect();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"name": "mixed", "primitives": [
    {{"attributes": {{"POSITION": 0}}, "mode": 3}},
    {{"attributes": {{"POSITION": 0}}}}]}}],
  "buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}}]}}"#,
        base64(&buffer)
    );
    // No "scene" and no POSITION min/max: first scene used, min/max tolerated.
    let path = scratch.write("mixed.gltf", json.as_bytes());
    let (mesh, report) = load_static_mesh(&path).expect("mixed.gltf loads");
    assert_eq!(mesh.triangle_count(), 1);
    assert_eq!(report.scene, Some(0));
    assert_eq!(report.primitives, 1);
    assert_eq!(report.skipped.len(), 1);
    let skipped = &report.skipped[0];
    assert_eq!(
        (
            skipped.node,
            skipped.mesh.index,
            skipped.primitive,
            skipped.mode
        ),
        (0, 0, 0, "LINE_STRIP")
    );
    assert_eq!(skipped.mesh.name.as_deref(), Some("mixed"));
    let text = skipped.to_string();
    assert!(
        text.contains("mesh 0 \"mixed\" primitive 0") && text.contains("LINE_STRIP"),
        "{text}"
    );
}

#[test]
fn nan_position_is_reported_with_its_vertex() {
    let scratch = Scratch::new("nan");
    let positions = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, f32::NAN, 0.0]];
    let path = write_gltf(
        &scratch,
        "nan.gltf",
        &Spec {
            positions: &positions,
            ..Spec::default()
        },
    );
    let error = expect_error(
        &path,
        &["non-finite", "mesh 0 \"thing\"", "primitive 0", "vertex 2"],
    );
    assert!(matches!(
        error,
        LoadError::NonFinitePosition {
            vertex: 2,
            primitive: 0,
            ..
        }
    ));
}

#[test]
fn index_out_of_range_is_reported_with_its_value() {
    let scratch = Scratch::new("range");
    let path = write_gltf(
        &scratch,
        "range.gltf",
        &Spec {
            indices: Some(&[0, 1, 7]),
            ..Spec::default()
        },
    );
    let error = expect_error(
        &path,
        &[
            "index 7",
            "out of range",
            "mesh 0 \"thing\"",
            "primitive 0",
            "3 vertices",
        ],
    );
    assert!(matches!(
        error,
        LoadError::IndexOutOfRange {
            index: 7,
            entry: 2,
            vertex_count: 3,
            ..
        }
    ));
}

#[test]
fn missing_position_is_reported() {
    let scratch = Scratch::new("no-position");
    let json = r#"{"asset": {"version": "2.0"}, "scenes": [{"nodes": [0]}], "nodes": [{"mesh": 0}],
        "meshes": [{"primitives": [{"attributes": {}}]}]}"#;
    let path = scratch.write("bare.gltf", json.as_bytes());
    let error = expect_error(&path, &["POSITION", "mesh 0 primitive 0"]);
    assert!(matches!(
        error,
        LoadError::MissingPosition { primitive: 0, .. }
    ));

    // POSITION naming an accessor that does not exist.
    let json = json.replace(r#""attributes": {}"#, r#""attributes": {"POSITION": 5}"#);
    let path = scratch.write("dangling.gltf", json.as_bytes());
    expect_error(&path, &["invalid glTF", "POSITION", "accessor 5"]);
}

#[test]
fn accessor_past_its_buffer_is_an_error() {
    let scratch = Scratch::new("short-buffer");
    let path = write_gltf(&scratch, "short.gltf", &Spec::default());
    // Claim more vertices than the buffer view holds.
    let json = std::fs::read_to_string(&path).unwrap().replace(
        r#""count": 3, "type": "VEC3""#,
        r#""count": 300, "type": "VEC3""#,
    );
    std::fs::write(&path, json).unwrap();
    let error = expect_error(&path, &["accessor 0", "do not fit"]);
    assert!(matches!(error, LoadError::Accessor { accessor: 0, .. }));
}

#[test]
fn required_unknown_extensions_are_refused_and_compression_ones_are_read() {
    let scratch = Scratch::new("extensions");
    let path = write_gltf(&scratch, "unknown.gltf", &Spec::default());
    let plain = std::fs::read_to_string(&path).unwrap();
    let json = plain.replacen(
        r#""asset""#,
        r#""extensionsUsed": ["EXT_unknown_compression"], "extensionsRequired": ["EXT_unknown_compression", "KHR_draco_mesh_compression"], "asset""#,
        1,
    );
    std::fs::write(&path, json).unwrap();
    let error = expect_error(&path, &["EXT_unknown_compression", "unsupported"]);
    assert!(
        matches!(error, LoadError::UnsupportedExtension { ref extensions, .. } if extensions == &["EXT_unknown_compression"])
    );
    // The three compression extensions, required, are read (here the file
    // has no compressed data: it loads as it is).
    let json = plain.replacen(
        r#""asset""#,
        r#""extensionsUsed": ["KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization"], "extensionsRequired": ["KHR_draco_mesh_compression", "EXT_meshopt_compression", "KHR_mesh_quantization"], "asset""#,
        1,
    );
    std::fs::write(&path, json).unwrap();
    let (_, report) = load_static_mesh(&path).unwrap();
    assert_eq!(
        report
            .notes
            .iter()
            .filter(|n| n.ends_with("is used and read"))
            .count(),
        3,
        "{:?}",
        report.notes
    );
}

#[test]
fn node_transforms_are_composed_into_world_space() {
    let scratch = Scratch::new("transform");
    // Node 0 translates by (10, 0, 0) and holds node 1, which scales by 2 and
    // holds the mesh; node 2 places the same mesh again with a matrix
    // (column-major, translation (0, 0, 5)).
    let nodes = r#"{"translation": [10, 0, 0], "children": [1]},
        {"scale": [2, 2, 2], "mesh": 0},
        {"matrix": [1,0,0,0, 0,1,0,0, 0,0,1,0, 0,0,5,1], "mesh": 0}"#;
    let path = write_gltf(
        &scratch,
        "moved.gltf",
        &Spec {
            nodes,
            bin: Some("moved.bin"),
            ..Spec::default()
        },
    );
    // Node 1 is a child, not a root: make the scene list only nodes 0 and 2.
    let json = std::fs::read_to_string(&path)
        .unwrap()
        .replace(r#""nodes": [0, 1, 2]"#, r#""nodes": [0, 2]"#);
    std::fs::write(&path, json).unwrap();

    let (mesh, report) = load_static_mesh(&path).expect("moved.gltf loads");
    assert_eq!(
        (
            report.nodes_visited,
            report.meshes,
            report.distinct_meshes,
            report.primitives
        ),
        (3, 2, 1, 2)
    );
    assert_eq!(mesh.triangle_count(), 2);
    let p: Vec<[f32; 3]> = mesh.positions().iter().map(|p| [p.x, p.y, p.z]).collect();
    assert_eq!(
        p,
        vec![
            [10.0, 0.0, 0.0],
            [12.0, 0.0, 0.0],
            [10.0, 2.0, 0.0],
            [0.0, 0.0, 5.0],
            [1.0, 0.0, 5.0],
            [0.0, 1.0, 5.0]
        ]
    );
    assert_eq!(mesh.indices(), &[[0, 1, 2], [3, 4, 5]]);
}

#[test]
fn node_reached_twice_is_an_error() {
    let scratch = Scratch::new("cycle");
    let nodes = r#"{"mesh": 0, "children": [1]}, {"children": [0]}"#;
    let path = write_gltf(
        &scratch,
        "cycle.gltf",
        &Spec {
            nodes,
            ..Spec::default()
        },
    );
    let error = expect_error(&path, &["reached twice"]);
    assert!(matches!(error, LoadError::NodeGraph { .. }));
}

#[test]
fn triangle_strip_alternates_winding() {
    let scratch = Scratch::new("strip");
    let positions = [
        [0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [2.0, 0.0, 0.0],
    ];
    // Strip 0 1 2 3 4, plus a repeated index (a stitch) that must be dropped.
    let path = write_gltf(
        &scratch,
        "strip.gltf",
        &Spec {
            positions: &positions,
            indices: Some(&[0, 1, 2, 3, 4, 4]),
            mode: 5,
            ..Spec::default()
        },
    );
    let (mesh, report) = load_static_mesh(&path).expect("strip.gltf loads");
    assert_eq!(mesh.indices(), &[[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
    assert_eq!(report.degenerate_dropped, 1);
    // Every triangle keeps the first one's orientation (all -z here).
    for (_, t) in mesh.iter_triangles() {
        assert!(t.scaled_normal().z < 0.0, "flipped triangle {t:?}");
    }

    // Without indices: implicit 0..n.
    let path = write_gltf(
        &scratch,
        "strip-plain.gltf",
        &Spec {
            positions: &positions,
            indices: None,
            mode: 5,
            ..Spec::default()
        },
    );
    let (mesh, _) = load_static_mesh(&path).expect("strip-plain.gltf loads");
    assert_eq!(mesh.indices(), &[[0, 1, 2], [1, 3, 2], [2, 3, 4]]);
}

#[test]
fn triangle_fan_is_converted() {
    let scratch = Scratch::new("fan");
    let positions = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [1.0, 1.0, 0.0],
        [0.0, 1.0, 0.0],
    ];
    let path = write_gltf(
        &scratch,
        "fan.gltf",
        &Spec {
            positions: &positions,
            indices: None,
            mode: 6,
            ..Spec::default()
        },
    );
    let (mesh, _) = load_static_mesh(&path).expect("fan.gltf loads");
    assert_eq!(mesh.indices(), &[[1, 2, 0], [2, 3, 0]]);
}

#[test]
fn skinned_node_transform_is_ignored() {
    let scratch = Scratch::new("skin");
    // Node 0 carries the mesh and a skin whose single joint is node 1; node 0's
    // translation must not move the mesh.
    let nodes = r#"{"mesh": 0, "skin": 0, "translation": [100, 0, 0]}, {}"#;
    let path = write_gltf(
        &scratch,
        "skinned.gltf",
        &Spec {
            nodes,
            ..Spec::default()
        },
    );
    let json = std::fs::read_to_string(&path).unwrap().replacen(
        r#""asset""#,
        r#""skins": [{"joints": [1]}], "asset""#,
        1,
    );
    std::fs::write(&path, json).unwrap();
    let (mesh, report) = load_static_mesh(&path).expect("skinned.gltf loads");
    assert_eq!(report.skinned_instances, 1);
    assert_eq!(mesh.positions()[1].x, 1.0);
}

#[test]
fn hostile_numbers_never_panic() {
    let scratch = Scratch::new("hostile");
    let path = write_gltf(&scratch, "base.gltf", &Spec::default());
    let json = std::fs::read_to_string(&path).unwrap();
    let json = json.replacen(
        r#""byteOffset": 0, "byteLength""#,
        r#""byteOffset": 0, "byteStride": 12, "byteLength""#,
        1,
    );
    // Every number that follows `": ` (a JSON member value), one at a time.
    let numbers: Vec<(usize, usize)> = json
        .match_indices(": ")
        .filter_map(|(at, _)| {
            let start = at + 2;
            let len = json[start..].bytes().take_while(u8::is_ascii_digit).count();
            (len > 0).then_some((start, start + len))
        })
        .collect();
    assert!(numbers.len() > 10);
    let target = scratch.0.join("hostile.gltf");
    for &(start, end) in &numbers {
        for value in [
            "0",
            "1",
            "2",
            "5",
            "13",
            "4294967295",
            "18446744073709551615",
            "-1",
            "1e300",
        ] {
            let mutated = format!("{}{value}{}", &json[..start], &json[end..]);
            std::fs::write(&target, mutated).unwrap();
            // Either outcome is fine; a panic fails the test.
            let _ = load_static_mesh(&target);
        }
    }
}

#[test]
fn corrupted_glb_never_panics() {
    let scratch = Scratch::new("corrupt-glb");
    let original = std::fs::read(asset("CesiumMan.glb")).unwrap();
    let target = scratch.0.join("corrupt.glb");
    let json_length =
        u32::from_le_bytes([original[12], original[13], original[14], original[15]]) as usize;
    let bin_header = 20 + json_length;
    // Header and chunk lengths. (Like the gltf crate, the loader accepts a
    // declared total length at most the file's, so only chunk lengths must fail.)
    for at in [8, 12, bin_header] {
        for value in [0u32, 1, 12, 0x7fff_ffff, u32::MAX] {
            let mut bytes = original.clone();
            bytes[at..at + 4].copy_from_slice(&value.to_le_bytes());
            std::fs::write(&target, &bytes).unwrap();
            let result = load_static_mesh(&target);
            assert!(
                at == 8 || result.is_err(),
                "length {value} at byte {at} accepted"
            );
        }
    }
    // Truncations and byte flips in the binary chunk (deterministic positions).
    for cut in [
        13,
        20,
        bin_header,
        bin_header + 8,
        original.len() / 2,
        original.len() - 1,
    ] {
        std::fs::write(&target, &original[..cut]).unwrap();
        let _ = load_static_mesh(&target);
    }
    let mut state = 0x2545_f491_4f6c_dd1d_u64;
    for _ in 0..64 {
        let mut bytes = original.clone();
        for _ in 0..16 {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            let at = bin_header + 8 + (state % (original.len() - bin_header - 8) as u64) as usize;
            bytes[at] ^= 0xff;
        }
        std::fs::write(&target, &bytes).unwrap();
        if let Err(e) = load_static_mesh(&target) {
            assert!(!e.to_string().contains('\n'));
        }
    }
}

#[test]
fn sparse_positions_are_applied() {
    let scratch = Scratch::new("sparse");
    let mut buffer: Vec<u8> = [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]]
        .iter()
        .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes()))
        .collect();
    buffer.extend_from_slice(&[1, 0, 0, 0]); // sparse index 1 (u8), padded
    buffer.extend(
        Some([5.0f32, 0.0, 0.0])
            .iter()
            .flat_map(|p| p.iter().flat_map(|c| c.to_le_bytes())),
    );
    let json = |buffer: &[u8]| {
        format!(
            r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}], "nodes": [{{"mesh": 0}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "buffers": [{{"byteLength": 52, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 4}},
                  {{"buffer": 0, "byteOffset": 40, "byteLength": 12}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3",
    "sparse": {{"count": 1, "indices": {{"bufferView": 1, "componentType": 5121}},
               "values": {{"bufferView": 2}}}}}}]}}"#,
            base64(buffer)
        )
    };
    let path = scratch.write("sparse.gltf", json(&buffer).as_bytes());
    let (mesh, _) = load_static_mesh(&path).expect("sparse.gltf loads");
    assert_eq!(mesh.positions()[1].x, 5.0);

    // A sparse index past the accessor's 3 elements.
    buffer[36] = 9;
    let path = scratch.write("sparse-bad.gltf", json(&buffer).as_bytes());
    expect_error(&path, &["accessor 0", "sparse index 9", "out of range"]);
}
