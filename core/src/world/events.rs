//! Contacts between bodies as events: which bodies touch now, which began
//! to touch since the last step and which stopped, for an engine that
//! reacts to a touch once (a sound, a hit, a trigger) rather than to every
//! triangle pair of every step.

use super::contacts::{Contacts, Detection};
use super::handles::CharacterHandle;
use super::queries::BodyRef;

/// Two bodies with at least one contact: a character and what it touches
/// (a room, an object, another character of a higher handle, or itself).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct BodyPair {
    /// The character.
    pub character: CharacterHandle,
    /// What it touches (the character itself for self-contact).
    pub other: BodyRef,
}

/// A change in which bodies touch.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum ContactEvent {
    /// The two bodies touch now and did not at the last update.
    Began(BodyPair),
    /// The two bodies touched at the last update and do not now.
    Ended(BodyPair),
}

/// The bodies touching at each update and the events between updates; one
/// per world (or per detection kind: steps and sweeps each keep their own).
/// After its buffers have grown to the most body pairs seen, an update
/// allocates nothing.
///
/// ```
/// use cornertree::world::events::{BodyPair, ContactEvent, ContactEvents};
/// use cornertree::world::{BodyRef, CharacterHandle, RoomHandle, RoomPair, StepContacts};
///
/// let mut events = ContactEvents::new();
/// let mut step = StepContacts::default();
/// let hero = CharacterHandle(0);
/// let floor = BodyPair { character: hero, other: BodyRef::Room(RoomHandle(0)) };
/// // Two of the hero's triangles on the floor: the touch begins.
/// for triangle in [4, 9] {
///     step.room_pairs.push(RoomPair { character: hero, triangle, room: RoomHandle(0), room_triangle: 1 });
/// }
/// assert_eq!(events.update(&step), [ContactEvent::Began(floor)]);
/// assert_eq!(events.touching(), [(floor, 2)]);
/// // Still touching: no event.
/// assert!(events.update(&step).is_empty());
/// // Lifted: it ends.
/// step.room_pairs.clear();
/// assert_eq!(events.update(&step), [ContactEvent::Ended(floor)]);
/// ```
#[derive(Clone, Debug, Default)]
pub struct ContactEvents {
    /// The body pairs touching at the last update, sorted, with their
    /// triangle pairs.
    current: Vec<(BodyPair, u32)>,
    /// Those of the update before, while an update compares them.
    previous: Vec<(BodyPair, u32)>,
    events: Vec<ContactEvent>,
}

impl ContactEvents {
    /// No body touching yet.
    pub fn new() -> Self {
        Self::default()
    }

    /// Takes a step's (or a sweep's) contacts: the body pairs touching now,
    /// and the events since the last update (sorted: every `Began` before
    /// every `Ended`, each by body pair).
    pub fn update<D: Detection>(&mut self, contacts: &Contacts<D>) -> &[ContactEvent] {
        std::mem::swap(&mut self.current, &mut self.previous);
        let now = &mut self.current;
        now.clear();
        let mut add = |character, other| now.push((BodyPair { character, other }, 1));
        for p in &contacts.room_pairs {
            let p = D::pair(p);
            add(p.character, BodyRef::Room(p.room));
        }
        for p in &contacts.object_pairs {
            let p = D::pair(p);
            add(p.character, BodyRef::Object(p.object));
        }
        for p in &contacts.character_pairs {
            let p = D::pair(p);
            add(p.a, BodyRef::Character(p.b));
        }
        for p in &contacts.self_pairs {
            let p = D::pair(p);
            add(p.character, BodyRef::Character(p.character));
        }
        // One entry per body pair, counting its triangle pairs.
        now.sort_unstable_by_key(|e| e.0);
        now.dedup_by(|later, kept| {
            let same = later.0 == kept.0;
            if same {
                kept.1 += later.1;
            }
            same
        });
        // Both lists sorted: one merge finds what began and what ended.
        self.events.clear();
        let (mut i, mut j) = (0, 0);
        let (before, now) = (&self.previous, &self.current);
        while i < before.len() || j < now.len() {
            match (before.get(i), now.get(j)) {
                (Some(b), Some(n)) if b.0 == n.0 => (i, j) = (i + 1, j + 1),
                (Some(b), Some(n)) if b.0 < n.0 => {
                    self.events.push(ContactEvent::Ended(b.0));
                    i += 1;
                }
                (Some(b), None) => {
                    self.events.push(ContactEvent::Ended(b.0));
                    i += 1;
                }
                (_, Some(n)) => {
                    self.events.push(ContactEvent::Began(n.0));
                    j += 1;
                }
                (None, None) => unreachable!("the loop runs while either has more"),
            }
        }
        self.events.sort_unstable();
        &self.events
    }

