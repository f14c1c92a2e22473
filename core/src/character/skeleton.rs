//! The skeleton: a forest of joints, each with its rest transform relative to
//! its parent and its inverse bind matrix.

use nalgebra::Matrix4;

use super::Trs;

/// Index of a joint in its skeleton (and in a skin's joint list).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct JointId(pub u16);

impl JointId {
    /// The id as an index into the skeleton's joint list.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// One joint: its name, parent, rest transform and inverse bind matrix.
#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
    /// The joint's name (from glTF, the node's name or `"node N"`), for
    /// [`Skeleton::find`] and errors.
    pub name: String,
    /// `None` for a root joint.
    pub parent: Option<JointId>,
    /// Transform relative to the parent joint (or to the skeleton's base for a root).
    pub rest: Trs,
    /// Maps bind-space (mesh) positions into the joint's space at bind time.
    pub inverse_bind: Matrix4<f32>,
}

/// Why joints do not form a usable skeleton.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SkeletonError {
    /// The joint list is empty.
    #[error("skeleton has no joints")]
    Empty,
    /// More joints than a [`JointId`] can number (the count is given).
    #[error("skeleton has {0} joints; at most 65535 are supported")]
    TooMany(usize),
    /// A joint's parent has the same or a later index.
    #[error("joint {joint} ({name}) has parent {parent}, which does not come before it")]
    ParentNotBefore {
        /// Index of the joint.
        joint: usize,
        /// Its name.
        name: String,
        /// Index of its parent.
        parent: usize,
    },
    /// A joint's rest transform or inverse bind matrix has a NaN or infinite entry.
    #[error("joint {joint} ({name}) has a non-finite rest transform or inverse bind matrix")]
    NonFinite {
        /// Index of the joint.
        joint: usize,
        /// Its name.
        name: String,
    },
    /// A joint's inverse bind matrix is not affine beyond rounding.
    #[error(
        "joint {joint} ({name}): the inverse bind matrix's fourth row is {row:?}, not [0, 0, 0, 1]"
    )]
    NotAffine {
        /// Index of the joint.
        joint: usize,
        /// Its name.
        name: String,
        /// The matrix's fourth row as found.
        row: [f32; 4],
    },
    /// The base matrix is not affine beyond rounding (its fourth row is given).
    #[error("the skeleton base's fourth row is {0:?}, not [0, 0, 0, 1]")]
    BaseNotAffine([f32; 4]),
}

/// Deviation of a fourth row from `[0, 0, 0, 1]` accepted as rounding (a
/// matrix inverted in `f32` lands within a few ulps of it).
const AFFINE_TOLERANCE: f32 = 1e-4;

/// `m` with its fourth row set to exactly `[0, 0, 0, 1]`, or `None` when that
/// row is further than [`AFFINE_TOLERANCE`] from it (or not a number). Exact
/// affine matrices keep skinning free of a projective division (see
/// [`PAPER_ROUNDINGS`](super::skinning::PAPER_ROUNDINGS)).
pub(crate) fn exactly_affine(mut m: Matrix4<f32>) -> Option<Matrix4<f32>> {
    let row = [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)] - 1.0];
    if row.iter().any(|x| x.is_nan() || x.abs() > AFFINE_TOLERANCE) {
        return None;
    }
    m[(3, 0)] = 0.0;
    m[(3, 1)] = 0.0;
    m[(3, 2)] = 0.0;
    m[(3, 3)] = 1.0;
    Some(m)
}

fn fourth_row(m: &Matrix4<f32>) -> [f32; 4] {
    [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)]]
}

/// Joints in an order where every parent comes before its children, so world
/// transforms are one forward sweep.
#[derive(Clone, Debug, PartialEq)]
pub struct Skeleton {
    joints: Vec<Joint>,
    /// Rest transforms, kept contiguous for sampling clips without allocation.
    rest: Vec<Trs>,
    /// World transform of the frame the root joints hang from (the glTF nodes
    /// above the skeleton; identity for generated characters).
    base: Matrix4<f32>,
}

impl Skeleton {
    /// Checks the joints; inverse bind matrices and the base get an exact
    /// `[0, 0, 0, 1]` fourth row (a deviation beyond rounding is an error).
    pub fn new(mut joints: Vec<Joint>, base: Matrix4<f32>) -> Result<Self, SkeletonError> {
        if joints.is_empty() {
            return Err(SkeletonError::Empty);
        }
        if joints.len() > u16::MAX as usize {
            return Err(SkeletonError::TooMany(joints.len()));
        }
        for (i, j) in joints.iter().enumerate() {
            if let Some(p) = j.parent
                && p.index() >= i
            {
                return Err(SkeletonError::ParentNotBefore {
                    joint: i,
                    name: j.name.clone(),
                    parent: p.index(),
                });
            }
            let finite = j.rest.translation.iter().all(|c| c.is_finite())
                && j.rest.rotation.coords.iter().all(|c| c.is_finite())
                && j.rest.scale.iter().all(|c| c.is_finite())
                && j.inverse_bind.iter().all(|c| c.is_finite());
            if !finite {
                return Err(SkeletonError::NonFinite {
                    joint: i,
                    name: j.name.clone(),
                });
            }
        }
        for (i, j) in joints.iter_mut().enumerate() {
            j.inverse_bind =
                exactly_affine(j.inverse_bind).ok_or_else(|| SkeletonError::NotAffine {
                    joint: i,
                    name: j.name.clone(),
                    row: fourth_row(&j.inverse_bind),
                })?;
        }
        let base =
            exactly_affine(base).ok_or_else(|| SkeletonError::BaseNotAffine(fourth_row(&base)))?;
        let rest = joints.iter().map(|j| j.rest).collect();
        Ok(Self { joints, rest, base })
    }

