//! A sphere moving over a step against a still triangle's plane: the
//! continuous form of the plane-sphere test (Algorithm 1, paper §5).
//!
//! The sphere is interpolated between its two ends, `c(t) = c₀ + t(c₁ − c₀)`,
//! `r(t) = r₀ + t(r₁ − r₀)` (it holds a node's triangles at every `t`, see
//! `geometry::sphere_sweep`). With `n` the triangle's (unnormalised) normal and
//! `v₀` a corner, `D(t) = n·(c(t) − v₀)` and `R(t) = r(t)‖n‖` are linear in
//! `t`, and the sphere meets the plane at `t` iff `−R(t) ≤ D(t) ≤ R(t)`: two
//! linear inequalities, whose common solutions in `[0, 1]` form an interval.
//! Its start is the time of impact.
//!
//! Conservative in floating point: `D` at both ends and `‖n‖` are computed
//! in `f64` from `f32` inputs (differences exact, the normal's products
//! exact, a handful of roundings after), within `1e-14` of
//! `‖n‖ (|c₀ − v₀|₁ + |c₁ − v₀|₁ + r₀ + r₁)` (1-norms, at least the
//! lengths), which both inequalities are relaxed by; the interval's ends
//! are widened by `1e-12`. So `None` means
//! the sphere stays strictly on one side of the plane over the whole step.
//!
//! Operations: about 40 against a [`StillPlane`] prepared once (two dot
//! products, the margin, the two bounds); the normal adds about 20.

use super::{Sphere, Triangle};

/// Relative bound of the rounding of `D` (module doc), generous.
const ROUNDING: f64 = 1e-14;
/// Widening of the solution interval's ends (divisions' rounding).
const TIME_SLACK: f64 = 1e-12;

/// A still triangle's plane, prepared once (`f64`): a corner `v₀`, the
/// normal `n = (v₁ − v₀) × (v₂ − v₀)` and `‖n‖` (0 for a degenerate
/// triangle, which no sphere meets).
///
/// ```
/// use cornertree::geometry::ccd_sphere_plane::{StillPlane, sweep_meets_plane};
/// use cornertree::geometry::{Point, Sphere, Triangle};
///
/// // A wall in the plane x = 0, prepared once for several sweeps.
/// let wall = Triangle::new(
///     Point::new(0.0, -1.0, -1.0),
///     Point::new(0.0, 2.0, -1.0),
///     Point::new(0.0, -1.0, 2.0),
/// );
/// let plane = StillPlane::new(&wall);
/// let at = |x: f32, r: f32| Sphere::new(Point::new(x, 0.0, 0.0), r);
/// // Moving from x = 1 to x = 0, radius 0.25: touches at x = 0.25, t = 0.75.
/// let toi = plane.sweep_toi(&at(1.0, 0.25), &at(0.0, 0.25)).unwrap();
/// assert!(toi <= 0.75 && toi > 0.75 - 1e-9);
/// // Moving away: no contact.
/// assert_eq!(plane.sweep_toi(&at(1.0, 0.25), &at(2.0, 0.25)), None);
/// for (a, b) in [(at(1.0, 0.25), at(0.0, 0.25)), (at(1.0, 0.25), at(2.0, 0.25))] {
///     assert_eq!(plane.sweep_toi(&a, &b), sweep_meets_plane(&a, &b, &wall));
/// }
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StillPlane {
    v0: [f64; 3],
    n: [f64; 3],
    norm: f64,
}

