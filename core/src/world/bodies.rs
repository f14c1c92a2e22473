//! The bodies of a world and what each keeps between steps.
//!
//! A body is a hierarchy, a triangle source and a pose. A rigid body (a room
//! or a moving object) has its hierarchy built once in its own frame over its
//! triangles; a room's pose is the identity. A character instance has its
//! tree built once (bind space), its pose set every step, and its refit
//! spheres and skinned vertices of the step.

use std::sync::Arc;

use nalgebra::{Isometry3, Matrix4};

use crate::character::{OnDemandSkin, SkinPose};
use crate::geometry::Sphere;
use crate::mesh::TriMesh;
use crate::pipeline::EnvironmentTree;
use crate::pipeline::FrameCounters;
use crate::pipeline::continuous_narrow::{CcdCounters, TimedPair};
use crate::pipeline::pass::PassScratch;
use crate::pipeline::visit_log::TestedNodes;
use crate::pipeline::{Method, SweepState};
use crate::sphere_tree::character::CharacterTree;
use crate::sphere_tree::normal_cones::NodeCones;
use crate::sphere_tree::refit::RefitState;
use crate::sphere_tree::self_contact::{RigidGaps, SelfContactData};

use super::character_model::CharacterModel;
use super::contacts::{Contacts, Detection, ObjectPair, Timed};
use super::groups::CollisionGroups;
use super::handles::CharacterHandle;

/// A room or a moving object: its triangles and their hierarchy, in its
/// own frame, and its pose (object frame → world).
pub(crate) struct RigidBody {
    pub(crate) mesh: Arc<TriMesh>,
    pub(crate) tree: EnvironmentTree,
    pub(crate) pose: Isometry3<f32>,
    /// Whether it takes part in steps, sweeps and queries.
    pub(crate) active: bool,
    /// Which characters it meets.
    pub(crate) groups: CollisionGroups,
}

impl RigidBody {
    /// Whether a character of `groups` is tested against it: it is active
    /// and their groups meet.
    #[inline]
    pub(crate) fn meets(&self, groups: CollisionGroups) -> bool {
        self.active && self.groups.meets(groups)
    }
}

/// Joint matrices as skinning reads them: one skin matrix per joint (world ·
/// inverse bind, placed) and the placed skeleton base.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct JointMatrices {
    pub(crate) skin: Vec<Matrix4<f32>>,
    pub(crate) base: Matrix4<f32>,
}

impl JointMatrices {
    pub(crate) fn as_pose(&self) -> SkinPose<'_> {
        SkinPose {
            skin: &self.skin,
            base: &self.base,
        }
    }
}

/// What a character's own passes (against the rooms and objects) found in
/// a step.
#[derive(Default)]
pub(crate) struct OwnPasses {
    /// Its root sphere this step (`None`: an empty tree).
    pub(crate) root: Option<Sphere>,
    /// Against the rooms, the frame start's refits included.
    pub(crate) rooms: FrameCounters,
    /// Against the objects, root tests of the broad phase included.
    pub(crate) objects: FrameCounters,
    /// Against itself.
    pub(crate) itself: FrameCounters,
    pub(crate) broad_phase_tests: u64,
    pub(crate) body_pairs: u64,
    pub(crate) ccd: CcdCounters,
    /// Seconds the step's start took (stale marks, the root sphere's refit).
    pub(crate) start_seconds: f32,
}

impl OwnPasses {
    /// Adds its counters to a step's: the room and object kinds, the broad
    /// phase's root tests (counted with the objects) and body pairs.
    pub(crate) fn add_to<D: Detection>(&self, out: &mut Contacts<D>) {
        out.by_kind.environment.add(&self.rooms);
        out.by_kind.objects.add(&self.objects);
        out.by_kind.self_contact.add(&self.itself);
        out.by_kind.objects.sphere_sphere += self.broad_phase_tests;
        out.broad_phase_tests += self.broad_phase_tests;
        out.body_pairs += self.body_pairs;
    }
}

