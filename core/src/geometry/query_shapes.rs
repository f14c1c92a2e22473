//! The shapes an engine asks about (not in the paper): a ray (a half-line
//! or a segment), a ball and a capsule, with the tests a query needs — the
//! shape against a node's sphere (conservative: never says no to a sphere
//! the shape reaches) and against a triangle (in `f64` from the `f32`
//! corners).
//!
//! The ray-triangle test is *watertight* (after Woop, Benthin and Wald,
//! "Watertight ray/triangle intersection", JCGT 2013): the ray is sheared so
//! that it runs along an axis, and each triangle edge gets a signed edge
//! function computed from its two end points alone. The same edge seen from
//! its two triangles gives values of opposite sign bit for bit, and zero
//! counts as inside, so a ray through an edge or a vertex shared by two
//! triangles is never let through between them.

use nalgebra::{Isometry3, Vector3};

use super::closest_point::{Point64, closest_point_on_segment, point_triangle_distance};
use super::{Point, Real, Sphere, Triangle, Vector};

/// Relative widening of the spheres a shape is tested against: a sphere
/// test computed in `f64` from `f32` data is within a few `f64` ulps; this
/// is a millionth of the distances involved, so it never rejects a sphere the
/// shape touches and costs a few spurious descents at most.
const SPHERE_SLACK: f64 = 1e-6;

/// Why a query shape was refused.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum ShapeError {
    /// A value that is not a finite number.
    #[error("{0} is not finite")]
    NonFinite(&'static str),
    /// A ray whose direction has no length.
    #[error("the ray's direction has zero length")]
    ZeroDirection,
    /// A radius or a length below zero.
    #[error("{0} is negative")]
    Negative(&'static str),
}

/// A ray: the points `origin + t·direction` for `0 ≤ t ≤ max_distance`,
/// `direction` of unit length (so `t` is a distance).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Where it starts.
    pub origin: Point,
    /// Its direction, of unit length.
    pub direction: Vector,
    /// How far it goes (`f32::INFINITY`: a half-line).
    pub max_distance: Real,
}

/// Where a ray meets a triangle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayTriangleHit {
    /// Distance from the ray's origin along its unit direction.
    pub distance: f64,
    /// Barycentric coordinates of the point on the triangle's corners
    /// `(a, b, c)`, each in `[0, 1]`, summing to 1.
    pub barycentric: [f64; 3],
}

impl Ray {
    /// The ray from `origin` along `direction` (normalised here) up to
    /// `max_distance` (`f32::INFINITY` for no end).
    ///
    /// ```
    /// use cornertree::geometry::query_shapes::Ray;
    /// use cornertree::geometry::{Point, Vector};
    ///
    /// let r = Ray::new(Point::origin(), Vector::new(0.0, 0.0, -2.0), f32::INFINITY).unwrap();
    /// assert_eq!(r.direction, Vector::new(0.0, 0.0, -1.0));
    /// assert!(Ray::new(Point::origin(), Vector::zeros(), 1.0).is_err());
    /// ```
    pub fn new(origin: Point, direction: Vector, max_distance: Real) -> Result<Self, ShapeError> {
        if !origin.iter().all(|x| x.is_finite()) {
            return Err(ShapeError::NonFinite("the ray's origin"));
        }
        if !direction.iter().all(|x| x.is_finite()) {
            return Err(ShapeError::NonFinite("the ray's direction"));
        }
        if max_distance.is_nan() {
            return Err(ShapeError::NonFinite("the ray's length"));
        }
        if max_distance < 0.0 {
            return Err(ShapeError::Negative("the ray's length"));
        }
        let d = direction.cast::<f64>();
        let len = d.norm();
        if len == 0.0 || !len.is_finite() {
            return Err(ShapeError::ZeroDirection);
        }
        Ok(Self {
            origin,
            direction: (d / len).cast::<f32>(),
            max_distance,
        })
    }

    /// The point at distance `t` along the ray, in `f64`.
    #[inline]
    pub fn at(&self, t: f64) -> Point64 {
        self.origin.cast::<f64>() + self.direction.cast::<f64>() * t
    }

    /// The same ray in another frame (`to` maps this frame into it);
    /// distances are kept.
    pub fn in_frame(&self, to: &Isometry3<Real>) -> Ray {
        Ray {
            origin: to * self.origin,
            direction: to.rotation * self.direction,
            max_distance: self.max_distance,
        }
    }

