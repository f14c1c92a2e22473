//! The collision-detection pipeline: methods, the environment hierarchy they
//! build, and (later) the per-frame driver and its counters.
//!
//! | file | what | paper |
//! |---|---|---|
//! | [`method`] | [`Method`]: original, sphere division, plane-sphere, quaternary plane-sphere | §5, §6 |
//! | [`environment_tree`] | the environment's sphere tree with big-triangle hierarchies grafted in | §5 |

pub mod environment_tree;
pub mod method;

pub use environment_tree::{DEFAULT_THRESHOLD, EnvironmentTree, Threshold};
pub use method::{LeafTest, Method};
