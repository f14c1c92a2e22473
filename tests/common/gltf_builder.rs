//! Small glTF files written in memory: accessors in one data-URI buffer.

use super::base64;

/// Accessors in one data-URI buffer, one buffer view each.
#[derive(Default)]
pub struct Builder {
    buffer: Vec<u8>,
    views: Vec<String>,
    accessors: Vec<String>,
}

impl Builder {
    pub fn add(
        &mut self,
        bytes: &[u8],
        component: u32,
        count: usize,
        ty: &str,
        normalized: bool,
    ) -> usize {
        while !self.buffer.len().is_multiple_of(4) {
            self.buffer.push(0);
        }
        self.views.push(format!(
            r#"{{"buffer": 0, "byteOffset": {}, "byteLength": {}}}"#,
            self.buffer.len(),
            bytes.len()
        ));
        self.buffer.extend_from_slice(bytes);
        self.accessors.push(format!(
            r#"{{"bufferView": {}, "componentType": {component}, "count": {count}, "type": "{ty}", "normalized": {normalized}}}"#,
            self.views.len() - 1
        ));
        self.accessors.len() - 1
    }

    pub fn f32s(&mut self, values: &[f32], ty: &str, per: usize) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.add(&bytes, 5126, values.len() / per, ty, false)
    }

    pub fn u8s(&mut self, values: &[u8], ty: &str, per: usize, normalized: bool) -> usize {
        self.add(values, 5121, values.len() / per, ty, normalized)
    }

    pub fn u16s(&mut self, values: &[u16], ty: &str, per: usize, normalized: bool) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.add(&bytes, 5123, values.len() / per, ty, normalized)
    }

    pub fn i16s(&mut self, values: &[i16], ty: &str, per: usize, normalized: bool) -> usize {
        let bytes: Vec<u8> = values.iter().flat_map(|v| v.to_le_bytes()).collect();
        self.add(&bytes, 5122, values.len() / per, ty, normalized)
    }

    /// The whole file: `body` holds scene, nodes, meshes, skins, animations.
    pub fn finish(&self, body: &str) -> String {
        format!(
            r#"{{"asset": {{"version": "2.0"}}, {body},
  "buffers": [{{"byteLength": {}, "uri": "data:application/octet-stream;base64,{}"}}],
  "bufferViews": [{}],
  "accessors": [{}]}}"#,
            self.buffer.len(),
            base64(&self.buffer),
            self.views.join(", "),
            self.accessors.join(", ")
        )
    }
}
