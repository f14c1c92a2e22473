//! A world of one character in a room of random triangles, per method,
//! against brute force; determinism; the visit log changes nothing.

mod common;

use std::collections::BTreeSet;
use std::sync::Arc;

use cornertree::character::{Character, PoseBuffers, SkinningModel};
use cornertree::geometry::tri_tri::triangles_intersect;
use cornertree::geometry::{Point, Triangle};
use cornertree::mesh::TriMesh;
use cornertree::pipeline::{FrameCounters, LeafTest, Method};
use cornertree::world::{
    CharacterHandle, CharacterModel, CollisionWorld, RoomHandle, WorldSettings,
};
use nalgebra::{Matrix4, Vector3};
use rand::{Rng, SeedableRng, rngs::SmallRng};

/// Small random triangles plus a few big ones, around (3, 3, 3).
fn environment(seed: u64) -> TriMesh {
    let small = common::soup(seed, 400, 6.0, 0.2);
    let mut p = small.positions().to_vec();
    let mut t = small.indices().to_vec();
    let mut rng = SmallRng::seed_from_u64(seed ^ 99);
    for _ in 0..5 {
        let base = p.len() as u32;
        for _ in 0..3 {
            p.push(Point::new(
                rng.random_range(-1.0..7.0),
                rng.random_range(-1.0..7.0),
                rng.random_range(-1.0..7.0),
            ));
        }
        t.push([base, base + 1, base + 2]);
    }
    TriMesh::new(p, t).unwrap()
}

fn brute_force(character: &Character, positions: &[Point], env: &TriMesh) -> BTreeSet<(u32, u32)> {
    let tri = |i: usize| {
        let [a, b, c] = character.mesh.indices()[i];
        Triangle::new(
            positions[a as usize],
            positions[b as usize],
            positions[c as usize],
        )
    };
    let mut out = BTreeSet::new();
    for i in 0..character.mesh.triangle_count() {
        let ct = tri(i);
        for (e, et) in env.iter_triangles() {
            if triangles_intersect(&ct, &et) {
                out.insert((i as u32, e.0));
            }
        }
    }
    out
}

/// One character in one room, detected with `method`.
struct One {
    method: Method,
    world: CollisionWorld,
    room: RoomHandle,
    character: CharacterHandle,
}

impl One {
    fn new(
        character: &Arc<Character>,
        env: &Arc<TriMesh>,
        method: Method,
        dedup: bool,
        skinning: SkinningModel,
    ) -> Self {
        let settings = WorldSettings {
            threshold: 1.0,
            ..WorldSettings::default()
        };
        let mut world = CollisionWorld::with_settings(method, settings);
        let room = world.add_room(env.clone()).unwrap();
        let model = if dedup {
            CharacterModel::deduplicated(character.clone(), skinning)
        } else {
            CharacterModel::new(character.clone(), skinning)
        };
        let character = world.add_character(Arc::new(model.unwrap())).unwrap();
        Self {
            method,
            world,
            room,
            character,
        }
    }

    /// One step at `pose`: its counters.
    fn detect(&mut self, pose: &PoseBuffers) -> FrameCounters {
        self.world.set_pose(self.character, pose).unwrap();
        self.world.step().total
    }

    /// The last step's (character triangle, room triangle) pairs.
    fn pairs(&self) -> Vec<(u32, u32)> {
        self.world
            .contacts()
            .room_pairs
            .iter()
            .map(|p| (p.triangle, p.room_triangle))
            .collect()
    }
}

