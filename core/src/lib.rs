//! # cornertree
//!
//! Collision detection for animated, skinned virtual characters with sphere
//! trees, after *Real time accurate collision detection for virtual
//! characters* (the paper).
//!
//! An engine starts at [`world::CollisionWorld`]: its own rooms, objects
//! and characters in, by handle; poses each frame; contacts by handle and
//! kind, [`world::CollisionWorld::contact_geometry`] for where they are;
//! ray and shape queries; collision groups, self-collision per character,
//! bodies set inactive and back. The repository's `docs/library.md` walks
//! through it in that order.
//!
//! | module | what | paper |
//! |---|---|---|
//! | [`geometry`] | points, spheres, triangles; the tests of the operation model; enclosing spheres; exact oracle; continuous kernels | §2, §3, §5, §6, §7 |
//! | [`mesh`] | indexed triangle meshes; edge de-duplication | §4 |
//! | [`sphere_tree`] | sphere-tree build, n-ary collapse, validation, on-demand refit, simultaneous traversal | §3 |
//! | [`big_triangle`] | sphere division, corner-trees and quaternary trees inside big triangles | §4–5 |
//! | [`character`] | skeletons, clips, skinning models | §3 |
//! | [`io`] | glTF loading (feature `gltf`), load limits | |
//! | [`pipeline`] | methods, the environment hierarchy per method, the passes | §3–6 |
//! | [`choice`] | the names of methods, skinning models and refit rules, parsed back |  |
//! | [`world`] | several characters, moving objects and a room on one frame loop | §1, §6 |

#![warn(missing_docs)]

pub mod big_triangle;
pub mod character;
pub mod choice;
pub mod geometry;
pub mod io;
pub mod mesh;
pub mod pipeline;
pub(crate) mod prefetch;
pub mod sphere_tree;
#[cfg(test)]
pub(crate) mod test_rng;
pub mod world;

// The library's own name inside it: the workbench's humanoid generator,
// compiled into the unit tests below, names the library `cornertree`.
extern crate self as cornertree;

/// The workbench's generated humanoid (`src/humanoid.rs` of the workbench
/// package), for unit tests that need a realistic skinned character. A
/// dev-dependency on the workbench would link a second copy of this crate.
#[cfg(test)]
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
pub(crate) mod humanoid;
