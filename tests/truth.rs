//! Ground truth (`cornertree_workbench::truth`): parry's answer against brute force with
//! the exact oracle, the BVH refit across poses, accuracy arithmetic and the
//! classification of disagreements. Counts are printed
//! (`cargo test --test truth -- --nocapture`).

mod common;

use common::{soup, uv_sphere};
use cornertree::geometry::exact::{Contact, classify};
use cornertree::geometry::{Point, Triangle, Vector};
use cornertree::mesh::{TriMesh, TriangleId};
use cornertree_workbench::truth::disagreement::{
    classify_pair, compare, degeneracy, differences, separation_depth,
};
use cornertree_workbench::truth::parry_reference::{parry_triangle, parry_triangles_intersect};
use cornertree_workbench::truth::{
    Accuracy, AccuracyTotals, FrameAccuracy, Kind, ParryReference, Tolerances, TruthError,
    brute_force_pairs, triangle_distance,
};
use parry3d::math::Pose;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// What a comparison of parry's pairs with brute force found.
#[derive(Default, Debug)]
struct Tally {
    frames: usize,
    exact_pairs: usize,
    parry_pairs: usize,
    candidates: usize,
    /// Differences reported by parry only, and by the exact oracle only.
    parry_only: usize,
    exact_only: usize,
    /// Differences the exact oracle calls `Touching`.
    exact_touching: usize,
    /// Other differences within the touching tolerance (near misses and
    /// shallow overlaps), and the largest distance or depth among them.
    near: usize,
    worst_near: f64,
    near_degenerate: usize,
    /// Clear disagreements, and the largest distance or depth among them.
    true_error: usize,
    worst_error: f64,
}

impl Tally {
    fn differences(&self) -> usize {
        self.parry_only + self.exact_only
    }

    fn print(&self, name: &str) {
        println!(
            "{name}: {} frames, {} exact pairs, {} parry pairs, {} candidates; \
             differences: {} parry only, {} exact only = {} exact-touching \
             + {} within tolerance (max {:.2e}) + {} near-degenerate \
             + {} true errors (max {:.2e})",
            self.frames,
            self.exact_pairs,
            self.parry_pairs,
            self.candidates,
            self.parry_only,
            self.exact_only,
            self.exact_touching,
            self.near,
            self.worst_near,
            self.near_degenerate,
            self.true_error,
            self.worst_error
        );
    }
}

/// Checks one posed frame. parry's BVH with the exact narrow phase must
/// equal brute force exactly (the refit BVH loses no pair); parry's own
/// pairs are compared with brute force and every difference is classified
/// at the scene's default tolerance and tallied.
fn check_frame(
    reference: &mut ParryReference,
    positions: &[Point],
    indices: &[[u32; 3]],
    env: &TriMesh,
    tally: &mut Tally,
) {
    let tol = Tolerances::for_scale(env.size() as f64);
    reference.update(positions).unwrap();
    let want = brute_force_pairs(positions, indices, env);
    let mut exact = Vec::new();
    reference.exact_pairs(&mut exact);
    assert_eq!(exact, want, "parry's BVH with the exact test");
    let mut got = Vec::new();
    reference.pairs(&mut got);
    assert!(got.windows(2).all(|w| w[0] < w[1]), "sorted and distinct");
    assert!(reference.candidates() >= got.len());
    assert!(reference.candidates() <= indices.len() * env.triangle_count());
    let (mut only_parry, mut only_exact) = (Vec::new(), Vec::new());
    differences(&got, &want, &mut only_parry, &mut only_exact);
    tally.parry_only += only_parry.len();
    tally.exact_only += only_exact.len();
    for &(c, e) in only_parry.iter().chain(&only_exact) {
        let [a, b, d] = indices[c as usize].map(|i| positions[i as usize]);
        let tc = Triangle::new(a, b, d);
        let te = env.triangle(TriangleId(e));
        let contact = classify(&tc, &te);
        let size = match contact {
            Contact::Disjoint => triangle_distance(&tc, &te),
            _ => separation_depth(&tc, &te),
        };
        match (classify_pair(&tc, &te, &tol), contact) {
            (Kind::Touching, Contact::Touching) => tally.exact_touching += 1,
            (Kind::Touching, _) => {
                tally.near += 1;
                tally.worst_near = tally.worst_near.max(size);
            }
            (Kind::NearDegenerate, _) => tally.near_degenerate += 1,
            (Kind::TrueError, _) => {
                tally.true_error += 1;
                tally.worst_error = tally.worst_error.max(size);
                println!(
                    "  true error ({c}, {e}): parry {}, exact {contact:?}, distance or depth {size:.2e}",
                    only_parry.contains(&(c, e))
                );
            }
        }
    }
    tally.frames += 1;
    tally.exact_pairs += want.len();
    tally.parry_pairs += got.len();
    tally.candidates += reference.candidates();
}

