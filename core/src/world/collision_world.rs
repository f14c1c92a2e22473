//! [`CollisionWorld`]: the bodies an engine hands in, by handle, and their
//! poses; one method's hierarchies built once per body.

use std::sync::{Arc, Mutex, MutexGuard};

use nalgebra::{Isometry3, Matrix4};

use crate::character::OnDemandSkin;
use crate::character::{PoseBuffers, SkinPose, Trs};
use crate::geometry::Sphere;
use crate::geometry::ccd_root_finder::CcdParams;
use crate::io::limits::{MAX_COORDINATE, within_range};
use crate::mesh::TriMesh;
use crate::pipeline::visit_log::TestedNodes;
use crate::pipeline::{DEFAULT_THRESHOLD, EnvironmentTree, Method, SweepState};
use crate::sphere_tree::BuildParams;
use crate::sphere_tree::character::CharacterTree;
use crate::sphere_tree::refit::RefitState;
use crate::sphere_tree::self_contact::SelfContactData;
use crate::sphere_tree::traverse::LeafPair;

use super::bodies::{CharacterBody, PassSlot, RigidBody, SelfState};
use super::broad_phase::SortAndSweep;
use super::character_model::CharacterModel;
use super::contacts::StepContacts;
use super::continuous_state::ContinuousState;
use super::error::WorldError;
use super::groups::CollisionGroups;
use super::handles::{CharacterHandle, ObjectHandle, RoomHandle};
use super::pass_graph::PassGraph;
use super::pass_pool::PassPool;

/// How a world builds its hierarchies and measures its steps.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WorldSettings {
    /// Big-triangle threshold: a room or object triangle whose longest edge
    /// exceeds it gets the method's division (§4–5), in model units.
    pub threshold: f32,
    /// How rigid bodies' trees are built (the paper's collapse of similar
    /// spheres, §3); characters' trees are built from it as the method says
    /// ([`Method::character_build`]).
    pub build: BuildParams,
    /// Whether each pass splits its refit time from its traversal time (two
    /// time-stamp reads per refit).
    pub time_refit: bool,
    /// Whether each character is also tested against itself (pair kind
    /// `self`: triangles sharing a corner are never a contact), as it is
    /// added; [`CollisionWorld::set_self_collision`] changes it for one
    /// character. Its data (welds, the joint moving each node, rest
    /// distances) is computed once per character model.
    pub self_collision: bool,
    /// Whether the self pass skips parts one joint moves that lie apart at
    /// rest (exact: `sphere_tree::self_contact`); off only to measure what
    /// that saves.
    pub self_rigid_culling: bool,
    /// Whether the self pass skips a node, or a pair of nodes, whose
    /// triangles form a disk of the mesh facing one direction with a simple
    /// outline seen along it (normal cones with their contour test, exact:
    /// `sphere_tree::flat_patches`). Off by default: measured, it does not
    /// pay on our trees (docs/self-collision.md).
    pub self_normal_cone_culling: bool,
}

impl Default for WorldSettings {
    fn default() -> Self {
        Self {
            threshold: DEFAULT_THRESHOLD,
            build: BuildParams::default(),
            time_refit: true,
            self_collision: false,
            self_rigid_culling: true,
            self_normal_cone_culling: false,
        }
    }
}

/// The state of one character pair's pass, kept between steps.
#[derive(Default)]
pub(crate) struct PairState {
    pub(crate) a: u32,
    pub(crate) b: u32,
    pub(crate) counters: crate::pipeline::FrameCounters,
    /// The pair's contacts this step.
    pub(crate) hits: Vec<(u32, u32)>,
}

