//! `KHR_draco_mesh_compression`: a primitive whose triangles and attributes
//! are one Draco stream, decoded with `draco-core` (a pure-Rust Draco
//! decoder).
//!
//! The primitive's extension object names the buffer view holding the stream
//! and, for each attribute (`POSITION`, `JOINTS_0`, …), its unique id in the
//! stream. The primitive's accessors keep their `count`, `type` and
//! `componentType` but have no data of their own: the decoded values are what
//! they describe. [`decode_primitive`] decodes the stream once, converts each
//! attribute the loaders read (`POSITION`, `JOINTS_n`, `WEIGHTS_n`) to its
//! accessor's component type, and stores it in the load's [`Buffers`] as that
//! accessor's bytes, so the accessor readers check and convert them like any
//! other; it returns the decoded triangles, which stand for the primitive's
//! indices. Normals and texture coordinates are not decoded into accessors
//! (the loaders do not read them).
//!
//! Limits: the decoder is told the load budget's remainder as its ceiling on
//! decoded bytes, points and faces (it refuses a stream that would decode
//! past them), and what it decoded is charged to the budget.

use draco_core::{DecodeLimits, DecoderBuffer, Mesh, MeshDecoder, PointAttribute};
use gltf::accessor::{DataType, Dimensions};
use gltf::json::Value;
use gltf::mesh::{Mode, Semantic};

use super::gltf_accessor::Buffers;

/// The extension's name, as in `extensionsUsed` and on primitives.
pub(crate) const EXTENSION: &str = "KHR_draco_mesh_compression";

/// Bytes a decoded face and point cost the decoder at most, beyond the
/// attribute values it counts itself (the face list, the corner table and
/// the point-to-value maps), for the limits it is given.
const BYTES_PER_FACE: u64 = 48;
const BYTES_PER_POINT: u64 = 16;

/// If `primitive` is Draco-compressed: decodes it, stores the decoded
/// `POSITION`, `JOINTS_n` and `WEIGHTS_n` as their accessors' data in
/// `buffers`, and returns the triangles as a flat index list (`Ok(None)` for
/// a primitive without the extension). Errors are one line, without the
/// file, mesh and primitive, which the caller adds.
pub(crate) fn decode_primitive(
    primitive: &gltf::Primitive<'_>,
    buffers: &Buffers,
) -> Result<Option<Vec<u32>>, String> {
    let Some(extension) = primitive.extension_value(EXTENSION) else {
        return Ok(None);
    };
    let fail = |reason: String| format!("{EXTENSION}: {reason}");
    if primitive.mode() != Mode::Triangles {
        return Err(fail(format!(
            "mode {:?} is not supported with Draco (only TRIANGLES)",
            primitive.mode()
        )));
    }
    let view = extension
        .get("bufferView")
        .and_then(Value::as_u64)
        .and_then(|v| usize::try_from(v).ok())
        .ok_or_else(|| fail("bufferView is missing or not a whole number".into()))?;
    let ids = extension
        .get("attributes")
        .and_then(Value::as_object)
        .ok_or_else(|| fail("attributes is missing or not an object".into()))?;
    let stream = buffers.view_bytes_at(view).map_err(&fail)?;

    let room = buffers.budget.remaining() as u64;
    let limits = DecodeLimits::default()
        .with_max_decoded_bytes(room)
        .with_max_faces(room / BYTES_PER_FACE)
        .with_max_points(room / BYTES_PER_POINT);
    let mut input = DecoderBuffer::new(stream).with_limits(limits);
    let mut mesh = Mesh::new();
    MeshDecoder::new()
        .decode(&mut input, &mut mesh)
        .map_err(|e| {
            fail(format!(
                "buffer view {view}: the Draco stream cannot be decoded: {e}"
            ))
        })?;
    let (points, faces) = (mesh.num_points(), mesh.num_faces());
    buffers
        .budget
        .charge("the decoded Draco faces", faces, BYTES_PER_FACE as usize)
        .and_then(|()| {
            buffers
                .budget
                .charge("the decoded Draco points", points, BYTES_PER_POINT as usize)
        })
        .map_err(&fail)?;

    for (semantic, accessor) in primitive.attributes() {
        let name = match semantic {
            Semantic::Positions => "POSITION".to_owned(),
            Semantic::Joints(n) => format!("JOINTS_{n}"),
            Semantic::Weights(n) => format!("WEIGHTS_{n}"),
            _ => continue,
        };
        let Some(id) = ids.get(&name) else {
            if accessor.view().is_none() && accessor.sparse().is_none() {
                return Err(fail(format!(
                    "{name} (accessor {}) is neither in the Draco stream nor stored",
                    accessor.index()
                )));
            }
            continue;
        };
        let attribute = id
            .as_u64()
            .and_then(|id| u32::try_from(id).ok())
            .and_then(|id| mesh.attribute_by_unique_id(id))
            .ok_or_else(|| {
                fail(format!(
                    "{name}: attribute id {id} is not in the Draco stream"
                ))
            })?;
        let bytes = accessor_bytes(attribute, points, &accessor)
            .map_err(|reason| fail(format!("{name} (accessor {}): {reason}", accessor.index())))?;
        buffers
            .budget
            .charge("the decoded Draco attribute", bytes.len(), 1)
            .map_err(&fail)?;
        buffers.set_decoded_accessor(accessor.index(), bytes);
    }

    buffers
        .budget
        .charge("the decoded Draco indices", faces, 12)
        .map_err(&fail)?;
    let mut indices = Vec::with_capacity(faces * 3);
    for face in mesh.faces() {
        indices.extend(face.iter().map(|p| p.0));
    }
    Ok(Some(indices))
}

