//! Where two triangles cross: the segment they share, in `f64`.
//!
//! Geometry handed to a caller about a contact already decided (by the exact
//! or the floating-point triangle-triangle test), not a predicate: no test
//! of the paper's operation model depends on it. Two triangles that are not
//! coplanar and meet share one segment (a point where they only touch): each
//! crosses the other's plane along a segment, and both of those lie on the
//! line where the two planes meet; the shared part is where the two
//! overlap on that line.

use nalgebra::Vector3;

use super::closest_point::Point64;
use super::{Point, Triangle};

/// The segment two triangles share, its ends in the world's `f32`
/// coordinates (the same point twice where they touch at one point); `None`
/// where they do not meet, where they lie in one plane, or where either is
/// degenerate (no plane).
///
/// ```
/// use cornertree::geometry::intersection_segment::intersection_segment;
/// use cornertree::geometry::{Point, Triangle, Vector};
///
/// // A triangle in the floor, another standing through it along x = 0.
/// let floor = Triangle::new(
///     Point::new(-1.0, 0.0, -1.0),
///     Point::new(1.0, 0.0, -1.0),
///     Point::new(0.0, 0.0, 1.0),
/// );
/// let fin = Triangle::new(
///     Point::new(0.0, -1.0, -0.5),
///     Point::new(0.0, 1.0, -0.5),
///     Point::new(0.0, -1.0, 0.5),
/// );
/// let [p, q] = intersection_segment(&floor, &fin).unwrap();
/// let (lo, hi) = if p.z < q.z { (p, q) } else { (q, p) };
/// assert!((lo - Point::new(0.0, 0.0, -0.5)).norm() < 1e-6);
/// assert!((hi - Point::new(0.0, 0.0, 0.0)).norm() < 1e-6);
/// // Lifted above the floor: they do not meet.
/// let up = Vector::new(0.0, 2.0, 0.0);
/// let lifted = Triangle::new(fin.a + up, fin.b + up, fin.c + up);
/// assert_eq!(intersection_segment(&floor, &lifted), None);
/// ```
pub fn intersection_segment(a: &Triangle, b: &Triangle) -> Option<[Point; 2]> {
    let wide = |t: &Triangle| t.vertices().map(|p| p.cast::<f64>());
    let (pa, pb) = (wide(a), wide(b));
    let (na, nb) = (normal(&pa)?, normal(&pb)?);
    // Each triangle's crossing of the other's plane.
    let sa = crossing(&pa, &pb[0], &nb)?;
    let sb = crossing(&pb, &pa[0], &na)?;
    // Both lie on the line the planes share (or are single points on it):
    // the overlap, along the longer of the two.
    let (long, short) = if (sa[1] - sa[0]).norm_squared() >= (sb[1] - sb[0]).norm_squared() {
        (sa, sb)
    } else {
        (sb, sa)
    };
    let d = long[1] - long[0];
    let len2 = d.norm_squared();
    if len2 == 0.0 {
        // Both are points: the triangles meet there, if anywhere.
        let scale = scale_of(&pa, &pb);
        return ((long[0] - short[0]).norm() <= 1e-9 * scale).then(|| {
            let p = to_f32(&long[0]);
            [p, p]
        });
    }
    let at = |p: &Point64| (p - long[0]).dot(&d) / len2;
    let (s0, s1) = (at(&short[0]), at(&short[1]));
    let (lo, hi) = (s0.min(s1).max(0.0), s0.max(s1).min(1.0));
    // A gap of rounding's size still counts as touching.
    let slack = 1e-9 * scale_of(&pa, &pb) / len2.sqrt();
    if lo > hi + slack {
        return None;
    }
    let hi = hi.max(lo);
    Some([to_f32(&(long[0] + d * lo)), to_f32(&(long[0] + d * hi))])
}

/// The unit normal of a triangle, `None` if it is degenerate.
fn normal(p: &[Point64; 3]) -> Option<Vector3<f64>> {
    let n = (p[1] - p[0]).cross(&(p[2] - p[0]));
    let len = n.norm();
    (len > 0.0 && len.is_finite()).then(|| n / len)
}

/// Where triangle `p` crosses the plane through `o` with unit normal `n`:
/// the ends of that segment (a point twice where it touches the plane at a
/// corner); `None` if it lies wholly on one side, or in the plane.
fn crossing(p: &[Point64; 3], o: &Point64, n: &Vector3<f64>) -> Option<[Point64; 2]> {
    let d = p.map(|q| n.dot(&(q - o)));
    if d.iter().all(|&x| x > 0.0) || d.iter().all(|&x| x < 0.0) {
        return None;
    }
    if d.iter().all(|&x| x == 0.0) {
        return None;
    }
    let mut ends = [Point64::origin(); 4];
    let mut k = 0;
    for i in 0..3 {
        let j = (i + 1) % 3;
        if d[i] == 0.0 {
            ends[k] = p[i];
            k += 1;
        }
        if (d[i] < 0.0 && d[j] > 0.0) || (d[i] > 0.0 && d[j] < 0.0) {
            let t = d[i] / (d[i] - d[j]);
            ends[k] = p[i] + (p[j] - p[i]) * t;
            k += 1;
        }
    }
    // A corner in the plane and the opposite edge across it, two corners in
    // it, or two edges across it: two ends; one corner touching: one.
    match k {
        0 => None,
        1 => Some([ends[0], ends[0]]),
        _ => Some([ends[0], ends[1]]),
    }
}