/// Collision detection of skinned characters against static rooms, moving
/// rigid objects and each other, with one method (paper §3–6; our pruned
/// methods beside the paper's).
///
/// Bodies come from the caller's data and are named by handle; each step the
/// caller poses them (joint transforms for characters, rigid transforms for
/// objects) and reads the contacts by handle and pair kind, with the
/// counters of the paper's operation model. The step runs on the caller's
/// rayon pool, or rayon's global one outside any pool; the contacts do not
/// depend on the number of threads. After the first steps have sized its
/// buffers, a step allocates nothing.
///
/// ```
/// use std::sync::Arc;
/// use cornertree::character::skinning::Influences;
/// use cornertree::character::{Character, Joint, Skeleton, SkinningModel, Trs};
/// use cornertree::geometry::Point;
/// use cornertree::mesh::TriMesh;
/// use cornertree::pipeline::Method;
/// use cornertree::world::{CharacterModel, CollisionWorld};
/// use nalgebra::{Isometry3, Matrix4};
///
/// // A floor of two triangles, 4 m by 4 m.
/// let floor = TriMesh::new(
///     vec![
///         Point::new(-2.0, 0.0, -2.0),
///         Point::new(2.0, 0.0, -2.0),
///         Point::new(2.0, 0.0, 2.0),
///         Point::new(-2.0, 0.0, 2.0),
///     ],
///     vec![[0, 2, 1], [0, 3, 2]],
/// )
/// .unwrap();
/// // A character of one joint: a tetrahedron 20 cm tall above its joint.
/// let joint = Joint {
///     name: "root".into(),
///     parent: None,
///     rest: Trs::IDENTITY,
///     inverse_bind: Matrix4::identity(),
/// };
/// let skeleton = Skeleton::new(vec![joint], Matrix4::identity()).unwrap();
/// let tetrahedron = TriMesh::new(
///     vec![
///         Point::new(-0.1, 0.0, -0.1),
///         Point::new(0.1, 0.0, -0.1),
///         Point::new(0.0, 0.0, 0.1),
///         Point::new(0.0, 0.2, 0.0),
///     ],
///     vec![[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]],
/// )
/// .unwrap();
/// let weights = Influences::new(vec![[0; 4]; 4], vec![[1.0, 0.0, 0.0, 0.0]; 4], 1).unwrap();
/// let body = Character::new("tetra".into(), skeleton, tetrahedron, weights, Vec::new());
///
/// let mut world = CollisionWorld::new(Method::UndividedPrunedTriTri);
/// let room = world.add_room(Arc::new(floor)).unwrap();
/// let model = CharacterModel::new(body, SkinningModel::Linear).unwrap();
/// let tetra = world.add_character(Arc::new(model)).unwrap();
///
/// // Half sunk into the floor, inside its first triangle: the three side
/// // faces cross that triangle, the base is below it.
/// let sunk = Isometry3::translation(0.5, -0.1, -0.5);
/// world.set_joint_transforms(tetra, &[Trs::IDENTITY], &sunk).unwrap();
/// let contacts = world.step();
/// let hits = contacts.room_contacts_of(tetra);
/// assert_eq!(hits.len(), 3);
/// let pairs: Vec<(u32, u32)> = hits.iter().map(|c| (c.triangle, c.room_triangle)).collect();
/// assert_eq!(pairs, [(1, 0), (2, 0), (3, 0)]);
/// assert!(hits.iter().all(|c| c.room == room));
///
/// // Lifted 1 m: nothing touches.
/// let lifted = Isometry3::translation(0.0, 1.0, 0.0);
/// world.set_joint_transforms(tetra, &[Trs::IDENTITY], &lifted).unwrap();
/// assert!(world.step().is_empty());
///
/// // A transform that is not a number is refused, not a panic.
/// let broken = Isometry3::translation(f32::NAN, 0.0, 0.0);
/// assert!(world.set_joint_transforms(tetra, &[Trs::IDENTITY], &broken).is_err());
/// ```
pub struct CollisionWorld {
    pub(crate) method: Method,
    pub(crate) settings: WorldSettings,
    pub(crate) rooms: Vec<RigidBody>,
    pub(crate) objects: Vec<RigidBody>,
    /// Each object's root sphere in the world this step.
    pub(crate) object_roots: Vec<Option<Sphere>>,
    pub(crate) characters: Vec<Mutex<CharacterBody>>,
    /// Character pairs whose roots met this step, `(i, j)` with `i < j`.
    pub(crate) candidates: Vec<(u32, u32)>,
    /// Each character's root sphere this step, for the broad phase.
    pub(crate) character_roots: Vec<Option<Sphere>>,
    /// The broad phase between characters.
    pub(crate) broad_phase: SortAndSweep,
    pub(crate) pairs: Vec<Mutex<PairState>>,
    /// The step's passes and the order they may run in.
    pub(crate) graph: PassGraph,
    /// What the passes running borrow, one set per thread.
    pub(crate) lent: PassPool,
    pub(crate) contacts: StepContacts,
    pub(crate) continuous: Option<Box<ContinuousState>>,
    /// Whether passes against rooms log the room nodes they test.
    pub(crate) visit_logs: bool,
}

