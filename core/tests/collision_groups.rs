//! Collision groups: a world whose bodies carry groups reports, step by
//! step and sweep by sweep, exactly the contacts of the same world without
//! groups whose two bodies' groups meet; a query looking at the bodies
//! meeting some groups finds the nearest hit among those bodies only.

#[path = "common/box_mesh.rs"]
mod box_mesh;
/// The workbench's generated humanoid, for a realistic skinned character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;
#[path = "common/walkers.rs"]
#[allow(dead_code)]
mod walkers;

use cornertree::geometry::Point;
use cornertree::geometry::query_shapes::Ray;
use cornertree::world::{
    BodyRef, CharacterHandle, CollisionGroups, Contacts, Detection, ObjectHandle, QueryScratch,
    QueryTargets, RoomHandle,
};
use rand::{Rng, SeedableRng, rngs::SmallRng};
use walkers::Scene;

const FLOOR: u32 = 1;
const CROWD: u32 = 2;
const PROPS: u32 = 4;
const HERO: u32 = 8;

/// Walker 0 (the hero, whom the box crosses) meets the floor and the crowd
/// but not the box; walker 1 meets everything; walker 2 only the box (no
/// floor, no walker).
fn walker_groups(c: u32) -> CollisionGroups {
    match c {
        0 => CollisionGroups::new(HERO, FLOOR | CROWD),
        1 => CollisionGroups::new(CROWD, u32::MAX),
        _ => CollisionGroups::new(CROWD, PROPS),
    }
}
const FLOOR_GROUPS: CollisionGroups = CollisionGroups::new(FLOOR, u32::MAX);
const BOX_GROUPS: CollisionGroups = CollisionGroups::new(PROPS, u32::MAX);

fn character(h: CharacterHandle) -> CollisionGroups {
    walker_groups(h.0)
}

/// The contacts of `c` whose bodies meet, and how many do not, by kind
/// (rooms, objects, characters).
fn split<D: Detection>(c: &Contacts<D>) -> (Vec<String>, [usize; 3]) {
    let (mut kept, mut dropped) = (Vec::new(), [0; 3]);
    let mut keep = |kind: usize, meets: bool, text: String| {
        if meets {
            kept.push(text);
        } else {
            dropped[kind] += 1;
        }
    };
    for p in &c.room_pairs {
        let q = D::pair(p);
        keep(
            0,
            character(q.character).meets(FLOOR_GROUPS),
            format!("{p:?}"),
        );
    }
    for p in &c.object_pairs {
        let q = D::pair(p);
        keep(
            1,
            character(q.character).meets(BOX_GROUPS),
            format!("{p:?}"),
        );
    }
    for p in &c.character_pairs {
        let q = D::pair(p);
        keep(2, character(q.a).meets(character(q.b)), format!("{p:?}"));
    }
    (kept, dropped)
}

/// Every contact of `c`, as `split` writes them.
fn all<D: Detection>(c: &Contacts<D>) -> Vec<String> {
    let pairs = c.room_pairs.iter().map(|p| format!("{p:?}"));
    let pairs = pairs.chain(c.object_pairs.iter().map(|p| format!("{p:?}")));
    pairs
        .chain(c.character_pairs.iter().map(|p| format!("{p:?}")))
        .collect()
}

#[test]
fn groups_leave_out_exactly_the_pairs_that_do_not_meet() {
    let mut scene = Scene::new();
    let mut grouped = scene.world_with(3, true, false);
    let mut plain = scene.world_with(3, true, false);
    grouped
        .set_room_groups(RoomHandle(0), FLOOR_GROUPS)
        .unwrap();
    grouped
        .set_object_groups(ObjectHandle(0), BOX_GROUPS)
        .unwrap();
    for c in 0..3 {
        grouped
            .set_character_groups(CharacterHandle(c), walker_groups(c))
            .unwrap();
    }
    let mut rng = SmallRng::seed_from_u64(9);
    let mut scratch = QueryScratch::new();
    let (mut dropped_steps, mut dropped_sweeps, mut ray_hits) = ([0; 3], [0; 3], 0);
    let hero_query = CollisionGroups::new(u32::MAX, !HERO);
    for k in 0..6 {
        scene.pose(k, false);
        for c in 0..3 {
            let h = CharacterHandle(c as u32);
            grouped.set_pose(h, &scene.poses[c]).unwrap();
            plain.set_pose(h, &scene.poses[c]).unwrap();
        }
        for w in [&mut grouped, &mut plain] {
            w.set_object_pose(ObjectHandle(0), Scene::object_pose(k))
                .unwrap();
        }
        // A hit-scan that ignores the hero: the nearest hit among the other
        // bodies, as every hit of the plain world shows.
        for _ in 0..30 {
            let o = Point::new(
                rng.random_range(-1.5..1.5),
                rng.random_range(0.3..1.8),
                rng.random_range(1.5..3.0),
            );
            let to = Point::new(rng.random_range(-1.0..1.0), rng.random_range(0.0..1.8), 0.1);
            let ray = Ray::new(o, to - o, f32::INFINITY).unwrap();
            let got = grouped
                .cast_ray(&ray, QueryTargets::Meeting(hero_query), &mut scratch)
                .unwrap();
            let mut every = Vec::new();
            plain
                .cast_ray_all(&ray, QueryTargets::All, &mut scratch, &mut every)
                .unwrap();
            let expected = every
                .into_iter()
                .find(|h| h.body != BodyRef::Character(CharacterHandle(0)));
            assert_eq!(
                got.map(|h| (h.body, h.triangle)),
                expected.map(|h| (h.body, h.triangle)),
                "frame {k}: a ray ignoring the hero"
            );
            ray_hits += usize::from(got.is_some());
        }

        let got = all(grouped.step());
        let (expected, dropped) = split(plain.step());
        assert_eq!(got, expected, "step {k}");
        (0..3).for_each(|i| dropped_steps[i] += dropped[i]);
        let got = all(grouped.sweep().unwrap());
        let (expected, dropped) = split(plain.sweep().unwrap());
        assert_eq!(got, expected, "sweep {k}");
        (0..3).for_each(|i| dropped_sweeps[i] += dropped[i]);
    }
    // Every kind loses pairs to the groups.
    assert!(
        dropped_steps.iter().chain(&dropped_sweeps).all(|&n| n > 0),
        "pairs left out by kind: {dropped_steps:?} in steps, {dropped_sweeps:?} in sweeps"
    );
    assert!(ray_hits > 30, "{ray_hits} rays hit");
}
