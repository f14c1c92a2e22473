//! A world refuses the caller's bad data with a typed error naming the
//! body, the joint or the vertex at fault, never a panic, and keeps what it
//! had: a refused pose leaves the last one in place.

use std::sync::Arc;

use cornertree::character::skinning::{Influences, SkinError};
use cornertree::character::{Character, Joint, PoseBuffers, Skeleton, SkinningModel, Trs};
use cornertree::geometry::Point;
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;
use cornertree::world::{
    CharacterHandle, CharacterModel, CollisionWorld, ObjectHandle, WorldError,
};
use nalgebra::{Isometry3, Matrix4, Quaternion, UnitQuaternion, Vector3};

/// A one-joint character: one triangle 10 cm across, around its origin.
fn chip() -> Character {
    let skeleton = Skeleton::new(
        vec![Joint {
            name: "root".into(),
            parent: None,
            rest: Trs::IDENTITY,
            inverse_bind: Matrix4::identity(),
        }],
        Matrix4::identity(),
    )
    .unwrap();
    let mesh = TriMesh::new(
        vec![
            Point::new(-0.05, 0.0, 0.0),
            Point::new(0.05, 0.0, 0.0),
            Point::new(0.0, 0.1, 0.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    let influences = Influences::rigid(&[cornertree::character::JointId(0); 3]);
    Character::new("chip".into(), skeleton, mesh, influences, Vec::new())
}

/// A floor of two triangles at `y = 0`.
fn floor() -> TriMesh {
    TriMesh::new(
        vec![
            Point::new(-1.0, 0.0, -1.0),
            Point::new(1.0, 0.0, -1.0),
            Point::new(1.0, 0.0, 1.0),
            Point::new(-1.0, 0.0, 1.0),
        ],
        vec![[0, 2, 1], [0, 3, 2]],
    )
    .unwrap()
}

fn world() -> (CollisionWorld, CharacterHandle) {
    let mut w = CollisionWorld::new(Method::PrunedTriTri);
    w.add_room(Arc::new(floor())).unwrap();
    let model = CharacterModel::new(chip(), SkinningModel::Linear).unwrap();
    let h = w.add_character(Arc::new(model)).unwrap();
    (w, h)
}

#[test]
fn handles_the_world_did_not_give_are_refused() {
    let (mut w, _) = world();
    let stranger = CharacterHandle(7);
    assert_eq!(
        w.set_joint_transforms(stranger, &[Trs::IDENTITY], &Isometry3::identity()),
        Err(WorldError::UnknownCharacter(stranger))
    );
    assert!(matches!(
        w.set_object_pose(ObjectHandle(0), Isometry3::identity()),
        Err(WorldError::UnknownObject(ObjectHandle(0)))
    ));
    assert!(w.character(stranger).is_err());
    let e = WorldError::UnknownCharacter(stranger).to_string();
    assert_eq!(e, "character 7: no such character in this world");
}

#[test]
fn bad_poses_are_refused_and_the_last_pose_is_kept() {
    let (mut w, h) = world();
    // Half through the floor: one contact with each floor triangle it crosses.
    let through = Isometry3::translation(0.0, -0.05, 0.0);
    w.set_joint_transforms(h, &[Trs::IDENTITY], &through)
        .unwrap();
    let pairs = w.step().room_pairs.clone();
    assert!(!pairs.is_empty());

    assert_eq!(
        w.set_joint_transforms(h, &[Trs::IDENTITY, Trs::IDENTITY], &through),
        Err(WorldError::JointCount {
            character: h,
            expected: 1,
            got: 2
        })
    );
    let nan = Trs {
        translation: Vector3::new(f32::NAN, 0.0, 0.0),
        ..Trs::IDENTITY
    };
    assert_eq!(
        w.set_joint_transforms(h, &[nan], &through),
        Err(WorldError::NonFiniteJoint {
            character: h,
            joint: 0
        })
    );
    let bad_turn = UnitQuaternion::new_unchecked(Quaternion::new(f32::NAN, 0.0, 0.0, 0.0));
    assert_eq!(
        w.set_joint_transforms(
            h,
            &[Trs::IDENTITY],
            &Isometry3::from_parts(Vector3::zeros().into(), bad_turn)
        ),
        Err(WorldError::NonFinitePlacement { character: h })
    );
    let far = Isometry3::translation(3.0e9, 0.0, 0.0);
    assert!(matches!(
        w.set_joint_transforms(h, &[Trs::IDENTITY], &far),
        Err(WorldError::PoseOutOfRange { character, .. }) if character == h
    ));
    let mut pose = PoseBuffers::new(&chip());
    pose.skin[0][(0, 3)] = f32::INFINITY;
    assert_eq!(
        w.set_pose(h, &pose),
        Err(WorldError::NonFiniteJoint {
            character: h,
            joint: 0
        })
    );
    // A matrix is finite as a whole, its last row (which skinning never
    // reads) included.
    let mut pose = PoseBuffers::new(&chip());
    pose.skin[0][(3, 1)] = f32::NAN;
    assert_eq!(
        w.set_pose(h, &pose),
        Err(WorldError::NonFiniteJoint {
            character: h,
            joint: 0
        })
    );
    // None of the refused poses replaced the last one.
    assert_eq!(w.step().room_pairs, pairs);
}

#[test]
fn bad_bodies_are_refused() {
    let (mut w, _) = world();
    let far = TriMesh::new(
        vec![
            Point::new(0.0, 0.0, 0.0),
            Point::new(2.0e9, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
        ],
        vec![[0, 1, 2]],
    )
    .unwrap();
    assert!(matches!(
        w.add_room(Arc::new(far.clone())),
        Err(WorldError::MeshOutOfRange {
            what: "room",
            vertex: 1,
            ..
        })
    ));
    assert!(matches!(
        w.add_object(
            Arc::new(floor()),
            Isometry3::translation(f32::NAN, 0.0, 0.0)
        ),
        Err(WorldError::BadObjectPose { .. })
    ));
    // Influences for two vertices, a mesh of three.
    let mut c = chip();
    c.influences = Influences::rigid(&[cornertree::character::JointId(0); 2]);
    assert_eq!(
        CharacterModel::new(c, SkinningModel::Linear).unwrap_err(),
        WorldError::Skin(SkinError::Length {
            what: "influences",
            got: 2,
            vertices: 3
        })
    );
    assert_eq!(w.sweep().unwrap_err(), WorldError::ContinuousOff);
}
