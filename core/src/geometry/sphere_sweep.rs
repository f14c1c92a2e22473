//! A sphere moving over one frame step: its interpolated and swept spheres
//! (continuous detection; the argument that they hold a node's triangles is
//! in `sphere_tree::swept`, docs/ccd.md "Swept hierarchies").

use super::enclosing::round_up;
use super::sphere::distance_f64;
use super::{Point, Sphere};

/// Relative growth covering the `f64` arithmetic of a radius (as refit).
pub(crate) const F64_SLACK: f64 = 1e-12;

/// The smallest ball holding both `a` and `b`, its centre rounded to `f32`
/// and its radius grown by that rounding (in `f64`) and rounded up, so both
/// are inside without tolerance.
pub fn enclosing_pair(a: &Sphere, b: &Sphere) -> Sphere {
    let (ra, rb) = (a.radius as f64, b.radius as f64);
    let d = distance_f64(&a.center, &b.center);
    if d + rb <= ra {
        return grown(a, b);
    }
    if d + ra <= rb {
        return grown(b, a);
    }
    // On the segment, `(d + rb − ra) / 2` from `a`'s centre, radius
    // `(d + ra + rb) / 2`; the centre's rounding to `f32` is added to the
    // radius (its 1-norm bounds its length).
    let f = ((d + rb - ra) / (2.0 * d)).clamp(0.0, 1.0);
    let exact = |x: f32, y: f32| x as f64 + (y as f64 - x as f64) * f;
    let e = [
        exact(a.center.x, b.center.x),
        exact(a.center.y, b.center.y),
        exact(a.center.z, b.center.z),
    ];
    let center = Point::new(e[0] as f32, e[1] as f32, e[2] as f32);
    let shift = (center.x as f64 - e[0]).abs()
        + (center.y as f64 - e[1]).abs()
        + (center.z as f64 - e[2]).abs();
    let r = (d + ra + rb) * 0.5 + shift;
    Sphere::new(center, round_up(r * (1.0 + F64_SLACK)))
}

/// `outer` grown, if need be, to hold `inner` (measured from its centre).
fn grown(outer: &Sphere, inner: &Sphere) -> Sphere {
    let need = distance_f64(&outer.center, &inner.center) + inner.radius as f64;
    let r = (outer.radius as f64).max(need * (1.0 + F64_SLACK));
    Sphere::new(outer.center, round_up(r))
}

/// A node's refit spheres at both ends of a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereSweep {
    /// The refit sphere at the start of the step (world).
    pub start: Sphere,
    /// The refit sphere at the end of the step (world).
    pub end: Sphere,
}

impl SphereSweep {
    /// The interpolated sphere at `t ∈ [0, 1]` (module doc), radius rounded up
    /// by the `f64` slack.
    pub fn at(&self, t: f64) -> Sphere {
        let lerp = |x: f32, y: f32| x as f64 + (y as f64 - x as f64) * t;
        let c = Point::new(
            lerp(self.start.center.x, self.end.center.x) as f32,
            lerp(self.start.center.y, self.end.center.y) as f32,
            lerp(self.start.center.z, self.end.center.z) as f32,
        );
        // The exact interpolated centre is within the rounding of `c`.
        let exact = nalgebra::Vector3::new(
            lerp(self.start.center.x, self.end.center.x),
            lerp(self.start.center.y, self.end.center.y),
            lerp(self.start.center.z, self.end.center.z),
        );
        let shift = (exact - c.coords.cast::<f64>()).norm();
        let r = lerp(self.start.radius, self.end.radius) + shift;
        Sphere::new(c, round_up(r * (1.0 + F64_SLACK)))
    }

    /// The swept sphere: holds the node over the whole step.
    pub fn swept(&self) -> Sphere {
        enclosing_pair(&self.start, &self.end)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(x: f32, y: f32, z: f32, r: f32) -> Sphere {
        Sphere::new(Point::new(x, y, z), r)
    }

    #[test]
    fn enclosing_pair_holds_both() {
        for (a, b) in [
            (s(0.0, 0.0, 0.0, 1.0), s(3.0, 0.0, 0.0, 0.5)),
            (s(0.0, 0.0, 0.0, 1.0), s(0.2, 0.1, 0.0, 0.1)),
            (s(0.1, 0.2, 0.3, 0.01), s(0.1, 0.2, 0.3, 2.0)),
            (s(1e3, -2e3, 5.0, 0.3), s(1e3 + 0.1, -2e3, 5.0, 0.3)),
        ] {
            let e = enclosing_pair(&a, &b);
            assert!(e.contains_sphere(&a, 0.0) && e.contains_sphere(&b, 0.0));
            let tight =
                (distance_f64(&a.center, &b.center) + a.radius as f64 + b.radius as f64) / 2.0;
            let tight = tight.max(a.radius as f64).max(b.radius as f64);
            assert!(e.radius as f64 <= tight * (1.0 + 1e-6), "{e:?} vs {tight}");
        }
    }
}