/// Random inputs: parry's differences from the exact answer must be rare.
fn assert_few_differences(name: &str, t: &Tally) {
    t.print(name);
    assert!(t.exact_pairs > 0, "{name}: the test must see contacts");
    assert!(
        t.differences() * 100 <= t.exact_pairs,
        "{name}: differences are more than 1% of pairs"
    );
}

/// Random soups compared, and frames of the sphere moving through a soup.
const SOUPS: u64 = 20;
const SPHERE_FRAMES: usize = 30;

#[test]
fn soup_against_soup_matches_exact_brute_force() {
    let mut tally = Tally::default();
    for seed in 0..SOUPS {
        let character = soup(1000 + seed, 200, 1.0, 0.12);
        let env = soup(2000 + seed, 300, 1.0, 0.12);
        let mut reference = ParryReference::new(&env, character.indices()).unwrap();
        check_frame(
            &mut reference,
            character.positions(),
            character.indices(),
            &env,
            &mut tally,
        );
    }
    assert_few_differences("soup vs soup", &tally);
}

/// The sphere's vertices at frame `k`: moved along x through the soup and
/// squashed along z by a frame-dependent factor (a non-rigid pose, so the
/// refit boxes change shape, not just place).
fn sphere_pose(rest: &[Point], centre: Point, k: usize) -> Vec<Point> {
    let squash = 1.0 - 0.04 * (k % 5) as f32;
    let offset = Vector::new(0.06 * k as f32, 0.01 * k as f32, 0.0);
    rest.iter()
        .map(|p| {
            let d = p - centre;
            centre + Vector::new(d.x, d.y, d.z * squash) + offset
        })
        .collect()
}

#[test]
fn sphere_moving_through_soup_matches_exact_brute_force() {
    let env = soup(7, 500, 2.0, 0.15);
    let centre = Point::new(0.1, 0.8, 1.0);
    let sphere = uv_sphere(centre, 0.4, 12, 20);
    let mut reference = ParryReference::new(&env, sphere.indices()).unwrap();
    let mut tally = Tally::default();
    for k in 0..SPHERE_FRAMES {
        let pose = sphere_pose(sphere.positions(), centre, k);
        check_frame(&mut reference, &pose, sphere.indices(), &env, &mut tally);
    }
    assert_few_differences("sphere through soup", &tally);
}

