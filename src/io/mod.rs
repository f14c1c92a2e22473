//! Loading meshes and characters from files.
//!
//! | file | what |
//! |---|---|
//! | [`gltf_static`] | every triangle of a glTF/GLB scene in its static pose, world space |
//! | [`gltf_character`] | the skinned character of a glTF/GLB scene: skeleton, bind-pose mesh, influences, clips |
//! | [`ccd_queries`] | CCD query files with exact answers (CSV of exact rationals; `cornertree ccd-queries`) |
//! | [`ply`] | writing triangle meshes as PLY (`run --dump-frame`) |
//! | [`source`] | a character source: a glTF file or `generated:humanoid?vertices=N&seed=S` |
//! | [`limits`] | [`LoadLimits`]: the byte budget a file may make the loaders allocate |
//! | `gltf_bind` | how a character's meshes bind to its one skeleton: several skins (joint slots, bind spaces), rigid meshes below a joint (private) |
//! | `gltf_accessor` | bounds-checked reading of glTF accessors (private, used by both loaders) |

pub mod ccd_queries;
mod gltf_accessor;
mod gltf_bind;
pub mod gltf_character;
pub mod gltf_static;
pub mod limits;
pub mod ply;
pub mod source;

pub use gltf_character::{load_character, load_character_from, load_character_with};
pub use gltf_static::{
    AttachedMesh, LoadError, LoadReport, MeshRef, SkippedChannel, SkippedPrimitive,
    load_static_mesh, load_static_mesh_from, load_static_mesh_with,
};
pub use limits::LoadLimits;
pub use source::{CharacterSource, SourceError};
