//! Queries against a world (rays, balls, capsules) give what a brute-force
//! pass over every triangle of every body at the same poses gives, with
//! the same shape-triangle tests: the traversal, the on-demand refit and
//! the culling lose nothing. A ray that misses every root costs one test
//! per body; a frame's spheres are refit once whether a query or a step
//! asks first, and a step's contacts do not depend on queries before it.

use std::sync::Arc;

#[path = "common/box_mesh.rs"]
mod box_mesh;
/// The workbench's generated humanoid, for a realistic skinned character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;
use box_mesh::box_mesh;

use cornertree::character::{Character, PoseBuffers, SkinningModel};
use cornertree::geometry::query_shapes::{Capsule, Ray};
use cornertree::geometry::{Point, Sphere, Triangle, Vector};
use cornertree::mesh::{TriMesh, TriangleId};
use cornertree::pipeline::Method;
use cornertree::world::{
    BodyRef, CharacterHandle, CharacterModel, CollisionWorld, ObjectHandle, QueryScratch,
    QueryTargets, RoomHandle, Touched,
};
use nalgebra::{Isometry3, Matrix4, Translation3, UnitQuaternion, Vector3};
use rand::{Rng, SeedableRng, rngs::SmallRng};

/// A floor and a wall of big triangles, and a strip of small ones.
fn room() -> TriMesh {
    let mut p = vec![
        Point::new(-3.0, 0.0, -3.0),
        Point::new(3.0, 0.0, -3.0),
        Point::new(3.0, 0.0, 3.0),
        Point::new(-3.0, 0.0, 3.0),
        Point::new(-3.0, 0.0, -0.6),
        Point::new(3.0, 0.0, -0.6),
        Point::new(3.0, 2.5, -0.6),
        Point::new(-3.0, 2.5, -0.6),
    ];
    let mut t = vec![[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7]];
    for k in 0..20u32 {
        let x = -1.0 + 0.1 * k as f32;
        let base = p.len() as u32;
        p.extend([
            Point::new(x, 0.8, -0.5),
            Point::new(x + 0.1, 0.8, -0.5),
            Point::new(x + 0.05, 0.9, -0.45),
        ]);
        t.push([base, base + 1, base + 2]);
    }
    TriMesh::new(p, t).unwrap()
}

/// A world of a room, a box and three walkers, and every body's triangles
/// in the world at its current pose (the brute force's input).
struct Scene {
    world: CollisionWorld,
    character: Arc<Character>,
    poses: Vec<PoseBuffers>,
    room: Arc<TriMesh>,
    object: Arc<TriMesh>,
    object_pose: Isometry3<f32>,
}

impl Scene {
    fn new(method: Method, model: SkinningModel) -> Self {
        let character = Arc::new(
            humanoid::generate_humanoid(&humanoid::HumanoidParams {
                vertices: 2500,
                seed: 3,
            })
            .unwrap(),
        );
        let mut world = CollisionWorld::new(method);
        let room = Arc::new(room());
        let object = Arc::new(box_mesh());
        world.add_room(room.clone()).unwrap();
        world
            .add_object(object.clone(), Isometry3::identity())
            .unwrap();
        let m = Arc::new(CharacterModel::new(character.clone(), model).unwrap());
        let poses = (0..3)
            .map(|_| {
                world.add_character(m.clone()).unwrap();
                PoseBuffers::new(&character)
            })
            .collect();
        Self {
            world,
            character,
            poses,
            room,
            object,
            object_pose: Isometry3::identity(),
        }
    }

    /// Frame `k`: each walker sampled and placed, the box moved and turned.
    fn pose(&mut self, k: usize) {
        let clip = &self.character.clips[0];
        for (c, pose) in self.poses.iter_mut().enumerate() {
            let t = clip.start() + clip.duration() * ((k + 7 * c) % 30) as f32 / 30.0;
            pose.pose(&self.character, Some(clip), t);
            let place =
                Matrix4::new_translation(&Vector3::new(0.6 * c as f32 - 0.6, 0.0, 0.1 * c as f32))
                    * Matrix4::from_euler_angles(0.0, 0.4 * c as f32 + 0.05 * k as f32, 0.0);
            pose.place(&place);
            pose.skin_all(&self.character, SkinningModel::Linear);
            self.world
                .set_pose(CharacterHandle(c as u32), pose)
                .unwrap();
        }
        self.object_pose = Isometry3::from_parts(
            Translation3::new(-0.8 + 0.05 * k as f32, 1.0, 0.3),
            UnitQuaternion::from_euler_angles(0.3, 0.1 * k as f32, 0.0),
        );
        self.world
            .set_object_pose(ObjectHandle(0), self.object_pose)
            .unwrap();
    }

