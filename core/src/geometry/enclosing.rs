//! Enclosing spheres.
//!
//! - [`triangle_sphere`]: the minimal sphere of a triangle (leaf spheres, §3).
//! - [`points_sphere`]: the minimal sphere of a point set, by Welzl's
//!   randomised incremental algorithm (inner spheres of the tree, §3).
//! - [`spheres_sphere_paper`]: the paper's sphere of spheres (§3, sphere update):
//!   centre at the mean of the centres, radius the largest `‖c_u − c_i‖ + r_i`.
//!
//! Centres are solved in `f64`; the radius is then re-measured from the rounded
//! `f32` centre to every input and rounded up, so the result contains its input
//! whatever the rounding.

use nalgebra::Vector3;

use super::{Point, Real, Sphere, Triangle};

type V = Vector3<f64>;

#[inline]
fn wide(p: &Point) -> V {
    V::new(p.x as f64, p.y as f64, p.z as f64)
}

/// Back to `f32` (exact for points that came from `f32`).
#[inline]
fn narrow(p: &V) -> Point {
    Point::new(p.x as Real, p.y as Real, p.z as Real)
}

/// Sphere at the `f32` rounding of `center` whose radius reaches every point.
fn conservative(center: V, points: impl Iterator<Item = V>) -> Sphere {
    let c = Point::new(center.x as Real, center.y as Real, center.z as Real);
    // Same arithmetic as `Sphere::contains_point`, so containment holds exactly.
    let r = points
        .map(|p| super::sphere::distance_f64(&narrow(&p), &c))
        .fold(0.0f64, f64::max);
    Sphere::new(c, round_up(r))
}

/// Smallest `f32` not below `x`.
#[inline]
pub(crate) fn round_up(x: f64) -> Real {
    let r = x as Real;
    if (r as f64) < x { r.next_up() } else { r }
}

/// Grows `s` (centre kept) just enough to hold `child`; rounding up keeps the
/// containment exact. A child already inside changes nothing.
///
/// ```
/// use cornertree::geometry::enclosing::grow_to_hold;
/// use cornertree::geometry::{Point, Sphere};
///
/// let mut s = Sphere::new(Point::origin(), 1.0);
/// grow_to_hold(&mut s, &Sphere::new(Point::new(0.25, 0.0, 0.0), 0.5));
/// assert_eq!(s, Sphere::new(Point::origin(), 1.0));
/// grow_to_hold(&mut s, &Sphere::new(Point::new(0.0, 2.0, 0.0), 0.5));
/// assert_eq!(s, Sphere::new(Point::origin(), 2.5));
/// ```
pub fn grow_to_hold(s: &mut Sphere, child: &Sphere) {
    let need = super::sphere::distance_f64(&child.center, &s.center) + child.radius as f64;
    if need > s.radius as f64 {
        s.radius = round_up(need);
    }
}

/// The minimal enclosing sphere of a triangle: on the longest edge when the
/// angle opposite it is not acute (degenerate triangles included), else the
/// circumsphere. The leaf spheres of the paper's sphere trees (§3). Solved in
/// `f64`; the `f32` radius is rounded up so that every corner lies inside.
///
/// ```
/// use cornertree::geometry::enclosing::triangle_sphere;
/// use cornertree::geometry::{Point, Triangle};
///
/// // Obtuse at (2, 1, 0): the sphere on the longest edge, not the
/// // circumsphere (centre (2, -1.5, 0), radius 2.5).
/// let obtuse = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(4.0, 0.0, 0.0),
///     Point::new(2.0, 1.0, 0.0),
/// );
/// let s = triangle_sphere(&obtuse);
/// assert_eq!((s.center, s.radius), (Point::new(2.0, 0.0, 0.0), 2.0));
///
/// // Right angle at the origin: centred on the hypotenuse, radius √2.
/// let right = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(2.0, 0.0, 0.0),
///     Point::new(0.0, 2.0, 0.0),
/// );
/// let s = triangle_sphere(&right);
/// assert_eq!(s.center, Point::new(1.0, 1.0, 0.0));
/// assert!(s.radius as f64 >= 2f64.sqrt() && s.radius < 1.4143);
/// assert!(right.vertices().iter().all(|p| s.contains_point(p, 0.0)));
///
/// // Acute (equilateral, side 2): the circumsphere, radius 2 / √3.
/// let h = 3f32.sqrt();
/// let acute = Triangle::new(
///     Point::new(-1.0, 0.0, 0.0),
///     Point::new(1.0, 0.0, 0.0),
///     Point::new(0.0, h, 0.0),
/// );
/// let s = triangle_sphere(&acute);
/// assert!((s.radius - 2.0 / h).abs() < 1e-6);
/// assert!(acute.vertices().iter().all(|p| s.contains_point(p, 0.0)));
/// ```
pub fn triangle_sphere(t: &Triangle) -> Sphere {
    let p = [wide(&t.a), wide(&t.b), wide(&t.c)];
    let center = min_ball_3(&p);
    conservative(center, p.into_iter())
}

