//! Whether a closed polygon, seen along a direction, is a simple polygon:
//! proved by its being strictly star-shaped around one point (ours, after
//! the star-contour idea of Schvartzman, Pérez & Otaduy 2010, which makes
//! the contour test of normal-cone culling linear in the contour's length).
//!
//! Seen along `d` (projected onto a plane normal to `d`), a polygon whose
//! every edge turns strictly counterclockwise around a point `c`, and which
//! winds around `c` exactly once, meets every ray from `c` exactly once: it
//! is a simple closed curve. Both conditions are checked in `f64` with a
//! relative margin far above the rounding of the few operations involved,
//! so a `true` holds for the exact values; near-ties answer `false` (not
//! proved), never a wrong `true`.

use nalgebra::Vector3;

use super::Point;

/// Relative margin of every sign decided here. The values compared are a
/// handful of `f64` operations on exactly represented inputs (relative
/// error about 1e-15), so the margin leaves six orders of magnitude.
const MARGIN: f64 = 1e-9;

/// Whether the closed polygon through `corner(0) .. corner(n - 1)` (and
/// back), seen from the tip of `d` (a unit vector) looking down, is a simple
/// polygon, counterclockwise, star-shaped around its corners' mean.
/// `false` also when it is not proved (fewer than three corners, a corner
/// on a ray it is tested on, a turn within the margin).
pub fn is_star_around_mean(d: &Vector3<f64>, n: usize, corner: impl Fn(usize) -> Point) -> bool {
    if n < 3 {
        return false;
    }
    let p = |k: usize| corner(k).coords.cast::<f64>();
    let mean = (0..n).fold(Vector3::zeros(), |s, k| s + p(k)) / n as f64;
    // A fixed direction in the plane normal to `d`, and the one a quarter
    // turn counterclockwise from it.
    let helper = if d.x.abs() < 0.6 {
        Vector3::x()
    } else {
        Vector3::y()
    };
    let e1 = d.cross(&helper).normalize();
    let e2 = d.cross(&e1);
    // Each corner relative to the centre: one rounding each, relative to
    // the difference itself.
    let first = p(0) - mean;
    let mut r = first;
    let mut crossings = 0u32;
    for k in 0..n {
        let next = if k + 1 == n { first } else { p(k + 1) - mean };
        let (lr, ln) = (r.norm(), next.norm());
        // Strictly counterclockwise around the centre, seen from `d`.
        if d.dot(&r.cross(&next)) <= MARGIN * lr * ln {
            return false;
        }
        // Winding: the edges that cross the ray from the centre along `e1`
        // (below it to above it). A corner too close to the ray's line
        // leaves the count unproved.
        let (y0, y1) = (r.dot(&e2), next.dot(&e2));
        if y0.abs() <= MARGIN * lr {
            return false;
        }
        if y0 < 0.0 && y1 > 0.0 {
            crossings += 1;
        }
        r = next;
    }
    crossings == 1
}

#[cfg(test)]
mod tests {
    use super::is_star_around_mean;
    use crate::geometry::Point;
    use nalgebra::Vector3;

    fn polygon(pts: &[(f32, f32)]) -> Vec<Point> {
        pts.iter()
            .map(|&(x, y)| Point::new(x, y, 0.3 * x - 0.2 * y))
            .collect()
    }

    fn star(d: Vector3<f64>, pts: &[Point]) -> bool {
        is_star_around_mean(&d.normalize(), pts.len(), |k| pts[k])
    }

    /// Simplicity by brute force: no two non-adjacent edges of the projected
    /// polygon meet (for the test polygons, which have no collinear edges).
    fn simple_by_brute_force(pts: &[(f64, f64)]) -> bool {
        let n = pts.len();
        let orient = |a: (f64, f64), b: (f64, f64), c: (f64, f64)| {
            (b.0 - a.0) * (c.1 - a.1) - (b.1 - a.1) * (c.0 - a.0)
        };
        for i in 0..n {
            for j in i + 1..n {
                if j == i + 1 || (i == 0 && j == n - 1) {
                    continue;
                }
                let (a, b) = (pts[i], pts[(i + 1) % n]);
                let (c, e) = (pts[j], pts[(j + 1) % n]);
                if orient(a, b, c) * orient(a, b, e) < 0.0
                    && orient(c, e, a) * orient(c, e, b) < 0.0
                {
                    return false;
                }
            }
        }
        true
    }

    #[test]
    fn convex_counterclockwise_is_proved_clockwise_is_not() {
        let square = polygon(&[(0.0, 0.0), (1.0, 0.0), (1.0, 1.0), (0.0, 1.0)]);
        assert!(star(Vector3::z(), &square));
        // Seen from below, the same polygon turns clockwise.
        assert!(!star(-Vector3::z(), &square));
        let mut reversed = square.clone();
        reversed.reverse();
        assert!(!star(Vector3::z(), &reversed));
    }

    #[test]
    fn twice_around_is_not_simple() {
        // A pentagram's corners in the order that winds twice: every turn is
        // counterclockwise around the centre, but it crosses itself.
        let pts: Vec<(f32, f32)> = (0..5)
            .map(|k| {
                let a = (k as f32) * 4.0 * std::f32::consts::PI / 5.0 + 0.1;
                (a.cos(), a.sin())
            })
            .collect();
        assert!(!star(Vector3::z(), &polygon(&pts)));
    }

    #[test]
    fn a_proved_polygon_is_simple_by_brute_force() {
        // Random wobbly loops around the origin; a `true` must be simple.
        let mut unit = crate::test_rng::unit_floats(7);
        let mut next = move || f64::from(unit());
        let (mut proved, mut refused) = (0, 0);
        for _ in 0..2000 {
            let n = 3 + (next() * 12.0) as usize;
            let mut angles: Vec<f64> = (0..n).map(|_| next() * std::f64::consts::TAU).collect();
            angles.sort_by(f64::total_cmp);
            // Sometimes shuffle two corners, making a loop that may cross.
            if next() < 0.3 {
                let (i, j) = (
                    (next() * n as f64) as usize % n,
                    (next() * n as f64) as usize % n,
                );
                angles.swap(i, j);
            }
            let pts: Vec<(f64, f64)> = angles
                .iter()
                .map(|a| {
                    let r = 0.2 + next();
                    (r * a.cos() + 0.3, r * a.sin() - 0.1)
                })
                .collect();
            let p32: Vec<(f32, f32)> = pts.iter().map(|&(x, y)| (x as f32, y as f32)).collect();
            let back: Vec<(f64, f64)> = p32.iter().map(|&(x, y)| (x as f64, y as f64)).collect();
            if star(Vector3::z(), &polygon(&p32)) {
                proved += 1;
                assert!(simple_by_brute_force(&back), "{back:?}");
            } else {
                refused += 1;
            }
        }
        assert!(
            proved > 100 && refused > 100,
            "{proved} proved, {refused} refused"
        );
    }

    #[test]
    fn a_tilted_view_still_proves_a_convex_polygon() {
        let hexagon: Vec<(f32, f32)> = (0..6)
            .map(|k| {
                let a = k as f32 * std::f32::consts::PI / 3.0;
                (a.cos(), a.sin())
            })
            .collect();
        // Seen along a direction 45 degrees off the polygon's plane normal.
        assert!(star(Vector3::new(0.0, 1.0, 1.0), &polygon(&hexagon)));
        // Edge-on, nothing is proved.
        assert!(!star(Vector3::new(1.0, 0.0, 0.3), &polygon(&hexagon)));
    }
}
