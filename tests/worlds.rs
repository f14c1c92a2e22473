//! Worlds (several characters, moving objects, characters against
//! themselves) on the library frame loop:
//! the exact methods report exactly the reference pairs of every kind on
//! every frame of the shipped worlds; the outcome does not depend on the
//! number of threads; bad worlds fail in one line naming the field.

use std::path::Path;

use cornertree::pipeline::Method;
use cornertree::world::PairKind;
use cornertree_workbench::scenario::{Resolved, Scenario, open_scenario};
use cornertree_workbench::session::Session;
use cornertree_workbench::truth::Truth;

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

/// Plays `r` through its methods, checking every frame's pairs of every
/// kind against the truth (`name` in messages); calls `each` with every
/// frame's truth and each method's contacts. Returns the frames played.
fn exact_pairs_every_frame(
    r: Resolved,
    name: &str,
    mut each: impl FnMut(&Truth, &cornertree::world::StepContacts),
) -> usize {
    let mut world = Session::new(r, 0).unwrap();
    let mut truth = Truth::new(&world.scene).unwrap();
    let frames = world.frames();
    for k in 0..frames {
        world.pose(k);
        world.skin_all();
        truth
            .update(&world.scene, &world.buffers, &world.object_poses)
            .unwrap();
        world.detect_all();
        for (m, method) in world.methods().enumerate() {
            let o = world.contacts(m);
            assert_eq!(
                o.room_pairs, truth.exact.environment,
                "{name} frame {k} {method} room"
            );
            assert_eq!(
                o.object_pairs, truth.exact.objects,
                "{name} frame {k} {method} objects"
            );
            assert_eq!(
                o.character_pairs, truth.exact.characters,
                "{name} frame {k} {method} characters"
            );
            assert_eq!(
                o.self_pairs, truth.exact.self_contact,
                "{name} frame {k} {method} self"
            );
            each(&truth, o);
        }
    }
    frames
}

/// Plays `name` without de-duplication through the exact methods; checks
/// every frame against the truth and that `kind` has contacts in at least a
/// quarter of the frames.
fn exact_on_every_frame(name: &str, kind: PairKind) {
    let mut r = open_scenario(&root().join(format!("scenarios/{name}.toml"))).unwrap();
    r.dedup = false;
    r.methods = vec![
        Method::SphereDivision,
        Method::PrunedTriTri,
        Method::UndividedPrunedTriTri,
    ];
    let methods = r.methods.len();
    let mut with_contact = 0;
    let frames = exact_pairs_every_frame(r, name, |truth, _| {
        let exact_of_kind = match kind {
            PairKind::Environment => truth.exact.environment.len(),
            PairKind::Objects => truth.exact.objects.len(),
            PairKind::Characters => truth.exact.characters.len(),
            PairKind::SelfContact => truth.exact.self_contact.len(),
        };
        with_contact += usize::from(exact_of_kind > 0);
    });
    // Counted once per method.
    let with_contact = with_contact / methods;
    assert!(
        4 * with_contact >= frames,
        "{name}: {} contacts in {with_contact} of {frames} frames",
        kind.name()
    );
}

#[test]
fn handshake_exact_pairs_every_frame() {
    exact_on_every_frame("handshake", PairKind::Characters);
}

#[test]
fn door_exact_pairs_every_frame() {
    exact_on_every_frame("door", PairKind::Objects);
}

#[test]
fn crowd_exact_pairs_every_frame() {
    exact_on_every_frame("crowd", PairKind::Characters);
}

#[test]
fn self_contact_exact_pairs_every_frame() {
    exact_on_every_frame("self_contact", PairKind::SelfContact);
}

#[test]
fn inside_furniture_exact_pairs_every_frame() {
    exact_on_every_frame("inside_furniture", PairKind::Environment);
}

