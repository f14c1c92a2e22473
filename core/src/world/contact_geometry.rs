//! Where a contact is: its two triangles as posed now, and the segment they
//! share, asked for one contact at a time after a step.
//!
//! A step reports which triangles touch; an engine that responds to a
//! contact also wants where. Nothing of this is computed during the step: a
//! contact's triangles are posed again on request, a character's corners
//! skinned with the same arithmetic as the step's narrow phase (bit for bit,
//! at the same pose), an object's moved by its pose.

use crate::geometry::intersection_segment::intersection_segment;
use crate::geometry::{Point, Triangle};
use crate::mesh::{TriMesh, TriangleId};

use super::collision_world::CollisionWorld;
use super::contacts::{CharacterPair, ObjectPair, RoomPair, SelfPair};
use super::error::WorldError;
use super::handles::{CharacterHandle, ObjectHandle, RoomHandle};
use super::queries::BodyRef;

/// A contact of any kind, as a step reports it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ContactRef {
    /// A character against a room.
    Room(RoomPair),
    /// A character against an object.
    Object(ObjectPair),
    /// Two characters.
    Characters(CharacterPair),
    /// A character against itself.
    Itself(SelfPair),
}

impl From<RoomPair> for ContactRef {
    fn from(p: RoomPair) -> Self {
        ContactRef::Room(p)
    }
}

impl From<ObjectPair> for ContactRef {
    fn from(p: ObjectPair) -> Self {
        ContactRef::Object(p)
    }
}

impl From<CharacterPair> for ContactRef {
    fn from(p: CharacterPair) -> Self {
        ContactRef::Characters(p)
    }
}

impl From<SelfPair> for ContactRef {
    fn from(p: SelfPair) -> Self {
        ContactRef::Itself(p)
    }
}

/// Where a contact is, at the current poses.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactGeometry {
    /// The contact's two triangles in the world, in the order of its pair
    /// (a character's triangle first against a room or an object;
    /// `triangle_a`, then `triangle_b`).
    pub triangles: [Triangle; 2],
    /// The segment both triangles share (one point twice where they touch
    /// at a point); `None` where they lie in one plane, where one is
    /// degenerate, or where they no longer meet (the poses changed since
    /// the step). Its direction, or a triangle's normal, orients a response.
    pub segment: Option<[Point; 2]>,
}

