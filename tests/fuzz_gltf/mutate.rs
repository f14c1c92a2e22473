//! Mutations and their proptest strategies: edits of the JSON text (a value
//! after a chosen key, any number, a key dropped), of the binary buffer
//! (special floats and integers aimed at one buffer view, byte runs), and of
//! the packed file (bit flips, bytes set, cuts, truncation, GLB header and
//! chunk header fields).

use proptest::prelude::*;
use proptest::sample::Index;

use super::seeds::{BIN_NAME, Kind, Seed, pack_glb};

/// Keys whose values the JSON edits aim at.
const KEYS: &[&str] = &[
    "byteOffset",
    "byteLength",
    "byteStride",
    "count",
    "componentType",
    "bufferView",
    "buffer",
    "type",
    "normalized",
    "input",
    "output",
    "sampler",
    "interpolation",
    "node",
    "path",
    "mesh",
    "skin",
    "inverseBindMatrices",
    "joints",
    "skeleton",
    "indices",
    "POSITION",
    "JOINTS_0",
    "WEIGHTS_0",
    "JOINTS_1",
    "WEIGHTS_1",
    "mode",
    "scene",
    "nodes",
    "children",
    "translation",
    "rotation",
    "scale",
    "matrix",
    "sparse",
    "values",
    "uri",
    "version",
    "weights",
    "min",
    "max",
    "extensionsRequired",
    "samplers",
    "channels",
    "target",
    "primitives",
    "attributes",
    // The compression extensions' own members.
    "filter",
    "fallback",
    "KHR_draco_mesh_compression",
    "EXT_meshopt_compression",
];

/// Replacement numbers: boundaries, component types, absurd sizes, values
/// past `f32` and `u32`.
const NUMBERS: &[&str] = &[
    "0",
    "1",
    "-1",
    "2",
    "3",
    "4",
    "5",
    "7",
    "12",
    "16",
    "255",
    "256",
    "5120",
    "5121",
    "5122",
    "5123",
    "5125",
    "5126",
    "65535",
    "65536",
    "2147483647",
    "2147483648",
    "4294967295",
    "4294967296",
    "18446744073709551615",
    "1e300",
    "-1e300",
    "1e-300",
    "0.5",
    "-0.0",
    "1e38",
    "3.5e38",
    "1e30",
    "1e9",
    "1e-45",
];

/// Replacement strings: the spec's enumerations, and a few that are wrong.
const STRINGS: &[&str] = &[
    "\"SCALAR\"",
    "\"VEC2\"",
    "\"VEC3\"",
    "\"VEC4\"",
    "\"MAT2\"",
    "\"MAT4\"",
    "\"STEP\"",
    "\"LINEAR\"",
    "\"CUBICSPLINE\"",
    "\"translation\"",
    "\"rotation\"",
    "\"scale\"",
    "\"weights\"",
    "\"\"",
    "\"missing.bin\"",
    "\"data:,\"",
    "\"3.0\"",
    "\"2.1\"",
    "\"ATTRIBUTES\"",
    "\"TRIANGLES\"",
    "\"INDICES\"",
    "\"NONE\"",
    "\"OCTAHEDRAL\"",
    "\"QUATERNION\"",
    "\"EXPONENTIAL\"",
    "\"COLOR\"",
];

/// Replacements of the wrong type, and non-finite spellings JSON does not allow.
const OTHERS: &[&str] = &[
    "NaN",
    "\"NaN\"",
    "Infinity",
    "-Infinity",
    "null",
    "true",
    "[]",
    "{}",
    "[0]",
    "[1e30, 1e30, 1e30]",
    "[0, 0, 0, 0]",
    "[1e38, 0, 0, 1]",
    "[\"KHR_draco_mesh_compression\"]",
    "[\"EXT_meshopt_compression\", \"KHR_mesh_quantization\"]",
    "[\"EXT_unknown_compression\"]",
    "[0, 0, 0]",
    "[1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15, 16]",
];

