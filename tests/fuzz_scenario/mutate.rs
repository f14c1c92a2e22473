//! Mutations of scenario text and their proptest strategies: a number
//! replaced (0, negatives, huge, tiny, NaN and infinities, wrong types) or
//! scaled; a key's value replaced; a key inserted; a line (key) or a block
//! (table, array entry) dropped or duplicated; an array element dropped or
//! duplicated; the text truncated or a character changed.

use proptest::prelude::*;
use proptest::sample::Index;

/// Replacement numbers: boundaries of the documented ranges and far past
/// them, past `f32`, `i64` and `u64`, and TOML's non-finite floats.
pub const NUMBERS: &[&str] = &[
    "0",
    "-0.0",
    "1",
    "-1",
    "2",
    "-3",
    "0.5",
    "7",
    "16",
    "17",
    "1e30",
    "-1e30",
    "1e300",
    "-1e300",
    "1e-300",
    "1e-45",
    "1e-7",
    "3.5e38",
    "1e6",
    "1000001",
    "-1e6",
    "1e9",
    "1000000000000",
    "10000000000",
    "20000000",
    "20000001",
    "2000000",
    "2000001",
    "499",
    "4294967296",
    "9223372036854775807",
    "-9223372036854775808",
    "18446744073709551616",
    "nan",
    "-nan",
    "inf",
    "-inf",
    "+inf",
];

/// Replacement values of other types, and values that name things.
pub const OTHERS: &[&str] = &[
    "\"NaN\"",
    "\"inf\"",
    "\"1e30\"",
    "\"\"",
    "true",
    "false",
    "[]",
    "{}",
    "[0]",
    "[1e30, 1e30, 1e30]",
    "[nan, 0, 0]",
    "[0, 0, 0]",
    "[[0, 0, 0]]",
    "[0, 1, 2, 3]",
    "\"museum\"",
    "\"living-room\"",
    "\"gltf\"",
    "\"swing\"",
    "\"closed\"",
    "\"paper\"",
    "\"linear\"",
    "\"walk\"",
    "\"reach\"",
    "\"no such clip\"",
    "\"south wall\"",
    "\"floor\"",
    "\"ceiling\"",
    "\"box\"",
    "\"ball\"",
    "\"door\"",
    "\"panel\"",
    "\"generated:humanoid?vertices=10000000000\"",
    "\"generated:humanoid?vertices=2000000\"",
    "\"generated:humanoid?vertices=500\"",
    "\"generated:humanoid?vertices=-1\"",
    "\"generated:humanoid?seed=18446744073709551616\"",
    "\"generated:robot\"",
    "\"../assets/CesiumMan.glb\"",
    "\"../assets/BrainStem.glb\"",
    "\"../assets\"",
    "\"/dev/zero\"",
    "\"/dev/null\"",
    "\"no/such/file.glb\"",
    "[\"original\", \"original\"]",
    "[\"plane-sphere-pruned\"]",
    "[\"fastest\"]",
    "{ surface = \"south wall\", metres = -1e30 }",
    "{ gap = { surface = \"south wall\", metres = -1e30 } }",
    "{ start = { translation = [1e30, 0, 0] } }",
    "{ path = { waypoints = [[0, 0, 0], [1e6, 0, 0]], speed = 1e-300 } }",
    "{ times = [0, 1e300], positions = [[0, 0, 0], [1, 0, 0]] }",
    "{ times = [0, 1], degrees = [0, 1e30], axis = [0, 1e-30, 0] }",
    "[{ object = \"south wall\", times = 16 }]",
    "[{ object = \"floor\", times = 10 }, { object = \"south wall\", times = 10 }]",
];

