//! Acceptance test: both floating-point triangle-triangle kernels (the Tropp
//! test, `geometry::tropp`, and the edge-crossing test,
//! `geometry::edge_crossing`) agree with the exact oracle on 1,000,000
//! triangle pairs from a fixed seed, most of them built to be at or near
//! contact. The only disagreements allowed are on pairs the oracle classifies
//! as `Touching`; the counts are printed per generator and kernel
//! (`cargo test --test tri_tri_agreement -- --nocapture`).

use std::time::Instant;

use cornertree::geometry::exact::{Contact, classify};
use cornertree::geometry::{Point, Triangle};
use cornertree::geometry::{edge_crossing, tropp};
use nalgebra::{Point3, Vector3};
use rand::rngs::SmallRng;
use rand::{Rng, SeedableRng};

const PAIRS: usize = 1_000_000;
const SEED: u64 = 0x5EED_C0FF_EE00_0001;

/// Grid step: integer grid coordinates `n` stand for `n · 2⁻²⁰`, exact in
/// `f32` while `|n| < 2²⁴`, so built contacts are exact contacts.
const STEP: f64 = 1.0 / (1u64 << 20) as f64;
type G = [i64; 3];

fn grid(n: G) -> Point {
    assert!(
        n.iter().all(|c| c.abs() < 1 << 24),
        "grid coordinate out of f32 range: {n:?}"
    );
    Point::new(
        (n[0] as f64 * STEP) as f32,
        (n[1] as f64 * STEP) as f32,
        (n[2] as f64 * STEP) as f32,
    )
}

fn gtri(a: G, b: G, c: G) -> Triangle {
    Triangle::new(grid(a), grid(b), grid(c))
}

fn rand_g(rng: &mut SmallRng, m: i64) -> G {
    [
        rng.random_range(-m..=m),
        rng.random_range(-m..=m),
        rng.random_range(-m..=m),
    ]
}

/// A random grid point that is a multiple of `k`.
fn rand_g_mult(rng: &mut SmallRng, m: i64, k: i64) -> G {
    rand_g(rng, m / k).map(|c| c * k)
}

