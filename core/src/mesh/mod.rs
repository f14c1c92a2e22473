//! Indexed triangle meshes and the mesh-level optimisation of paper §4.
//!
//! | file | what | paper |
//! |---|---|---|
//! | [`trimesh`] | [`TriMesh`]: positions plus index triples, validated on construction | |
//! | [`dedup`] | edge de-duplication: leave out a triangle whose edges are all covered | §4, Fig. 1 |

pub mod dedup;
pub mod trimesh;

pub use dedup::{EdgeDedup, dedup_edges};
pub use trimesh::{MeshError, TriMesh, TriangleId};
