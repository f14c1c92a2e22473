//! The broad phase between characters' root spheres: sort and sweep against
//! testing every pair, at 8, 64, 1,024 and 4,096 bodies standing in a plaza
//! crowd's grid (columns 0.59 m apart, rows 1 m, root spheres of 0.95 m
//! radius, jittered a few centimetres as a walk moves them). Prints each
//! count's pairs and sphere tests beside the times.
//!
//! `cargo bench --bench broad_phase`

use std::hint::black_box;

use cornertree::geometry::{Point, Sphere};
use cornertree::world::broad_phase::{SortAndSweep, all_pairs};
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

/// `n` root spheres in a grid about as wide as deep.
fn crowd(n: usize) -> Vec<Option<Sphere>> {
    let (sx, sz) = (0.59f32, 1.0f32);
    let cols = ((n as f32 * sz / sx).sqrt().ceil() as usize).max(1);
    let mut rng = SmallRng::seed_from_u64(7);
    (0..n)
        .map(|i| {
            let (c, r) = (i % cols, i / cols);
            Some(Sphere {
                center: Point::new(
                    c as f32 * sx + rng.random_range(-0.03..0.03),
                    0.9,
                    r as f32 * sz + rng.random_range(-0.03..0.03),
                ),
                radius: 0.95,
            })
        })
        .collect()
}

fn broad_phase(c: &mut Criterion) {
    let mut g = c.benchmark_group("broad phase");
    for n in [8usize, 64, 1024, 4096] {
        let spheres = crowd(n);
        let mut out = Vec::new();
        let mut sweep = SortAndSweep::new();
        let all_tests = all_pairs(&spheres, &mut out);
        let pairs = out.len();
        let sweep_tests = sweep.sweep(&spheres, &mut out);
        assert_eq!(out.len(), pairs);
        println!(
            "{n} bodies: {pairs} pairs; sphere tests: every pair {all_tests}, sort and sweep {sweep_tests}"
        );
        g.bench_with_input(BenchmarkId::new("every pair", n), &spheres, |b, s| {
            b.iter(|| all_pairs(black_box(s), &mut out))
        });
        g.bench_with_input(BenchmarkId::new("sort and sweep", n), &spheres, |b, s| {
            b.iter(|| sweep.sweep(black_box(s), &mut out))
        });
    }
    g.finish();
}

criterion_group!(benches, broad_phase);
criterion_main!(benches);
