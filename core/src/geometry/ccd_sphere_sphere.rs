//! Two spheres interpolated over a step: do they meet at some `t ∈ [0, 1]`?
//! The continuous form of the sphere-sphere test (paper §2, §6), tighter
//! than testing the balls around each sphere's two ends.
//!
//! With `cᵢ(t)`, `rᵢ(t)` linear in `t` (a still sphere has equal ends), the
//! centres' difference `q + t v` and the radii's sum `a + t b` are linear,
//! and the spheres meet at `t` iff `|q + t v|² − (a + t b)² ≤ 0` (both radii
//! are non-negative): a quadratic in `t`, whose least value on `[0, 1]` is
//! at an end or at its vertex.
//!
//! Conservative in floating point: evaluated in `f64` from `f32` inputs,
//! the comparison is relaxed by `10⁻¹²` of `(|q|₁ + |v|₁ + a + |b|)²`, far
//! above the few roundings of each term. So `false` means the spheres stay
//! apart over the whole step.
//!
//! Operations: about 40.

use super::Sphere;

/// Relative slack of the comparison (module doc).
const SLACK: f64 = 1e-12;

/// Whether sphere `a` (from `a0` to `a1`) and sphere `b` (from `b0` to
/// `b1`), each interpolated linearly over the step, meet at some time.
///
/// Closed sets (touching counts) and conservative: `false` is certain,
/// `true` may also cover a miss within the slack of the module doc.
///
/// ```
/// use cornertree::geometry::ccd_sphere_sphere::sweeps_meet;
/// use cornertree::geometry::{Point, Sphere};
///
/// let s = |x: f32, y: f32, r: f32| Sphere::new(Point::new(x, y, 0.0), r);
/// let still = s(0.0, 0.0, 0.1);
/// // From x = -1 to x = 1 at y = 0.05: apart at both ends, through the
/// // still ball in the middle of the step.
/// assert!(!s(-1.0, 0.05, 0.1).overlaps(&still) && !s(1.0, 0.05, 0.1).overlaps(&still));
/// assert!(sweeps_meet(&s(-1.0, 0.05, 0.1), &s(1.0, 0.05, 0.1), &still, &still));
/// // The same pass at y = 0.3: never within 0.2 of the centre.
/// assert!(!sweeps_meet(&s(-1.0, 0.3, 0.1), &s(1.0, 0.3, 0.1), &still, &still));
/// // Radii 0.25 and 0.125 passing 0.375 apart: touching at t = 0.5 only.
/// let ball = s(0.0, 0.0, 0.125);
/// assert!(sweeps_meet(&s(-1.0, 0.375, 0.25), &s(1.0, 0.375, 0.25), &ball, &ball));
/// // Both moving: side by side, never; crossing paths at the same time, yes.
/// let (a0, a1) = (s(0.0, 0.0, 0.1), s(5.0, 0.0, 0.1));
/// assert!(!sweeps_meet(&a0, &a1, &s(0.0, 0.5, 0.1), &s(5.0, 0.5, 0.1)));
/// assert!(sweeps_meet(&a0, &a1, &s(2.5, -2.5, 0.1), &s(2.5, 2.5, 0.1)));
/// ```
#[inline]
pub fn sweeps_meet(a0: &Sphere, a1: &Sphere, b0: &Sphere, b1: &Sphere) -> bool {
    let w = |s: &Sphere| [s.center.x as f64, s.center.y as f64, s.center.z as f64];
    let (pa0, pa1, pb0, pb1) = (w(a0), w(a1), w(b0), w(b1));
    let q: [f64; 3] = std::array::from_fn(|k| pa0[k] - pb0[k]);
    let v: [f64; 3] = std::array::from_fn(|k| (pa1[k] - pb1[k]) - q[k]);
    let a = a0.radius as f64 + b0.radius as f64;
    let b = (a1.radius as f64 + b1.radius as f64) - a;
    let dot = |x: &[f64; 3], y: &[f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    let (qq, qv, vv) = (dot(&q, &q), dot(&q, &v), dot(&v, &v));
    // f(t) = A t² + 2 B t + C.
    let (qa, qb, qc) = (vv - b * b, qv - a * b, qq - a * a);
    // 1-norms bound the lengths (no square root).
    let l1 = |x: &[f64; 3]| x[0].abs() + x[1].abs() + x[2].abs();
    let scale = l1(&q) + l1(&v) + a + b.abs();
    let slack = SLACK * scale * scale;
    let f = |t: f64| (qa * t + 2.0 * qb) * t + qc;
    if qc <= slack || f(1.0) <= slack {
        return true;
    }
    qa > 0.0 && {
        let t = -qb / qa;
        t > 0.0 && t < 1.0 && f(t) <= slack
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn s(x: f32, y: f32, r: f32) -> Sphere {
        Sphere::new(Point::new(x, y, 0.0), r)
    }

    #[test]
    fn passing_through_in_the_middle_of_the_step() {
        // From one side of a still ball to the other, apart at both ends.
        let still = s(0.0, 0.0, 0.1);
        assert!(sweeps_meet(
            &s(-1.0, 0.05, 0.1),
            &s(1.0, 0.05, 0.1),
            &still,
            &still
        ));
        // Passing 0.3 above: never within 0.2.
        assert!(!sweeps_meet(
            &s(-1.0, 0.3, 0.1),
            &s(1.0, 0.3, 0.1),
            &still,
            &still
        ));
    }

    #[test]
    fn both_moving_together_never_meet() {
        let (a0, a1) = (s(0.0, 0.0, 0.1), s(5.0, 0.0, 0.1));
        let (b0, b1) = (s(0.0, 0.5, 0.1), s(5.0, 0.5, 0.1));
        assert!(!sweeps_meet(&a0, &a1, &b0, &b1));
        // Crossing paths at the same time.
        let (c0, c1) = (s(2.5, -2.5, 0.1), s(2.5, 2.5, 0.1));
        assert!(sweeps_meet(&a0, &a1, &c0, &c1));
    }

    #[test]
    fn agrees_with_dense_sampling() {
        let mut state = 99u64;
        let mut rnd = || {
            state = state
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((state >> 33) as f32 / (1u64 << 31) as f32) * 2.0 - 1.0
        };
        // Clearly overlapping at a sampled time (f64, a margin of 1e-6).
        let meet_at = |a0: &Sphere, a1: &Sphere, b0: &Sphere, b1: &Sphere, t: f64| {
            let l = |x: f32, y: f32| x as f64 + (y as f64 - x as f64) * t;
            let d = [
                l(a0.center.x, a1.center.x) - l(b0.center.x, b1.center.x),
                l(a0.center.y, a1.center.y) - l(b0.center.y, b1.center.y),
                l(a0.center.z, a1.center.z) - l(b0.center.z, b1.center.z),
            ];
            let dist = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
            dist <= l(a0.radius, a1.radius) + l(b0.radius, b1.radius) - 1e-6
        };
        for _ in 0..3000 {
            let mut ball = || Sphere::new(Point::new(rnd(), rnd(), rnd()), rnd().abs() * 0.4);
            let (a0, a1, b0, b1) = (ball(), ball(), ball(), ball());
            let sampled = (0..=2000).any(|i| meet_at(&a0, &a1, &b0, &b1, i as f64 / 2000.0));
            if sampled {
                assert!(
                    sweeps_meet(&a0, &a1, &b0, &b1),
                    "{a0:?} {a1:?} {b0:?} {b1:?}"
                );
            }
        }
    }
}
