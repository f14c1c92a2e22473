//! `EXT_meshopt_compression`: buffer views whose bytes are stored compressed
//! by meshoptimizer's codecs, decoded with the `meshopt` crate (bindings to
//! meshoptimizer, the extension's reference decoder).
//!
//! A compressed view carries, in its extension object, where the compressed
//! bytes lie (`buffer`, `byteOffset`, `byteLength`), what they decode to
//! (`count` elements of `byteStride` bytes) and how (`mode`: `ATTRIBUTES`,
//! `TRIANGLES` or `INDICES`; `filter`: `NONE`, `OCTAHEDRAL`, `QUATERNION`,
//! `EXPONENTIAL`, `COLOR`). The decoded bytes stand for the view's own, so
//! every accessor on the view is read as if the file had stored them plainly;
//! the view's own buffer is then usually a *fallback* buffer (extension
//! `fallback: true`) with no bytes at all, which the loaders do not read.
//!
//! Everything the file says is checked before the C decoder sees it: the
//! source range lies in its buffer, the stride and count fit the mode and
//! filter (the decoders' own preconditions, which are assertions in C), the
//! decoded size equals the view's `byteLength`, and the decoded bytes are
//! charged to the load's budget before they are allocated. The decoders
//! themselves validate the compressed stream (meshoptimizer's decoders are
//! written for untrusted input); a stream they reject is an error naming the
//! view.

use gltf::buffer::Data;
use gltf::json::Value;

use super::limits::Budget;

/// The extension's name, as in `extensionsUsed` and on buffers and views.
pub(crate) const EXTENSION: &str = "EXT_meshopt_compression";

/// Whether a buffer is a meshopt fallback buffer (`fallback: true`): it only
/// reserves room for decoded views and may have no bytes.
pub(crate) fn is_fallback(buffer: &gltf::Buffer<'_>) -> bool {
    buffer
        .extension_value(EXTENSION)
        .and_then(|e| e.get("fallback"))
        .and_then(Value::as_bool)
        .unwrap_or(false)
}

/// How the compressed bytes are laid out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Mode {
    Attributes,
    Triangles,
    Indices,
}

/// What is applied to decoded attributes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Filter {
    None,
    Octahedral,
    Quaternion,
    Exponential,
    Color,
}

/// The view's extension object, parsed and checked.
struct Compressed {
    buffer: usize,
    offset: usize,
    length: usize,
    stride: usize,
    count: usize,
    mode: Mode,
    filter: Filter,
}

/// The decoded bytes of buffer view `view`, of `view_length` bytes, whose
/// extension object is `extension`. `data` are the loaded buffers (a
/// fallback buffer's are empty).
pub(crate) fn decode_view(
    view: usize,
    extension: &Value,
    view_length: usize,
    data: &[Data],
    budget: &Budget,
) -> Result<DecodedView, String> {
    let fail = |reason: String| format!("buffer view {view}: {EXTENSION}: {reason}");
    let c = parse(extension).map_err(fail)?;
    check(&c, view_length).map_err(fail)?;
    let source = data.get(c.buffer).ok_or_else(|| {
        fail(format!(
            "refers to buffer {}, which does not exist",
            c.buffer
        ))
    })?;
    let compressed = c
        .offset
        .checked_add(c.length)
        .and_then(|end| source.get(c.offset..end))
        .ok_or_else(|| {
            fail(format!(
                "compressed bytes (offset {}, length {}) extend past the end of buffer {} ({} bytes)",
                c.offset,
                c.length,
                c.buffer,
                source.len()
            ))
        })?;
    // check() proved count * stride == view.length(), which fits usize.
    budget
        .charge(
            "decoding a meshopt-compressed buffer view",
            c.count,
            c.stride,
        )
        .map_err(fail)?;
    let mut out = DecodedView::zeroed(c.count * c.stride);
    decode(&c, compressed, out.bytes_mut()).map_err(fail)?;
    Ok(out)
}

/// A decoded view's bytes, 8-byte aligned: the filters read and write
/// 16- and 32-bit components in place.
pub(crate) struct DecodedView {
    words: Vec<u64>,
    len: usize,
}

impl DecodedView {
    fn zeroed(len: usize) -> Self {
        Self {
            words: vec![0; len.div_ceil(8)],
            len,
        }
    }

    /// The decoded bytes.
    pub(crate) fn bytes(&self) -> &[u8] {
        // SAFETY: `words` holds at least `len` initialised bytes (8 per
        // word, len.div_ceil(8) words) and u8 has no alignment requirement.
        unsafe { std::slice::from_raw_parts(self.words.as_ptr().cast(), self.len) }
    }

    fn bytes_mut(&mut self) -> &mut [u8] {
        // SAFETY: as in bytes(), borrowed mutably through `self`.
        unsafe { std::slice::from_raw_parts_mut(self.words.as_mut_ptr().cast(), self.len) }
    }
}

