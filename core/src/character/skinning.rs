//! Skinning: bind-space vertices to posed world positions.
//!
//! Two models run on the same asset:
//!
//! - **glTF linear blend skinning**: `v' = Σ_k w_k · M_{j_k} · v` over up to four
//!   influences, with `M_j = world_j · inverse_bind_j` (skin matrices).
//! - **The paper's model** (§3): each vertex belongs to one joint `a` with a
//!   weight `w` and follows its parent chain and a linear blend of identity and
//!   `a`'s local transform: `C_v = (Π C_i) · ((1 − w)·I + w·C_a)`. In bind space
//!   this is `v' = (1 − w)·M_p·v + w·M_a·v` with `p` the parent of `a`: linear in
//!   `w`, which is what makes the min/max-weight sphere refit conservative. For a
//!   root joint the parent frame is the skeleton's base.
//!
//! [`PaperBinding::from_influences`] converts glTF weights to the paper's model.
//!
//! **Rounding.** Both models run in `f32`. [`LINEAR_ROUNDINGS`] and
//! [`PAPER_ROUNDINGS`] count the roundings on any path from an input product
//! to a skinned coordinate; refit turns them into a bound on how far a skinned
//! vertex can lie from its exact position (see [`crate::sphere_tree::refit`]).
//! Change the arithmetic below and those counts must be checked again.

use std::fmt;
use std::str::FromStr;

use nalgebra::Matrix4;

use crate::choice::{Choice, UnknownName, parse_choice, show};
use crate::geometry::Point;

use super::{JointId, Skeleton};

/// Roundings on any path of [`Influences::skin_vertex`]: the product
/// `m·h` (1), the four-term row sum of `M_j·h` in any order (at most 3), the
/// weight product (1), and the sum over at most four influences (at most 3;
/// adding to the zero start is exact). The result differs from
/// `Σ_j w_j·M_j·h`, computed exactly from the same `f32` numbers, by at most
/// `γ_8 · Σ_j w_j·|M_j|·|h|` per coordinate (`γ_n = n·u / (1 − n·u)`,
/// `u = 2⁻²⁴`).
pub const LINEAR_ROUNDINGS: u32 = 8;

/// Roundings on any path of [`PaperBinding::skin_vertex`]: the blend
/// `(1 − w)·M_p + w·M_a` element by element (a product and a sum: 2; `1 − w`
/// is taken as the exact weight it rounds to), then `transform_point` (a
/// product and at most 3 additions: 4). Its division is exact: the blend's last
/// row is `[0, 0, 0, fl(fl(1 − w) + w)] = [0, 0, 0, 1]` for `w ∈ [0, 1]` because
/// the skeleton keeps every matrix affine ([`Skeleton::new`]).
pub const PAPER_ROUNDINGS: u32 = 6;

/// How far a vertex that joint matrix `m` alone skins
/// ([`super::Character::sole_joint`]) can lie from its exact image `M·v`:
/// `fl(M·v)` is off by at most `γ₈·Σ_k |m_ik|·c` in each coordinate (at
/// most eight roundings on any path, either model: [`LINEAR_ROUNDINGS`]),
/// so by `√3·γ₈·r·c`, with `r` the largest row sum of `|m|` over its three
/// spatial rows and `c` the largest bind coordinate, 1 included
/// ([`super::Character::bind_coordinate_bound`]). Not finite when `m` is
/// not.
pub fn sole_joint_rounding(m: &Matrix4<f32>, coordinate_bound: f32) -> f64 {
    let u = f64::from(f32::EPSILON) / 2.0;
    let gamma8 = 8.0 * u / (1.0 - 8.0 * u);
    3f64.sqrt() * gamma8 * largest_row_sum(m) * f64::from(coordinate_bound)
}

/// The largest row sum of `|m|` over its three spatial rows: a skinned
/// coordinate is at most this times the largest bind coordinate.
pub fn largest_row_sum(m: &Matrix4<f32>) -> f64 {
    (0..3)
        .map(|i| (0..4).map(|k| f64::from(m[(i, k)]).abs()).sum::<f64>())
        .fold(0.0f64, f64::max)
}

