//! Damaging a GLB file on purpose: numbers in its binary chunk overwritten
//! at the place the JSON chunk says an accessor's element lies, or a
//! compressed stream's bytes overwritten.

use serde_json::Value;

/// A GLB file's bytes and its parsed JSON chunk.
pub struct Glb {
    pub bytes: Vec<u8>,
    pub json: Value,
    /// Where the binary chunk's data starts in `bytes`.
    bin_start: usize,
}

impl Glb {
    pub fn parse(bytes: Vec<u8>) -> Self {
        let json_len = u32::from_le_bytes(bytes[12..16].try_into().unwrap()) as usize;
        let json = serde_json::from_slice(&bytes[20..20 + json_len]).expect("JSON chunk");
        Self {
            bytes,
            json,
            bin_start: 20 + json_len + 8,
        }
    }

    /// Accessor number `accessor` of the JSON.
    pub fn accessor(&self, accessor: usize) -> &Value {
        &self.json["accessors"][accessor]
    }

    /// The output accessor of animation `a`'s channel `c`.
    pub fn channel_output(&self, a: usize, c: usize) -> usize {
        let animation = &self.json["animations"][a];
        let sampler = animation["channels"][c]["sampler"].as_u64().unwrap() as usize;
        animation["samplers"][sampler]["output"].as_u64().unwrap() as usize
    }

    /// Writes `value` as component `component` of element `element` of a
    /// FLOAT accessor (no sparse storage).
    pub fn set_float(&mut self, accessor: usize, element: usize, component: usize, value: f32) {
        let a = self.accessor(accessor);
        assert_eq!(a["componentType"], 5126, "a FLOAT accessor");
        let components = match a["type"].as_str().unwrap() {
            "SCALAR" => 1,
            "VEC2" => 2,
            "VEC3" => 3,
            "VEC4" => 4,
            "MAT4" => 16,
            other => panic!("type {other}"),
        };
        let view = &self.json["bufferViews"][a["bufferView"].as_u64().unwrap() as usize];
        let stride = view["byteStride"].as_u64().unwrap_or(4 * components) as usize;
        let at = self.bin_start
            + view["byteOffset"].as_u64().unwrap_or(0) as usize
            + a["byteOffset"].as_u64().unwrap_or(0) as usize
            + element * stride
            + 4 * component;
        self.bytes[at..at + 4].copy_from_slice(&value.to_le_bytes());
    }

    /// Where buffer view `view`'s bytes lie in the binary chunk: the view's
    /// own range, or for a meshopt-compressed view its compressed stream's
    /// (`byteOffset`, `byteLength`).
    pub fn stream_range(&self, view: usize) -> (usize, usize) {
        let v = &self.json["bufferViews"][view];
        let v = v
            .get("extensions")
            .and_then(|e| e.get("EXT_meshopt_compression"))
            .unwrap_or(v);
        (
            v["byteOffset"].as_u64().unwrap_or(0) as usize,
            v["byteLength"].as_u64().unwrap() as usize,
        )
    }

    /// Sets `len` bytes of the binary chunk, from `at`, to `byte`.
    pub fn fill(&mut self, at: usize, len: usize, byte: u8) {
        let start = self.bin_start + at;
        self.bytes[start..start + len].fill(byte);
    }
}
