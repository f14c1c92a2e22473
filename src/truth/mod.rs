//! Ground truth: which (character triangle, environment triangle) pairs really
//! collide in a frame, and how a method's answer compares with it.
//!
//! | file | what |
//! |---|---|
//! | [`parry_reference`] | [`ParryReference`]: parry3d's triangle meshes and BVH leaf pairs, decided by parry's triangle-triangle test (GJK) or by the exact oracle; a brute-force exact helper |
//! | [`parry_world`] | [`ParryWorld`]: the parry3d baseline for a whole world (a `TriMesh` per body, a broad phase over their boxes, BVH leaf pairs, parry's `f32` test) |
//! | [`disagreement`] | the pairs two answers differ on, each classified as touching, near-degenerate or a true error |
//! | [`ground_truth`] | [`Truth`]: a frame's truth for one character or many, per pair kind: the exact pairs on parry's broad phase, parry's answer beside it; a method's score per kind, and in detail (false positives with distances, false negatives with causes) per body pair |
//! | [`self_truth`] | [`self_truth::SelfTruth`]: one character against itself, its posed mesh's BVH against itself, neighbours dropped, the exact oracle and parry's answer |
//! | [`body_pair`] | [`BodyPairTruth`]: the truth of one body pair, the piece the above is made of |
//! | [`substep`] | the truth of continuous detection: the exact oracle on dense sub-steps of each frame step |
//! | [`substep_score`] | a continuous step against it: recall, misses, pairs only continuous detection found, classified by refining around their time of impact |
//! | [`accuracy`] | precision and recall per frame and over a run, at the levels of pairs, character triangles and frames |
//!
//! Every pair list here is a sorted list of distinct `(character triangle,
//! environment triangle)` indices, as a `CollisionWorld`'s contacts of a
//! body pair give them.
//!
//! parry's own test is GJK, not exact: in `f32` it reports pairs that miss by
//! ~1e-5 of the scene size and, between a small and a big triangle or with a
//! thin one, by millimetres; in `f64` (used for [`ParryReference::pairs`]) it
//! matched the exact answer on every shipped scenario.
//! [`ParryReference::exact_pairs`] (parry's broad phase, the exact oracle as
//! narrow phase) is the exact answer, the truth every method is scored
//! against; [`ParryReference::pairs`] is parry's, compared beside it.

pub mod accuracy;
pub mod body_pair;
pub mod disagreement;
pub mod ground_truth;
pub mod parry_reference;
pub mod parry_world;
pub mod ray_reference;
pub mod self_truth;
pub mod substep;
pub mod substep_score;

pub use accuracy::{Accuracy, AccuracyTotals, FrameAccuracy};
pub use body_pair::{
    BodyPairTruth, FalseNegative, FalsePositive, MethodContext, MethodTruth, MissCause,
};
pub use disagreement::{Classified, Disagreement, Kind, Tolerances, triangle_distance};
pub use ground_truth::{Truth, WorldPairs};
pub use parry_reference::{ParryReference, brute_force_pairs};
pub use parry_world::ParryWorld;

/// Why a ground-truth query cannot be answered.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum TruthError {
    #[error("the {0} has no triangles")]
    NoTriangles(&'static str),
    #[error(
        "character triangle {triangle} refers to vertex {index}, but the pose has only {vertex_count} vertices"
    )]
    IndexOutOfRange {
        triangle: usize,
        index: u32,
        vertex_count: usize,
    },
    #[error("the pose has {got} vertices, the first pose had {expected}")]
    VertexCountChanged { expected: usize, got: usize },
    #[error("posed vertex {0} is not finite")]
    NonFinitePosition(usize),
    #[error("pair ({character}, {environment}) names a triangle that does not exist")]
    PairOutOfRange { character: u32, environment: u32 },
}
