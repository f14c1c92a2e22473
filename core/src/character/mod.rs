//! Animated characters (paper §3, "Virtual Character Animation").
//!
//! | file | what | paper |
//! |---|---|---|
//! | [`transform`] | [`Trs`]: translation, rotation, scale | |
//! | [`skeleton`] | [`Skeleton`]: joints, parents before children, rest pose, inverse bind matrices | §3 |
//! | [`model`] | [`Character`] and reusable [`PoseBuffers`] | §3 |
//! | [`on_demand`] | [`OnDemandSkin`]: skins only the vertices a frame's narrow phase reads | |
//! | [`clip`] | [`Clip`]: keyframed channels (STEP, LINEAR, CUBICSPLINE) sampled at any time | |
//! | [`skinning`] | glTF linear blend skinning and the paper's one-joint model, with the conversion | §3 |

pub mod clip;
pub mod model;
pub mod on_demand;
pub mod skeleton;
pub mod skinning;
pub mod transform;

pub use clip::{Channel, ChannelValues, Clip, Interpolation};
pub use model::{Character, PoseBuffers, SkinPose, UnknownClip};
pub use on_demand::OnDemandSkin;
pub use skeleton::{Joint, JointId, Skeleton, SkeletonError};
pub use skinning::{Influences, PaperBinding, SkinningModel};
pub use transform::Trs;
