//! Loading meshes and characters from files, and the limits of what a
//! file may make the loaders allocate.
//!
//! | file | what |
//! |---|---|
//! | [`limits`] | [`LoadLimits`]: the byte budget a file may make the loaders allocate; the coordinate range accepted |
//! | `gltf_static` | every triangle of a glTF/GLB scene in its static pose, world space (feature `gltf`) |
//! | `gltf_character` | the skinned character of a glTF/GLB scene: skeleton, bind-pose mesh, influences, clips (feature `gltf`) |
//! | `gltf_bind` | how a character's meshes bind to its one skeleton: several skins (joint slots, bind spaces), rigid meshes below a joint (private) |
//! | `gltf_accessor` | bounds-checked reading of glTF accessors, quantized positions included (private, used by both loaders) |
//! | `gltf_meshopt` | `EXT_meshopt_compression`: compressed buffer views decoded by meshoptimizer (private) |
//! | `gltf_draco` | `KHR_draco_mesh_compression`: compressed primitives decoded by `draco-core` (private) |

#[cfg(feature = "gltf")]
mod gltf_accessor;
#[cfg(feature = "gltf")]
mod gltf_bind;
#[cfg(feature = "gltf")]
pub mod gltf_character;
#[cfg(feature = "gltf")]
mod gltf_draco;
#[cfg(feature = "gltf")]
mod gltf_meshopt;
#[cfg(feature = "gltf")]
pub mod gltf_static;
pub mod limits;

#[cfg(feature = "gltf")]
pub use gltf_character::{load_character, load_character_from, load_character_with};
#[cfg(feature = "gltf")]
pub use gltf_static::{
    AttachedMesh, LoadError, LoadReport, MeshRef, SkippedChannel, SkippedPrimitive,
    load_static_mesh, load_static_mesh_from, load_static_mesh_with,
};
pub use limits::LoadLimits;
