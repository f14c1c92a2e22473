//! What one step of a world found and cost: the colliding triangle pairs of
//! every kind (character–room, character–object, character–character, a
//! character against itself), by handle, and the counters per kind and in
//! total.
//!
//! Discrete steps ([`CollisionWorld::step`](super::CollisionWorld::step))
//! give [`StepContacts`]; continuous steps over a frame step
//! ([`CollisionWorld::sweep`](super::CollisionWorld::sweep)) give
//! [`SweepContacts`], whose pairs carry a time of impact. Both are one type,
//! [`Contacts`], told apart by its [`Detection`].

use std::fmt::Debug;

use crate::pipeline::FrameCounters;
use crate::pipeline::continuous_narrow::CcdCounters;

use super::handles::{CharacterHandle, ObjectHandle, RoomHandle};

/// The kinds of body pairs of a world.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "snake_case"))]
pub enum PairKind {
    /// A character against a static room.
    Environment,
    /// A character against a moving rigid object.
    Objects,
    /// Two characters.
    Characters,
    /// A character against itself (worlds with
    /// [`WorldSettings::self_collision`](super::WorldSettings::self_collision)).
    #[cfg_attr(feature = "serde", serde(rename = "self"))]
    SelfContact,
}

impl PairKind {
    /// Every kind, in report order.
    pub const ALL: [PairKind; 4] = [
        PairKind::Environment,
        PairKind::Objects,
        PairKind::Characters,
        PairKind::SelfContact,
    ];

    /// The kind's name in reports.
    pub fn name(self) -> &'static str {
        match self {
            PairKind::Environment => "environment",
            PairKind::Objects => "objects",
            PairKind::Characters => "characters",
            PairKind::SelfContact => "self",
        }
    }
}

/// One value per pair kind.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ByKind<T> {
    /// Characters against rooms.
    pub environment: T,
    /// Characters against moving objects.
    pub objects: T,
    /// Characters against characters.
    pub characters: T,
    /// Each character against itself (named `self` in reports).
    #[cfg_attr(feature = "serde", serde(rename = "self"))]
    pub self_contact: T,
}

impl<T> ByKind<T> {
    /// The value of kind `k`.
    pub fn get(&self, k: PairKind) -> &T {
        match k {
            PairKind::Environment => &self.environment,
            PairKind::Objects => &self.objects,
            PairKind::Characters => &self.characters,
            PairKind::SelfContact => &self.self_contact,
        }
    }

    /// The value of kind `k`, to change.
    pub fn get_mut(&mut self, k: PairKind) -> &mut T {
        match k {
            PairKind::Environment => &mut self.environment,
            PairKind::Objects => &mut self.objects,
            PairKind::Characters => &mut self.characters,
            PairKind::SelfContact => &mut self.self_contact,
        }
    }
}

/// A character triangle touching a room triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct RoomPair {
    /// The character.
    pub character: CharacterHandle,
    /// Its triangle (an index into its mesh).
    pub triangle: u32,
    /// The room.
    pub room: RoomHandle,
    /// The room's triangle.
    pub room_triangle: u32,
}

/// A character triangle touching an object triangle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct ObjectPair {
    /// The character.
    pub character: CharacterHandle,
    /// Its triangle.
    pub triangle: u32,
    /// The object.
    pub object: ObjectHandle,
    /// The object's triangle (an index into its mesh).
    pub object_triangle: u32,
}

/// A triangle of one character touching one of another (`a < b`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct CharacterPair {
    /// The first character (the lower handle).
    pub a: CharacterHandle,
    /// Its triangle.
    pub triangle_a: u32,
    /// The second character.
    pub b: CharacterHandle,
    /// Its triangle.
    pub triangle_b: u32,
}

/// Two triangles of one character touching, neither sharing a corner
/// with the other (`triangle_a < triangle_b`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct SelfPair {
    /// The character.
    pub character: CharacterHandle,
    /// The lower triangle index.
    pub triangle_a: u32,
    /// The higher.
    pub triangle_b: u32,
}

