//! Bounds-checked reading of glTF accessors: `POSITION` (VEC3 FLOAT, or with
//! `KHR_mesh_quantization` VEC3 of (normalized) BYTE, UNSIGNED_BYTE, SHORT or
//! UNSIGNED_SHORT), indices
//! (SCALAR unsigned byte/short/int), and for skinned characters `JOINTS_n`,
//! `WEIGHTS_n`, inverse bind matrices and animation keyframes, each in every
//! component format core glTF 2.0 allows; dense or sparse.
//!
//! Every offset, stride and count comes from the file, so all arithmetic is
//! checked and every range is verified before it is read, and what is decoded
//! is charged to the load's [`Budget`] before it is allocated; a bad accessor
//! is an `Err` with a one-line reason, never a panic. Floats must be finite
//! (NaN and infinities are refused with the element and component), except
//! positions, whose caller reports them by vertex.
//!
//! Compressed data reads through the same functions: a buffer view with
//! `EXT_meshopt_compression` is decoded the first time an accessor reads it
//! ([`gltf_meshopt`](super::gltf_meshopt)), and an accessor of a
//! Draco-compressed primitive reads the values its primitive's stream decoded
//! ([`gltf_draco`](super::gltf_draco)).

use std::cell::OnceCell;

use gltf::accessor::{Accessor, DataType, Dimensions};
use gltf::buffer::Data;
use gltf::json::Value;

use super::gltf_meshopt::{self, DecodedView};
use super::limits::Budget;

/// The loaded buffers of a file and the budget its decoding is charged to,
/// with what was decoded from compressed views and primitives.
pub(crate) struct Buffers {
    pub data: Vec<Data>,
    pub budget: Budget,
    views: Vec<ViewEntry>,
    decoded_accessors: Vec<OnceCell<Vec<u8>>>,
}

/// A buffer view: where its bytes lie, and, for a meshopt-compressed one, its
/// extension object and (once read) its decoded bytes or why they cannot be had.
struct ViewEntry {
    buffer: usize,
    offset: usize,
    length: usize,
    meshopt: Option<Value>,
    decoded: OnceCell<Result<DecodedView, String>>,
}

impl Buffers {
    /// The buffers' bytes `data` of `document`, charged to `budget`.
    pub(crate) fn new(data: Vec<Data>, budget: Budget, document: &gltf::Document) -> Self {
        let views = document
            .views()
            .map(|view| ViewEntry {
                buffer: view.buffer().index(),
                offset: view.offset(),
                length: view.length(),
                meshopt: view.extension_value(gltf_meshopt::EXTENSION).cloned(),
                decoded: OnceCell::new(),
            })
            .collect();
        let decoded_accessors = (0..document.accessors().len())
            .map(|_| OnceCell::new())
            .collect();
        Self {
            data,
            budget,
            views,
            decoded_accessors,
        }
    }

    /// The bytes of buffer view `index`: decoded if it is meshopt-compressed,
    /// else checked against its loaded buffer.
    pub(crate) fn view_bytes_at(&self, index: usize) -> Result<&[u8], String> {
        let view = self
            .views
            .get(index)
            .ok_or_else(|| format!("buffer view {index} does not exist"))?;
        if let Some(extension) = &view.meshopt {
            return view
                .decoded
                .get_or_init(|| {
                    gltf_meshopt::decode_view(
                        index,
                        extension,
                        view.length,
                        &self.data,
                        &self.budget,
                    )
                })
                .as_ref()
                .map(DecodedView::bytes)
                .map_err(Clone::clone);
        }
        let buffer = view.buffer;
        let data = self.data.get(buffer).ok_or_else(|| {
            format!("buffer view {index} refers to buffer {buffer}, which was not loaded")
        })?;
        let (start, length) = (view.offset, view.length);
        start
            .checked_add(length)
            .and_then(|end| data.get(start..end))
            .ok_or_else(|| {
                format!(
                    "buffer view {index} (offset {start}, length {length}) extends past the end of buffer {buffer} ({} bytes)",
                    data.len()
                )
            })
    }

    /// Sets what accessor `index` holds (decoded from its primitive's Draco
    /// stream). An accessor two compressed primitives share keeps the first.
    pub(crate) fn set_decoded_accessor(&self, index: usize, bytes: Vec<u8>) {
        if let Some(cell) = self.decoded_accessors.get(index) {
            let _ = cell.set(bytes);
        }
    }

    fn decoded_accessor(&self, index: usize) -> Option<&[u8]> {
        self.decoded_accessors
            .get(index)
            .and_then(OnceCell::get)
            .map(Vec::as_slice)
    }
}

/// Most elements an accessor without a buffer view (all zeros, perhaps with
/// sparse overrides) may declare: nothing bounds its count by real data, so a
/// hostile count could otherwise request an absurd allocation.
const MAX_ELEMENTS_WITHOUT_VIEW: usize = 1 << 24;