/// A character of a world as observers read it after a step (its tree,
/// this step's refit spheres and skinned vertices, the leaf pairs of its
/// room passes); holds the character while alive.
pub struct CharacterView<'a>(MutexGuard<'a, CharacterBody>);

impl CharacterView<'_> {
    /// What the character is made of.
    pub fn model(&self) -> &Arc<CharacterModel> {
        &self.0.model
    }

    /// Its sphere tree for the world's method.
    pub fn tree(&self) -> &CharacterTree {
        &self.0.tree
    }

    /// This step's refit spheres (valid where refit).
    pub fn refit_state(&self) -> &RefitState {
        &self.0.refit
    }

    /// This step's skinned vertices (those the passes read).
    pub fn skinned(&self) -> &OnDemandSkin {
        &self.0.skin
    }

    /// The pose of the last step, as skinning reads it.
    pub fn pose(&self) -> SkinPose<'_> {
        self.0.pose.as_pose()
    }

    /// The leaf pairs the last step's pass against `room` handed to its
    /// narrow phase (character leaf first).
    pub fn room_leaf_pairs(&self, room: RoomHandle) -> &[LeafPair] {
        self.0
            .rooms
            .get(room.index())
            .map_or(&[], |s| s.scratch.leaf_pairs())
    }

    /// The room nodes the last step's pass against `room` tested, if
    /// [`CollisionWorld::set_visit_log`] is on.
    pub fn visit_log(&self, room: RoomHandle) -> Option<&TestedNodes> {
        self.0.visits.as_ref()?.get(room.index())
    }

    /// The character's continuous state (refit spheres at both ends of the
    /// last sweep), when continuous detection is on.
    pub fn sweep_state(&self) -> Option<&SweepState> {
        self.0.sweep.as_ref().map(|s| &s.state)
    }
}

impl CollisionWorld {
    /// An empty world detecting with `method` under the default settings.
    pub fn new(method: Method) -> Self {
        Self::with_settings(method, WorldSettings::default())
    }

    /// An empty world detecting with `method` under `settings`.
    pub fn with_settings(method: Method, settings: WorldSettings) -> Self {
        Self {
            method,
            settings,
            rooms: Vec::new(),
            objects: Vec::new(),
            object_roots: Vec::new(),
            characters: Vec::new(),
            candidates: Vec::new(),
            character_roots: Vec::new(),
            broad_phase: SortAndSweep::new(),
            pairs: Vec::new(),
            graph: PassGraph::new(0),
            lent: PassPool::default(),
            contacts: StepContacts::default(),
            continuous: None,
            visit_logs: false,
        }
    }

    /// The method every pass uses.
    pub fn method(&self) -> Method {
        self.method
    }

    /// The settings the world was built with.
    pub fn settings(&self) -> &WorldSettings {
        &self.settings
    }

    /// Adds a static room made of `mesh`'s triangles (world coordinates);
    /// its hierarchy is built now, big triangles divided as the method says.
    pub fn add_room(&mut self, mesh: Arc<TriMesh>) -> Result<RoomHandle, WorldError> {
        check_mesh(&mesh, "room")?;
        let tree = EnvironmentTree::build(
            &mesh,
            self.method,
            self.settings.threshold,
            self.settings.build,
        );
        self.rooms.push(RigidBody {
            mesh,
            tree,
            pose: Isometry3::identity(),
            active: true,
            groups: CollisionGroups::ALL,
        });
        let nodes = self.rooms.last().map_or(0, |r| r.tree.tree.len());
        for c in &mut self.characters {
            let c = c.get_mut().expect("no pass panicked");
            c.rooms.push(PassSlot::default());
            if let Some(v) = c.visits.as_mut() {
                v.push(TestedNodes::new(nodes));
            }
        }
        if let Some(cs) = self.continuous.as_mut() {
            let room = self.rooms.last().expect("just added");
            cs.add_room(room, &mut self.characters);
        }
        Ok(RoomHandle(self.rooms.len() as u32 - 1))
    }

