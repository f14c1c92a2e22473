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
///
/// ```
/// use cornertree::geometry::plane_sphere::sphere_meets_plane;
/// use cornertree::geometry::{Point, Sphere, Triangle};
///
/// // A floor triangle in the plane z = 0.
/// let floor = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(4.0, 0.0, 0.0),
///     Point::new(0.0, 4.0, 0.0),
/// );
/// // A unit ball resting on the floor: tangent, which counts.
/// assert!(sphere_meets_plane(&Sphere::new(Point::new(1.0, 1.0, 1.0), 1.0), &floor));
/// // The same ball 0.001 higher: clear.
/// assert!(!sphere_meets_plane(&Sphere::new(Point::new(1.0, 1.0, 1.001), 1.0), &floor));
/// // Below the plane works the same (the test is two-sided).
/// assert!(sphere_meets_plane(&Sphere::new(Point::new(1.0, 1.0, -0.5), 1.0), &floor));
/// // The plane, not the triangle: a ball far outside the triangle but
/// // on its plane meets it (paper §5: the corner-tree rules this case out).
/// assert!(sphere_meets_plane(&Sphere::new(Point::new(100.0, 100.0, 0.0), 1.0), &floor));
/// // Collinear corners: no plane, no contact.
/// let segment = Triangle::new(floor.a, floor.b, Point::new(8.0, 0.0, 0.0));
/// assert!(!sphere_meets_plane(&Sphere::new(Point::new(1.0, 0.0, 0.0), 5.0), &segment));
/// ```
pub fn sphere_meets_plane(s: &Sphere, t: &Triangle) -> bool {
    sphere_meets_plane_as::<f64>(s, t)
}

/// [`sphere_meets_plane`] computed in `T` (e.g. to count its operations).
///
/// ```
/// use cornertree::geometry::counted::{Counted, Operations, count_operations_by_kind};
/// use cornertree::geometry::plane_sphere::{TrianglePlane, sphere_meets_plane_as};
/// use cornertree::geometry::{Point, Sphere, Triangle};
///
/// let floor = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(4.0, 0.0, 0.0),
///     Point::new(0.0, 4.0, 0.0),
/// );
/// let s = Sphere::new(Point::new(1.0, 1.0, 0.5), 1.0);
/// let (hit, all) = count_operations_by_kind(|| sphere_meets_plane_as::<Counted>(&s, &floor));
/// assert!(hit && sphere_meets_plane_as::<f64>(&s, &floor));
/// // The plane (two edges, their cross product, its length) then the test
/// // (offset, dot product, `abs`, the radius times the length).
/// assert_eq!(all, Operations { arithmetic: 31, comparisons: 2 });
/// // Prepared once, the plane's share is not paid again.
/// let plane = TrianglePlane::<Counted>::new(&floor);
/// let (_, test) = count_operations_by_kind(|| plane.meets(&s));
/// assert_eq!(test, Operations { arithmetic: 10, comparisons: 2 });
/// ```
#[inline]
pub fn sphere_meets_plane_as<T: Scalar>(s: &Sphere, t: &Triangle) -> bool {
    TrianglePlane::<T>::new(t).meets(s)
}

/// The plane of a triangle, prepared for [`sphere_meets_plane`]: `v0`, `p`
/// and `‖p‖` of Algorithm 1, computed once for a static triangle. A test is
/// then a subtraction, a dot product and a comparison, with the same
/// arithmetic, so the same answers bit for bit. Computed in `T` (`f64` in
/// the pipeline).
///
/// ```
/// use cornertree::geometry::plane_sphere::{TrianglePlane, sphere_meets_plane};
/// use cornertree::geometry::{Point, Sphere, Triangle};
///
/// // A wall in the plane x = 2.
/// let wall = Triangle::new(
///     Point::new(2.0, 0.0, 0.0),
///     Point::new(2.0, 3.0, 0.0),
///     Point::new(2.0, 0.0, 3.0),
/// );
/// let plane = TrianglePlane::<f64>::new(&wall);
/// let touching = Sphere::new(Point::new(1.5, 1.0, 1.0), 0.5);
/// let short = Sphere::new(Point::new(1.5, 1.0, 1.0), 0.25);
/// let beyond = Sphere::new(Point::new(2.75, 1.0, 1.0), 0.75);
/// assert!(plane.meets(&touching) && plane.meets(&beyond));
/// assert!(!plane.meets(&short));
/// for s in [touching, short, beyond] {
///     assert_eq!(plane.meets(&s), sphere_meets_plane(&s, &wall));
/// }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TrianglePlane<T = f64> {
    v0: V3<T>,
    p: V3<T>,
    /// `‖p‖`; 0 for a degenerate triangle (no sphere meets it).
    p_norm: T,
}

impl<T: Scalar> TrianglePlane<T> {
    /// Prepares the plane of `t`: its first corner `v0`, `p = (v1 - v0) ×
    /// (v2 - v0)` and `‖p‖`, in `T`.
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
///
/// ```
/// use cornertree::geometry::plane_sphere::{sphere_meets_plane, sphere_triangle_distance};
/// use cornertree::geometry::{Point, Sphere, Triangle};
///
/// let floor = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(4.0, 0.0, 0.0),
///     Point::new(0.0, 4.0, 0.0),
/// );
/// // 3 above the face, radius 1: a gap of 2.
/// assert_eq!(sphere_triangle_distance(&Sphere::new(Point::new(1.0, 1.0, 3.0), 1.0), &floor), 2.0);
/// // 0.5 deep into the face.
/// assert_eq!(sphere_triangle_distance(&Sphere::new(Point::new(1.0, 1.0, 0.5), 1.0), &floor), -0.5);
/// // On the plane, 3-4-5 beyond the corner (0, 0, 0): the plane test's
/// // false positive, a gap of 4.
/// let s = Sphere::new(Point::new(-3.0, -4.0, 0.0), 1.0);
/// assert!(sphere_meets_plane(&s, &floor));
/// assert_eq!(sphere_triangle_distance(&s, &floor), 4.0);
/// ```
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