/// The positions of a `POSITION` accessor: VEC3 FLOAT (core glTF 2.0), or
/// with `KHR_mesh_quantization` VEC3 of BYTE, UNSIGNED_BYTE, SHORT or
/// UNSIGNED_SHORT, normalized (converted as the spec says) or not (the
/// integer as a float; the node's transform usually scales it back).
pub(crate) fn read_positions(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
) -> Result<Vec<[f32; 3]>, String> {
    let integer = matches!(
        accessor.data_type(),
        DataType::I8 | DataType::U8 | DataType::I16 | DataType::U16
    );
    if accessor.dimensions() != Dimensions::Vec3
        || !(accessor.data_type() == DataType::F32 && !accessor.normalized() || integer)
    {
        return Err(format!(
            "POSITION must be VEC3 FLOAT, or (KHR_mesh_quantization) VEC3 BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT, normalized or not; found {}",
            describe(accessor)
        ));
    }
    if accessor.data_type() == DataType::F32 {
        read_floats::<3>(accessor, buffers)
    } else {
        read_small_integers::<3>(accessor, buffers, accessor.normalized())
    }
}

/// A VEC3 FLOAT accessor (`what` names it in errors): positions, and
/// translation/scale keyframes, which core glTF 2.0 requires to be FLOAT.
pub(crate) fn read_vec3_f32(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
    what: &str,
) -> Result<Vec<[f32; 3]>, String> {
    expect_float(accessor, Dimensions::Vec3, what, "VEC3 FLOAT")?;
    finite(what, read_floats::<3>(accessor, buffers)?)
}

/// A SCALAR FLOAT accessor: keyframe times.
pub(crate) fn read_scalars_f32(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
    what: &str,
) -> Result<Vec<f32>, String> {
    expect_float(accessor, Dimensions::Scalar, what, "SCALAR FLOAT")?;
    Ok(finite(what, read_floats::<1>(accessor, buffers)?)?
        .into_iter()
        .map(|[x]| x)
        .collect())
}

/// A MAT4 FLOAT accessor (inverse bind matrices), each matrix column-major as stored.
pub(crate) fn read_mat4_f32(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
    what: &str,
) -> Result<Vec<[f32; 16]>, String> {
    expect_float(accessor, Dimensions::Mat4, what, "MAT4 FLOAT")?;
    finite(what, read_floats::<16>(accessor, buffers)?)
}

/// `JOINTS_n`: VEC4 UNSIGNED_BYTE or UNSIGNED_SHORT, not normalized.
pub(crate) fn read_joints(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
    what: &str,
) -> Result<Vec<[u16; 4]>, String> {
    if accessor.dimensions() != Dimensions::Vec4 || accessor.normalized() {
        return Err(format!(
            "{what} must be VEC4 UNSIGNED_BYTE or UNSIGNED_SHORT, not normalized; found {}",
            describe(accessor)
        ));
    }
    match accessor.data_type() {
        DataType::U8 => read_elements(accessor, 4, buffers, [0; 4], |b| {
            [b[0], b[1], b[2], b[3]].map(u16::from)
        }),
        DataType::U16 => read_elements(accessor, 8, buffers, [0; 4], |b| {
            std::array::from_fn(|k| u16::from_le_bytes([b[2 * k], b[2 * k + 1]]))
        }),
        _ => Err(format!(
            "{what} must be VEC4 UNSIGNED_BYTE or UNSIGNED_SHORT; found {}",
            describe(accessor)
        )),
    }
}

/// `WEIGHTS_n`: VEC4 FLOAT, normalized UNSIGNED_BYTE or normalized
/// UNSIGNED_SHORT, converted to floats as the spec says (`c / 255`, `c / 65535`).
pub(crate) fn read_weights(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
    what: &str,
) -> Result<Vec<[f32; 4]>, String> {
    read_unit_vec4(
        accessor,
        buffers,
        what,
        "VEC4 FLOAT, normalized UNSIGNED_BYTE or normalized UNSIGNED_SHORT",
        &[DataType::U8, DataType::U16],
    )
}

/// Rotation keyframes: VEC4 FLOAT or normalized BYTE, UNSIGNED_BYTE, SHORT,
/// UNSIGNED_SHORT, converted as the spec says; `[x, y, z, w]` as stored.
pub(crate) fn read_rotations(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
    what: &str,
) -> Result<Vec<[f32; 4]>, String> {
    read_unit_vec4(
        accessor,
        buffers,
        what,
        "VEC4 FLOAT or normalized BYTE, UNSIGNED_BYTE, SHORT or UNSIGNED_SHORT",
        &[DataType::I8, DataType::U8, DataType::I16, DataType::U16],
    )
}

