//! A character, an object or a room set inactive takes part in nothing: while it
//! is out, a world steps, sweeps and answers queries exactly as a world
//! built without it (the same pairs, the same tests); set active again, it
//! is stepped as in a world where it never left, and continuous detection
//! starts its steps where it is (the first sweep back finds nothing for
//! it, the next ones what a world that kept it finds).

use std::ops::Range;
use std::sync::Arc;

#[path = "common/box_mesh.rs"]
mod box_mesh;
/// The workbench's generated humanoid, for a realistic skinned character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;
#[path = "common/walkers.rs"]
mod walkers;

use cornertree::geometry::Point;
use cornertree::geometry::query_shapes::Ray;
use cornertree::mesh::TriMesh;
use cornertree::pipeline::FrameCounters;
use cornertree::world::contacts::{
    CharacterPair, Contacts, Detection, ObjectPair, RoomPair, SelfPair, Timed,
};
use cornertree::world::{
    BodyRef, CharacterHandle, ObjectHandle, QueryScratch, QueryTargets, RoomHandle, WorldError,
};
use rand::{Rng, SeedableRng, rngs::SmallRng};
use walkers::{Scene, WALKERS};

const FRAMES: usize = 7;
/// The frames character 1 and the object are out.
const OUT: Range<usize> = 2..4;
/// The walkers of the world built without character 1, by their handles
/// in the world that has it.
const KEPT: [u32; 3] = [0, 2, 3];

/// A contact's time of impact, as text (a step's contacts have none).
trait Toi {
    fn toi(&self) -> Option<f64>;
}

impl<P> Toi for Timed<P> {
    fn toi(&self) -> Option<f64> {
        Some(self.toi)
    }
}

macro_rules! untimed {
    ($($t:ty),*) => {
        $(impl Toi for $t {
            fn toi(&self) -> Option<f64> {
                None
            }
        })*
    };
}
untimed!(RoomPair, ObjectPair, CharacterPair, SelfPair);

/// Every contact of a step or a sweep, its handles mapped by `character`
/// and `object` (a pair naming a body the map drops is a failure).
fn contacts<D: Detection>(
    c: &Contacts<D>,
    character: impl Fn(CharacterHandle) -> CharacterHandle,
    object: impl Fn(ObjectHandle) -> ObjectHandle,
) -> Vec<String>
where
    D::Pair<RoomPair>: Toi,
    D::Pair<ObjectPair>: Toi,
    D::Pair<CharacterPair>: Toi,
    D::Pair<SelfPair>: Toi,
{
    let mut out = Vec::new();
    for p in &c.room_pairs {
        let (q, t) = (D::pair(p), p.toi());
        out.push(format!(
            "room {} {} {} {} {t:?}",
            character(q.character),
            q.triangle,
            q.room,
            q.room_triangle
        ));
    }
    for p in &c.object_pairs {
        let (q, t) = (D::pair(p), p.toi());
        out.push(format!(
            "object {} {} {} {} {t:?}",
            character(q.character),
            q.triangle,
            object(q.object),
            q.object_triangle
        ));
    }
    for p in &c.character_pairs {
        let (q, t) = (D::pair(p), p.toi());
        out.push(format!(
            "characters {} {} {} {} {t:?}",
            character(q.a),
            q.triangle_a,
            character(q.b),
            q.triangle_b
        ));
    }
    for p in &c.self_pairs {
        let (q, t) = (D::pair(p), p.toi());
        out.push(format!(
            "self {} {} {} {t:?}",
            character(q.character),
            q.triangle_a,
            q.triangle_b
        ));
    }
    out.sort();
    out
}

/// The tests a step or a sweep made, kind by kind (not its times, nor its
/// refits: a character back from a pause refits ahead from older steps).
fn tests<D: Detection>(c: &Contacts<D>) -> Vec<(u64, u64, u64)> {
    let t = |f: &FrameCounters| (f.sphere_sphere, f.tri_tri, f.plane_sphere);
    vec![
        t(&c.by_kind.environment),
        t(&c.by_kind.objects),
        t(&c.by_kind.characters),
        t(&c.by_kind.self_contact),
        (c.broad_phase_tests, c.body_pairs, 0),
    ]
}

fn same(h: CharacterHandle) -> CharacterHandle {
    h
}
fn kept(h: CharacterHandle) -> CharacterHandle {
    CharacterHandle(KEPT[h.index()])
}
fn same_object(h: ObjectHandle) -> ObjectHandle {
    h
}
fn no_object(h: ObjectHandle) -> ObjectHandle {
    panic!("{h}: the world without the object reports it")
}