    /// All joints, parents before children.
    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    /// Joint `id`.
    pub fn joint(&self, id: JointId) -> &Joint {
        &self.joints[id.index()]
    }

    /// Number of joints.
    pub fn len(&self) -> usize {
        self.joints.len()
    }

    /// Whether there are no joints (never true for a checked skeleton).
    pub fn is_empty(&self) -> bool {
        self.joints.is_empty()
    }

    /// World transform of the frame the root joints hang from.
    pub fn base(&self) -> &Matrix4<f32> {
        &self.base
    }

    /// The parent of joint `id`, `None` for a root.
    pub fn parent(&self, id: JointId) -> Option<JointId> {
        self.joints[id.index()].parent
    }

    /// The first joint named `name`, if any.
    pub fn find(&self, name: &str) -> Option<JointId> {
        self.joints
            .iter()
            .position(|j| j.name == name)
            .map(|i| JointId(i as u16))
    }

    /// The rest pose: every joint at its rest transform.
    pub fn rest_pose(&self) -> Vec<Trs> {
        self.rest.clone()
    }

    /// The rest pose without copying.
    pub fn rest_pose_ref(&self) -> &[Trs] {
        &self.rest
    }

    /// Children of each joint.
    pub fn children(&self) -> Vec<Vec<JointId>> {
        let mut c = vec![Vec::new(); self.joints.len()];
        for (i, j) in self.joints.iter().enumerate() {
            if let Some(p) = j.parent {
                c[p.index()].push(JointId(i as u16));
            }
        }
        c
    }

    /// World matrices of a pose (one local transform per joint).
    pub fn world_matrices(&self, local: &[Trs], world: &mut [Matrix4<f32>]) {
        for (i, j) in self.joints.iter().enumerate() {
            let parent = match j.parent {
                Some(p) => world[p.index()],
                None => self.base,
            };
            world[i] = parent * local[i].to_matrix();
        }
    }

    /// Skinning matrices `world_j · inverse_bind_j`: bind-space position to
    /// posed world position for a vertex rigidly bound to joint `j`.
    pub fn skin_matrices(&self, world: &[Matrix4<f32>], skin: &mut [Matrix4<f32>]) {
        for (i, j) in self.joints.iter().enumerate() {
            skin[i] = world[i] * j.inverse_bind;
        }
    }

    /// Whether `ancestor` is `joint` or above it.
    pub fn is_ancestor_or_self(&self, ancestor: JointId, joint: JointId) -> bool {
        let mut j = Some(joint);
        while let Some(x) = j {
            if x == ancestor {
                return true;
            }
            j = self.parent(x);
        }
        false
    }

    /// Depth of a joint (a root has depth 0).
    pub fn depth(&self, id: JointId) -> usize {
        let mut d = 0;
        let mut j = self.parent(id);
        while let Some(x) = j {
            d += 1;
            j = self.parent(x);
        }
        d
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn joint(inverse_bind: Matrix4<f32>) -> Joint {
        Joint {
            name: "j".into(),
            parent: None,
            rest: Trs::IDENTITY,
            inverse_bind,
        }
    }

    #[test]
    fn fourth_rows_become_exact_or_are_rejected() {
        let mut near = Matrix4::new_translation(&nalgebra::Vector3::new(1.0, 2.0, 3.0));
        near[(3, 3)] = 1.0 + 3e-7;
        near[(3, 1)] = -2e-8;
        let s = Skeleton::new(vec![joint(near)], near).unwrap();
        let ib = s.joint(JointId(0)).inverse_bind;
        assert_eq!(
            [ib[(3, 0)], ib[(3, 1)], ib[(3, 2)], ib[(3, 3)]],
            [0.0, 0.0, 0.0, 1.0]
        );
        assert_eq!(ib[(1, 3)], 2.0);
        assert_eq!(s.base()[(3, 3)], 1.0);

        let mut projective = Matrix4::identity();
        projective[(3, 2)] = 0.5;
        assert!(matches!(
            Skeleton::new(vec![joint(projective)], Matrix4::identity()),
            Err(SkeletonError::NotAffine { joint: 0, .. })
        ));
        assert!(matches!(
            Skeleton::new(vec![joint(Matrix4::identity())], projective),
            Err(SkeletonError::BaseNotAffine(_))
        ));
    }
}
