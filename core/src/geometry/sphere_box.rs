//! A sphere against an axis-aligned box held in six bytes (ours; the paper
//! bounds everything by spheres).
//!
//! A static tree's node already has a sphere; the box of the geometry under
//! it is often much tighter (a flat patch of a table top, a wall's strip),
//! and costs nothing to keep up, because the node never moves. A
//! [`QuantizedBox`] stores each face of that box as one of 256 levels across
//! the cube around the node's sphere, rounded outward, so the box it
//! stands for always holds the geometry. [`sphere_meets_box`] then drops a
//! sphere that lies wholly outside it.
//!
//! Conservative by construction:
//! - a face's level is checked at build time with the very `f64` arithmetic
//!   the test uses ([`QuantizedBox::bounds_as`]), so the box the test sees
//!   holds every point of the geometry inside the node's sphere;
//! - the test computes the squared distance from the sphere's centre to the
//!   box in `f64` (its `f32` inputs widened exactly; signs of differences
//!   are exact, each further step rounds by at most half an ulp) and drops
//!   the sphere only when that distance exceeds the squared radius by a
//!   relative margin of 2⁻⁴⁰, far above the few ulps of rounding; a `NaN`
//!   anywhere keeps the sphere.

use super::Sphere;
use super::scalar::Scalar;
use super::vec3::V3;

/// Operations of [`sphere_meets_box_as`] on a box's bounds: per axis two
/// differences, two comparisons (the two against each other, the larger
/// against zero), a square and a sum, then the squared radius, its margin,
/// their sum and the comparison; counted by
/// [`super::counted::Counted`] in this module's tests. Turning the six
/// bytes into bounds ([`QuantizedBox::bounds_as`]) costs two operations a
/// face more (a product and a sum): [`SPHERE_BOX`] in all.
pub const SPHERE_BOX_ON_BOUNDS: u64 = 3 * 6 + 4;

/// Operations charged per sphere-box test: [`SPHERE_BOX_ON_BOUNDS`] plus
/// twelve to turn the six bytes into bounds.
pub const SPHERE_BOX: u64 = SPHERE_BOX_ON_BOUNDS + 12;

/// Relative margin on the squared radius before a sphere is dropped.
const MARGIN: f64 = 1.0 / (1u64 << 40) as f64;

/// The top level of a face.
const TOP: u8 = u8::MAX;

/// Where level `q` lies across the cube, from `−1` (its low face) to `1`.
#[inline(always)]
fn level(q: u8) -> f64 {
    f64::from(q) * (2.0 / f64::from(TOP)) - 1.0
}

/// An axis-aligned box as levels across the cube around a sphere (the
/// node's own): on each axis `k`, the box spans
/// `c_k + r·level(lo_k) ..= c_k + r·level(hi_k)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct QuantizedBox {
    /// Low faces' levels.
    pub lo: [u8; 3],
    /// High faces' levels.
    pub hi: [u8; 3],
}

impl QuantizedBox {
    /// The whole cube around the sphere (no tighter box known).
    pub const CUBE: QuantizedBox = QuantizedBox {
        lo: [0; 3],
        hi: [TOP; 3],
    };

    /// The smallest box of levels around `sphere` holding `min..=max` (an
    /// extent of the geometry, e.g. its corners' `f32` coordinates widened),
    /// clipped to the cube around `sphere` (the geometry lies in the
    /// sphere). An empty or non-finite extent, or an invalid sphere, gives
    /// [`QuantizedBox::CUBE`].
    pub fn enclosing(min: [f64; 3], max: [f64; 3], sphere: &Sphere) -> Self {
        let finite = min.iter().chain(&max).all(|x| x.is_finite());
        if !finite || !sphere.is_valid() || (0..3).any(|k| min[k] > max[k]) {
            return Self::CUBE;
        }
        let (r, top) = (f64::from(sphere.radius), f64::from(TOP));
        let mut b = Self::CUBE;
        for k in 0..3 {
            let c = f64::from(sphere.center[k]);
            let at = |q: u8| c + r * level(q);
            // A first guess, then the highest level at or below `min` and
            // the lowest at or above `max`, by the test's own arithmetic.
            let guess = |x: f64| {
                if r > 0.0 {
                    ((x - c) / r + 1.0) * top / 2.0
                } else {
                    0.0
                }
            };
            let mut ql = guess(min[k]).floor().clamp(0.0, top) as u8;
            while ql > 0 && at(ql) > min[k] {
                ql -= 1;
            }
            let mut qh = guess(max[k]).ceil().clamp(0.0, top) as u8;
            while qh < TOP && at(qh) < max[k] {
                qh += 1;
            }
            b.lo[k] = ql;
            b.hi[k] = qh.max(ql);
        }
        b
    }