/// The size of the two triangles' coordinates, for tolerances.
fn scale_of(a: &[Point64; 3], b: &[Point64; 3]) -> f64 {
    a.iter()
        .chain(b)
        .map(|p| p.coords.amax())
        .fold(1.0, f64::max)
}

fn to_f32(p: &Point64) -> Point {
    p.cast::<f32>()
}

#[cfg(test)]
mod tests {
    use super::intersection_segment;
    use crate::geometry::exact::triangles_intersect_exact;
    use crate::geometry::query_shapes::Ray;
    use crate::geometry::{Point, Triangle};
    use crate::test_rng::unit_floats;

    /// Another way to the same segment: every edge of each triangle cast as
    /// a ray against the other (the watertight ray-triangle test), the two
    /// points found farthest apart.
    fn by_edges(a: &Triangle, b: &Triangle) -> Option<[Point; 2]> {
        let mut points = Vec::new();
        for (s, t) in [(a, b), (b, a)] {
            for (p, q) in s.edges() {
                let len = (q - p).norm();
                let Ok(ray) = Ray::new(p, q - p, len) else {
                    continue;
                };
                if let Some(h) = ray.triangle_hit(t) {
                    let [u, v, w] = h.barycentric;
                    let at = |k: usize| {
                        (u * f64::from(t.a[k]) + v * f64::from(t.b[k]) + w * f64::from(t.c[k]))
                            as f32
                    };
                    points.push(Point::new(at(0), at(1), at(2)));
                }
            }
        }
        let mut best: Option<(f32, [Point; 2])> = None;
        for (i, p) in points.iter().enumerate() {
            for q in &points[i..] {
                let d = (p - q).norm();
                if best.is_none_or(|(b, _)| d > b) {
                    best = Some((d, [*p, *q]));
                }
            }
        }
        best.map(|(_, s)| s)
    }

    fn same_segment(x: [Point; 2], y: [Point; 2], tol: f32) -> bool {
        let close = |p: Point, q: Point| (p - q).norm() <= tol;
        (close(x[0], y[0]) && close(x[1], y[1])) || (close(x[0], y[1]) && close(x[1], y[0]))
    }

    /// Random pairs in general position: the segment is the edges' one
    /// wherever the exact test says they meet, and there is none where it
    /// says they do not.
    #[test]
    fn equals_the_edges_crossings_and_follows_the_exact_test() {
        let mut unit = unit_floats(17);
        let mut point = |_: &mut ()| {
            let mut c = || 2.0 * unit() - 1.0;
            Point::new(c(), c(), c())
        };
        let mut rng = ();
        let (mut met, mut apart) = (0, 0);
        for _ in 0..20_000 {
            let a = Triangle::new(point(&mut rng), point(&mut rng), point(&mut rng));
            let b = Triangle::new(point(&mut rng), point(&mut rng), point(&mut rng));
            let ours = intersection_segment(&a, &b);
            if triangles_intersect_exact(&a, &b) {
                met += 1;
                let s = ours.unwrap_or_else(|| panic!("{a:?} and {b:?} meet: no segment"));
                let e = by_edges(&a, &b).expect("meeting triangles: an edge crosses");
                assert!(same_segment(s, e, 2e-5), "{a:?} {b:?}: {s:?} against {e:?}");
            } else {
                apart += 1;
                assert_eq!(ours, None, "{a:?} and {b:?} do not meet");
            }
        }
        assert!(met > 2_000 && apart > 2_000, "{met} met, {apart} apart");
    }

    #[test]
    fn coplanar_degenerate_and_touching_cases() {
        let t = Triangle::new(
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
        );
        // In one plane: no segment.
        let shifted = Triangle::new(
            Point::new(0.2, 0.2, 0.0),
            Point::new(1.2, 0.2, 0.0),
            Point::new(0.2, 1.2, 0.0),
        );
        assert_eq!(intersection_segment(&t, &shifted), None);
        // Degenerate (three corners on a line): no plane, no segment.
        let line = Triangle::new(
            Point::new(0.1, 0.1, -1.0),
            Point::new(0.1, 0.1, 0.0),
            Point::new(0.1, 0.1, 1.0),
        );
        assert_eq!(intersection_segment(&t, &line), None);
        // A corner resting on the face: the point twice.
        let resting = Triangle::new(
            Point::new(0.25, 0.25, 0.0),
            Point::new(0.5, 0.25, 1.0),
            Point::new(0.25, 0.5, 1.0),
        );
        let [p, q] = intersection_segment(&t, &resting).unwrap();
        assert_eq!(p, q);
        assert!((p - Point::new(0.25, 0.25, 0.0)).norm() < 1e-7);
    }
}