    /// The part `[t0, t1]` of the ray (clipped to `[0, max_distance]`) that
    /// may lie in `s`, or `None` when the ray surely misses it. Conservative:
    /// the sphere is widened by a millionth relatively.
    #[inline]
    pub fn sphere_interval(&self, s: &Sphere) -> Option<(f64, f64)> {
        let o = self.origin.cast::<f64>();
        let d = self.direction.cast::<f64>();
        let m = s.center.cast::<f64>() - o;
        let along = m.dot(&d);
        let across = m - d * along;
        let scale = f64::from(s.radius) + m.norm();
        let r = f64::from(s.radius) + SPHERE_SLACK * scale;
        let h2 = r * r - across.norm_squared();
        if h2 < 0.0 {
            return None;
        }
        let h = h2.sqrt();
        let (t0, t1) = (
            (along - h).max(0.0),
            (along + h).min(f64::from(self.max_distance)),
        );
        (t0 <= t1).then_some((t0, t1))
    }

    /// Whether the ray may pass through `s`: its nearest point to the
    /// centre (clamped to `[0, max_distance]`) lies within the radius,
    /// widened by a billionth relatively and a millionth of the centre's
    /// distance squared (`f64` rounding here is below 10⁻¹⁵ of those
    /// distances). No square root: the traversal's guard.
    #[inline]
    pub fn reaches_sphere(&self, s: &Sphere) -> bool {
        let o = self.origin.cast::<f64>();
        let d = self.direction.cast::<f64>();
        let m = s.center.cast::<f64>() - o;
        let along = m.dot(&d);
        let max = f64::from(self.max_distance);
        let m2 = m.norm_squared();
        let dist2 = if along <= 0.0 {
            m2
        } else if along >= max {
            (m - d * max).norm_squared()
        } else {
            (m - d * along).norm_squared()
        };
        let r = f64::from(s.radius);
        dist2 <= r * r * (1.0 + 1e-9) + 1e-12 * m2
    }

    /// A sphere holding the ray's points between distances `t0` and `t1`
    /// (finite), rounded outwards.
    pub fn bounding_sphere(&self, t0: f64, t1: f64) -> Sphere {
        let mid = self.at(0.5 * (t0 + t1));
        let half = 0.5 * (t1 - t0);
        let scale = half + mid.coords.norm();
        Sphere::new(
            mid.cast::<f32>(),
            (half + SPHERE_SLACK * scale + 1e-12) as f32 * (1.0 + 4.0 * f32::EPSILON),
        )
    }

    /// Where the ray meets triangle `t` (a closed set), if it does within
    /// `[0, max_distance]`: the watertight test of the module doc, in `f64`.
    /// A ray lying in the triangle's plane meets it nowhere.
    ///
    /// ```
    /// use cornertree::geometry::query_shapes::Ray;
    /// use cornertree::geometry::{Point, Triangle, Vector};
    ///
    /// let t = Triangle::new(
    ///     Point::new(0.0, 0.0, 0.0),
    ///     Point::new(1.0, 0.0, 0.0),
    ///     Point::new(0.0, 1.0, 0.0),
    /// );
    /// let down = |x, y| Ray::new(Point::new(x, y, 2.0), Vector::new(0.0, 0.0, -1.0), 10.0).unwrap();
    /// let hit = down(0.25, 0.5).triangle_hit(&t).unwrap();
    /// assert_eq!(hit.distance, 2.0);
    /// assert_eq!(hit.barycentric, [0.25, 0.25, 0.5]);
    /// assert!(down(0.5, 0.5).triangle_hit(&t).is_some()); // on the long edge
    /// assert!(down(0.6, 0.5).triangle_hit(&t).is_none());
    /// ```
    #[inline]
    pub fn triangle_hit(&self, t: &Triangle) -> Option<RayTriangleHit> {
        let d = self.direction.cast::<f64>();
        // The axis the ray runs most along becomes z; x and y follow it
        // cyclically, swapped when it points down z to keep the winding.
        let kz = d.iamax();
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        let (sx, sy, sz) = (d[kx] / d[kz], d[ky] / d[kz], 1.0 / d[kz]);
        let o = self.origin.cast::<f64>();
        let rel = |p: &Point| p.cast::<f64>() - o;
        let [a, b, c] = [rel(&t.a), rel(&t.b), rel(&t.c)];
        let shear = |p: &Vector3<f64>| (p[kx] - sx * p[kz], p[ky] - sy * p[kz]);
        let ((ax, ay), (bx, by), (cx, cy)) = (shear(&a), shear(&b), shear(&c));
        // Edge functions: u of edge bc (weight of a), v of ca, w of ab.
        let u = cx * by - cy * bx;
        let v = ax * cy - ay * cx;
        let w = bx * ay - by * ax;
        if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
            return None;
        }
        let det = u + v + w;
        if det == 0.0 {
            return None;
        }
        let along = u * (sz * a[kz]) + v * (sz * b[kz]) + w * (sz * c[kz]);
        let distance = along / det;
        if !(0.0..=f64::from(self.max_distance)).contains(&distance) {
            return None;
        }
        Some(RayTriangleHit {
            distance,
            barycentric: [u / det, v / det, w / det],
        })
    }
}

