//! Narrow-phase and traversal kernels, nanoseconds per test: our two
//! triangle-triangle tests (the Tropp test the paper names, §3, and the
//! edge-crossing test), the exact oracle, parry3d's test in f32 and f64, the
//! sphere-sphere test and the plane-sphere test (§5), plain and prepared. Inputs: 4,096 pairs of 1–4 cm triangles with a corner in a
//! common 1 cm box (and as many sphere pairs), from fixed seeds; the bench
//! prints how many triangle pairs intersect (a fair share of each answer, so
//! branches are not predictable). Throughput is per test.
//!
//! `cargo bench --bench kernels`

use std::hint::black_box;

use cornertree::geometry::exact::triangles_intersect_exact;
use cornertree::geometry::plane_sphere::{TrianglePlane, sphere_meets_plane};
use cornertree::geometry::{Point, Sphere, Triangle, Vector, edge_crossing, tropp};
use cornertree_workbench::truth::parry_reference::{
    parry_f64_triangles_intersect, parry_triangle, parry_triangles_intersect,
};
use criterion::measurement::WallTime;
use criterion::{BenchmarkGroup, Criterion, Throughput, criterion_group, criterion_main};
use parry3d::shape::Triangle as ParryTriangle;
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const PAIRS: usize = 4096;

fn point(rng: &mut SmallRng, extent: f32) -> Point {
    Point::new(
        rng.random_range(0.0..extent),
        rng.random_range(0.0..extent),
        rng.random_range(0.0..extent),
    )
}

fn triangle(rng: &mut SmallRng) -> Triangle {
    let a = point(rng, 0.01);
    let size = rng.random_range(0.01..0.04);
    let mut corner = || {
        let d = Vector::new(
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
            rng.random_range(-1.0..1.0),
        );
        a + d.normalize() * size
    };
    Triangle::new(a, corner(), corner())
}

fn triangle_pairs(seed: u64) -> Vec<(Triangle, Triangle)> {
    let mut rng = SmallRng::seed_from_u64(seed);
    (0..PAIRS)
        .map(|_| (triangle(&mut rng), triangle(&mut rng)))
        .collect()
}

fn kernels(c: &mut Criterion) {
    let pairs = triangle_pairs(7);
    let hits = pairs
        .iter()
        .filter(|(a, b)| triangles_intersect_exact(a, b))
        .count();
    eprintln!(
        "kernels: {hits} of {PAIRS} triangle pairs intersect ({:.0}%)",
        100.0 * hits as f64 / PAIRS as f64
    );
    let parry_pairs: Vec<(ParryTriangle, ParryTriangle)> = pairs
        .iter()
        .map(|(a, b)| (parry_triangle(a), parry_triangle(b)))
        .collect();

    let mut g = c.benchmark_group("narrow_phase");
    g.throughput(Throughput::Elements(PAIRS as u64));
    bench_test(&mut g, "tri-tri Tropp", &pairs, |(x, y)| {
        tropp::triangles_intersect(x, y)
    });
    bench_test(&mut g, "tri-tri edge crossing", &pairs, |(x, y)| {
        edge_crossing::triangles_intersect(x, y)
    });
    bench_test(&mut g, "tri-tri exact oracle", &pairs, |(x, y)| {
        triangles_intersect_exact(x, y)
    });
    bench_test(&mut g, "tri-tri parry3d f32", &parry_pairs, |(x, y)| {
        parry_triangles_intersect(x, y)
    });
    bench_test(&mut g, "tri-tri parry3d-f64", &parry_pairs, |(x, y)| {
        parry_f64_triangles_intersect(x, y)
    });

    let mut rng = SmallRng::seed_from_u64(11);
    let spheres: Vec<(Sphere, Sphere)> = (0..PAIRS)
        .map(|_| {
            let mut s = || Sphere::new(point(&mut rng, 0.1), rng.random_range(0.005..0.03));
            (s(), s())
        })
        .collect();
    bench_test(&mut g, "sphere-sphere", &spheres, |(x, y)| x.overlaps(y));
    let plane_sphere: Vec<(Sphere, Triangle)> = spheres
        .iter()
        .zip(&pairs)
        .map(|((s, _), (t, _))| (*s, *t))
        .collect();
    bench_test(&mut g, "plane-sphere", &plane_sphere, |(s, t)| {
        sphere_meets_plane(s, t)
    });
    let prepared: Vec<(Sphere, TrianglePlane)> = plane_sphere
        .iter()
        .map(|(s, t)| (*s, TrianglePlane::new(t)))
        .collect();
    bench_test(&mut g, "plane-sphere prepared", &prepared, |(s, p)| {
        p.meets(s)
    });
    g.finish();
}

/// Times `test` over every input of `inputs` (one iteration: all of them).
fn bench_test<T>(
    g: &mut BenchmarkGroup<'_, WallTime>,
    name: &str,
    inputs: &[T],
    test: impl Fn(&T) -> bool,
) {
    g.bench_function(name, |b| {
        b.iter(|| inputs.iter().filter(|x| test(black_box(x))).count())
    });
}

criterion_group!(benches, kernels);
criterion_main!(benches);
