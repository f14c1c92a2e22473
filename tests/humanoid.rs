//! The procedural humanoid: vertex counts, closed parts, triangle quality,
//! weights, skeleton, clips, determinism and refit containment while animated.

use std::collections::HashMap;

use cornertree::character::{Character, PoseBuffers, SkinningModel};
use cornertree::choice::Choice;
use cornertree::mesh::dedup_edges;
use cornertree::sphere_tree::BuildParams;
use cornertree::sphere_tree::character::CharacterTree;
use cornertree::sphere_tree::containment::VertexSets;
use cornertree::sphere_tree::refit::{RefitRule, RefitState, Refitter};
use cornertree_workbench::humanoid::{
    BodyPart, HumanoidError, HumanoidParams, generate_humanoid, generate_humanoid_parts,
};

const JOINT_NAMES: [&str; 22] = [
    "pelvis",
    "spine_01",
    "spine_02",
    "chest",
    "neck",
    "head",
    "clavicle_l",
    "clavicle_r",
    "upper_arm_l",
    "upper_arm_r",
    "forearm_l",
    "forearm_r",
    "hand_l",
    "hand_r",
    "thigh_l",
    "thigh_r",
    "shin_l",
    "shin_r",
    "foot_l",
    "foot_r",
    "toe_l",
    "toe_r",
];

fn humanoid(vertices: usize) -> (Character, Vec<BodyPart>) {
    generate_humanoid_parts(&HumanoidParams { vertices, seed: 0 }).unwrap()
}

/// Smallest interior angle of a triangle, in degrees.
fn min_angle(p: [nalgebra::Point3<f32>; 3]) -> f32 {
    (0..3)
        .map(|i| {
            let (a, b, c) = (p[i], p[(i + 1) % 3], p[(i + 2) % 3]);
            (b - a).angle(&(c - a)).to_degrees()
        })
        .fold(f32::INFINITY, f32::min)
}

#[test]
fn vertex_count_within_one_percent() {
    for target in [3_273, 10_000, 44_345, 100_000] {
        let c = generate_humanoid(&HumanoidParams {
            vertices: target,
            seed: 0,
        })
        .unwrap();
        let got = c.mesh.vertex_count();
        assert!(
            got.abs_diff(target) * 100 <= target,
            "target {target}: got {got}"
        );
    }
    assert_eq!(HumanoidParams::default().vertices, 44_345);
}

#[test]
fn vertex_count_across_the_range() {
    for target in [500, 1_000, 3_000, 20_000, 200_000] {
        let c = generate_humanoid(&HumanoidParams {
            vertices: target,
            seed: 0,
        })
        .unwrap();
        let got = c.mesh.vertex_count();
        println!(
            "target {target}: {got} vertices, {} triangles",
            c.mesh.triangle_count()
        );
        if target >= 1_000 {
            assert!(
                got.abs_diff(target) * 100 <= target,
                "target {target}: got {got}"
            );
        }
    }
}

#[test]
fn absurd_vertex_counts_are_rejected() {
    for n in [0, 10, 100, 3_000_000] {
        let e = generate_humanoid(&HumanoidParams {
            vertices: n,
            seed: 0,
        })
        .unwrap_err();
        assert!(matches!(e, HumanoidError::VertexCount { requested } if requested == n));
        assert!(e.to_string().contains("supported"), "{e}");
    }
}

#[test]
fn every_part_is_closed_and_well_shaped() {
    for target in [3_273, 44_345] {
        let (c, parts) = humanoid(target);
        let idx = c.mesh.indices();
        assert_eq!(parts.len(), 17);
        assert_eq!(parts.last().unwrap().vertices.end, c.mesh.vertex_count());
        assert_eq!(parts.last().unwrap().triangles.end, idx.len());
        for part in &parts {
            let mut uses: HashMap<(u32, u32), u32> = HashMap::new();
            for t in &idx[part.triangles.clone()] {
                for k in 0..3 {
                    let (a, b) = (t[k], t[(k + 1) % 3]);
                    assert!(
                        part.vertices.contains(&(a as usize)),
                        "{}: vertex {a} outside the part",
                        part.name
                    );
                    *uses.entry((a.min(b), a.max(b))).or_default() += 1;
                }
            }
            let bad = uses.values().filter(|&&n| n != 2).count();
            assert_eq!(
                bad, 0,
                "{} ({target}): {bad} edges not used exactly twice",
                part.name
            );
            // A closed genus-0 surface: V - E + F = 2.
            let euler =
                part.vertices.len() as i64 - uses.len() as i64 + part.triangles.len() as i64;
            assert_eq!(euler, 2, "{}", part.name);
        }
        let mut worst = f32::INFINITY;
        for t in idx {
            let p = t.map(|v| c.mesh.positions()[v as usize]);
            assert!(
                (p[1] - p[0]).cross(&(p[2] - p[0])).norm() > 0.0,
                "zero-area triangle {t:?}"
            );
            worst = worst.min(min_angle(p));
        }
        println!("{target}: smallest angle {worst:.1}°");
        assert!(worst > 10.0, "{target}: sliver with a {worst}° angle");
    }
}

