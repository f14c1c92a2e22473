//! The per-frame pipeline against brute force, per method; determinism.

mod common;

use std::collections::BTreeSet;

use cornertree::character::{Character, PoseBuffers, SkinningModel};
use cornertree::geometry::tri_tri::triangles_intersect;
use cornertree::geometry::{Point, Triangle};
use cornertree::mesh::TriMesh;
use cornertree::pipeline::driver::{FrameCounters, Pipeline, PipelineOptions};
use cornertree::pipeline::{LeafTest, Method};
use cornertree::sphere_tree::BuildParams;
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

fn options(dedup: bool, skinning: SkinningModel) -> PipelineOptions {
    PipelineOptions {
        skinning,
        dedup,
        threshold: 1.0,
        build: BuildParams::default(),
    }
}

#[test]
fn every_method_against_brute_force() {
    let mut contacts = 0;
    let mut skinned_all = 0;
    let mut leaf_plane_tests = 0;
    for seed in 0..4u64 {
        let character = common::random_character(seed, 6, 300);
        let env = environment(seed);
        let placement = Matrix4::new_translation(&Vector3::new(3.0, 3.0, 3.0));
        // Both skinning models: the pipeline skins with the one it was built for.
        let model = if seed % 2 == 0 {
            SkinningModel::Linear
        } else {
            SkinningModel::Paper
        };
        for dedup in [false, true] {
            let mut pipes: Vec<Pipeline> = Method::ALL
                .iter()
                .map(|&m| Pipeline::new(&character, &env, m, options(dedup, model)))
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
                    let c = p.detect(&buffers, &character, &env);
                    // What it skinned is what full skinning gives (on demand,
                    // or every vertex when most are tested).
                    assert!(c.skinned_vertices <= buffers.positions.len() as u64);
                    skinned_all +=
                        usize::from(c.skinned_vertices == buffers.positions.len() as u64);
                    for v in 0..buffers.positions.len() as u32 {
                        if p.skinned().is_current(v) {
                            assert_eq!(p.skinned().position(v), buffers.positions[v as usize]);
                        }
                    }
                    let got: BTreeSet<(u32, u32)> = p.pairs.iter().copied().collect();
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
                        let ctree = &p.character_tree.tree;
                        let at_division: Vec<_> = p
                            .leaf_pairs()
                            .iter()
                            .filter(|lp| p.environment.is_division_leaf(lp.leaf_b))
                            .collect();
                        assert_eq!(c.plane_sphere, at_division.len() as u64, "{m}");
                        leaf_plane_tests += at_division.len();
                        for lp in at_division {
                            assert!(ctree.node(lp.leaf_a).is_leaf(), "{m}");
                            assert!(p.environment.tree.node(lp.leaf_b).is_leaf(), "{m}");
                        }
                    }
                    assert_eq!(
                        c.operations(),
                        10 * c.sphere_sphere + 96 * c.tri_tri + 30 * c.plane_sphere
                    );
                }
                // Testing the plane on the way down only removes pairs (and,
                // above, never a contact): each pruned method reports a subset
                // of what its leaf-only twin (the paper's reading) reports.
                let pairs_of = |m: Method| -> BTreeSet<(u32, u32)> {
                    let p = pipes.iter().find(|p| p.method == m).unwrap();
                    p.pairs.iter().copied().collect()
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
    let character = common::random_character(3, 5, 200);
    let env = environment(3);
    let placement = Matrix4::new_translation(&Vector3::new(3.0, 3.0, 3.0));
    let run = || -> Vec<(FrameCounters, Vec<(u32, u32)>)> {
        let mut p = Pipeline::new(
            &character,
            &env,
            Method::PlaneSphere,
            options(true, SkinningModel::Linear),
        );
        let mut b = PoseBuffers::new(&character);
        (0..4)
            .map(|k| {
                let local = common::random_pose(k, &character.skeleton, 1.0);
                b.local.copy_from_slice(&local);
                b.pose_local(&character);
                b.place(&placement);
                let mut c = p.detect(&b, &character, &env);
                c.time = Default::default();
                (c, p.pairs.clone())
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
    let env = &r.environment.mesh;
    for m in Method::ALL {
        let mut plain = Pipeline::new(&r.first().character, env, m, r.pipeline_options(r.first()));
        let mut logged = Pipeline::new(&r.first().character, env, m, r.pipeline_options(r.first()));
        logged.set_visit_log(true);
        let mut b = PoseBuffers::new(&r.first().character);
        for k in 0..3 {
            r.first().pose_frame(&mut b, k);
            let mut c0 = plain.detect(&b, &r.first().character, env);
            let mut c1 = logged.detect(&b, &r.first().character, env);
            c0.time = Default::default();
            c1.time = Default::default();
            assert_eq!(c0, c1, "{m} frame {k}");
            assert!(c0.pairs > 0, "{m} frame {k}: contacts");
            assert_eq!(plain.leaf_pairs(), logged.leaf_pairs(), "{m} frame {k}");
            assert_eq!(plain.pairs, logged.pairs, "{m} frame {k}");
            assert!(plain.visit_log().is_none());
            let log = logged.visit_log().unwrap();
            assert_eq!(log.sphere_tests(), c1.sphere_sphere, "{m} frame {k}");
        }
    }
}