fn add(a: G, b: G) -> G {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}
fn sub(a: G, b: G) -> G {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn scale(a: G, s: i64) -> G {
    a.map(|c| c * s)
}
fn div(a: G, d: i64) -> G {
    debug_assert!(a.iter().all(|c| c % d == 0));
    a.map(|c| c / d)
}

/// `(α a + β b + γ c) / 8` with `α + β + γ = 8`; exact for corners that are multiples of 8.
fn bary8(a: G, b: G, c: G, w: [i64; 3]) -> G {
    div(add(add(scale(a, w[0]), scale(b, w[1])), scale(c, w[2])), 8)
}

/// Weights for a point strictly inside (edge = false) or on the relative
/// interior of edge ab (edge = true).
fn weights(rng: &mut SmallRng, edge: bool) -> [i64; 3] {
    if edge {
        let a = rng.random_range(1..=7);
        [a, 8 - a, 0]
    } else {
        let a = rng.random_range(1..=6);
        let b = rng.random_range(1..=7 - a);
        [a, b, 8 - a - b]
    }
}

fn uniform_point(rng: &mut SmallRng, lo: f32, hi: f32) -> Point {
    Point::new(
        rng.random_range(lo..=hi),
        rng.random_range(lo..=hi),
        rng.random_range(lo..=hi),
    )
}

fn uniform_tri(rng: &mut SmallRng) -> Triangle {
    Triangle::new(
        uniform_point(rng, -1.0, 1.0),
        uniform_point(rng, -1.0, 1.0),
        uniform_point(rng, -1.0, 1.0),
    )
}

/// Random corner order (one of six).
fn jumble(rng: &mut SmallRng, t: Triangle) -> Triangle {
    let [a, b, c] = t.vertices();
    let r = match rng.random_range(0..3) {
        0 => [a, b, c],
        1 => [b, c, a],
        _ => [c, a, b],
    };
    if rng.random_bool(0.5) {
        Triangle::new(r[0], r[2], r[1])
    } else {
        Triangle::new(r[0], r[1], r[2])
    }
}

fn p64(p: &Point) -> Point3<f64> {
    p.cast::<f64>()
}
fn p32(p: &Point3<f64>) -> Point {
    p.cast::<f32>()
}

/// A unit vector with random direction.
fn rand_dir(rng: &mut SmallRng) -> Vector3<f64> {
    loop {
        let v = Vector3::new(
            rng.random_range(-1.0..=1.0),
            rng.random_range(-1.0..=1.0),
            rng.random_range(-1.0..=1.0),
        );
        let n = v.norm();
        if n > 0.1 && n <= 1.0 {
            return v / n;
        }
    }
}

/// A relative gap in [1e-6, 1e-3], log-uniform, signed.
fn tiny_gap(rng: &mut SmallRng) -> f64 {
    let g = 10f64.powf(-rng.random_range(3.0..=6.0));
    if rng.random_bool(0.5) { g } else { -g }
}

#[derive(Clone, Copy, Debug)]
enum Gen {
    Uniform,
    UniformClose,
    SharedVertex,
    SharedEdge,
    VertexOnFace,
    VertexOnEdge,
    EdgeCrossesEdge,
    CoplanarLattice,
    CoplanarAxis,
    SmallGrid,
    Degenerate,
    NearFace,
    NearEdge,
    NearParallel,
}

const GENS: [Gen; 14] = [
    Gen::Uniform,
    Gen::UniformClose,
    Gen::SharedVertex,
    Gen::SharedEdge,
    Gen::VertexOnFace,
    Gen::VertexOnEdge,
    Gen::EdgeCrossesEdge,
    Gen::CoplanarLattice,
    Gen::CoplanarAxis,
    Gen::SmallGrid,
    Gen::Degenerate,
    Gen::NearFace,
    Gen::NearEdge,
    Gen::NearParallel,
];

const M: i64 = 1 << 20; // grid half-width: coordinates in [-1, 1]

fn generate(rng: &mut SmallRng, g: Gen) -> (Triangle, Triangle) {
    match g {
        Gen::Uniform => (uniform_tri(rng), uniform_tri(rng)),
        Gen::UniformClose => {
            let t1 = uniform_tri(rng);
            let c = t1.centroid();
            let mut q = || c + uniform_point(rng, -0.6, 0.6).coords;
            (t1, Triangle::new(q(), q(), q()))
        }
        Gen::SharedVertex => {
            let (a, b, c) = (rand_g(rng, M), rand_g(rng, M), rand_g(rng, M));
            let k = [a, b, c][rng.random_range(0..3)];
            // Other corners near k (so piercing happens) or anywhere.
            let r = if rng.random_bool(0.5) { M / 2 } else { M };
            let (y, z) = (add(k, rand_g(rng, r)), add(k, rand_g(rng, r)));
            (gtri(a, b, c), gtri(k, y, z))
        }
        Gen::SharedEdge => {
            let (a, b, c) = (
                rand_g_mult(rng, M, 8),
                rand_g_mult(rng, M, 8),
                rand_g_mult(rng, M, 8),
            );
            let z = if rng.random_bool(0.5) {
                rand_g(rng, M)
            } else {
                // Coplanar third corner: a + (i (b - a) + j (c - a)) / 8.
                let (i, j) = (rng.random_range(-8..=8), rng.random_range(-8..=8));
                add(a, div(add(scale(sub(b, a), i), scale(sub(c, a), j)), 8))
            };
            (gtri(a, b, c), gtri(a, b, z))
        }
        Gen::VertexOnFace | Gen::VertexOnEdge => {
            let (a, b, c) = (
                rand_g_mult(rng, M, 8),
                rand_g_mult(rng, M, 8),
                rand_g_mult(rng, M, 8),
            );
            let x = bary8(a, b, c, weights(rng, matches!(g, Gen::VertexOnEdge)));
            let r = M / 2;
            (
                gtri(a, b, c),
                gtri(x, add(x, rand_g(rng, r)), add(x, rand_g(rng, r))),
            )
        }
        Gen::EdgeCrossesEdge => {
            let (a, b, c) = (
                rand_g_mult(rng, M, 8),
                rand_g_mult(rng, M, 8),
                rand_g_mult(rng, M, 8),
            );
            let x = bary8(a, b, c, weights(rng, true));
            let e = rand_g(rng, M / 2);
            let z = add(x, rand_g(rng, M / 2));
            (gtri(a, b, c), gtri(add(x, e), sub(x, e), z))
        }
        Gen::CoplanarLattice => {
            let o = rand_g(rng, M / 2);
            let (e1, e2) = (rand_g(rng, 1 << 16), rand_g(rng, 1 << 16));
            let mut q = || {
                add(
                    o,
                    add(
                        scale(e1, rng.random_range(-6..=6)),
                        scale(e2, rng.random_range(-6..=6)),
                    ),
                )
            };
            (gtri(q(), q(), q()), gtri(q(), q(), q()))
        }
        Gen::CoplanarAxis => {
            let z: f32 = rng.random_range(-1.0..=1.0);
            let axis = rng.random_range(0..3);
            let mut q = || {
                let mut p = uniform_point(rng, -1.0, 1.0);
                p[axis] = z;
                p
            };
            (Triangle::new(q(), q(), q()), Triangle::new(q(), q(), q()))
        }
        Gen::SmallGrid => {
            let mut q = || {
                Point::new(
                    rng.random_range(-2..=2) as f32,
                    rng.random_range(-2..=2) as f32,
                    rng.random_range(-2..=2) as f32,
                )
            };
            (Triangle::new(q(), q(), q()), Triangle::new(q(), q(), q()))
        }
        Gen::Degenerate => {
            let (a, b, c) = (
                rand_g_mult(rng, M, 8),
                rand_g_mult(rng, M, 8),
                rand_g_mult(rng, M, 8),
            );
            // A contact point on T1 (face, edge or corner), or anywhere.
            let x = match rng.random_range(0..4) {
                0 => bary8(a, b, c, weights(rng, false)),
                1 => bary8(a, b, c, weights(rng, true)),
                2 => a,
                _ => rand_g(rng, M),
            };
            let e = rand_g(rng, M / 4);
            let t2 = match rng.random_range(0..4) {
                0 => gtri(x, x, x),                           // a point
                1 => gtri(sub(x, e), add(x, e), x),           // segment through x
                2 => gtri(x, add(x, e), add(x, scale(e, 2))), // segment ending at x
                _ => gtri(x, add(x, e), add(x, e)),           // doubled corner
            };
            // Sometimes T1 is degenerate too.
            let t1 = if rng.random_bool(0.2) {
                gtri(a, b, div(add(a, b), 2))
            } else {
                gtri(a, b, c)
            };
            (t1, t2)
        }
        Gen::NearFace => {
            // T2 rests a corner on (or near) a point of T1 and stays on one side.
            let t1 = uniform_tri(rng);
            let [a, b, c] = t1.vertices().map(|p| p64(&p));
            let n = (b - a).cross(&(c - a));
            if n.norm() < 1e-3 {
                return (t1, uniform_tri(rng));
            }
            let n = n.normalize();
            let (u, v) = (rng.random::<f64>(), rng.random::<f64>());
            let (u, v) = if u + v > 1.0 {
                (1.0 - u, 1.0 - v)
            } else {
                (u, v)
            };
            let x = a + (b - a) * u + (c - a) * v;
            let size = t1.longest_edge() as f64;
            let side = if rng.random_bool(0.5) { 1.0 } else { -1.0 };
            let shift = n * (tiny_gap(rng) * size);
            let mut q = || {
                x + shift + (rand_dir(rng) * 0.5 + n * side * rng.random_range(0.05..=1.0)) * size
            };
            let t2 = Triangle::new(p32(&(x + shift)), p32(&q()), p32(&q()));
            (t1, t2)
        }
        Gen::NearEdge => {
            // T2's edge passes (nearly) through a point of T1's edge.
            let t1 = uniform_tri(rng);
            let [a, b, _] = t1.vertices().map(|p| p64(&p));
            let x = a + (b - a) * rng.random::<f64>();
            let size = t1.longest_edge() as f64;
            let e = rand_dir(rng);
            let m = (b - a).cross(&e);
            if m.norm() < 1e-3 {
                return (t1, uniform_tri(rng));
            }
            let shift = m.normalize() * (tiny_gap(rng) * size);
            let h = e * rng.random_range(0.05..=0.5) * size;
            let z = x + rand_dir(rng) * 0.5 * size;
            (
                t1,
                Triangle::new(
                    p32(&(x + shift + h)),
                    p32(&(x + shift - h)),
                    p32(&(z + shift)),
                ),
            )
        }
        Gen::NearParallel => {
            // T2 is T1 moved off its plane by a tiny gap, shifted, maybe tilted.
            let t1 = uniform_tri(rng);
            let [a, b, c] = t1.vertices().map(|p| p64(&p));
            let n = (b - a).cross(&(c - a));
            if n.norm() < 1e-3 {
                return (t1, uniform_tri(rng));
            }
            let n = n.normalize();
            let size = t1.longest_edge() as f64;
            let d = rand_dir(rng);
            let slide = (d - n * n.dot(&d)) * 0.3 * size;
            let gap = n * (tiny_gap(rng) * size);
            // Tilted by up to four gaps: then T2 often crosses T1's plane.
            let tilt = if rng.random_bool(0.5) {
                0.0
            } else {
                gap.norm() * rng.random_range(0.0..=4.0)
            };
            let t2 = Triangle::new(
                p32(&(a + gap + slide)),
                p32(&(b + gap + slide + n * tilt)),
                p32(&(c + gap + slide - n * tilt)),
            );
            (t1, t2)
        }
    }
}

/// A triangle-triangle test.
type TriTest = fn(&Triangle, &Triangle) -> bool;

/// The kernels under test.
const KERNELS: [(&str, TriTest); 2] = [
    ("Tropp", tropp::triangles_intersect),
    ("edge-crossing", edge_crossing::triangles_intersect),
];

#[derive(Default)]
struct Stats {
    /// Oracle class counts: disjoint, touching, overlapping.
    class: [u64; 3],
    /// Disagreements by kernel, then by oracle class.
    disagree: [[u64; 3]; KERNELS.len()],
    /// Pairs with a degenerate triangle.
    degenerate: u64,
}

fn idx(c: Contact) -> usize {
    match c {
        Contact::Disjoint => 0,
        Contact::Touching => 1,
        Contact::Overlapping => 2,
    }
}

#[test]
fn kernels_agree_with_exact_oracle() {
    let start = Instant::now();
    let mut rng = SmallRng::seed_from_u64(SEED);
    let mut stats: Vec<Stats> = GENS.iter().map(|_| Stats::default()).collect();
    let mut examples: Vec<String> = Vec::new();
    for i in 0..PAIRS {
        let gi = i % GENS.len();
        let (t1, t2) = generate(&mut rng, GENS[gi]);
        let (mut t1, mut t2) = (jumble(&mut rng, t1), jumble(&mut rng, t2));
        if rng.random_bool(0.5) {
            std::mem::swap(&mut t1, &mut t2);
        }
        let want = classify(&t1, &t2);
        let s = &mut stats[gi];
        s.class[idx(want)] += 1;
        if t1.area() == 0.0 || t2.area() == 0.0 {
            s.degenerate += 1;
        }
        for (k, (name, test)) in KERNELS.iter().enumerate() {
            let got = test(&t1, &t2);
            if got != (want != Contact::Disjoint) {
                s.disagree[k][idx(want)] += 1;
                if want != Contact::Touching && examples.len() < 10 {
                    examples.push(format!(
                        "{:?}: oracle {want:?}, {name} {got}: {t1:?} / {t2:?}",
                        GENS[gi]
                    ));
                }
            }
        }
    }
    let elapsed = start.elapsed();

    println!(
        "{PAIRS} pairs, seed {SEED:#x}, {:.2} s",
        elapsed.as_secs_f64()
    );
    println!(
        "{:<56} | disagreements with the oracle, by its class",
        "oracle classes"
    );
    println!(
        "{:<16} {:>9} {:>9} {:>11} {:>7} | {:>13} {:>8} {:>8} {:>11}",
        "generator",
        "disjoint",
        "touching",
        "overlapping",
        "degen",
        "kernel",
        "disjoint",
        "touching",
        "overlapping"
    );
    let mut total = Stats::default();
    let row = |name: String, s: &Stats| {
        for (k, (kernel, _)) in KERNELS.iter().enumerate() {
            let counts = if k == 0 {
                format!(
                    "{name:<16} {:>9} {:>9} {:>11} {:>7}",
                    s.class[0], s.class[1], s.class[2], s.degenerate
                )
            } else {
                String::new()
            };
            println!(
                "{counts:<56} | {kernel:>13} {:>8} {:>8} {:>11}",
                s.disagree[k][0], s.disagree[k][1], s.disagree[k][2]
            );
        }
    };
    for (g, s) in GENS.iter().zip(&stats) {
        row(format!("{g:?}"), s);
        for c in 0..3 {
            total.class[c] += s.class[c];
            for k in 0..KERNELS.len() {
                total.disagree[k][c] += s.disagree[k][c];
            }
        }
        total.degenerate += s.degenerate;
    }
    row("total".into(), &total);
    for e in &examples {
        println!("  {e}");
    }

    for (k, (name, _)) in KERNELS.iter().enumerate() {
        assert_eq!(
            total.disagree[k][0], 0,
            "{name} test reports contact on disjoint pairs"
        );
        assert_eq!(
            total.disagree[k][2], 0,
            "{name} test misses overlapping pairs"
        );
    }
    // Not vacuous: every class occurs in bulk, and the contact generators make contacts.
    assert!(
        total.class.iter().all(|&n| n >= 50_000),
        "class counts {:?}",
        total.class
    );
    assert!(
        total.degenerate >= 20_000,
        "degenerate pairs {}",
        total.degenerate
    );
    for (g, s) in GENS.iter().zip(&stats) {
        match g {
            Gen::SharedVertex
            | Gen::SharedEdge
            | Gen::VertexOnFace
            | Gen::VertexOnEdge
            | Gen::EdgeCrossesEdge
            | Gen::Degenerate => {
                assert!(
                    s.class[1] >= 10_000,
                    "{g:?} makes few touching pairs: {:?}",
                    s.class
                )
            }
            Gen::CoplanarLattice | Gen::SmallGrid => {
                assert!(
                    s.class.iter().all(|&n| n >= 1_000),
                    "{g:?} lacks variety: {:?}",
                    s.class
                )
            }
            Gen::CoplanarAxis => {
                assert!(
                    s.class[0] >= 10_000 && s.class[2] >= 10_000,
                    "{g:?}: {:?}",
                    s.class
                )
            }
            Gen::NearFace | Gen::NearEdge | Gen::NearParallel => {
                assert!(
                    s.class[0] >= 10_000 && s.class[2] + s.class[1] >= 10_000,
                    "{g:?}: {:?}",
                    s.class
                )
            }
            Gen::Uniform | Gen::UniformClose => {}
        }
    }
}