#[test]
fn weights_are_normalised_and_smooth() {
    let (c, _) = humanoid(10_000);
    let inf = &c.influences;
    assert_eq!(inf.len(), c.mesh.vertex_count());
    let mut blended = 0;
    for v in 0..inf.len() {
        let w: Vec<(_, f32)> = inf.of(v).collect();
        assert!(!w.is_empty() && w.len() <= 4);
        let sum: f32 = w.iter().map(|x| x.1).sum();
        assert!((sum - 1.0).abs() < 1e-5, "vertex {v}: sum {sum}");
        if w.len() == 2 {
            // Two influences are a parent and its child.
            let (a, b) = (w[0].0, w[1].0);
            assert!(c.skeleton.parent(b) == Some(a) || c.skeleton.parent(a) == Some(b));
            blended += 1;
        }
    }
    assert!(blended > inf.len() / 20, "only {blended} blended vertices");
    // Neighbours: the weight of any joint changes little along an edge.
    let weight_of = |v: usize, j| inf.of(v).find(|x| x.0 == j).map_or(0.0, |x| x.1);
    let (mut worst, mut at) = (0.0f32, 0);
    for t in c.mesh.indices() {
        for k in 0..3 {
            let (a, b) = (t[k] as usize, t[(k + 1) % 3] as usize);
            for (j, _) in inf.of(a).chain(inf.of(b)) {
                let d = (weight_of(a, j) - weight_of(b, j)).abs();
                if d > worst {
                    (worst, at) = (d, j.index());
                }
            }
        }
    }
    println!(
        "largest weight step along an edge: {worst} ({})",
        c.skeleton.joints()[at].name
    );
    // At most the smoothstep slope (1.5 / zone width) times the ring spacing.
    assert!(worst < 0.4, "weight jumps by {worst} along an edge");
}

#[test]
fn skeleton_has_named_joints_parents_first() {
    let (c, _) = humanoid(3_273);
    let s = &c.skeleton;
    assert!(s.len() >= 20);
    for name in JOINT_NAMES {
        assert!(s.find(name).is_some(), "no joint {name}");
    }
    let pelvis = s.find("pelvis").unwrap();
    assert_eq!(s.parent(pelvis), None);
    assert_eq!(s.base(), &nalgebra::Matrix4::identity());
    // Inverse bind matrices invert the rest world matrices.
    let mut world = vec![nalgebra::Matrix4::identity(); s.len()];
    s.world_matrices(s.rest_pose_ref(), &mut world);
    for (j, w) in s.joints().iter().zip(&world) {
        assert!(
            (j.inverse_bind * w - nalgebra::Matrix4::identity()).norm() < 1e-5,
            "{}",
            j.name
        );
    }
    // About 1.75 m tall, feet on the ground, facing +Z (toes forward).
    let (min, max) = c.mesh.bounds();
    println!("height {:.3} m, {} joints", max.y - min.y, s.len());
    assert!(
        (1.70..1.80).contains(&(max.y - min.y)),
        "height {}",
        max.y - min.y
    );
    assert!(min.y.abs() < 0.03, "lowest point {}", min.y);
    let toe = world[s.find("toe_l").unwrap().index()].column(3).z;
    assert!(toe > 0.05);
}

#[test]
fn clips_present_and_deterministic() {
    let a = generate_humanoid(&HumanoidParams {
        vertices: 5_000,
        seed: 7,
    })
    .unwrap();
    let b = generate_humanoid(&HumanoidParams {
        vertices: 5_000,
        seed: 7,
    })
    .unwrap();
    for name in ["walk", "reach", "turn"] {
        let clip = a.clip(Some(name)).unwrap();
        assert!(clip.duration() > 0.0, "{name}");
        println!(
            "{name}: {:.3} s, {} channels",
            clip.duration(),
            clip.channels.len()
        );
    }
    let walk = a.clip(Some("walk")).unwrap().duration();
    assert!((1.0..=1.2).contains(&walk), "walk cycle {walk} s");
    let same_bits = a
        .mesh
        .positions()
        .iter()
        .zip(b.mesh.positions())
        .all(|(p, q)| p.coords.map(f32::to_bits) == q.coords.map(f32::to_bits));
    assert!(same_bits);
    assert_eq!(a.mesh.indices(), b.mesh.indices());
    assert_eq!(a.influences, b.influences);
    assert_eq!(a.clips, b.clips);
    // Another seed varies the clips, not the mesh.
    let c = generate_humanoid(&HumanoidParams {
        vertices: 5_000,
        seed: 8,
    })
    .unwrap();
    assert_eq!(a.mesh.positions(), c.mesh.positions());
    assert_ne!(a.clips, c.clips);
}

