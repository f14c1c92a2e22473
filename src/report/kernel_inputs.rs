//! Seeded inputs for `cornertree kernels`: triangle pairs, sphere pairs and
//! sphere-triangle pairs at the scale of a character's triangles (1–4 cm),
//! about a third each disjoint, near touching (a relative gap of 1e-5 to
//! 1e-3, either sign) and intersecting, in a fixed order (class `i % 3`).
//!
//! The generator is a SplitMix64 stream, so the set depends on the seed only.
//!
//! The CCD kernels take [`KernelInputs::moving_pairs`]: each triangle pair
//! as the end of a step, the second triangle arriving from elsewhere.

use nalgebra::Vector3;

use cornertree::geometry::ccd_triangles::MovingTriangle;
use cornertree::geometry::{Point, Sphere, Triangle};

/// The three input classes, in turn.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputClass {
    Disjoint,
    NearTouching,
    Intersecting,
}

impl InputClass {
    pub fn of(i: usize) -> Self {
        match i % 3 {
            0 => InputClass::Disjoint,
            1 => InputClass::NearTouching,
            _ => InputClass::Intersecting,
        }
    }
}

/// Inputs of every kernel, `n` of each.
pub struct KernelInputs {
    pub triangle_pairs: Vec<(Triangle, Triangle)>,
    pub sphere_pairs: Vec<(Sphere, Sphere)>,
    pub sphere_triangles: Vec<(Sphere, Triangle)>,
}

impl KernelInputs {
    pub fn new(n: usize, seed: u64) -> Self {
        let mut rng = SplitMix64(seed);
        Self {
            triangle_pairs: (0..n)
                .map(|i| triangle_pair(&mut rng, InputClass::of(i)))
                .collect(),
            sphere_pairs: (0..n)
                .map(|i| sphere_pair(&mut rng, InputClass::of(i)))
                .collect(),
            sphere_triangles: (0..n)
                .map(|i| sphere_triangle(&mut rng, InputClass::of(i)))
                .collect(),
        }
    }
}

impl KernelInputs {
    /// The first `n` triangle pairs as the end (`t = 1`) of a step: the
    /// first triangle still, the second arriving from one to three of its
    /// sizes away in a random direction, each of its corners also moving by
    /// up to a tenth of its size (so it deforms). Intersecting pairs touch
    /// during the step, others may (passing through) or not.
    pub fn moving_pairs(
        &self,
        n: usize,
        seed: u64,
    ) -> Vec<(MovingTriangle<f64>, MovingTriangle<f64>)> {
        let mut rng = SplitMix64(seed);
        let widen = |t: &Triangle| t.vertices().map(|p| [p.x as f64, p.y as f64, p.z as f64]);
        self.triangle_pairs
            .iter()
            .take(n)
            .map(|(a, b)| {
                let (a, b) = (widen(a), widen(b));
                let size = diameter(&b.map(|p| P::new(p[0], p[1], p[2])));
                let away = rng.direction() * size * rng.range(1.0, 3.0);
                let start = b.map(|p| {
                    let q = P::new(p[0], p[1], p[2]) - away
                        + rng.direction() * size * rng.range(0.0, 0.1);
                    [q.x, q.y, q.z]
                });
                (
                    MovingTriangle { start: a, end: a },
                    MovingTriangle { start, end: b },
                )
            })
            .collect()
    }
}

/// SplitMix64 (Steele, Lea, Flood 2014): a small, well-mixed seeded stream.
struct SplitMix64(u64);

