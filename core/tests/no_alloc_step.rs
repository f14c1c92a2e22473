//! After its buffers are sized, a world's step allocates nothing: the
//! caller's poses handed in, every character's passes against the room and
//! a moving object, the character pairs, rayon's scheduling (the steps run
//! inside the caller's pool), on one thread and on two. One test in this
//! binary, so no other test's allocations are counted.

use std::sync::Arc;
use std::sync::atomic::Ordering;

#[path = "common/box_mesh.rs"]
mod box_mesh;
#[path = "../../tests/common/counting_alloc.rs"]
mod counting_alloc;
/// The workbench's generated humanoid, for a realistic skinned character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;
use box_mesh::box_mesh;

use cornertree::character::{Character, Trs};
use cornertree::geometry::Point;
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;
use cornertree::world::{CharacterModel, CollisionWorld, StepContacts};
use counting_alloc::ALLOCATIONS;
use nalgebra::{Isometry3, Translation3, UnitQuaternion};

/// A floor and a wall (big triangles), in world coordinates.
fn room() -> TriMesh {
    let p = vec![
        Point::new(-3.0, 0.0, -3.0),
        Point::new(3.0, 0.0, -3.0),
        Point::new(3.0, 0.0, 3.0),
        Point::new(-3.0, 0.0, 3.0),
        Point::new(-3.0, 0.0, -0.3),
        Point::new(3.0, 0.0, -0.3),
        Point::new(3.0, 2.5, -0.3),
        Point::new(-3.0, 2.5, -0.3),
    ];
    TriMesh::new(p, vec![[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7]]).unwrap()
}

/// Three walkers 35 cm apart, and a box crossing them.
struct Scene {
    world: CollisionWorld,
    character: Arc<Character>,
    local: Vec<Trs>,
}

impl Scene {
    fn new(method: Method, normal_cones: bool) -> Self {
        let character = Arc::new(
            humanoid::generate_humanoid(&humanoid::HumanoidParams {
                vertices: 3000,
                seed: 5,
            })
            .unwrap(),
        );
        // Each walker also against itself: every kind of pass takes part.
        let settings = cornertree::world::WorldSettings {
            self_collision: true,
            self_normal_cone_culling: normal_cones,
            ..Default::default()
        };
        let mut world = CollisionWorld::with_settings(method, settings);
        world.add_room(Arc::new(room())).unwrap();
        world
            .add_object(Arc::new(box_mesh()), Isometry3::identity())
            .unwrap();
        let model = Arc::new(
            CharacterModel::new(
                character.clone(),
                cornertree::character::SkinningModel::Linear,
            )
            .unwrap(),
        );
        for _ in 0..3 {
            world.add_character(model.clone()).unwrap();
        }
        let local = character.skeleton.rest_pose();
        Self {
            world,
            character,
            local,
        }
    }

    /// Step `k`: each walker's clip sampled by the caller, placed; walker 2
    /// and the box out on some steps; the box moved; the world stepped.
    fn step(&mut self, k: usize) -> &StepContacts {
        let clip = &self.character.clips[0];
        let t = clip.start() + clip.duration() * (k % 30) as f32 / 30.0;
        for c in 0..3 {
            clip.sample(
                t + 0.1 * c as f32,
                self.character.skeleton.rest_pose_ref(),
                &mut self.local,
            );
            let placement = Isometry3::from_parts(
                Translation3::new(0.35 * c as f32, 0.0, 0.0),
                UnitQuaternion::identity(),
            );
            let h = cornertree::world::CharacterHandle(c);
            self.world
                .set_joint_transforms(h, &self.local, &placement)
                .unwrap();
        }
        // Walker 2 and the box sit some steps out (a pool of instances):
        // toggling allocates nothing either.
        self.world
            .set_character_active(cornertree::world::CharacterHandle(2), k % 4 != 1)
            .unwrap();
        self.world
            .set_object_active(cornertree::world::ObjectHandle(0), k % 5 != 2)
            .unwrap();
        let x = -0.5 + 1.5 * (k % 30) as f32 / 30.0;
        self.world
            .set_object_pose(
                cornertree::world::ObjectHandle(0),
                Isometry3::translation(x, 1.0, 0.1),
            )
            .unwrap();
        self.world.step()
    }
}

#[test]
fn steps_allocate_nothing_once_buffers_are_sized() {
    let frames = 12;
    // The self pass's normal cones (off by default) once, on one method.
    for (method, cones) in [
        (Method::UndividedPrunedTriTri, false),
        (Method::PlaneSphere, false),
        (Method::UndividedPrunedTriTri, true),
    ] {
        for threads in [1, 2] {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(threads)
                .build()
                .unwrap();
            let mut scene = Scene::new(method, cones);
            let mut events = cornertree::world::ContactEvents::new();
            let (first, second, kinds) = pool.install(|| {
                let mut kinds = [0usize; 4];
                let mut pass = |kinds: &mut [usize; 4]| {
                    (0..frames)
                        .map(|k| {
                            let before = ALLOCATIONS.load(Ordering::Relaxed);
                            let c = scene.step(k);
                            // Which bodies began or stopped touching.
                            events.update(c);
                            let n = ALLOCATIONS.load(Ordering::Relaxed) - before;
                            kinds[0] += c.room_pairs.len();
                            kinds[1] += c.object_pairs.len();
                            kinds[2] += c.character_pairs.len();
                            kinds[3] += c.self_pairs.len();
                            n
                        })
                        .collect::<Vec<u64>>()
                };
                let first = pass(&mut kinds);
                let second = pass(&mut kinds);
                (first, second, kinds)
            });
            assert!(first[0] > 0, "{method}: the first step sizes the buffers");
            assert!(
                second.iter().all(|&n| n == 0),
                "{method} (normal cones {cones}), {threads} threads: allocations per step on the replay: \
                 {second:?} (first pass {first:?})"
            );
            // Every kind of pair takes part.
            assert!(
                kinds.iter().all(|&n| n > 0),
                "{method}: pairs per kind {kinds:?}"
            );
        }
    }
}
