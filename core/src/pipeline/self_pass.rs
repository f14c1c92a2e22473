//! A character against itself in one frame (self-collision; ours): its
//! tree walked against itself ([`traverse_self`]), refit on demand as in
//! every other pass; pairs of triangles sharing a corner dropped (the
//! neighbour rule); pairs one joint moves skipped where their rest distance
//! proves them apart ([`SelfContactData`]); every other overlapping leaf
//! pair answered by the triangle-triangle test.

use crate::geometry::tri_tri::prepared_intersect;
use crate::sphere_tree::character::CharacterTree;
use crate::sphere_tree::self_contact::{RigidGaps, SelfContactData};
use crate::sphere_tree::self_traverse::traverse_self;
use crate::sphere_tree::traverse::LeafPair;
use crate::sphere_tree::{Hierarchy, SphereTree, Workspace};

use super::character_side::CharacterSide;
use super::counters::FrameCounters;
use super::pass::{Pass, Traversed};
use super::prepared_triangles::PreparedTriangles;

/// Character `side`, already started this frame, against itself.
pub(crate) struct SelfPass<'a> {
    pub(crate) side: CharacterSide<'a>,
    pub(crate) data: &'a SelfContactData,
    /// This frame's gaps per joint (updated by the pass when culling).
    pub(crate) gaps: &'a mut RigidGaps,
    /// Whether parts one joint moves are skipped (off: every pair is
    /// traversed, for measuring what the culling saves).
    pub(crate) cull_rigid: bool,
    /// Whether refit time is split from traversal time.
    pub(crate) timed: bool,
}

impl Pass for SelfPass<'_> {
    /// The two triangles, lower index first.
    type Hit = (u32, u32);

    fn work(&self) -> (u64, u64) {
        self.side.work()
    }

    fn timed(&self) -> bool {
        self.timed
    }

    fn traverse<const TIMED: bool>(
        &mut self,
        ws: &mut Workspace,
        leaf_pairs: &mut Vec<LeafPair>,
    ) -> Traversed {
        let data = self.data;
        let cull = self.cull_rigid;
        if cull {
            self.gaps
                .update(self.side.pose.skin, data.coordinate_bound());
        }
        let gaps = &*self.gaps;
        let tree: &CharacterTree = self.side.tree;
        let topology: &SphereTree = &tree.tree;
        let mut h = self.side.hierarchy::<TIMED>();
        let stats = traverse_self(
            topology,
            &mut h,
            ws,
            |n| cull && data.skips_node(gaps, n),
            |_, i, j| !(cull && data.skips_pair(gaps, i, j)),
            |_, p| {
                if !data.neighbours(p.primitive_a, p.primitive_b) {
                    leaf_pairs.push(p);
                }
            },
        );
        Traversed {
            stats,
            refit_ticks: h.refit_ticks(),
            ..Traversed::default()
        }
    }

    fn prepare(&mut self, leaf_pairs: &[LeafPair]) {
        for p in leaf_pairs {
            self.side.ensure_triangle(p.primitive_a);
            self.side.ensure_triangle(p.primitive_b);
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
        let ta = pa.get(p.primitive_a, || self.side.triangle(p.primitive_a));
        let tb = pb.get(p.primitive_b, || self.side.triangle(p.primitive_b));
        prepared_intersect(ta, tb).then_some((
            p.primitive_a.min(p.primitive_b),
            p.primitive_a.max(p.primitive_b),
        ))
    }

    /// Each pair of leaves is reached once: no repeats to remove.
    fn finish(hits: &mut Vec<(u32, u32)>) {
        hits.sort_unstable();
    }
}
