//! Sphere-tree build, validation and traversal against brute force.

mod common;

use std::collections::BTreeSet;

use cornertree::mesh::{TriMesh, TriangleId, dedup_edges};
use cornertree::sphere_tree::validate::Checks;
use cornertree::sphere_tree::{
    BuildParams, Node, NodeId, SphereTree, Workspace, build_tree, traverse,
};
use proptest::prelude::*;

fn all(mesh: &TriMesh) -> Vec<TriangleId> {
    (0..mesh.triangle_count() as u32).map(TriangleId).collect()
}

fn checks(list: &[TriangleId]) -> Checks<'_> {
    Checks {
        triangles: Some(list),
        nested: true,
        tolerance: 0.0,
    }
}

/// Independent reference: plain recursion with the same opening rule, counting
/// each sphere test where it is made.
fn reference(
    a: &SphereTree,
    b: &SphereTree,
    i: u32,
    j: u32,
    tests: &mut u64,
    out: &mut BTreeSet<(u32, u32)>,
) {
    let (na, nb): (&Node, &Node) = (&a.nodes()[i as usize], &b.nodes()[j as usize]);
    if na.is_leaf() && nb.is_leaf() {
        out.insert((na.primitive().unwrap(), nb.primitive().unwrap()));
        return;
    }
    if nb.is_leaf() || (!na.is_leaf() && na.sphere.radius >= nb.sphere.radius) {
        for c in na.children() {
            *tests += 1;
            if a.nodes()[c as usize].sphere.overlaps(&nb.sphere) {
                reference(a, b, c, j, tests, out);
            }
        }
    } else {
        for c in nb.children() {
            *tests += 1;
            if na.sphere.overlaps(&b.nodes()[c as usize].sphere) {
                reference(a, b, i, c, tests, out);
            }
        }
    }
}

fn leaves(t: &SphereTree) -> Vec<&Node> {
    t.nodes().iter().filter(|n| n.is_leaf()).collect()
}

fn check_against_brute_force(a: &SphereTree, b: &SphereTree) -> usize {
    // Brute force over every pair of leaves.
    let brute: BTreeSet<(u32, u32)> = leaves(a)
        .iter()
        .flat_map(|x| leaves(b).into_iter().map(move |y| (*x, y)))
        .filter(|(x, y)| x.sphere.overlaps(&y.sphere))
        .map(|(x, y)| (x.primitive().unwrap(), y.primitive().unwrap()))
        .collect();

    let mut ws = Workspace::new();
    let mut got = BTreeSet::new();
    let (mut a2, mut b2) = (a.clone(), b.clone());
    let stats = traverse(&mut a2, &mut b2, &mut ws, |p| {
        assert!(
            got.insert((p.primitive_a, p.primitive_b)),
            "pair reported twice"
        );
    });
    assert_eq!(got, brute, "traversal leaf pairs differ from brute force");
    assert_eq!(stats.leaf_pairs as usize, brute.len());

    let mut tests = 1;
    let mut reference_pairs = BTreeSet::new();
    if a.nodes()[0].sphere.overlaps(&b.nodes()[0].sphere) {
        reference(a, b, 0, 0, &mut tests, &mut reference_pairs);
    }
    assert_eq!(stats.sphere_tests, tests, "sphere-test counter");
    assert_eq!(reference_pairs, brute);
    brute.len()
}

#[test]
fn validator_passes_on_generated_meshes_and_catches_breakage() {
    for (i, mesh) in [
        common::soup(1, 500, 10.0, 0.5),
        common::uv_sphere(nalgebra::Point3::new(1.0, 2.0, 3.0), 2.0, 24, 32),
        common::soup(2, 1, 1.0, 1.0),
    ]
    .iter()
    .enumerate()
    {
        for ratio in [0.5, 0.9, 1.0] {
            let list = all(mesh);
            let t = build_tree(
                mesh,
                &list,
                BuildParams {
                    collapse_ratio: ratio,
                },
            );
            t.validate(mesh, checks(&list))
                .unwrap_or_else(|e| panic!("mesh {i} ratio {ratio}: {e}"));
            assert_eq!(t.leaf_count(), mesh.triangle_count());
            assert_eq!(t.nodes_per_level().iter().sum::<usize>(), t.len());
            if ratio >= 1.0 && mesh.triangle_count() > 1 {
                // Binary: 2n - 1 nodes.
                assert_eq!(t.len(), 2 * mesh.triangle_count() - 1);
            }
        }
    }
    // Shrinking one sphere must be caught.
    let mesh = common::soup(3, 64, 5.0, 0.5);
    let list = all(&mesh);
    let t = build_tree(&mesh, &list, BuildParams::default());
    let mut nodes = t.nodes().to_vec();
    let leaf = nodes.iter().position(|n| n.is_leaf()).unwrap();
    nodes[leaf].sphere.radius *= 0.5;
    let broken = SphereTree::from_nodes(nodes);
    assert!(broken.validate(&mesh, checks(&list)).is_err());
}

