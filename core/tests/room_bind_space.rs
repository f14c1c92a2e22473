//! A wall through a character's body: the room pass answers many of the
//! triangles one joint moves from their bind corners, never skinning them
//! (`pipeline::bind_planes`), and still reports exactly the contacts an
//! exact brute force over every skinned triangle finds, under both skinning
//! models and for both methods that test each pair once.

use std::collections::BTreeSet;
use std::sync::Arc;

/// The workbench's generated humanoid, for a realistic skinned character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;

use cornertree::character::{PoseBuffers, SkinningModel};
use cornertree::geometry::exact::triangles_intersect_exact;
use cornertree::geometry::{Point, Triangle};
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;
use cornertree::world::{CharacterModel, CollisionWorld};
use nalgebra::Matrix4;

/// A floor at `floor_y` and a wall `x = wall_x`, two big triangles each,
/// reaching well past the character.
fn room(floor_y: f32, wall_x: f32) -> TriMesh {
    let p = vec![
        Point::new(-4.0, floor_y, -4.0),
        Point::new(4.0, floor_y, -4.0),
        Point::new(4.0, floor_y, 4.0),
        Point::new(-4.0, floor_y, 4.0),
        Point::new(wall_x, -4.0, -4.0),
        Point::new(wall_x, 4.0, -4.0),
        Point::new(wall_x, 4.0, 4.0),
        Point::new(wall_x, -4.0, 4.0),
    ];
    TriMesh::new(p, vec![[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7]]).expect("a valid mesh")
}

#[test]
fn a_wall_through_the_body_gives_the_exact_pairs_mostly_unskinned() {
    let character = Arc::new(
        humanoid::generate_humanoid(&humanoid::HumanoidParams {
            vertices: 3000,
            seed: 2,
        })
        .expect("valid parameters"),
    );
    let clip = &character.clips[0];
    let (lo, hi) = character.mesh.bounds();
    // Per model, (apart, contact) pairs answered with a corner left unskinned.
    let mut unskinned = [[0usize; 2]; 2];
    let mut contacts = 0;
    for (m, model) in [SkinningModel::Linear, SkinningModel::Paper]
        .into_iter()
        .enumerate()
    {
        let shared = Arc::new(CharacterModel::new(character.clone(), model).expect("a model"));
        for method in [Method::UndividedPrunedTriTri, Method::PrunedTriTri] {
            for share in [0.35f32, 0.5] {
                let mesh = Arc::new(room(lo.y + 0.01, lo.x + share * (hi.x - lo.x)));
                let mut world = CollisionWorld::new(method);
                let room_handle = world.add_room(mesh.clone()).expect("in range");
                let h = world.add_character(shared.clone()).expect("in range");
                let mut b = PoseBuffers::new(&character);
                for k in 0..4 {
                    let t = clip.start() + clip.duration() * k as f32 / 4.0;
                    b.pose(&character, Some(clip), t);
                    b.place(&Matrix4::identity());
                    b.skin_all(&character, model);
                    world.set_pose(h, &b).expect("joints match");
                    world.step();

                    let tri = |i: usize| {
                        let [x, y, z] = character.mesh.indices()[i];
                        let p = |v: u32| b.positions[v as usize];
                        Triangle::new(p(x), p(y), p(z))
                    };
                    let mut exact = BTreeSet::new();
                    for i in 0..character.mesh.triangle_count() {
                        for (r, rt) in mesh.iter_triangles() {
                            if triangles_intersect_exact(&tri(i), &rt) {
                                exact.insert((i as u32, r.0));
                            }
                        }
                    }
                    let got: BTreeSet<(u32, u32)> = world
                        .contacts()
                        .room_pairs
                        .iter()
                        .map(|p| (p.triangle, p.room_triangle))
                        .collect();
                    assert_eq!(got, exact, "{model:?} {method} wall at {share} frame {k}");
                    contacts += exact.len();

                    let view = world.character(h).expect("added");
                    for lp in view.room_leaf_pairs(room_handle) {
                        let corners = character.mesh.indices()[lp.primitive_a as usize];
                        if !corners.iter().all(|&v| view.skinned().is_current(v)) {
                            let hit = exact.contains(&(lp.primitive_a, lp.primitive_b));
                            unskinned[m][usize::from(hit)] += 1;
                        }
                    }
                }
            }
        }
    }
    assert!(
        contacts > 5_000,
        "the wall cuts the body: {contacts} contacts"
    );
    // Both answers, under both models (about 11,000 and 3,000 each).
    for [apart, contact] in unskinned {
        assert!(
            apart > 4_000 && contact > 1_000,
            "pairs answered from bind corners (apart, contact): {unskinned:?}"
        );
    }
}
