//! A world's continuous state beside its bodies' (continuous detection,
//! [`CollisionWorld::sweep`](super::CollisionWorld::sweep)): the planes of
//! the rooms' big triangles, the objects' poses at the start of the next
//! sweep and their paths, the character pairs' pass and the last sweep's
//! contacts; and each character's state at both ends of a step.

use nalgebra::Isometry3;

use crate::geometry::ccd_root_finder::CcdParams;
use crate::geometry::ccd_sphere_plane::StillPlane;
use crate::pipeline::SweepState;
use crate::pipeline::continuous_narrow::{CcdCounters, TimedPair};
use crate::pipeline::swept_passes::room_planes;
use crate::sphere_tree::swept_rigid::RigidPath;

use super::bodies::{CharacterBody, CharacterSweep, PassSlot, RigidBody};
use super::contacts::SweepContacts;

/// A world's continuous state beside its bodies'.
pub(crate) struct ContinuousState {
    pub(crate) params: CcdParams,
    /// Per room, the plane of each division's big triangle.
    pub(super) room_planes: Vec<Vec<StillPlane>>,
    /// Each object's pose at the start of the next sweep.
    pub(super) object_starts: Vec<Isometry3<f32>>,
    /// Whether the last sweep recorded that start while the object was
    /// active (an object set active again starts its steps where it is).
    pub(super) object_primed: Vec<bool>,
    /// Whether this sweep sweeps each object (active, and primed).
    pub(super) object_swept: Vec<bool>,
    /// Each object's path over the next sweep, where the caller gave one.
    pub(super) next_paths: Vec<Option<RigidPath>>,
    /// Each object's path over the last sweep.
    pub(super) paths: Vec<RigidPath>,
    /// Whether a sweep has recorded the start poses.
    pub(super) started: bool,
    pub(super) pairs: PassSlot<TimedPair>,
    pub(super) pair_ccd: CcdCounters,
    pub(crate) contacts: SweepContacts,
}

impl ContinuousState {
    pub(crate) fn new(params: CcdParams, rooms: &[RigidBody], objects: &[RigidBody]) -> Self {
        Self {
            params,
            room_planes: rooms
                .iter()
                .map(|r| room_planes(&r.tree, &r.mesh))
                .collect(),
            object_starts: objects.iter().map(|o| o.pose).collect(),
            object_primed: vec![true; objects.len()],
            object_swept: vec![false; objects.len()],
            next_paths: vec![None; objects.len()],
            paths: objects.iter().map(|o| RigidPath::still(o.pose)).collect(),
            started: false,
            pairs: PassSlot::default(),
            pair_ccd: CcdCounters::default(),
            contacts: SweepContacts::default(),
        }
    }

    pub(crate) fn add_room(
        &mut self,
        room: &RigidBody,
        characters: &mut [std::sync::Mutex<CharacterBody>],
    ) {
        self.room_planes.push(room_planes(&room.tree, &room.mesh));
        for c in characters {
            if let Some(s) = c.get_mut().expect("no pass panicked").sweep.as_mut() {
                s.rooms.push(PassSlot::default());
            }
        }
    }

    pub(crate) fn add_object(&mut self, pose: &Isometry3<f32>) {
        self.object_starts.push(*pose);
        self.object_primed.push(true);
        self.object_swept.push(false);
        self.next_paths.push(None);
        self.paths.push(RigidPath::still(*pose));
    }
}

impl ContinuousState {
    /// A character's continuous state.
    pub(crate) fn character_sweep(&self, c: &CharacterBody, rooms: usize) -> CharacterSweep {
        let ch = c.model.character();
        CharacterSweep {
            state: SweepState::new(&c.tree, ch.skeleton.len(), ch.mesh.vertex_count()),
            start: c.pose.clone(),
            continues: false,
            primed: true,
            swept: false,
            rooms: (0..rooms).map(|_| PassSlot::default()).collect(),
            objects: PassSlot::default(),
            object_pairs: Vec::new(),
            itself: c.itself.as_ref().map(|_| PassSlot::default()),
        }
    }
}