#[test]
fn collapse_removes_children_close_to_parent_size() {
    let mesh = common::uv_sphere(nalgebra::Point3::origin(), 1.0, 16, 16);
    let list = all(&mesh);
    let binary = build_tree(
        &mesh,
        &list,
        BuildParams {
            collapse_ratio: 1.0,
        },
    );
    let nary = build_tree(
        &mesh,
        &list,
        BuildParams {
            collapse_ratio: 0.8,
        },
    );
    assert!(nary.len() < binary.len());
    // No kept inner child has a radius within the ratio of its parent's.
    for n in nary.nodes() {
        for c in n.children() {
            let child = &nary.nodes()[c as usize];
            assert!(child.is_leaf() || child.sphere.radius <= 0.8 * n.sphere.radius);
        }
    }
}

#[test]
fn tree_over_deduplicated_triangles() {
    let mesh = common::uv_sphere(nalgebra::Point3::origin(), 1.0, 20, 30);
    let d = dedup_edges(&mesh);
    let kept: Vec<TriangleId> = d.kept().collect();
    let t = build_tree(&mesh, &kept, BuildParams::default());
    t.validate(&mesh, checks(&kept)).unwrap();
    assert_eq!(t.leaf_count(), d.kept_count());
}

#[test]
fn traversal_of_touching_spheres_and_empty_trees() {
    let a = common::uv_sphere(nalgebra::Point3::origin(), 1.0, 10, 12);
    let b = common::uv_sphere(nalgebra::Point3::new(1.9, 0.0, 0.0), 1.0, 10, 12);
    let ta = build_tree(&a, &all(&a), BuildParams::default());
    let tb = build_tree(&b, &all(&b), BuildParams::default());
    assert!(check_against_brute_force(&ta, &tb) > 0);
    let far = common::uv_sphere(nalgebra::Point3::new(10.0, 0.0, 0.0), 1.0, 10, 12);
    let tf = build_tree(&far, &all(&far), BuildParams::default());
    assert_eq!(check_against_brute_force(&ta, &tf), 0);
    let mut empty = SphereTree::default();
    let stats = traverse(
        &mut ta.clone(),
        &mut empty,
        &mut Workspace::new(),
        |_| panic!(),
    );
    assert_eq!(stats.sphere_tests, 0);
    let _ = NodeId::ROOT;
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]
    #[test]
    fn traversal_equals_brute_force_on_random_meshes(
        seed_a in any::<u64>(), seed_b in any::<u64>(),
        na in 1usize..120, nb in 1usize..120,
        size in 0.05f32..1.5, ratio in 0.3f32..1.0,
    ) {
        let a = common::soup(seed_a, na, 4.0, size);
        let b = common::soup(seed_b, nb, 4.0, size);
        let p = BuildParams { collapse_ratio: ratio };
        let ta = build_tree(&a, &all(&a), p);
        let tb = build_tree(&b, &all(&b), p);
        ta.validate(&a, checks(&all(&a))).unwrap();
        tb.validate(&b, checks(&all(&b))).unwrap();
        check_against_brute_force(&ta, &tb);
    }
}

#[test]
fn workspace_stops_growing_after_warm_up() {
    let a = common::soup(7, 400, 3.0, 0.4);
    let b = common::soup(8, 400, 3.0, 0.4);
    let mut ta = build_tree(&a, &all(&a), BuildParams::default());
    let mut tb = build_tree(&b, &all(&b), BuildParams::default());
    let mut ws = Workspace::new();
    traverse(&mut ta, &mut tb, &mut ws, |_| {});
    let cap = ws.capacity();
    assert!(cap > 0);
    for _ in 0..5 {
        traverse(&mut ta, &mut tb, &mut ws, |_| {});
        assert_eq!(ws.capacity(), cap);
    }
}