/// Special floats written into the binary buffer.
const FLOATS: &[f32] = &[
    f32::NAN,
    f32::INFINITY,
    f32::NEG_INFINITY,
    1e30,
    -1e30,
    1e10,
    1e9,
    f32::MAX,
    f32::MIN,
    1e-40,
    0.0,
    -0.0,
    1.0,
    -1.0,
    0.5,
    1e-30,
    65535.0,
];

/// Special 32-bit words written into the binary buffer.
const WORDS: &[u32] = &[
    0,
    1,
    2,
    0xff,
    0x100,
    0xffff,
    0x1_0000,
    0x7fff_ffff,
    0x8000_0000,
    u32::MAX,
];

#[derive(Clone, Debug)]
pub enum Value {
    /// One of [`NUMBERS`].
    Number(usize),
    /// One of [`STRINGS`].
    String(usize),
    /// One of [`OTHERS`].
    Other(usize),
    /// The number there, plus this.
    Plus(i64),
    /// The number there, times this.
    Times(i64),
}

#[derive(Clone, Debug)]
pub enum Mutation {
    /// The value after the `nth` occurrence of `"KEYS[key]":`; inside an
    /// array value, with `element`, only that element.
    KeyValue {
        key: usize,
        nth: Index,
        element: Option<Index>,
        value: Value,
    },
    /// The `nth` number of the JSON text.
    Number { nth: Index, value: Value },
    /// The `nth` occurrence of a key renamed, so its member is ignored.
    DropKey { key: usize, nth: Index },
    /// A special float at a 4-aligned offset inside buffer view `view`.
    Float {
        view: Index,
        at: Index,
        value: usize,
    },
    /// A special word at a 4-aligned offset inside buffer view `view`.
    Word {
        view: Index,
        at: Index,
        value: usize,
    },
    /// `len` bytes of the binary buffer set to `byte`.
    BinRun { at: Index, len: usize, byte: u8 },
    /// One bit of the packed file flipped.
    Flip { at: Index, bit: u8 },
    /// One byte of the packed file set.
    SetByte { at: Index, byte: u8 },
    /// `len` bytes cut out of the packed file.
    Cut { at: Index, len: usize },
    /// The packed file truncated.
    Truncate { at: Index },
    /// A GLB header field: 0 magic, 1 version, 2 length, 3 JSON chunk
    /// length, 4 JSON chunk type, 5 BIN chunk length, 6 BIN chunk type.
    Header { field: usize, value: HeaderValue },
}

