//! Plane-sphere test, the paper's Algorithm 1 (§5).
//!
//! Where the corner-tree guarantees that a small character sphere `S_t` lies
//! in front of a big environment triangle `T`, the paper replaces the
//! triangle-triangle test by this test of `S_t` against the plane of `T`. Its
//! operation model (§5, §6) charges 30 basic operations.

use super::closest_point::point_triangle_distance;
use super::scalar::Scalar;
use super::vec3::{V3, cross, dot, norm_squared, sub, widen, widen_triangle};
use super::{Sphere, Triangle};

/// Whether the closed ball meets the plane of the triangle (Algorithm 1):
/// `p = e1 × e2`, `n = c - v0`, meets iff `|p · n| <= r ‖p‖`.
///
/// Computed in `f64`. The paper writes `<`; we use `<=` so that a tangent
/// sphere counts as meeting, consistent with the closed sets everywhere else.
/// A degenerate (zero-area) triangle has no plane: `false`.
pub fn sphere_meets_plane(s: &Sphere, t: &Triangle) -> bool {
    sphere_meets_plane_as::<f64>(s, t)
}

/// [`sphere_meets_plane`] computed in `T` (e.g. to count its operations).
#[inline]
pub fn sphere_meets_plane_as<T: Scalar>(s: &Sphere, t: &Triangle) -> bool {
    TrianglePlane::<T>::new(t).meets(s)
}

/// The plane of a triangle, prepared for [`sphere_meets_plane`]: `v0`, `p`
/// and `‖p‖` of Algorithm 1, computed once for a static triangle. A test is
/// then a subtraction, a dot product and a comparison, with the same
/// arithmetic, so the same answers bit for bit. Computed in `T` (`f64` in
/// the pipeline).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrianglePlane<T = f64> {
    v0: V3<T>,
    p: V3<T>,
    /// `‖p‖`; 0 for a degenerate triangle (no sphere meets it).
    p_norm: T,
}

impl<T: Scalar> TrianglePlane<T> {
    #[inline]
    pub fn new(t: &Triangle) -> Self {
        let [v0, v1, v2] = widen_triangle::<T>(t);
        let p = cross(&sub(&v1, &v0), &sub(&v2, &v0));
        Self {
            v0,
            p,
            p_norm: norm_squared(&p).sqrt(),
        }
    }

    /// [`sphere_meets_plane`] against this plane's triangle.
    #[inline]
    pub fn meets(&self, s: &Sphere) -> bool {
        if self.p_norm == T::zero() {
            return false;
        }
        let n = sub(&widen::<T>(&s.center), &self.v0);
        dot(&self.p, &n).abs() <= T::from_f32(s.radius) * self.p_norm
    }
}

/// Signed gap between the ball and the closed triangle: the distance from
/// the centre to the triangle minus the radius (`<= 0` iff they meet), in
/// `f64`. The exact-enough reference for plane-sphere false positives.
pub fn sphere_triangle_distance(s: &Sphere, t: &Triangle) -> f64 {
    point_triangle_distance(&s.center.cast::<f64>(), t) - s.radius as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn floor() -> Triangle {
        Triangle::new(
            Point::new(0.0, 0.0, 0.0),
            Point::new(4.0, 0.0, 0.0),
            Point::new(0.0, 4.0, 0.0),
        )
    }

    #[test]
    fn sphere_through_plane() {
        assert!(sphere_meets_plane(
            &Sphere::new(Point::new(1.0, 1.0, 0.5), 1.0),
            &floor()
        ));
        assert!(sphere_meets_plane(
            &Sphere::new(Point::new(1.0, 1.0, -0.5), 1.0),
            &floor()
        ));
    }

    #[test]
    fn tangent_sphere_counts() {
        assert!(sphere_meets_plane(
            &Sphere::new(Point::new(1.0, 1.0, 1.0), 1.0),
            &floor()
        ));
        assert!(sphere_meets_plane(
            &Sphere::new(Point::new(1.0, 1.0, -2.0), 2.0),
            &floor()
        ));
    }

    #[test]
    fn far_sphere_misses() {
        assert!(!sphere_meets_plane(
            &Sphere::new(Point::new(1.0, 1.0, 1.001), 1.0),
            &floor()
        ));
        assert!(!sphere_meets_plane(
            &Sphere::new(Point::new(0.0, 0.0, 10.0), 1.0),
            &floor()
        ));
    }

    #[test]
    fn plane_not_triangle() {
        // Far outside the triangle but on its plane: the plane test says yes,
        // the distance says no. This is the false positive the corner-tree avoids.
        let s = Sphere::new(Point::new(100.0, 100.0, 0.0), 1.0);
        assert!(sphere_meets_plane(&s, &floor()));
        assert!(sphere_triangle_distance(&s, &floor()) > 0.0);
    }

    #[test]
    fn degenerate_triangle_has_no_plane() {
        let seg = Triangle::new(
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 1.0, 1.0),
            Point::new(2.0, 2.0, 2.0),
        );
        let pt = Triangle::new(
            Point::new(1.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
        );
        let s = Sphere::new(Point::new(1.0, 1.0, 1.0), 5.0);
        assert!(!sphere_meets_plane(&s, &seg));
        assert!(!sphere_meets_plane(&s, &pt));
    }
}
