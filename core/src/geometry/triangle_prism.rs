//! Whether a sphere can reach a triangle, by the triangle's three edge
//! planes: a cheap test before the triangle-triangle test (ours).
//!
//! The triangle lies in the intersection of the three half-spaces bounded by
//! the planes through its edges perpendicular to it, on its side (its
//! infinite prism). A ball entirely outside one of them holds no point of
//! the triangle, so no triangle inside the ball meets it. A ball that passes
//! may still miss the triangle (near a corner, or far above it): the test
//! only ever says "cannot meet", and the triangle-triangle test decides the
//! rest. Evaluated in `f64` from the `f32` data with a margin far above the
//! rounding, so it never rejects a ball that reaches the triangle; a
//! degenerate triangle gets planes that reject nothing.

use nalgebra::Vector3;

use super::{Sphere, Triangle};

/// Relative margin on distances (rounding of `f64` products of `f32` data is
/// below 1e-15 of the magnitudes involved).
pub(crate) const MARGIN: f64 = 1e-9;

/// The three inward edge planes of a triangle, prepared once.
///
/// ```
/// use cornertree::geometry::triangle_prism::TrianglePrism;
/// use cornertree::geometry::{Point, Sphere, Triangle};
///
/// let floor = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(1.0, 0.0, 0.0),
///     Point::new(0.0, 1.0, 0.0),
/// );
/// let prism = TrianglePrism::new(&floor);
/// // A unit ball touching the edge x = 0 from outside: may meet (closed).
/// assert!(prism.may_meet(&Sphere::new(Point::new(-1.0, 0.5, 0.0), 1.0)));
/// // Moved 0.01 further out: surely holds no point of the triangle.
/// assert!(!prism.may_meet(&Sphere::new(Point::new(-1.01, 0.5, 0.0), 1.0)));
/// // Beyond the hypotenuse x + y = 1 by 2/√2 ≈ 1.41 with radius 1: rejected.
/// assert!(!prism.may_meet(&Sphere::new(Point::new(1.5, 1.5, 0.0), 1.0)));
/// // Conservative: high above the face it passes (the prism is infinite),
/// // though the ball misses the triangle.
/// assert!(prism.may_meet(&Sphere::new(Point::new(0.25, 0.25, 10.0), 1.0)));
///
/// // A degenerate triangle rejects nothing.
/// let segment = Triangle::new(floor.a, floor.b, Point::new(2.0, 0.0, 0.0));
/// let far = Sphere::new(Point::new(100.0, 100.0, 100.0), 1.0);
/// assert!(TrianglePrism::new(&segment).may_meet(&far));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrianglePrism {
    /// Unit inward normals (zero for a degenerate triangle) and offsets:
    /// the triangle's side of edge `k` is `normals[k] · x ≥ offsets[k]`.
    normals: [Vector3<f64>; 3],
    offsets: [f64; 3],
}

impl TrianglePrism {
    /// The prism of `t`: for each edge, the plane through it perpendicular to
    /// the triangle, facing inward (computed in `f64`).
    pub fn new(t: &Triangle) -> Self {
        let v = [t.a, t.b, t.c].map(|p| p.coords.map(|x| x as f64));
        let n = (v[1] - v[0]).cross(&(v[2] - v[0]));
        let mut normals = [Vector3::zeros(); 3];
        let mut offsets = [0.0; 3];
        for k in 0..3 {
            let (p, q, r) = (v[k], v[(k + 1) % 3], v[(k + 2) % 3]);
            let mut e = n.cross(&(q - p));
            let len = e.norm();
            if !(len > 0.0 && len.is_finite()) {
                return Self {
                    normals: [Vector3::zeros(); 3],
                    offsets: [0.0; 3],
                };
            }
            e /= len;
            if e.dot(&(r - p)) < 0.0 {
                e = -e;
            }
            normals[k] = e;
            offsets[k] = e.dot(&p);
        }
        Self { normals, offsets }
    }

    /// The three edge planes: unit inward normals (zero for a degenerate
    /// triangle) and offsets, the triangle's side of edge `k` being
    /// `normals[k] · x ≥ offsets[k]`.
    pub(crate) fn edge_planes(&self) -> (&[Vector3<f64>; 3], &[f64; 3]) {
        (&self.normals, &self.offsets)
    }

    /// Whether the ball `s` may hold a point of the triangle (`false`: it
    /// surely holds none).
    #[inline]
    pub fn may_meet(&self, s: &Sphere) -> bool {
        let c = s.center.coords.map(|x| x as f64);
        // The margin's scale: the 1-norm bounds the centre's length from
        // above and takes no square root (a third of this test's time).
        let scale = c.x.abs() + c.y.abs() + c.z.abs() + s.radius as f64;
        for k in 0..3 {
            let d = self.normals[k].dot(&c) - self.offsets[k];
            let slack = s.radius as f64 + MARGIN * (scale + self.offsets[k].abs());
            if d < -slack {
                return false;
            }
        }
        true
    }