/// Centre of the minimal ball of three points.
fn min_ball_3(p: &[V; 3]) -> V {
    // Longest edge (i, j) with k opposite.
    let edges = [(0, 1, 2), (1, 2, 0), (2, 0, 1)];
    let (i, j, k) = edges
        .into_iter()
        .max_by(|a, b| {
            let la = (p[a.0] - p[a.1]).norm_squared();
            let lb = (p[b.0] - p[b.1]).norm_squared();
            la.total_cmp(&lb)
        })
        .unwrap();
    // Angle at k is not acute: the ball on edge ij contains k.
    if (p[i] - p[k]).dot(&(p[j] - p[k])) <= 0.0 {
        return (p[i] + p[j]) * 0.5;
    }
    circumcenter(&p[0], &p[1], &p[2]).unwrap_or((p[i] + p[j]) * 0.5)
}

/// Centre of the circle through three points, in their plane; `None` when collinear.
fn circumcenter(a: &V, b: &V, c: &V) -> Option<V> {
    let u = a - c;
    let v = b - c;
    let n = u.cross(&v);
    let d = 2.0 * n.norm_squared();
    if d <= f64::MIN_POSITIVE {
        return None;
    }
    Some(c + (v * u.norm_squared() - u * v.norm_squared()).cross(&n) / d)
}

/// Centre of the sphere through four points; `None` when coplanar.
fn circumcenter_4(a: &V, b: &V, c: &V, d: &V) -> Option<V> {
    let u = b - a;
    let v = c - a;
    let w = d - a;
    let det = 2.0 * u.dot(&v.cross(&w));
    let scale = u.norm() * v.norm() * w.norm();
    if det.abs() <= 1e-12 * scale || scale == 0.0 {
        return None;
    }
    let x = (v.cross(&w) * u.norm_squared()
        + w.cross(&u) * v.norm_squared()
        + u.cross(&v) * w.norm_squared())
        / det;
    Some(a + x)
}

#[derive(Clone, Copy)]
struct Ball {
    c: V,
    r2: f64,
}

impl Ball {
    fn from_center(c: V, support: &[&V]) -> Ball {
        let r2 = support
            .iter()
            .map(|p| (*p - c).norm_squared())
            .fold(0.0, f64::max);
        Ball { c, r2 }
    }
    /// Inside, with a relative slack so that rounding on support points does not
    /// restart the search forever; the final radius is re-measured anyway.
    #[inline]
    fn contains(&self, p: &V) -> bool {
        (p - self.c).norm_squared() <= self.r2 * (1.0 + 1e-12) + 1e-30
    }
}

/// Smallest ball with `a` and `b` on its boundary.
fn ball_2(a: &V, b: &V) -> Ball {
    Ball::from_center((a + b) * 0.5, &[a, b])
}

/// Smallest ball with `a`, `b`, `c` on its boundary (their circumcircle's ball);
/// for collinear points, the ball on the farthest pair.
fn ball_3(a: &V, b: &V, c: &V) -> Ball {
    match circumcenter(a, b, c) {
        Some(center) => Ball::from_center(center, &[a, b, c]),
        None => {
            let cands = [ball_2(a, b), ball_2(b, c), ball_2(a, c)];
            cands
                .into_iter()
                .max_by(|x, y| x.r2.total_cmp(&y.r2))
                .unwrap()
        }
    }
}

/// Smallest ball with four points on its boundary; for coplanar points, the
/// smallest three-point ball containing the fourth.
fn ball_4(a: &V, b: &V, c: &V, d: &V) -> Ball {
    if let Some(center) = circumcenter_4(a, b, c, d) {
        return Ball::from_center(center, &[a, b, c, d]);
    }
    let pts = [a, b, c, d];
    let mut best: Option<Ball> = None;
    for skip in 0..4 {
        let s: Vec<&V> = (0..4).filter(|&i| i != skip).map(|i| pts[i]).collect();
        let ball = ball_3(s[0], s[1], s[2]);
        if ball.contains(pts[skip]) && best.is_none_or(|b| ball.r2 < b.r2) {
            best = Some(ball);
        }
    }
    best.unwrap_or_else(|| {
        // Numerically unlucky: enclose all four around their mean.
        let c = (a + b + c + d) * 0.25;
        Ball::from_center(c, &pts)
    })
}