/// Keys inserted on a line of their own (in whatever table precedes), with
/// values that stress their ranges.
pub const INSERTED: &[&str] = &[
    "frames = 1000000000000",
    "frames = 1000000",
    "frames = 0",
    "fps = 1e-300",
    "fps = 1e300",
    "fps = 0.001",
    "threshold = 1e-6",
    "threshold = 1e-300",
    "threshold = 1e6",
    "dedup = false",
    "ccd = true",
    "ccd = 1",
    "ccd_substeps = 0",
    "ccd_substeps = 65537",
    "ccd_substeps = 1",
    "methods = [\"original\", \"sphere-division\", \"quaternary-plane-sphere\"]",
    "vertices = 10000000000",
    "vertices = 20000000",
    "vertices = 3",
    "seed = -1",
    "seed = 9223372036854775807",
    "subdivide = [{ object = \"south wall\", times = 16 }]",
    "subdivide = [{ object = \"south wall\", times = 4 }]",
    "subdivide = [{ object = \"floor\", times = 6 }, { object = \"floor\", times = 6 }]",
    "doors = \"swing\"",
    "clip_offset = 1e300",
    "clip_offset = -1e6",
    "radius = 1e30",
    "subdivisions = 7",
    "size = [1e6, 1e6, 1e6]",
    "size = [0, 1, 1]",
    "mesh_every = 0",
    "spheres_every = 4294967296",
    "all_spheres = true",
    "path = \"../assets/CesiumMan.glb\"",
    "kind = \"gltf\"",
    "[[characters]]",
    "[[objects]]",
    "[placement]",
    "[recording]",
];

#[derive(Clone, Debug)]
pub enum Value {
    /// One of [`NUMBERS`].
    Number(usize),
    /// One of [`OTHERS`].
    Other(usize),
    /// The number there times `10^k`.
    Scale(i32),
    /// The number there, negated.
    Negate,
}

#[derive(Clone, Debug)]
pub enum Mutation {
    /// The `nth` number of the text.
    Number { nth: Index, value: Value },
    /// The value of the `nth` `key = value`.
    KeyValue { nth: Index, value: Value },
    /// One of [`INSERTED`] on a new line after line `line`.
    Insert { line: Index, key: usize },
    /// Line `line` (a key, a header) dropped, or written twice.
    Line { line: Index, duplicate: bool },
    /// The `nth` block (a header and the lines up to the next header)
    /// dropped, or written twice.
    Block { nth: Index, duplicate: bool },
    /// Element `element` of the `nth` array value dropped, or written twice.
    Element {
        nth: Index,
        element: Index,
        duplicate: bool,
    },
    /// The text cut at a character.
    Truncate { at: Index },
    /// One character replaced.
    Char { at: Index, with: char },
}

/// An input: a seed and the mutations applied to it in order.
#[derive(Clone, Debug)]
pub struct Input {
    pub seed: usize,
    pub mutations: Vec<Mutation>,
}

fn value() -> impl Strategy<Value = Value> {
    prop_oneof![
        6 => (0..NUMBERS.len()).prop_map(Value::Number),
        2 => (0..OTHERS.len()).prop_map(Value::Other),
        3 => prop_oneof![Just(-30i32), Just(-6), Just(-1), Just(1), Just(3), Just(6), Just(12), Just(30), Just(300)]
            .prop_map(Value::Scale),
        2 => Just(Value::Negate),
    ]
}

fn mutation() -> impl Strategy<Value = Mutation> {
    prop_oneof![
        10 => (any::<Index>(), value()).prop_map(|(nth, value)| Mutation::Number { nth, value }),
        4 => (any::<Index>(), value()).prop_map(|(nth, value)| Mutation::KeyValue { nth, value }),
        3 => (any::<Index>(), 0..INSERTED.len()).prop_map(|(line, key)| Mutation::Insert { line, key }),
        1 => (any::<Index>(), any::<bool>()).prop_map(|(line, duplicate)| Mutation::Line { line, duplicate }),
        2 => (any::<Index>(), any::<bool>()).prop_map(|(nth, duplicate)| Mutation::Block { nth, duplicate }),
        2 => (any::<Index>(), any::<Index>(), any::<bool>())
            .prop_map(|(nth, element, duplicate)| Mutation::Element { nth, element, duplicate }),
        1 => any::<Index>().prop_map(|at| Mutation::Truncate { at }),
        1 => (any::<Index>(), prop_oneof![Just('"'), Just('['), Just(']'), Just('{'), Just('='), Just('\n'), Just('#'), Just('-'), Just('9'), Just('\u{e9}')])
            .prop_map(|(at, with)| Mutation::Char { at, with }),
    ]
}