/// The decoded `attribute`, converted to `accessor`'s component type and
/// packed tightly: what the accessor would hold had the file stored it.
fn accessor_bytes(
    attribute: &PointAttribute,
    points: usize,
    accessor: &gltf::Accessor<'_>,
) -> Result<Vec<u8>, String> {
    if accessor.count() != points {
        return Err(format!(
            "the accessor declares {} elements but the Draco stream decodes {points} points",
            accessor.count()
        ));
    }
    let components = match accessor.dimensions() {
        Dimensions::Scalar => 1,
        Dimensions::Vec2 => 2,
        Dimensions::Vec3 => 3,
        Dimensions::Vec4 => 4,
        other => return Err(format!("type {other:?} cannot come from a Draco stream")),
    };
    if usize::from(attribute.num_components()) != components {
        return Err(format!(
            "the Draco attribute has {} components, the accessor {components}",
            attribute.num_components()
        ));
    }
    // Every stored type widened to f32, exactly for the integer types glTF
    // attributes use (at most 16 bits); not normalised.
    let values = attribute.read_f32s(points, components);
    let scale = normalising_scale(attribute);
    let mut out = Vec::with_capacity(values.len() * accessor.data_type().size());
    for (k, &raw) in values.iter().enumerate() {
        let integer = |max: f32, min: f32| -> Result<f32, String> {
            if raw.fract() == 0.0 && (min..=max).contains(&raw) {
                Ok(raw)
            } else {
                Err(format!(
                    "point {}, component {}: {raw} does not fit the accessor's {:?}",
                    k / components,
                    k % components,
                    accessor.data_type()
                ))
            }
        };
        match accessor.data_type() {
            DataType::F32 => {
                let value = match scale {
                    Some(s) => (raw / s).max(-1.0),
                    None => raw,
                };
                out.extend_from_slice(&value.to_le_bytes());
            }
            DataType::U8 => out.push(integer(255.0, 0.0)? as u8),
            DataType::I8 => out.push(integer(127.0, -128.0)? as i8 as u8),
            DataType::U16 => out.extend_from_slice(&(integer(65535.0, 0.0)? as u16).to_le_bytes()),
            DataType::I16 => {
                out.extend_from_slice(&(integer(32767.0, -32768.0)? as i16).to_le_bytes());
            }
            DataType::U32 => {
                out.extend_from_slice(&(integer(16_777_216.0, 0.0)? as u32).to_le_bytes());
            }
        }
    }
    Ok(out)
}

/// For a normalised integer attribute, the divisor that maps it to floats
/// (the glTF rules: `c / max`, signed values clamped at -1); `None` otherwise.
fn normalising_scale(attribute: &PointAttribute) -> Option<f32> {
    use draco_core::DataType as D;
    if !attribute.normalized() {
        return None;
    }
    match attribute.data_type() {
        D::Uint8 => Some(255.0),
        D::Int8 => Some(127.0),
        D::Uint16 => Some(65535.0),
        D::Int16 => Some(32767.0),
        _ => None,
    }
}
