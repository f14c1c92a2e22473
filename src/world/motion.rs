//! How a rigid object moves: its pose (object frame → world) at any time.
//!
//! Keyframed motions are what scenario files give (`[[objects]] motion`,
//! docs/scenarios.md); a room's own doors keep their periodic swing
//! ([`RigidMotion`]). Between keys the motion is interpolated linearly (in
//! position, yaw or hinge angle); before the first key and after the last it
//! holds the end key's pose.

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

use crate::environment::RigidMotion;
use cornertree::geometry::Real;

/// An object's motion over world time (seconds).
#[derive(Clone, Debug, PartialEq)]
pub enum Motion {
    /// A room object's periodic motion (a door's swing), from its rest pose.
    Periodic(RigidMotion),
    /// The object's origin through `positions` at `times` (strictly
    /// increasing), turned by `yaw_degrees` about +Y (one per key).
    Waypoints {
        times: Vec<Real>,
        positions: Vec<Vector3<Real>>,
        yaw_degrees: Vec<Real>,
    },
    /// Turned by `yaw_degrees` about +Y, then rotated about the axis through
    /// `pivot` along `axis` by `degrees` at `times`, the object's origin at
    /// `pivot`.
    Hinge {
        pivot: Vector3<Real>,
        axis: Unit<Vector3<Real>>,
        yaw_degrees: Real,
        times: Vec<Real>,
        degrees: Vec<Real>,
    },
}

/// Index of the key interval holding `t` and the fraction into it.
fn locate(times: &[Real], t: Real) -> (usize, Real) {
    if times.len() < 2 || t <= times[0] {
        return (0, 0.0);
    }
    let last = times.len() - 1;
    if t >= times[last] {
        return (last - 1, 1.0);
    }
    // First key after t.
    let i = times.partition_point(|&k| k <= t).clamp(1, last);
    let (a, b) = (times[i - 1], times[i]);
    (i - 1, ((t - a) / (b - a)).clamp(0.0, 1.0))
}

fn lerp(a: Real, b: Real, f: Real) -> Real {
    a + (b - a) * f
}

fn yaw(degrees: Real) -> UnitQuaternion<Real> {
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), degrees.to_radians())
}

impl Motion {
    /// The object's pose at world time `t`: world = pose · object frame.
    pub fn pose_at(&self, t: Real) -> Isometry3<Real> {
        match self {
            Motion::Periodic(m) => m.transform_at(t),
            Motion::Waypoints {
                times,
                positions,
                yaw_degrees,
            } => {
                if times.len() == 1 {
                    return Isometry3::from_parts(
                        Translation3::from(positions[0]),
                        yaw(yaw_degrees[0]),
                    );
                }
                let (i, f) = locate(times, t);
                let p = positions[i].lerp(&positions[i + 1], f);
                let y = lerp(yaw_degrees[i], yaw_degrees[i + 1], f);
                Isometry3::from_parts(Translation3::from(p), yaw(y))
            }
            Motion::Hinge {
                pivot,
                axis,
                yaw_degrees,
                times,
                degrees,
            } => {
                let angle = if times.len() == 1 {
                    degrees[0]
                } else {
                    let (i, f) = locate(times, t);
                    lerp(degrees[i], degrees[i + 1], f)
                };
                let turn = UnitQuaternion::from_axis_angle(axis, angle.to_radians());
                Isometry3::from_parts(Translation3::from(*pivot), turn * yaw(*yaw_degrees))
            }
        }
    }
}
