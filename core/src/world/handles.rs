//! Handles of a world's bodies: what [`CollisionWorld`](super::CollisionWorld)'s
//! `add_*` calls return and its contacts name. A handle is the body's
//! position among the bodies of its kind, in the order they were added
//! (bodies are never removed), so a caller may keep its own data in a
//! vector indexed by [`index`](CharacterHandle::index). A body that leaves
//! the scene is set inactive instead, and active again when it comes back
//! (`CollisionWorld::set_character_active`, `set_object_active`,
//! `set_room_active`): a pool of instances for a crowd that comes and goes,
//! a level streamed out and in.

macro_rules! handle {
    ($(#[$doc:meta])* $name:ident, $what:literal) => {
        $(#[$doc])*
        #[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
        #[cfg_attr(feature = "serde", derive(serde::Serialize))]
        #[cfg_attr(feature = "serde", serde(transparent))]
        pub struct $name(pub u32);

        impl $name {
            /// The body's position among the bodies of its kind, from 0.
            #[inline]
            pub fn index(self) -> usize {
                self.0 as usize
            }
        }

        impl std::fmt::Display for $name {
            fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                write!(f, concat!($what, " {}"), self.0)
            }
        }
    };
}

handle!(
    /// A static room of a world (triangles that never move).
    RoomHandle,
    "room"
);
handle!(
    /// A moving rigid object of a world.
    ObjectHandle,
    "object"
);
handle!(
    /// A skinned character of a world.
    CharacterHandle,
    "character"
);
