//! What one frame of a world cost and found, per method: counters by pair
//! kind and in total, and the colliding pairs of every kind.

use crate::pipeline::Method;
use crate::pipeline::driver::FrameCounters;

/// The three kinds of body pairs of a world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum PairKind {
    /// A character against the static room.
    Environment,
    /// A character against a moving rigid object.
    Objects,
    /// Two characters.
    Characters,
}

impl PairKind {
    pub const ALL: [PairKind; 3] = [
        PairKind::Environment,
        PairKind::Objects,
        PairKind::Characters,
    ];

    pub fn name(self) -> &'static str {
        match self {
            PairKind::Environment => "environment",
            PairKind::Objects => "objects",
            PairKind::Characters => "characters",
        }
    }
}

/// One value per pair kind.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ByKind<T> {
    pub environment: T,
    pub objects: T,
    pub characters: T,
}

impl<T> ByKind<T> {
    pub fn get(&self, k: PairKind) -> &T {
        match k {
            PairKind::Environment => &self.environment,
            PairKind::Objects => &self.objects,
            PairKind::Characters => &self.characters,
        }
    }

    pub fn get_mut(&mut self, k: PairKind) -> &mut T {
        match k {
            PairKind::Environment => &mut self.environment,
            PairKind::Objects => &mut self.objects,
            PairKind::Characters => &mut self.characters,
        }
    }
}

/// A character triangle touching a room triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct RoomPair {
    pub character: u32,
    pub triangle: u32,
    pub room_triangle: u32,
}

/// A character triangle touching an object triangle (object frame indices).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ObjectPair {
    pub character: u32,
    pub triangle: u32,
    pub object: u32,
    pub object_triangle: u32,
}

/// A triangle of one character touching one of another (`a < b`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct CharacterPair {
    pub a: u32,
    pub triangle_a: u32,
    pub b: u32,
    pub triangle_b: u32,
}

/// One method's frame of a world.
#[derive(Clone, Debug, Default)]
pub struct MethodOutcome {
    pub method: Option<Method>,
    /// Sum over the kinds; refits and skinned vertices over the characters.
    /// Times are summed over the passes (CPU milliseconds); with several
    /// threads the frame took [`Self::wall_ms`].
    pub total: FrameCounters,
    /// Tests and pairs per kind (refits and skinning are the characters',
    /// counted in the pass that did them first).
    pub by_kind: ByKind<FrameCounters>,
    /// Root-sphere tests of the world's broad phase (included in the kinds'
    /// sphere-sphere tests).
    pub broad_phase_tests: u64,
    /// Body pairs whose hierarchies were traversed this frame (character
    /// against object, character against character).
    pub body_pairs: u64,
    /// Wall-clock milliseconds of the method's frame (posing excluded).
    pub wall_ms: f64,
    /// Sorted.
    pub room_pairs: Vec<RoomPair>,
    /// Sorted.
    pub object_pairs: Vec<ObjectPair>,
    /// Sorted.
    pub character_pairs: Vec<CharacterPair>,
}

/// Adds `b`'s tests, pairs, refits, skinned vertices and times to `a`.
pub fn add_counters(a: &mut FrameCounters, b: &FrameCounters) {
    a.sphere_sphere += b.sphere_sphere;
    a.tri_tri += b.tri_tri;
    a.plane_sphere += b.plane_sphere;
    a.refits += b.refits;
    a.pairs += b.pairs;
    a.skinned_vertices += b.skinned_vertices;
    a.time.pose_ms += b.time.pose_ms;
    a.time.skinning_ms += b.time.skinning_ms;
    a.time.refit_ms += b.time.refit_ms;
    a.time.traversal_ms += b.time.traversal_ms;
    a.time.narrow_ms += b.time.narrow_ms;
}
