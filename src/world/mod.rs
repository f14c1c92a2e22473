//! Worlds: several characters, moving rigid objects and a static room, on
//! one frame loop (the paper's "virtual world composed of several
//! interactive avatars ... and objects", §1).
//!
//! | file | what |
//! |---|---|
//! | [`session`] | [`World`]: builds every method's hierarchies for a scene; [`World::step`] plays a frame |
//! | [`continuous`] | [`ContinuousWorld`]: continuous detection of every frame step beside a world (swept hierarchies, times of impact) |
//! | [`continuous_outcome`] | [`ContinuousOutcome`]: pairs touching during a step, with times of impact |
//! | [`pass_graph`] | [`pass_graph::PassGraph`]: a frame's passes, run on every thread, a character's own pass before its pairs, one pass per character at a time, no barrier between kinds |
//! | [`pinning`] | each thread of a world's pool on a processor of its own (Linux) |
//! | [`outcome`] | [`MethodOutcome`]: counters per pair kind and in total, pairs of every kind |
//! | [`motion`] | [`Motion`]: an object's pose over time (waypoints, hinge, a room door's swing) |
//! | [`shapes`] | meshes of the generated objects (box, panel, ball, door) |

pub mod continuous;
pub mod continuous_outcome;
pub mod motion;
pub mod outcome;
pub mod pass_graph;
pub mod pinning;
pub mod session;
pub mod shapes;

pub use continuous::ContinuousWorld;
pub use continuous_outcome::{ContinuousOutcome, Timed};
pub use motion::Motion;
pub use outcome::{
    ByKind, CharacterPair, MethodOutcome, ObjectPair, PairKind, RoomPair, add_counters,
};
pub use session::{MethodWorld, World};
