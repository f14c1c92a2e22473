//! The inputs mutations start from: the two shipped characters (GLB), a
//! small generated character written both as `.gltf` + `.bin` and as GLB,
//! and CesiumMan compressed four ways (`tests/compressed/`: Draco, meshopt
//! by gltf-transform and by gltfpack, quantized), so the decoders of
//! `KHR_draco_mesh_compression`, `EXT_meshopt_compression` and
//! `KHR_mesh_quantization` see damaged streams.

use std::path::Path;

/// How a case is stored on disk.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    /// One GLB file: header, JSON chunk, BIN chunk.
    Glb,
    /// A `.gltf` JSON file whose buffer 0 is the file `case.bin` next to it.
    Gltf,
}

/// A seed split into its JSON text and its binary buffer.
pub struct Seed {
    pub name: &'static str,
    pub kind: Kind,
    pub json: Vec<u8>,
    pub bin: Vec<u8>,
    /// `(byteOffset, byteLength)` of each buffer view, clipped to `bin`, so
    /// binary mutations can aim at one accessor's data.
    pub views: Vec<(usize, usize)>,
}

/// Name of the binary buffer of [`Kind::Gltf`] cases.
pub const BIN_NAME: &str = "case.bin";

/// The compressed seeds, after the four plain ones.
pub const COMPRESSED: [&str; 4] = [
    "cesium_draco.glb",
    "cesium_meshopt.glb",
    "cesium_gltfpack.glb",
    "cesium_quantized.glb",
];

pub fn all() -> Vec<Seed> {
    let assets = Path::new(env!("CARGO_MANIFEST_DIR")).join("assets");
    let mut seeds = Vec::new();
    let (json, bin) = small_character(None);
    seeds.push(seed("small.glb", Kind::Glb, json, bin));
    let (json, bin) = small_character(Some(BIN_NAME));
    seeds.push(seed("small.gltf", Kind::Gltf, json, bin));
    for name in ["CesiumMan.glb", "BrainStem.glb"] {
        let bytes = std::fs::read(assets.join(name)).expect("shipped asset");
        let (json, bin) = split_glb(&bytes).expect("shipped assets are GLB");
        seeds.push(seed(name, Kind::Glb, json, bin));
    }
    let compressed = assets.join("../tests/compressed");
    for name in COMPRESSED {
        let bytes = std::fs::read(compressed.join(name)).expect("compressed test file");
        let (json, bin) = split_glb(&bytes).expect("compressed test files are GLB");
        seeds.push(seed(name, Kind::Glb, json, bin));
    }
    seeds
}

fn seed(name: &'static str, kind: Kind, json: Vec<u8>, bin: Vec<u8>) -> Seed {
    let root: serde_json::Value = serde_json::from_slice(&json).expect("seed JSON parses");
    let views = root["bufferViews"]
        .as_array()
        .map(|views| {
            views
                .iter()
                .filter_map(|v| {
                    // A meshopt-compressed view's bytes lie where its
                    // extension says (buffer 0, the binary chunk); its own
                    // range is in the fallback buffer, which has none.
                    let v = v
                        .get("extensions")
                        .and_then(|e| e.get("EXT_meshopt_compression"))
                        .unwrap_or(v);
                    let offset = v["byteOffset"].as_u64().unwrap_or(0) as usize;
                    let length = v["byteLength"].as_u64()? as usize;
                    let end = (offset + length).min(bin.len());
                    (offset < end).then_some((offset, end - offset))
                })
                .collect()
        })
        .unwrap_or_default();
    Seed {
        name,
        kind,
        json,
        bin,
        views,
    }
}

