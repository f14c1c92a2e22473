//! Loading meshes from files.
//!
//! | file | what |
//! |---|---|
//! | [`gltf_static`] | every triangle of a glTF/GLB scene in its static pose, world space |
//! | [`source`] | a character source: a glTF file or `generated:humanoid?vertices=N&seed=S` |
//! | `gltf_accessor` | bounds-checked reading of glTF accessors (private, used by `gltf_static`) |

mod gltf_accessor;
pub mod gltf_static;
pub mod source;

pub use gltf_static::{LoadError, LoadReport, MeshRef, SkippedPrimitive, load_static_mesh};
pub use source::{CharacterSource, SourceError};
