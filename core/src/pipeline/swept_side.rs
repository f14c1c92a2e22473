//! A character over a frame step (continuous detection, the paper's future
//! work, §7; docs/ccd.md, "Swept hierarchies"): its swept spheres
//! (`sphere_tree::swept`), refit on demand at both ends, and its triangles
//! skinned on demand at both ends.
//!
//! [`SweepState`] keeps what one character needs between steps: refit
//! states and on-demand skinning at both ends. The end of one step is the
//! start of the next, so its states are swapped, not redone; after the first
//! step nothing is allocated.

use crate::character::{Character, OnDemandSkin, SkinPose, SkinningModel};
use crate::geometry::Sphere;
use crate::geometry::ccd_triangles::MovingTriangle;
use crate::sphere_tree::NodeId;
use crate::sphere_tree::character::CharacterTree;
use crate::sphere_tree::refit::{RefitState, Refitter};
use crate::sphere_tree::swept::{SweptCache, SweptCharacter};

use super::continuous_narrow::wide;

/// The poses of one character at the start and the end of a step.
#[derive(Clone, Copy)]
pub(crate) struct StepPose<'a> {
    pub(crate) start: SkinPose<'a>,
    pub(crate) end: SkinPose<'a>,
}

/// One character's continuous state.
#[derive(Debug)]
pub struct SweepState {
    start: RefitState,
    end: RefitState,
    skin_start: OnDemandSkin,
    skin_end: OnDemandSkin,
    cache: SweptCache,
    /// The start state's refits and skinned vertices when the step began
    /// (carried over from the previous step's end).
    start_refits: u64,
    start_skinned: u64,
}

impl SweepState {
    /// Continuous state for a character of `vertices` vertices and
    /// `joints` joints whose tree is `tree`.
    pub fn new(tree: &CharacterTree, joints: usize, vertices: usize) -> Self {
        Self {
            start: RefitState::new(tree, joints),
            end: RefitState::new(tree, joints),
            skin_start: OnDemandSkin::new(vertices),
            skin_end: OnDemandSkin::new(vertices),
            cache: SweptCache::new(tree.tree.len()),
            start_refits: 0,
            start_skinned: 0,
        }
    }

    /// Starts a step. With `continues`, the last step ended at this step's
    /// start pose: its end states become the start states (nothing refit or
    /// skinned again); otherwise both ends start empty.
    pub(crate) fn begin_step(&mut self, pose: StepPose<'_>, continues: bool) {
        if continues {
            std::mem::swap(&mut self.start, &mut self.end);
            std::mem::swap(&mut self.skin_start, &mut self.skin_end);
        } else {
            self.start
                .begin_frame_with_base(pose.start.skin, pose.start.base);
            self.skin_start.begin_frame();
        }
        self.end.begin_frame_with_base(pose.end.skin, pose.end.base);
        self.skin_end.begin_frame();
        self.cache.begin_step();
        self.start_refits = self.start.refits;
        self.start_skinned = self.skin_start.skinned();
    }

    /// Spheres refit this step, at both ends (the start's refits of the
    /// previous step, whose end it was, not counted).
    pub fn refits(&self) -> u64 {
        self.start.refits - self.start_refits + self.end.refits
    }

    /// Vertices skinned this step, at both ends (likewise).
    pub fn skinned(&self) -> u64 {
        self.skin_start.skinned() - self.start_skinned + self.skin_end.skinned()
    }

    /// The refit states at the start and the end (valid where refit).
    pub fn refit_states(&self) -> (&RefitState, &RefitState) {
        (&self.start, &self.end)
    }

    /// Node `id`'s swept sphere this step, if a pass reached it.
    pub fn swept_sphere(&self, id: NodeId) -> Option<Sphere> {
        self.cache.is_fresh(id).then(|| self.cache.swept(id))
    }
}

/// A character's step, borrowed for a pass.
pub(crate) struct SweptSide<'a> {
    pub(crate) character: &'a Character,
    pub(crate) tree: &'a CharacterTree,
    pub(crate) model: SkinningModel,
    pub(crate) pose: StepPose<'a>,
    pub(crate) state: &'a mut SweepState,
}

impl SweptSide<'_> {
    /// The same character for a shorter borrow (one pass of several).
    pub(crate) fn reborrow(&mut self) -> SweptSide<'_> {
        SweptSide {
            character: self.character,
            tree: self.tree,
            model: self.model,
            pose: self.pose,
            state: self.state,
        }
    }

    /// Spheres refit and vertices skinned this step so far.
    pub(crate) fn work(&self) -> (u64, u64) {
        (self.state.refits(), self.state.skinned())
    }

    /// The swept hierarchy of the step, and the cache its guard reads.
    pub(crate) fn hierarchy(&mut self) -> (SweptCharacter<'_>, &SweptCache) {
        let s = &mut *self.state;
        (
            SweptCharacter {
                start: Refitter {
                    tree: self.tree,
                    skin: self.pose.start.skin,
                    state: &mut s.start,
                },
                start_base: *self.pose.start.base,
                end: Refitter {
                    tree: self.tree,
                    skin: self.pose.end.skin,
                    state: &mut s.end,
                },
                end_base: *self.pose.end.base,
                cache: &s.cache,
            },
            &s.cache,
        )
    }

    /// The root's swept sphere this step (refit at both ends if not yet).
    pub(crate) fn root_sphere(&mut self) -> Option<Sphere> {
        use crate::sphere_tree::Hierarchy;
        if self.tree.tree.is_empty() {
            return None;
        }
        Some(self.hierarchy().0.sphere(NodeId::ROOT))
    }

    /// Leaf `id`'s refit spheres at both ends (fresh after a pass reached it).
    pub(crate) fn leaf_sweep(&self, id: NodeId) -> (Sphere, Sphere) {
        let e = self.state.cache.ends(id);
        (e.start, e.end)
    }

    /// Character triangle `t` at both ends, skinning its corners on demand.
    pub(crate) fn moving_triangle(&mut self, t: u32) -> MovingTriangle<f64> {
        let idx = self.character.mesh.indices()[t as usize];
        let (character, model) = (self.character, self.model);
        let at = |skin: &mut OnDemandSkin, pose: SkinPose<'_>| {
            idx.map(|v| {
                skin.ensure(pose, character, model, v);
                wide(&skin.position(v))
            })
        };
        let start = at(&mut self.state.skin_start, self.pose.start);
        let end = at(&mut self.state.skin_end, self.pose.end);
        MovingTriangle { start, end }
    }
}