/// A capsule: the points within `radius` of the segment `a b`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Capsule {
    /// One end of its axis.
    pub a: Point,
    /// The other end.
    pub b: Point,
    /// Its radius.
    pub radius: Real,
}

impl Capsule {
    /// The capsule of axis `a b` and `radius`, checked.
    pub fn new(a: Point, b: Point, radius: Real) -> Result<Self, ShapeError> {
        if !a.iter().chain(b.iter()).all(|x| x.is_finite()) {
            return Err(ShapeError::NonFinite("the capsule's axis"));
        }
        if !radius.is_finite() {
            return Err(ShapeError::NonFinite("the capsule's radius"));
        }
        if radius < 0.0 {
            return Err(ShapeError::Negative("the capsule's radius"));
        }
        Ok(Self { a, b, radius })
    }

    /// The same capsule in another frame.
    pub fn in_frame(&self, to: &Isometry3<Real>) -> Capsule {
        Capsule {
            a: to * self.a,
            b: to * self.b,
            radius: self.radius,
        }
    }

    /// A sphere holding the capsule, rounded outwards.
    pub fn bounding_sphere(&self) -> Sphere {
        let (a, b) = (self.a.cast::<f64>(), self.b.cast::<f64>());
        let mid = nalgebra::center(&a, &b);
        let r = 0.5 * (b - a).norm() + f64::from(self.radius);
        let scale = r + mid.coords.norm();
        Sphere::new(
            mid.cast::<f32>(),
            (r + SPHERE_SLACK * scale + 1e-12) as f32 * (1.0 + 4.0 * f32::EPSILON),
        )
    }

    /// Whether the capsule may meet `s` (conservative, as for rays).
    #[inline]
    pub fn reaches_sphere(&self, s: &Sphere) -> bool {
        let c = s.center.cast::<f64>();
        let q = closest_point_on_segment(&c, &self.a.cast(), &self.b.cast());
        let reach = f64::from(s.radius) + f64::from(self.radius);
        let r = reach + SPHERE_SLACK * (reach + c.coords.norm());
        (q - c).norm_squared() <= r * r
    }

    /// Whether the capsule meets triangle `t` (both closed), in `f64`: the
    /// axis crosses the triangle, or lies within `radius` of it.
    pub fn overlaps_triangle(&self, t: &Triangle) -> bool {
        segment_triangle_distance(&self.a, &self.b, t) <= f64::from(self.radius)
    }
}

/// Whether the ball `s` (closed) meets triangle `t` (closed), in `f64`.
#[inline]
pub fn sphere_overlaps_triangle(s: &Sphere, t: &Triangle) -> bool {
    point_triangle_distance(&s.center.cast(), t) <= f64::from(s.radius)
}

/// Whether the query ball `q` may meet the node sphere `s` (conservative).
#[inline]
pub fn sphere_reaches_sphere(q: &Sphere, s: &Sphere) -> bool {
    let (c, d) = (q.center.cast::<f64>(), s.center.cast::<f64>());
    let reach = f64::from(q.radius) + f64::from(s.radius);
    let r = reach + SPHERE_SLACK * (reach + c.coords.norm());
    (c - d).norm_squared() <= r * r
}

