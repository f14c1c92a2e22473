//! Self-collision for some characters of a world only: a character turned
//! on in a world that tests none against itself finds, step by step and
//! sweep by sweep, the self pairs a world testing every character finds for
//! it, and the other kinds' pairs do not change; turned off, it finds none.

#[path = "common/box_mesh.rs"]
mod box_mesh;
/// The workbench's generated humanoid, for a realistic skinned character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;
#[path = "common/walkers.rs"]
#[allow(dead_code)]
mod walkers;

use cornertree::world::{CharacterHandle, WorldError};
use walkers::Scene;

#[test]
fn one_character_against_itself_as_in_a_world_that_tests_all() {
    let mut scene = Scene::new();
    let mut some = scene.world_with(3, true, false);
    let mut all = scene.world_with(3, true, true);
    let hero = CharacterHandle(1);
    let (mut hero_pairs, mut swept_hero_pairs) = (0, 0);
    for k in 0..6 {
        // On from the second step, off again for the last.
        let on = (1..5).contains(&k);
        some.set_self_collision(hero, on).unwrap();
        assert_eq!(some.self_collision_of(hero).unwrap(), on);
        assert!(!some.self_collision_of(CharacterHandle(0)).unwrap());
        scene.pose(k, false);
        for c in 0..3 {
            let h = CharacterHandle(c as u32);
            some.set_pose(h, &scene.poses[c]).unwrap();
            all.set_pose(h, &scene.poses[c]).unwrap();
        }
        let object_pose = Scene::object_pose(k);
        for w in [&mut some, &mut all] {
            w.set_object_pose(cornertree::world::ObjectHandle(0), object_pose)
                .unwrap();
        }
        let got = some.step().clone();
        let reference = all.step();
        let expected: Vec<_> = if on {
            reference.self_contacts_of(hero).to_vec()
        } else {
            Vec::new()
        };
        assert_eq!(got.self_pairs, expected, "step {k}: self pairs");
        assert_eq!(got.room_pairs, reference.room_pairs, "step {k}");
        assert_eq!(got.object_pairs, reference.object_pairs, "step {k}");
        assert_eq!(got.character_pairs, reference.character_pairs, "step {k}");
        hero_pairs += got.self_pairs.len();

        // Continuous detection: the same, over each step.
        let got = some.sweep().unwrap().clone();
        let reference = all.sweep().unwrap();
        let expected: Vec<_> = if on {
            reference.self_contacts_of(hero).to_vec()
        } else {
            Vec::new()
        };
        assert_eq!(got.self_pairs, expected, "sweep {k}: self pairs");
        assert_eq!(got.room_pairs, reference.room_pairs, "sweep {k}");
        assert_eq!(got.character_pairs, reference.character_pairs, "sweep {k}");
        swept_hero_pairs += got.self_pairs.len();
    }
    assert!(hero_pairs > 100, "{hero_pairs} self pairs of the hero");
    assert!(
        swept_hero_pairs > 100,
        "{swept_hero_pairs} swept self pairs"
    );
    assert_eq!(
        some.set_self_collision(CharacterHandle(3), true),
        Err(WorldError::UnknownCharacter(CharacterHandle(3)))
    );
}