    /// Adds a rigid object made of `mesh`'s triangles in its own frame, at
    /// `pose` (object frame → world); its hierarchy is built now, once, in
    /// its own frame.
    pub fn add_object(
        &mut self,
        mesh: Arc<TriMesh>,
        pose: Isometry3<f32>,
    ) -> Result<ObjectHandle, WorldError> {
        check_mesh(&mesh, "object")?;
        let h = ObjectHandle(self.objects.len() as u32);
        check_object_pose(h, &pose)?;
        let tree = EnvironmentTree::build(
            &mesh,
            self.method,
            self.settings.threshold,
            self.settings.build,
        );
        self.objects.push(RigidBody {
            mesh,
            tree,
            pose,
            active: true,
            groups: CollisionGroups::ALL,
        });
        self.object_roots.push(None);
        if let Some(cs) = self.continuous.as_mut() {
            cs.add_object(&pose);
        }
        Ok(h)
    }

    /// Adds an instance of the character `model` at its rest pose. Its tree
    /// for the world's method is built now, the first time `model` is added;
    /// every later instance of the same `Arc` shares it (and the model's
    /// mesh, skeleton and weights) and holds only its own pose, refit state
    /// and per-step buffers.
    pub fn add_character(
        &mut self,
        model: Arc<CharacterModel>,
    ) -> Result<CharacterHandle, WorldError> {
        let m = self.method;
        let shared = self.characters.iter_mut().find_map(|c| {
            let c = c.get_mut().expect("no pass panicked");
            Arc::ptr_eq(&c.model, &model).then(|| c.tree.clone())
        });
        let tree = shared.unwrap_or_else(|| {
            Arc::new(CharacterTree::build_with_rule(
                model.character(),
                model.kept(),
                model.skinning(),
                m.character_build(self.settings.build),
                m.refit_rule(),
            ))
        });
        let self_data = self
            .settings
            .self_collision
            .then(|| self.self_contact_data(&model, &tree));
        let handle = CharacterHandle(self.characters.len() as u32);
        self.lent
            .fit(model.character().mesh.triangle_count(), tree.tree.len());
        let mut body = CharacterBody::new(handle, model, m, tree);
        body.itself = self_data.map(|d| Box::new(SelfState::new(d)));
        body.rooms = self.rooms.iter().map(|_| PassSlot::default()).collect();
        if self.visit_logs {
            body.visits = Some(self.room_logs());
        }
        if let Some(cs) = self.continuous.as_ref() {
            body.sweep = Some(Box::new(cs.character_sweep(&body, self.rooms.len())));
        }
        self.characters.push(Mutex::new(body));
        Ok(handle)
    }

    /// What the self pass knows of `model` (welds, the joint moving each
    /// node, rest distances): another instance's if one has it, else
    /// computed now.
    fn self_contact_data(
        &mut self,
        model: &Arc<CharacterModel>,
        tree: &CharacterTree,
    ) -> Arc<SelfContactData> {
        let shared = self.characters.iter_mut().find_map(|c| {
            let c = c.get_mut().expect("no pass panicked");
            Arc::ptr_eq(&c.model, model)
                .then(|| c.itself.as_ref().map(|s| s.data.clone()))
                .flatten()
        });
        shared.unwrap_or_else(|| {
            let flat = self.settings.self_normal_cone_culling;
            Arc::new(SelfContactData::new(model.character(), tree, flat))
        })
    }

    /// Turns character `h`'s test against itself (pair kind `self`) on or
    /// off; a character added gets [`WorldSettings::self_collision`]. A
    /// crowd may test only the few characters whose limbs matter against
    /// themselves. Turning it on computes what the self pass knows of the
    /// character's model once per model (shared with the model's other
    /// instances; 0.14 s for the 10,000-vertex humanoid, release build) and
    /// sizes its buffers: it allocates, a step after it does not.
    pub fn set_self_collision(&mut self, h: CharacterHandle, on: bool) -> Result<(), WorldError> {
        let has = self.character_mut(h)?.itself.is_some();
        if has == on {
            return Ok(());
        }
        let data = if on {
            let (model, tree) = {
                let c = self.character_mut(h)?;
                (c.model.clone(), c.tree.clone())
            };
            Some(self.self_contact_data(&model, &tree))
        } else {
            None
        };
        let c = self.character_mut(h)?;
        c.itself = data.map(|d| Box::new(SelfState::new(d)));
        let with_self = c.itself.is_some();
        if let Some(s) = c.sweep.as_mut() {
            s.itself = with_self.then(PassSlot::default);
            // Its sweep state's end is still the last sweep's: only the
            // self pass starts anew.
        }
        Ok(())
    }

