//! How the meshes of a glTF character bind to its one skeleton when they come
//! with several skins, or with no skin below a joint (a prop in a hand).
//!
//! glTF skins a vertex of skin `S` as `Σ_k w_k · World(j_k) · IBM_S(j_k) · v`:
//! the inverse bind matrix belongs to the pair (skin, joint). A [`Character`]
//! has one inverse bind matrix per joint. The loader gives every joint of the
//! merged skeleton the matrix of the first skin that lists it (its
//! *canonical* matrix) and binds each vertex with [`JointSlots::bind`]:
//!
//! 1. **Same matrices.** Every influence's `IBM_S(j)` equals the canonical
//!    one: the vertex is kept as stored, bit for bit (a one-skin file takes
//!    only this path, so it loads exactly as before multi-skin support).
//! 2. **Moved into the canonical bind space.** Otherwise the vertex is moved
//!    to `v' = IBM(j)⁻¹ · IBM_S(j) · v` for its first differing joint `j`,
//!    and kept there when every influence then agrees:
//!    `IBM(j_k) · v' = IBM_S(j_k) · v` within [`CORRECTION_TOLERANCE`] of the
//!    size of the terms. This is the usual case, a skin whose matrices are
//!    another skin's times one mesh transform (`IBM_S = IBM · B`, `v' = B·v`):
//!    the skeleton stays the file's, and the paper's one-joint model (§3) sees
//!    every vertex in one bind space.
//! 3. **Added joint slots.** Where the influences disagree (or the canonical
//!    matrix has no inverse, or `v'` would be out of range), each differing
//!    pair (joint, `IBM_S(j)`) gets a joint slot of its own: a child of `j`
//!    with the identity rest transform and no animation, so its world
//!    transform is `j`'s and its skinning matrix `World(j) · IBM_S(j)`,
//!    exactly glTF's term. Pairs with equal matrices share a slot.
//!
//! Either way linear blend skinning gives glTF's positions. Option 2 is tried
//! before option 3 because added slots are not joints of the file: they
//! lengthen the skeleton, get per-joint trees of their own in the sphere
//! tree, and the paper's one-joint model sees them as children of `j` that
//! never move relative to it.
//!
//! **Rigid meshes.** A mesh node without a skin at or below a joint `J` of
//! the skeleton is bound wholly to `J`: its vertices are first placed in
//! `J`'s frame by the node transforms from `J` down to the node (`L·v`,
//! [`Attachments`]), then bound as a skin whose inverse bind matrix for `J`
//! is the identity. At rest the mesh sits where the file puts it; posed it
//! follows `J` (animation of the nodes between `J` and the mesh is not
//! played: they are not joints).

use std::collections::HashMap;

use nalgebra::{Matrix4, Point3, Vector4};

use super::limits::MAX_COORDINATE;
use crate::character::{Joint, JointId, Skeleton, SkeletonError, Trs};
use crate::geometry::Point;

/// Largest disagreement, relative to the size of the terms, accepted when a
/// vertex is moved into the canonical bind space (option 2 of the module
/// docs): far above the `f32` rounding of stored matrices (about 1e-7), far
/// below anything visible.
pub const CORRECTION_TOLERANCE: f64 = 1e-5;

/// A joint slot added for a (joint, inverse bind matrix) pair.
#[derive(Clone, Debug)]
struct AddedSlot {
    joint: JointId,
    inverse_bind: Matrix4<f32>,
    /// What it binds, for its name: `"skin 2"` or `"rigid meshes"`.
    origin: String,
}

/// The skeleton's joints and the slots added for meshes whose inverse bind
/// matrices differ from them. See the module docs.
#[derive(Debug)]
pub(super) struct JointSlots {
    /// The canonical inverse bind matrix of each joint.
    canonical: Vec<Matrix4<f32>>,
    /// Its inverse, where it has a finite one.
    inverse: Vec<Option<Matrix4<f64>>>,
    /// Slot of each added (joint, matrix bits) pair.
    added_index: HashMap<(u16, [u32; 16]), u16>,
    added: Vec<AddedSlot>,
}

/// How one vertex was bound: the joint slot of each influence, and the bind
/// position when it was moved (`None`: as given).
pub(super) struct Bound {
    pub slots: [u16; 4],
    pub moved: Option<Point>,
}

impl JointSlots {
    pub fn new(skeleton: &Skeleton) -> Self {
        let canonical: Vec<Matrix4<f32>> =
            skeleton.joints().iter().map(|j| j.inverse_bind).collect();
        let inverse = canonical
            .iter()
            .map(|m| {
                m.cast::<f64>()
                    .try_inverse()
                    .filter(|i| i.iter().all(|x| x.is_finite()))
            })
            .collect();
        Self {
            canonical,
            inverse,
            added_index: HashMap::new(),
            added: Vec::new(),
        }
    }

