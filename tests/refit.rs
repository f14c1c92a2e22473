//! Refit containment for both skinning models, and on-demand equals full refit.

mod common;

use cornertree::character::{Character, PoseBuffers, SkinningModel};
use cornertree::mesh::{EdgeDedup, dedup_edges};
use cornertree::sphere_tree::character::CharacterTree;
use cornertree::sphere_tree::containment::VertexSets;
use cornertree::sphere_tree::refit::{OnDemand, RefitState, Refitter};
use cornertree::sphere_tree::validate::Checks;
use cornertree::sphere_tree::{BuildParams, Workspace, build_tree, traverse};
use proptest::prelude::*;

fn posed(c: &Character, local: &[cornertree::character::Trs], model: SkinningModel) -> PoseBuffers {
    let mut b = PoseBuffers::new(c);
    b.local.copy_from_slice(local);
    c.skeleton.world_matrices(&b.local, &mut b.world);
    c.skeleton.skin_matrices(&b.world, &mut b.skin);
    b.skin_all(c, model);
    b
}

/// Full refit of `c` in pose `local`: returns violations, checks, worst excess.
fn full_refit_violations(
    c: &Character,
    local: &[cornertree::character::Trs],
    model: SkinningModel,
) -> (u64, u64, f64) {
    let ct = CharacterTree::build(
        c,
        &EdgeDedup::keep_all(&c.mesh),
        model,
        BuildParams::default(),
    );
    // Bind-pose tree is a valid, nested sphere tree.
    let list: Vec<_> = ct.triangles.clone();
    ct.tree
        .validate(
            &c.mesh,
            Checks {
                triangles: Some(&list),
                nested: true,
                tolerance: 0.0,
            },
        )
        .unwrap();
    let b = posed(c, local, model);
    let mut state = RefitState::new(&ct, c.skeleton.len());
    state.begin_frame(&c.skeleton, &b.skin);
    Refitter {
        tree: &ct,
        skin: &b.skin,
        state: &mut state,
    }
    .refit_all(c.skeleton.base());
    let tol = 1e-5 * c.mesh.size() as f64;
    let r = VertexSets::new(&ct.tree, &c.mesh).check(&state.spheres, &b.positions, tol);
    // The independent ancestor walk agrees on whether anything sticks out.
    let (walk, walk_worst) = common::ancestor_walk_violations(
        &ct.tree,
        &state.spheres,
        &b.positions,
        c.mesh.indices(),
        tol,
    );
    assert_eq!(walk == 0, r.violations == 0);
    assert!((walk_worst.max(0.0) - r.worst_excess.max(0.0)).abs() < 1e-6);
    (r.violations, r.checks, r.worst_excess)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    #[test]
    fn refit_contains_every_vertex(seed in any::<u64>(), joints in 1usize..9, tris in 1usize..80, pose_seed in any::<u64>(), scaled in any::<bool>()) {
        let c = common::random_character(seed, joints, tris);
        let local = common::random_pose(pose_seed, &c.skeleton, if scaled { 1.5 } else { 1.0 });
        for model in [SkinningModel::Paper, SkinningModel::Linear] {
            let (violations, checks, worst) = full_refit_violations(&c, &local, model);
            prop_assert!(checks > 0);
            prop_assert_eq!(violations, 0, "{:?}: worst excess {}", model, worst);
        }
    }
}

/// Full refit of `c` in pose `local`, placed at `offset`, against every vertex
/// skinned by the production code (`PoseBuffers::place`, then `skin_all`),
/// with tolerance 0: returns violations, checks, worst excess.
fn placed_refit_violations(
    c: &Character,
    local: &[cornertree::character::Trs],
    model: SkinningModel,
    offset: [f32; 3],
) -> (u64, u64, f64) {
    let ct = CharacterTree::build(
        c,
        &EdgeDedup::keep_all(&c.mesh),
        model,
        BuildParams::default(),
    );
    let mut b = PoseBuffers::new(c);
    b.local.copy_from_slice(local);
    b.pose_local(c);
    b.place(&nalgebra::Matrix4::new_translation(&offset.into()));
    b.skin_all(c, model);
    let mut state = RefitState::new(&ct, c.skeleton.len());
    state.begin_frame_with_base(&b.skin, &b.base);
    Refitter {
        tree: &ct,
        skin: &b.skin,
        state: &mut state,
    }
    .refit_all(&b.base);
    let r = VertexSets::new(&ct.tree, &c.mesh).check(&state.spheres, &b.positions, 0.0);
    let (walk, _) = common::ancestor_walk_violations(
        &ct.tree,
        &state.spheres,
        &b.positions,
        c.mesh.indices(),
        0.0,
    );
    assert_eq!(walk == 0, r.violations == 0);
    (r.violations, r.checks, r.worst_excess)
}