/// The minimal enclosing sphere of a point set (Welzl, iterative form with a
/// fixed pseudo-random order so results are reproducible). Empty input gives a
/// zero sphere at the origin. The inner spheres of the paper's sphere trees
/// (§3). Solved in `f64`; the `f32` radius is rounded up so that every point
/// lies inside.
///
/// ```
/// use cornertree::geometry::enclosing::points_sphere;
/// use cornertree::geometry::{Point, Sphere};
///
/// // The corners of the unit cube, and its centre (which changes nothing).
/// let mut cube: Vec<Point> = (0..8)
///     .map(|i| Point::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
///     .collect();
/// cube.push(Point::new(0.5, 0.5, 0.5));
/// let s = points_sphere(&cube);
/// assert!((s.center - Point::new(0.5, 0.5, 0.5)).norm() < 1e-6);
/// assert!((s.radius - 3f32.sqrt() / 2.0).abs() < 1e-6); // half the diagonal
/// assert!(cube.iter().all(|p| s.contains_point(p, 0.0)));
///
/// // Two points: the sphere on their segment.
/// let pair = [Point::new(-3.0, 0.0, 0.0), Point::new(3.0, 0.0, 0.0)];
/// assert_eq!(points_sphere(&pair), Sphere::new(Point::origin(), 3.0));
/// assert_eq!(points_sphere(&[]), Sphere::new(Point::origin(), 0.0));
/// ```
pub fn points_sphere(points: &[Point]) -> Sphere {
    if points.is_empty() {
        return Sphere::new(Point::origin(), 0.0);
    }
    let mut p: Vec<V> = points.iter().map(wide).collect();
    shuffle(&mut p);
    let n = p.len();
    let mut ball = Ball { c: p[0], r2: 0.0 };
    for i in 1..n {
        if ball.contains(&p[i]) {
            continue;
        }
        ball = Ball { c: p[i], r2: 0.0 };
        for j in 0..i {
            if ball.contains(&p[j]) {
                continue;
            }
            ball = ball_2(&p[i], &p[j]);
            for k in 0..j {
                if ball.contains(&p[k]) {
                    continue;
                }
                ball = ball_3(&p[i], &p[j], &p[k]);
                for l in 0..k {
                    if !ball.contains(&p[l]) {
                        ball = ball_4(&p[i], &p[j], &p[k], &p[l]);
                    }
                }
            }
        }
    }
    conservative(ball.c, p.iter().copied())
}

/// Deterministic Fisher–Yates shuffle (xorshift); Welzl's expected linear time
/// needs a random order, not a secret one.
fn shuffle(v: &mut [V]) {
    let mut s: u64 = 0x9E37_79B9_7F4A_7C15 ^ v.len() as u64;
    for i in (1..v.len()).rev() {
        s ^= s << 13;
        s ^= s >> 7;
        s ^= s << 17;
        v.swap(i, (s % (i as u64 + 1)) as usize);
    }
}

