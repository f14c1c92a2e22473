//! Worlds: skinned characters, moving rigid objects and static rooms on one
//! step (the paper's "virtual world composed of several interactive
//! avatars ... and objects", §1), the library's entry point.
//!
//! | file | what |
//! |---|---|
//! | [`collision_world`] | [`CollisionWorld`]: bodies by handle, poses, settings, observers' views |
//! | `step` | [`CollisionWorld::step`]: a discrete step, every pass on the caller's threads |
//! | `sweep` | [`CollisionWorld::sweep`]: continuous detection over the step since the last sweep |
//! | [`queries`] | rays (first hit, all hits), balls and capsules against the bodies at their current poses, refit on demand |
//! | `continuous_state` | what continuous detection keeps beside the bodies |
//! | [`character_model`] | [`CharacterModel`]: what a character instance is made from, checked once |
//! | [`contacts`] | [`Contacts`]: pairs of every kind by handle, with counters ([`StepContacts`], [`SweepContacts`]) |
//! | [`events`] | [`ContactEvents`]: which bodies began and stopped touching between updates |
//! | [`contact_geometry`] | where a contact is: its triangles at the current poses and the segment they share ([`CollisionWorld::contact_geometry`]) |
//! | [`handles`] | [`RoomHandle`], [`ObjectHandle`], [`CharacterHandle`] |
//! | [`groups`] | [`CollisionGroups`]: which bodies meet (memberships and filter) |
//! | [`error`] | [`WorldError`]: the caller's bad data, named |
//! | `bodies` | what each body keeps between steps |
//! | [`broad_phase`] | which bodies' root spheres meet: sort and sweep, and every pair as its reference |
//! | `pass_pool` | what a pass needs only while it runs (marks, scratch), one set per thread, not per body |
//! | `pass_graph` | a step's passes on every thread, a character's own passes before its pairs, one pass per character at a time |
//! | [`pinning`] | opt-in: each thread of a pool on a processor of its own (Linux) |

pub(crate) mod bodies;
pub mod broad_phase;
pub mod character_model;
pub mod collision_world;
pub mod contact_geometry;
pub mod contacts;
mod continuous_state;
pub mod error;
pub mod events;
pub mod groups;
pub mod handles;
pub(crate) mod pass_graph;
mod pass_pool;
pub mod pinning;
pub mod queries;
mod step;
mod sweep;

pub use character_model::CharacterModel;
pub use collision_world::{CharacterView, CollisionWorld, WorldSettings};
pub use contact_geometry::{ContactGeometry, ContactRef};
pub use contacts::{
    ByKind, CharacterPair, Contacts, Detection, Discrete, ObjectPair, PairKind, RoomPair, SelfPair,
    StepContacts, SweepContacts, Swept, Timed,
};
pub use error::WorldError;
pub use events::{BodyPair, ContactEvent, ContactEvents};
pub use groups::CollisionGroups;
pub use handles::{CharacterHandle, ObjectHandle, RoomHandle};
pub use queries::{BodyRef, QueryCounters, QueryScratch, QueryTargets, RayHit, Touched};
