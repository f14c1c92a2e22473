//! Sphere trees (paper §3, "Collision detection").
//!
//! | file | what |
//! |---|---|
//! | [`node`] | [`SphereTree`], [`Node`], [`NodeId`]: compact storage, children after parents |
//! | [`build`] | top-down binary split, then collapse to an n-ary tree |
//! | [`character`] | the character's tree: one tree per joint under root and extremity spheres |
//! | [`node_boxes`] | a static tree's nodes' boxes of their triangles, six bytes a node (ours: the room's guard) |
//! | [`containment`] | distinct vertices per node; checking refit spheres hold them |
//! | [`refit`] | on-demand refit from per-joint weight ranges (§3 sphere update) |
//! | `refit_ahead` | last frame's asked-for nodes refit in one loop before traversal |
//! | [`validate`] | the public validator tests call after every step |
//! | [`swept`] | swept spheres of the character tree over a frame step, refit at both ends on demand (continuous detection) |
//! | [`swept_rigid`] | swept spheres of a rigid body's tree over a step (its chord and its rotation) |
//! | [`traverse`](mod@traverse) | simultaneous traversal of two trees with a reusable [`Workspace`] |
//! | `pass_marks` | per index, the last key met in a pass (no clearing between passes) |
//! | [`self_traverse`] | one tree against itself: each pair of overlapping leaves once, by the traversal above started at pairs of siblings |
//! | [`self_contact`] | what a character's self pass knows from its skinning: welded corners (the neighbour rule), parts one joint moves, their rest gaps |
//! | [`normal_cones`] | each node's cone of triangle normals in a pose, from the leaves up |
//! | [`flat_patches`] | which nodes and pairs of nodes cover a disk of the mesh, with its boundary loop (the contour test of normal-cone culling) |
//! | `grouped` | the same, descending each sphere once per group of leaves (a big triangle's division) |
//!
//! Invariants (checked by [`SphereTree::validate`]): node 0 is the root; the
//! children of a node are contiguous and stored after it, level by level, so a
//! reverse sweep visits children before parents; a leaf holds one primitive
//! (a triangle) which lies inside its sphere and the spheres of all its
//! ancestors; a built tree is also *nested* (each child sphere inside its
//! parent), which makes pruning exact with respect to leaf spheres.

pub mod build;
pub mod character;
pub mod containment;
pub mod flat_patches;
pub(crate) mod grouped;
pub mod node;
pub mod node_boxes;
pub mod normal_cones;
pub(crate) mod pass_marks;
pub mod refit;
mod refit_ahead;
mod refit_rules;
pub mod self_contact;
pub mod self_traverse;
pub mod swept;
pub mod swept_rigid;
pub mod traverse;
pub mod validate;

pub use build::{BuildParams, build_tree};
pub(crate) use grouped::traverse_grouped;
pub use node::{Node, NodeId, SphereTree};
pub(crate) use pass_marks::PassMarks;
pub use traverse::{
    AsTested, Hierarchy, Order, TraversalStats, Workspace, traverse, traverse_guarded,
    traverse_ordered,
};
pub use validate::TreeError;
