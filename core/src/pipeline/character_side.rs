//! A character as a pass sees it: its tree refit on demand (§3, "Sphere
//! update"), and its triangles skinned on demand, both at most once a frame
//! whichever pass asks first.

use nalgebra::Matrix4;

use crate::character::{Character, OnDemandSkin, SkinPose, SkinningModel};
use crate::geometry::leveled_box::LeveledBox;
use crate::geometry::{Sphere, Triangle};
use crate::mesh::TriangleId;
use crate::sphere_tree::character::CharacterTree;
use crate::sphere_tree::refit::{RefitState, Refitter};
use crate::sphere_tree::{Hierarchy, NodeId, SphereTree};

use super::counters::ticks;

/// One character's frame, borrowed for a pass: what it is (mesh, skeleton,
/// tree), how it is posed, and its refit and skinning state this frame.
pub(crate) struct CharacterSide<'a> {
    pub(crate) character: &'a Character,
    pub(crate) tree: &'a CharacterTree,
    pub(crate) model: SkinningModel,
    pub(crate) pose: SkinPose<'a>,
    pub(crate) refit: &'a mut RefitState,
    pub(crate) skin: &'a mut OnDemandSkin,
}

impl CharacterSide<'_> {
    /// The same character for a shorter borrow (one pass of several).
    #[inline]
    pub(crate) fn reborrow(&mut self) -> CharacterSide<'_> {
        CharacterSide {
            character: self.character,
            tree: self.tree,
            model: self.model,
            pose: self.pose,
            refit: self.refit,
            skin: self.skin,
        }
    }

    /// Spheres refit and vertices skinned this frame so far.
    #[inline]
    pub(crate) fn work(&self) -> (u64, u64) {
        (self.refit.refits, self.skin.skinned())
    }

    /// The tree as traversal reads it: each sphere refit the first time it
    /// is asked for this frame; with `TIMED`, the time-stamp ticks spent
    /// refitting are counted.
    #[inline]
    pub(crate) fn hierarchy<const TIMED: bool>(&mut self) -> TimedRefit<'_, TIMED> {
        self.hierarchy_and_skin().0
    }

    /// [`Self::hierarchy`] beside this frame's skinned vertices, for a pass
    /// that reads positions while it walks.
    #[inline]
    pub(crate) fn hierarchy_and_skin<const TIMED: bool>(
        &mut self,
    ) -> (TimedRefit<'_, TIMED>, &OnDemandSkin) {
        (TimedRefit::new(self.tree, self.pose, self.refit), self.skin)
    }

    /// Skins the corners of triangle `t` unless done this frame.
    #[inline(always)]
    pub(crate) fn ensure_triangle(&mut self, t: u32) {
        for v in self.character.mesh.indices()[t as usize] {
            self.skin.ensure(self.pose, self.character, self.model, v);
        }
    }

    /// Triangle `t` as skinned this frame ([`Self::ensure_triangle`] first).
    #[inline]
    pub(crate) fn triangle(&self, t: u32) -> Triangle {
        self.skin
            .triangle(self.character.mesh.indices()[TriangleId(t).index()])
    }

    /// The root sphere this frame, refit now if not yet (`None`: an empty
    /// tree).
    pub(crate) fn root_sphere(&mut self) -> Option<Sphere> {
        if self.tree.tree.is_empty() {
            return None;
        }
        let base = *self.pose.base;
        Some(
            Refitter {
                tree: self.tree,
                skin: self.pose.skin,
                state: self.refit,
            }
            .fresh(NodeId::ROOT, &base),
        )
    }

    /// Refits ahead the nodes asked for last frame, when the method does
    /// (`sphere_tree::refit_ahead`); nothing otherwise.
    pub(crate) fn refit_ahead(&mut self) {
        let base = *self.pose.base;
        Refitter {
            tree: self.tree,
            skin: self.pose.skin,
            state: self.refit,
        }
        .refit_ahead(&base);
    }
}

/// [`Hierarchy`] over a character tree that refits on first request and,
/// if `TIMED`, counts the time-stamp ticks spent refitting (two `rdtsc` per
/// refit: a quarter of the traversal's time on a virtual machine, so `bench`
/// turns it off).
pub(crate) struct TimedRefit<'a, const TIMED: bool> {
    pub(crate) refitter: Refitter<'a>,
    pub(crate) base: Matrix4<f32>,
    pub(crate) ticks: u64,
}

impl<'a, const TIMED: bool> TimedRefit<'a, TIMED> {
    /// `tree` refit into `refit` for `pose` (a borrow of a
    /// [`CharacterSide`]'s refit state alone, its skinning left free).
    pub(crate) fn new(
        tree: &'a CharacterTree,
        pose: SkinPose<'a>,
        refit: &'a mut RefitState,
    ) -> Self {
        TimedRefit {
            refitter: Refitter {
                tree,
                skin: pose.skin,
                state: refit,
            },
            base: *pose.base,
            ticks: 0,
        }
    }
}

impl<const TIMED: bool> Hierarchy for TimedRefit<'_, TIMED> {
    #[inline]
    fn tree(&self) -> &SphereTree {
        &self.refitter.tree.tree
    }

    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        if self.refitter.state.is_fresh(id) {
            return self.refitter.state.spheres[id.index()];
        }
        // Refit ahead (then only marked asked for), or refit now.
        let base = self.base;
        if !TIMED {
            return self.refitter.fresh(id, &base);
        }
        let t0 = ticks();
        let s = self.refitter.fresh(id, &base);
        self.ticks += ticks().wrapping_sub(t0);
        s
    }

    #[inline]
    fn prefetch(&self, id: NodeId) {
        self.refitter.prefetch(id);
    }

    #[inline]
    fn refit_ticks(&self) -> u64 {
        self.ticks
    }

    const BOXES: bool = true;

    #[inline]
    fn node_box(&mut self, id: NodeId) -> LeveledBox {
        self.refitter.node_box(id)
    }

    #[inline]
    fn has_boxes(&self) -> bool {
        self.refitter.state.has_boxes()
    }

    #[inline]
    fn prefetch_box(&self, id: NodeId) {
        self.refitter.prefetch_box(id);
    }
}