/// A floor of `n × n` squares over [0, 1]², two triangles each, at z = 0.
fn floor_grid(n: u32) -> TriMesh {
    let step = 1.0 / n as f32;
    let mut p = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            p.push(Point::new(i as f32 * step, j as f32 * step, 0.0));
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut t = Vec::new();
    for j in 0..n {
        for i in 0..n {
            t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    TriMesh::new(p, t).unwrap()
}

#[test]
fn exact_contacts_on_a_floor() {
    // Contacts built to be exact in f32: a sphere of radius 1/4 whose south
    // pole rests on the floor (at a grid vertex, on a grid edge, inside a
    // triangle), sinks into it or hovers above it by 2^-22, and a flat
    // character lying in the floor's plane (coplanar overlaps).
    let env = floor_grid(8);
    let r = 0.25f32;
    let sphere = uv_sphere(Point::new(0.0, 0.0, r), r, 10, 16);
    let mut reference = ParryReference::new(&env, sphere.indices()).unwrap();
    let mut tally = Tally::default();
    let h = 1.0 / (1u32 << 22) as f32;
    for (x, y) in [(0.5, 0.5), (0.5, 0.3), (0.3, 0.6)] {
        for dz in [0.0, -h, h] {
            let pose: Vec<Point> = sphere
                .positions()
                .iter()
                .map(|p| p + Vector::new(x, y, dz))
                .collect();
            check_frame(&mut reference, &pose, sphere.indices(), &env, &mut tally);
        }
    }
    tally.print("sphere on floor");
    assert!(tally.exact_pairs > 0);
    assert_eq!(tally.differences(), tally.exact_touching + tally.near);

    let flat = soup(5, 60, 1.0, 0.1);
    let pose: Vec<Point> = flat
        .positions()
        .iter()
        .map(|p| Point::new(p.x, p.y, 0.0))
        .collect();
    let mut reference = ParryReference::new(&env, flat.indices()).unwrap();
    let mut coplanar = Tally::default();
    check_frame(&mut reference, &pose, flat.indices(), &env, &mut coplanar);
    coplanar.print("coplanar on floor");
    assert!(coplanar.exact_pairs > 0);
    assert_eq!(
        coplanar.differences(),
        coplanar.exact_touching + coplanar.near
    );
}

#[test]
fn refit_follows_the_character_out_of_and_back_into_contact() {
    let env = soup(11, 300, 1.0, 0.1);
    let centre = Point::new(0.5, 0.5, 0.5);
    let sphere = uv_sphere(centre, 0.3, 8, 12);
    let indices = sphere.indices();
    let mut reference = ParryReference::new(&env, indices).unwrap();
    let mut pairs = Vec::new();
    let mut tally = Tally::default();

    // Built in contact, moved far away (a stale BVH would still report the
    // first pose's pairs), then back to a different place in the soup.
    check_frame(
        &mut reference,
        sphere.positions(),
        indices,
        &env,
        &mut tally,
    );
    let first = tally.parry_pairs;
    assert!(first > 0);

    let away: Vec<Point> = sphere
        .positions()
        .iter()
        .map(|p| p + Vector::new(10.0, 0.0, 0.0))
        .collect();
    reference.update(&away).unwrap();
    reference.pairs(&mut pairs);
    assert!(pairs.is_empty(), "{} pairs after moving away", pairs.len());
    assert!(reference.candidates() <= 4, "{}", reference.candidates());

    let back: Vec<Point> = sphere
        .positions()
        .iter()
        .map(|p| p + Vector::new(0.0, 0.25, -0.2))
        .collect();
    check_frame(&mut reference, &back, indices, &env, &mut tally);
    assert!(tally.parry_pairs > first);
    assert_few_differences("out and back", &tally);
}

#[test]
fn update_rejects_bad_poses() {
    let env = soup(3, 10, 1.0, 0.1);
    let character = soup(4, 5, 1.0, 0.1);
    let p = character.positions();
    assert_eq!(
        ParryReference::new(&env, &[]).unwrap_err(),
        TruthError::NoTriangles("character")
    );
    let mut reference = ParryReference::new(&env, character.indices()).unwrap();
    let mut pairs = vec![(9, 9)];
    reference.pairs(&mut pairs);
    assert!(pairs.is_empty(), "no pairs before the first pose");
    assert_eq!(
        reference.update(&p[..14]).unwrap_err(),
        TruthError::IndexOutOfRange {
            triangle: 4,
            index: 14,
            vertex_count: 14
        }
    );
    let mut nan = p.to_vec();
    nan[3].y = f32::NAN;
    assert_eq!(
        reference.update(&nan).unwrap_err(),
        TruthError::NonFinitePosition(3)
    );
    reference.update(p).unwrap();
    assert_eq!(
        reference.update(&p[..14]).unwrap_err(),
        TruthError::VertexCountChanged {
            expected: 15,
            got: 14
        }
    );
}

#[test]
fn parry_calls_agree_with_our_helpers() {
    let mut rng = SmallRng::seed_from_u64(0x7247);
    let point = |rng: &mut SmallRng| {
        Point::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        )
    };
    let (mut disjoint, mut meeting, mut gjk_wrong, mut worst) = (0, 0, 0, 0.0f64);
    for _ in 0..2000 {
        let t1 = Triangle::new(point(&mut rng), point(&mut rng), point(&mut rng));
        let t2 = Triangle::new(point(&mut rng), point(&mut rng), point(&mut rng));
        let (p1, p2) = (parry_triangle(&t1), parry_triangle(&t2));
        // The dispatcher answers a triangle pair.
        let hit = parry3d::query::intersection_test(&Pose::IDENTITY, &p1, &Pose::IDENTITY, &p2)
            .expect("triangle pairs are supported");
        assert_eq!(hit.intersecting, parry_triangles_intersect(&p1, &p2));
        let ours = triangle_distance(&t1, &t2);
        let theirs = parry3d::query::distance(&Pose::IDENTITY, &p1, &Pose::IDENTITY, &p2)
            .expect("triangle pairs are supported")
            .distance as f64;
        // parry's GJK returns points on the triangles, so its distance is an
        // upper bound, converged to a relative sqrt(10 f32::EPSILON) ≈ 1.1e-3.
        let err = theirs - ours;
        worst = worst.max(err.abs());
        assert!(
            err >= -1e-6 && err <= 1.1e-3 * theirs + 1e-6,
            "ours {ours:e} parry {theirs:e}"
        );
        let meets = classify(&t1, &t2) != Contact::Disjoint;
        if meets {
            meeting += 1;
            assert_eq!(ours, 0.0);
        } else {
            disjoint += 1;
            assert!(ours > 0.0);
        }
        // GJK against the exact oracle, away from contact.
        let clear = if meets {
            separation_depth(&t1, &t2)
        } else {
            ours
        };
        if clear > 1e-4 && hit.intersecting != meets {
            gjk_wrong += 1;
        }
    }
    println!(
        "distance check: {disjoint} disjoint, {meeting} meeting pairs; \
         worst |ours - parry distance| {worst:.2e}; GJK wrong by more than 1e-4: {gjk_wrong}"
    );
    assert!(disjoint > 100 && meeting > 100);
    assert!(gjk_wrong <= 2);
}

fn acc(tp: u64, fp: u64, fn_: u64) -> Accuracy {
    Accuracy { tp, fp, fn_ }
}

#[test]
fn accuracy_counts_pairs_triangles_and_frames() {
    // Truth: triangles 1 and 3 in contact (1 twice). Reported: one true pair
    // of triangle 1, a wrong partner for triangle 3, and triangle 5 falsely.
    let truth = [(1, 10), (1, 11), (3, 30)];
    let reported = [(1, 11), (3, 31), (5, 50)];
    let f = FrameAccuracy::compare(&reported, &truth);
    assert_eq!(f.pairs, acc(1, 2, 2));
    assert_eq!(f.triangles, acc(2, 1, 0));
    assert_eq!(f.frame, acc(1, 0, 0));
    assert_eq!(f.pairs.precision(), 1.0 / 3.0);
    assert_eq!(f.pairs.recall(), 1.0 / 3.0);
    assert_eq!(f.triangles.precision(), 2.0 / 3.0);
    assert_eq!(f.triangles.recall(), 1.0);

    // Order and repeats do not matter.
    let shuffled = [(5, 50), (3, 31), (1, 11), (5, 50)];
    assert_eq!(FrameAccuracy::compare(&shuffled, &truth), f);

    // Empty cases: nothing reported, nothing true, neither.
    let missed = FrameAccuracy::compare(&[], &truth);
    assert_eq!(missed.pairs, acc(0, 0, 3));
    assert_eq!(missed.triangles, acc(0, 0, 2));
    assert_eq!(missed.frame, acc(0, 0, 1));
    assert_eq!(missed.pairs.precision(), 1.0);
    assert_eq!(missed.pairs.recall(), 0.0);
    let ghost = FrameAccuracy::compare(&reported, &[]);
    assert_eq!(ghost.pairs, acc(0, 3, 0));
    assert_eq!(ghost.triangles, acc(0, 3, 0));
    assert_eq!(ghost.frame, acc(0, 1, 0));
    assert_eq!(ghost.pairs.precision(), 0.0);
    assert_eq!(ghost.pairs.recall(), 1.0);
    let quiet = FrameAccuracy::compare(&[], &[]);
    assert_eq!(quiet, FrameAccuracy::default());
    assert_eq!(quiet.frame.precision(), 1.0);
    assert_eq!(quiet.frame.recall(), 1.0);

    let mut totals = AccuracyTotals::default();
    for frame in [&f, &missed, &ghost, &quiet] {
        totals.add(frame);
    }
    assert_eq!(totals.frames, 4);
    assert_eq!(totals.pairs, acc(1, 5, 5));
    assert_eq!(totals.triangles, acc(2, 4, 2));
    assert_eq!(totals.frames_with_contact, acc(1, 1, 1));
    assert_eq!(totals.frames_with_contact.precision(), 0.5);

    let json = serde_json::to_value(totals).unwrap();
    assert_eq!(json["pairs"]["fn"], 5);
    assert_eq!(json["frames_with_contact"]["tp"], 1);
}

fn p(x: f32, y: f32, z: f32) -> Point {
    Point::new(x, y, z)
}

fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
    Triangle::new(
        p(a[0], a[1], a[2]),
        p(b[0], b[1], b[2]),
        p(c[0], c[1], c[2]),
    )
}