/// A pair touching during a step: the pair, a lower bound of its time of
/// impact (fraction of the step, 0 at its start) and whether a plane test
/// (not a triangle test) answered it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Timed<P> {
    /// The pair.
    #[cfg_attr(feature = "serde", serde(flatten))]
    pub pair: P,
    /// A lower bound of the time of impact, in `[0, 1]`.
    pub toi: f64,
    /// Answered by a big triangle's plane (plane-sphere methods).
    pub by_plane: bool,
}

/// How a step detects: what a contact carries and which counters come
/// beside the tests.
pub trait Detection: Copy + Default + Debug {
    /// A contact of pair type `P`.
    type Pair<P: Copy + Ord + Debug>: Copy + Debug + PartialEq;
    /// Counters of this kind of detection beside [`FrameCounters`].
    type Extra: Copy + Default + Debug + PartialEq;
    /// The pair of a contact.
    fn pair<P: Copy + Ord + Debug>(c: &Self::Pair<P>) -> &P;
}

/// Discrete detection at one pose: a contact is its pair.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Discrete;

impl Detection for Discrete {
    type Pair<P: Copy + Ord + Debug> = P;
    type Extra = ();
    #[inline]
    fn pair<P: Copy + Ord + Debug>(c: &P) -> &P {
        c
    }
}

/// Continuous detection over a step: a contact is its pair with a time of
/// impact.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Swept;

impl Detection for Swept {
    type Pair<P: Copy + Ord + Debug> = Timed<P>;
    type Extra = CcdCounters;
    #[inline]
    fn pair<P: Copy + Ord + Debug>(c: &Timed<P>) -> &P {
        &c.pair
    }
}

/// One step's contacts and counters.
#[derive(Clone, Debug)]
pub struct Contacts<D: Detection> {
    /// Sum over the kinds; refits and skinned vertices over the characters.
    /// Times are summed over the passes (CPU milliseconds); with several
    /// threads the step took [`Self::wall_ms`].
    pub total: FrameCounters,
    /// Tests and pairs per kind (refits and skinning are the characters',
    /// counted in the pass that did them first; what a character's frame
    /// start refit is counted with its room passes).
    pub by_kind: ByKind<FrameCounters>,
    /// Counters of continuous detection (nothing for discrete steps).
    pub extra: D::Extra,
    /// Root-sphere tests of the world's broad phase (included in the kinds'
    /// sphere-sphere tests).
    pub broad_phase_tests: u64,
    /// Body pairs whose hierarchies were traversed (character against
    /// object, character against character).
    pub body_pairs: u64,
    /// Wall-clock milliseconds of the step.
    pub wall_ms: f64,
    /// Milliseconds of work in the step: every pass's time and the step's
    /// own (every character's start, the broad phase, the gathering of the
    /// contacts), as one thread would take them. Discrete steps only (0 for
    /// sweeps).
    pub work_ms: f64,
    /// Milliseconds of the step's span: the longest chain of its work that
    /// must run one after another (the slowest character's start, the broad
    /// phase, the character whose passes together took longest, since they
    /// run one at a time, and the gathering). No number of threads finishes
    /// the step sooner. Discrete steps only.
    pub span_ms: f64,
    /// Character–room contacts, sorted.
    pub room_pairs: Vec<D::Pair<RoomPair>>,
    /// Character–object contacts, sorted.
    pub object_pairs: Vec<D::Pair<ObjectPair>>,
    /// Character–character contacts, sorted.
    pub character_pairs: Vec<D::Pair<CharacterPair>>,
    /// Each character's contacts with itself, sorted (empty unless the
    /// world detects them).
    pub self_pairs: Vec<D::Pair<SelfPair>>,
}

impl<D: Detection> Default for Contacts<D> {
    fn default() -> Self {
        Self {
            total: FrameCounters::default(),
            by_kind: ByKind::default(),
            extra: D::Extra::default(),
            broad_phase_tests: 0,
            body_pairs: 0,
            wall_ms: 0.0,
            work_ms: 0.0,
            span_ms: 0.0,
            room_pairs: Vec::new(),
            object_pairs: Vec::new(),
            character_pairs: Vec::new(),
            self_pairs: Vec::new(),
        }
    }
}