impl SplitMix64 {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        let unit = (self.next() >> 11) as f64 / (1u64 << 53) as f64;
        lo + (hi - lo) * unit
    }

    fn coin(&mut self) -> bool {
        self.next() & 1 == 1
    }

    /// A random unit vector.
    fn direction(&mut self) -> Vector3<f64> {
        loop {
            let v = Vector3::new(
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
                self.range(-1.0, 1.0),
            );
            let n = v.norm();
            if n > 0.1 && n <= 1.0 {
                return v / n;
            }
        }
    }

    /// A signed relative gap, log-uniform in [1e-5, 1e-3].
    fn tiny_gap(&mut self) -> f64 {
        let g = 10f64.powf(-self.range(3.0, 5.0));
        if self.coin() { g } else { -g }
    }

    /// Positive barycentric weights, each at least `min`.
    fn weights(&mut self, min: f64) -> [f64; 3] {
        let w = [
            self.range(min, 1.0),
            self.range(min, 1.0),
            self.range(min, 1.0),
        ];
        let s = w[0] + w[1] + w[2];
        w.map(|x| x / s)
    }
}

type P = Vector3<f64>;

fn point(p: &P) -> Point {
    Point::new(p.x as f32, p.y as f32, p.z as f32)
}

fn tri(p: [P; 3]) -> Triangle {
    Triangle::new(point(&p[0]), point(&p[1]), point(&p[2]))
}

/// A triangle of 1–4 cm edges around a corner in a 1 cm box, with its corners
/// and a unit normal (in `f64`, before rounding to `f32`).
fn small_triangle(rng: &mut SplitMix64) -> ([P; 3], P) {
    loop {
        let a = P::new(
            rng.range(0.0, 0.01),
            rng.range(0.0, 0.01),
            rng.range(0.0, 0.01),
        );
        let size = rng.range(0.01, 0.04);
        let (b, c) = (a + rng.direction() * size, a + rng.direction() * size);
        let n = (b - a).cross(&(c - a));
        // Not a sliver: the normal is well defined.
        if n.norm() > 0.2 * size * size {
            return ([a, b, c], n.normalize());
        }
    }
}

fn blend(p: &[P; 3], w: [f64; 3]) -> P {
    p[0] * w[0] + p[1] * w[1] + p[2] * w[2]
}

fn diameter(p: &[P; 3]) -> f64 {
    let e = |i: usize, j: usize| (p[i] - p[j]).norm();
    e(0, 1).max(e(1, 2)).max(e(2, 0))
}

/// A triangle with the point `x` inside it (positive weights).
fn triangle_around(rng: &mut SplitMix64, x: &P, size: f64) -> [P; 3] {
    let w = rng.weights(0.2);
    let q0 = x + rng.direction() * size;
    let q1 = x + rng.direction() * size;
    // x = w0 q0 + w1 q1 + w2 q2.
    let q2 = (x - q0 * w[0] - q1 * w[1]) / w[2];
    [q0, q1, q2]
}

fn triangle_pair(rng: &mut SplitMix64, class: InputClass) -> (Triangle, Triangle) {
    let (a, n) = small_triangle(rng);
    let size = diameter(&a);
    match class {
        InputClass::Intersecting | InputClass::Disjoint => {
            // A point of A's interior inside B: they intersect.
            let x = blend(&a, rng.weights(0.1));
            let scale = size * rng.range(0.3, 1.0);
            let mut b = triangle_around(rng, &x, scale);
            if class == InputClass::Disjoint {
                // Moved further than both diameters: apart, in any direction.
                let t = rng.direction() * (size + diameter(&b)) * rng.range(1.05, 2.0);
                b = b.map(|q| q + t);
            }
            (tri(a), tri(b))
        }
        InputClass::NearTouching => {
            let gap = rng.tiny_gap() * size;
            let b = if rng.coin() {
                // A corner of B on (or just off) A's face, B on one side.
                let x = blend(&a, rng.weights(0.05)) + n * gap;
                let mut q = || {
                    let d = rng.direction() * 0.5;
                    x + (d + n * rng.range(0.05, 1.0)) * size
                };
                [x, q(), q()]
            } else {
                // An edge of B passing (just) by a point of A's edge a0a1.
                let x = a[0] + (a[1] - a[0]) * rng.range(0.0, 1.0);
                let e = rng.direction();
                let m = (a[1] - a[0]).cross(&e);
                let shift = if m.norm() > 1e-9 {
                    m.normalize() * gap
                } else {
                    P::zeros()
                };
                let h = e * rng.range(0.05, 0.5) * size;
                let z = x + rng.direction() * 0.5 * size;
                [x + shift + h, x + shift - h, z + shift]
            };
            (tri(a), tri(b))
        }
    }
}