#[test]
fn disagreements_are_classified() {
    let tol = Tolerances::for_scale(10.0);
    assert!((tol.touching - 1e-5).abs() < 1e-18);
    let floor = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);

    // Clearly apart: 0.5 above the floor.
    let above = tri([0.1, 0.1, 0.5], [0.6, 0.1, 0.5], [0.1, 0.6, 0.9]);
    assert_eq!(classify(&floor, &above), Contact::Disjoint);
    assert_eq!(triangle_distance(&floor, &above), 0.5);
    assert_eq!(classify_pair(&floor, &above, &tol), Kind::TrueError);

    // Coplanar, sharing the edge from (1,0,0) to (0,1,0): exactly touching.
    let neighbour = tri([1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]);
    assert_eq!(classify(&floor, &neighbour), Contact::Touching);
    assert_eq!(classify_pair(&floor, &neighbour, &tol), Kind::Touching);

    // A hair above the floor (2^-20 ≈ 1e-6 < 1e-5): touching by distance.
    let h = 1.0 / (1u32 << 20) as f32;
    let hovering = tri([0.1, 0.1, h], [0.6, 0.1, h], [0.1, 0.6, 0.5]);
    assert_eq!(classify(&floor, &hovering), Contact::Disjoint);
    assert_eq!(triangle_distance(&floor, &hovering), h as f64);
    assert_eq!(classify_pair(&floor, &hovering, &tol), Kind::Touching);

    // Piercing the floor by a hair: touching by depth; by 0.25: a true error
    // if missed.
    let grazing = tri([0.1, 0.1, -h], [0.6, 0.1, -h], [0.1, 0.6, 0.5]);
    assert_eq!(classify(&floor, &grazing), Contact::Overlapping);
    assert!(separation_depth(&floor, &grazing) <= h as f64 * 1.000001);
    assert_eq!(classify_pair(&floor, &grazing, &tol), Kind::Touching);
    let piercing = tri([0.2, 0.2, -0.25], [0.6, 0.1, 0.5], [0.1, 0.6, 0.5]);
    assert_eq!(classify(&floor, &piercing), Contact::Overlapping);
    assert_eq!(separation_depth(&floor, &piercing), 0.25);
    assert_eq!(classify_pair(&floor, &piercing, &tol), Kind::TrueError);

    // Coplanar overlap with positive area: depth 0, touching.
    let overlapping = tri([0.2, 0.2, 0.0], [2.0, 0.2, 0.0], [0.2, 2.0, 0.0]);
    assert_eq!(classify(&floor, &overlapping), Contact::Overlapping);
    assert_eq!(classify_pair(&floor, &overlapping, &tol), Kind::Touching);

    // Zero-area (collinear corners) and nearly so, away from the floor.
    let needle = tri([0.0, 0.0, 1.0], [1.0, 1.0, 1.0], [2.0, 2.0, 1.0]);
    assert_eq!(degeneracy(&needle), 0.0);
    assert_eq!(classify_pair(&floor, &needle, &tol), Kind::NearDegenerate);
    assert_eq!(classify_pair(&needle, &floor, &tol), Kind::NearDegenerate);
    let sliver = tri([0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [2.0, 1e-8, 1.0]);
    assert!(degeneracy(&sliver) < Tolerances::DEGENERATE_RATIO);
    assert_eq!(classify_pair(&floor, &sliver, &tol), Kind::NearDegenerate);
    assert!(degeneracy(&floor) > 0.2);
}

