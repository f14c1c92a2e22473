//! The collision-detection pipeline: the methods, the environment hierarchy
//! they build, and the per-frame driver with its counters.
//!
//! | file | what | paper |
//! |---|---|---|
//! | [`driver`] | one method's per-frame pipeline: on-demand refit inside traversal, narrow phase, counters, stage times | §3–6 |
//! | [`continuous`] | one character over a frame step: swept spheres against the room, a moving object or another character (continuous detection) | §7 |
//! | [`continuous_narrow`] | the continuous leaf tests: plane of a big triangle, triangle–triangle CCD, times of impact | §5, §7 |
//! | [`method`] | [`Method`]: original, sphere division, plane-sphere and quaternary plane-sphere (§5 as written), their pruned twins and pruned tri-tri (ours) | §5, §6 |
//! | [`environment_tree`] | the environment's sphere tree with big-triangle hierarchies grafted in | §5 |
//! | [`prepared_triangles`] | triangles prepared once for the triangle-triangle test while a narrow phase meets them again | §3 |
//! | [`visit_log`] | which environment nodes the timed traversal tested (for recordings) | §3 |

pub mod bodies;
pub mod continuous;
pub mod continuous_narrow;
pub mod driver;
pub mod environment_tree;
pub mod method;
pub mod prepared_triangles;
pub mod visit_log;

pub use environment_tree::{DEFAULT_THRESHOLD, EnvironmentTree, Threshold};
pub use method::{LeafTest, Method};