/// Which skinning model animates the mesh.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum SkinningModel {
    /// glTF linear blend skinning, up to four influences.
    Linear,
    /// The paper's one-joint model (§3).
    Paper,
}

impl Choice for SkinningModel {
    const WHAT: &'static str = "skinning model";
    const ALL: &'static [Self] = &[SkinningModel::Linear, SkinningModel::Paper];

    fn name(self) -> &'static str {
        match self {
            SkinningModel::Linear => "linear",
            SkinningModel::Paper => "paper",
        }
    }

    fn summary(self) -> &'static str {
        match self {
            SkinningModel::Linear => "glTF linear blend skinning, up to four influences",
            SkinningModel::Paper => "the paper's one-joint model (§3)",
        }
    }
}

impl FromStr for SkinningModel {
    type Err = UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_choice(s)
    }
}

impl fmt::Display for SkinningModel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        show(*self, f)
    }
}

/// Why per-vertex skinning data is unusable. Vertex indices are the mesh's.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum SkinError {
    /// Two per-vertex arrays differ in length.
    #[error("{what} has {got} entries for {vertices} vertices")]
    Length {
        /// The array whose length is off (`"JOINTS_0"`, `"paper weights"`).
        what: &'static str,
        /// Its number of entries.
        got: usize,
        /// The number of vertices, from the other array.
        vertices: usize,
    },
    /// A vertex is bound, with non-zero weight, to a joint the skin does not have.
    #[error("vertex {vertex}: joint index {joint} is out of range (the skin has {joints} joints)")]
    JointOutOfRange {
        /// The vertex.
        vertex: usize,
        /// The joint index it names.
        joint: usize,
        /// Number of joints in the skin.
        joints: usize,
    },
    /// A vertex's glTF weights are negative, non-finite or do not sum to a
    /// positive number; or its paper weight is not in `[0, 1]`.
    #[error("vertex {vertex}: weights sum to {sum}, not a positive finite number")]
    BadWeights {
        /// The vertex.
        vertex: usize,
        /// The weights' sum (for the paper's model, the one weight).
        sum: f32,
    },
}

/// Up to four (joint, weight) influences per vertex; weights are normalised to
/// sum to one, and an influence of weight zero points at joint 0.
#[derive(Clone, Debug, PartialEq)]
pub struct Influences {
    joints: Vec<[JointId; 4]>,
    weights: Vec<[f32; 4]>,
}

impl Influences {
    /// Validates and normalises. A joint index only matters (and is only
    /// checked) where its weight is non-zero, as glTF allows.
    pub fn new(
        joints: Vec<[u16; 4]>,
        weights: Vec<[f32; 4]>,
        joint_count: usize,
    ) -> Result<Self, SkinError> {
        if joints.len() != weights.len() {
            return Err(SkinError::Length {
                what: "JOINTS_0",
                got: joints.len(),
                vertices: weights.len(),
            });
        }
        let mut out_j = Vec::with_capacity(joints.len());
        let mut out_w = Vec::with_capacity(joints.len());
        for (vertex, (j, w)) in joints.iter().zip(&weights).enumerate() {
            let sum: f32 = w.iter().sum();
            if !(sum.is_finite() && sum > 0.0) || w.iter().any(|x| !x.is_finite() || *x < 0.0) {
                return Err(SkinError::BadWeights { vertex, sum });
            }
            let mut jj = [JointId(0); 4];
            let mut ww = [0.0; 4];
            for k in 0..4 {
                if w[k] > 0.0 {
                    if j[k] as usize >= joint_count {
                        return Err(SkinError::JointOutOfRange {
                            vertex,
                            joint: j[k] as usize,
                            joints: joint_count,
                        });
                    }
                    jj[k] = JointId(j[k]);
                    ww[k] = w[k] / sum;
                }
            }
            out_j.push(jj);
            out_w.push(ww);
        }
        Ok(Self {
            joints: out_j,
            weights: out_w,
        })
    }

