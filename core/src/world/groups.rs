//! Which bodies meet: collision groups, the filter every engine's layers
//! come down to. Each body belongs to some groups (`memberships`) and meets
//! bodies of some groups (`filter`); two bodies are tested against each
//! other only if each one's memberships share a group with the other's
//! filter. By default every body is in every group and meets every group.

/// The groups a body belongs to and the groups it meets (32 groups, one bit
/// each).
///
/// ```
/// use cornertree::world::CollisionGroups;
///
/// const FLOOR: u32 = 1;
/// const CROWD: u32 = 2;
/// const PROPS: u32 = 4;
/// let floor = CollisionGroups::new(FLOOR, u32::MAX);
/// // Extras stand on the floor and brush each other, but walk through props.
/// let extra = CollisionGroups::new(CROWD, FLOOR | CROWD);
/// let prop = CollisionGroups::new(PROPS, u32::MAX);
/// assert!(extra.meets(floor) && extra.meets(extra));
/// assert!(!extra.meets(prop) && !prop.meets(extra));
/// assert!(CollisionGroups::ALL.meets(prop));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
pub struct CollisionGroups {
    /// The groups the body belongs to.
    pub memberships: u32,
    /// The groups it meets.
    pub filter: u32,
}

impl CollisionGroups {
    /// In every group, meeting every group (every body's default).
    pub const ALL: Self = Self::new(u32::MAX, u32::MAX);

    /// A body in `memberships` meeting `filter`.
    pub const fn new(memberships: u32, filter: u32) -> Self {
        Self {
            memberships,
            filter,
        }
    }

    /// Whether two bodies of these groups are tested against each other:
    /// each one's memberships share a group with the other's filter.
    #[inline]
    pub const fn meets(self, other: Self) -> bool {
        self.memberships & other.filter != 0 && other.memberships & self.filter != 0
    }
}

impl Default for CollisionGroups {
    fn default() -> Self {
        Self::ALL
    }
}
