//! Where a contact is: for every contact of a step (a character against a
//! room, an object, another character and itself), the triangles
//! `contact_geometry` gives are the ones every vertex skinned at the same
//! pose gives (bit for bit: the same skinning, the same move of an
//! object's corners); they meet by the exact test; and the segment lies on
//! both.

#[path = "common/box_mesh.rs"]
mod box_mesh;
/// The workbench's generated humanoid, for a realistic skinned character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;
#[path = "common/walkers.rs"]
mod walkers;

use cornertree::character::SkinningModel;
use cornertree::geometry::closest_point::closest_point_on_triangle;
use cornertree::geometry::exact::triangles_intersect_exact;
use cornertree::geometry::{Point, Triangle};
use cornertree::mesh::TriangleId;
use cornertree::world::{
    BodyRef, CharacterHandle, ContactRef, ObjectHandle, RoomHandle, RoomPair, WorldError,
};
use walkers::{Scene, WALKERS};

/// Distance from `p` to triangle `t`, in `f64`.
fn distance(p: &Point, t: &Triangle) -> f64 {
    let q = p.cast::<f64>();
    (closest_point_on_triangle(&q, t) - q).norm()
}

#[test]
fn every_contacts_triangles_are_the_posed_ones_and_meet_along_the_segment() {
    let mut scene = Scene::new();
    let mut world = scene.world(WALKERS, true);
    let floor = walkers::floor();
    let mesh = scene.character.mesh.clone();
    let (mut seen, mut segments, mut kinds) = (0, 0, [0usize; 4]);
    for k in 0..3 {
        scene.pose(k, false);
        for c in 0..WALKERS {
            world
                .set_pose(CharacterHandle(c as u32), &scene.poses[c])
                .unwrap();
        }
        let object_pose = Scene::object_pose(k);
        world.set_object_pose(ObjectHandle(0), object_pose).unwrap();
        // Every vertex of every walker skinned: the reference triangles.
        let posed: Vec<Vec<Point>> = scene
            .poses
            .iter()
            .map(|p| {
                let mut out = vec![Point::origin(); mesh.vertex_count()];
                p.skin_all_into(&scene.character, SkinningModel::Linear, &mut out);
                out
            })
            .collect();
        let walker = |c: CharacterHandle, t: u32| {
            let [i, j, l] = mesh.indices()[t as usize];
            let p = &posed[c.index()];
            Triangle::new(p[i as usize], p[j as usize], p[l as usize])
        };
        let contacts = world.step();
        let all: Vec<(ContactRef, Triangle, Triangle)> = contacts
            .room_pairs
            .iter()
            .map(|p| {
                (
                    ContactRef::from(*p),
                    walker(p.character, p.triangle),
                    floor.triangle(TriangleId(p.room_triangle)),
                )
            })
            .chain(contacts.object_pairs.iter().map(|p| {
                let t = scene.object.triangle(TriangleId(p.object_triangle));
                let m = |q: Point| object_pose * q;
                (
                    ContactRef::from(*p),
                    walker(p.character, p.triangle),
                    Triangle::new(m(t.a), m(t.b), m(t.c)),
                )
            }))
            .chain(contacts.character_pairs.iter().map(|p| {
                (
                    ContactRef::from(*p),
                    walker(p.a, p.triangle_a),
                    walker(p.b, p.triangle_b),
                )
            }))
            .chain(contacts.self_pairs.iter().map(|p| {
                (
                    ContactRef::from(*p),
                    walker(p.character, p.triangle_a),
                    walker(p.character, p.triangle_b),
                )
            }))
            .collect();
        for (contact, a, b) in all {
            let g = world.contact_geometry(contact).unwrap();
            let kind = match contact {
                ContactRef::Room(_) => 0,
                ContactRef::Object(_) => 1,
                ContactRef::Characters(_) => 2,
                ContactRef::Itself(_) => 3,
            };
            kinds[kind] += 1;
            assert_eq!(g.triangles[0], a, "{contact:?}: the first triangle");
            assert_eq!(g.triangles[1], b, "{contact:?}: the second triangle");
            assert!(
                triangles_intersect_exact(&g.triangles[0], &g.triangles[1]),
                "{contact:?}: the triangles do not meet"
            );
            seen += 1;
            if let Some([p, q]) = g.segment {
                segments += 1;
                for e in [p, q] {
                    for t in &g.triangles {
                        assert!(
                            distance(&e, t) < 1e-5,
                            "{contact:?}: {e:?} is {} from {t:?}",
                            distance(&e, t)
                        );
                    }
                }
            }
        }
    }
    assert!(kinds.iter().all(|&n| n > 0), "contacts by kind {kinds:?}");
    assert!(
        segments * 100 >= seen * 99,
        "{segments} segments for {seen} contacts"
    );
    // A handle or a triangle the world does not have is named.
    let bad = RoomPair {
        character: CharacterHandle(0),
        triangle: mesh.triangle_count() as u32,
        room: RoomHandle(0),
        room_triangle: 0,
    };
    let e = world.contact_geometry(bad).unwrap_err();
    assert_eq!(
        e,
        WorldError::UnknownTriangle {
            body: BodyRef::Character(CharacterHandle(0)),
            triangle: mesh.triangle_count() as u32,
            count: mesh.triangle_count(),
        }
    );
    assert_eq!(
        e.to_string(),
        format!(
            "character 0: no triangle {} (its mesh has {})",
            mesh.triangle_count(),
            mesh.triangle_count()
        )
    );
    let e = world
        .contact_geometry(RoomPair {
            triangle: 0,
            room: RoomHandle(4),
            ..bad
        })
        .unwrap_err();
    assert_eq!(e, WorldError::UnknownRoom(RoomHandle(4)));
}