    /// Every vertex bound rigidly to one joint.
    pub fn rigid(joints: &[JointId]) -> Self {
        Self {
            joints: joints
                .iter()
                .map(|&j| [j, JointId(0), JointId(0), JointId(0)])
                .collect(),
            weights: joints.iter().map(|_| [1.0, 0.0, 0.0, 0.0]).collect(),
        }
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.joints.len()
    }

    /// Whether there are no vertices.
    pub fn is_empty(&self) -> bool {
        self.joints.is_empty()
    }

    /// Non-zero influences of vertex `v`.
    pub fn of(&self, v: usize) -> impl Iterator<Item = (JointId, f32)> + '_ {
        self.joints[v]
            .iter()
            .zip(&self.weights[v])
            .filter(|(_, w)| **w > 0.0)
            .map(|(j, w)| (*j, *w))
    }

    /// The joint with the largest weight on vertex `v`.
    pub fn dominant(&self, v: usize) -> JointId {
        let w = &self.weights[v];
        let k = (0..4)
            .max_by(|&a, &b| w[a].total_cmp(&w[b]).then(b.cmp(&a)))
            .unwrap();
        self.joints[v][k]
    }

    /// Linear blend skinning of every vertex.
    pub fn skin(&self, bind: &[Point], skin: &[Matrix4<f32>], out: &mut [Point]) {
        for (v, p) in bind.iter().enumerate() {
            out[v] = self.skin_vertex(v, p, skin);
        }
    }

    /// Linear blend skinning of vertex `v` at bind-space position `p`: its
    /// posed position under the skin matrices `skin` (one per joint).
    #[inline]
    pub fn skin_vertex(&self, v: usize, p: &Point, skin: &[Matrix4<f32>]) -> Point {
        let h = p.to_homogeneous();
        let mut acc = nalgebra::Vector4::zeros();
        for k in 0..4 {
            let w = self.weights[v][k];
            if w > 0.0 {
                acc += skin[self.joints[v][k].index()] * h * w;
            }
        }
        Point::new(acc.x, acc.y, acc.z)
    }
}

/// The paper's model: one joint and one weight per vertex (§3).
#[derive(Clone, Debug, PartialEq)]
pub struct PaperBinding {
    joint: Vec<JointId>,
    weight: Vec<f32>,
}

impl PaperBinding {
    /// Checks one joint and one weight per vertex: every joint in `skeleton`,
    /// every weight in `[0, 1]`.
    pub fn new(
        joint: Vec<JointId>,
        weight: Vec<f32>,
        skeleton: &Skeleton,
    ) -> Result<Self, SkinError> {
        if joint.len() != weight.len() {
            return Err(SkinError::Length {
                what: "paper weights",
                got: weight.len(),
                vertices: joint.len(),
            });
        }
        for (vertex, (j, w)) in joint.iter().zip(&weight).enumerate() {
            if j.index() >= skeleton.len() {
                return Err(SkinError::JointOutOfRange {
                    vertex,
                    joint: j.index(),
                    joints: skeleton.len(),
                });
            }
            if !(w.is_finite() && (0.0..=1.0).contains(w)) {
                return Err(SkinError::BadWeights { vertex, sum: *w });
            }
        }
        Ok(Self { joint, weight })
    }