/// Distance between the closed segment `p q` and the closed triangle `t`,
/// in `f64`: zero where the segment crosses it; otherwise the least of its
/// ends' distances to the triangle and its distances to the three edges.
///
/// ```
/// use cornertree::geometry::query_shapes::segment_triangle_distance;
/// use cornertree::geometry::{Point, Triangle};
///
/// let t = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(1.0, 0.0, 0.0),
///     Point::new(0.0, 1.0, 0.0),
/// );
/// let d = |p: [f32; 3], q: [f32; 3]| segment_triangle_distance(&p.into(), &q.into(), &t);
/// assert_eq!(d([0.2, 0.2, 1.0], [0.2, 0.2, -1.0]), 0.0); // through the face
/// assert_eq!(d([0.2, 0.2, 1.0], [0.2, 0.2, 3.0]), 1.0); // above it
/// assert_eq!(d([-1.0, 2.0, 0.5], [2.0, -1.0, 0.5]), 0.5); // across over the long edge
/// ```
pub fn segment_triangle_distance(p: &Point, q: &Point, t: &Triangle) -> f64 {
    let pq = (q - p).cast::<f64>();
    let len = pq.norm();
    if len > 0.0
        && let Ok(ray) = Ray::new(*p, q - p, f32::INFINITY)
        && ray.triangle_hit(t).is_some_and(|h| h.distance <= len)
    {
        return 0.0;
    }
    let (p64, q64) = (p.cast::<f64>(), q.cast::<f64>());
    let ends = point_triangle_distance(&p64, t).min(point_triangle_distance(&q64, t));
    t.edges()
        .iter()
        .map(|(u, v)| segment_segment_distance(&p64, &q64, &u.cast(), &v.cast()))
        .fold(ends, f64::min)
}