/// Inputs over the seeds, picked with the given weights.
pub fn input(weights: &[u32]) -> impl Strategy<Value = Input> {
    let seeds: Vec<(u32, BoxedStrategy<usize>)> = weights
        .iter()
        .enumerate()
        .filter(|(_, w)| **w > 0)
        .map(|(i, &w)| (w, Just(i).boxed()))
        .collect();
    (
        proptest::strategy::Union::new_weighted(seeds),
        proptest::collection::vec(mutation(), 1..=2),
    )
        .prop_map(|(seed, mutations)| Input { seed, mutations })
}

/// Applies `input`'s mutations to `seed` in order.
pub fn apply(seed: &str, input: &Input) -> String {
    let mut text = seed.to_owned();
    for m in &input.mutations {
        text = edit(&text, m);
    }
    text
}

fn edit(text: &str, m: &Mutation) -> String {
    match m {
        Mutation::Number { nth, value } => {
            let spans = numbers(text);
            if spans.is_empty() {
                return text.to_owned();
            }
            let (a, b) = spans[nth.index(spans.len())];
            splice(text, a, b, &replacement(&text[a..b], value))
        }
        Mutation::KeyValue { nth, value } => {
            let spans = values(text);
            if spans.is_empty() {
                return text.to_owned();
            }
            let (a, b) = spans[nth.index(spans.len())];
            splice(text, a, b, &replacement(&text[a..b], value))
        }
        Mutation::Insert { line, key } => {
            let mut lines: Vec<&str> = text.lines().collect();
            let at = line.index(lines.len() + 1);
            lines.insert(at, INSERTED[*key]);
            lines.join("\n") + "\n"
        }
        Mutation::Line { line, duplicate } => {
            let mut lines: Vec<&str> = text.lines().collect();
            if lines.is_empty() {
                return text.to_owned();
            }
            let at = line.index(lines.len());
            if *duplicate {
                lines.insert(at, lines[at]);
            } else {
                lines.remove(at);
            }
            lines.join("\n") + "\n"
        }
        Mutation::Block { nth, duplicate } => {
            let lines: Vec<&str> = text.lines().collect();
            let headers: Vec<usize> = (0..lines.len())
                .filter(|&i| lines[i].trim_start().starts_with('['))
                .collect();
            if headers.is_empty() {
                return text.to_owned();
            }
            let k = nth.index(headers.len());
            let (start, end) = (
                headers[k],
                headers.get(k + 1).copied().unwrap_or(lines.len()),
            );
            let mut out: Vec<&str> = lines[..end].to_vec();
            if *duplicate {
                out.extend_from_slice(&lines[start..end]);
            } else {
                out.truncate(start);
            }
            out.extend_from_slice(&lines[end..]);
            out.join("\n") + "\n"
        }
        Mutation::Element {
            nth,
            element,
            duplicate,
        } => {
            let arrays = arrays(text);
            if arrays.is_empty() {
                return text.to_owned();
            }
            let (a, b) = arrays[nth.index(arrays.len())];
            let elements = elements(text, a, b);
            if elements.is_empty() {
                return text.to_owned();
            }
            let (ea, eb) = elements[element.index(elements.len())];
            if *duplicate {
                splice(text, eb, eb, &format!(", {}", &text[ea..eb]))
            } else {
                // The element and the comma after it (or before it, for the last).
                let bytes = text.as_bytes();
                let mut end = eb;
                while end < b && bytes[end] != b',' && bytes[end] != b']' {
                    end += 1;
                }
                if end < b && bytes[end] == b',' {
                    splice(text, ea, end + 1, "")
                } else {
                    let mut start = ea;
                    while start > a + 1 && bytes[start - 1] != b',' {
                        start -= 1;
                    }
                    let start = if start > a + 1 { start - 1 } else { ea };
                    splice(text, start, eb, "")
                }
            }
        }
        Mutation::Truncate { at } => {
            let cuts: Vec<usize> = text.char_indices().map(|(i, _)| i).collect();
            if cuts.is_empty() {
                return text.to_owned();
            }
            text[..cuts[at.index(cuts.len())]].to_owned()
        }
        Mutation::Char { at, with } => {
            let cuts: Vec<(usize, char)> = text.char_indices().collect();
            if cuts.is_empty() {
                return text.to_owned();
            }
            let (i, c) = cuts[at.index(cuts.len())];
            splice(text, i, i + c.len_utf8(), &with.to_string())
        }
    }
}