    /// From glTF weights: the vertex goes to its dominant joint `a`; when the
    /// runner-up influence is `a`'s parent, `w = w_a / (w_a + w_parent)`; when
    /// the runner-up is a child `c` of `a`, the vertex goes to `c` with
    /// `w = w_c / (w_a + w_c)`; otherwise `w = 1` (rigid). Root-joint vertices
    /// get `w = 1`.
    pub fn from_influences(inf: &Influences, skeleton: &Skeleton) -> Self {
        let mut joint = Vec::with_capacity(inf.len());
        let mut weight = Vec::with_capacity(inf.len());
        for v in 0..inf.len() {
            let mut top: [(JointId, f32); 2] = [(JointId(0), 0.0); 2];
            for (j, w) in inf.of(v) {
                if w > top[0].1 {
                    top[1] = top[0];
                    top[0] = (j, w);
                } else if w > top[1].1 {
                    top[1] = (j, w);
                }
            }
            let [(j1, w1), (j2, w2)] = top;
            let (a, w) = if w2 > 0.0 && skeleton.parent(j1) == Some(j2) {
                (j1, w1 / (w1 + w2))
            } else if w2 > 0.0 && skeleton.parent(j2) == Some(j1) {
                (j2, w2 / (w1 + w2))
            } else {
                (j1, 1.0)
            };
            let w = if skeleton.parent(a).is_none() { 1.0 } else { w };
            joint.push(a);
            weight.push(w);
        }
        Self { joint, weight }
    }

    /// Number of vertices.
    pub fn len(&self) -> usize {
        self.joint.len()
    }

    /// Whether there are no vertices.
    pub fn is_empty(&self) -> bool {
        self.joint.is_empty()
    }

    /// The joint `a` vertex `v` belongs to.
    pub fn joint(&self, v: usize) -> JointId {
        self.joint[v]
    }

    /// The weight `w` of vertex `v` on its joint's local transform, in `[0, 1]`
    /// (0: follows the parent frame only, 1: rigid with the joint).
    pub fn weight(&self, v: usize) -> f32 {
        self.weight[v]
    }

    /// The bind-space matrix a vertex of joint `a` blends from at `w = 0`: the
    /// parent's skin matrix, or the (placed) skeleton base for a root joint.
    #[inline]
    pub fn parent_matrix(
        skeleton: &Skeleton,
        skin: &[Matrix4<f32>],
        base: &Matrix4<f32>,
        a: JointId,
    ) -> Matrix4<f32> {
        match skeleton.parent(a) {
            Some(p) => skin[p.index()],
            None => *base,
        }
    }

    /// `((1 − w)·M_p + w·M_a)`: the paper's vertex transform in bind space.
    #[inline]
    pub fn blend(
        skeleton: &Skeleton,
        skin: &[Matrix4<f32>],
        base: &Matrix4<f32>,
        a: JointId,
        w: f32,
    ) -> Matrix4<f32> {
        Self::parent_matrix(skeleton, skin, base, a) * (1.0 - w) + skin[a.index()] * w
    }

    /// Skins vertex `v` (bind position `p`) with the paper's model; `base` is
    /// the skeleton's base frame as placed this frame.
    #[inline]
    pub fn skin_vertex(
        &self,
        skeleton: &Skeleton,
        base: &Matrix4<f32>,
        v: usize,
        p: &Point,
        skin: &[Matrix4<f32>],
    ) -> Point {
        Self::blend(skeleton, skin, base, self.joint[v], self.weight[v]).transform_point(p)
    }