#[test]
fn clips_move_the_character_plausibly() {
    let c = generate_humanoid(&HumanoidParams {
        vertices: 3_273,
        seed: 0,
    })
    .unwrap();
    for clip in &c.clips {
        println!("seed 0 {}: {:.3} s", clip.name, clip.duration());
    }
    let mut b = PoseBuffers::new(&c);
    let joint_pos = |b: &PoseBuffers, name: &str| {
        b.world[c.skeleton.find(name).unwrap().index()]
            .column(3)
            .xyz()
    };
    // Walk: moves forward; the feet alternate.
    let walk = c.clip(Some("walk")).unwrap();
    b.pose(&c, Some(walk), walk.end());
    assert!(joint_pos(&b, "pelvis").z > 0.8);
    b.pose(&c, Some(walk), walk.duration() * 0.25);
    let (l, r) = (joint_pos(&b, "foot_l").z, joint_pos(&b, "foot_r").z);
    assert!((l - r).abs() > 0.2, "feet at {l} and {r}");
    // Reach: the right hand ends up well in front of the chest.
    let reach = c.clip(Some("reach")).unwrap();
    b.pose(&c, Some(reach), reach.duration() * 0.5);
    assert!(
        joint_pos(&b, "hand_r").z > 0.35,
        "hand at {}",
        joint_pos(&b, "hand_r")
    );
    b.pose(&c, Some(reach), reach.end());
    assert!(joint_pos(&b, "hand_r").z.abs() < 1e-3);
    // Turn: the pelvis faces about +X at the end (turned 90° left).
    let turn = c.clip(Some("turn")).unwrap();
    b.pose(&c, Some(turn), turn.end());
    let toe = joint_pos(&b, "toe_l") - joint_pos(&b, "foot_l");
    assert!(toe.x > 0.1 && toe.z.abs() < 0.05, "toe direction {toe}");
}

/// Poses `clip` at `fps` over its duration (or only its middle frame) and
/// returns `(violations, checks)` over both skinning models and both refit
/// rules.
fn containment(c: &Character, fps: f32, only_middle: bool) -> (u64, u64) {
    let dedup = dedup_edges(&c.mesh);
    let tol = 1e-5 * c.mesh.size() as f64;
    let (mut violations, mut checks) = (0, 0);
    for (model, rule) in [SkinningModel::Paper, SkinningModel::Linear]
        .into_iter()
        .flat_map(|m| RefitRule::ALL.iter().map(move |&r| (m, r)))
    {
        let ct = CharacterTree::build_with_rule(c, &dedup, model, BuildParams::default(), rule);
        let sets = VertexSets::new(&ct.tree, &c.mesh);
        let mut state = RefitState::new(&ct, c.skeleton.len());
        let mut b = PoseBuffers::new(c);
        for clip in &c.clips {
            let frames = (clip.duration() * fps).ceil() as usize;
            let times: Vec<f32> = if only_middle {
                vec![clip.start() + 0.5 * clip.duration()]
            } else {
                (0..=frames)
                    .map(|i| (clip.start() + i as f32 / fps).min(clip.end()))
                    .collect()
            };
            for t in times {
                b.pose(c, Some(clip), t);
                b.skin_all(c, model);
                state.begin_frame(&c.skeleton, &b.skin);
                Refitter {
                    tree: &ct,
                    skin: &b.skin,
                    state: &mut state,
                }
                .refit_all(c.skeleton.base());
                let r = sets.check(&state.spheres, &b.positions, tol);
                assert_eq!(
                    r.violations, 0,
                    "{model:?} {rule:?} {} t={t}: worst excess {}",
                    clip.name, r.worst_excess
                );
                violations += r.violations;
                checks += r.checks;
            }
        }
    }
    (violations, checks)
}

#[test]
fn refit_contains_the_animated_humanoid() {
    let c = generate_humanoid(&HumanoidParams {
        vertices: 5_000,
        seed: 3,
    })
    .unwrap();
    let (violations, checks) = containment(&c, 30.0, false);
    println!("5,000 vertices, every frame at 30 fps: {checks} checks");
    assert_eq!(violations, 0);
    assert!(checks > 0);
}

#[test]
fn refit_contains_the_default_humanoid() {
    let c = generate_humanoid(&HumanoidParams::default()).unwrap();
    let (violations, checks) = containment(&c, 30.0, true);
    println!("44,345 vertices, middle frame of each clip: {checks} checks");
    assert_eq!(violations, 0);
}
