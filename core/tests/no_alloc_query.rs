//! After a scratch has served its first queries, a query allocates nothing:
//! rays (first hit and every hit), balls and capsules against a world of a
//! room and walkers, each in a new pose (so spheres are refit and vertices
//! skinned on demand). One test in this binary, so no other test's
//! allocations are counted.

use std::sync::Arc;
use std::sync::atomic::Ordering;

#[path = "../../tests/common/counting_alloc.rs"]
mod counting_alloc;
/// The workbench's generated humanoid, for a realistic skinned character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;

use cornertree::character::{SkinningModel, Trs};
use cornertree::geometry::query_shapes::{Capsule, Ray};
use cornertree::geometry::{Point, Sphere, Vector};
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;
use cornertree::world::{
    CharacterHandle, CharacterModel, CollisionWorld, QueryScratch, QueryTargets,
};
use counting_alloc::ALLOCATIONS;
use nalgebra::{Isometry3, Translation3, UnitQuaternion};

#[test]
fn queries_allocate_nothing_once_the_scratch_is_sized() {
    let character = Arc::new(
        humanoid::generate_humanoid(&humanoid::HumanoidParams {
            vertices: 3000,
            seed: 5,
        })
        .unwrap(),
    );
    let floor = TriMesh::new(
        vec![
            Point::new(-3.0, 0.0, -3.0),
            Point::new(3.0, 0.0, -3.0),
            Point::new(3.0, 0.0, 3.0),
            Point::new(-3.0, 0.0, 3.0),
        ],
        vec![[0, 2, 1], [0, 3, 2]],
    )
    .unwrap();
    let mut world = CollisionWorld::new(Method::UndividedPrunedTriTri);
    world.add_room(Arc::new(floor)).unwrap();
    let model = Arc::new(CharacterModel::new(character.clone(), SkinningModel::Linear).unwrap());
    for _ in 0..3 {
        world.add_character(model.clone()).unwrap();
    }
    let mut local: Vec<Trs> = character.skeleton.rest_pose();
    let clip = &character.clips[0];
    // A grid of rays over the walkers, a ball and a capsule at each.
    let rays: Vec<Ray> = (0..400)
        .map(|i| {
            let (x, y) = ((i % 20) as f32 * 0.08 - 0.5, (i / 20) as f32 * 0.09);
            Ray::new(
                Point::new(x, y, 3.0),
                Vector::new(0.02, 0.0, -1.0),
                f32::INFINITY,
            )
            .unwrap()
        })
        .collect();
    let mut scratch = QueryScratch::new();
    let (mut all, mut touched) = (Vec::new(), Vec::new());
    let mut frame =
        |k: usize, world: &mut CollisionWorld, scratch: &mut QueryScratch| -> (u64, usize) {
            let t = clip.start() + clip.duration() * (k % 20) as f32 / 20.0;
            for c in 0..3u32 {
                clip.sample(
                    t + 0.1 * c as f32,
                    character.skeleton.rest_pose_ref(),
                    &mut local,
                );
                let place = Isometry3::from_parts(
                    Translation3::new(0.4 * c as f32 - 0.4, 0.0, 0.0),
                    UnitQuaternion::identity(),
                );
                world
                    .set_joint_transforms(CharacterHandle(c), &local, &place)
                    .unwrap();
            }
            let before = ALLOCATIONS.load(Ordering::Relaxed);
            let mut hits = 0;
            for r in &rays {
                hits += world
                    .cast_ray(r, QueryTargets::All, scratch)
                    .unwrap()
                    .is_some() as usize;
                world
                    .cast_ray_all(r, QueryTargets::Characters, scratch, &mut all)
                    .unwrap();
                let p = r.origin + r.direction * 2.9;
                world
                    .overlap_sphere(
                        &Sphere::new(p, 0.05),
                        QueryTargets::All,
                        scratch,
                        &mut touched,
                    )
                    .unwrap();
                let cap = Capsule::new(p, p + Vector::new(0.0, 0.2, 0.0), 0.03).unwrap();
                world
                    .overlap_capsule(&cap, QueryTargets::All, scratch, &mut touched)
                    .unwrap();
            }
            (ALLOCATIONS.load(Ordering::Relaxed) - before, hits)
        };
    let first: Vec<(u64, usize)> = (0..20)
        .map(|k| frame(k, &mut world, &mut scratch))
        .collect();
    let second: Vec<(u64, usize)> = (0..20)
        .map(|k| frame(k, &mut world, &mut scratch))
        .collect();
    assert!(first[0].0 > 0, "the first queries size the scratch");
    assert!(
        second.iter().all(|&(n, _)| n == 0),
        "allocations per frame of queries on the replay: {second:?}"
    );
    assert!(
        second.iter().all(|&(_, hits)| hits > 50),
        "the rays hit: {second:?}"
    );
}