    /// Skins every vertex with the paper's model.
    pub fn skin(
        &self,
        skeleton: &Skeleton,
        base: &Matrix4<f32>,
        bind: &[Point],
        skin: &[Matrix4<f32>],
        out: &mut [Point],
    ) {
        for (v, p) in bind.iter().enumerate() {
            out[v] = self.skin_vertex(skeleton, base, v, p, skin);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::character::{Joint, Trs};
    use nalgebra::{UnitQuaternion, Vector3};

    fn two_bones() -> Skeleton {
        let rest0 = Trs::IDENTITY;
        let rest1 = Trs::from_translation(Vector3::new(0.0, 1.0, 0.0));
        let j = |name: &str, parent, rest: Trs, bind_world: Matrix4<f32>| Joint {
            name: name.into(),
            parent,
            rest,
            inverse_bind: bind_world.try_inverse().unwrap(),
        };
        Skeleton::new(
            vec![
                j("root", None, rest0, rest0.to_matrix()),
                j("child", Some(JointId(0)), rest1, rest1.to_matrix()),
            ],
            Matrix4::identity(),
        )
        .unwrap()
    }

    fn posed(s: &Skeleton) -> Vec<Matrix4<f32>> {
        let mut local = s.rest_pose();
        local[0].translation = Vector3::new(5.0, 0.0, 0.0);
        local[1].rotation =
            UnitQuaternion::from_euler_angles(0.0, 0.0, std::f32::consts::FRAC_PI_2);
        let mut world = vec![Matrix4::identity(); 2];
        let mut skin = vec![Matrix4::identity(); 2];
        s.world_matrices(&local, &mut world);
        s.skin_matrices(&world, &mut skin);
        skin
    }

    #[test]
    fn rest_pose_skins_to_bind_positions() {
        let s = two_bones();
        let mut world = vec![Matrix4::identity(); 2];
        let mut skin = vec![Matrix4::identity(); 2];
        s.world_matrices(&s.rest_pose(), &mut world);
        s.skin_matrices(&world, &mut skin);
        let inf = Influences::new(vec![[0, 1, 0, 0]], vec![[0.3, 0.7, 0.0, 0.0]], 2).unwrap();
        let p = [Point::new(0.2, 1.5, 0.1)];
        let mut out = [Point::origin()];
        inf.skin(&p, &skin, &mut out);
        assert!((out[0] - p[0]).norm() < 1e-6);
    }

    #[test]
    fn paper_model_blends_parent_and_joint() {
        let s = two_bones();
        let skin = posed(&s);
        let p = [Point::new(0.0, 2.0, 0.0)];
        let rigid_child = skin[1].transform_point(&p[0]);
        let rigid_parent = skin[0].transform_point(&p[0]);
        for (w, expected) in [(1.0, rigid_child), (0.0, rigid_parent)] {
            let b = PaperBinding::new(vec![JointId(1)], vec![w], &s).unwrap();
            let mut out = [Point::origin()];
            b.skin(&s, s.base(), &p, &skin, &mut out);
            assert!((out[0] - expected).norm() < 1e-5, "w={w}");
        }
        // The paper's model equals two-influence linear blend skinning.
        let b = PaperBinding::new(vec![JointId(1)], vec![0.25], &s).unwrap();
        let inf = Influences::new(vec![[0, 1, 0, 0]], vec![[0.75, 0.25, 0.0, 0.0]], 2).unwrap();
        let (mut x, mut y) = ([Point::origin()], [Point::origin()]);
        b.skin(&s, s.base(), &p, &skin, &mut x);
        inf.skin(&p, &skin, &mut y);
        assert!((x[0] - y[0]).norm() < 1e-5);
    }

    #[test]
    fn conversion_from_gltf_weights() {
        let s = two_bones();
        let inf = Influences::new(
            vec![[0, 1, 0, 0], [1, 0, 0, 0], [0, 0, 0, 0]],
            vec![
                [0.6, 0.4, 0.0, 0.0],
                [0.9, 0.1, 0.0, 0.0],
                [1.0, 0.0, 0.0, 0.0],
            ],
            2,
        )
        .unwrap();
        let b = PaperBinding::from_influences(&inf, &s);
        // Runner-up is a child: the vertex goes to the child with its share.
        assert_eq!((b.joint(0), b.weight(0)), (JointId(1), 0.4));
        assert_eq!((b.joint(1), b.weight(1)), (JointId(1), 0.9));
        assert_eq!((b.joint(2), b.weight(2)), (JointId(0), 1.0));
    }

    #[test]
    fn bad_weights_and_joints() {
        assert!(matches!(
            Influences::new(vec![[0, 0, 0, 0]], vec![[0.0; 4]], 2),
            Err(SkinError::BadWeights { vertex: 0, .. })
        ));
        assert!(matches!(
            Influences::new(vec![[0, 7, 0, 0]], vec![[0.5, 0.5, 0.0, 0.0]], 2),
            Err(SkinError::JointOutOfRange {
                vertex: 0,
                joint: 7,
                ..
            })
        ));
        // A zero-weight influence may name any joint.
        assert!(Influences::new(vec![[0, 7, 0, 0]], vec![[1.0, 0.0, 0.0, 0.0]], 2).is_ok());
    }
}