/// The shipped plazas hold a thousand instances of one source; shrunk to 12
/// (same spacing, same plaza rule), their exact methods' pairs equal the
/// truth's on four frames, and the packed one has at least 300 colliding
/// triangle pairs per character a frame between characters (counting each
/// pair for both its characters), the brushing one some but far fewer.
#[test]
fn shipped_plazas_exact_and_as_dense_as_they_say() {
    for (name, least, most) in [
        ("plaza_brushing", 1.0, 100.0),
        ("plaza_packed", 300.0, f64::MAX),
    ] {
        let path = root().join(format!("scenarios/{name}.toml"));
        let mut s = cornertree_workbench::scenario::load_scenario(&path).unwrap();
        assert_eq!(s.characters.len(), 1000, "{name}");
        let mut crowd = s.crowd.clone().unwrap();
        crowd.count = 12;
        s.set_crowd(crowd);
        s.frames = Some(4);
        s.dedup = false;
        let mut r = cornertree_workbench::scenario::resolve(&s, &root().join("scenarios")).unwrap();
        r.methods = vec![Method::UndividedPrunedTriTri];
        let mut pairs = 0;
        exact_pairs_every_frame(r, name, |_, o| pairs += o.character_pairs.len());
        // In the middle of a grid a character has two side neighbours; 12
        // characters stand in 5 columns (brushing) or 6 (packed); the edge
        // ones have one.
        let per_character = 2.0 * pairs as f64 / (12.0 * 4.0);
        assert!(
            (least..most).contains(&per_character),
            "{name}: {per_character:.1} colliding pairs per character a frame"
        );
    }
}

/// A plaza crowd of `count` humanoids of `vertices` vertices, `spacing`
/// apart, as scenario text.
fn plaza(count: usize, vertices: usize, spacing: f32, frames: usize) -> String {
    format!(
        "frames = {frames}\ndedup = false\n[environment]\nkind = \"plaza\"\n[crowd]\n\
         source = \"generated:humanoid?vertices={vertices}&seed=11\"\ncount = {count}\n\
         clip = \"walk\"\nspacing = [{spacing}, 1.0]\n"
    )
}

/// A packed plaza of 120 characters (over the broad phase's every-pair
/// threshold, so its sort and sweep is the one that runs; 1,500-vertex
/// humanoids to keep CI short, the shipped plazas have 10,000): the exact
/// methods' pairs of every kind equal the world truth's on every frame
/// played, and characters do touch.
#[test]
fn plaza_exact_pairs_every_frame() {
    let text = plaza(120, 1500, 0.45, 4);
    let s = Scenario::parse(&text, Path::new("plaza.toml")).unwrap();
    assert_eq!(s.characters.len(), 120);
    let mut r = cornertree_workbench::scenario::resolve(&s, Path::new(".")).unwrap();
    r.methods = vec![Method::PrunedTriTri, Method::UndividedPrunedTriTri];
    let mut touching = 0;
    exact_pairs_every_frame(r, "plaza", |truth, o| {
        touching += truth.exact.characters.len();
        // The sweep tested far fewer root pairs than every pair.
        assert!(
            o.broad_phase_tests < 120 * 119 / 2 / 4,
            "{}",
            o.broad_phase_tests
        );
    });
    assert!(
        touching > 1000,
        "{touching} character pairs in 4 frames, 2 methods"
    );
}

