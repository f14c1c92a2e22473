//! Per index, the last key met in the current pass: "seen this pass?"
//! without clearing anything between passes (a pass stamp does it).
//!
//! Two uses, both in `pruned-tri-tri`:
//! - [`super::grouped`]: per character sphere, the big triangle it was last
//!   descended against (a sphere is descended once per big triangle);
//! - the narrow phase (`pipeline::rigid_pass`): per
//!   character triangle, the big triangle it was last tested against. Every
//!   leaf of a big triangle's division names that triangle (§5, "the
//!   leaf-nodes ... point to the big triangle T"), so one triangle reaching
//!   several neighbouring leaves reaches the narrow phase once per leaf
//!   with the same pair; it is tested once, without sorting. Repeats of one
//!   pair come from neighbouring leaves, so one entry catches nearly all of
//!   them; a repeat it misses (a triangle alternating between two big
//!   triangles, at a room's corner) is tested again and removed with the
//!   pass's other duplicates.

/// `(pass, key)` per index.
#[derive(Clone, Debug, Default)]
pub struct PassMarks {
    last: Vec<(u32, u32)>,
    pass: u32,
}

impl PassMarks {
    /// Marks for indices `0..len`.
    #[cfg(test)]
    pub fn new(len: usize) -> Self {
        Self {
            last: vec![(0, 0); len],
            pass: 0,
        }
    }

    /// Indices it has room for.
    #[cfg(test)]
    pub fn len(&self) -> usize {
        self.last.len()
    }

    /// Room for indices `0..len` at least (allocates only when it grows).
    pub fn grow_to(&mut self, len: usize) {
        if self.last.len() < len {
            self.last.resize(len, (0, 0));
        }
    }

    /// Starts a pass: every (index, key) is new again. No allocation.
    pub fn begin_pass(&mut self) {
        self.pass = self.pass.wrapping_add(1);
        if self.pass == 0 {
            self.last.fill((0, 0));
            self.pass = 1;
        }
    }

    /// Starts loading `index`'s entry (a hint, for an index
    /// [`Self::first_time`] will be asked about soon).
    #[inline(always)]
    pub fn prefetch(&self, index: u32) {
        crate::prefetch::prefetch_at(&self.last, index as usize);
    }

    /// Whether `(index, key)` is met for the first time in this pass (as far
    /// as one entry per index remembers); notes it.
    #[inline]
    pub fn first_time(&mut self, index: u32, key: u32) -> bool {
        let entry = &mut self.last[index as usize];
        let seen = *entry == (self.pass, key);
        *entry = (self.pass, key);
        !seen
    }
}

#[cfg(test)]
mod tests {
    use super::PassMarks;

    /// Against a set of seen pairs: a first meeting is never dropped, an
    /// immediate repeat is, and a new pass forgets everything.
    #[test]
    fn never_drops_a_first_meeting() {
        let mut f = PassMarks::new(8);
        let mut x = 12345u32;
        for _pass in 0..50 {
            f.begin_pass();
            let mut seen = std::collections::HashSet::new();
            for _ in 0..200 {
                x = x.wrapping_mul(1_103_515_245).wrapping_add(12_345);
                let (a, b) = ((x >> 16) % 8, (x >> 8) % 3);
                let first = f.first_time(a, b);
                if seen.insert((a, b)) {
                    assert!(first, "first meeting of {a}, {b} dropped");
                }
                assert!(!f.first_time(a, b), "immediate repeat of {a}, {b} kept");
            }
        }
    }
}
