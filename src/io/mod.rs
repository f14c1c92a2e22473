//! Loading meshes from files.
//!
//! | file | what |
//! |---|---|
//! | [`gltf_static`] | every triangle of a glTF/GLB scene in its static pose, world space |

pub mod gltf_static;

pub use gltf_static::{LoadError, LoadReport, load_static_mesh};