/// Distance between the closed segments `p1 q1` and `p2 q2` (either may be
/// a point), in `f64`.
///
/// ```
/// use cornertree::geometry::closest_point::Point64;
/// use cornertree::geometry::query_shapes::segment_segment_distance;
///
/// let p = |x, y, z| Point64::new(x, y, z);
/// // Skew lines one apart, crossing within both segments.
/// let d = segment_segment_distance(&p(-1.0, 0.0, 0.0), &p(1.0, 0.0, 0.0), &p(0.0, -1.0, 1.0), &p(0.0, 1.0, 1.0));
/// assert_eq!(d, 1.0);
/// // Parallel, end to end 3 apart.
/// let d = segment_segment_distance(&p(0.0, 0.0, 0.0), &p(1.0, 0.0, 0.0), &p(4.0, 0.0, 0.0), &p(5.0, 0.0, 0.0));
/// assert_eq!(d, 3.0);
/// ```
pub fn segment_segment_distance(p1: &Point64, q1: &Point64, p2: &Point64, q2: &Point64) -> f64 {
    let (d1, d2, r) = (q1 - p1, q2 - p2, p1 - p2);
    let (a, e, f) = (d1.norm_squared(), d2.norm_squared(), d2.dot(&r));
    let (s, t);
    if a == 0.0 && e == 0.0 {
        return r.norm();
    }
    if a == 0.0 {
        s = 0.0;
        t = (f / e).clamp(0.0, 1.0);
    } else {
        let c = d1.dot(&r);
        if e == 0.0 {
            t = 0.0;
            s = (-c / a).clamp(0.0, 1.0);
        } else {
            let b = d1.dot(&d2);
            let denom = a * e - b * b;
            let s0 = if denom > 0.0 {
                ((b * f - c * e) / denom).clamp(0.0, 1.0)
            } else {
                0.0
            };
            let t0 = (b * s0 + f) / e;
            if t0 < 0.0 {
                t = 0.0;
                s = (-c / a).clamp(0.0, 1.0);
            } else if t0 > 1.0 {
                t = 1.0;
                s = ((b - c) / a).clamp(0.0, 1.0);
            } else {
                t = t0;
                s = s0;
            }
        }
    }
    ((p1 + d1 * s) - (p2 + d2 * t)).norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::closest_point::closest_point_on_triangle;

    fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
        Triangle::new(a.into(), b.into(), c.into())
    }

    /// A fan of triangles around a vertex: rays through the shared vertex
    /// and along the shared edges, from many directions, each hit by at
    /// least one triangle of the fan (watertightness).
    #[test]
    fn rays_through_shared_edges_and_vertices_never_leak() {
        let centre = [0.3f32, 0.1, 0.7];
        let ring: Vec<[f32; 3]> = (0..7)
            .map(|k| {
                let a = k as f32 * std::f32::consts::TAU / 7.0;
                [0.3 + a.cos(), 0.1 + a.sin(), 0.7 + 0.2 * (3.0 * a).sin()]
            })
            .collect();
        let fan: Vec<Triangle> = (0..7)
            .map(|k| tri(centre, ring[k], ring[(k + 1) % 7]))
            .collect();
        let mut targets: Vec<Point> = vec![centre.into()];
        for spoke in &ring {
            // Points on each spoke (shared edges).
            for s in [0.1f32, 0.37, 0.5, 0.81] {
                let p = Point::from(centre) + (Point::from(*spoke) - Point::from(centre)) * s;
                targets.push(p);
            }
        }
        let mut rays = 0;
        for target in &targets {
            for (i, from) in [
                [0.0f32, 0.0, 5.0],
                [1.3, -2.1, 4.0],
                [-3.0, 0.7, -2.0],
                [0.9, 0.4, 3.3],
                [2.0, 2.0, 2.0],
            ]
            .iter()
            .enumerate()
            {
                let o = Point::from(*from);
                let r = Ray::new(o, target - o, f32::INFINITY).unwrap();
                let hits = fan.iter().filter(|t| r.triangle_hit(t).is_some()).count();
                assert!(hits >= 1, "ray {i} to {target:?} slipped through the fan");
                rays += 1;
            }
        }
        assert_eq!(rays, targets.len() * 5);
    }

    /// Random rays against random triangles: hit or miss as the exact
    /// orientation tests say, wherever they are not borderline; the hit
    /// point lies on the triangle and on the ray.
    #[test]
    fn agrees_with_exact_orientation_away_from_edges() {
        use rand::{Rng, SeedableRng, rngs::SmallRng};
        let mut rng = SmallRng::seed_from_u64(7);
        let mut p = || {
            Point::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
        };
        let (mut hits, mut decided) = (0, 0);
        for _ in 0..20_000 {
            let t = Triangle::new(p(), p(), p());
            let o = p() * 3.0;
            let target = p();
            let r = Ray::new(o, target - o, f32::INFINITY).unwrap();
            let far = r.at(64.0);
            let [o64, a, b, c] = [o.cast::<f64>(), t.a.cast(), t.b.cast(), t.c.cast()];
            let orient = |p: &Point64, q: &Point64, r: &Point64, s: &Point64| {
                let co = |x: &Point64| robust::Coord3D {
                    x: x.x,
                    y: x.y,
                    z: x.z,
                };
                robust::orient3d(co(p), co(q), co(r), co(s))
            };
            let e = [
                orient(&o64, &far, &a, &b),
                orient(&o64, &far, &b, &c),
                orient(&o64, &far, &c, &a),
            ];
            let sides = [orient(&a, &b, &c, &o64), orient(&a, &b, &c, &far)];
            let scale = 1e-9;
            if e.iter().chain(&sides).any(|x| x.abs() < scale) {
                continue; // borderline: either answer is within rounding
            }
            decided += 1;
            let exact = (e.iter().all(|x| *x > 0.0) || e.iter().all(|x| *x < 0.0))
                && (sides[0] > 0.0) != (sides[1] > 0.0);
            let ours = r.triangle_hit(&t);
            assert_eq!(ours.is_some(), exact, "ray {r:?} triangle {t:?}");
            if let Some(h) = ours {
                hits += 1;
                let q = r.at(h.distance);
                let on = closest_point_on_triangle(&q, &t);
                assert!((on - q).norm() < 1e-9, "hit point off the triangle");
                let [u, v, w] = h.barycentric;
                let back = a.coords * u + b.coords * v + c.coords * w;
                assert!((back - q.coords).norm() < 1e-9);
            }
        }
        assert!(
            decided > 19_000 && hits > 1_000,
            "{decided} decided, {hits} hits"
        );
    }

    /// Spheres: an interval exactly where the ray passes within the radius.
    #[test]
    fn sphere_interval_brackets_the_crossing() {
        let r = Ray::new(Point::new(0.0, 0.0, 0.0), Vector::new(1.0, 0.0, 0.0), 10.0).unwrap();
        let (t0, t1) = r
            .sphere_interval(&Sphere::new(Point::new(5.0, 0.6, 0.0), 1.0))
            .unwrap();
        assert!((t0 - 4.2).abs() < 1e-5 && (t1 - 5.8).abs() < 1e-5);
        assert!(
            r.sphere_interval(&Sphere::new(Point::new(5.0, 1.01, 0.0), 1.0))
                .is_none()
        );
        // Behind the origin, beyond the end.
        assert!(
            r.sphere_interval(&Sphere::new(Point::new(-3.0, 0.0, 0.0), 1.0))
                .is_none()
        );
        assert!(
            r.sphere_interval(&Sphere::new(Point::new(12.0, 0.0, 0.0), 1.0))
                .is_none()
        );
        // The origin inside: starts at 0.
        assert_eq!(
            r.sphere_interval(&Sphere::new(Point::new(0.5, 0.0, 0.0), 1.0))
                .unwrap()
                .0,
            0.0
        );
        // The guard agrees with the interval away from tangency.
        for (c, yes) in [
            ([5.0, 0.99, 0.0], true),
            ([5.0, 1.01, 0.0], false),
            ([-0.5, 0.8, 0.0], true),
            ([-1.2, 0.0, 0.0], false),
            ([10.9, 0.0, 0.0], true),
            ([11.1, 0.0, 0.0], false),
        ] {
            let s = Sphere::new(Point::from(c), 1.0);
            assert_eq!(r.reaches_sphere(&s), yes, "{c:?}");
            assert_eq!(r.sphere_interval(&s).is_some(), yes, "{c:?}");
        }
        // The bounding sphere of a stretch holds both its ends.
        let b = r.bounding_sphere(2.0, 7.0);
        assert!(b.contains_point(&Point::new(2.0, 0.0, 0.0), 0.0));
        assert!(b.contains_point(&Point::new(7.0, 0.0, 0.0), 0.0));
    }

    /// Capsules and balls against triangles, by distance; segment-segment
    /// distance against a dense sampling of both segments.
    #[test]
    fn capsule_and_ball_distances() {
        let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let cap = |a: [f32; 3], b: [f32; 3], r| Capsule::new(a.into(), b.into(), r).unwrap();
        assert!(cap([0.2, 0.2, 1.0], [0.2, 0.2, -1.0], 0.0).overlaps_triangle(&t));
        assert!(cap([0.2, 0.2, 1.0], [0.2, 0.2, 3.0], 1.0).overlaps_triangle(&t));
        assert!(!cap([0.2, 0.2, 1.0], [0.2, 0.2, 3.0], 0.99).overlaps_triangle(&t));
        assert!(cap([2.0, 0.0, 0.0], [2.0, 2.0, 0.0], 1.0).overlaps_triangle(&t));
        assert!(!cap([2.0, 0.0, 0.0], [2.0, 2.0, 0.0], 0.7).overlaps_triangle(&t));
        assert!(Capsule::new(Point::origin(), Point::origin(), -1.0).is_err());
        assert!(sphere_overlaps_triangle(
            &Sphere::new(Point::new(0.2, 0.2, 0.5), 0.5),
            &t
        ));
        assert!(!sphere_overlaps_triangle(
            &Sphere::new(Point::new(0.2, 0.2, 0.5), 0.49),
            &t
        ));

        use rand::{Rng, SeedableRng, rngs::SmallRng};
        let mut rng = SmallRng::seed_from_u64(3);
        let mut p = || {
            Point64::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
        };
        for _ in 0..300 {
            let (a, b, c, d) = (p(), p(), p(), p());
            let got = segment_segment_distance(&a, &b, &c, &d);
            let mut best = f64::INFINITY;
            for i in 0..=200 {
                let x = a + (b - a) * (i as f64 / 200.0);
                let y = closest_point_on_segment(&x, &c, &d);
                best = best.min((x - y).norm());
            }
            assert!(
                got <= best + 1e-12 && got >= best - 2e-2,
                "{got} vs sampled {best}"
            );
        }
    }
}
