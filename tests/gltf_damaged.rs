//! Damaged glTF files (issue #15): a NaN keyframe, an infinite inverse bind
//! matrix, keyframe times out of order, non-finite node transforms, truncated
//! buffers, finite keyframes that pose the character out of range, the load
//! budget, and node chains long enough to expose quadratic walks. Each error
//! is checked whole: one line, the file first, then where and what.

mod common;
use common::Scratch;
use common::glb::Glb;

use std::path::{Path, PathBuf};
use std::time::Instant;

use cornertree::io::{LoadLimits, load_character, load_character_from, load_static_mesh};
use cornertree_workbench::report::animate::{AnimateError, AnimateOptions, animate};

fn asset(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name)
}

fn cesium_man() -> Glb {
    Glb::parse(std::fs::read(asset("CesiumMan.glb")).unwrap())
}

/// The character loader's error for `path`, checked to be one line whose
/// `path()` is the file.
fn character_error(path: &Path) -> String {
    let error = match load_character(path) {
        Ok(_) => panic!("{} should not load", path.display()),
        Err(e) => e,
    };
    let message = error.to_string();
    assert!(!message.contains('\n'), "{message}");
    assert_eq!(error.path(), path);
    message
}

#[test]
fn nan_keyframe_names_animation_channel_sampler_accessor_and_element() {
    let scratch = Scratch::new("damaged-nan-keyframe");
    let mut glb = cesium_man();
    let output = glb.channel_output(0, 0);
    let property = glb.json["animations"][0]["channels"][0]["target"]["path"]
        .as_str()
        .unwrap()
        .to_owned();
    let sampler = glb.json["animations"][0]["channels"][0]["sampler"].clone();
    glb.set_float(output, 5, 1, f32::NAN);
    let path = scratch.write("nan-keyframe.glb", &glb.bytes);
    assert_eq!(
        character_error(&path),
        format!(
            "{}: animation 0 channel 0: sampler {sampler} output accessor {output}: {property} output element 5, component 1 is NaN; only finite numbers are accepted",
            path.display()
        )
    );
    // The static loader does not read animations: the mesh still loads.
    assert!(load_static_mesh(&path).is_ok());
}

#[test]
fn infinite_inverse_bind_matrix_names_skin_accessor_and_element() {
    let scratch = Scratch::new("damaged-ibm");
    let mut glb = cesium_man();
    let accessor = glb.json["skins"][0]["inverseBindMatrices"]
        .as_u64()
        .unwrap() as usize;
    glb.set_float(accessor, 3, 12, f32::INFINITY);
    let path = scratch.write("infinite-ibm.glb", &glb.bytes);
    assert_eq!(
        character_error(&path),
        format!(
            "{}: skin 0: accessor {accessor}: inverseBindMatrices element 3, component 12 is inf; only finite numbers are accepted",
            path.display()
        )
    );
}

#[test]
fn keyframe_times_out_of_order_name_the_two_times() {
    let scratch = Scratch::new("damaged-times");
    let mut glb = cesium_man();
    let animation = &glb.json["animations"][0];
    let sampler = animation["channels"][0]["sampler"].as_u64().unwrap() as usize;
    let input = animation["samplers"][sampler]["input"].as_u64().unwrap() as usize;
    glb.set_float(input, 3, 0, -1.0);
    let path = scratch.write("times.glb", &glb.bytes);
    let message = character_error(&path);
    let expected = format!(
        "{}: animation 0 channel 0: sampler {sampler} input accessor {input}: time 3 (-1) is not after time 2 (",
        path.display()
    );
    assert!(message.starts_with(&expected), "{message}");
    assert!(
        message.ends_with("); keyframe times must strictly increase"),
        "{message}"
    );
}

#[test]
fn finite_keyframes_that_pose_out_of_range_are_refused_by_animate() {
    let scratch = Scratch::new("damaged-huge");
    let mut glb = cesium_man();
    let output = glb.channel_output(0, 0);
    for element in 0..glb.accessor(output)["count"].as_u64().unwrap() as usize {
        glb.set_float(output, element, 0, 1e30);
    }
    let path = scratch.write("huge.glb", &glb.bytes);
    let (character, _) = load_character(&path).expect("finite keyframes load");
    let error = animate(&character, &AnimateOptions::default()).unwrap_err();
    assert!(
        matches!(error, AnimateError::PoseOutOfRange { .. }),
        "{error}"
    );
    let message = error.to_string();
    assert!(
        message.contains(
            "beyond 1e9 in magnitude; the joint transforms take the character out of range"
        ),
        "{message}"
    );
}