    /// Joint slots added so far.
    pub fn added(&self) -> usize {
        self.added.len()
    }

    /// Binds a vertex at `position` (in its skin's bind space) with
    /// influences `joints[k]` (joints of the skeleton), `binds[k]` (the
    /// inverse bind matrix its skin gives that joint, fourth row exact) and
    /// `weights[k]`; only positive weights count. `origin` names the skin
    /// in added slots. Fails only past 65535 joint slots.
    pub fn bind(
        &mut self,
        joints: [u16; 4],
        binds: [&Matrix4<f32>; 4],
        weights: [f32; 4],
        position: &Point3<f64>,
        origin: &dyn Fn() -> String,
    ) -> Result<Bound, String> {
        let joint_count = self.canonical.len();
        let active: [bool; 4] =
            std::array::from_fn(|k| weights[k] > 0.0 && (joints[k] as usize) < joint_count);
        let differs: [bool; 4] =
            std::array::from_fn(|k| active[k] && *binds[k] != self.canonical[joints[k] as usize]);
        let Some(first) = (0..4).find(|&k| differs[k]) else {
            return Ok(Bound {
                slots: joints,
                moved: None,
            });
        };
        if let Some(moved) = self.move_to_canonical(joints, binds, active, first, position) {
            return Ok(Bound {
                slots: joints,
                moved: Some(moved),
            });
        }
        let mut slots = joints;
        for k in (0..4).filter(|&k| differs[k]) {
            slots[k] = self.slot(JointId(joints[k]), binds[k], origin)?;
        }
        Ok(Bound { slots, moved: None })
    }

    /// Option 2 of the module docs: `position` moved by joint `first`'s
    /// correction, if every active influence agrees with it.
    fn move_to_canonical(
        &self,
        joints: [u16; 4],
        binds: [&Matrix4<f32>; 4],
        active: [bool; 4],
        first: usize,
        position: &Point3<f64>,
    ) -> Option<Point> {
        let j = joints[first] as usize;
        let correction = self.inverse[j]? * binds[first].cast::<f64>();
        let moved = correction.transform_point(position);
        if !moved
            .coords
            .iter()
            .all(|c| c.abs() <= f64::from(MAX_COORDINATE))
        {
            return None;
        }
        let stored = moved.cast::<f32>();
        let (v, w) = (
            position.to_homogeneous(),
            stored.cast::<f64>().to_homogeneous(),
        );
        for k in (0..4).filter(|&k| active[k]) {
            let want = binds[k].cast::<f64>();
            let target = want * v;
            let got = self.canonical[joints[k] as usize].cast::<f64>() * w;
            // Coordinates only: the fourth is exactly 1 on both sides.
            let size = (want.abs() * v.abs()).fixed_rows::<3>(0).max();
            let error = (target - got).fixed_rows::<3>(0).abs().max();
            // Not `>`: a NaN fails the check.
            let agrees = error <= CORRECTION_TOLERANCE * size;
            if !agrees {
                return None;
            }
        }
        Some(stored)
    }

    /// The slot of (`joint`, `inverse_bind`): the joint itself when the matrix
    /// is its canonical one, else an added slot (made on first use).
    fn slot(
        &mut self,
        joint: JointId,
        inverse_bind: &Matrix4<f32>,
        origin: &dyn Fn() -> String,
    ) -> Result<u16, String> {
        if *inverse_bind == self.canonical[joint.index()] {
            return Ok(joint.0);
        }
        let key = (joint.0, std::array::from_fn(|i| inverse_bind[i].to_bits()));
        if let Some(&slot) = self.added_index.get(&key) {
            return Ok(slot);
        }
        let slot = self.canonical.len() + self.added.len();
        if slot >= u16::MAX as usize {
            return Err(format!(
                "binding the meshes needs more than {} joint slots (joints of the skeleton plus one per differing inverse bind matrix)",
                u16::MAX
            ));
        }
        self.added.push(AddedSlot {
            joint,
            inverse_bind: *inverse_bind,
            origin: origin(),
        });
        self.added_index.insert(key, slot as u16);
        Ok(slot as u16)
    }

    /// `skeleton` with the added slots appended (children of their joints,
    /// identity rest transform, their own inverse bind matrix).
    pub fn finish(&self, skeleton: Skeleton) -> Result<Skeleton, SkeletonError> {
        if self.added.is_empty() {
            return Ok(skeleton);
        }
        let mut joints = skeleton.joints().to_vec();
        for slot in &self.added {
            joints.push(Joint {
                name: format!(
                    "{} (bind of {})",
                    skeleton.joint(slot.joint).name,
                    slot.origin
                ),
                parent: Some(slot.joint),
                rest: Trs::IDENTITY,
                inverse_bind: slot.inverse_bind,
            });
        }
        Skeleton::new(joints, *skeleton.base())
    }
}