fn parse(extension: &Value) -> Result<Compressed, String> {
    let whole = |key: &str, default: Option<usize>| -> Result<usize, String> {
        match extension.get(key) {
            None => default.ok_or_else(|| format!("{key} is missing")),
            Some(v) => v
                .as_u64()
                .and_then(|n| usize::try_from(n).ok())
                .ok_or_else(|| format!("{key} must be a whole number, not {}", short(v))),
        }
    };
    let word = |key: &str| {
        extension
            .get(key)
            .map(|v| {
                v.as_str()
                    .ok_or_else(|| format!("{key} must be a string, not {}", short(v)))
            })
            .transpose()
    };
    let mode = match word("mode")? {
        Some("ATTRIBUTES") => Mode::Attributes,
        Some("TRIANGLES") => Mode::Triangles,
        Some("INDICES") => Mode::Indices,
        Some(other) => {
            return Err(format!(
                "mode {other:?} is not one of ATTRIBUTES, TRIANGLES, INDICES"
            ));
        }
        None => return Err("mode is missing".into()),
    };
    let filter = match word("filter")? {
        None | Some("NONE") => Filter::None,
        Some("OCTAHEDRAL") => Filter::Octahedral,
        Some("QUATERNION") => Filter::Quaternion,
        Some("EXPONENTIAL") => Filter::Exponential,
        Some("COLOR") => Filter::Color,
        Some(other) => {
            return Err(format!(
                "filter {other:?} is not one of NONE, OCTAHEDRAL, QUATERNION, EXPONENTIAL, COLOR"
            ));
        }
    };
    Ok(Compressed {
        buffer: whole("buffer", None)?,
        offset: whole("byteOffset", Some(0))?,
        length: whole("byteLength", None)?,
        stride: whole("byteStride", None)?,
        count: whole("count", None)?,
        mode,
        filter,
    })
}

/// The decoders' preconditions, and the decoded size against the view's.
fn check(c: &Compressed, view_length: usize) -> Result<(), String> {
    match c.mode {
        Mode::Attributes => {
            if c.stride == 0 || !c.stride.is_multiple_of(4) || c.stride > 256 {
                return Err(format!(
                    "byteStride {} must be a multiple of 4 from 4 to 256 for ATTRIBUTES",
                    c.stride
                ));
            }
        }
        Mode::Triangles | Mode::Indices => {
            if c.stride != 2 && c.stride != 4 {
                return Err(format!(
                    "byteStride {} must be 2 or 4 for {:?}",
                    c.stride, c.mode
                ));
            }
            if c.mode == Mode::Triangles && !c.count.is_multiple_of(3) {
                return Err(format!(
                    "count {} is not a multiple of 3 (mode TRIANGLES)",
                    c.count
                ));
            }
            if c.filter != Filter::None {
                return Err(format!("filter {:?} applies only to ATTRIBUTES", c.filter));
            }
        }
    }
    let filter_fits = match c.filter {
        Filter::None => true,
        Filter::Octahedral | Filter::Color => c.stride == 4 || c.stride == 8,
        Filter::Quaternion => c.stride == 8,
        Filter::Exponential => c.stride.is_multiple_of(4),
    };
    if !filter_fits {
        return Err(format!(
            "filter {:?} cannot apply to byteStride {}",
            c.filter, c.stride
        ));
    }
    match c.count.checked_mul(c.stride) {
        Some(bytes) if bytes == view_length => Ok(()),
        Some(bytes) => Err(format!(
            "decodes to {} elements of {} bytes ({bytes} bytes) but the buffer view holds {view_length}",
            c.count, c.stride
        )),
        None => Err(format!(
            "{} elements of {} bytes overflow",
            c.count, c.stride
        )),
    }
}

/// Decodes `compressed` into `out` (`count × stride` bytes), then filters.
fn decode(c: &Compressed, compressed: &[u8], out: &mut [u8]) -> Result<(), String> {
    debug_assert_eq!(out.len(), c.count * c.stride);
    if c.count == 0 {
        return Ok(());
    }
    // SAFETY: `out` holds exactly count × stride bytes (checked by the caller
    // and asserted above), which is what each decoder writes; `compressed` is
    // a valid slice the decoders only read within its length; and check()
    // established each function's documented preconditions (stride a
    // multiple of 4 up to 256 for vertices, 2 or 4 for indices, a multiple
    // of 3 for triangles; the filters' strides), which are assertions in C.
    let code = unsafe {
        let dst = out.as_mut_ptr().cast();
        let (src, n) = (compressed.as_ptr(), compressed.len());
        match c.mode {
            Mode::Attributes => {
                meshopt::ffi::meshopt_decodeVertexBuffer(dst, c.count, c.stride, src, n)
            }
            Mode::Triangles => {
                meshopt::ffi::meshopt_decodeIndexBuffer(dst, c.count, c.stride, src, n)
            }
            Mode::Indices => {
                meshopt::ffi::meshopt_decodeIndexSequence(dst, c.count, c.stride, src, n)
            }
        }
    };
    if code != 0 {
        return Err(format!(
            "the {:?} stream is malformed (meshoptimizer's decoder returned {code})",
            c.mode
        ));
    }
    // SAFETY: `out` holds count elements of stride bytes, the stride each
    // filter requires was checked, and the filters work in place.
    unsafe {
        let buffer = out.as_mut_ptr().cast();
        match c.filter {
            Filter::None => {}
            Filter::Octahedral => meshopt::ffi::meshopt_decodeFilterOct(buffer, c.count, c.stride),
            Filter::Quaternion => meshopt::ffi::meshopt_decodeFilterQuat(buffer, c.count, c.stride),
            Filter::Exponential => meshopt::ffi::meshopt_decodeFilterExp(buffer, c.count, c.stride),
            Filter::Color => meshopt::ffi::meshopt_decodeFilterColor(buffer, c.count, c.stride),
        }
    }
    Ok(())
}

/// A JSON value cut to a few dozen characters, for messages.
fn short(v: &Value) -> String {
    let s = v.to_string();
    if s.len() > 40 {
        format!("{}…", &s[..s.floor_char_boundary(40)])
    } else {
        s
    }
}
