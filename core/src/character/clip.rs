//! Animation clips: keyframed channels on joints, sampled at any time with the
//! glTF 2.0 interpolation rules (STEP, LINEAR with spherical interpolation of
//! rotations, CUBICSPLINE Hermite with in/out tangents).

use nalgebra::{Quaternion, UnitQuaternion, Vector3};

use super::{JointId, Trs};

/// How a channel's values vary between keyframes (glTF's `interpolation`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Interpolation {
    /// Hold each keyframe's value until the next keyframe.
    Step,
    /// Linear for translation and scale, spherical for rotation.
    Linear,
    /// Cubic Hermite spline through the values, with in- and out-tangents.
    CubicSpline,
}

/// Keyframe values. For [`Interpolation::CubicSpline`] each keyframe holds three
/// entries in order: in-tangent, value, out-tangent.
#[derive(Clone, Debug, PartialEq)]
pub enum ChannelValues {
    /// Translations, in the parent joint's space and units.
    Translation(Vec<Vector3<f32>>),
    /// Quaternions as stored (tangents are not unit quaternions).
    Rotation(Vec<Quaternion<f32>>),
    /// Scale factors along the joint's local axes.
    Scale(Vec<Vector3<f32>>),
}

impl ChannelValues {
    fn len(&self) -> usize {
        match self {
            ChannelValues::Translation(v) | ChannelValues::Scale(v) => v.len(),
            ChannelValues::Rotation(v) => v.len(),
        }
    }
}

/// Keyframes animating one property (translation, rotation or scale) of one joint.
#[derive(Clone, Debug, PartialEq)]
pub struct Channel {
    /// The animated joint.
    pub joint: JointId,
    /// How values vary between keyframes.
    pub interpolation: Interpolation,
    /// Keyframe times in seconds, strictly increasing.
    pub times: Vec<f32>,
    /// The keyframe values, which also say which property is animated.
    pub values: ChannelValues,
}

/// Why a channel cannot be sampled.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum ChannelError {
    /// A channel has no keyframe times.
    #[error("channel {channel}: no keyframes")]
    Empty {
        /// Index of the channel in the clip.
        channel: usize,
    },
    /// A channel's keyframe times are not all finite or not strictly increasing.
    #[error("channel {channel}: keyframe times are not finite and increasing")]
    BadTimes {
        /// Index of the channel in the clip.
        channel: usize,
    },
    /// A channel's value count does not fit its keyframes (one value per
    /// keyframe, three for a cubic spline).
    #[error(
        "channel {channel}: {values} values for {times} keyframes ({interpolation:?} needs {expected})"
    )]
    ValueCount {
        /// Index of the channel in the clip.
        channel: usize,
        /// Number of values given.
        values: usize,
        /// Number of keyframe times.
        times: usize,
        /// The channel's interpolation.
        interpolation: Interpolation,
        /// Number of values that interpolation needs.
        expected: usize,
    },
    /// A channel animates a joint the skeleton does not have.
    #[error("channel {channel}: targets joint {joint}, but the skeleton has {joints}")]
    JointOutOfRange {
        /// Index of the channel in the clip.
        channel: usize,
        /// The joint index it targets.
        joint: usize,
        /// Number of joints in the skeleton.
        joints: usize,
    },
}

/// A named animation.
#[derive(Clone, Debug, PartialEq)]
pub struct Clip {
    /// The clip's name, for choosing it (from glTF, the animation's name or
    /// `"animation N"`).
    pub name: String,
    /// The channels, each animating one property of one joint.
    pub channels: Vec<Channel>,
}

impl Clip {
    /// Checks every channel against a skeleton of `joint_count` joints.
    pub fn new(
        name: String,
        channels: Vec<Channel>,
        joint_count: usize,
    ) -> Result<Self, ChannelError> {
        for (i, c) in channels.iter().enumerate() {
            if c.times.is_empty() {
                return Err(ChannelError::Empty { channel: i });
            }
            if !c.times.iter().all(|t| t.is_finite()) || c.times.windows(2).any(|w| w[1] <= w[0]) {
                return Err(ChannelError::BadTimes { channel: i });
            }
            let per = if c.interpolation == Interpolation::CubicSpline {
                3
            } else {
                1
            };
            if c.values.len() != per * c.times.len() {
                return Err(ChannelError::ValueCount {
                    channel: i,
                    values: c.values.len(),
                    times: c.times.len(),
                    interpolation: c.interpolation,
                    expected: per * c.times.len(),
                });
            }
            if c.joint.index() >= joint_count {
                return Err(ChannelError::JointOutOfRange {
                    channel: i,
                    joint: c.joint.index(),
                    joints: joint_count,
                });
            }
        }
        Ok(Self { name, channels })
    }

    /// Time of the first keyframe of any channel.
    pub fn start(&self) -> f32 {
        self.channels
            .iter()
            .map(|c| c.times[0])
            .fold(f32::INFINITY, f32::min)
            .min(f32::INFINITY)
    }