/// The joint node a node hangs from and its transform relative to that
/// joint; `None` when no joint is at or above it.
type Hang = Option<(usize, Matrix4<f64>)>;

/// Where each node hangs from the skeleton: the nearest joint at or above it
/// and the node's transform relative to that joint. Each node is computed
/// once (walks stop at nodes already known), so lookups over a whole scene
/// stay linear in its nodes.
pub(super) struct Attachments {
    /// Per node: not computed yet, or computed.
    known: Vec<Option<Hang>>,
}

impl Attachments {
    pub fn new(nodes: usize) -> Self {
        Self {
            known: vec![None; nodes],
        }
    }

    /// The joint node at or above `node` and `node`'s transform relative to
    /// it; `is_joint` tells joint nodes, `parents` the node graph (a forest),
    /// `local` a node's checked local transform.
    pub fn of<E>(
        &mut self,
        node: usize,
        parents: &[Option<usize>],
        is_joint: &dyn Fn(usize) -> bool,
        local: &mut dyn FnMut(usize) -> Result<Matrix4<f64>, E>,
    ) -> Result<Hang, E> {
        let mut chain = Vec::new();
        let mut cur = Some(node);
        while let Some(c) = cur
            && self.known[c].is_none()
        {
            chain.push(c);
            if is_joint(c) {
                break;
            }
            cur = parents[c];
        }
        for &c in chain.iter().rev() {
            let value = if is_joint(c) {
                Some((c, Matrix4::identity()))
            } else {
                match parents[c].and_then(|p| self.known[p].flatten()) {
                    Some((joint, above)) => Some((joint, above * local(c)?)),
                    None => None,
                }
            };
            self.known[c] = Some(value);
        }
        Ok(self.known[node].flatten())
    }
}

/// `m · (x, y, z, 1)` with the division glTF's static placement uses.
pub(super) fn place(m: &Matrix4<f64>, v: [f32; 3]) -> Point3<f64> {
    let h = m * Vector4::new(f64::from(v[0]), f64::from(v[1]), f64::from(v[2]), 1.0);
    Point3::new(h.x / h.w, h.y / h.w, h.z / h.w)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3;

    fn two_joints(ibm1: Matrix4<f32>) -> Skeleton {
        let joint = |parent, inverse_bind| Joint {
            name: "j".into(),
            parent,
            rest: Trs::IDENTITY,
            inverse_bind,
        };
        Skeleton::new(
            vec![
                joint(None, Matrix4::identity()),
                joint(Some(JointId(0)), ibm1),
            ],
            Matrix4::identity(),
        )
        .unwrap()
    }

    #[test]
    fn agreeing_corrections_move_the_vertex_and_disagreeing_ones_add_slots() {
        let ibm1 = Matrix4::new_translation(&Vector3::new(0.0, -1.0, 0.0));
        let mut slots = JointSlots::new(&two_joints(ibm1));
        let shift = Matrix4::new_translation(&Vector3::new(2.0, 0.0, 0.0));
        let (s0, s1) = (shift, ibm1 * shift);
        let v = Point3::new(0.5, 0.25, 0.0);
        let origin = || "skin 1".to_owned();
        // Both joints corrected by the same shift: moved, no slot.
        let b = slots
            .bind(
                [0, 1, 0, 0],
                [&s0, &s1, &s0, &s0],
                [0.5, 0.5, 0.0, 0.0],
                &v,
                &origin,
            )
            .unwrap();
        assert_eq!(b.slots, [0, 1, 0, 0]);
        assert_eq!(b.moved, Some(Point::new(2.5, 0.25, 0.0)));
        // Joint 0 as canonical, joint 1 shifted: a slot for joint 1 only.
        let id = Matrix4::identity();
        let b = slots
            .bind(
                [0, 1, 0, 0],
                [&id, &s1, &id, &id],
                [0.5, 0.5, 0.0, 0.0],
                &v,
                &origin,
            )
            .unwrap();
        assert_eq!((b.slots, b.moved), ([0, 2, 0, 0], None));
        // The same pair again shares the slot.
        let b = slots
            .bind(
                [1, 0, 0, 0],
                [&s1, &id, &id, &id],
                [1.0, 0.0, 0.0, 0.0],
                &v,
                &origin,
            )
            .unwrap();
        assert_eq!(b.moved, Some(Point::new(2.5, 0.25, 0.0)));
        assert_eq!(slots.added(), 1);
        let skeleton = slots.finish(two_joints(ibm1)).unwrap();
        assert_eq!(skeleton.len(), 3);
        assert_eq!(skeleton.parent(JointId(2)), Some(JointId(1)));
        assert_eq!(skeleton.joint(JointId(2)).inverse_bind, s1);
    }
}
