//! Triangles prepared for the triangle-triangle test
//! ([`Prepared`]), kept during one
//! narrow phase in a small direct-mapped table keyed by triangle index.
//!
//! Two brushing characters' overlapping leaf pairs name each triangle
//! several times: in `scenarios/crowd.toml` (de-duplication off, the frame
//! mean over 60 frames) 1,905 leaf pairs between characters name 258
//! distinct triangles of one side and 257 of the other. Preparing a
//! triangle (its corners in `f64`, two edges, the normal, the snapping
//! scale) is about half of a test that ends at the first plane-side exit,
//! and most end there; the answers are those of the unprepared test, bit
//! for bit (the same arithmetic). Traversal hands the pairs of one leaf
//! over in a row, so a small table keyed by the index's low bits keeps
//! most repeats.

use crate::geometry::Triangle;
use crate::geometry::tri_tri::Prepared;

/// Entries of a table (a power of two).
const SLOTS: usize = 64;

/// Prepared triangles of one mesh in its current pose.
#[derive(Clone, Debug)]
pub struct PreparedTriangles {
    /// `(tag, preparation)`: the tag is `pass << 32 | triangle index`, so
    /// an entry of an earlier pass never matches and clearing writes
    /// nothing; 0 (pass 0 is never current) marks a free entry.
    slots: Box<[(u64, Prepared<f64>)]>,
    /// The current pass, from 1.
    pass: u32,
}

impl Default for PreparedTriangles {
    fn default() -> Self {
        Self::new()
    }
}

impl PreparedTriangles {
    pub fn new() -> Self {
        let none = Prepared::new(&Triangle::new(
            Default::default(),
            Default::default(),
            Default::default(),
        ));
        Self {
            slots: vec![(0, none); SLOTS].into_boxed_slice(),
            pass: 1,
        }
    }

    /// Forgets every triangle (call when the positions have changed, e.g.
    /// at a narrow phase's start). Writes nothing but the pass number,
    /// except once every 2³² − 1 passes, when it wraps.
    pub fn clear(&mut self) {
        self.pass = self.pass.wrapping_add(1);
        if self.pass == 0 {
            for s in self.slots.iter_mut() {
                s.0 = 0;
            }
            self.pass = 1;
        }
    }

    /// Whether triangle `id` is kept (prepared since the last
    /// [`PreparedTriangles::clear`]): [`PreparedTriangles::get`] would not
    /// ask for it.
    #[inline(always)]
    pub fn holds(&self, id: u32) -> bool {
        self.slots[id as usize & (SLOTS - 1)].0 == (self.pass as u64) << 32 | id as u64
    }

    /// Triangle `id` prepared, from `triangle()` unless kept since the last
    /// [`PreparedTriangles::clear`].
    #[inline(always)]
    pub fn get(&mut self, id: u32, triangle: impl FnOnce() -> Triangle) -> &Prepared<f64> {
        let tag = (self.pass as u64) << 32 | id as u64;
        let slot = &mut self.slots[id as usize & (SLOTS - 1)];
        if slot.0 != tag {
            *slot = (tag, Prepared::new(&triangle()));
        }
        &slot.1
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::geometry::tropp::{prepared_intersect, triangles_intersect};

    fn tri(seed: u32) -> Triangle {
        let f = |k: u32| {
            ((seed.wrapping_mul(2_654_435_761).wrapping_add(k * 40_503)) % 1000) as f32 / 500.0
        };
        Triangle::new(
            Point::new(f(1), f(2), f(3)),
            Point::new(f(4), f(5), f(6)),
            Point::new(f(7), f(8), f(9)),
        )
    }

    /// Triangles kept in the table, evicted by others of the same slot,
    /// and forgotten by `clear`, against the unprepared test on every pair:
    /// the same answers, and `triangle()` asked for exactly when the entry
    /// does not hold the triangle.
    #[test]
    fn table_answers_as_the_unprepared_test_and_forgets_on_clear() {
        let mut table = PreparedTriangles::new();
        let mut other = PreparedTriangles::new();
        let mut made = 0;
        let mut hits = 0;
        for round in 0..4 {
            if round >= 2 {
                table.clear();
            }
            for id in [1u32, 2, 1, 65, 1, 3, 200, 2] {
                let mut asked = false;
                let held = table.holds(id);
                let a = *table.get(id, || {
                    asked = true;
                    tri(id)
                });
                made += asked as u32;
                assert_eq!(held, !asked, "held {id}");
                for j in 0..40u32 {
                    let b = other.get(j, || tri(j + 7));
                    let expect = triangles_intersect(&tri(id), &tri(j + 7));
                    assert_eq!(prepared_intersect(&a, b), expect, "{id} against {j}");
                    hits += expect as u32;
                }
            }
        }
        // Round 0 makes 1, 2, 65 (evicting 1), 1 (evicting 65), 3 and 200;
        // round 1 finds all but 65 and 1 (one slot) kept; after `clear`,
        // rounds 2 and 3 make what round 0 made.
        assert_eq!(made, 6 + 2 + 6 + 6, "triangles prepared");
        assert!(hits > 0, "some pairs intersect");
    }

    /// When the pass number wraps back to 1, an entry kept from the first
    /// pass 1 does not come back.
    #[test]
    fn a_wrapped_pass_number_forgets_the_first_pass() {
        let mut table = PreparedTriangles::new();
        table.get(5, || tri(5));
        table.pass = u32::MAX;
        table.clear();
        assert_eq!(table.pass, 1);
        let mut asked = false;
        table.get(5, || {
            asked = true;
            tri(5)
        });
        assert!(asked, "a stale entry was found");
    }
}