fn ray(rng: &mut SmallRng) -> Ray {
    let o = Point::new(
        rng.random_range(-2.0..2.0),
        rng.random_range(0.2..2.0),
        rng.random_range(1.5..3.0),
    );
    let target = Point::new(
        rng.random_range(-1.2..1.2),
        rng.random_range(0.0..1.8),
        rng.random_range(-0.3..0.6),
    );
    Ray::new(o, target - o, f32::INFINITY).unwrap()
}

/// The world that sets walker 1 and the box out over `OUT` (`toggled`)
/// against the world that never had them (`without`) while they are out,
/// and against the world that always has them (`always`) otherwise: steps,
/// sweeps and rays.
#[test]
fn an_inactive_body_is_as_if_absent_and_comes_back_as_if_never_gone() {
    let mut scene = Scene::new();
    let mut toggled = scene.world(WALKERS, true);
    let mut always = scene.world(WALKERS, true);
    let mut without = scene.world(KEPT.len(), false);
    let mut rng = SmallRng::seed_from_u64(7);
    let mut scratch = QueryScratch::new();
    let (mut out_contacts, mut out_object_contacts, mut ray_hits_on_1) = (0, 0, 0);
    for k in 0..FRAMES {
        let out = OUT.contains(&k);
        let walker = CharacterHandle(1);
        let object = ObjectHandle(0);
        toggled.set_character_active(walker, !out).unwrap();
        toggled.set_object_active(object, !out).unwrap();
        assert_eq!(toggled.character_is_active(walker).unwrap(), !out);
        assert_eq!(toggled.object_is_active(object).unwrap(), !out);

        // `toggled` poses its walker 1 far away while it is out: where a
        // paused instance is does not matter.
        scene.pose(k, out);
        for c in 0..WALKERS {
            toggled
                .set_pose(CharacterHandle(c as u32), &scene.poses[c])
                .unwrap();
        }
        scene.pose(k, false);
        for c in 0..WALKERS {
            always
                .set_pose(CharacterHandle(c as u32), &scene.poses[c])
                .unwrap();
        }
        for (b, &a) in KEPT.iter().enumerate() {
            without
                .set_pose(CharacterHandle(b as u32), &scene.poses[a as usize])
                .unwrap();
        }
        let op = Scene::object_pose(k);
        toggled.set_object_pose(object, op).unwrap();
        always.set_object_pose(object, op).unwrap();

        // Rays first (a query's refits serve the step after it).
        for _ in 0..40 {
            let r = ray(&mut rng);
            let got = toggled
                .cast_ray(&r, QueryTargets::All, &mut scratch)
                .unwrap();
            let (reference, name) = if out {
                let mut h = without
                    .cast_ray(&r, QueryTargets::All, &mut scratch)
                    .unwrap();
                if let Some(h) = h.as_mut()
                    && let BodyRef::Character(c) = h.body
                {
                    h.body = BodyRef::Character(kept(c));
                }
                (h, "without")
            } else {
                let h = always
                    .cast_ray(&r, QueryTargets::All, &mut scratch)
                    .unwrap();
                if h.is_some_and(|h| h.body == BodyRef::Character(walker)) {
                    ray_hits_on_1 += 1;
                }
                (h, "always")
            };
            assert_eq!(
                got, reference,
                "frame {k}: a ray's first hit against {name}"
            );
        }
        if out {
            // A query naming an inactive body finds nothing, and no error.
            let r = ray(&mut rng);
            for t in [
                QueryTargets::Character(walker),
                QueryTargets::Object(object),
            ] {
                assert_eq!(toggled.cast_ray(&r, t, &mut scratch).unwrap(), None);
                assert_eq!(scratch.counters().root_tests, 0);
            }
        }

        let got = toggled.step();
        let (g, gt) = (contacts(got, same, same_object), tests(got));
        if out {
            let w = without.step();
            assert_eq!(g, contacts(w, kept, no_object), "frame {k}: step");
            assert_eq!(gt, tests(w), "frame {k}: step's tests");
            let a = always.step();
            let always_pairs = contacts(a, same, same_object);
            out_object_contacts += always_pairs
                .iter()
                .filter(|p| p.starts_with("object"))
                .count();
            out_contacts += always_pairs
                .iter()
                .filter(|p| p.contains("character 1 "))
                .count();
            assert_ne!(g, always_pairs);
        } else {
            let a = always.step();
            assert_eq!(g, contacts(a, same, same_object), "frame {k}: step");
            assert_eq!(gt, tests(a), "frame {k}: step's tests");
            without.step();
        }

        // Sweeps: while out, and on the first sweep back (which records
        // where walker 1 and the box are now and finds nothing for them),
        // as the world without them; otherwise as the world with them.
        let got = toggled.sweep().unwrap();
        let (g, gt) = (contacts(got, same, same_object), tests(got));
        let w = without.sweep().unwrap();
        let (wc, wt) = (contacts(w, kept, no_object), tests(w));
        let a = always.sweep().unwrap();
        let (ac, at) = (contacts(a, same, same_object), tests(a));
        if out || k == OUT.end {
            assert_eq!(g, wc, "frame {k}: sweep");
            assert_eq!(gt, wt, "frame {k}: sweep's tests");
        } else {
            assert_eq!(g, ac, "frame {k}: sweep");
            assert_eq!(gt, at, "frame {k}: sweep's tests");
            if k > 0 {
                assert!(!ac.is_empty(), "frame {k}: a sweep without contacts");
            }
        }
        if k == OUT.end {
            assert_ne!(
                g, ac,
                "frame {k}: walker 1 came back 20 m away: nothing to find on its way"
            );
        }
    }
    assert!(
        out_contacts > 50,
        "walker 1 met {out_contacts} triangles while out"
    );
    assert!(
        out_object_contacts > 5,
        "the box met {out_object_contacts} triangles while out"
    );
    assert!(ray_hits_on_1 > 3, "rays met walker 1 {ray_hits_on_1} times");
}