fn sphere(c: &P, r: f64) -> Sphere {
    Sphere::new(point(c), r as f32)
}

/// How far apart to place two shapes whose contact distance is `reach`.
fn separation(rng: &mut SplitMix64, class: InputClass, reach: f64) -> f64 {
    match class {
        InputClass::Disjoint => reach * rng.range(1.1, 3.0),
        InputClass::NearTouching => reach * (1.0 + rng.tiny_gap()),
        InputClass::Intersecting => reach * rng.range(0.0, 0.9),
    }
}

fn sphere_pair(rng: &mut SplitMix64, class: InputClass) -> (Sphere, Sphere) {
    let c1 = P::new(
        rng.range(0.0, 0.1),
        rng.range(0.0, 0.1),
        rng.range(0.0, 0.1),
    );
    let (r1, r2) = (rng.range(0.005, 0.03), rng.range(0.005, 0.03));
    let c2 = c1 + rng.direction() * separation(rng, class, r1 + r2);
    (sphere(&c1, r1), sphere(&c2, r2))
}

fn sphere_triangle(rng: &mut SplitMix64, class: InputClass) -> (Sphere, Triangle) {
    let (a, n) = small_triangle(rng);
    // A point of the plane near the triangle (not always over it: the test
    // is against the plane).
    let w = rng.weights(0.0);
    let x = blend(&a, w) + (a[1] - a[0]) * rng.range(-0.5, 0.5);
    let r = rng.range(0.005, 0.03);
    let side = if rng.coin() { 1.0 } else { -1.0 };
    let c = x + n * side * separation(rng, class, r);
    (sphere(&c, r), tri(a))
}

#[cfg(test)]
mod tests {
    use super::*;
    use cornertree::geometry::exact::triangles_intersect_exact;
    use cornertree::geometry::plane_sphere::sphere_meets_plane;

    #[test]
    fn classes_are_what_they_say() {
        let k = KernelInputs::new(300, 7);
        for (i, (a, b)) in k.triangle_pairs.iter().enumerate() {
            match InputClass::of(i) {
                InputClass::Disjoint => assert!(!triangles_intersect_exact(a, b), "{i}"),
                InputClass::Intersecting => assert!(triangles_intersect_exact(a, b), "{i}"),
                InputClass::NearTouching => {}
            }
        }
        for (i, (s, t)) in k.sphere_pairs.iter().enumerate() {
            match InputClass::of(i) {
                InputClass::Disjoint => assert!(!s.overlaps(t), "{i}"),
                InputClass::Intersecting => assert!(s.overlaps(t), "{i}"),
                InputClass::NearTouching => {}
            }
        }
        for (i, (s, t)) in k.sphere_triangles.iter().enumerate() {
            match InputClass::of(i) {
                InputClass::Disjoint => assert!(!sphere_meets_plane(s, t), "{i}"),
                InputClass::Intersecting => assert!(sphere_meets_plane(s, t), "{i}"),
                InputClass::NearTouching => {}
            }
        }
        // Near touching: both answers occur.
        let near: Vec<bool> = k
            .triangle_pairs
            .iter()
            .skip(1)
            .step_by(3)
            .map(|(a, b)| triangles_intersect_exact(a, b))
            .collect();
        assert!(near.iter().any(|&x| x) && near.iter().any(|&x| !x));
    }

    #[test]
    fn same_seed_same_inputs() {
        let (a, b) = (KernelInputs::new(20, 3), KernelInputs::new(20, 3));
        assert_eq!(a.triangle_pairs, b.triangle_pairs);
        assert_eq!(a.sphere_triangles, b.sphere_triangles);
        assert_ne!(a.sphere_pairs, KernelInputs::new(20, 4).sphere_pairs);
    }
}