    /// The box's bounds around `sphere` (the one it was built around), in
    /// `T`: the arithmetic [`QuantizedBox::enclosing`] checked its levels
    /// with.
    #[inline(always)]
    pub fn bounds_as<T: Scalar>(&self, sphere: &Sphere) -> (V3<T>, V3<T>) {
        let r = T::from_f32(sphere.radius);
        let at = |k: usize, q: u8| T::from_f32(sphere.center[k]) + r * T::from_f64(level(q));
        (
            [at(0, self.lo[0]), at(1, self.lo[1]), at(2, self.lo[2])],
            [at(0, self.hi[0]), at(1, self.hi[1]), at(2, self.hi[2])],
        )
    }
}

/// Whether the sphere `s` may meet the box `b` built around the sphere
/// `around`: `false` only when every point of `s` lies outside the box.
#[inline]
pub fn sphere_meets_box(s: &Sphere, b: &QuantizedBox, around: &Sphere) -> bool {
    let (lo, hi) = b.bounds_as::<f64>(around);
    sphere_meets_box_as(s, &lo, &hi)
}

/// Whether the sphere `s` may meet the box `lo..=hi`, computed in `T`
/// (`f64` in use; [`super::counted::Counted`] to count its operations).
#[inline(always)]
pub fn sphere_meets_box_as<T: Scalar>(s: &Sphere, lo: &V3<T>, hi: &V3<T>) -> bool {
    let z = T::zero();
    let mut d2 = z;
    for k in 0..3 {
        let c = T::from_f32(s.center[k]);
        // Zero inside the slab; a NaN stays a NaN (and keeps the sphere).
        let e = z.max_of((lo[k] - c).max_of(c - hi[k]));
        d2 = d2 + e * e;
    }
    let r = T::from_f32(s.radius);
    let r2 = r * r;
    // Dropped only when provably outside (a NaN compares false: kept).
    #[allow(clippy::neg_cmp_op_on_partial_ord)]
    let keep = !(d2 > r2 + r2 * T::from_f64(MARGIN));
    keep
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::closest_point::point_triangle_distance;
    use crate::geometry::counted::{Counted, count_operations};
    use crate::geometry::{Point, Triangle, bounds_of};

    /// A point within `scale / 2` of `(at, at, at)` on each axis.
    fn point(unit: &mut impl FnMut() -> f32, scale: f32, at: f32) -> Point {
        Point::new(
            at + scale * (unit() - 0.5),
            at + scale * (unit() - 0.5),
            at + scale * (unit() - 0.5),
        )
    }

    fn wide(p: Point) -> [f64; 3] {
        [p.x, p.y, p.z].map(f64::from)
    }

    fn enclosing_sphere(t: &Triangle) -> Sphere {
        crate::geometry::enclosing::triangle_sphere(t)
    }

    /// Against the exact distance from a sphere's centre to a triangle
    /// (closest point in `f64`): a sphere that reaches the triangle is never
    /// dropped, and most spheres that miss its box are. Triangles of every
    /// size and place, some flat on an axis plane (a box of zero
    /// thickness), spheres from a point to larger than the triangle.
    #[test]
    fn never_drops_a_sphere_that_reaches_the_triangle() {
        let mut unit = crate::test_rng::unit_floats(0x9e37_79b9_7f4a_7c15);
        let (mut reached, mut dropped, mut missed) = (0, 0, 0);
        for i in 0..20_000 {
            let scale = [1e-3, 0.05, 1.0, 40.0][i % 4];
            let at = [0.0, 3.0, -250.0][i % 3];
            let mut t = Triangle::new(
                point(&mut unit, scale, at),
                point(&mut unit, scale, at),
                point(&mut unit, scale, at),
            );
            if i % 5 == 0 {
                // Flat on a plane of constant y.
                t.b.y = t.a.y;
                t.c.y = t.a.y;
            }
            let around = enclosing_sphere(&t);
            let (min, max) = bounds_of([t.a, t.b, t.c]).unwrap();
            let b = QuantizedBox::enclosing(wide(min), wide(max), &around);
            for _ in 0..8 {
                let centre = point(&mut unit, scale * 2.0, at);
                let radius = scale * unit() * [0.0, 0.3, 1.0][i % 3];
                let s = Sphere::new(centre, radius);
                let d = point_triangle_distance(&centre.cast::<f64>(), &t);
                let keeps = sphere_meets_box(&s, &b, &around);
                if d <= f64::from(radius) * (1.0 - 1e-9) {
                    reached += 1;
                    assert!(
                        keeps,
                        "dropped a sphere {s:?} reaching {t:?} (distance {d})"
                    );
                } else {
                    missed += 1;
                    dropped += !keeps as u32;
                }
            }
        }
        assert!(reached > 10_000 && missed > 10_000, "{reached} {missed}");
        assert!(dropped > missed / 2, "drops {dropped} of {missed} misses");
    }

    /// The levels hold the extent, and a box built around a sphere stays in
    /// its cube; degenerate input gives the whole cube.
    #[test]
    fn levels_hold_the_extent_and_degenerate_input_gives_the_cube() {
        let s = Sphere::new(Point::new(1.0, 2.0, 3.0), 0.5);
        let (min, max) = (Point::new(0.7, 2.0, 2.6), Point::new(1.1, 2.0, 3.5));
        let b = QuantizedBox::enclosing(wide(min), wide(max), &s);
        let (lo, hi) = b.bounds_as::<f64>(&s);
        for k in 0..3 {
            assert!(lo[k] <= f64::from(min[k]) && hi[k] >= f64::from(max[k]));
            // Within one level (a 255th of the cube's side) of the extent.
            assert!(f64::from(min[k]) - lo[k] <= 1.0 / 255.0 + 1e-12);
            assert!(hi[k] - f64::from(max[k]) <= 1.0 / 255.0 + 1e-12);
        }
        // An extent beyond the cube is clipped to it.
        let far = QuantizedBox::enclosing([-9.0; 3], [9.0; 3], &s);
        assert_eq!(far, QuantizedBox::CUBE);
        // Flat in y: a box one level thick at most.
        assert!(b.hi[1] - b.lo[1] <= 1);
        let nan = Point::new(f32::NAN, 0.0, 0.0);
        assert_eq!(
            QuantizedBox::enclosing(wide(nan), wide(max), &s),
            QuantizedBox::CUBE
        );
        assert_eq!(
            QuantizedBox::enclosing(wide(max), wide(min), &s),
            QuantizedBox::CUBE
        );
        // A sphere with a NaN centre is kept.
        let odd = Sphere::new(nan, 1.0);
        assert!(sphere_meets_box(&odd, &b, &s));
    }

    /// The operations charged are the ones paid.
    #[test]
    fn charges_the_operations_it_pays() {
        let around = Sphere::new(Point::new(0.0, 0.0, 0.0), 1.0);
        let b = QuantizedBox {
            lo: [10, 20, 30],
            hi: [200, 210, 220],
        };
        let s = Sphere::new(Point::new(3.0, 0.1, -0.2), 0.5);
        let (_, on_bounds) = count_operations(|| {
            let (lo, hi) = b.bounds_as::<f64>(&around);
            let (lo, hi) = (lo.map(Counted::from_f64), hi.map(Counted::from_f64));
            sphere_meets_box_as::<Counted>(&s, &lo, &hi)
        });
        assert_eq!(on_bounds, SPHERE_BOX_ON_BOUNDS);
        let (_, all) = count_operations(|| {
            let (lo, hi) = b.bounds_as::<Counted>(&around);
            sphere_meets_box_as::<Counted>(&s, &lo, &hi)
        });
        assert_eq!(all, SPHERE_BOX);
    }
}