    /// Time of the last keyframe of any channel (0 for a clip with no channels).
    pub fn end(&self) -> f32 {
        self.channels
            .iter()
            .map(|c| *c.times.last().unwrap())
            .fold(0.0, f32::max)
    }

    /// Length in seconds from the first to the last keyframe.
    pub fn duration(&self) -> f32 {
        if self.channels.is_empty() {
            0.0
        } else {
            self.end() - self.start()
        }
    }

    /// Local transforms at time `t` (seconds, clamped to the keyframes):
    /// `rest` with every animated property replaced. No allocation.
    pub fn sample(&self, t: f32, rest: &[Trs], out: &mut [Trs]) {
        out.copy_from_slice(rest);
        for c in &self.channels {
            let trs = &mut out[c.joint.index()];
            match &c.values {
                ChannelValues::Translation(v) => trs.translation = sample_vec(c, v, t),
                ChannelValues::Scale(v) => trs.scale = sample_vec(c, v, t),
                ChannelValues::Rotation(q) => trs.rotation = sample_rot(c, q, t),
            }
        }
    }
}

/// Keyframe segment `k` (with `times[k] <= t < times[k+1]`) and the fraction
/// within it; `None` past either end (then `k` is the end keyframe).
fn locate(times: &[f32], t: f32) -> (usize, Option<f32>) {
    if t <= times[0] {
        return (0, None);
    }
    let last = times.len() - 1;
    if t >= times[last] {
        return (last, None);
    }
    let k = times.partition_point(|&x| x <= t) - 1;
    let s = (t - times[k]) / (times[k + 1] - times[k]);
    (k, Some(s))
}

/// Cubic Hermite weights for value k, out-tangent k, value k+1, in-tangent k+1.
fn hermite(s: f32) -> [f32; 4] {
    let (s2, s3) = (s * s, s * s * s);
    [
        2.0 * s3 - 3.0 * s2 + 1.0,
        s3 - 2.0 * s2 + s,
        -2.0 * s3 + 3.0 * s2,
        s3 - s2,
    ]
}

fn sample_vec(c: &Channel, v: &[Vector3<f32>], t: f32) -> Vector3<f32> {
    let (k, s) = locate(&c.times, t);
    match (c.interpolation, s) {
        (Interpolation::CubicSpline, None) => v[3 * k + 1],
        (_, None) => v[k],
        (Interpolation::Step, Some(_)) => v[k],
        (Interpolation::Linear, Some(s)) => v[k].lerp(&v[k + 1], s),
        (Interpolation::CubicSpline, Some(s)) => {
            let td = c.times[k + 1] - c.times[k];
            let h = hermite(s);
            v[3 * k + 1] * h[0]
                + v[3 * k + 2] * (h[1] * td)
                + v[3 * k + 4] * h[2]
                + v[3 * k + 3] * (h[3] * td)
        }
    }
}

/// Spherical linear interpolation along the shorter arc. The angle comes from
/// `2·atan2(|a − b|, |a + b|)`, which stays accurate in `f32` for nearly equal
/// rotations (nalgebra's `try_slerp` takes `acos` of the dot product, which
/// loses them, and returns `a` unchanged once the dot product rounds to 1).
fn slerp(a: UnitQuaternion<f32>, b: UnitQuaternion<f32>, s: f32) -> UnitQuaternion<f32> {
    let qa = a.into_inner();
    let mut qb = b.into_inner();
    if qa.coords.dot(&qb.coords) < 0.0 {
        qb = -qb;
    }
    let theta = 2.0 * (qa - qb).norm().atan2((qa + qb).norm());
    let sin = theta.sin();
    let (wa, wb) = if sin < 1e-6 {
        (1.0 - s, s)
    } else {
        (((1.0 - s) * theta).sin() / sin, (s * theta).sin() / sin)
    };
    UnitQuaternion::from_quaternion(qa * wa + qb * wb)
}