/// One character pass's working memory and hits, kept between steps.
pub(crate) struct PassSlot<H> {
    pub(crate) scratch: PassScratch,
    pub(crate) hits: Vec<H>,
}

impl<H> Default for PassSlot<H> {
    fn default() -> Self {
        Self {
            scratch: PassScratch::default(),
            hits: Vec::new(),
        }
    }
}

/// A character of a world: what it is made of, its tree for the world's
/// method, its pose and its state this step.
pub(crate) struct CharacterBody {
    /// Its handle in its world.
    pub(crate) handle: CharacterHandle,
    pub(crate) model: Arc<CharacterModel>,
    pub(crate) tree: Arc<CharacterTree>,
    pub(crate) pose: JointMatrices,
    /// A pose being checked before it replaces [`Self::pose`].
    pub(crate) next_pose: JointMatrices,
    /// Each joint's world matrix (for poses given as local transforms).
    pub(crate) joint_world: Vec<Matrix4<f32>>,
    pub(crate) refit: RefitState,
    pub(crate) skin: OnDemandSkin,
    /// One slot per room: its leaf pairs and hits this step.
    pub(crate) rooms: Vec<PassSlot<(u32, u32)>>,
    /// Which nodes of each room the step's traversal tested, when asked.
    pub(crate) visits: Option<Vec<TestedNodes>>,
    /// The contacts of its last object pass (each object pass borrows its
    /// scratch from the world's pass pool).
    pub(crate) object_hits: Vec<(u32, u32)>,
    /// This step's object contacts.
    pub(crate) object_pairs: Vec<ObjectPair>,
    /// Its self pass, in worlds that detect self-contact (none otherwise:
    /// an instance pays nothing for it).
    pub(crate) itself: Option<Box<SelfState>>,
    pub(crate) own: OwnPasses,
    /// Continuous detection's state, when on.
    pub(crate) sweep: Option<Box<CharacterSweep>>,
    /// Whether `refit` and `skin` are in a frame of the current pose (a
    /// step or a query began it since the pose was last set).
    pub(crate) frame_of_pose: bool,
    /// Whether a step ran in that frame (a second step at the same pose
    /// starts a frame of its own, as it always did).
    pub(crate) stepped_in_frame: bool,
    /// Spheres refit and vertices skinned in the frame before the step
    /// began (by queries): not the step's work.
    pub(crate) before_step: (u64, u64),
    /// Whether it takes part in steps, sweeps and queries
    /// ([`CollisionWorld::set_character_active`](super::CollisionWorld::set_character_active)).
    pub(crate) active: bool,
    /// Which bodies it meets.
    pub(crate) groups: CollisionGroups,
}

/// A character's self pass: what it knows of the character model (shared
/// by its instances), its working memory and contacts this step, and this
/// step's gaps per joint.
pub(crate) struct SelfState {
    pub(crate) data: Arc<SelfContactData>,
    pub(crate) slot: PassSlot<(u32, u32)>,
    pub(crate) gaps: RigidGaps,
    /// This step's normal cones of the character tree's nodes.
    pub(crate) cones: NodeCones,
}

impl SelfState {
    pub(crate) fn new(data: Arc<SelfContactData>) -> Self {
        Self {
            data,
            slot: PassSlot::default(),
            gaps: RigidGaps::default(),
            cones: NodeCones::default(),
        }
    }
}