#[test]
fn a_clip_needing_too_many_frames_is_refused_before_playing() {
    let (character, _) = load_character(&asset("CesiumMan.glb")).unwrap();
    let options = AnimateOptions {
        fps: 1e9,
        ..AnimateOptions::default()
    };
    let message = animate(&character, &options).unwrap_err().to_string();
    assert!(
        message.contains("at 1000000000 fps that is more than the 1000000 frames allowed"),
        "{message}"
    );
}

/// A `.gltf` with its buffer in `case.bin`, cut to `keep` bytes.
fn truncated_external_buffer(scratch: &Scratch, keep: usize) -> (PathBuf, usize) {
    let glb = cesium_man();
    let json_len = u32::from_le_bytes(glb.bytes[12..16].try_into().unwrap()) as usize;
    let bin_len =
        u32::from_le_bytes(glb.bytes[20 + json_len..24 + json_len].try_into().unwrap()) as usize;
    let bin = &glb.bytes[28 + json_len..28 + json_len + bin_len];
    let mut json = glb.json.clone();
    let declared = json["buffers"][0]["byteLength"].as_u64().unwrap() as usize;
    json["buffers"][0]["uri"] = "case.bin".into();
    scratch.write("case.bin", &bin[..keep]);
    let path = scratch.write("case.gltf", serde_json::to_vec(&json).unwrap());
    (path, declared)
}

#[test]
fn truncated_buffer_file_is_refused_with_both_lengths() {
    let scratch = Scratch::new("damaged-truncated-bin");
    let (path, declared) = truncated_external_buffer(&scratch, 1000);
    let expected = format!(
        "{}: buffer 0: declares {declared} bytes but has 1000",
        path.display()
    );
    assert_eq!(character_error(&path), expected);
    let error = load_static_mesh(&path).unwrap_err();
    assert_eq!(error.to_string(), expected);
}

#[test]
fn truncated_glb_is_refused_in_one_line() {
    let scratch = Scratch::new("damaged-truncated-glb");
    let bytes = std::fs::read(asset("CesiumMan.glb")).unwrap();
    for keep in [11, 12, 100, bytes.len() / 2, bytes.len() - 1] {
        let path = scratch.write("cut.glb", &bytes[..keep]);
        let message = character_error(&path);
        assert!(
            message.starts_with(&format!("{}: not a glTF 2.0 file: ", path.display())),
            "{message}"
        );
    }
}

/// The static loader's error for a small `.gltf` whose node 0 (holding the
/// mesh) has `transform` (JSON members), checked to be one line.
fn node_transform_error(scratch: &Scratch, transform: &str) -> String {
    let positions: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0]}}],
  "nodes": [{{"mesh": 0, {transform}}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0}}}}]}}],
  "buffers": [{{"byteLength": 36, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}}]}}"#,
        common::base64(&positions)
    );
    let path = scratch.write("node.gltf", json);
    let error = load_static_mesh(&path).unwrap_err();
    let message = error.to_string();
    assert!(!message.contains('\n'));
    message
        .strip_prefix(&format!("{}: ", path.display()))
        .unwrap_or_else(|| panic!("names the file: {message}"))
        .to_owned()
}