    /// The body pairs touching at the last update, sorted, each with its
    /// number of triangle pairs.
    pub fn touching(&self) -> &[(BodyPair, u32)] {
        &self.current
    }

    /// The events of the last update.
    pub fn events(&self) -> &[ContactEvent] {
        &self.events
    }
}

#[cfg(test)]
mod tests {
    use std::collections::{BTreeMap, BTreeSet};

    use super::{BodyPair, ContactEvent, ContactEvents};
    use crate::test_rng::unit_floats;
    use crate::world::{
        BodyRef, CharacterHandle, CharacterPair, ObjectHandle, ObjectPair, RoomHandle, RoomPair,
        SelfPair, StepContacts,
    };

    /// Random contacts over many updates: the touching pairs are those a
    /// map of every contact counts, and the events the differences of two
    /// sets of them.
    #[test]
    fn events_are_the_differences_of_the_touching_sets() {
        let mut unit = unit_floats(23);
        let mut pick = |n: u32| ((unit() * n as f32) as u32).min(n - 1);
        let mut events = ContactEvents::new();
        let mut before: BTreeSet<BodyPair> = BTreeSet::new();
        let (mut began, mut ended) = (0, 0);
        for _ in 0..300 {
            let mut step = StepContacts::default();
            let mut naive: BTreeMap<BodyPair, u32> = BTreeMap::new();
            let mut count = |character: u32, other: BodyRef| {
                let p = BodyPair {
                    character: CharacterHandle(character),
                    other,
                };
                *naive.entry(p).or_default() += 1;
            };
            for _ in 0..pick(12) {
                let (c, r, t) = (pick(4), pick(2), pick(50));
                step.room_pairs.push(RoomPair {
                    character: CharacterHandle(c),
                    triangle: t,
                    room: RoomHandle(r),
                    room_triangle: pick(3),
                });
                count(c, BodyRef::Room(RoomHandle(r)));
            }
            for _ in 0..pick(6) {
                let (c, o) = (pick(4), pick(3));
                step.object_pairs.push(ObjectPair {
                    character: CharacterHandle(c),
                    triangle: pick(50),
                    object: ObjectHandle(o),
                    object_triangle: pick(12),
                });
                count(c, BodyRef::Object(ObjectHandle(o)));
            }
            for _ in 0..pick(6) {
                let a = pick(3);
                let b = a + 1 + pick(3 - a);
                step.character_pairs.push(CharacterPair {
                    a: CharacterHandle(a),
                    triangle_a: pick(50),
                    b: CharacterHandle(b),
                    triangle_b: pick(50),
                });
                count(a, BodyRef::Character(CharacterHandle(b)));
            }
            for _ in 0..pick(4) {
                let c = pick(4);
                step.self_pairs.push(SelfPair {
                    character: CharacterHandle(c),
                    triangle_a: pick(25),
                    triangle_b: 25 + pick(25),
                });
                count(c, BodyRef::Character(CharacterHandle(c)));
            }
            let got = events.update(&step).to_vec();
            let now: BTreeSet<BodyPair> = naive.keys().copied().collect();
            let mut expected: Vec<ContactEvent> = now
                .difference(&before)
                .map(|p| ContactEvent::Began(*p))
                .chain(before.difference(&now).map(|p| ContactEvent::Ended(*p)))
                .collect();
            expected.sort_unstable();
            assert_eq!(got, expected);
            let touching: Vec<(BodyPair, u32)> = naive.into_iter().collect();
            assert_eq!(events.touching(), touching);
            for e in &got {
                match e {
                    ContactEvent::Began(_) => began += 1,
                    ContactEvent::Ended(_) => ended += 1,
                }
            }
            before = now;
        }
        assert!(began > 100 && ended > 100, "{began} began, {ended} ended");
    }
}
