//! The collision-detection pipeline: the methods, the hierarchy they build
//! inside a rigid body, and the one pass skeleton every pair of bodies runs
//! through, with its counters.
//!
//! | file | what | paper |
//! |---|---|---|
//! | [`method`] | [`Method`]: original, sphere division, plane-sphere and quaternary plane-sphere (§5 as written), their pruned twins and pruned tri-tri (ours) | §5, §6 |
//! | [`environment_tree`] | [`EnvironmentTree`]: a rigid body's sphere tree with big-triangle hierarchies grafted in | §5 |
//! | [`counters`] | [`FrameCounters`]: tests by kind, refits, skinned vertices, pairs, time per stage | §6 |
//! | `pass` | the one pass skeleton: traversal, preparation, the leaf test of every pair, the hits' order | §3 |
//! | `frame` | a pass in its second body's frame: the room's (nothing moves) or a moving object's | §1 |
//! | `character_side` | a character in a pass: its tree refit and its triangles skinned on demand | §3 |
//! | `rigid_pass`, `pair_pass` | the discrete passes: a character against a rigid body, two characters | §3–5 |
//! | `self_pass` | a character against itself: its tree walked against itself, neighbours dropped, parts one joint moves skipped where their rest gap proves them apart; optionally, disks facing one direction with a simple outline (normal cones) | (ours) |
//! | `query_pass` | a ray, ball or capsule against one body: the same skeleton, the shape as a one-leaf hierarchy | (queries) |
//! | `swept_side`, `swept_passes` | the continuous passes over a frame step: a character's swept tree against the room, an object, a character | §7 |
//! | [`continuous_narrow`] | the continuous leaf tests: plane of a big triangle, triangle–triangle CCD, times of impact | §5, §7 |
//! | `prepared_triangles` | triangles prepared once for the triangle-triangle test while a narrow phase meets them again | §3 |
//! | [`visit_log`] | which nodes of a rigid body the timed traversal tested (for recordings) | §3 |

pub(crate) mod bind_planes;
pub(crate) mod character_side;
pub mod continuous_narrow;
pub mod counters;
pub mod environment_tree;
mod frame;
pub mod method;
pub(crate) mod pair_pass;
pub(crate) mod pass;
pub(crate) mod prepared_triangles;
pub(crate) mod query_pass;
pub(crate) mod rigid_pass;
pub(crate) mod self_pass;
pub(crate) mod swept_passes;
pub(crate) mod swept_side;
pub mod visit_log;

pub use counters::{FrameCounters, FrameTime};
pub use environment_tree::{DEFAULT_THRESHOLD, EnvironmentTree, Threshold};
pub use frame::{Frame, Identity};
pub use method::{LeafTest, Method, WIDE_CHARACTER_COLLAPSE};
pub use swept_side::SweepState;
pub use visit_log::TestedNodes;
