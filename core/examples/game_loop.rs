//! The library in a game loop, on the caller's own data: a room made of
//! triangles, a character made of a mesh, a skeleton and skin weights, and
//! every step's joint transforms from the caller's own animation code. No
//! file is read and no scenario is involved.
//!
//! Each step, the contacts the world reports are checked against an exact
//! oracle: every vertex skinned, every (character triangle, room triangle)
//! pair decided with exact predicates. For a few steps the character is
//! set inactive (out of the scene) and reports nothing.
//!
//! `cargo run -p cornertree --example game_loop`

use std::collections::BTreeSet;
use std::f32::consts::PI;
use std::sync::Arc;

use cornertree::character::skinning::Influences;
use cornertree::character::{Character, Joint, JointId, PoseBuffers, Skeleton, SkinningModel, Trs};
use cornertree::geometry::exact::triangles_intersect_exact;
use cornertree::geometry::{Point, Triangle};
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;
use cornertree::world::{CharacterModel, CollisionWorld, WorldError};
use nalgebra::{Isometry3, Matrix4, UnitQuaternion, Vector3};

/// Joints of the arm, shoulder to wrist, and how far apart (metres).
const JOINTS: [&str; 3] = ["shoulder", "elbow", "wrist"];
const BONE: f32 = 0.3;
/// The tube: radius, rings along it, points around each ring.
const RADIUS: f32 = 0.05;
const RINGS: usize = 31;
const AROUND: usize = 12;
/// Steps of the loop.
const STEPS: usize = 60;
/// Steps the arm is out of the scene (two of them would have contacts).
const AWAY: std::ops::Range<usize> = 40..44;

/// The room: a floor and a wall (two big triangles each) and a small box on
/// the floor (twelve triangles), in world coordinates.
fn room() -> TriMesh {
    let mut p = vec![
        // Floor, y = 0.
        Point::new(-2.0, 0.0, -2.0),
        Point::new(3.0, 0.0, -2.0),
        Point::new(3.0, 0.0, 2.0),
        Point::new(-2.0, 0.0, 2.0),
        // Wall, x = 1.3.
        Point::new(1.3, 0.0, -2.0),
        Point::new(1.3, 2.5, -2.0),
        Point::new(1.3, 2.5, 2.0),
        Point::new(1.3, 0.0, 2.0),
    ];
    let mut t = vec![[0, 2, 1], [0, 3, 2], [4, 5, 6], [4, 6, 7]];
    // A box 20 cm on a side around (0.7, 0.1, 0.1).
    let base = p.len() as u32;
    for i in 0..8 {
        let c = |bit: usize, lo: f32| if i & bit == 0 { lo } else { lo + 0.2 };
        p.push(Point::new(c(1, 0.6), c(2, 0.0), c(4, 0.0)));
    }
    for [a, b, c, d] in [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ] {
        t.push([base + a, base + b, base + c]);
        t.push([base + a, base + c, base + d]);
    }
    TriMesh::new(p, t).expect("a valid room")
}

/// An arm: a closed tube along +Y, three joints a bone apart, each vertex
/// weighted between the two joints nearest to it (blended over 5 cm around
/// the elbow and the wrist).
fn arm() -> Character {
    let joints: Vec<Joint> = JOINTS
        .iter()
        .enumerate()
        .map(|(i, name)| Joint {
            name: name.to_string(),
            parent: i.checked_sub(1).map(|p| JointId(p as u16)),
            rest: Trs::from_translation(Vector3::new(0.0, if i == 0 { 0.0 } else { BONE }, 0.0)),
            inverse_bind: Matrix4::new_translation(&Vector3::new(0.0, -BONE * i as f32, 0.0)),
        })
        .collect();
    let skeleton = Skeleton::new(joints, Matrix4::identity()).expect("a valid skeleton");
    let length = BONE * JOINTS.len() as f32;
    let mut positions = Vec::new();
    let (mut bones, mut weights) = (Vec::new(), Vec::new());
    let mut push = |p: Point| {
        let y = p.y;
        // The joint below and the share of the one above it.
        let j = ((y / BONE).floor() as usize).min(JOINTS.len() - 1);
        let above = ((y - BONE * (j + 1) as f32 + 0.05) / 0.1).clamp(0.0, 1.0);
        if j + 1 < JOINTS.len() && above > 0.0 {
            bones.push([j as u16, j as u16 + 1, 0, 0]);
            weights.push([1.0 - above, above, 0.0, 0.0]);
        } else {
            bones.push([j as u16, 0, 0, 0]);
            weights.push([1.0, 0.0, 0.0, 0.0]);
        }
        positions.push(p);
    };
    for r in 0..RINGS {
        let y = length * r as f32 / (RINGS - 1) as f32;
        for a in 0..AROUND {
            let angle = 2.0 * PI * a as f32 / AROUND as f32;
            push(Point::new(RADIUS * angle.cos(), y, RADIUS * angle.sin()));
        }
    }
    // Both ends closed by a centre vertex.
    push(Point::new(0.0, 0.0, 0.0));
    push(Point::new(0.0, length, 0.0));
    let (bottom, top) = ((RINGS * AROUND) as u32, (RINGS * AROUND) as u32 + 1);
    let at = |r: usize, a: usize| (r * AROUND + a % AROUND) as u32;
    let mut triangles = Vec::new();
    for r in 0..RINGS - 1 {
        for a in 0..AROUND {
            triangles.push([at(r, a), at(r + 1, a), at(r + 1, a + 1)]);
            triangles.push([at(r, a), at(r + 1, a + 1), at(r, a + 1)]);
        }
    }
    for a in 0..AROUND {
        triangles.push([bottom, at(0, a), at(0, a + 1)]);
        triangles.push([top, at(RINGS - 1, a + 1), at(RINGS - 1, a)]);
    }
    let mesh = TriMesh::new(positions, triangles).expect("a valid mesh");
    let influences = Influences::new(bones, weights, JOINTS.len()).expect("valid weights");
    Character::new("arm".into(), skeleton, mesh, influences, Vec::new())
}