impl StillPlane {
    /// Prepares the plane of `tri` in `f64`: its first corner, the normal
    /// `(v₁ − v₀) × (v₂ − v₀)` and its length.
    pub fn new(tri: &Triangle) -> Self {
        let w = |p: &crate::geometry::Point| [p.x as f64, p.y as f64, p.z as f64];
        let (v0, v1, v2) = (w(&tri.a), w(&tri.b), w(&tri.c));
        let e1 = [v1[0] - v0[0], v1[1] - v0[1], v1[2] - v0[2]];
        let e2 = [v2[0] - v0[0], v2[1] - v0[1], v2[2] - v0[2]];
        let n = [
            e1[1] * e2[2] - e1[2] * e2[1],
            e1[2] * e2[0] - e1[0] * e2[2],
            e1[0] * e2[1] - e1[1] * e2[0],
        ];
        Self {
            v0,
            n,
            norm: (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt(),
        }
    }

    /// The earliest `t ∈ [0, 1]` at which the sphere interpolated from
    /// `start` to `end` meets this plane (a lower bound, within `1e-12`), or
    /// `None` if it never does (module doc).
    #[inline]
    pub fn sweep_toi(&self, start: &Sphere, end: &Sphere) -> Option<f64> {
        let norm = self.norm;
        if norm == 0.0 {
            return None;
        }
        let (n, v0) = (&self.n, &self.v0);
        let rel = |c: &crate::geometry::Point| {
            [c.x as f64 - v0[0], c.y as f64 - v0[1], c.z as f64 - v0[2]]
        };
        let (q0, q1) = (rel(&start.center), rel(&end.center));
        let dot = |q: [f64; 3]| n[0] * q[0] + n[1] * q[1] + n[2] * q[2];
        // The 1-norm bounds the length (no square root).
        let l1 = |q: [f64; 3]| q[0].abs() + q[1].abs() + q[2].abs();
        let (d0, d1) = (dot(q0), dot(q1));
        let (sr, er) = (start.radius as f64, end.radius as f64);
        let (r0, r1) = (sr * norm, er * norm);
        let e = ROUNDING * norm * (l1(q0) + l1(q1) + sr + er);
        // D − R ≤ e and D + R ≥ −e, each `a + b t ≤ 0` from the ends.
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        for (a, b) in [
            (d0 - r0 - e, (d1 - r1) - (d0 - r0)),
            (-(d0 + r0) - e, -((d1 + r1) - (d0 + r0))),
        ] {
            if b == 0.0 {
                if a > 0.0 {
                    return None;
                }
            } else {
                let root = -a / b;
                if b > 0.0 {
                    hi = hi.min(root + TIME_SLACK);
                } else {
                    lo = lo.max(root - TIME_SLACK);
                }
            }
        }
        (lo <= hi && lo <= 1.0 && hi >= 0.0).then_some(lo.max(0.0))
    }
}

/// The earliest `t ∈ [0, 1]` at which the sphere interpolated from `start`
/// to `end` meets the plane of `tri` (a lower bound, within `1e-12`), or
/// `None` if it never does. A degenerate triangle has no plane: `None`.
///
/// The plane, not the triangle: as in Algorithm 1 (paper §5), the sphere
/// may meet the plane outside the triangle. Closed sets: touching counts.
///
/// ```
/// use cornertree::geometry::ccd_sphere_plane::sweep_meets_plane;
/// use cornertree::geometry::{Point, Sphere, Triangle};
///
/// // A floor in the plane y = 0.
/// let floor = Triangle::new(
///     Point::new(-1.0, 0.0, -1.0),
///     Point::new(-1.0, 0.0, 2.0),
///     Point::new(2.0, 0.0, -1.0),
/// );
/// let ball = |y: f32, r: f32| Sphere::new(Point::new(0.0, y, 0.0), r);
/// // From 0.375 above to 0.125 below, radius 0.125: apart at both ends,
/// // touching at t = 0.5 (0.375 − 0.5 t = 0.125).
/// let toi = sweep_meets_plane(&ball(0.375, 0.125), &ball(-0.125, 0.125), &floor).unwrap();
/// assert!(toi <= 0.5 && toi > 0.5 - 1e-9);
/// // Tangent at the start, then rising: contact at t = 0.
/// assert_eq!(sweep_meets_plane(&ball(0.1, 0.1), &ball(0.5, 0.1), &floor), Some(0.0));
/// // Staying 0.1 above the floor: none.
/// assert_eq!(sweep_meets_plane(&ball(0.3, 0.1), &ball(0.2, 0.1), &floor), None);
/// // A still centre whose radius grows from 0.125 to 0.625 reaches the
/// // floor at radius 0.375, t = 0.5.
/// let toi = sweep_meets_plane(&ball(0.375, 0.125), &ball(0.375, 0.625), &floor).unwrap();
/// assert!(toi <= 0.5 && toi > 0.5 - 1e-9);
/// ```
pub fn sweep_meets_plane(start: &Sphere, end: &Sphere, tri: &Triangle) -> Option<f64> {
    StillPlane::new(tri).sweep_toi(start, end)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn floor() -> Triangle {
        Triangle::new(
            Point::new(-1.0, 0.0, -1.0),
            Point::new(-1.0, 0.0, 2.0),
            Point::new(2.0, 0.0, -1.0),
        )
    }

    fn ball(y: f32, r: f32) -> Sphere {
        Sphere::new(Point::new(0.0, y, 0.0), r)
    }

    #[test]
    fn falling_through_between_frames() {
        // Above at the start, below at the end: meets at t = 0.5
        // (0.375 − 0.5 t = 0.125).
        let toi = sweep_meets_plane(&ball(0.375, 0.125), &ball(-0.125, 0.125), &floor()).unwrap();
        assert!((toi - 0.5).abs() < 1e-9 && toi <= 0.5, "{toi}");
    }

    #[test]
    fn touching_at_the_start_and_staying_clear() {
        assert_eq!(
            sweep_meets_plane(&ball(0.05, 0.1), &ball(0.5, 0.1), &floor()),
            Some(0.0)
        );
        assert_eq!(
            sweep_meets_plane(&ball(0.3, 0.1), &ball(0.2, 0.1), &floor()),
            None
        );
        assert_eq!(
            sweep_meets_plane(&ball(-0.3, 0.1), &ball(-0.2, 0.15), &floor()),
            None
        );
    }

    #[test]
    fn growing_into_the_plane() {
        // Still centre, radius growing from 0.125 to 0.625: meets when
        // r = 0.375, t = 0.5.
        let toi = sweep_meets_plane(&ball(0.375, 0.125), &ball(0.375, 0.625), &floor()).unwrap();
        assert!((toi - 0.5).abs() < 1e-9 && toi <= 0.5, "{toi}");
    }

    #[test]
    fn agrees_with_sampling() {
        let tri = Triangle::new(
            Point::new(0.1, 0.2, 0.3),
            Point::new(1.0, -0.4, 0.2),
            Point::new(-0.3, 0.9, 1.1),
        );
        let mut state = 12345u64;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) as f32 / (1u64 << 31) as f32) * 2.0 - 1.0
        };
        for _ in 0..2000 {
            let a = Sphere::new(Point::new(rnd(), rnd(), rnd()), rnd().abs() * 0.3);
            let b = Sphere::new(Point::new(rnd(), rnd(), rnd()), rnd().abs() * 0.3);
            let got = sweep_meets_plane(&a, &b, &tri);
            let sweep = crate::geometry::sphere_sweep::SphereSweep { start: a, end: b };
            let plane = crate::geometry::plane_sphere::TrianglePlane::<f64>::new(&tri);
            let first = (0..=1000)
                .map(|i| i as f64 / 1000.0)
                .find(|&t| plane.meets(&sweep.at(t)));
            if let Some(t) = first {
                let toi = got.expect("a sampled contact is found");
                assert!(toi <= t + 1e-9, "{toi} after {t}");
            }
        }
    }
}