    /// Whether character `h` is tested against itself.
    pub fn self_collision_of(&self, h: CharacterHandle) -> Result<bool, WorldError> {
        Ok(self.locked(h)?.itself.is_some())
    }

    /// Rooms, objects and characters added.
    pub fn counts(&self) -> (usize, usize, usize) {
        (self.rooms.len(), self.objects.len(), self.characters.len())
    }

    fn character_mut(&mut self, h: CharacterHandle) -> Result<&mut CharacterBody, WorldError> {
        self.characters
            .get_mut(h.index())
            .map(|c| c.get_mut().expect("no pass panicked"))
            .ok_or(WorldError::UnknownCharacter(h))
    }

    /// Character `h` as observers read it.
    pub fn character(&self, h: CharacterHandle) -> Result<CharacterView<'_>, WorldError> {
        self.locked(h).map(CharacterView)
    }

    /// Character `h`, locked.
    pub(super) fn locked(
        &self,
        h: CharacterHandle,
    ) -> Result<MutexGuard<'_, CharacterBody>, WorldError> {
        self.characters
            .get(h.index())
            .map(|c| c.lock().expect("no pass panicked"))
            .ok_or(WorldError::UnknownCharacter(h))
    }

    fn object_mut(&mut self, h: ObjectHandle) -> Result<&mut RigidBody, WorldError> {
        self.objects
            .get_mut(h.index())
            .ok_or(WorldError::UnknownObject(h))
    }

    fn room_mut(&mut self, h: RoomHandle) -> Result<&mut RigidBody, WorldError> {
        self.rooms
            .get_mut(h.index())
            .ok_or(WorldError::UnknownRoom(h))
    }

    /// Room `h`'s hierarchy and mesh.
    pub fn room(&self, h: RoomHandle) -> Option<(&EnvironmentTree, &TriMesh)> {
        self.rooms.get(h.index()).map(|r| (&r.tree, &*r.mesh))
    }

    /// Object `h`'s hierarchy and mesh (its frame) and its pose.
    pub fn object(&self, h: ObjectHandle) -> Option<(&EnvironmentTree, &TriMesh, Isometry3<f32>)> {
        self.objects
            .get(h.index())
            .map(|o| (&o.tree, &*o.mesh, o.pose))
    }

    /// Sets character `h`'s pose from matrices posed elsewhere (a clip
    /// sampled into `pose` with [`PoseBuffers::pose`] and placed; one pose
    /// handed to several worlds). Only its skin matrices and base are read.
    pub fn set_pose(&mut self, h: CharacterHandle, pose: &PoseBuffers) -> Result<(), WorldError> {
        let c = self.character_mut(h)?;
        let joints = c.pose.skin.len();
        if pose.skin.len() != joints {
            return Err(WorldError::JointCount {
                character: h,
                expected: joints,
                got: pose.skin.len(),
            });
        }
        check_pose(h, pose.skin_pose(), c.model.bind_reach())?;
        c.pose.skin.copy_from_slice(&pose.skin);
        c.pose.base = pose.base;
        c.pose_changed();
        Ok(())
    }

    /// Sets character `h`'s pose from each joint's transform relative to its
    /// parent (`local`, the skeleton's order) and a placement of the whole
    /// character in the world. Refused, and the last pose kept, when a value
    /// is not finite or the pose takes a vertex out of the coordinate range.
    pub fn set_joint_transforms(
        &mut self,
        h: CharacterHandle,
        local: &[Trs],
        placement: &Isometry3<f32>,
    ) -> Result<(), WorldError> {
        let c = self.character_mut(h)?;
        let skeleton = &c.model.character().skeleton;
        if local.len() != skeleton.len() {
            return Err(WorldError::JointCount {
                character: h,
                expected: skeleton.len(),
                got: local.len(),
            });
        }
        let p: Matrix4<f32> = placement.to_homogeneous();
        if !p.iter().all(|x| x.is_finite()) {
            return Err(WorldError::NonFinitePlacement { character: h });
        }
        skeleton.world_matrices(local, &mut c.joint_world);
        skeleton.skin_matrices(&c.joint_world, &mut c.next_pose.skin);
        for m in c.next_pose.skin.iter_mut() {
            *m = p * *m;
        }
        c.next_pose.base = p * *skeleton.base();
        check_pose(h, c.next_pose.as_pose(), c.model.bind_reach())?;
        std::mem::swap(&mut c.pose, &mut c.next_pose);
        c.pose_changed();
        Ok(())
    }

    /// Moves object `h` to `pose` (object frame → world).
    pub fn set_object_pose(
        &mut self,
        h: ObjectHandle,
        pose: Isometry3<f32>,
    ) -> Result<(), WorldError> {
        check_object_pose(h, &pose)?;
        self.object_mut(h)?.pose = pose;
        Ok(())
    }

    /// Takes character `h` out of the world (`active` false) or puts it
    /// back (`true`); a character is active when added. An inactive
    /// character keeps its handle, its model and its state, and may still
    /// be posed, but takes part in no step, sweep or query: no root sphere,
    /// no pass, no contact, no counter. Set active again, it is stepped at
    /// its current pose; continuous detection starts its steps there (the
    /// next sweep records its pose and finds nothing for it, as a world's
    /// first sweep does), so a character pooled far away and brought back
    /// elsewhere sweeps nothing on the way.
    pub fn set_character_active(
        &mut self,
        h: CharacterHandle,
        active: bool,
    ) -> Result<(), WorldError> {
        self.character_mut(h)?.active = active;
        Ok(())
    }

    /// Whether character `h` takes part in steps, sweeps and queries.
    pub fn character_is_active(&self, h: CharacterHandle) -> Result<bool, WorldError> {
        Ok(self.locked(h)?.active)
    }

    /// Takes object `h` out of the world or puts it back, as
    /// [`Self::set_character_active`] does for a character (an object set
    /// active again is swept from its pose at the next sweep on).
    pub fn set_object_active(&mut self, h: ObjectHandle, active: bool) -> Result<(), WorldError> {
        self.object_mut(h)?.active = active;
        Ok(())
    }

    /// Takes room `h` out of the world or puts it back (a level streamed
    /// out and in again): while out, no character is tested against it and
    /// no query looks at it.
    pub fn set_room_active(&mut self, h: RoomHandle, active: bool) -> Result<(), WorldError> {
        self.room_mut(h)?.active = active;
        Ok(())
    }

    /// Whether room `h` takes part in steps, sweeps and queries.
    pub fn room_is_active(&self, h: RoomHandle) -> Result<bool, WorldError> {
        self.rooms
            .get(h.index())
            .map(|r| r.active)
            .ok_or(WorldError::UnknownRoom(h))
    }

    /// Sets the groups character `h` belongs to and meets (by default
    /// [`CollisionGroups::ALL`]): it is tested against a room, an object or
    /// another character only if their groups meet, in steps and sweeps
    /// alike. Against itself, [`Self::set_self_collision`] decides.
    pub fn set_character_groups(
        &mut self,
        h: CharacterHandle,
        groups: CollisionGroups,
    ) -> Result<(), WorldError> {
        self.character_mut(h)?.groups = groups;
        Ok(())
    }

    /// Sets the groups object `h` belongs to and meets (see
    /// [`Self::set_character_groups`]).
    pub fn set_object_groups(
        &mut self,
        h: ObjectHandle,
        groups: CollisionGroups,
    ) -> Result<(), WorldError> {
        self.object_mut(h)?.groups = groups;
        Ok(())
    }

    /// Sets the groups room `h` belongs to and meets (see
    /// [`Self::set_character_groups`]).
    pub fn set_room_groups(
        &mut self,
        h: RoomHandle,
        groups: CollisionGroups,
    ) -> Result<(), WorldError> {
        self.room_mut(h)?.groups = groups;
        Ok(())
    }

    /// Whether object `h` takes part in steps, sweeps and queries.
    pub fn object_is_active(&self, h: ObjectHandle) -> Result<bool, WorldError> {
        self.objects
            .get(h.index())
            .map(|o| o.active)
            .ok_or(WorldError::UnknownObject(h))
    }

    /// The contacts and counters of the last step.
    pub fn contacts(&self) -> &StepContacts {
        &self.contacts
    }

    /// Whether each pass splits its refit time from its traversal time (on
    /// by default; off, refit time is in traversal time and each refit
    /// costs two time-stamp reads less).
    pub fn set_refit_timing(&mut self, on: bool) {
        self.settings.time_refit = on;
    }

    /// Whether the passes against rooms log the room nodes they test (off by
    /// default; a recorder turns it on). The counters are the same either
    /// way.
    pub fn set_visit_log(&mut self, on: bool) {
        self.visit_logs = on;
        let logs = on.then(|| self.room_logs());
        for c in &mut self.characters {
            c.get_mut().expect("no pass panicked").visits = logs.clone();
        }
    }

    fn room_logs(&self) -> Vec<TestedNodes> {
        self.rooms
            .iter()
            .map(|r| TestedNodes::new(r.tree.tree.len()))
            .collect()
    }

    /// Bytes of every hierarchy: each character's tree (and its self-contact
    /// data, in worlds that test characters against themselves), each
    /// room's and each object's (the "Data" row of the paper's Tables 2–3).
    pub fn hierarchy_bytes(&self) -> usize {
        let rigid: usize = self
            .rooms
            .iter()
            .chain(&self.objects)
            .map(|b| b.tree.bytes())
            .sum();
        let characters: usize = self
            .characters
            .iter()
            .map(|c| {
                let c = c.lock().expect("no pass panicked");
                c.tree.tree.bytes() + c.itself.as_ref().map_or(0, |s| s.data.bytes())
            })
            .sum();
        rigid + characters
    }

    /// Turns continuous detection on ([`Self::sweep`]): per character, refit
    /// states and skinned vertices at both ends of a step.
    pub fn enable_continuous(&mut self, params: CcdParams) {
        let mut cs = ContinuousState::new(params, &self.rooms, &self.objects);
        for c in &mut self.characters {
            let c = c.get_mut().expect("no pass panicked");
            c.sweep = Some(Box::new(cs.character_sweep(c, self.rooms.len())));
        }
        cs.contacts.clear();
        self.continuous = Some(Box::new(cs));
    }
}

