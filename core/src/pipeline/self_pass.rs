//! A character against itself in one frame (self-collision; ours): its
//! tree walked against itself ([`traverse_self`]), refit on demand as in
//! every other pass; pairs of triangles sharing a corner dropped (the
//! neighbour rule); pairs one joint moves skipped where their rest distance
//! proves them apart ([`SelfContactData`]); nodes and pairs of nodes that
//! cover a disk facing one direction with a simple outline skipped
//! ([`crate::sphere_tree::flat_patches`]); every other overlapping leaf
//! pair answered by the triangle-triangle test.

use crate::geometry::star_contour::is_star_around_mean;
use crate::geometry::tri_tri::prepared_intersect;
use crate::sphere_tree::NodeId;
use crate::sphere_tree::character::CharacterTree;
use crate::sphere_tree::normal_cones::{NodeCones, NormalCone};
use crate::sphere_tree::self_contact::{RigidGaps, SelfContactData};
use crate::sphere_tree::self_traverse::traverse_self;
use crate::sphere_tree::traverse::LeafPair;
use crate::sphere_tree::{Hierarchy, SphereTree, Workspace};

use super::character_side::CharacterSide;
use super::counters::FrameCounters;
use super::pass::{Pass, Traversed};
use super::prepared_triangles::PreparedTriangles;

/// What a self pass culls (each exact; off to measure what it saves).
#[derive(Clone, Copy, Debug)]
pub(crate) struct SelfCulling {
    /// Parts one joint moves that lie apart at rest.
    pub(crate) rigid: bool,
    /// Disks facing one direction with a simple outline.
    pub(crate) normal_cones: bool,
}

/// Character `side`, already started this frame, against itself.
pub(crate) struct SelfPass<'a> {
    pub(crate) side: CharacterSide<'a>,
    pub(crate) data: &'a SelfContactData,
    /// This frame's gaps per joint (updated by the pass when culling).
    pub(crate) gaps: &'a mut RigidGaps,
    /// This frame's normal cones (updated by the pass when culling by them).
    pub(crate) cones: &'a mut NodeCones,
    /// What is culled (off: every pair is traversed, for measuring what the
    /// culling saves).
    pub(crate) culling: SelfCulling,
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
        let cull = self.culling.rigid;
        let flat = self.culling.normal_cones && data.flat().is_some();
        if cull {
            self.gaps
                .update(self.side.pose.skin, data.coordinate_bound());
        }
        let gaps = &*self.gaps;
        let tree: &CharacterTree = self.side.tree;
        let topology: &SphereTree = &tree.tree;
        let side = &mut self.side;
        if flat {
            // Every triangle's normal is asked for: every vertex skinned.
            side.skin.skin_all(side.pose, side.character, side.model);
            let (skin, indices) = (&*side.skin, side.character.mesh.indices());
            self.cones
                .update(topology, |t| skin.triangle(indices[t as usize]));
        }
        let (cones, patches) = (&*self.cones, data.flat());
        let (mut h, skin) = side.hierarchy_and_skin::<TIMED>();
        let position = |v: u32| skin.position(v);
        // A disk whose normals all face `d` and whose outline, seen along
        // `d`, is simple has no two triangles without a common corner that
        // meet (`flat_patches`' module doc).
        let proved_flat = |outline: Option<&[u32]>, d: &nalgebra::Vector3<f64>| {
            outline.is_some_and(|o| is_star_around_mean(d, o.len(), |k| position(o[k])))
        };
        let flat_node = |n: NodeId| {
            let c = cones.of(n);
            !c.is_everything()
                && c.faces(&c.axis)
                && proved_flat(patches.and_then(|p| p.node_loop(n)), &c.axis)
        };
        let flat_pair = |i: NodeId, j: NodeId| {
            patches.is_some_and(|p| p.has_pairs(NodeId(i.0.min(j.0))))
                && NormalCone::common_facing(cones.of(i), cones.of(j))
                    .is_some_and(|d| proved_flat(patches.and_then(|p| p.pair_loop(i, j)), &d))
        };
        let stats = traverse_self(
            topology,
            &mut h,
            ws,
            |n| (cull && data.skips_node(gaps, n)) || (flat && flat_node(n)),
            |_, i, j| !((cull && data.skips_pair(gaps, i, j)) || (flat && flat_pair(i, j))),
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
        super::pass::sort_pairs(hits);
    }
}