/// VEC4 of FLOAT, or of one of the `normalized` integer types, as floats;
/// anything else is an error naming `what` and the `allowed` forms.
fn read_unit_vec4(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
    what: &str,
    allowed: &str,
    normalized: &[DataType],
) -> Result<Vec<[f32; 4]>, String> {
    let fits = accessor.dimensions() == Dimensions::Vec4
        && match (accessor.data_type(), accessor.normalized()) {
            (DataType::F32, false) => true,
            (t, true) => normalized.contains(&t),
            _ => false,
        };
    if !fits {
        return Err(format!(
            "{what} must be {allowed}; found {}",
            describe(accessor)
        ));
    }
    if accessor.data_type() == DataType::F32 {
        finite(what, read_floats::<4>(accessor, buffers)?)
    } else {
        read_small_integers::<4>(accessor, buffers, true)
    }
}

/// "VEC4 U16 normalized", for error messages.
fn describe(accessor: &Accessor<'_>) -> String {
    format!(
        "{:?} {:?}{}",
        accessor.dimensions(),
        accessor.data_type(),
        if accessor.normalized() {
            " normalized"
        } else {
            ""
        }
    )
}

fn expect_float(
    accessor: &Accessor<'_>,
    dimensions: Dimensions,
    what: &str,
    expected: &str,
) -> Result<(), String> {
    if accessor.dimensions() != dimensions
        || accessor.data_type() != DataType::F32
        || accessor.normalized()
    {
        return Err(format!(
            "{what} must be {expected}, found {}",
            describe(accessor)
        ));
    }
    Ok(())
}

/// `values` if every number is finite, else which element and component is not.
fn finite<const N: usize>(what: &str, values: Vec<[f32; N]>) -> Result<Vec<[f32; N]>, String> {
    for (i, v) in values.iter().enumerate() {
        if let Some((c, x)) = v.iter().enumerate().find(|(_, x)| !x.is_finite()) {
            let component = if N == 1 {
                String::new()
            } else {
                format!(", component {c}")
            };
            return Err(format!(
                "{what} element {i}{component} is {x}; only finite numbers are accepted"
            ));
        }
    }
    Ok(values)
}

/// `N` little-endian floats per element (the caller checked the type).
fn read_floats<const N: usize>(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
) -> Result<Vec<[f32; N]>, String> {
    read_elements(accessor, 4 * N, buffers, [0.0; N], |b| {
        std::array::from_fn(|k| le_f32(&b[4 * k..4 * k + 4]))
    })
}

/// A component's value read from its little-endian bytes.
type ComponentValue = fn(&[u8]) -> f32;

/// `N` 8- or 16-bit integers per element as floats: `normalized`, with the
/// spec's rules (unsigned `c / max`, signed `max(c / max, -1)`); else the
/// integer itself, exactly.
fn read_small_integers<const N: usize>(
    accessor: &Accessor<'_>,
    buffers: &Buffers,
    normalized: bool,
) -> Result<Vec<[f32; N]>, String> {
    // Bytes per component, the type's largest value, a component's value.
    let (size, max, value): (usize, f32, ComponentValue) = match accessor.data_type() {
        DataType::U8 => (1, 255.0, |b| f32::from(b[0])),
        DataType::I8 => (1, 127.0, |b| f32::from(b[0] as i8)),
        DataType::U16 => (2, 65535.0, |b| f32::from(u16::from_le_bytes([b[0], b[1]]))),
        DataType::I16 => (2, 32767.0, |b| f32::from(i16::from_le_bytes([b[0], b[1]]))),
        other => return Err(format!("{other:?} is not an 8- or 16-bit integer type")),
    };
    read_elements(accessor, size * N, buffers, [0.0; N], |b| {
        std::array::from_fn(|k| {
            let c = value(&b[size * k..]);
            if normalized { (c / max).max(-1.0) } else { c }
        })
    })
}

/// The values of an index accessor, widened to `u32`.
pub(crate) fn read_indices(accessor: &Accessor<'_>, buffers: &Buffers) -> Result<Vec<u32>, String> {
    if accessor.dimensions() != Dimensions::Scalar {
        return Err(format!(
            "indices must be SCALAR, found {:?}",
            accessor.dimensions()
        ));
    }
    match accessor.data_type() {
        DataType::U8 => read_elements(accessor, 1, buffers, 0, |b| u32::from(b[0])),
        DataType::U16 => read_elements(accessor, 2, buffers, 0, |b| {
            u32::from(u16::from_le_bytes([b[0], b[1]]))
        }),
        DataType::U32 => read_elements(accessor, 4, buffers, 0, |b| {
            u32::from_le_bytes([b[0], b[1], b[2], b[3]])
        }),
        other => Err(format!(
            "indices must be UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT, found {other:?}"
        )),
    }
}

