//! The skeleton: a forest of joints, each with its rest transform relative to
//! its parent and its inverse bind matrix.

use nalgebra::Matrix4;

use super::Trs;

/// Index of a joint in its skeleton (and in a skin's joint list).
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct JointId(pub u16);

impl JointId {
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

#[derive(Clone, Debug, PartialEq)]
pub struct Joint {
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
    #[error("skeleton has no joints")]
    Empty,
    #[error("skeleton has {0} joints; at most 65535 are supported")]
    TooMany(usize),
    #[error("joint {joint} ({name}) has parent {parent}, which does not come before it")]
    ParentNotBefore {
        joint: usize,
        name: String,
        parent: usize,
    },
    #[error("joint {joint} ({name}) has a non-finite rest transform or inverse bind matrix")]
    NonFinite { joint: usize, name: String },
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
    pub fn new(joints: Vec<Joint>, base: Matrix4<f32>) -> Result<Self, SkeletonError> {
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
        let rest = joints.iter().map(|j| j.rest).collect();
        Ok(Self { joints, rest, base })
    }

    pub fn joints(&self) -> &[Joint] {
        &self.joints
    }

    pub fn joint(&self, id: JointId) -> &Joint {
        &self.joints[id.index()]
    }

    pub fn len(&self) -> usize {
        self.joints.len()
    }

    pub fn is_empty(&self) -> bool {
        self.joints.is_empty()
    }

    pub fn base(&self) -> &Matrix4<f32> {
        &self.base
    }

    pub fn parent(&self, id: JointId) -> Option<JointId> {
        self.joints[id.index()].parent
    }

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