#[test]
fn bad_crowds_fail_in_one_line_naming_the_field() {
    let crowd = "[crowd]\nsource = \"generated:humanoid?vertices=3000\"\ncount = 4\n";
    let cases = [
        (format!("{ROOM}{ONE}{crowd}"), "crowd: give [crowd] alone"),
        (
            "[environment]\nkind = \"plaza\"\n".to_owned() + ONE,
            "environment.size: a plaza needs a size",
        ),
        (
            "[environment]\nkind = \"museum\"\nsize = [3, 4]\n".to_owned() + ONE,
            "environment.size: only for kind = \"plaza\"",
        ),
        (
            "[environment]\nkind = \"plaza\"\n".to_owned()
                + &crowd.replace("count = 4", "count = 0"),
            "crowd.count: must be a whole number from 1",
        ),
        (
            "[environment]\nkind = \"plaza\"\n".to_owned()
                + &crowd.replace("count = 4", "count = 4\nspacing = [0.5, -1]"),
            "crowd.spacing: must be metres from 0.05 to 100, not -1",
        ),
        (
            "[environment]\nkind = \"plaza\"\nsize = [20, 0]\n".to_owned() + crowd,
            "environment.size: must be positive metres",
        ),
    ];
    for (text, want) in cases {
        let e = parse_error(&text);
        assert!(e.starts_with("bad.toml:"), "{e}");
        assert!(e.contains(want), "wanted {want:?} in {e:?}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
}

#[test]
fn one_thread_and_two_give_the_same_outcome() {
    let mut r = open_scenario(&root().join("scenarios/crowd.toml")).unwrap();
    r.frames = 12;
    r.methods = vec![Method::PlaneSpherePruned, Method::PrunedTriTri];
    same_outcome_on_one_thread_and_two(r);
}

/// As above on a plaza of 120 characters: hundreds of passes a frame.
#[test]
fn one_thread_and_two_give_the_same_outcome_on_a_plaza() {
    let s = Scenario::parse(&plaza(120, 1500, 0.5, 3), Path::new("plaza.toml")).unwrap();
    let mut r = cornertree_workbench::scenario::resolve(&s, Path::new(".")).unwrap();
    r.methods = vec![Method::PlaneSpherePruned, Method::UndividedPrunedTriTri];
    same_outcome_on_one_thread_and_two(r);
}

fn same_outcome_on_one_thread_and_two(r: Resolved) {
    let mut one = Session::new(r.clone(), 1).unwrap();
    let mut two = Session::new(r, 2).unwrap();
    let mut character_pairs = 0;
    while let (Some(a), Some(b)) = (one.step(), two.step()) {
        assert_eq!(a, b);
        for (x, y) in one.worlds().iter().zip(two.worlds()) {
            let (x, y) = (x.contacts(), y.contacts());
            assert_eq!(x.room_pairs, y.room_pairs);
            assert_eq!(x.object_pairs, y.object_pairs);
            assert_eq!(x.character_pairs, y.character_pairs);
            for k in PairKind::ALL {
                let (cx, cy) = (x.by_kind.get(k), y.by_kind.get(k));
                // Refits and skinned vertices per kind too: a character's own
                // pass runs before its pairs, whichever thread runs what.
                assert_eq!(
                    (cx.sphere_sphere, cx.tri_tri, cx.plane_sphere, cx.pairs),
                    (cy.sphere_sphere, cy.tri_tri, cy.plane_sphere, cy.pairs)
                );
                assert_eq!(
                    (cx.refits, cx.skinned_vertices),
                    (cy.refits, cy.skinned_vertices),
                    "{k:?}"
                );
            }
            assert_eq!(x.total.refits, y.total.refits);
            assert_eq!(x.total.skinned_vertices, y.total.skinned_vertices);
            character_pairs += x.character_pairs.len();
        }
    }
    assert!(character_pairs > 0, "the frames compared have contacts");
}

fn parse_error(text: &str) -> String {
    Scenario::parse(text, Path::new("bad.toml"))
        .expect_err("a bad world")
        .to_string()
}

const ROOM: &str = "[environment]\nkind = \"living-room\"\n";
const ONE: &str = "[[characters]]\nname = \"a\"\nsource = \"generated:humanoid?vertices=3000\"\nplacement = { start = { translation = [1, 0, 1] } }\n";

#[test]
fn bad_worlds_fail_in_one_line_naming_the_field() {
    let cases = [
        (
            format!("{ROOM}{ONE}{ONE}"),
            "characters[1].name: two characters named \"a\"",
        ),
        (
            format!("{ROOM}{ONE}[[objects]]\nname = \"b\"\nkind = \"ball\"\n"),
            "objects[0].motion: no motion keys",
        ),
        (
            format!(
                "{ROOM}{ONE}[[objects]]\nname = \"b\"\nkind = \"ball\"\nmotion = {{ times = [0, 1, 0.5], positions = [[0,0,0],[1,0,0],[2,0,0]] }}\n"
            ),
            "objects[0].motion.times: keys out of time order: times[2] = 0.5 after times[1] = 1",
        ),
        (
            format!(
                "{ROOM}{ONE}[[objects]]\nname = \"b\"\nkind = \"sphere\"\nmotion = {{ times = [0], positions = [[0,0,0]] }}\n"
            ),
            "objects[0].kind: unknown object kind \"sphere\"",
        ),
        (
            format!(
                "{ROOM}{ONE}[[objects]]\nname = \"d\"\nkind = \"door\"\nmotion = {{ times = [0, 1], degrees = [0, 90], axis = [0, 0, 0] }}\n"
            ),
            "objects[0].motion.axis: a hinge axis of zero length",
        ),
    ];
    for (text, want) in cases {
        let e = parse_error(&text);
        assert!(e.starts_with("bad.toml:"), "{e}");
        assert!(e.contains(want), "wanted {want:?} in {e:?}");
        assert!(!e.contains('\n'), "one line: {e}");
    }
}