    /// Every triangle of the world at the current poses, with its body.
    fn triangles(&self, model: SkinningModel) -> Vec<(BodyRef, u32, Triangle)> {
        let mut out = Vec::new();
        for t in 0..self.room.triangle_count() as u32 {
            out.push((
                BodyRef::Room(RoomHandle(0)),
                t,
                self.room.triangle(TriangleId(t)),
            ));
        }
        for t in 0..self.object.triangle_count() as u32 {
            let tr = self.object.triangle(TriangleId(t));
            let m = |p: Point| self.object_pose * p;
            out.push((
                BodyRef::Object(ObjectHandle(0)),
                t,
                Triangle::new(m(tr.a), m(tr.b), m(tr.c)),
            ));
        }
        let mesh = &self.character.mesh;
        for (c, pose) in self.poses.iter().enumerate() {
            let mut posed = vec![Point::origin(); mesh.vertex_count()];
            pose.skin_all_into(&self.character, model, &mut posed);
            for (t, [i, j, k]) in mesh.indices().iter().enumerate() {
                out.push((
                    BodyRef::Character(CharacterHandle(c as u32)),
                    t as u32,
                    Triangle::new(posed[*i as usize], posed[*j as usize], posed[*k as usize]),
                ));
            }
        }
        out
    }
}

fn random_ray(rng: &mut SmallRng) -> Ray {
    // From around the room towards the characters' space.
    let o = Point::new(
        rng.random_range(-3.0..3.0),
        rng.random_range(0.0..2.5),
        rng.random_range(1.0..3.0),
    );
    let target = Point::new(
        rng.random_range(-1.5..1.5),
        rng.random_range(0.0..2.0),
        rng.random_range(-0.8..0.8),
    );
    let len = if rng.random_bool(0.2) {
        rng.random_range(0.5..3.0)
    } else {
        f32::INFINITY
    };
    Ray::new(o, target - o, len).unwrap()
}