/// An offset of up to 10 km per axis: a random direction scaled by 10^e.
fn offsets() -> impl Strategy<Value = [f32; 3]> {
    (prop::array::uniform3(-1.0f32..1.0), 0i32..=4).prop_map(|(d, e)| d.map(|x| x * 10f32.powi(e)))
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    /// Non-uniform joint scales, random weights (repeated joints included),
    /// random poses, the character up to 10 km from the origin: refit spheres
    /// hold every vertex the production skinning computes, with no tolerance.
    #[test]
    fn refit_contains_every_vertex_far_from_origin(
        seed in any::<u64>(),
        joints in 1usize..9,
        tris in 1usize..80,
        pose_seed in any::<u64>(),
        offset in offsets(),
    ) {
        let c = common::random_character(seed, joints, tris);
        let local = common::random_pose_nonuniform(pose_seed, &c.skeleton, 2.0);
        for model in [SkinningModel::Paper, SkinningModel::Linear] {
            let (violations, checks, worst) = placed_refit_violations(&c, &local, model, offset);
            prop_assert!(checks > 0);
            prop_assert_eq!(violations, 0, "{:?} at {:?}: worst excess {}", model, offset, worst);
        }
    }
}

#[test]
fn refit_is_not_vacuous() {
    // Breaking the rule (ignoring the pose) must produce violations.
    let c = common::random_character(11, 6, 200);
    let local = common::random_pose(12, &c.skeleton, 1.0);
    let ct = CharacterTree::build(
        &c,
        &EdgeDedup::keep_all(&c.mesh),
        SkinningModel::Linear,
        BuildParams::default(),
    );
    let b = posed(&c, &local, SkinningModel::Linear);
    let mut state = RefitState::new(&ct, c.skeleton.len());
    state.begin_frame(&c.skeleton, &b.skin);
    // Rest spheres, not refit: stamp them fresh by refitting then overwriting.
    Refitter {
        tree: &ct,
        skin: &b.skin,
        state: &mut state,
    }
    .refit_all(c.skeleton.base());
    for (s, n) in state.spheres.iter_mut().zip(ct.tree.nodes()) {
        *s = n.sphere;
    }
    let r = VertexSets::new(&ct.tree, &c.mesh).check(&state.spheres, &b.positions, 1e-5);
    assert!(r.violations > 0);
    let (walk, _) = common::ancestor_walk_violations(
        &ct.tree,
        &state.spheres,
        &b.positions,
        c.mesh.indices(),
        1e-5,
    );
    assert!(walk > 0);
}

#[test]
fn on_demand_refit_matches_full_refit_and_visits_less() {
    let c = common::random_character(5, 8, 400);
    let env = common::soup(9, 300, 3.0, 0.3);
    let envlist: Vec<_> = (0..env.triangle_count() as u32)
        .map(cornertree::mesh::TriangleId)
        .collect();
    let mut env_tree = build_tree(&env, &envlist, BuildParams::default());
    let dedup = dedup_edges(&c.mesh);
    for model in [SkinningModel::Paper, SkinningModel::Linear] {
        let ct = CharacterTree::build(&c, &dedup, model, BuildParams::default());
        let local = common::random_pose(3, &c.skeleton, 1.0);
        let b = posed(&c, &local, model);
        let base = *c.skeleton.base();

        let mut full = RefitState::new(&ct, c.skeleton.len());
        full.begin_frame(&c.skeleton, &b.skin);
        Refitter {
            tree: &ct,
            skin: &b.skin,
            state: &mut full,
        }
        .refit_all(&base);

        let mut lazy = RefitState::new(&ct, c.skeleton.len());
        let mut ws = Workspace::new();
        let mut pairs_lazy = Vec::new();
        for frame in 0..2 {
            lazy.begin_frame(&c.skeleton, &b.skin);
            let mut od = OnDemand {
                refitter: Refitter {
                    tree: &ct,
                    skin: &b.skin,
                    state: &mut lazy,
                },
                base,
            };
            pairs_lazy.clear();
            traverse(&mut od, &mut env_tree, &mut ws, |p| {
                pairs_lazy.push((p.primitive_a, p.primitive_b))
            });
            assert!(
                lazy.refits > 0 && (lazy.refits as usize) < ct.tree.len(),
                "frame {frame}: {} refits of {}",
                lazy.refits,
                ct.tree.len()
            );
        }
        for i in 0..ct.tree.len() {
            if lazy.is_fresh(cornertree::sphere_tree::NodeId(i as u32)) {
                assert_eq!(lazy.spheres[i], full.spheres[i], "node {i}");
            }
        }
        // Same pairs as traversing the fully refit tree.
        let mut refit_tree = ct.tree.clone();
        for (s, f) in refit_tree.spheres_mut().zip(&full.spheres) {
            *s = *f;
        }
        let mut pairs_full = Vec::new();
        traverse(&mut refit_tree, &mut env_tree, &mut ws, |p| {
            pairs_full.push((p.primitive_a, p.primitive_b))
        });
        pairs_lazy.sort();
        pairs_full.sort();
        assert!(!pairs_full.is_empty(), "the scene must collide somewhere");
        assert_eq!(pairs_lazy, pairs_full);
    }
}
