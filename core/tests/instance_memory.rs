//! Instances of one character model share what does not move: the model's
//! mesh, skeleton and weights and each world's tree over it are built once,
//! and every further instance holds only its pose, its refit state and its
//! per-step buffers. Measured in live heap bytes with a counting allocator
//! (one test in this binary, so no other test's allocations are counted).

use std::alloc::{GlobalAlloc, Layout, System};
use std::sync::Arc;
use std::sync::atomic::{AtomicIsize, Ordering};

/// The workbench's generated humanoid, for a realistic skinned character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;

use cornertree::character::SkinningModel;
use cornertree::geometry::Point;
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;
use cornertree::world::{CharacterModel, CollisionWorld};
use nalgebra::{Isometry3, Translation3, UnitQuaternion};

struct Live;

static LIVE: AtomicIsize = AtomicIsize::new(0);

unsafe impl GlobalAlloc for Live {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        LIVE.fetch_add(layout.size() as isize, Ordering::Relaxed);
        unsafe { System.alloc(layout) }
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        LIVE.fetch_sub(layout.size() as isize, Ordering::Relaxed);
        unsafe { System.dealloc(ptr, layout) }
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        LIVE.fetch_add(
            new_size as isize - layout.size() as isize,
            Ordering::Relaxed,
        );
        unsafe { System.realloc(ptr, layout, new_size) }
    }
}

#[global_allocator]
static GLOBAL: Live = Live;

fn live() -> isize {
    LIVE.load(Ordering::Relaxed)
}

/// A floor 40 m on a side (two big triangles).
fn floor() -> TriMesh {
    let p = vec![
        Point::new(-20.0, 0.0, -20.0),
        Point::new(20.0, 0.0, -20.0),
        Point::new(20.0, 0.0, 20.0),
        Point::new(-20.0, 0.0, 20.0),
    ];
    TriMesh::new(p, vec![[0, 2, 1], [0, 3, 2]]).unwrap()
}

/// Bytes an instance of a 10k-vertex humanoid holds alone in a world of
/// the crowd's method, its first steps included.
const MOST_PER_INSTANCE: isize = 1 << 20;

#[test]
fn instances_of_one_model_share_it_and_hold_at_most_a_mebibyte_each() {
    let character = humanoid::generate_humanoid(&humanoid::HumanoidParams {
        vertices: 10_000,
        seed: 11,
    })
    .unwrap();
    let model = Arc::new(CharacterModel::new(character, SkinningModel::Linear).unwrap());
    let local = model.character().skeleton.rest_pose_ref().to_vec();
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| {
        let mut world = CollisionWorld::new(Method::UndividedPrunedTriTri);
        world.add_room(Arc::new(floor())).unwrap();
        // Each instance stands on the floor in a grid 0.6 m apart (feet in
        // contact with the floor, neighbours' root spheres overlapping).
        let place = |world: &mut CollisionWorld, n: usize| {
            for i in 0..n {
                let h = cornertree::world::CharacterHandle(i as u32);
                let at = Isometry3::from_parts(
                    Translation3::new((i % 8) as f32 * 0.6, 0.0, (i / 8) as f32 * 0.6),
                    UnitQuaternion::identity(),
                );
                world.set_joint_transforms(h, &local, &at).unwrap();
            }
        };
        let before = live();
        world.add_character(model.clone()).unwrap();
        place(&mut world, 1);
        world.step();
        let first = live() - before;
        let (more, steps) = (16usize, 3);
        let before = live();
        for _ in 0..more {
            world.add_character(model.clone()).unwrap();
        }
        let built = (live() - before) / more as isize;
        for _ in 0..steps {
            place(&mut world, 1 + more);
            world.step();
        }
        let per = (live() - before) / more as isize;
        eprintln!(
            "first instance (tree built): {:.0} KiB; each further one: {:.0} KiB built, {:.0} KiB after steps",
            first as f64 / 1024.0,
            built as f64 / 1024.0,
            per as f64 / 1024.0
        );
        assert!(
            per <= MOST_PER_INSTANCE,
            "an instance holds {per} bytes alone, more than {MOST_PER_INSTANCE}"
        );
        assert!(
            per * 3 < first,
            "instances do not share the tree: {per} bytes each, {first} for the first"
        );
    });
}