#[test]
fn rays_balls_and_capsules_equal_brute_force() {
    for (method, model) in [
        (Method::UndividedPrunedTriTri, SkinningModel::Linear),
        (Method::Original, SkinningModel::Paper),
        (Method::SphereDivision, SkinningModel::Linear),
    ] {
        let mut scene = Scene::new(method, model);
        let mut rng = SmallRng::seed_from_u64(11);
        let mut scratch = QueryScratch::new();
        let mut all = Vec::new();
        let mut touched = Vec::new();
        let (mut first_hits, mut character_hits) = (0, 0);
        for k in 0..4 {
            scene.pose(k);
            let tris = scene.triangles(model);
            for _ in 0..300 {
                let ray = random_ray(&mut rng);
                // Brute force: every triangle, the same ray test.
                let mut expected: Vec<(f64, BodyRef, u32)> = tris
                    .iter()
                    .filter_map(|(b, t, tri)| ray.triangle_hit(tri).map(|h| (h.distance, *b, *t)))
                    .collect();
                expected
                    .sort_by(|x, y| x.0.total_cmp(&y.0).then(x.1.cmp(&y.1)).then(x.2.cmp(&y.2)));
                let got = scene
                    .world
                    .cast_ray(&ray, QueryTargets::All, &mut scratch)
                    .unwrap();
                match (got, expected.first()) {
                    (None, None) => {}
                    (Some(g), Some(e)) => {
                        first_hits += 1;
                        character_hits += matches!(g.body, BodyRef::Character(_)) as usize;
                        let rel = (f64::from(g.distance) - e.0).abs() / e.0.max(1e-3);
                        assert!(rel < 1e-6, "{method}: distance {} vs {}", g.distance, e.0);
                        // Ties (a ray through a shared edge) may name either.
                        let tied: Vec<_> = expected
                            .iter()
                            .filter(|x| (x.0 - e.0).abs() <= 1e-12 * e.0.max(1.0))
                            .collect();
                        assert!(
                            tied.iter().any(|x| (x.1, x.2) == (g.body, g.triangle)),
                            "{method}: first hit {:?} {} but brute force {:?}",
                            g.body,
                            g.triangle,
                            tied
                        );
                        let p = ray.at(e.0);
                        assert!((g.point.cast::<f64>() - p).norm() < 1e-5);
                        let [u, v, w] = g.barycentric;
                        assert!(
                            (u + v + w - 1.0).abs() < 1e-5
                                && u >= -1e-6
                                && v >= -1e-6
                                && w >= -1e-6
                        );
                    }
                    (g, e) => panic!("{method}: ours {g:?}, brute force {e:?} for {ray:?}"),
                }
                scene
                    .world
                    .cast_ray_all(&ray, QueryTargets::All, &mut scratch, &mut all)
                    .unwrap();
                let mut got_all: Vec<(BodyRef, u32)> =
                    all.iter().map(|h| (h.body, h.triangle)).collect();
                let mut exp_all: Vec<(BodyRef, u32)> =
                    expected.iter().map(|x| (x.1, x.2)).collect();
                got_all.sort();
                exp_all.sort();
                assert_eq!(got_all, exp_all, "{method}: all hits of {ray:?}");
                assert!(all.windows(2).all(|w| w[0].distance <= w[1].distance));
            }
            // Balls and capsules.
            for _ in 0..60 {
                let c = Point::new(
                    rng.random_range(-1.5..1.5),
                    rng.random_range(0.0..2.0),
                    rng.random_range(-0.8..0.8),
                );
                let r = rng.random_range(0.01..0.3);
                let ball = Sphere::new(c, r);
                scene
                    .world
                    .overlap_sphere(&ball, QueryTargets::All, &mut scratch, &mut touched)
                    .unwrap();
                let mut exp: Vec<Touched> = tris
                    .iter()
                    .filter(|(_, _, tri)| {
                        cornertree::geometry::query_shapes::sphere_overlaps_triangle(&ball, tri)
                    })
                    .map(|(b, t, _)| Touched {
                        body: *b,
                        triangle: *t,
                    })
                    .collect();
                exp.sort();
                assert_eq!(touched, exp, "{method}: ball {ball:?}");
                let d = Vector::new(
                    rng.random_range(-0.5..0.5),
                    rng.random_range(-0.5..0.5),
                    rng.random_range(-0.5..0.5),
                );
                let cap = Capsule::new(c, c + d, r * 0.5).unwrap();
                scene
                    .world
                    .overlap_capsule(&cap, QueryTargets::All, &mut scratch, &mut touched)
                    .unwrap();
                let mut exp: Vec<Touched> = tris
                    .iter()
                    .filter(|(_, _, tri)| cap.overlaps_triangle(tri))
                    .map(|(b, t, _)| Touched {
                        body: *b,
                        triangle: *t,
                    })
                    .collect();
                exp.sort();
                assert_eq!(touched, exp, "{method}: capsule {cap:?}");
            }
        }
        assert!(
            first_hits > 600 && character_hits > 200,
            "{method}: {first_hits} hits, {character_hits} on characters"
        );
    }
}

