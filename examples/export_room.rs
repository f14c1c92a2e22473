//! Writes a generated room as a plain glTF 2.0 binary (`.glb`): one mesh, one
//! node, `POSITION` as VEC3 FLOAT and `UNSIGNED_INT` indices, no material.
//! The compressed test files under `tests/compressed/` start from it (see
//! their README: the room goes through gltf-transform's Draco and meshopt
//! compressors), and `kind = "gltf"` scenarios read it back.
//!
//! `cargo run --example export_room -- museum room.glb` (or `living-room`).

use std::path::PathBuf;

use cornertree_workbench::environment::{living_room, museum};

fn main() -> Result<(), String> {
    let mut args = std::env::args().skip(1);
    let (Some(kind), Some(out)) = (args.next(), args.next()) else {
        return Err("usage: export_room museum|living-room OUT.glb".into());
    };
    let environment = match kind.as_str() {
        "museum" => museum(0),
        "living-room" => living_room(0),
        other => {
            return Err(format!(
                "unknown room {other:?}; rooms: museum, living-room"
            ));
        }
    };
    let out = PathBuf::from(out);
    let bytes = room_glb(
        environment.mesh.positions().iter().map(|p| [p.x, p.y, p.z]),
        environment.mesh.indices(),
    );
    std::fs::write(&out, bytes).map_err(|e| format!("{}: {e}", out.display()))?;
    println!(
        "{}: {} vertices, {} triangles",
        out.display(),
        environment.mesh.vertex_count(),
        environment.mesh.triangle_count()
    );
    Ok(())
}

/// A GLB holding one triangle mesh.
fn room_glb(positions: impl Iterator<Item = [f32; 3]>, triangles: &[[u32; 3]]) -> Vec<u8> {
    let positions: Vec<[f32; 3]> = positions.collect();
    let mut min = [f32::INFINITY; 3];
    let mut max = [f32::NEG_INFINITY; 3];
    let mut bin = Vec::new();
    for p in &positions {
        for k in 0..3 {
            min[k] = min[k].min(p[k]);
            max[k] = max[k].max(p[k]);
            bin.extend_from_slice(&p[k].to_le_bytes());
        }
    }
    let position_bytes = bin.len();
    for t in triangles {
        for i in t {
            bin.extend_from_slice(&i.to_le_bytes());
        }
    }
    let index_bytes = bin.len() - position_bytes;
    let json = format!(
        r#"{{"asset":{{"version":"2.0","generator":"cornertree export_room"}},"scene":0,"scenes":[{{"nodes":[0]}}],"nodes":[{{"mesh":0,"name":"room"}}],"meshes":[{{"primitives":[{{"attributes":{{"POSITION":0}},"indices":1}}]}}],"buffers":[{{"byteLength":{total}}}],"bufferViews":[{{"buffer":0,"byteOffset":0,"byteLength":{position_bytes},"target":34962}},{{"buffer":0,"byteOffset":{position_bytes},"byteLength":{index_bytes},"target":34963}}],"accessors":[{{"bufferView":0,"componentType":5126,"count":{vertices},"type":"VEC3","min":[{},{},{}],"max":[{},{},{}]}},{{"bufferView":1,"componentType":5125,"count":{indices},"type":"SCALAR"}}]}}"#,
        min[0],
        min[1],
        min[2],
        max[0],
        max[1],
        max[2],
        total = bin.len(),
        vertices = positions.len(),
        indices = triangles.len() * 3,
    );
    let mut json = json.into_bytes();
    while json.len() % 4 != 0 {
        json.push(b' ');
    }
    let length = 12 + 8 + json.len() + 8 + bin.len();
    let mut glb = Vec::with_capacity(length);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(length as u32).to_le_bytes());
    glb.extend_from_slice(&(json.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json);
    glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    glb
}
