//! What one method's continuous detection found over one frame step: the
//! pairs touching during the step with their times of impact, the earliest,
//! and the counters (docs/ccd.md, "Swept hierarchies").

use crate::pipeline::Method;
use crate::pipeline::continuous_narrow::CcdCounters;
use crate::pipeline::driver::FrameCounters;

use super::outcome::{ByKind, CharacterPair, ObjectPair, RoomPair};

/// A pair touching during a step: the pair, a lower bound of its time of
/// impact (fraction of the step, 0 at the previous frame) and whether a
/// plane test (not a triangle test) answered it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Timed<P> {
    #[cfg_attr(feature = "serde", serde(flatten))]
    pub pair: P,
    pub toi: f64,
    pub by_plane: bool,
}

/// One method's step from frame `frame − 1` to `frame`.
#[derive(Clone, Debug, Default)]
pub struct ContinuousOutcome {
    pub method: Option<Method>,
    /// The step's end frame; `None` before the first step (frame 0 has no
    /// previous frame).
    pub frame: Option<usize>,
    /// Sum over the kinds. `tri_tri` counts triangle pairs tested,
    /// `plane_sphere` every sphere tested against a plane (guards and
    /// leaves), `refits` and `skinned_vertices` both ends.
    pub total: FrameCounters,
    pub by_kind: ByKind<FrameCounters>,
    pub ccd: CcdCounters,
    /// Root-sphere tests of the world's broad phase (swept roots).
    pub broad_phase_tests: u64,
    pub body_pairs: u64,
    /// Sorted by pair.
    pub room_pairs: Vec<Timed<RoomPair>>,
    pub object_pairs: Vec<Timed<ObjectPair>>,
    pub character_pairs: Vec<Timed<CharacterPair>>,
    /// The wall-clock milliseconds of the step's detection (posing excluded).
    pub wall_ms: f64,
}

impl ContinuousOutcome {
    /// The earliest time of impact of the step, if any pair touches.
    pub fn earliest(&self) -> Option<f64> {
        self.room_pairs
            .iter()
            .map(|p| p.toi)
            .chain(self.object_pairs.iter().map(|p| p.toi))
            .chain(self.character_pairs.iter().map(|p| p.toi))
            .min_by(f64::total_cmp)
    }

    /// Pairs of every kind.
    pub fn pair_count(&self) -> usize {
        self.room_pairs.len() + self.object_pairs.len() + self.character_pairs.len()
    }

    pub fn clear(&mut self) {
        self.frame = None;
        self.total = FrameCounters::default();
        self.by_kind = ByKind::default();
        self.ccd = CcdCounters::default();
        self.broad_phase_tests = 0;
        self.body_pairs = 0;
        self.room_pairs.clear();
        self.object_pairs.clear();
        self.character_pairs.clear();
        self.wall_ms = 0.0;
    }
}