/// A character's continuous state: its refit and skinning at both ends of
/// the step, the pose at its start, and its passes' memory.
pub(crate) struct CharacterSweep {
    pub(crate) state: SweepState,
    /// The pose at the start of the next sweep (the end of the last).
    pub(crate) start: JointMatrices,
    /// Whether `state`'s end is `start` (the last sweep ended there).
    pub(crate) continues: bool,
    /// Whether the last sweep recorded `start` while the character was
    /// active (only then may the next sweep detect for it: a character set
    /// active again starts its steps where it is, as a first sweep does).
    pub(crate) primed: bool,
    /// Whether this sweep swept it (its contacts and counters are this
    /// sweep's; otherwise it has none).
    pub(crate) swept: bool,
    pub(crate) rooms: Vec<PassSlot<TimedPair>>,
    pub(crate) objects: PassSlot<TimedPair>,
    pub(crate) object_pairs: Vec<Timed<ObjectPair>>,
    /// Its step against itself, in worlds that test self-contact.
    pub(crate) itself: Option<PassSlot<TimedPair>>,
}

impl CharacterBody {
    pub(crate) fn new(
        handle: CharacterHandle,
        model: Arc<CharacterModel>,
        method: Method,
        tree: Arc<CharacterTree>,
    ) -> Self {
        let c = model.character();
        let joints = c.skeleton.len();
        let mut refit = RefitState::new(&tree, joints);
        refit.set_refit_ahead(method.refits_ahead());
        let mut world = vec![Matrix4::identity(); joints];
        let mut skin = vec![Matrix4::identity(); joints];
        c.skeleton
            .world_matrices(c.skeleton.rest_pose_ref(), &mut world);
        c.skeleton.skin_matrices(&world, &mut skin);
        let pose = JointMatrices {
            skin,
            base: *c.skeleton.base(),
        };
        Self {
            handle,
            tree,
            next_pose: pose.clone(),
            pose,
            joint_world: world,
            refit,
            skin: OnDemandSkin::new(c.mesh.vertex_count()),
            rooms: Vec::new(),
            visits: None,
            object_hits: Vec::new(),
            object_pairs: Vec::new(),
            itself: None,
            own: OwnPasses::default(),
            sweep: None,
            frame_of_pose: false,
            stepped_in_frame: false,
            before_step: (0, 0),
            active: true,
            groups: CollisionGroups::ALL,
            model,
        }
    }

    /// The pose changed: the next step or query starts a frame.
    pub(crate) fn pose_changed(&mut self) {
        self.frame_of_pose = false;
    }

    /// Before a step's passes: starts a frame unless a query already
    /// started one at this pose (then its refit spheres and skinned
    /// vertices serve the step: nothing is refit twice).
    pub(crate) fn begin_step_frame(&mut self) {
        if !self.frame_of_pose || self.stepped_in_frame {
            self.begin_step();
        }
        self.frame_of_pose = true;
        self.stepped_in_frame = true;
        self.before_step = (self.refit.refits, self.skin.skinned());
    }

    /// Spheres refit and vertices skinned since the step began.
    pub(crate) fn step_work(&self) -> (u64, u64) {
        (
            self.refit.refits - self.before_step.0,
            self.skin.skinned() - self.before_step.1,
        )
    }

    /// Before a query: starts a frame unless one is open at this pose.
    pub(crate) fn begin_query_frame(&mut self) {
        if !self.frame_of_pose {
            self.begin_step();
            self.frame_of_pose = true;
            self.stepped_in_frame = false;
        }
    }

    /// A step that leaves the character out (it is inactive): no
    /// contacts, no counters, nothing refit or skinned.
    pub(crate) fn sit_out_step(&mut self) {
        self.own = OwnPasses::default();
        for slot in &mut self.rooms {
            slot.hits.clear();
        }
        if let Some(s) = self.itself.as_deref_mut() {
            s.slot.hits.clear();
        }
        self.object_pairs.clear();
        self.before_step = (self.refit.refits, self.skin.skinned());
    }

    /// Starts a step: every sphere and skinned vertex of the last one is
    /// stale from here on (refit and skinning then happen on demand in the
    /// passes of this step, each at most once).
    pub(crate) fn begin_step(&mut self) {
        self.refit
            .begin_frame_with_base(&self.pose.skin, &self.pose.base);
        self.skin.begin_frame();
    }
}
