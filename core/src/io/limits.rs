//! What a glTF file may make the loaders allocate: one budget of bytes for the
//! file itself, its buffers and everything decoded from its accessors.
//!
//! Every size in a glTF file (accessor counts, buffer lengths, how often a
//! mesh is instanced, how many channels share a keyframe accessor) is read
//! from the file, so a damaged or hostile file could ask for any amount of
//! memory and time. The loaders charge each allocation derived from the file
//! to a byte budget *before* making it; past [`LoadLimits::max_bytes`] the
//! load is refused with the value that drove it. Decoding is linear in what
//! is charged, so the budget bounds the loading time too.

#[cfg(feature = "gltf")]
use std::cell::Cell;

/// Largest magnitude of a coordinate the loaders accept (positions as stored
/// and in world space), and `inspect --animate` in a posed character: a
/// million kilometres in metres, a thousand in millimetres. It keeps squared
/// distances and the triangle kernels' cubic terms far inside `f32` range.
pub const MAX_COORDINATE: f32 = 1.0e9;

/// Whether a length is a number no larger than [`MAX_COORDINATE`] (NaN is
/// not).
pub fn within_range(length: f32) -> bool {
    length.is_finite() && length <= MAX_COORDINATE
}

/// One GiB.
const GIB: usize = 1 << 30;

/// Limits of one load.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LoadLimits {
    /// Most bytes the file, its buffers and its decoded accessors may take,
    /// summed over the whole load (an accessor read twice counts twice).
    pub max_bytes: usize,
}

impl Default for LoadLimits {
    /// 2 GiB: the bundled characters need about 1% of it (BrainStem, the
    /// largest, reads 3 MB of file and decodes about 20 MB).
    fn default() -> Self {
        Self { max_bytes: 2 * GIB }
    }
}

/// The bytes charged so far against a [`LoadLimits`].
#[derive(Debug)]
#[cfg(feature = "gltf")]
pub(crate) struct Budget {
    max: usize,
    used: Cell<usize>,
}

#[cfg(feature = "gltf")]
impl Budget {
    pub(crate) fn new(limits: &LoadLimits) -> Self {
        Self {
            max: limits.max_bytes,
            used: Cell::new(0),
        }
    }

    /// Bytes left before the budget is spent.
    pub(crate) fn remaining(&self) -> usize {
        self.max.saturating_sub(self.used.get())
    }

    /// Charges `count` items of `size` bytes (`what` names them in the error)
    /// or refuses, saying how far over the budget the load would go.
    pub(crate) fn charge(&self, what: &str, count: usize, size: usize) -> Result<(), String> {
        let bytes = count.checked_mul(size);
        match bytes.and_then(|b| b.checked_add(self.used.get())) {
            Some(total) if total <= self.max => {
                self.used.set(total);
                Ok(())
            }
            _ => Err(format!(
                "{what}: {} would take the load to {} bytes, over its budget of {} bytes (LoadLimits::max_bytes)",
                if size == 1 {
                    format!("{count} bytes")
                } else {
                    format!("{count} × {size} bytes")
                },
                bytes
                    .and_then(|b| b.checked_add(self.used.get()))
                    .map(|total| total.to_string())
                    .unwrap_or_else(|| "more than 2^64".into()),
                self.max
            )),
        }
    }
}

#[cfg(all(test, feature = "gltf"))]
mod tests {
    use super::*;

    #[test]
    fn charges_up_to_the_budget_then_refuses() {
        let b = Budget::new(&LoadLimits { max_bytes: 100 });
        assert!(b.charge("a", 10, 9).is_ok());
        assert!(b.charge("b", 1, 10).is_ok());
        let e = b.charge("c", 1, 1).unwrap_err();
        assert!(e.starts_with("c: 1 bytes would take"), "{e}");
        let e = b.charge("f", 3, 4).unwrap_err();
        assert!(e.starts_with("f: 3 × 4 bytes would take"), "{e}");
        assert_eq!(
            e,
            "f: 3 × 4 bytes would take the load to 112 bytes, over its budget of 100 bytes (LoadLimits::max_bytes)"
        );
        assert!(b.charge("d", usize::MAX, 2).unwrap_err().contains("2^64"));
        assert!(b.charge("e", 0, 1).is_ok());
    }
}