/// JSON and BIN chunks of a GLB file.
pub fn split_glb(bytes: &[u8]) -> Option<(Vec<u8>, Vec<u8>)> {
    let word = |at: usize| -> Option<usize> {
        let b = bytes.get(at..at + 4)?;
        Some(u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
    };
    let json_len = word(12)?;
    let json = bytes.get(20..20 + json_len)?.to_vec();
    let bin_at = 20 + json_len;
    let bin_len = word(bin_at)?;
    let bin = bytes.get(bin_at + 8..bin_at + 8 + bin_len)?.to_vec();
    Some((json, bin))
}

/// A GLB file of `json` and `bin`, each chunk padded to 4 bytes as the spec says.
pub fn pack_glb(json: &[u8], bin: &[u8]) -> Vec<u8> {
    let pad = |n: usize| n.next_multiple_of(4);
    let (json_len, bin_len) = (pad(json.len()), pad(bin.len()));
    let total = 12 + 8 + json_len + 8 + bin_len;
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json_len as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(json);
    out.resize(20 + json_len, b' ');
    out.extend_from_slice(&(bin_len as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(bin);
    out.resize(total, 0);
    out
}

/// Accessors over one buffer, one buffer view each.
#[derive(Default)]
struct Builder {
    bin: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Builder {
    fn add(
        &mut self,
        bytes: &[u8],
        component: u32,
        count: usize,
        ty: &str,
        normalized: bool,
    ) -> usize {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        self.views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            self.bin.len(),
            bytes.len()
        ));
        self.bin.extend_from_slice(bytes);
        self.accessors.push(format!(
            r#"{{"bufferView": {}, "componentType": {component}, "count": {count}, "type": "{ty}", "normalized": {normalized}}}"#,
            self.views.len() - 1
        ));
        self.accessors.len() - 1
    }

    fn f32s(&mut self, values: &[f32], ty: &str, per: usize) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.add(&bytes, 5126, values.len() / per, ty, false)
    }

    fn u16s(&mut self, values: &[u16], ty: &str, per: usize) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.add(&bytes, 5123, values.len() / per, ty, false)
    }

    fn u8s(&mut self, values: &[u8], ty: &str, per: usize, normalized: bool) -> usize {
        self.add(values, 5121, values.len() / per, ty, normalized)
    }

    fn i16s(&mut self, values: &[i16], ty: &str, per: usize) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.add(&bytes, 5122, values.len() / per, ty, true)
    }
}