/// The paper's enclosing sphere of spheres (§3, sphere update): centre at the
/// mean of the centres, radius `max_i(‖c_u − c_i‖ + r_i)`. Not minimal, but
/// cheap and containing every input. Empty input gives a zero sphere. The
/// radius is rounded up to `f32`.
///
/// ```
/// use cornertree::geometry::enclosing::spheres_sphere_paper;
/// use cornertree::geometry::{Point, Sphere};
///
/// let a = Sphere::new(Point::new(-2.0, 0.0, 0.0), 1.0);
/// let b = Sphere::new(Point::new(2.0, 0.0, 0.0), 1.0);
/// assert_eq!(spheres_sphere_paper(&[a, b]), Sphere::new(Point::origin(), 3.0));
///
/// // Not minimal: the big sphere alone would hold both (radius 3), but the
/// // centre goes to the mean, (1, 0, 0), and the radius to 1 + 3.
/// let big = Sphere::new(Point::origin(), 3.0);
/// let small = Sphere::new(Point::new(2.0, 0.0, 0.0), 0.5);
/// let u = spheres_sphere_paper(&[big, small]);
/// assert_eq!(u, Sphere::new(Point::new(1.0, 0.0, 0.0), 4.0));
/// assert!(u.contains_sphere(&big, 0.0) && u.contains_sphere(&small, 0.0));
/// ```
pub fn spheres_sphere_paper(spheres: &[Sphere]) -> Sphere {
    if spheres.is_empty() {
        return Sphere::new(Point::origin(), 0.0);
    }
    let sum: V = spheres.iter().map(|s| wide(&s.center)).sum();
    let c = sum / spheres.len() as f64;
    let cp = Point::new(c.x as Real, c.y as Real, c.z as Real);
    let r = spheres
        .iter()
        .map(|s| super::sphere::distance_f64(&s.center, &cp) + s.radius as f64)
        .fold(0.0, f64::max);
    Sphere::new(cp, round_up(r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use proptest::prelude::*;

    fn pt() -> impl Strategy<Value = Point> {
        (-10.0f32..10.0, -10.0f32..10.0, -10.0f32..10.0).prop_map(|(x, y, z)| Point::new(x, y, z))
    }

    /// Radius of the minimal ball by brute force over all 2-, 3- and 4-point
    /// supports (tiny inputs only): the smallest candidate containing everything.
    fn brute_force_radius(points: &[Point]) -> f64 {
        let p: Vec<V> = points.iter().map(wide).collect();
        let n = p.len();
        let all_in = |b: &Ball| {
            p.iter()
                .all(|q| (q - b.c).norm_squared() <= b.r2 * (1.0 + 1e-9) + 1e-12)
        };
        let mut best = f64::INFINITY;
        let mut consider = |b: Ball| {
            if all_in(&b) {
                best = best.min(b.r2.sqrt());
            }
        };
        if n == 1 {
            return 0.0;
        }
        for i in 0..n {
            for j in i + 1..n {
                consider(ball_2(&p[i], &p[j]));
                for k in j + 1..n {
                    if let Some(c) = circumcenter(&p[i], &p[j], &p[k]) {
                        consider(Ball::from_center(c, &[&p[i], &p[j], &p[k]]));
                    }
                    for l in k + 1..n {
                        if let Some(c) = circumcenter_4(&p[i], &p[j], &p[k], &p[l]) {
                            consider(Ball::from_center(c, &[&p[i], &p[j], &p[k], &p[l]]));
                        }
                    }
                }
            }
        }
        best
    }

    proptest! {
        #[test]
        fn welzl_is_minimal_and_contains(points in prop::collection::vec(pt(), 1..9)) {
            let s = points_sphere(&points);
            for p in &points {
                prop_assert!(s.contains_point(p, 0.0), "{p:?} outside {s:?}");
            }
            let best = brute_force_radius(&points);
            prop_assert!((s.radius as f64) <= best * (1.0 + 1e-5) + 1e-5, "{} vs brute force {}", s.radius, best);
        }

        #[test]
        fn triangle_sphere_is_minimal_and_contains(a in pt(), b in pt(), c in pt()) {
            let t = Triangle::new(a, b, c);
            let s = triangle_sphere(&t);
            for p in t.vertices() {
                prop_assert!(s.contains_point(&p, 0.0));
            }
            let best = brute_force_radius(&[a, b, c]);
            prop_assert!((s.radius as f64) <= best * (1.0 + 1e-5) + 1e-5);
            // Same answer as the general algorithm.
            let w = points_sphere(&[a, b, c]);
            prop_assert!((w.radius - s.radius).abs() <= 1e-4 * (1.0 + s.radius));
        }

        #[test]
        fn paper_sphere_of_spheres_contains_inputs(
            spheres in prop::collection::vec((pt(), 0.0f32..3.0), 1..12)
        ) {
            let s: Vec<Sphere> = spheres.into_iter().map(|(c, r)| Sphere::new(c, r)).collect();
            let u = spheres_sphere_paper(&s);
            for x in &s {
                prop_assert!(u.contains_sphere(x, 0.0), "{x:?} not in {u:?}");
            }
        }
    }

    #[test]
    fn known_cases() {
        // Right triangle: sphere on the hypotenuse.
        let t = Triangle::new(
            Point::origin(),
            Point::new(2.0, 0.0, 0.0),
            Point::new(0.0, 2.0, 0.0),
        );
        let s = triangle_sphere(&t);
        assert!((s.radius - 2f32.sqrt()).abs() < 1e-6);
        // Equilateral: circumradius side/sqrt(3).
        let h = 3f32.sqrt();
        let t = Triangle::new(
            Point::new(-1.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, h, 0.0),
        );
        assert!((triangle_sphere(&t).radius - 2.0 / h).abs() < 1e-6);
        // Degenerate (all equal): zero radius.
        let p = Point::new(1.0, 2.0, 3.0);
        assert_eq!(triangle_sphere(&Triangle::new(p, p, p)).radius, 0.0);
        // Cube corners: the circumscribed sphere.
        let cube: Vec<Point> = (0..8)
            .map(|i| Point::new((i & 1) as f32, ((i >> 1) & 1) as f32, ((i >> 2) & 1) as f32))
            .collect();
        let s = points_sphere(&cube);
        assert!((s.radius - 3f32.sqrt() / 2.0).abs() < 1e-6);
    }
}
