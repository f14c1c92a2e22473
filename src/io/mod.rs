//! Loading meshes from files.
//!
//! | file | what |
//! |---|---|
//! | [`gltf_static`] | every triangle of a glTF/GLB scene in its static pose, world space |
//! | `gltf_accessor` | bounds-checked reading of glTF accessors (private, used by `gltf_static`) |

mod gltf_accessor;
pub mod gltf_static;

pub use gltf_static::{LoadError, LoadReport, MeshRef, SkippedPrimitive, load_static_mesh};
