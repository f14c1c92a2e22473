//! Skipping repeated triangle tests against a big triangle, without sorting.
//!
//! Every leaf of a big triangle's division names the big triangle (§5, "the
//! leaf-nodes ... point to the big triangle T"), so one character triangle
//! whose sphere meets several neighbouring division leaves reaches the
//! narrow phase once per leaf with the same pair. The paper's methods test
//! each such leaf pair; `pruned-tri-tri` tests each distinct pair once
//! ([`super::Method::tests_each_pair_once`]).
//!
//! Per character triangle the filter keeps the last big triangle it was
//! tested against in this pass (a pass stamp makes clearing free). Repeats
//! of one pair come from neighbouring leaves, so a single entry catches
//! nearly all of them; the rare repeat it misses (a triangle alternating
//! between two big triangles, at a room's corner) is tested again and
//! removed with the pass's other duplicates, so the answer is the same.

/// Last big triangle each character triangle met in the current pass.
#[derive(Clone, Debug, Default)]
pub struct RepeatFilter {
    /// `(pass, big triangle)` per character triangle.
    last: Vec<(u32, u32)>,
    pass: u32,
}

impl RepeatFilter {
    /// A filter for a character of `triangles` triangles.
    pub fn new(triangles: usize) -> Self {
        Self {
            last: vec![(0, 0); triangles],
            pass: 0,
        }
    }

    /// Starts a pass: every pair is new again. No allocation.
    pub fn begin_pass(&mut self) {
        self.pass = self.pass.wrapping_add(1);
        if self.pass == 0 {
            self.last.fill((0, 0));
            self.pass = 1;
        }
    }

    /// Whether `(character triangle, big triangle)` is met for the first time
    /// in this pass (as far as the filter remembers); notes it.
    #[inline]
    pub fn first_time(&mut self, character_triangle: u32, big_triangle: u32) -> bool {
        let entry = &mut self.last[character_triangle as usize];
        let seen = *entry == (self.pass, big_triangle);
        *entry = (self.pass, big_triangle);
        !seen
    }
}

#[cfg(test)]
mod tests {
    use super::RepeatFilter;

    /// Against a set of seen pairs: the filter never drops a first meeting,
    /// drops an immediate repeat, and forgets everything at a new pass.
    #[test]
    fn never_drops_a_first_meeting() {
        let mut f = RepeatFilter::new(8);
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
