//! Closest points on segments and triangles, in `f64`.
//!
//! Reference geometry, not a kernel of the paper's operation model: used to
//! measure how often the plane-sphere test of Algorithm 1 (§5) reports a
//! sphere that does not actually reach the triangle.

use nalgebra::Point3;

use super::Triangle;

/// A point in `f64`.
pub type Point64 = Point3<f64>;

/// Closest point to `p` on the closed segment `ab` (`a` if it is a point).
///
/// ```
/// use cornertree::geometry::closest_point::{Point64, closest_point_on_segment};
///
/// let (a, b) = (Point64::new(0.0, 0.0, 0.0), Point64::new(2.0, 0.0, 0.0));
/// let at = |x, y, z| closest_point_on_segment(&Point64::new(x, y, z), &a, &b);
/// assert_eq!(at(0.5, 1.0, 3.0), Point64::new(0.5, 0.0, 0.0)); // beside the segment
/// assert_eq!(at(5.0, 1.0, 0.0), b); // beyond an end: clamped
/// assert_eq!(at(-1.0, 0.0, 0.0), a);
/// ```
pub fn closest_point_on_segment(p: &Point64, a: &Point64, b: &Point64) -> Point64 {
    let e = b - a;
    let len2 = e.norm_squared();
    if len2 == 0.0 {
        return *a;
    }
    let t = ((p - a).dot(&e) / len2).clamp(0.0, 1.0);
    a + e * t
}

/// Closest point to `p` on the closed triangle `t` (a degenerate triangle is
/// the segment or point it spans).
///
/// If the orthogonal projection of `p` onto the plane lies inside the
/// triangle it is the answer; otherwise the closest point lies on the
/// boundary, the nearest of the three edges' closest points.
///
/// ```
/// use cornertree::geometry::closest_point::{Point64, closest_point_on_triangle};
/// use cornertree::geometry::{Point, Triangle};
///
/// let t = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(1.0, 0.0, 0.0),
///     Point::new(0.0, 1.0, 0.0),
/// );
/// let at = |x, y, z| closest_point_on_triangle(&Point64::new(x, y, z), &t);
/// assert_eq!(at(0.25, 0.5, 2.0), Point64::new(0.25, 0.5, 0.0)); // above the face
/// assert_eq!(at(-3.0, -4.0, 1.0), Point64::new(0.0, 0.0, 0.0)); // beyond a corner
/// assert_eq!(at(0.5, -2.0, -1.0), Point64::new(0.5, 0.0, 0.0)); // beyond the edge y = 0
/// assert_eq!(at(1.0, 1.0, 0.0), Point64::new(0.5, 0.5, 0.0)); // beyond the hypotenuse
/// ```
pub fn closest_point_on_triangle(p: &Point64, t: &Triangle) -> Point64 {
    let [a, b, c] = t.vertices().map(|v| v.cast::<f64>());
    let n = (b - a).cross(&(c - a));
    let n2 = n.norm_squared();
    if n2 > 0.0 {
        let q = p - n * ((p - a).dot(&n) / n2);
        let inside = [(a, b), (b, c), (c, a)]
            .iter()
            .all(|(u, v)| (v - u).cross(&(q - u)).dot(&n) >= 0.0);
        if inside {
            return q;
        }
    }
    [(a, b), (b, c), (c, a)]
        .iter()
        .map(|(u, v)| closest_point_on_segment(p, u, v))
        .min_by(|x, y| (x - p).norm_squared().total_cmp(&(y - p).norm_squared()))
        .expect("three edges")
}

/// Euclidean distance from `p` to the closed triangle `t` (zero on it).
///
/// ```
/// use cornertree::geometry::closest_point::{Point64, point_triangle_distance};
/// use cornertree::geometry::{Point, Triangle};
///
/// let t = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(1.0, 0.0, 0.0),
///     Point::new(0.0, 1.0, 0.0),
/// );
/// let d = |x, y, z| point_triangle_distance(&Point64::new(x, y, z), &t);
/// assert_eq!(d(0.25, 0.25, -2.0), 2.0); // below the face
/// assert_eq!(d(-3.0, -4.0, 0.0), 5.0); // 3-4-5 from the corner at the origin
/// assert_eq!(d(0.5, 0.5, 0.0), 0.0); // on the hypotenuse
/// ```
pub fn point_triangle_distance(p: &Point64, t: &Triangle) -> f64 {
    (closest_point_on_triangle(p, t) - p).norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn unit() -> Triangle {
        Triangle::new(
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
        )
    }

    #[test]
    fn regions() {
        let t = unit();
        let d = |x, y, z| point_triangle_distance(&Point64::new(x, y, z), &t);
        assert_eq!(d(0.25, 0.25, 2.0), 2.0); // above the face
        assert_eq!(d(-3.0, -4.0, 0.0), 5.0); // beyond corner a
        assert_eq!(d(0.5, -2.0, 0.0), 2.0); // beyond edge ab
        assert!((d(1.0, 1.0, 0.0) - 0.5f64.sqrt()).abs() < 1e-15); // beyond edge bc
        assert_eq!(d(0.2, 0.3, 0.0), 0.0); // on the face
    }

    #[test]
    fn degenerate_triangles() {
        let seg = Triangle::new(
            Point::new(0.0, 0.0, 0.0),
            Point::new(2.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
        );
        assert_eq!(
            point_triangle_distance(&Point64::new(1.5, 3.0, 4.0), &seg),
            5.0
        );
        let pt = Triangle::new(
            Point::new(1.0, 1.0, 1.0),
            Point::new(1.0, 1.0, 1.0),
            Point::new(1.0, 1.0, 1.0),
        );
        assert_eq!(
            point_triangle_distance(&Point64::new(1.0, 1.0, 3.0), &pt),
            2.0
        );
    }
}