#[test]
fn every_method_against_brute_force() {
    let mut contacts = 0;
    let mut skinned_all = 0;
    let mut leaf_plane_tests = 0;
    for seed in 0..4u64 {
        let character = Arc::new(common::random_character(seed, 6, 300));
        let env = Arc::new(environment(seed));
        let placement = Matrix4::new_translation(&Vector3::new(3.0, 3.0, 3.0));
        // Both skinning models: the pipeline skins with the one it was built for.
        let model = if seed % 2 == 0 {
            SkinningModel::Linear
        } else {
            SkinningModel::Paper
        };
        for dedup in [false, true] {
            let mut pipes: Vec<One> = Method::ALL
                .iter()
                .map(|&m| One::new(&character, &env, m, dedup, model))
                .collect();
            let mut buffers = PoseBuffers::new(&character);
            for frame in 0..3u64 {
                let local = common::random_pose(seed * 10 + frame, &character.skeleton, 1.0);
                buffers.local.copy_from_slice(&local);
                // Pose by hand (random poses are not a clip), then place and
                // skin every vertex for the brute force (the pipeline skins
                // what it needs itself).
                buffers.pose_local(&character);
                buffers.place(&placement);
                buffers.skin_all(&character, model);
                let exact = brute_force(&character, &buffers.positions, &env);
                contacts += exact.len();
                for p in &mut pipes {
                    let c = p.detect(&buffers);
                    let view = p.world.character(p.character).unwrap();
                    // What it skinned is what full skinning gives (on demand,
                    // or every vertex when most are tested).
                    assert!(c.skinned_vertices <= buffers.positions.len() as u64);
                    skinned_all +=
                        usize::from(c.skinned_vertices == buffers.positions.len() as u64);
                    for v in 0..buffers.positions.len() as u32 {
                        if view.skinned().is_current(v) {
                            assert_eq!(view.skinned().position(v), buffers.positions[v as usize]);
                        }
                    }
                    let got: BTreeSet<(u32, u32)> = p.pairs().into_iter().collect();
                    assert_eq!(c.pairs as usize, got.len());
                    let m = p.method;
                    match (m.big_leaf_test(), dedup) {
                        (LeafTest::TriTri, false) => {
                            assert_eq!(got, exact, "seed {seed} frame {frame} {m}")
                        }
                        (LeafTest::TriTri, true) => {
                            assert!(got.is_subset(&exact), "{m}: dedup only removes")
                        }
                        (LeafTest::PlaneSphere, false) => assert!(
                            got.is_superset(&exact),
                            "seed {seed} frame {frame} {m}: missed contacts"
                        ),
                        (LeafTest::PlaneSphere, true) => {}
                    }
                    if m == Method::Original {
                        assert_eq!(c.plane_sphere, 0);
                    }
                    // The paper's reading: every plane-sphere test pairs a
                    // character leaf with a big triangle's division leaf, one
                    // test per such leaf pair, none on the way down.
                    if m.big_leaf_test() == LeafTest::PlaneSphere && !m.prunes_at_plane() {
                        let ctree = &view.tree().tree;
                        let (room, _) = p.world.room(p.room).unwrap();
                        let at_division: Vec<_> = view
                            .room_leaf_pairs(p.room)
                            .iter()
                            .filter(|lp| room.is_division_leaf(lp.leaf_b))
                            .collect();
                        assert_eq!(c.plane_sphere, at_division.len() as u64, "{m}");
                        leaf_plane_tests += at_division.len();
                        for lp in at_division {
                            assert!(ctree.node(lp.leaf_a).is_leaf(), "{m}");
                            assert!(room.tree.node(lp.leaf_b).is_leaf(), "{m}");
                        }
                    }
                    // Our sphere-box tests (34 operations) come with the
                    // room's node boxes, which only these methods ask.
                    if !m.tests_each_pair_once() {
                        assert_eq!(c.sphere_box, 0, "{m}");
                    }
                    assert_eq!(
                        c.operations(),
                        10 * c.sphere_sphere
                            + 96 * c.tri_tri
                            + 30 * c.plane_sphere
                            + 34 * c.sphere_box
                            + 30 * c.box_box
                    );
                }
                // Testing the plane on the way down only removes pairs (and,
                // above, never a contact): each pruned method reports a subset
                // of what its leaf-only twin (the paper's reading) reports.
                let pairs_of = |m: Method| -> BTreeSet<(u32, u32)> {
                    let p = pipes.iter().find(|p| p.method == m).unwrap();
                    p.pairs().into_iter().collect()
                };
                for (pruned, literal) in [
                    (Method::PlaneSpherePruned, Method::PlaneSphere),
                    (
                        Method::QuaternaryPlaneSpherePruned,
                        Method::QuaternaryPlaneSphere,
                    ),
                ] {
                    assert!(
                        pairs_of(pruned).is_subset(&pairs_of(literal)),
                        "seed {seed} frame {frame}: {pruned} against {literal}"
                    );
                }
            }
        }
    }
    assert!(skinned_all > 0, "the skin-everything path is exercised");
    assert!(
        leaf_plane_tests > 0,
        "leaf-only plane-sphere tests are exercised"
    );
    assert!(
        contacts > 50,
        "the scenes must collide ({contacts} contacts)"
    );
}

#[test]
fn same_inputs_same_counters_and_pairs() {
    let character = Arc::new(common::random_character(3, 5, 200));
    let env = Arc::new(environment(3));
    let placement = Matrix4::new_translation(&Vector3::new(3.0, 3.0, 3.0));
    let run = || -> Vec<(FrameCounters, Vec<(u32, u32)>)> {
        let mut p = One::new(
            &character,
            &env,
            Method::PlaneSphere,
            true,
            SkinningModel::Linear,
        );
        let mut b = PoseBuffers::new(&character);
        (0..4)
            .map(|k| {
                let local = common::random_pose(k, &character.skeleton, 1.0);
                b.local.copy_from_slice(&local);
                b.pose_local(&character);
                b.place(&placement);
                let mut c = p.detect(&b);
                c.time = Default::default();
                (c, p.pairs())
            })
            .collect()
    };
    assert_eq!(run(), run());
}

/// The visit log a recorder turns on changes nothing that is measured: the
/// counters (times aside), the leaf pairs and the colliding pairs, for every
/// method, frame by frame.
#[test]
fn the_visit_log_changes_no_counter() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios/touching.toml");
    let r = cornertree_workbench::scenario::open_scenario(&path).unwrap();
    let env = Arc::new(r.environment.mesh.clone());
    let a = r.first();
    for m in Method::ALL {
        let mut plain = One::new(&a.character, &env, m, r.dedup, a.skinning);
        let mut logged = One::new(&a.character, &env, m, r.dedup, a.skinning);
        logged.world.set_visit_log(true);
        let mut b = PoseBuffers::new(&a.character);
        for k in 0..3 {
            a.pose_frame(&mut b, k);
            let mut c0 = plain.detect(&b);
            let mut c1 = logged.detect(&b);
            c0.time = Default::default();
            c1.time = Default::default();
            assert_eq!(c0, c1, "{m} frame {k}");
            assert!(c0.pairs > 0, "{m} frame {k}: contacts");
            let (v0, v1) = (
                plain.world.character(plain.character).unwrap(),
                logged.world.character(logged.character).unwrap(),
            );
            assert_eq!(
                v0.room_leaf_pairs(plain.room),
                v1.room_leaf_pairs(logged.room),
                "{m} frame {k}"
            );
            assert_eq!(plain.pairs(), logged.pairs(), "{m} frame {k}");
            assert!(v0.visit_log(plain.room).is_none());
            let log = v1.visit_log(logged.room).unwrap();
            assert_eq!(log.sphere_tests(), c1.sphere_sphere, "{m} frame {k}");
        }
    }
}