/// A wall the walkers' fronts cross.
fn wall() -> TriMesh {
    TriMesh::new(
        vec![
            Point::new(-2.0, 0.0, 0.12),
            Point::new(2.0, 0.0, 0.12),
            Point::new(2.0, 2.0, 0.12),
            Point::new(-2.0, 2.0, 0.12),
        ],
        vec![[0, 1, 2], [0, 2, 3]],
    )
    .unwrap()
}

/// A room set out (the wall, a level streamed out) is as if absent, and
/// back is as if it never left: steps, sweeps and rays.
#[test]
fn an_inactive_room_is_as_if_absent() {
    let mut scene = Scene::new();
    let worlds = |with_wall: bool| {
        let mut w = scene.world(2, false);
        if with_wall {
            w.add_room(Arc::new(wall())).unwrap();
        }
        w
    };
    let (mut toggled, mut always, mut without) = (worlds(true), worlds(true), worlds(false));
    let wall = RoomHandle(1);
    let mut rng = SmallRng::seed_from_u64(3);
    let mut scratch = QueryScratch::new();
    let mut wall_contacts = 0;
    for k in 0..5 {
        let out = (1..3).contains(&k);
        toggled.set_room_active(wall, !out).unwrap();
        assert_eq!(toggled.room_is_active(wall).unwrap(), !out);
        scene.pose(k, false);
        for w in [&mut toggled, &mut always, &mut without] {
            for c in 0..2 {
                w.set_pose(CharacterHandle(c as u32), &scene.poses[c])
                    .unwrap();
            }
        }
        let reference = if out { &mut without } else { &mut always };
        for _ in 0..30 {
            let r = ray(&mut rng);
            assert_eq!(
                toggled
                    .cast_ray(&r, QueryTargets::All, &mut scratch)
                    .unwrap(),
                reference
                    .cast_ray(&r, QueryTargets::All, &mut scratch)
                    .unwrap(),
                "frame {k}: a ray"
            );
        }
        let (g, gt) = {
            let c = toggled.step();
            (contacts(c, same, same_object), tests(c))
        };
        let r = reference.step();
        assert_eq!(g, contacts(r, same, same_object), "frame {k}: step");
        assert_eq!(gt, tests(r), "frame {k}: step's tests");
        let a = always.step();
        if out {
            wall_contacts += contacts(a, same, same_object)
                .iter()
                .filter(|p| p.contains("room 1 "))
                .count();
        }
        let g = contacts(toggled.sweep().unwrap(), same, same_object);
        let r = if out { &mut without } else { &mut always };
        assert_eq!(
            g,
            contacts(r.sweep().unwrap(), same, same_object),
            "frame {k}: sweep"
        );
        let other = if out { &mut always } else { &mut without };
        other.sweep().unwrap();
    }
    assert!(
        wall_contacts > 20,
        "the wall met {wall_contacts} triangles while out"
    );
}

#[test]
fn unknown_handles_are_refused() {
    let scene = Scene::new();
    let mut w = scene.world(1, true);
    assert!(matches!(
        w.set_character_active(CharacterHandle(1), false),
        Err(WorldError::UnknownCharacter(CharacterHandle(1)))
    ));
    assert!(matches!(
        w.object_is_active(ObjectHandle(3)),
        Err(WorldError::UnknownObject(ObjectHandle(3)))
    ));
    assert!(matches!(
        w.set_room_active(RoomHandle(1), false),
        Err(WorldError::UnknownRoom(RoomHandle(1)))
    ));
    assert!(w.character_is_active(CharacterHandle(0)).unwrap());
    assert!(w.room_is_active(RoomHandle(0)).unwrap());
}