#[derive(Clone, Debug)]
pub enum HeaderValue {
    Word(u32),
    /// The field's value plus this.
    Plus(i32),
    Tag(&'static [u8; 4]),
}

/// An input: a seed and the mutations applied to it.
#[derive(Clone, Debug)]
pub struct Input {
    pub seed: usize,
    pub mutations: Vec<Mutation>,
    /// Animate with the paper's skinning model instead of linear blending.
    pub paper: bool,
}

fn value() -> impl Strategy<Value = Value> {
    prop_oneof![
        6 => (0..NUMBERS.len()).prop_map(Value::Number),
        2 => (0..STRINGS.len()).prop_map(Value::String),
        1 => (0..OTHERS.len()).prop_map(Value::Other),
        2 => prop_oneof![Just(1i64), Just(-1), Just(4), Just(-4), Just(1 << 20)].prop_map(Value::Plus),
        1 => prop_oneof![Just(2i64), Just(-1), Just(1000), Just(0)].prop_map(Value::Times),
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    let header_value = prop_oneof![
        prop_oneof![
            Just(0u32),
            Just(1),
            Just(2),
            Just(3),
            Just(12),
            Just(20),
            Just(0x7fff_ffff),
            Just(u32::MAX)
        ]
        .prop_map(HeaderValue::Word),
        prop_oneof![
            Just(1i32),
            Just(-1),
            Just(4),
            Just(-4),
            Just(-8),
            Just(1 << 20)
        ]
        .prop_map(HeaderValue::Plus),
        prop_oneof![
            Just(b"glTF"),
            Just(b"JSON"),
            Just(b"BIN\0"),
            Just(b"\0\0\0\0")
        ]
        .prop_map(HeaderValue::Tag),
    ];
    prop_oneof![
        6 => (0..KEYS.len(), any::<Index>(), proptest::option::of(any::<Index>()), value())
            .prop_map(|(key, nth, element, value)| Mutation::KeyValue { key, nth, element, value }),
        2 => (any::<Index>(), value()).prop_map(|(nth, value)| Mutation::Number { nth, value }),
        1 => (0..KEYS.len(), any::<Index>()).prop_map(|(key, nth)| Mutation::DropKey { key, nth }),
        4 => (any::<Index>(), any::<Index>(), 0..FLOATS.len())
            .prop_map(|(view, at, value)| Mutation::Float { view, at, value }),
        1 => (any::<Index>(), any::<Index>(), 0..WORDS.len())
            .prop_map(|(view, at, value)| Mutation::Word { view, at, value }),
        1 => (any::<Index>(), 1usize..64, any::<u8>())
            .prop_map(|(at, len, byte)| Mutation::BinRun { at, len, byte }),
        3 => (any::<Index>(), 0u8..8).prop_map(|(at, bit)| Mutation::Flip { at, bit }),
        1 => (any::<Index>(), any::<u8>()).prop_map(|(at, byte)| Mutation::SetByte { at, byte }),
        1 => (any::<Index>(), 1usize..32).prop_map(|(at, len)| Mutation::Cut { at, len }),
        1 => any::<Index>().prop_map(|at| Mutation::Truncate { at }),
        2 => (0usize..7, header_value).prop_map(|(field, value)| Mutation::Header { field, value }),
    ]
}

/// Inputs over `seeds` seeds, picked with the given weights.
pub fn input(weights: &[u32]) -> impl Strategy<Value = Input> {
    let seeds: Vec<(u32, BoxedStrategy<usize>)> = weights
        .iter()
        .enumerate()
        .filter(|(_, w)| **w > 0)
        .map(|(i, &w)| (w, Just(i).boxed()))
        .collect();
    (
        proptest::strategy::Union::new_weighted(seeds),
        proptest::collection::vec(mutation(), 1..=3),
        any::<bool>(),
    )
        .prop_map(|(seed, mutations, paper)| Input {
            seed,
            mutations,
            paper,
        })
}

/// The files of a case: the main file's bytes and, for `.gltf` cases, the
/// binary buffer's (written as [`BIN_NAME`] next to it).
pub struct Files {
    pub main: Vec<u8>,
    pub bin: Option<Vec<u8>>,
}

/// Applies `input`'s mutations to its seed: JSON edits, then buffer edits,
/// then packing, then edits of the packed bytes.
pub fn apply(seed: &Seed, input: &Input) -> Files {
    let mut json = seed.json.clone();
    let mut bin = seed.bin.clone();
    for m in &input.mutations {
        edit_json(&mut json, m);
        edit_bin(&mut bin, &seed.views, m);
    }
    let (mut main, bin) = match seed.kind {
        Kind::Glb => (pack_glb(&json, &bin), None),
        Kind::Gltf => (json, Some(bin)),
    };
    for m in &input.mutations {
        edit_packed(&mut main, seed.kind, m);
    }
    Files { main, bin }
}

/// The byte range of the JSON value starting at `at` (after `"key":` and
/// blanks): a string, a bracketed array or object, or a bare token.
fn value_span(text: &[u8], at: usize) -> Option<(usize, usize)> {
    let first = *text.get(at)?;
    let end = match first {
        b'"' => {
            let mut i = at + 1;
            while i < text.len() && text[i] != b'"' {
                i += if text[i] == b'\\' { 2 } else { 1 };
            }
            (i + 1).min(text.len())
        }
        b'[' | b'{' => {
            let mut depth = 0usize;
            let mut in_string = false;
            let mut i = at;
            while i < text.len() {
                match (in_string, text[i]) {
                    (true, b'\\') => i += 1,
                    (true, b'"') | (false, b'"') => in_string = !in_string,
                    (false, b'[' | b'{') => depth += 1,
                    (false, b']' | b'}') => {
                        depth -= 1;
                        if depth == 0 {
                            break;
                        }
                    }
                    _ => {}
                }
                i += 1;
            }
            (i + 1).min(text.len())
        }
        _ => {
            at + text[at..]
                .iter()
                .position(|c| b",}] \n\r\t".contains(c))
                .unwrap_or(text.len() - at)
        }
    };
    Some((at, end))
}

/// Spans of the numbers in `text[from..to]` outside strings.
fn numbers(text: &[u8], from: usize, to: usize) -> Vec<(usize, usize)> {
    let mut out = Vec::new();
    let mut in_string = false;
    let mut i = from;
    while i < to {
        let c = text[i];
        if in_string {
            match c {
                b'\\' => i += 1,
                b'"' => in_string = false,
                _ => {}
            }
            i += 1;
        } else if c == b'"' {
            in_string = true;
            i += 1;
        } else if c == b'-' || c.is_ascii_digit() {
            let start = i;
            while i < to && (text[i].is_ascii_digit() || b"+-.eE".contains(&text[i])) {
                i += 1;
            }
            out.push((start, i));
        } else {
            i += 1;
        }
    }
    out
}

/// Start offsets of the values of `"key":` in `text`.
fn key_values(text: &[u8], key: &str) -> Vec<usize> {
    let needle = format!("\"{key}\"");
    let n = needle.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    while i + n.len() <= text.len() {
        if &text[i..i + n.len()] == n {
            let mut j = i + n.len();
            while j < text.len() && text[j].is_ascii_whitespace() {
                j += 1;
            }
            if text.get(j) == Some(&b':') {
                j += 1;
                while j < text.len() && text[j].is_ascii_whitespace() {
                    j += 1;
                }
                out.push(j);
            }
            i += n.len();
        } else {
            i += 1;
        }
    }
    out
}

/// The replacement text of the value `old` (the text there now).
fn replacement(old: &[u8], value: &Value) -> Vec<u8> {
    let number = std::str::from_utf8(old)
        .ok()
        .and_then(|s| s.parse::<f64>().ok());
    match (value, number) {
        (Value::Number(i), _) => NUMBERS[*i].as_bytes().to_vec(),
        (Value::String(i), _) => STRINGS[*i].as_bytes().to_vec(),
        (Value::Other(i), _) => OTHERS[*i].as_bytes().to_vec(),
        (Value::Plus(d), Some(x)) if x.fract() == 0.0 => format!("{}", x as i64 + d).into_bytes(),
        (Value::Plus(d), Some(x)) => format!("{}", x + *d as f64).into_bytes(),
        (Value::Times(k), Some(x)) if x.fract() == 0.0 => {
            format!("{}", (x as i64).saturating_mul(*k)).into_bytes()
        }
        (Value::Times(k), Some(x)) => format!("{}", x * *k as f64).into_bytes(),
        // Arithmetic on a non-number: a fixed absurd count instead.
        (_, None) => b"4294967295".to_vec(),
    }
}

fn splice(text: &mut Vec<u8>, (start, end): (usize, usize), with: &[u8]) {
    text.splice(start..end, with.iter().copied());
}

fn edit_json(json: &mut Vec<u8>, m: &Mutation) {
    match m {
        Mutation::KeyValue {
            key,
            nth,
            element,
            value,
        } => {
            let starts = key_values(json, KEYS[*key]);
            if starts.is_empty() {
                return;
            }
            let Some(span) = value_span(json, starts[nth.index(starts.len())]) else {
                return;
            };
            let target = match (element, json[span.0]) {
                (Some(e), b'[') => {
                    let inner = numbers(json, span.0 + 1, span.1.saturating_sub(1));
                    if inner.is_empty() {
                        span
                    } else {
                        inner[e.index(inner.len())]
                    }
                }
                _ => span,
            };
            let new = replacement(&json[target.0..target.1], value);
            splice(json, target, &new);
        }
        Mutation::Number { nth, value } => {
            let all = numbers(json, 0, json.len());
            if !all.is_empty() {
                let target = all[nth.index(all.len())];
                let new = replacement(&json[target.0..target.1], value);
                splice(json, target, &new);
            }
        }
        Mutation::DropKey { key, nth } => {
            let name = format!("\"{}\"", KEYS[*key]);
            let at: Vec<usize> = json
                .windows(name.len())
                .enumerate()
                .filter(|(_, w)| *w == name.as_bytes())
                .map(|(i, _)| i)
                .collect();
            if !at.is_empty() {
                // Same length, so the member stays well-formed but unknown.
                json[at[nth.index(at.len())] + 1] = b'_';
            }
        }
        _ => {}
    }
}

fn edit_bin(bin: &mut [u8], views: &[(usize, usize)], m: &Mutation) {
    let aligned = |view: &Index, at: &Index| -> Option<usize> {
        let &(offset, length) = views.get(view.index(views.len().max(1)))?;
        let slots = length / 4;
        (slots > 0).then(|| offset + 4 * at.index(slots))
    };
    match m {
        Mutation::Float { view, at, value } => {
            if let Some(p) = aligned(view, at).filter(|p| p + 4 <= bin.len()) {
                bin[p..p + 4].copy_from_slice(&FLOATS[*value].to_le_bytes());
            }
        }
        Mutation::Word { view, at, value } => {
            if let Some(p) = aligned(view, at).filter(|p| p + 4 <= bin.len()) {
                bin[p..p + 4].copy_from_slice(&WORDS[*value].to_le_bytes());
            }
        }
        Mutation::BinRun { at, len, byte } if !bin.is_empty() => {
            let start = at.index(bin.len());
            let end = (start + len).min(bin.len());
            bin[start..end].fill(*byte);
        }
        _ => {}
    }
}

fn edit_packed(main: &mut Vec<u8>, kind: Kind, m: &Mutation) {
    if main.is_empty() {
        return;
    }
    match m {
        Mutation::Flip { at, bit } => {
            let i = at.index(main.len());
            main[i] ^= 1 << bit;
        }
        Mutation::SetByte { at, byte } => {
            let i = at.index(main.len());
            main[i] = *byte;
        }
        Mutation::Cut { at, len } => {
            let start = at.index(main.len());
            let end = (start + len).min(main.len());
            main.drain(start..end);
        }
        Mutation::Truncate { at } => {
            let keep = at.index(main.len());
            main.truncate(keep);
        }
        Mutation::Header { field, value } if kind == Kind::Glb => {
            let json_len = main
                .get(12..16)
                .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as usize)
                .unwrap_or(0);
            let at = [0, 4, 8, 12, 16, 20 + json_len, 24 + json_len][*field];
            let Some(slot) = main.get_mut(at..at + 4) else {
                return;
            };
            let old = u32::from_le_bytes([slot[0], slot[1], slot[2], slot[3]]);
            let new = match value {
                HeaderValue::Word(w) => w.to_le_bytes(),
                HeaderValue::Plus(d) => old.wrapping_add_signed(*d).to_le_bytes(),
                HeaderValue::Tag(t) => **t,
            };
            slot.copy_from_slice(&new);
        }
        _ => {}
    }
}

/// The files of a case as they are written to disk: the main file's name
/// and, for `.gltf` cases, the buffer.
pub fn file_names(kind: Kind) -> (&'static str, Option<&'static str>) {
    match kind {
        Kind::Glb => ("case.glb", None),
        Kind::Gltf => ("case.gltf", Some(BIN_NAME)),
    }
}
