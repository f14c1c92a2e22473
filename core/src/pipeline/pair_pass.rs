//! Two characters against each other in one frame: both trees refit on
//! demand during one simultaneous traversal (§3's traversal, with two
//! deforming trees); leaves are triangles on both sides, answered by the
//! triangle-triangle test, each side's triangles prepared once for it.

use crate::geometry::tri_tri::prepared_intersect;
use crate::sphere_tree::traverse::LeafPair;
use crate::sphere_tree::{Hierarchy, Workspace, traverse};

use super::character_side::CharacterSide;
use super::counters::FrameCounters;
use super::pass::{Pass, Traversed};
use super::prepared_triangles::PreparedTriangles;

/// Characters `a` and `b` of a world, both already started this frame.
pub(crate) struct PairPass<'a> {
    pub(crate) a: CharacterSide<'a>,
    pub(crate) b: CharacterSide<'a>,
    /// Whether refit time is split from traversal time.
    pub(crate) timed: bool,
}

impl Pass for PairPass<'_> {
    type Hit = (u32, u32);

    fn work(&self) -> (u64, u64) {
        let (ra, sa) = self.a.work();
        let (rb, sb) = self.b.work();
        (ra + rb, sa + sb)
    }

    fn timed(&self) -> bool {
        self.timed
    }

    fn traverse<const TIMED: bool>(
        &mut self,
        ws: &mut Workspace,
        leaf_pairs: &mut Vec<LeafPair>,
    ) -> Traversed {
        let mut ha = self.a.hierarchy::<TIMED>();
        let mut hb = self.b.hierarchy::<TIMED>();
        let stats = traverse(&mut ha, &mut hb, ws, |p| leaf_pairs.push(p));
        Traversed {
            stats,
            refit_ticks: ha.refit_ticks() + hb.refit_ticks(),
            ..Traversed::default()
        }
    }

    fn prepare(&mut self, leaf_pairs: &[LeafPair]) {
        for p in leaf_pairs {
            self.a.ensure_triangle(p.primitive_a);
            self.b.ensure_triangle(p.primitive_b);
        }
    }

    #[inline]
    fn test(
        &mut self,
        leaf_pairs: &[LeafPair],
        k: usize,
        prepared: &mut [PreparedTriangles; 2],
        c: &mut FrameCounters,
    ) -> Option<(u32, u32)> {
        let p = leaf_pairs[k];
        c.tri_tri += 1;
        let [pa, pb] = prepared;
        let ta = pa.get(p.primitive_a, || self.a.triangle(p.primitive_a));
        let tb = pb.get(p.primitive_b, || self.b.triangle(p.primitive_b));
        prepared_intersect(ta, tb).then_some((p.primitive_a, p.primitive_b))
    }

    /// Leaves are distinct triangles on both sides: no repeats to remove.
    fn finish(hits: &mut Vec<(u32, u32)>) {
        super::pass::sort_pairs(hits);
    }
}