/// A three-joint leg under a transformed non-joint root: a six-vertex strip
/// skinned with two influence sets (u16 joints and float weights; u8 joints
/// and normalized u8 weights), inverse bind matrices, a joint given as a
/// matrix, and clips with LINEAR, STEP and CUBICSPLINE channels (one rotation
/// as normalized i16, one translation with sparse keyframes), plus channels
/// the loader skips (a node above the skeleton, morph weights).
/// `uri`: the buffer's file, or `None` for the GLB binary chunk.
fn small_character(uri: Option<&str>) -> (Vec<u8>, Vec<u8>) {
    let mut b = Builder::default();
    let positions = b.f32s(
        &[
            -0.5, 0.0, 0.0, 0.5, 0.0, 0.0, -0.5, 1.0, 0.0, 0.5, 1.0, 0.0, -0.5, 2.0, 0.0, 0.5, 2.0,
            0.0,
        ],
        "VEC3",
        3,
    );
    let indices = b.u16s(&[0, 1, 2, 2, 1, 3, 2, 3, 4, 4, 3, 5], "SCALAR", 1);
    let joints0 = b.u16s(
        &[
            0, 1, 0, 0, 0, 1, 0, 0, 1, 2, 0, 0, 1, 2, 0, 0, 2, 0, 0, 0, 2, 0, 0, 0,
        ],
        "VEC4",
        4,
    );
    let weights0 = b.f32s(
        &[
            0.8, 0.2, 0.0, 0.0, 0.8, 0.2, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 0.5, 0.5, 0.0, 0.0, 1.0,
            0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0,
        ],
        "VEC4",
        4,
    );
    let joints1 = b.u8s(&[2; 24], "VEC4", 4, false);
    let weights1 = b.u8s(
        &[
            0, 0, 0, 0, 0, 0, 0, 0, 10, 0, 0, 0, 10, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0, 0,
        ],
        "VEC4",
        4,
        true,
    );
    let identity_at = |y: f32| {
        [
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, -y, 0.0, 1.0,
        ]
    };
    let ibm = b.f32s(
        &[identity_at(0.5), identity_at(1.5), identity_at(2.5)].concat(),
        "MAT4",
        16,
    );
    let times = b.f32s(&[0.0, 0.5, 1.0], "SCALAR", 1);
    let translations = b.f32s(&[0.0, 0.0, 0.0, 0.1, 0.0, 0.0, 0.0, 0.0, 0.0], "VEC3", 3);
    let rotations = b.f32s(
        &[
            0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.38268343, 0.9238795, 0.0, 0.0, 0.0, 1.0,
        ],
        "VEC4",
        4,
    );
    // CUBICSPLINE: in-tangent, value, out-tangent per keyframe.
    let spline = b.i16s(
        &[
            0, 0, 0, 0, 0, 0, 0, 32767, 0, 0, 0, 0, //
            0, 0, 0, 0, 0, 0, 12539, 30272, 0, 0, 0, 0, //
            0, 0, 0, 0, 0, 0, 0, 32767, 0, 0, 0, 0,
        ],
        "VEC4",
        4,
    );
    let scales = b.f32s(&[1.0, 1.0, 1.0, 1.2, 1.0, 1.2, 1.0, 1.0, 1.0], "VEC3", 3);
    let step_times = b.f32s(&[0.25, 0.75], "SCALAR", 1);
    let morph = b.f32s(&[0.0, 1.0], "SCALAR", 1);
    // Sparse keyframes: translation 1 of `translations` replaced.
    let sparse_indices = b.u8s(&[1, 0, 0, 0], "SCALAR", 1, false);
    let sparse_values = b.f32s(&[0.0, 0.2, 0.0], "VEC3", 3);
    let sparse = b.accessors.len();
    b.accessors.push(format!(
        r#"{{"bufferView": {}, "componentType": 5126, "count": 3, "type": "VEC3",
          "sparse": {{"count": 1, "indices": {{"bufferView": {}, "componentType": 5121}},
                      "values": {{"bufferView": {}}}}}}}"#,
        translations, sparse_indices, sparse_values
    ));
    let buffer = match uri {
        Some(uri) => format!(r#"{{"byteLength": {}, "uri": "{uri}"}}"#, b.bin.len()),
        None => format!(r#"{{"byteLength": {}}}"#, b.bin.len()),
    };
    let json = format!(
        r#"{{"asset": {{"version": "2.0"}}, "scene": 0, "scenes": [{{"nodes": [0, 4]}}],
  "nodes": [
    {{"name": "root", "translation": [0, 0.5, 0], "rotation": [0, 0.7071068, 0, 0.7071068], "children": [1]}},
    {{"name": "hip", "children": [2]}},
    {{"name": "knee", "matrix": [1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1, 0, 0, 1, 0, 1], "children": [3]}},
    {{"name": "foot", "translation": [0, 1, 0], "scale": [1, 1, 1]}},
    {{"name": "leg", "mesh": 0, "skin": 0}}],
  "meshes": [{{"name": "leg", "primitives": [{{"attributes": {{"POSITION": {positions},
      "JOINTS_0": {joints0}, "WEIGHTS_0": {weights0}, "JOINTS_1": {joints1}, "WEIGHTS_1": {weights1}}},
      "indices": {indices}, "mode": 4}}], "weights": [0]}}],
  "skins": [{{"joints": [1, 2, 3], "inverseBindMatrices": {ibm}, "skeleton": 1}}],
  "animations": [
    {{"name": "walk", "samplers": [
        {{"input": {times}, "output": {translations}}},
        {{"input": {times}, "output": {rotations}, "interpolation": "LINEAR"}},
        {{"input": {times}, "output": {spline}, "interpolation": "CUBICSPLINE"}},
        {{"input": {times}, "output": {scales}, "interpolation": "STEP"}},
        {{"input": {step_times}, "output": {morph}}},
        {{"input": {times}, "output": {sparse}}}],
      "channels": [
        {{"sampler": 0, "target": {{"node": 1, "path": "translation"}}}},
        {{"sampler": 1, "target": {{"node": 2, "path": "rotation"}}}},
        {{"sampler": 2, "target": {{"node": 3, "path": "rotation"}}}},
        {{"sampler": 3, "target": {{"node": 2, "path": "scale"}}}},
        {{"sampler": 4, "target": {{"node": 4, "path": "weights"}}}},
        {{"sampler": 5, "target": {{"node": 0, "path": "translation"}}}}]}},
    {{"name": "wave", "samplers": [{{"input": {times}, "output": {sparse}}}],
      "channels": [{{"sampler": 0, "target": {{"node": 3, "path": "translation"}}}}]}}],
  "buffers": [{buffer}],
  "bufferViews": [{views}],
  "accessors": [{accessors}]}}"#,
        views = b.views.join(", "),
        accessors = b.accessors.join(", "),
    );
    (json.into_bytes(), b.bin)
}