impl CollisionWorld {
    /// Where `contact` is: its two triangles at the current poses (the
    /// step's, until a pose is set again) and the segment they share.
    /// Refused for a handle or a triangle this world does not have.
    ///
    /// ```
    /// # use std::sync::Arc;
    /// # use cornertree::character::skinning::Influences;
    /// # use cornertree::character::{Character, Joint, Skeleton, SkinningModel, Trs};
    /// # use cornertree::geometry::Point;
    /// # use cornertree::mesh::TriMesh;
    /// # use cornertree::pipeline::Method;
    /// # use cornertree::world::{CharacterModel, CollisionWorld};
    /// # use nalgebra::{Isometry3, Matrix4};
    /// # let floor = TriMesh::new(
    /// #     vec![Point::new(-2.0, 0.0, -2.0), Point::new(2.0, 0.0, -2.0),
    /// #          Point::new(2.0, 0.0, 2.0), Point::new(-2.0, 0.0, 2.0)],
    /// #     vec![[0, 2, 1], [0, 3, 2]],
    /// # ).unwrap();
    /// # let joint = Joint { name: "root".into(), parent: None, rest: Trs::IDENTITY,
    /// #     inverse_bind: Matrix4::identity() };
    /// # let skeleton = Skeleton::new(vec![joint], Matrix4::identity()).unwrap();
    /// # let tetrahedron = TriMesh::new(
    /// #     vec![Point::new(-0.1, 0.0, -0.1), Point::new(0.1, 0.0, -0.1),
    /// #          Point::new(0.0, 0.0, 0.1), Point::new(0.0, 0.2, 0.0)],
    /// #     vec![[0, 1, 2], [0, 3, 1], [1, 3, 2], [2, 3, 0]],
    /// # ).unwrap();
    /// # let weights = Influences::new(vec![[0; 4]; 4], vec![[1.0, 0.0, 0.0, 0.0]; 4], 1).unwrap();
    /// # let body = Character::new("tetra".into(), skeleton, tetrahedron, weights, Vec::new());
    /// // A tetrahedron half sunk into a floor (as in `CollisionWorld`'s example).
    /// let mut world = CollisionWorld::new(Method::UndividedPrunedTriTri);
    /// world.add_room(Arc::new(floor)).unwrap();
    /// let model = CharacterModel::new(body, SkinningModel::Linear).unwrap();
    /// let tetra = world.add_character(Arc::new(model)).unwrap();
    /// let sunk = Isometry3::translation(0.5, -0.1, -0.5);
    /// world.set_joint_transforms(tetra, &[Trs::IDENTITY], &sunk).unwrap();
    /// let contacts: Vec<_> = world.step().room_contacts_of(tetra).to_vec();
    /// for c in contacts {
    ///     let g = world.contact_geometry(c).unwrap();
    ///     // Each side face crosses the floor along a segment in the floor.
    ///     let [p, q] = g.segment.unwrap();
    ///     assert!(p.y.abs() < 1e-6 && q.y.abs() < 1e-6 && (p - q).norm() > 0.05);
    /// }
    /// ```
    pub fn contact_geometry(
        &self,
        contact: impl Into<ContactRef>,
    ) -> Result<ContactGeometry, WorldError> {
        let triangles = match contact.into() {
            ContactRef::Room(p) => [
                self.character_triangle(p.character, p.triangle)?,
                self.room_triangle(p.room, p.room_triangle)?,
            ],
            ContactRef::Object(p) => [
                self.character_triangle(p.character, p.triangle)?,
                self.object_triangle(p.object, p.object_triangle)?,
            ],
            ContactRef::Characters(p) => [
                self.character_triangle(p.a, p.triangle_a)?,
                self.character_triangle(p.b, p.triangle_b)?,
            ],
            ContactRef::Itself(p) => [
                self.character_triangle(p.character, p.triangle_a)?,
                self.character_triangle(p.character, p.triangle_b)?,
            ],
        };
        Ok(ContactGeometry {
            triangles,
            segment: intersection_segment(&triangles[0], &triangles[1]),
        })
    }

    /// Triangle `t` of character `h` at its current pose, its corners
    /// skinned as the step's narrow phase skins them.
    pub fn character_triangle(&self, h: CharacterHandle, t: u32) -> Result<Triangle, WorldError> {
        let c = self.locked(h)?;
        let character = c.model.character();
        let [i, j, k] = *character
            .mesh
            .indices()
            .get(t as usize)
            .ok_or_else(|| unknown(BodyRef::Character(h), t, &character.mesh))?;
        let pose = c.pose.as_pose();
        let at = |v: u32| pose.skin_vertex(character, c.model.skinning(), v as usize);
        Ok(Triangle::new(at(i), at(j), at(k)))
    }

    /// Triangle `t` of room `h`.
    fn room_triangle(&self, h: RoomHandle, t: u32) -> Result<Triangle, WorldError> {
        let (_, mesh) = self.room(h).ok_or(WorldError::UnknownRoom(h))?;
        checked(mesh, BodyRef::Room(h), t)
    }

    /// Triangle `t` of object `h`, at its pose.
    fn object_triangle(&self, h: ObjectHandle, t: u32) -> Result<Triangle, WorldError> {
        let (_, mesh, pose) = self.object(h).ok_or(WorldError::UnknownObject(h))?;
        let tri = checked(mesh, BodyRef::Object(h), t)?;
        let m = |p: Point| pose * p;
        Ok(Triangle::new(m(tri.a), m(tri.b), m(tri.c)))
    }
}

/// Triangle `t` of `mesh`, or the error naming `body`.
fn checked(mesh: &TriMesh, body: BodyRef, t: u32) -> Result<Triangle, WorldError> {
    if (t as usize) < mesh.triangle_count() {
        Ok(mesh.triangle(TriangleId(t)))
    } else {
        Err(unknown(body, t, mesh))
    }
}

fn unknown(body: BodyRef, triangle: u32, mesh: &TriMesh) -> WorldError {
    WorldError::UnknownTriangle {
        body,
        triangle,
        count: mesh.triangle_count(),
    }
}
