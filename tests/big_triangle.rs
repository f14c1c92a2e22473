//! Big-triangle hierarchies: no false negatives with plane-sphere leaves, and
//! the environment tree per method against brute force.

mod common;

use std::collections::BTreeSet;

use cornertree::big_triangle::{Division, DivisionKind};
use cornertree::geometry::plane_sphere::{sphere_meets_plane, sphere_triangle_distance};
use cornertree::geometry::tri_tri::triangles_intersect;
use cornertree::geometry::{Point, Sphere, Triangle};
use cornertree::mesh::{TriMesh, TriangleId};
use cornertree::pipeline::{EnvironmentTree, LeafTest, Method};
use cornertree::sphere_tree::{BuildParams, Node, SphereTree, Workspace, build_tree, traverse};
use rand::{Rng, SeedableRng, rngs::SmallRng};

fn big() -> Triangle {
    Triangle::new(
        Point::new(-3.0, 0.0, -2.0),
        Point::new(4.0, 0.2, -1.5),
        Point::new(0.5, 0.1, 4.0),
    )
}

/// Whether a lone sphere hits the division with plane-sphere leaves.
fn plane_sphere_hit(d: &Division, s: Sphere, t: &Triangle, ws: &mut Workspace) -> bool {
    let mut one = SphereTree::from_nodes(vec![Node::leaf(s, 0)]);
    let mut tree = d.tree.clone();
    let mut hit = false;
    traverse(&mut one, &mut tree, ws, |_| {
        hit |= sphere_meets_plane(&s, t)
    });
    hit
}

#[test]
fn corner_tree_with_plane_sphere_has_no_false_negatives() {
    let t = big();
    let mut rng = SmallRng::seed_from_u64(42);
    let mut ws = Workspace::new();
    for (kind, name) in [
        (DivisionKind::Corner, "corner-tree"),
        (DivisionKind::Full, "quaternary"),
    ] {
        let d = Division::build(&t, TriangleId(0), kind, 0.4, 10);
        d.validate().unwrap();
        let (mut true_hits, mut false_pos, mut misses_checked) = (0u32, 0u32, 0u32);
        for _ in 0..20_000 {
            // Centres in a slab around the triangle, reaching past its edges.
            let c = Point::new(
                rng.random_range(-4.0..5.0),
                rng.random_range(-0.3..0.5),
                rng.random_range(-3.0..5.0),
            );
            let s = Sphere::new(c, rng.random_range(0.005..0.15));
            let truth = sphere_triangle_distance(&s, &t) <= 0.0;
            let hit = plane_sphere_hit(&d, s, &t, &mut ws);
            assert!(!truth || hit, "{name}: false negative for {s:?}");
            if truth {
                true_hits += 1;
            } else {
                misses_checked += 1;
                false_pos += hit as u32;
            }
        }
        assert!(true_hits > 1000, "the test must exercise real contacts");
        println!(
            "{name}: {true_hits} true contacts, all found; false positives {false_pos} of {misses_checked} non-contacts ({:.2}%)",
            100.0 * false_pos as f64 / misses_checked as f64
        );
    }
}

/// Small random triangles plus a few big ones.
fn environment(seed: u64) -> TriMesh {
    let small = common::soup(seed, 300, 6.0, 0.15);
    let mut p = small.positions().to_vec();
    let mut t = small.indices().to_vec();
    let mut rng = SmallRng::seed_from_u64(seed ^ 77);
    for _ in 0..4 {
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

fn all(m: &TriMesh) -> Vec<TriangleId> {
    (0..m.triangle_count() as u32).map(TriangleId).collect()
}

#[test]
fn environment_tree_per_method_against_brute_force() {
    for seed in 0..6u64 {
        let env = environment(seed);
        let avatar = common::soup(seed + 100, 250, 6.0, 0.12);
        let mut avatar_tree = build_tree(&avatar, &all(&avatar), BuildParams::default());
        let avatar_nodes = avatar_tree.nodes().to_vec();
        // Exact pairs by brute force.
        let exact: BTreeSet<(u32, u32)> = avatar
            .iter_triangles()
            .flat_map(|(a, ta)| env.iter_triangles().map(move |(e, te)| (a, ta, e, te)))
            .filter(|(_, ta, _, te)| triangles_intersect(ta, te))
            .map(|(a, _, e, _)| (a.0, e.0))
            .collect();
        assert!(!exact.is_empty());
        for method in Method::ALL {
            let et = EnvironmentTree::build(&env, method, 1.0, BuildParams::default());
            assert_eq!(et.big_count(), 4, "four big triangles at threshold 1");
            for d in &et.divisions {
                d.validate().unwrap();
            }
            let mut tree = et.tree.clone();
            let mut reported = BTreeSet::new();
            let mut ws = Workspace::new();
            traverse(&mut avatar_tree, &mut tree, &mut ws, |p| {
                let ta = avatar.triangle(TriangleId(p.primitive_a));
                let te = env.triangle(TriangleId(p.primitive_b));
                let hit = if et.is_division_leaf(p.leaf_b)
                    && method.big_leaf_test() == LeafTest::PlaneSphere
                {
                    let s = avatar_nodes[p.leaf_a.index()].sphere;
                    sphere_meets_plane(&s, &te)
                } else {
                    triangles_intersect(&ta, &te)
                };
                if hit {
                    reported.insert((p.primitive_a, p.primitive_b));
                }
            });
            match method.big_leaf_test() {
                LeafTest::TriTri => assert_eq!(reported, exact, "seed {seed} {method}"),
                LeafTest::PlaneSphere => assert!(
                    reported.is_superset(&exact),
                    "seed {seed} {method}: missed contacts"
                ),
            }
        }
    }
}
