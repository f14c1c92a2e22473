//! Worlds: several characters, moving rigid objects and a static room, on
//! one frame loop (the paper's "virtual world composed of several
//! interactive avatars ... and objects", §1).
//!
//! | file | what |
//! |---|---|
//! | [`continuous_outcome`] | [`ContinuousOutcome`]: pairs touching during a step, with times of impact |
//! | [`pass_graph`] | [`pass_graph::PassGraph`]: a frame's passes, run on every thread, a character's own pass before its pairs, one pass per character at a time, no barrier between kinds |
//! | [`pinning`] | each thread of a world's pool on a processor of its own (Linux) |
//! | [`outcome`] | [`MethodOutcome`]: counters per pair kind and in total, pairs of every kind |

pub mod continuous_outcome;
pub mod outcome;
pub mod pass_graph;
pub mod pinning;

pub use continuous_outcome::{ContinuousOutcome, Timed};
pub use outcome::{
    ByKind, CharacterPair, MethodOutcome, ObjectPair, PairKind, RoomPair, add_counters,
};