/// Charges `count` decoded elements of type `T` to the load's budget.
fn charge<T>(buffers: &Buffers, count: usize) -> Result<(), String> {
    buffers
        .budget
        .charge("decoding the accessor", count, std::mem::size_of::<T>())
}

fn le_f32(b: &[u8]) -> f32 {
    f32::from_le_bytes([b[0], b[1], b[2], b[3]])
}

/// Reads `accessor.count()` elements of `size` bytes each (base data, else
/// zeros), then applies its sparse substitutions, if any.
fn read_elements<T: Copy>(
    accessor: &Accessor<'_>,
    size: usize,
    buffers: &Buffers,
    zero: T,
    decode: impl Fn(&[u8]) -> T,
) -> Result<Vec<T>, String> {
    let count = accessor.count();
    let mut out = if let Some(decoded) = buffers.decoded_accessor(accessor.index()) {
        let elements = Strided::new(decoded, 0, None, size, count)
            .map_err(|e| format!("its values decoded from Draco: {e}"))?;
        charge::<T>(buffers, count)?;
        (0..count).map(|i| decode(elements.get(i))).collect()
    } else {
        match accessor.view() {
            Some(view) => {
                let elements = Strided::new(
                    buffers.view_bytes_at(view.index())?,
                    accessor.offset(),
                    view.stride(),
                    size,
                    count,
                )
                .map_err(|e| format!("buffer view {}: {e}", view.index()))?;
                charge::<T>(buffers, count)?;
                (0..count).map(|i| decode(elements.get(i))).collect()
            }
            None if accessor.sparse().is_none() => {
                return Err(
                    "has no buffer view, no sparse values and was not decoded from a Draco stream"
                        .into(),
                );
            }
            None if count <= MAX_ELEMENTS_WITHOUT_VIEW => {
                charge::<T>(buffers, count)?;
                vec![zero; count]
            }
            None => {
                return Err(format!(
                    "has no buffer view but declares {count} elements (at most {MAX_ELEMENTS_WITHOUT_VIEW} are accepted)"
                ));
            }
        }
    };
    if let Some(sparse) = accessor.sparse() {
        let n = sparse.count();
        let indices = sparse.indices();
        let index_size = indices.index_type().size();
        let index_view = indices.view();
        let index_elements = Strided::new(
            buffers.view_bytes_at(index_view.index())?,
            indices.offset(),
            None,
            index_size,
            n,
        )
        .map_err(|e| format!("sparse indices (buffer view {}): {e}", index_view.index()))?;
        let values = sparse.values();
        let value_view = values.view();
        let value_elements = Strided::new(
            buffers.view_bytes_at(value_view.index())?,
            values.offset(),
            None,
            size,
            n,
        )
        .map_err(|e| format!("sparse values (buffer view {}): {e}", value_view.index()))?;
        for k in 0..n {
            let b = index_elements.get(k);
            let i = match index_size {
                1 => usize::from(b[0]),
                2 => usize::from(u16::from_le_bytes([b[0], b[1]])),
                _ => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize,
            };
            let slot = out.get_mut(i).ok_or_else(|| {
                format!("sparse index {i} (entry {k}) is out of range; the accessor has {count} elements")
            })?;
            *slot = decode(value_elements.get(k));
        }
    }
    Ok(out)
}

/// `count` elements of `size` bytes, `stride` bytes apart from `offset`, all
/// verified to lie inside `bytes` at construction.
struct Strided<'b> {
    bytes: &'b [u8],
    offset: usize,
    stride: usize,
    size: usize,
}

impl<'b> Strided<'b> {
    fn new(
        bytes: &'b [u8],
        offset: usize,
        stride: Option<usize>,
        size: usize,
        count: usize,
    ) -> Result<Self, String> {
        let stride = stride.unwrap_or(size);
        if stride < size {
            return Err(format!(
                "byteStride {stride} is smaller than the element size {size}"
            ));
        }
        if count > 0 {
            let needed = (count - 1)
                .checked_mul(stride)
                .and_then(|n| n.checked_add(size))
                .and_then(|n| n.checked_add(offset));
            match needed {
                Some(needed) if needed <= bytes.len() => {}
                _ => {
                    return Err(format!(
                        "{count} elements of {size} bytes (stride {stride}, offset {offset}) do not fit in its {} bytes",
                        bytes.len()
                    ));
                }
            }
        }
        Ok(Self {
            bytes,
            offset,
            stride,
            size,
        })
    }

    /// Element `i`; `i` must be below the `count` given to [`Strided::new`],
    /// which proved `offset + i * stride + size <= bytes.len()`.
    fn get(&self, i: usize) -> &'b [u8] {
        let start = self.offset + i * self.stride;
        &self.bytes[start..start + self.size]
    }
}