/// The caller's animation at step `k`: each joint's transform relative to
/// its parent, and where the shoulder is in the world. The arm hangs from a
/// shoulder moving towards the wall, swinging and bending its elbow; it
/// brushes the floor, the box and the wall on the way.
fn animate(k: usize, skeleton: &Skeleton) -> (Vec<Trs>, Isometry3<f32>) {
    let s = k as f32 / STEPS as f32;
    let mut local: Vec<Trs> = skeleton.rest_pose_ref().to_vec();
    let swing = 0.6 * (2.0 * PI * s).sin();
    let bend = 0.5 + 0.4 * (4.0 * PI * s).sin();
    local[0].rotation = UnitQuaternion::from_euler_angles(0.0, 0.0, swing);
    local[1].rotation = UnitQuaternion::from_euler_angles(0.0, 0.0, bend);
    local[2].rotation = UnitQuaternion::from_euler_angles(0.3 * s, 0.0, 0.2);
    // The shoulder 88 cm up, the arm hanging down (+Y of the arm turned to
    // −Y), moving along +X.
    let placement = Isometry3::from_parts(
        Vector3::new(0.2 + 1.0 * s, 0.88, 0.15).into(),
        UnitQuaternion::from_euler_angles(0.0, 0.0, PI),
    );
    (local, placement)
}

/// The exact oracle: every vertex skinned (`pose`), every pair of triangles
/// decided with exact predicates.
fn oracle(arm: &Character, pose: &PoseBuffers, room: &TriMesh) -> BTreeSet<(u32, u32)> {
    let p = &pose.positions;
    let mut out = BTreeSet::new();
    for (t, [a, b, c]) in arm.mesh.indices().iter().enumerate() {
        let ct = Triangle::new(p[*a as usize], p[*b as usize], p[*c as usize]);
        for (r, rt) in room.iter_triangles() {
            if triangles_intersect_exact(&ct, &rt) {
                out.insert((t as u32, r.0));
            }
        }
    }
    out
}

/// What the loop saw.
#[derive(Debug, Default)]
struct Seen {
    steps_with_contact: usize,
    pairs: usize,
    sphere_tests: u64,
    triangle_tests: u64,
}

fn run() -> Result<Seen, WorldError> {
    let room = Arc::new(room());
    let arm = Arc::new(arm());
    let mut world = CollisionWorld::new(Method::UndividedPrunedTriTri);
    let room_handle = world.add_room(room.clone())?;
    let model = CharacterModel::new(arm.clone(), SkinningModel::Linear)?;
    let hand = world.add_character(Arc::new(model))?;

    // The oracle's own pose of every vertex (the world skins only what its
    // narrow phase reads).
    let mut pose = PoseBuffers::new(&arm);
    let mut seen = Seen::default();
    for k in 0..STEPS {
        let (local, placement) = animate(k, &arm.skeleton);
        world.set_joint_transforms(hand, &local, &placement)?;
        // For a few steps the arm leaves the scene (a despawned or pooled
        // instance): inactive, it takes part in nothing, and comes back
        // where it is posed.
        let away = AWAY.contains(&k);
        world.set_character_active(hand, !away)?;
        let contacts = world.step();

        let reported: BTreeSet<(u32, u32)> = contacts
            .room_contacts_of(hand)
            .iter()
            .inspect(|c| assert_eq!(c.room, room_handle))
            .map(|c| (c.triangle, c.room_triangle))
            .collect();
        pose.local.copy_from_slice(&local);
        pose.pose_local(&arm);
        pose.place(&placement.to_homogeneous());
        pose.skin_all(&arm, SkinningModel::Linear);
        let exact = if away {
            BTreeSet::new()
        } else {
            oracle(&arm, &pose, &room)
        };
        assert_eq!(
            reported, exact,
            "step {k}: the world's pairs against the oracle's"
        );

        seen.steps_with_contact += usize::from(!exact.is_empty());
        seen.pairs += exact.len();
        seen.sphere_tests += contacts.total.sphere_sphere;
        seen.triangle_tests += contacts.total.tri_tri;
    }
    Ok(seen)
}

fn main() {
    let seen = run().expect("the arm's data is valid");
    println!(
        "{STEPS} steps: {} with contact, {} colliding pairs in all (each the exact oracle's), \
         {} sphere tests and {} triangle tests",
        seen.steps_with_contact, seen.pairs, seen.sphere_tests, seen.triangle_tests
    );
    // The loop brushes the room on some steps and not on others.
    assert!(seen.steps_with_contact > 0 && seen.steps_with_contact < STEPS);
}

#[test]
fn the_game_loop_finds_the_oracles_pairs_on_every_step() {
    main();
}