#[test]
fn non_finite_node_transforms_name_the_node_and_component() {
    let scratch = Scratch::new("damaged-node");
    // JSON has no NaN; a number past f32 becomes infinite when read.
    assert_eq!(
        node_transform_error(&scratch, r#""translation": [0, 1e39, 0]"#),
        "node 0: translation component 1 is inf; only finite numbers are accepted"
    );
    assert_eq!(
        node_transform_error(&scratch, r#""scale": [1, 1, -1e39]"#),
        "node 0: scale component 2 is -inf; only finite numbers are accepted"
    );
    assert_eq!(
        node_transform_error(
            &scratch,
            r#""matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 1e40, 1]"#
        ),
        "node 0: matrix entry 14 (column 3, row 2) is inf; only finite numbers are accepted"
    );
    assert_eq!(
        node_transform_error(&scratch, r#""rotation": [0, 0, 0, 0]"#),
        "node 0: rotation [0.0, 0.0, 0.0, 0.0] is the zero quaternion, not a rotation"
    );
}

#[test]
fn the_load_budget_refuses_the_file_or_the_accessor_that_exceeds_it() {
    let path = asset("CesiumMan.glb");
    let bytes = std::fs::read(&path).unwrap();
    let tiny = LoadLimits { max_bytes: 1000 };
    let message = load_character_from(&path, &bytes, &tiny)
        .unwrap_err()
        .to_string();
    assert_eq!(
        message,
        format!(
            "{}: the file: {} bytes would take the load to {} bytes, over its budget of 1000 bytes (LoadLimits::max_bytes)",
            path.display(),
            bytes.len(),
            bytes.len()
        )
    );
    // Budgets growing by 2% from the file's size up to one that suffices: each
    // stage of the load (file, JSON, binary chunk, each accessor) refuses
    // cleanly when it is the one that does not fit.
    let mut max_bytes = bytes.len();
    let mut decoding_refused = 0;
    loop {
        match load_character_from(&path, &bytes, &LoadLimits { max_bytes }) {
            Ok(_) => break,
            Err(error) => {
                let message = error.to_string();
                assert!(
                    message.starts_with(&format!("{}: ", path.display())),
                    "{message}"
                );
                assert!(!message.contains('\n'), "{message}");
                assert!(
                    message.ends_with(&format!(
                        "over its budget of {max_bytes} bytes (LoadLimits::max_bytes)"
                    )),
                    "{message}"
                );
                if message.contains("decoding the accessor: ") {
                    if decoding_refused == 0 {
                        eprintln!("{message}");
                    }
                    decoding_refused += 1;
                }
            }
        }
        max_bytes += max_bytes / 50;
    }
    assert!(decoding_refused > 0, "no budget stopped the decoding");
    assert!(
        max_bytes < 4 * bytes.len(),
        "CesiumMan needs {max_bytes} bytes"
    );
    assert!(load_character_from(&path, &bytes, &LoadLimits::default()).is_ok());
}

/// A two-joint character whose root joint hangs below a chain of `chain`
/// identity nodes, with `siblings` more root joints hanging from the chain's
/// last node: walking up the chain once per joint would be quadratic.
fn long_chain(chain: usize, siblings: usize) -> String {
    let positions: Vec<u8> = [0.0f32, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]
        .iter()
        .flat_map(|v| v.to_le_bytes())
        .chain([0u8; 12]) // JOINTS_0: three vertices, joint 0
        .chain(
            [1.0f32, 0.0, 0.0, 0.0]
                .repeat(3)
                .iter()
                .flat_map(|v| v.to_le_bytes()),
        )
        .collect();
    // Nodes: 0 mesh, 1..=chain the chain, then the joints.
    let first_joint = chain + 1;
    let joints = 1 + siblings;
    let mut nodes = vec![r#"{"mesh": 0, "skin": 0}"#.to_owned()];
    for k in 1..chain {
        nodes.push(format!(r#"{{"children": [{}]}}"#, k + 1));
    }
    let hanging: Vec<String> = (first_joint..first_joint + joints)
        .map(|j| j.to_string())
        .collect();
    nodes.push(format!(r#"{{"children": [{}]}}"#, hanging.join(", ")));
    for _ in 0..joints {
        nodes.push("{}".to_owned());
    }
    format!(
        r#"{{"asset": {{"version": "2.0"}}, "scenes": [{{"nodes": [0, 1]}}],
  "nodes": [{nodes}],
  "skins": [{{"joints": [{hanging}]}}],
  "meshes": [{{"primitives": [{{"attributes": {{"POSITION": 0, "JOINTS_0": 1, "WEIGHTS_0": 2}}}}]}}],
  "buffers": [{{"byteLength": {len}, "uri": "data:application/octet-stream;base64,{data}"}}],
  "bufferViews": [{{"buffer": 0, "byteLength": 36}}, {{"buffer": 0, "byteOffset": 36, "byteLength": 12}},
                  {{"buffer": 0, "byteOffset": 48, "byteLength": 48}}],
  "accessors": [{{"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3"}},
                {{"bufferView": 1, "componentType": 5121, "count": 3, "type": "VEC4"}},
                {{"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC4"}}]}}"#,
        nodes = nodes.join(", "),
        hanging = hanging.join(", "),
        len = positions.len(),
        data = common::base64(&positions),
    )
}

#[test]
fn long_node_chains_load_in_linear_time() {
    let scratch = Scratch::new("damaged-chain");
    let path = scratch.write("chain.gltf", long_chain(50_000, 10_000));
    let start = Instant::now();
    let (character, _) = load_character(&path).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(character.skeleton.len(), 10_001);
    let (mesh, report) = load_static_mesh(&path).unwrap();
    assert_eq!(mesh.triangle_count(), 1);
    assert_eq!(report.nodes_visited, 50_000 + 10_001 + 1);
    // Walking the chain once per root joint (5e8 matrix products) takes
    // minutes; the loaders take well under a second.
    let elapsed = start.elapsed();
    assert!(elapsed.as_secs() < 10, "took {elapsed:?}");
}