fn splice(text: &str, a: usize, b: usize, with: &str) -> String {
    format!("{}{with}{}", &text[..a], &text[b..])
}

/// What replaces `old` (a number or any value).
fn replacement(old: &str, value: &Value) -> String {
    match value {
        Value::Number(i) => NUMBERS[*i].to_owned(),
        Value::Other(i) => OTHERS[*i].to_owned(),
        Value::Scale(k) => match old.trim().replace('_', "").parse::<f64>() {
            Ok(v) => format!("{:e}", v * 10f64.powi(*k)),
            Err(_) => old.to_owned(),
        },
        Value::Negate => match old.trim().strip_prefix('-') {
            Some(rest) => rest.to_owned(),
            None => format!("-{}", old.trim()),
        },
    }
}

/// Byte spans of the code outside strings and comments, as a mask.
fn code_mask(text: &str) -> Vec<bool> {
    let bytes = text.as_bytes();
    let mut mask = vec![true; bytes.len()];
    let mut i = 0;
    while i < bytes.len() {
        match bytes[i] {
            b'#' => {
                while i < bytes.len() && bytes[i] != b'\n' {
                    mask[i] = false;
                    i += 1;
                }
            }
            q @ (b'"' | b'\'') => {
                mask[i] = false;
                i += 1;
                while i < bytes.len() && bytes[i] != q && bytes[i] != b'\n' {
                    if q == b'"' && bytes[i] == b'\\' {
                        mask[i] = false;
                        i += 1;
                    }
                    if i < bytes.len() {
                        mask[i] = false;
                    }
                    i += 1;
                }
                if i < bytes.len() {
                    mask[i] = false;
                    i += 1;
                }
            }
            _ => i += 1,
        }
    }
    mask
}

/// Spans of the numbers (and `inf`/`nan`) outside strings and comments.
fn numbers(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mask = code_mask(text);
    let word = |c: u8| c.is_ascii_alphanumeric() || b"_.+-".contains(&c);
    let mut out = Vec::new();
    let mut i = 0;
    while i < bytes.len() {
        let starts = mask[i]
            && (i == 0 || !(bytes[i - 1].is_ascii_alphanumeric() || bytes[i - 1] == b'_'))
            && (bytes[i].is_ascii_digit()
                || (b"+-".contains(&bytes[i])
                    && bytes
                        .get(i + 1)
                        .is_some_and(|c| c.is_ascii_digit() || *c == b'i' || *c == b'n'))
                || bytes[i..].starts_with(b"inf")
                || bytes[i..].starts_with(b"nan"));
        if starts {
            let a = i;
            i += 1;
            while i < bytes.len() && mask[i] && word(bytes[i]) {
                i += 1;
            }
            // Keys such as `mesh_every` are words, not numbers.
            if !text[a..i]
                .chars()
                .any(|c| c.is_ascii_alphabetic() && !"eEinfa".contains(c))
            {
                out.push((a, i));
            }
        } else {
            i += 1;
        }
    }
    out
}