    /// Whether every corner of `t` lies surely strictly inside the prism
    /// (inside all three edge planes, by the same margin [`Self::may_meet`]
    /// allows for rounding): then `t` meets the triangle exactly where it
    /// meets the triangle's plane, since the prism is convex and cuts the
    /// plane in the triangle. Never for a degenerate triangle.
    ///
    /// ```
    /// use cornertree::geometry::triangle_prism::TrianglePrism;
    /// use cornertree::geometry::{Point, Triangle};
    ///
    /// let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
    ///     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
    /// };
    /// let floor = TrianglePrism::new(&tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]));
    /// assert!(floor.holds_inside(&tri([0.1, 0.1, -1.0], [0.2, 0.1, 1.0], [0.1, 0.3, 5.0])));
    /// // A corner on the edge x = 0: not strictly inside.
    /// assert!(!floor.holds_inside(&tri([0.0, 0.1, -1.0], [0.2, 0.1, 1.0], [0.1, 0.3, 5.0])));
    /// ```
    #[inline]
    pub fn holds_inside(&self, t: &Triangle) -> bool {
        [t.a, t.b, t.c].iter().all(|p| {
            let c = p.coords.map(|x| x as f64);
            let scale = c.x.abs() + c.y.abs() + c.z.abs();
            (0..3).all(|k| {
                self.normals[k].dot(&c) - self.offsets[k] > MARGIN * (scale + self.offsets[k].abs())
            })
        })
    }
}

#[cfg(test)]
mod tests {
    use super::TrianglePrism;
    use crate::geometry::closest_point::point_triangle_distance;
    use crate::geometry::{Point, Sphere, Triangle};

    /// A triangle with corners in the cube of side 4 about the origin, from
    /// `next` (uniform in `[-0.5, 0.5)`).
    fn random_triangle(next: &mut impl FnMut() -> f32) -> Triangle {
        let mut corner = || Point::new(4.0 * next(), 4.0 * next(), 4.0 * next());
        Triangle::new(corner(), corner(), corner())
    }

    /// A point `holds_inside` claims is inside: its distance to the
    /// triangle is its distance to the triangle's plane (its foot lies in
    /// the triangle); and a good share of random points is claimed.
    #[test]
    fn inside_only_where_the_foot_is_in_the_triangle() {
        let mut unit = crate::test_rng::unit_floats(0x0005_eed0_f1a5);
        let mut next = move || unit() - 0.5;
        let mut claimed = 0;
        for _ in 0..20_000 {
            let t = random_triangle(&mut next);
            let prism = TrianglePrism::new(&t);
            let p = Point::new(3.0 * next(), 3.0 * next(), 3.0 * next());
            let p64 = p.map(|v| v as f64);
            let v = [t.a, t.b, t.c].map(|q| q.coords.map(|x| x as f64));
            let n = (v[1] - v[0]).cross(&(v[2] - v[0])).normalize();
            let to_plane = n.dot(&(p64.coords - v[0])).abs();
            let to_triangle = point_triangle_distance(&p64, &t);
            let inside = prism.holds_inside(&Triangle::new(p, p, p));
            if inside {
                claimed += 1;
                assert!(
                    (to_triangle - to_plane).abs() <= 1e-9 * (1.0 + to_plane),
                    "{t:?} {p:?}: {to_triangle} against {to_plane}"
                );
            }
        }
        assert!(claimed > 1_000, "claimed {claimed}");
    }

    /// Against the exact distance from the centre to the triangle: a ball
    /// that reaches the triangle is never rejected, and a ball far from the
    /// triangle's prism is.
    #[test]
    fn never_rejects_a_ball_that_reaches_the_triangle() {
        let mut unit = crate::test_rng::unit_floats(0x1234_5678_9abc_def1);
        let mut next = move || unit() - 0.5;
        let (mut rejected, mut reaching) = (0, 0);
        for _ in 0..20_000 {
            let t = random_triangle(&mut next);
            let prism = TrianglePrism::new(&t);
            let c = Point::new(6.0 * next(), 6.0 * next(), 6.0 * next());
            let d = point_triangle_distance(&c.map(|v| v as f64), &t);
            // Radii around the distance, to probe the boundary.
            for f in [0.5f64, 0.99, 1.0, 1.01, 2.0] {
                let s = Sphere::new(c, (d * f) as f32);
                let meets = (s.radius as f64) >= d;
                if meets {
                    reaching += 1;
                    assert!(prism.may_meet(&s), "{t:?} {s:?} reaches at {d}");
                } else if !prism.may_meet(&s) {
                    rejected += 1;
                }
            }
        }
        assert!(
            reaching > 10_000 && rejected > 10_000,
            "{reaching} {rejected}"
        );
    }
}