/// What a discrete step found.
pub type StepContacts = Contacts<Discrete>;
/// What a continuous step found, with times of impact.
pub type SweepContacts = Contacts<Swept>;

impl<D: Detection> Contacts<D> {
    /// Character `c`'s contacts with rooms (a slice of the sorted list).
    pub fn room_contacts_of(&self, c: CharacterHandle) -> &[D::Pair<RoomPair>] {
        let lo = self
            .room_pairs
            .partition_point(|p| D::pair(p).character < c);
        let hi = self
            .room_pairs
            .partition_point(|p| D::pair(p).character <= c);
        &self.room_pairs[lo..hi]
    }

    /// Character `c`'s contacts with objects.
    pub fn object_contacts_of(&self, c: CharacterHandle) -> &[D::Pair<ObjectPair>] {
        let lo = self
            .object_pairs
            .partition_point(|p| D::pair(p).character < c);
        let hi = self
            .object_pairs
            .partition_point(|p| D::pair(p).character <= c);
        &self.object_pairs[lo..hi]
    }

    /// Contacts between character `c` and others, either side.
    pub fn character_contacts_of(
        &self,
        c: CharacterHandle,
    ) -> impl Iterator<Item = &D::Pair<CharacterPair>> + '_ {
        self.character_pairs.iter().filter(move |p| {
            let p = D::pair(*p);
            p.a == c || p.b == c
        })
    }

    /// Character `c`'s contacts with itself (a slice of the sorted list).
    pub fn self_contacts_of(&self, c: CharacterHandle) -> &[D::Pair<SelfPair>] {
        let lo = self
            .self_pairs
            .partition_point(|p| D::pair(p).character < c);
        let hi = self
            .self_pairs
            .partition_point(|p| D::pair(p).character <= c);
        &self.self_pairs[lo..hi]
    }

    /// [`Self::work_ms`] over [`Self::span_ms`]: how many threads the step
    /// could keep busy (0 when not measured).
    pub fn available_parallelism(&self) -> f64 {
        if self.span_ms > 0.0 {
            self.work_ms / self.span_ms
        } else {
            0.0
        }
    }

    /// Contacts of every kind.
    pub fn len(&self) -> usize {
        self.room_pairs.len()
            + self.object_pairs.len()
            + self.character_pairs.len()
            + self.self_pairs.len()
    }

    /// Whether no pair of any kind touches.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Sets the totals: every kind's tests, pairs and times summed; the
    /// characters' `refits` and `skinned` vertices of the step (each
    /// counted once, whichever pass did it).
    pub(crate) fn sum_kinds(&mut self, refits: u64, skinned: u64) {
        self.total = FrameCounters::default();
        for k in PairKind::ALL {
            self.total.add(self.by_kind.get(k));
        }
        self.total.refits = refits;
        self.total.skinned_vertices = skinned;
    }

    /// Forgets the last step (no allocation).
    pub(crate) fn clear(&mut self) {
        self.total = FrameCounters::default();
        self.by_kind = ByKind::default();
        self.extra = D::Extra::default();
        self.broad_phase_tests = 0;
        self.body_pairs = 0;
        self.wall_ms = 0.0;
        self.work_ms = 0.0;
        self.span_ms = 0.0;
        self.room_pairs.clear();
        self.object_pairs.clear();
        self.character_pairs.clear();
        self.self_pairs.clear();
    }
}

impl SweepContacts {
    /// The earliest time of impact of the step, if any pair touches.
    pub fn earliest(&self) -> Option<f64> {
        self.room_pairs
            .iter()
            .map(|p| p.toi)
            .chain(self.object_pairs.iter().map(|p| p.toi))
            .chain(self.character_pairs.iter().map(|p| p.toi))
            .chain(self.self_pairs.iter().map(|p| p.toi))
            .min_by(f64::total_cmp)
    }
}