fn sample_rot(c: &Channel, q: &[Quaternion<f32>], t: f32) -> UnitQuaternion<f32> {
    let (k, s) = locate(&c.times, t);
    let unit = |q: Quaternion<f32>| {
        if q.norm() > 0.0 {
            UnitQuaternion::from_quaternion(q)
        } else {
            UnitQuaternion::identity()
        }
    };
    match (c.interpolation, s) {
        (Interpolation::CubicSpline, None) => unit(q[3 * k + 1]),
        (_, None) => unit(q[k]),
        (Interpolation::Step, Some(_)) => unit(q[k]),
        (Interpolation::Linear, Some(s)) => slerp(unit(q[k]), unit(q[k + 1]), s),
        (Interpolation::CubicSpline, Some(s)) => {
            let td = c.times[k + 1] - c.times[k];
            let h = hermite(s);
            unit(
                q[3 * k + 1] * h[0]
                    + q[3 * k + 2] * (h[1] * td)
                    + q[3 * k + 4] * h[2]
                    + q[3 * k + 3] * (h[3] * td),
            )
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clip(interpolation: Interpolation, times: Vec<f32>, values: ChannelValues) -> Clip {
        Clip::new(
            "c".into(),
            vec![Channel {
                joint: JointId(0),
                interpolation,
                times,
                values,
            }],
            1,
        )
        .unwrap()
    }

    fn at(c: &Clip, t: f32) -> Trs {
        let mut out = [Trs::IDENTITY];
        c.sample(t, &[Trs::IDENTITY], &mut out);
        out[0]
    }

    #[test]
    fn step_linear_and_clamping() {
        let v = vec![Vector3::new(0.0, 0.0, 0.0), Vector3::new(2.0, 0.0, 0.0)];
        let lin = clip(
            Interpolation::Linear,
            vec![1.0, 2.0],
            ChannelValues::Translation(v.clone()),
        );
        assert_eq!(at(&lin, 1.5).translation.x, 1.0);
        assert_eq!(at(&lin, 0.0).translation.x, 0.0);
        assert_eq!(at(&lin, 9.0).translation.x, 2.0);
        let step = clip(
            Interpolation::Step,
            vec![1.0, 2.0],
            ChannelValues::Translation(v),
        );
        assert_eq!(at(&step, 1.99).translation.x, 0.0);
        assert_eq!(at(&step, 2.0).translation.x, 2.0);
        assert_eq!(lin.duration(), 1.0);
    }

    #[test]
    fn rotation_slerps_halfway() {
        let a = UnitQuaternion::identity();
        let b = UnitQuaternion::from_euler_angles(0.0, 0.0, 1.0);
        let c = clip(
            Interpolation::Linear,
            vec![0.0, 1.0],
            ChannelValues::Rotation(vec![*a.quaternion(), *b.quaternion()]),
        );
        assert!((at(&c, 0.5).rotation.angle() - 0.5).abs() < 1e-5);
    }

    #[test]
    fn slerp_interpolates_nearly_equal_rotations() {
        // 2e-4 rad apart: the dot product rounds to 1 in f32.
        let a = UnitQuaternion::identity();
        let b = UnitQuaternion::from_euler_angles(0.0, 0.0, 2e-4);
        let c = clip(
            Interpolation::Linear,
            vec![0.0, 1.0],
            ChannelValues::Rotation(vec![*a.quaternion(), *b.quaternion()]),
        );
        assert!((at(&c, 0.5).rotation.angle() - 1e-4).abs() < 1e-7);
        // Opposite signs take the shorter arc.
        let d = clip(
            Interpolation::Linear,
            vec![0.0, 1.0],
            ChannelValues::Rotation(vec![
                *a.quaternion(),
                -*UnitQuaternion::from_euler_angles(0.0, 0.0, 1.0).quaternion(),
            ]),
        );
        assert!((at(&d, 0.5).rotation.angle() - 0.5).abs() < 1e-5);
    }

    #[test]
    fn cubic_spline_with_zero_tangents_hits_keys_and_is_smooth() {
        let z = Vector3::zeros();
        let v = vec![
            z,
            Vector3::new(0.0, 0.0, 0.0),
            z,
            z,
            Vector3::new(4.0, 0.0, 0.0),
            z,
        ];
        let c = clip(
            Interpolation::CubicSpline,
            vec![0.0, 1.0],
            ChannelValues::Translation(v),
        );
        assert_eq!(at(&c, 0.0).translation.x, 0.0);
        assert_eq!(at(&c, 1.0).translation.x, 4.0);
        assert!((at(&c, 0.5).translation.x - 2.0).abs() < 1e-6);
        assert!(
            at(&c, 0.25).translation.x < 1.0,
            "ease-in with zero tangents"
        );
    }

    #[test]
    fn bad_channels_are_rejected() {
        let v = ChannelValues::Scale(vec![Vector3::zeros()]);
        let ch = |times: Vec<f32>, joint| Channel {
            joint: JointId(joint),
            interpolation: Interpolation::Linear,
            times,
            values: v.clone(),
        };
        assert!(matches!(
            Clip::new("x".into(), vec![ch(vec![], 0)], 1),
            Err(ChannelError::Empty { .. })
        ));
        assert!(matches!(
            Clip::new("x".into(), vec![ch(vec![0.0, 1.0], 0)], 1),
            Err(ChannelError::ValueCount { .. })
        ));
        assert!(matches!(
            Clip::new("x".into(), vec![ch(vec![0.0], 3)], 1),
            Err(ChannelError::JointOutOfRange { .. })
        ));
        assert!(matches!(
            Clip::new("x".into(), vec![ch(vec![f32::NAN], 0)], 1),
            Err(ChannelError::BadTimes { .. })
        ));
    }
}