/// Every position of `mesh` inside the coordinate range.
fn check_mesh(mesh: &TriMesh, what: &'static str) -> Result<(), WorldError> {
    match mesh
        .positions()
        .iter()
        .enumerate()
        .find(|(_, p)| !within_range(p.coords.norm()))
    {
        Some((vertex, p)) => Err(WorldError::MeshOutOfRange {
            what,
            vertex,
            distance: p.coords.norm(),
            limit: MAX_COORDINATE,
        }),
        None => Ok(()),
    }
}

/// An object pose is finite and inside the coordinate range.
fn check_object_pose(h: ObjectHandle, pose: &Isometry3<f32>) -> Result<(), WorldError> {
    let m = pose.to_homogeneous();
    if m.iter().all(|x| x.is_finite()) && pose.translation.vector.norm() <= MAX_COORDINATE {
        Ok(())
    } else {
        Err(WorldError::BadObjectPose {
            object: h,
            limit: MAX_COORDINATE,
        })
    }
}

/// A pose is finite and keeps every vertex inside the coordinate range.
fn check_pose(h: CharacterHandle, pose: SkinPose<'_>, bind_reach: f32) -> Result<(), WorldError> {
    // A matrix that is not finite makes the reach infinite: one pass over
    // the matrices accepts a good pose; only a refused one is searched for
    // its culprit.
    let reach = pose.reach(bind_reach);
    if within_range(reach) {
        return Ok(());
    }
    if let Some(joint) = pose
        .skin
        .iter()
        .position(|m| !m.iter().all(|x| x.is_finite()))
    {
        return Err(WorldError::NonFiniteJoint {
            character: h,
            joint,
        });
    }
    if !pose.base.iter().all(|x| x.is_finite()) {
        return Err(WorldError::NonFinitePlacement { character: h });
    }
    Err(WorldError::PoseOutOfRange {
        character: h,
        reach,
        limit: MAX_COORDINATE,
    })
}
