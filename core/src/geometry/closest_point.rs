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

/// Distance between the closed segments `p1q1` and `p2q2` (either may be a
/// point): the clamped minimiser of `|p1 + s·d1 − p2 − t·d2|²` over
/// `[0, 1]²`, found by minimising in `s` for the best `t` and back once
/// (the function is convex, so one exchange from a clamped start reaches
/// the minimum).
pub fn segment_segment_distance(p1: &Point64, q1: &Point64, p2: &Point64, q2: &Point64) -> f64 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    let (s, t) = if a == 0.0 && e == 0.0 {
        (0.0, 0.0)
    } else if a == 0.0 {
        (0.0, (f / e).clamp(0.0, 1.0))
    } else {
        let c = d1.dot(&r);
        if e == 0.0 {
            ((-c / a).clamp(0.0, 1.0), 0.0)
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let mut s = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let mut t = (b * s + f) / e;
            if t < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            }
            (s, t)
        }
    };
    ((p1 + d1 * s) - (p2 + d2 * t)).norm()
}

/// Euclidean distance between two closed triangles, zero when they touch
/// ([`triangles_intersect_exact`](super::exact::triangles_intersect_exact)).
/// Apart, the nearest points of two triangles lie on a corner of one and
/// the other's face, or on an edge of each: the least of six point-triangle
/// and nine segment distances.
pub fn triangle_triangle_distance(t1: &Triangle, t2: &Triangle) -> f64 {
    if super::exact::triangles_intersect_exact(t1, t2) {
        return 0.0;
    }
    let (v1, v2) = (
        t1.vertices().map(|v| v.cast::<f64>()),
        t2.vertices().map(|v| v.cast::<f64>()),
    );
    let mut d = f64::INFINITY;
    for p in &v1 {
        d = d.min(point_triangle_distance(p, t2));
    }
    for p in &v2 {
        d = d.min(point_triangle_distance(p, t1));
    }
    for i in 0..3 {
        for j in 0..3 {
            d = d.min(segment_segment_distance(
                &v1[i],
                &v1[(i + 1) % 3],
                &v2[j],
                &v2[(j + 1) % 3],
            ));
        }
    }
    d
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

    /// Against sampling: no pair of sampled points is nearer than the
    /// distance, and the nearest sampled pair is not much farther.
    #[test]
    fn triangle_distance_agrees_with_dense_sampling() {
        let mut next = crate::test_rng::unit_floats(0x2545_f491_4f6c_dd1d);
        let samples = |t: &Triangle| {
            let [a, b, c] = t.vertices().map(|v| v.cast::<f64>());
            let n = 24;
            let mut out = Vec::new();
            for i in 0..=n {
                for j in 0..=n - i {
                    let (u, v) = (i as f64 / n as f64, j as f64 / n as f64);
                    out.push(a + (b - a) * u + (c - a) * v);
                }
            }
            out
        };
        for _ in 0..200 {
            let mut tri = |o: f32| {
                let mut p = || Point::new(next() + o, next(), next());
                Triangle::new(p(), p(), p())
            };
            let (t1, t2) = (tri(0.0), tri(0.8));
            let d = triangle_triangle_distance(&t1, &t2);
            let (s1, s2) = (samples(&t1), samples(&t2));
            let sampled = s1
                .iter()
                .flat_map(|p| s2.iter().map(move |q| (p - q).norm()))
                .fold(f64::INFINITY, f64::min);
            assert!(d <= sampled + 1e-9, "{d} > sampled {sampled}");
            let spacing = [t1, t2]
                .iter()
                .map(|t| f64::from(t.longest_edge()) / 24.0)
                .fold(0.0, f64::max);
            assert!(
                sampled - d <= 2.0 * spacing,
                "{d} far below sampled {sampled}"
            );
        }
    }

    #[test]
    fn segment_distance_of_crossing_parallel_and_point_segments() {
        let p = |x, y, z| Point64::new(x, y, z);
        let d = segment_segment_distance;
        assert_eq!(
            d(
                &p(-1., 0., 0.),
                &p(1., 0., 0.),
                &p(0., -1., 2.),
                &p(0., 1., 2.)
            ),
            2.0
        );
        assert_eq!(
            d(
                &p(0., 0., 0.),
                &p(1., 0., 0.),
                &p(3., 1., 0.),
                &p(5., 1., 0.)
            ),
            5f64.sqrt()
        );
        assert_eq!(
            d(
                &p(0., 0., 0.),
                &p(4., 0., 0.),
                &p(1., 3., 0.),
                &p(2., 3., 0.)
            ),
            3.0
        );
        assert_eq!(
            d(
                &p(0., 0., 0.),
                &p(0., 0., 0.),
                &p(3., 4., 0.),
                &p(3., 4., 0.)
            ),
            5.0
        );
    }
}
