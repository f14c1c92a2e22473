//! Operations paid by the kernels, counted with `geometry::counted::Counted`:
//! the count follows the work done (early exits pay less), and the counting
//! instantiation answers exactly as the one the pipeline runs.

use cornertree::geometry::counted::{Counted, count_operations};
use cornertree::geometry::plane_sphere::{
    TrianglePlane, sphere_meets_plane, sphere_meets_plane_as,
};
use cornertree::geometry::{Point, Sphere, Triangle, edge_crossing, tropp};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
    Triangle::new(Point::from(a), Point::from(b), Point::from(c))
}

fn base() -> Triangle {
    tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
}

fn paid_tropp(a: &Triangle, b: &Triangle) -> (bool, u64) {
    count_operations(|| tropp::triangles_intersect_as::<Counted>(a, b))
}

fn paid_edge_crossing(a: &Triangle, b: &Triangle) -> (bool, u64) {
    count_operations(|| edge_crossing::triangles_intersect_as::<Counted>(a, b))
}

#[test]
fn early_exits_pay_less() {
    let above = tri([0.2, 0.2, 0.5], [0.6, 0.2, 1.0], [0.2, 0.6, 0.7]);
    let pierce = tri([0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.5, 2.0, 0.0]);
    let beside = tri([2.0, 2.0, -1.0], [2.0, 2.0, 1.0], [3.0, 1.0, 0.0]);

    let (hit, rejected) = paid_tropp(&base(), &above);
    assert!(!hit);
    let (hit, full) = paid_tropp(&base(), &pierce);
    assert!(hit);
    let (hit, missed) = paid_tropp(&base(), &beside);
    assert!(!hit);
    // The plane-side exit skips the segment stage, whatever the answer after it.
    assert!(
        rejected < full,
        "Tropp: rejected {rejected}, piercing {full}"
    );
    assert!(
        rejected < missed,
        "Tropp: rejected {rejected}, beside {missed}"
    );

    let (_, rejected) = paid_edge_crossing(&base(), &above);
    let (_, full) = paid_edge_crossing(&base(), &pierce);
    assert!(
        rejected < full,
        "edge crossing: rejected {rejected}, full {full}"
    );
}

#[test]
fn tropp_looks_from_the_other_side_only_when_needed() {
    // Each crosses the other's plane and misses it. The base's corners are
    // off the plane x + y = 0.8 of `apart`, so one section decides; two
    // corners lie on the plane x + y = 1 of `beside`, so Tropp's test also
    // solves the base's section of that plane.
    let apart = tri([1.4, -0.6, -1.0], [1.4, -0.6, 1.0], [1.6, -0.8, 0.0]);
    let beside = tri([1.25, -0.25, -1.0], [1.25, -0.25, 1.0], [1.75, -0.75, 0.0]);
    let (hit, one) = paid_tropp(&base(), &apart);
    assert!(!hit);
    let (hit, two) = paid_tropp(&base(), &beside);
    assert!(!hit);
    assert!(one < two, "one section {one}, two sections {two}");
}

#[test]
fn plane_sphere_pays_less_on_a_degenerate_triangle() {
    let s = Sphere::new(Point::new(0.2, 0.2, 0.5), 1.0);
    let segment = tri([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [2.0, 2.0, 2.0]);
    let (hit, normal) = count_operations(|| sphere_meets_plane_as::<Counted>(&s, &base()));
    assert!(hit);
    let (hit, degenerate) = count_operations(|| sphere_meets_plane_as::<Counted>(&s, &segment));
    assert!(!hit);
    assert!(
        degenerate < normal,
        "degenerate {degenerate}, normal {normal}"
    );

    // Prepared: the plane's cost is paid once, outside the test.
    let (plane, prepare) = count_operations(|| TrianglePlane::<Counted>::new(&base()));
    let (_, meets) = count_operations(|| plane.meets(&s));
    assert_eq!(prepare + meets, normal);
    let flat = TrianglePlane::<Counted>::new(&segment);
    let (_, meets_degenerate) = count_operations(|| flat.meets(&s));
    assert!(meets_degenerate < meets);
}

#[test]
fn sphere_sphere_pays_its_hand_count() {
    // Three subtractions, three multiplications and two additions for the
    // squared distance, one addition and one multiplication for the squared
    // sum of radii (the paper's 10), and one comparison.
    let (a, b) = (
        Sphere::new(Point::new(0.0, 0.0, 0.0), 1.0),
        Sphere::new(Point::new(3.0, 0.0, 0.0), 1.0),
    );
    let (hit, n) = count_operations(|| a.overlaps_as::<Counted>(&b));
    assert!(!hit);
    assert_eq!(n, 11);
}

fn point(rng: &mut SmallRng, extent: f32) -> Point {
    Point::new(
        rng.random_range(-extent..extent),
        rng.random_range(-extent..extent),
        rng.random_range(-extent..extent),
    )
}

#[test]
fn counting_instantiation_answers_like_the_pipelines() {
    let mut rng = SmallRng::seed_from_u64(0xC0_07ED);
    let mut hits = [0usize; 5];
    const N: usize = 20_000;
    for i in 0..N {
        // Small grids make touching, coplanar and degenerate pairs common.
        let q = |rng: &mut SmallRng| {
            if i % 2 == 0 {
                point(rng, 1.0)
            } else {
                Point::new(
                    rng.random_range(-2..=2) as f32,
                    rng.random_range(-2..=2) as f32,
                    rng.random_range(-2..=2) as f32,
                )
            }
        };
        let a = Triangle::new(q(&mut rng), q(&mut rng), q(&mut rng));
        let b = Triangle::new(q(&mut rng), q(&mut rng), q(&mut rng));
        let t = tropp::triangles_intersect(&a, &b);
        assert_eq!(t, tropp::triangles_intersect_as::<Counted>(&a, &b));
        let e = edge_crossing::triangles_intersect(&a, &b);
        assert_eq!(e, edge_crossing::triangles_intersect_as::<Counted>(&a, &b));

        let s = Sphere::new(q(&mut rng), rng.random_range(0.0..1.5));
        let r = Sphere::new(q(&mut rng), rng.random_range(0.0..1.5));
        let ss = s.overlaps(&r);
        assert_eq!(ss, s.overlaps_as::<Counted>(&r));
        let ps = sphere_meets_plane(&s, &a);
        assert_eq!(ps, sphere_meets_plane_as::<Counted>(&s, &a));
        assert_eq!(ps, TrianglePlane::<Counted>::new(&a).meets(&s));
        for (h, x) in hits.iter_mut().zip([t, e, ss, ps, !ps]) {
            *h += x as usize;
        }
    }
    // Both answers occur often for every kernel.
    assert!(
        hits.iter().all(|&h| h > N / 20 && h < N - N / 20),
        "{hits:?}"
    );
}