/// The end of the value starting at `a` (a bracketed array or inline table,
/// a string, or a bare token).
fn value_end(text: &str, mask: &[bool], a: usize) -> usize {
    let bytes = text.as_bytes();
    match bytes.get(a) {
        Some(b'[' | b'{') => {
            let mut depth = 0usize;
            let mut i = a;
            while i < bytes.len() {
                if mask[i] {
                    match bytes[i] {
                        b'[' | b'{' => depth += 1,
                        b']' | b'}' => {
                            depth -= 1;
                            if depth == 0 {
                                return i + 1;
                            }
                        }
                        _ => {}
                    }
                }
                i += 1;
            }
            bytes.len()
        }
        Some(b'"' | b'\'') => {
            let mut i = a + 1;
            while i < bytes.len() && !mask[i] {
                i += 1;
            }
            i
        }
        _ => {
            let mut i = a;
            while i < bytes.len() && !(mask[i] && b",}]\n#".contains(&bytes[i])) {
                i += 1;
            }
            let mut end = i;
            while end > a && bytes[end - 1].is_ascii_whitespace() {
                end -= 1;
            }
            end
        }
    }
}

/// Spans of every value after `key =`, nested ones included.
fn values(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mask = code_mask(text);
    let mut out = Vec::new();
    for i in 0..bytes.len() {
        if mask[i] && bytes[i] == b'=' {
            let mut a = i + 1;
            while a < bytes.len() && (bytes[a] == b' ' || bytes[a] == b'\t') {
                a += 1;
            }
            if a < bytes.len() && bytes[a] != b'\n' {
                out.push((a, value_end(text, &mask, a)));
            }
        }
    }
    out
}

/// Spans of every array value (not table headers), nested ones included.
fn arrays(text: &str) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mask = code_mask(text);
    let mut out = Vec::new();
    for i in 0..bytes.len() {
        if mask[i] && bytes[i] == b'[' {
            // A header starts its line.
            let line_start = text[..i].rfind('\n').map_or(0, |n| n + 1);
            if text[line_start..i].trim().is_empty() || text[line_start..i].trim() == "[" {
                continue;
            }
            out.push((i, value_end(text, &mask, i)));
        }
    }
    out
}

/// Spans of the top-level elements of the array `text[a..b]`.
fn elements(text: &str, a: usize, b: usize) -> Vec<(usize, usize)> {
    let bytes = text.as_bytes();
    let mask = code_mask(text);
    let mut out = Vec::new();
    let mut i = a + 1;
    while i < b {
        while i < b && (bytes[i].is_ascii_whitespace() || (mask[i] && bytes[i] == b',')) {
            i += 1;
        }
        if i >= b || (mask[i] && bytes[i] == b']') {
            break;
        }
        let end = value_end(text, &mask, i).min(b);
        if end <= i {
            break;
        }
        out.push((i, end));
        i = end;
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    const TEXT: &str = "# c 1\nframes = 3\n[a]\nx = { y = [1, -2.5e3, [3]], z = \"s 4\" }\nmesh_every = 1\nw = nan\n";

    #[test]
    fn finds_numbers_values_and_arrays() {
        let n: Vec<&str> = numbers(TEXT).iter().map(|&(a, b)| &TEXT[a..b]).collect();
        assert_eq!(n, ["3", "1", "-2.5e3", "3", "1", "nan"]);
        let v: Vec<&str> = values(TEXT).iter().map(|&(a, b)| &TEXT[a..b]).collect();
        assert_eq!(
            v,
            [
                "3",
                "{ y = [1, -2.5e3, [3]], z = \"s 4\" }",
                "[1, -2.5e3, [3]]",
                "\"s 4\"",
                "1",
                "nan"
            ]
        );
        let arr: Vec<&str> = arrays(TEXT).iter().map(|&(a, b)| &TEXT[a..b]).collect();
        assert_eq!(arr, ["[1, -2.5e3, [3]]", "[3]"]);
        let (a, b) = arrays(TEXT)[0];
        let e: Vec<&str> = elements(TEXT, a, b)
            .iter()
            .map(|&(x, y)| &TEXT[x..y])
            .collect();
        assert_eq!(e, ["1", "-2.5e3", "[3]"]);
    }
}
