//! How a rigid object moves: its pose (object frame → world) at any time.
//!
//! Keyframed motions are what scenario files give (`[[objects]] motion`,
//! docs/scenarios.md); a room's own doors keep their periodic swing
//! ([`RigidMotion`]). Between keys the motion is interpolated linearly (in
//! position, yaw or hinge angle); before the first key and after the last it
//! holds the end key's pose.

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion, Vector3};

use cornertree::sphere_tree::swept_rigid::RigidPath;

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

/// An object's path over the step from world time `t0` to `t1`, posed
/// `from` and `to` at those times: the path length of its rotation axis's
/// point and the angle it turns, summed over the motion's pieces inside
/// the step (`sphere_tree::swept_rigid`).
pub fn rigid_path(
    motion: &Motion,
    t0: f32,
    t1: f32,
    from: Isometry3<f32>,
    to: Isometry3<f32>,
) -> RigidPath {
    let mut path = RigidPath {
        from,
        to,
        travel: 0.0,
        turn: 0.0,
        axis_point: Vector3::zeros(),
    };
    match motion {
        Motion::Periodic(RigidMotion::Hinge {
            pivot,
            open,
            period,
            ..
        }) => {
            path.axis_point = pivot.coords;
            path.turn = open.abs() as f64 * phase_variation(*period, t0, t1);
        }
        Motion::Periodic(RigidMotion::Slide { travel, period }) => {
            path.travel = travel.norm() as f64 * phase_variation(*period, t0, t1);
        }
        Motion::Waypoints {
            times,
            positions,
            yaw_degrees,
        } => {
            // Piecewise linear between keys: sum over the pieces in the step.
            let at = |t: f32| {
                keyed(times, t, |i, j, f| {
                    let p = positions[i].lerp(&positions[j], f);
                    let y = yaw_degrees[i] + (yaw_degrees[j] - yaw_degrees[i]) * f;
                    (p.cast::<f64>(), (y as f64).to_radians())
                })
            };
            let (mut p, mut y) = at(t0);
            for t in times
                .iter()
                .copied()
                .filter(|&t| t > t0 && t < t1)
                .chain([t1])
            {
                let (q, z) = at(t);
                path.travel += (q - p).norm();
                path.turn += (z - y).abs();
                (p, y) = (q, z);
            }
        }
        Motion::Hinge { times, degrees, .. } => {
            let at = |t: f32| {
                keyed(times, t, |i, j, f| {
                    ((degrees[i] + (degrees[j] - degrees[i]) * f) as f64).to_radians()
                })
            };
            let mut a = at(t0);
            for t in times
                .iter()
                .copied()
                .filter(|&t| t > t0 && t < t1)
                .chain([t1])
            {
                let b = at(t);
                path.turn += (b - a).abs();
                a = b;
            }
        }
    }
    // Rounding of the keys' interpolation in `f32`: a relative margin.
    path.travel *= 1.0 + 1e-5;
    path.turn *= 1.0 + 1e-5;
    path
}

/// A keyed value at time `t`: `value(i, j, f)` between keys `i` and `j` at
/// fraction `f` (held before the first key and after the last).
fn keyed<R>(times: &[f32], t: f32, value: impl Fn(usize, usize, f32) -> R) -> R {
    let last = times.len() - 1;
    if times.len() == 1 || t <= times[0] {
        return value(0, 0, 0.0);
    }
    if t >= times[last] {
        return value(last, last, 0.0);
    }
    let j = times.partition_point(|&k| k <= t).clamp(1, last);
    let i = j - 1;
    value(
        i,
        j,
        ((t - times[i]) / (times[j] - times[i])).clamp(0.0, 1.0),
    )
}

/// Total variation of `(1 − cos(2πt/P))/2` over `[t0, t1]`: it is monotone
/// between multiples of `P/2`.
fn phase_variation(period: f32, t0: f32, t1: f32) -> f64 {
    let p = period as f64;
    let phase = |t: f64| 0.5 * (1.0 - (std::f64::consts::TAU * t / p).cos());
    let (a, b) = (t0 as f64, t1 as f64);
    let mut sum = 0.0;
    let mut from = a;
    let mut k = (2.0 * a / p).floor() + 1.0;
    while k * p / 2.0 < b {
        let turn = k * p / 2.0;
        sum += (phase(turn) - phase(from)).abs();
        from = turn;
        k += 1.0;
    }
    sum + (phase(b) - phase(from)).abs()
}
