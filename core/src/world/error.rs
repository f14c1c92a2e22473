//! What is wrong with a caller's data: one error type for every call of a
//! [`CollisionWorld`](super::CollisionWorld), each naming the body, the
//! joint, the index or the value at fault. Nothing a caller hands in makes
//! a world panic.

use crate::character::skinning::SkinError;
use crate::mesh::MeshError;

use super::handles::{CharacterHandle, ObjectHandle};

/// Why a world refused a call.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum WorldError {
    /// A character handle this world did not give.
    #[error("{0}: no such character in this world")]
    UnknownCharacter(CharacterHandle),
    /// An object handle this world did not give.
    #[error("{0}: no such object in this world")]
    UnknownObject(ObjectHandle),
    /// A pose for another number of joints than the character's skeleton.
    #[error("{character}: the pose has {got} joints, the skeleton {expected}")]
    JointCount {
        /// The character posed.
        character: CharacterHandle,
        /// Joints in its skeleton.
        expected: usize,
        /// Joints in the pose given.
        got: usize,
    },
    /// A joint transform (or the placement) with a value that is not finite.
    #[error("{character}: joint {joint}'s transform is not finite")]
    NonFiniteJoint {
        /// The character posed.
        character: CharacterHandle,
        /// Index of the joint (in its skeleton) whose skin matrix is not
        /// finite.
        joint: usize,
    },
    /// The placement or the skeleton base frame is not finite.
    #[error("{character}: the placement is not finite")]
    NonFinitePlacement {
        /// The character placed.
        character: CharacterHandle,
    },
    /// A pose that takes a vertex beyond the coordinates the kernels accept
    /// ([`MAX_COORDINATE`](crate::io::limits::MAX_COORDINATE)).
    #[error(
        "{character}: the pose takes vertices up to {reach} from the origin, beyond the {limit} accepted for coordinates"
    )]
    PoseOutOfRange {
        /// The character posed.
        character: CharacterHandle,
        /// An upper bound of the posed vertices' distance from the origin
        /// (world units).
        reach: f32,
        /// The largest distance accepted.
        limit: f32,
    },
    /// An object pose that is not finite or beyond the coordinate range.
    #[error("{object}: its pose is not finite or beyond {limit} from the origin")]
    BadObjectPose {
        /// The object posed.
        object: ObjectHandle,
        /// The largest distance from the origin accepted for its position.
        limit: f32,
    },
    /// A mesh with a position beyond the coordinate range.
    #[error("{what}: vertex {vertex} lies {distance} from the origin, beyond the {limit} accepted")]
    MeshOutOfRange {
        /// Whose mesh: "room", "object" or "character".
        what: &'static str,
        /// Index of the first vertex out of range.
        vertex: usize,
        /// Its distance from the origin (in the mesh's coordinates).
        distance: f32,
        /// The largest distance accepted.
        limit: f32,
    },
    /// Skinning data that does not fit the mesh or the skeleton.
    #[error("character model: {0}")]
    Skin(#[from] SkinError),
    /// An unusable mesh.
    #[error("mesh: {0}")]
    Mesh(#[from] MeshError),
    /// The kept-triangle set of a character model for another mesh.
    #[error("character model: {got} triangles kept or dropped, the mesh has {expected}")]
    KeptCount {
        /// Triangles in the character's mesh.
        expected: usize,
        /// Triangles the set keeps or drops.
        got: usize,
    },
    /// A room handle this world did not give.
    #[error("{0}: no such room in this world")]
    UnknownRoom(super::handles::RoomHandle),
    /// A query shape that is not a shape (not finite, negative radius).
    #[error("query: {0}")]
    Shape(#[from] crate::geometry::query_shapes::ShapeError),
    /// A triangle index beyond a body's mesh.
    #[error("{body}: no triangle {triangle} (its mesh has {count})")]
    UnknownTriangle {
        /// The body.
        body: super::queries::BodyRef,
        /// The index asked for.
        triangle: u32,
        /// Triangles in the body's mesh.
        count: usize,
    },
    /// Continuous detection asked of a world that has not enabled it.
    #[error("continuous detection is off: call enable_continuous first")]
    ContinuousOff,
}