#[test]
fn compare_lists_both_directions() {
    // Environment: the floor triangle (0) and one far away (1).
    let env = TriMesh::new(
        vec![
            p(0.0, 0.0, 0.0),
            p(1.0, 0.0, 0.0),
            p(0.0, 1.0, 0.0),
            p(5.0, 5.0, 5.0),
            p(6.0, 5.0, 5.0),
            p(5.0, 6.0, 5.0),
        ],
        vec![[0, 1, 2], [3, 4, 5]],
    )
    .unwrap();
    // Character: 0 pierces the floor, 1 shares its edge, 2 is a needle.
    let character = vec![
        p(0.2, 0.2, -0.25),
        p(0.6, 0.1, 0.5),
        p(0.1, 0.6, 0.5),
        p(1.0, 0.0, 0.0),
        p(1.0, 1.0, 0.0),
        p(0.0, 1.0, 0.0),
        p(3.0, 3.0, 3.0),
        p(4.0, 4.0, 4.0),
        p(5.0, 5.0, 5.0),
    ];
    let indices = [[0, 1, 2], [3, 4, 5], [6, 7, 8]];
    let truth = brute_force_pairs(&character, &indices, &env);
    assert_eq!(truth, vec![(0, 0), (1, 0), (2, 1)]);

    // The method misses the piercing and the needle's touch, and reports
    // the piercing triangle against the far one.
    let method = [(0, 1), (1, 0)];
    let tol = Tolerances::for_scale(env.size() as f64);
    let d = compare(&method, &truth, &character, &indices, &env, &tol).unwrap();
    assert_eq!(d.extra.items, vec![(0, 1, Kind::TrueError)]);
    assert_eq!(
        d.missed.items,
        vec![(0, 0, Kind::TrueError), (2, 1, Kind::Touching)]
    );
    assert_eq!(
        (
            d.missed.touching,
            d.missed.near_degenerate,
            d.missed.true_error
        ),
        (1, 0, 1)
    );
    assert_eq!(
        compare(&[(3, 0)], &[], &character, &indices, &env, &tol).unwrap_err(),
        TruthError::PairOutOfRange {
            character: 3,
            environment: 0
        }
    );
    assert!(compare(&[(0, 2)], &[], &character, &indices, &env, &tol).is_err());
}
