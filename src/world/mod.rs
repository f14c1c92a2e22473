//! The scenario's world on the collision library's (transitional: the frame
//! loop of every method side by side, built from a scenario).
//!
//! | file | what |
//! |---|---|
//! | [`session`] | [`World`]: builds every method's hierarchies for a scene; [`World::step`] plays a frame |
//! | [`continuous`] | [`ContinuousWorld`]: continuous detection of every frame step beside a world |
//! | [`motion`] | [`Motion`]: an object's pose over time (waypoints, hinge, a room door's swing) |
//! | [`shapes`] | meshes of the generated objects (box, panel, ball, door) |

pub mod continuous;
pub mod motion;
pub mod session;
pub mod shapes;

pub use continuous::ContinuousWorld;
pub use cornertree::world::*;
pub use motion::Motion;
pub use session::{MethodWorld, World};
