//! Swept spheres of a rigid body's static tree over one frame step
//! (continuous detection; docs/ccd.md, "Swept hierarchies").
//!
//! The body's tree is built once in its own frame; at the two frames its pose
//! is `P₀` and `P₁` (object frame → world). Two motions between the frames
//! are bounded:
//!
//! * **the chord** (what the continuous kernels assume): every vertex on the
//!   straight line from `P₀ x` to `P₁ x`. The ball holding a node's sphere at
//!   both poses holds it, as for a character ([`super::swept`]);
//! * **the rigid motion itself** (the object's keyframed [`RigidPath`]):
//!   rotating, a point leaves that ball in general (half a turn takes a
//!   point at distance `ρ` from the axis across a diameter while the chord
//!   between its ends is short). A curve of length `L` from `A` to `B` stays
//!   within `L / 2` of the midpoint `(A + B) / 2` (`|y − A| + |y − B| ≤ L`
//!   for every point `y` of it). A point `x` of the node moves at most
//!   `L = T + ρ Θ` over the step (`T` the path length of the frame's origin
//!   on the axis, `Θ` the angle turned, `ρ ≤ |c − a| + r` its distance to
//!   the axis through `a`), and its midpoint is within `r` of the centre's
//!   (rigid motion), so the ball at the centre's midpoint of radius
//!   `r + max(|P₁c − P₀c|, L) / 2` holds the node under both motions.
//!   Without rotation and with a straight path, `L = |P₁c − P₀c|`: nothing
//!   is added.

use nalgebra::{Isometry3, Vector3};

use crate::geometry::enclosing::round_up;
use crate::geometry::sphere::distance_f64;
use crate::geometry::{Point, Sphere};

use super::node::{NodeId, SphereTree};
use super::traverse::Hierarchy;

/// How far a rigid body's frame travels over one step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RigidPath {
    /// Pose at the start of the step (object frame → world).
    pub from: Isometry3<f32>,
    /// Pose at the end of the step (object frame → world).
    pub to: Isometry3<f32>,
    /// Path length of the axis point (world units) over the step.
    pub travel: f64,
    /// Angle turned over the step, radians (total, not net).
    pub turn: f64,
    /// A point on the rotation axis, in the object's frame.
    pub axis_point: Vector3<f32>,
}

impl RigidPath {
    /// A still body at `pose`.
    pub fn still(pose: Isometry3<f32>) -> Self {
        Self {
            from: pose,
            to: pose,
            travel: 0.0,
            turn: 0.0,
            axis_point: Vector3::zeros(),
        }
    }

    /// The ball holding a sphere `s` of the object's frame over the step
    /// (module doc), in world coordinates.
    pub fn sweep(&self, s: &Sphere) -> Sphere {
        let a = s.in_frame(&self.from);
        let b = s.in_frame(&self.to);
        let mid = |x: f32, y: f32| ((x as f64 + y as f64) * 0.5) as f32;
        let center = Point::new(
            mid(a.center.x, b.center.x),
            mid(a.center.y, b.center.y),
            mid(a.center.z, b.center.z),
        );
        // The chord: both end spheres, measured from the rounded centre.
        let chord = (distance_f64(&center, &a.center) + a.radius as f64)
            .max(distance_f64(&center, &b.center) + b.radius as f64);
        // The rigid path: about the exact midpoint of the end centres (in
        // `f64`: a sum of two `f32` and a halving), `center` is its rounding.
        let m = (a.center.coords.cast::<f64>() + b.center.coords.cast::<f64>()) * 0.5;
        let shift = (center.coords.cast::<f64>() - m).norm();
        let rho = (s.center.coords - self.axis_point).cast::<f64>().norm() + s.radius as f64;
        let length = self.travel + rho * self.turn;
        let r_end = a.radius.max(b.radius) as f64;
        let rigid = r_end + length * 0.5 + shift;
        Sphere::new(center, round_up(chord.max(rigid) * (1.0 + 1e-12)))
    }
}

/// A rigid body's static tree seen over a step: each node's sphere swept
/// along [`RigidPath`], in world coordinates.
pub struct SweptRigid<'a> {
    /// The body's tree, its spheres in the object's frame.
    pub tree: &'a SphereTree,
    /// How the body moves over the step.
    pub path: RigidPath,
}

impl Hierarchy for SweptRigid<'_> {
    fn tree(&self) -> &SphereTree {
        self.tree
    }

    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.path.sweep(&self.tree.nodes()[id.index()].sphere)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Translation3, UnitQuaternion};

    #[test]
    fn half_a_turn_while_moving_stays_inside() {
        // A point 1 m from a vertical axis that moves 1 m along X while
        // turning half a turn: the ends are 1 m apart, the path swings 1 m
        // out to the side half-way.
        let s = Sphere::new(Point::new(1.0, 0.0, 0.0), 0.01);
        let at = |f: f32| {
            Isometry3::from_parts(
                Translation3::new(f, 0.0, 0.0),
                UnitQuaternion::from_axis_angle(&Vector3::y_axis(), std::f32::consts::PI * f),
            )
        };
        let path = RigidPath {
            from: at(0.0),
            to: at(1.0),
            travel: 1.0,
            turn: std::f64::consts::PI,
            axis_point: Vector3::zeros(),
        };
        let w = path.sweep(&s);
        for i in 0..=64 {
            let p = at(i as f32 / 64.0) * s.center;
            assert!(w.contains_point(&p, 0.0), "{i}: {p:?} outside {w:?}");
        }
        // The ball around both ends alone would not do.
        let chord =
            super::super::swept::enclosing_pair(&s.in_frame(&path.from), &s.in_frame(&path.to));
        assert!(!chord.contains_point(&(at(0.5) * s.center), 0.0));
    }

    #[test]
    fn straight_translation_adds_nothing() {
        let s = Sphere::new(Point::new(0.3, 0.2, 0.1), 0.05);
        let at = |x: f32| Isometry3::translation(x, 0.0, 0.0);
        let path = RigidPath {
            from: at(0.0),
            to: at(1.0),
            travel: 1.0,
            turn: 0.0,
            axis_point: Vector3::zeros(),
        };
        let w = path.sweep(&s);
        assert!((w.radius - 0.55).abs() < 1e-5, "{w:?}");
    }
}