#[test]
fn a_ray_missing_every_root_costs_one_test_per_body() {
    let mut scene = Scene::new(Method::UndividedPrunedTriTri, SkinningModel::Linear);
    scene.pose(0);
    let mut scratch = QueryScratch::new();
    // High above everything, going up.
    let up = Ray::new(
        Point::new(0.0, 10.0, 0.0),
        Vector::new(0.1, 1.0, 0.0),
        f32::INFINITY,
    )
    .unwrap();
    assert!(
        scene
            .world
            .cast_ray(&up, QueryTargets::All, &mut scratch)
            .unwrap()
            .is_none()
    );
    let c = *scratch.counters();
    assert_eq!(c.root_tests, 5, "a room, an object, three characters");
    assert_eq!(
        (c.bodies_entered, c.sphere_tests, c.triangle_tests),
        (0, 0, 0)
    );
    // Only the characters: three.
    assert!(
        scene
            .world
            .cast_ray(&up, QueryTargets::Characters, &mut scratch)
            .unwrap()
            .is_none()
    );
    assert_eq!(scratch.counters().root_tests, 3);
    assert_eq!(
        scratch.counters().refits,
        0,
        "roots refit by the first query this frame"
    );
    // One character.
    let one = QueryTargets::Character(CharacterHandle(1));
    assert!(
        scene
            .world
            .cast_ray(&up, one, &mut scratch)
            .unwrap()
            .is_none()
    );
    assert_eq!(scratch.counters().root_tests, 1);
    // Handles this world did not give are refused, naming them.
    let e = scene
        .world
        .cast_ray(
            &up,
            QueryTargets::Character(CharacterHandle(3)),
            &mut scratch,
        )
        .unwrap_err();
    assert_eq!(
        e.to_string(),
        "character 3: no such character in this world"
    );
    let mut touched = Vec::new();
    let e = scene
        .world
        .overlap_sphere(
            &Sphere::new(Point::origin(), 1.0),
            QueryTargets::Room(RoomHandle(1)),
            &mut scratch,
            &mut touched,
        )
        .unwrap_err();
    assert_eq!(e.to_string(), "room 1: no such room in this world");
    let e = scene
        .world
        .overlap_sphere(
            &Sphere::new(Point::origin(), -1.0),
            QueryTargets::All,
            &mut scratch,
            &mut touched,
        )
        .unwrap_err();
    assert_eq!(e.to_string(), "query: the ball's radius is negative");
    let cap = Capsule::new(Point::origin(), Point::origin(), 0.1).unwrap();
    assert!(
        scene
            .world
            .overlap_capsule(
                &cap,
                QueryTargets::Object(ObjectHandle(2)),
                &mut scratch,
                &mut touched
            )
            .is_err()
    );
}

#[test]
fn queries_and_steps_share_a_frame_and_change_no_contact() {
    for method in [Method::UndividedPrunedTriTri, Method::Original] {
        let mut queried = Scene::new(method, SkinningModel::Linear);
        let mut plain = Scene::new(method, SkinningModel::Linear);
        let mut scratch = QueryScratch::new();
        let mut rng = SmallRng::seed_from_u64(5);
        for k in 0..5 {
            queried.pose(k);
            plain.pose(k);
            let rays: Vec<Ray> = (0..50).map(|_| random_ray(&mut rng)).collect();
            let mut refits_by_queries = 0;
            for r in &rays {
                queried
                    .world
                    .cast_ray(r, QueryTargets::Characters, &mut scratch)
                    .unwrap();
                refits_by_queries += scratch.counters().refits;
            }
            // The same rays again: everything they reach is refit already.
            for r in &rays {
                queried
                    .world
                    .cast_ray(r, QueryTargets::Characters, &mut scratch)
                    .unwrap();
                assert_eq!(
                    scratch.counters().refits,
                    0,
                    "{method}: refit twice in a frame"
                );
                assert_eq!(
                    scratch.counters().skinned_vertices,
                    0,
                    "{method}: skinned twice"
                );
            }
            let a = queried.world.step();
            let (pairs_a, refits_a) = (
                (
                    a.room_pairs.clone(),
                    a.object_pairs.clone(),
                    a.character_pairs.clone(),
                ),
                a.total.refits,
            );
            let b = plain.world.step();
            let (pairs_b, refits_b) = (
                (
                    b.room_pairs.clone(),
                    b.object_pairs.clone(),
                    b.character_pairs.clone(),
                ),
                b.total.refits,
            );
            assert_eq!(pairs_a, pairs_b, "{method}: frame {k}");
            assert!(refits_by_queries > 0);
            // The step refits only what the queries did not (refit ahead
            // may refit nodes the plain world's step also refits).
            assert!(
                refits_a <= refits_b,
                "{method}: {refits_a} refits after queries, {refits_b} without"
            );
            // A query after the step: nothing new for the nodes it reached.
            for r in &rays {
                queried
                    .world
                    .cast_ray(r, QueryTargets::Characters, &mut scratch)
                    .unwrap();
                assert_eq!(scratch.counters().refits, 0);
            }
        }
    }
}
