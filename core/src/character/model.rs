//! A skinned character: skeleton, bind-pose mesh, per-vertex influences, clips.

use nalgebra::Matrix4;

use crate::geometry::Point;
use crate::mesh::TriMesh;

use super::skinning::{Influences, PaperBinding, SkinningModel};
use super::{Clip, Skeleton, Trs};

/// Everything needed to pose and skin a character.
#[derive(Clone, Debug)]
pub struct Character {
    /// The character's name (from glTF, the file's stem).
    pub name: String,
    /// The joints that pose the mesh.
    pub skeleton: Skeleton,
    /// Triangles with bind-space (mesh space) positions.
    pub mesh: TriMesh,
    /// glTF influences, one entry per mesh vertex.
    pub influences: Influences,
    /// The paper's one-joint binding, converted from `influences`.
    pub paper: PaperBinding,
    /// The animations; the first is the default.
    pub clips: Vec<Clip>,
}

/// An unknown clip name, with the names there are.
#[derive(Debug, thiserror::Error, PartialEq)]
#[error("no clip named {name:?}; clips: {}", if available.is_empty() { "(none)".to_string() } else { available.join(", ") })]
pub struct UnknownClip {
    /// The name asked for (`"(first)"` when the character has no clip).
    pub name: String,
    /// The names of the character's clips.
    pub available: Vec<String>,
}

impl Character {
    /// Assembles a character; the paper binding is derived from the influences.
    pub fn new(
        name: String,
        skeleton: Skeleton,
        mesh: TriMesh,
        influences: Influences,
        clips: Vec<Clip>,
    ) -> Self {
        let paper = PaperBinding::from_influences(&influences, &skeleton);
        Self {
            name,
            skeleton,
            mesh,
            influences,
            paper,
            clips,
        }
    }

    /// The joint that alone moves vertex `v` under `model`, if one does:
    /// one influence of weight exactly 1 (linear blend skinning), or the
    /// paper's weight 1. Such a vertex is skinned by that joint's skin
    /// matrix alone, `fl(M_j·v)` (the paper's blend at `w = 1` is `M_j`).
    pub fn sole_joint(&self, model: SkinningModel, v: usize) -> Option<super::JointId> {
        match model {
            SkinningModel::Linear => {
                let mut it = self.influences.of(v);
                match (it.next(), it.next()) {
                    (Some((j, 1.0)), None) => Some(j),
                    _ => None,
                }
            }
            SkinningModel::Paper => (self.paper.weight(v) == 1.0).then(|| self.paper.joint(v)),
        }
    }

    /// The largest magnitude of a bind coordinate, 1 included (the
    /// homogeneous coordinate): what bounds a skinned coordinate's rounding
    /// (`sphere_tree::self_contact::RigidGaps`).
    pub fn bind_coordinate_bound(&self) -> f32 {
        let (lo, hi) = self.mesh.bounds();
        [lo.x, lo.y, lo.z, hi.x, hi.y, hi.z, 1.0]
            .iter()
            .fold(0.0f32, |m, c| m.max(c.abs()))
    }

    /// The clip called `name`, or the first clip when `name` is `None`.
    pub fn clip(&self, name: Option<&str>) -> Result<&Clip, UnknownClip> {
        let found = match name {
            Some(n) => self.clips.iter().find(|c| c.name == n),
            None => self.clips.first(),
        };
        found.ok_or_else(|| UnknownClip {
            name: name.unwrap_or("(first)").to_string(),
            available: self.clips.iter().map(|c| c.name.clone()).collect(),
        })
    }
}

/// Reusable per-frame buffers: local transforms, world and skin matrices, the
/// placed skeleton base, and the posed vertex positions. Posing allocates
/// nothing after construction.
///
/// Posing ([`PoseBuffers::pose`], [`PoseBuffers::place`]) works per joint and
/// is cheap; skinning every vertex ([`PoseBuffers::skin_all`]) is not, and the
/// collision pipeline does without it: it skins only the vertices its narrow
/// phase reads ([`super::OnDemandSkin`]).
#[derive(Clone, Debug)]
pub struct PoseBuffers {
    /// Each joint's transform relative to its parent (the sampled clip).
    pub local: Vec<Trs>,
    /// Each joint's world matrix.
    pub world: Vec<Matrix4<f32>>,
    /// Each joint's skin matrix `world · inverse_bind`: bind space to world.
    pub skin: Vec<Matrix4<f32>>,
    /// The skeleton's base frame, placed: `placement · base` (the parent frame
    /// of root joints, for refit and for the paper's skinning model).
    pub base: Matrix4<f32>,
    /// Every vertex skinned, after [`PoseBuffers::skin_all`].
    pub positions: Vec<Point>,
}

impl PoseBuffers {
    /// Buffers sized for `character`, holding its rest pose and bind positions
    /// (matrices are identity until [`PoseBuffers::pose`]).
    pub fn new(character: &Character) -> Self {
        let n = character.skeleton.len();
        Self {
            local: character.skeleton.rest_pose(),
            world: vec![Matrix4::identity(); n],
            skin: vec![Matrix4::identity(); n],
            base: *character.skeleton.base(),
            positions: character.mesh.positions().to_vec(),
        }
    }

    /// Samples `clip` at `t` and computes world and skin matrices.
    pub fn pose(&mut self, character: &Character, clip: Option<&Clip>, t: f32) {
        let rest = character.skeleton.rest_pose_ref();
        match clip {
            Some(c) => c.sample(t, rest, &mut self.local),
            None => self.local.copy_from_slice(rest),
        }
        self.pose_local(character);
    }

    /// World and skin matrices from the local transforms in `self.local`
    /// (set by hand, or by [`PoseBuffers::pose`]); the base is unplaced.
    pub fn pose_local(&mut self, character: &Character) {
        character
            .skeleton
            .world_matrices(&self.local, &mut self.world);
        character
            .skeleton
            .skin_matrices(&self.world, &mut self.skin);
        self.base = *character.skeleton.base();
    }

    /// Moves the posed character rigidly: premultiplies world and skin matrices
    /// by `placement` (call after [`PoseBuffers::pose`], before skinning). The
    /// skeleton's base frame moves with it: use `placement · base` for refit.
    pub fn place(&mut self, placement: &Matrix4<f32>) {
        for m in self.world.iter_mut().chain(self.skin.iter_mut()) {
            *m = placement * *m;
        }
        self.base = placement * self.base;
    }

    /// An upper bound of the distance from the origin of any vertex skinned
    /// from the current matrices, for a character whose bind vertices lie
    /// within `bind_reach` of the origin: both skinning models blend skin
    /// matrices (and, for the paper's, the base) with convex weights, so no
    /// vertex goes further than the furthest matrix takes a bind vertex.
    /// Not finite when a matrix is not.
    pub fn reach(&self, bind_reach: f32) -> f32 {
        self.skin_pose().reach(bind_reach)
    }

    /// The skin matrices and placed base this pose skins with.
    #[inline]
    pub fn skin_pose(&self) -> SkinPose<'_> {
        SkinPose {
            skin: &self.skin,
            base: &self.base,
        }
    }

    /// Skins every vertex with `model` from the current skin matrices.
    pub fn skin_all(&mut self, character: &Character, model: SkinningModel) {
        skin_every_vertex(
            character,
            model,
            &self.skin,
            &self.base,
            &mut self.positions,
        );
    }

    /// [`PoseBuffers::skin_all`] into `out` (one point per vertex) instead
    /// of `self.positions`.
    pub fn skin_all_into(&self, character: &Character, model: SkinningModel, out: &mut [Point]) {
        self.skin_pose().skin_all_into(character, model, out);
    }

    /// Vertex `v` skinned with `model` from the current skin matrices (the
    /// same arithmetic as [`PoseBuffers::skin_all`], bit for bit).
    #[inline]
    pub fn skin_vertex(&self, character: &Character, model: SkinningModel, v: usize) -> Point {
        self.skin_pose().skin_vertex(character, model, v)
    }
}

/// What skinning reads of a pose: each joint's skin matrix (world ·
/// inverse bind, placed) and the placed skeleton base (the parent frame of
/// root joints in the paper's model). Borrowed from a [`PoseBuffers`] or
/// from a world's copy of a character's pose.
#[derive(Clone, Copy, Debug)]
pub struct SkinPose<'a> {
    /// One matrix per joint.
    pub skin: &'a [Matrix4<f32>],
    /// The placed skeleton base.
    pub base: &'a Matrix4<f32>,
}

impl SkinPose<'_> {
    /// An upper bound of the distance from the origin of any vertex skinned
    /// from these matrices, for a character whose bind vertices lie within
    /// `bind_reach` of the origin ([`PoseBuffers::reach`]). Not finite when
    /// a matrix is not.
    pub fn reach(&self, bind_reach: f32) -> f32 {
        self.skin
            .iter()
            .chain([self.base])
            .map(|m| {
                let linear = m.fixed_view::<3, 3>(0, 0).norm();
                let t = m.fixed_view::<3, 1>(0, 3).norm();
                // Zero, or NaN when the last row is not finite (skinning
                // never reads it, but a matrix is finite or not as a whole).
                let last_row = m.fixed_view::<1, 4>(3, 0).sum() * 0.0;
                linear * bind_reach + t + last_row
            })
            .fold(
                0.0,
                |a: f32, b| if b.is_nan() { f32::INFINITY } else { a.max(b) },
            )
    }

    /// Every vertex skinned with `model` into `out` (one point per vertex).
    pub fn skin_all_into(&self, character: &Character, model: SkinningModel, out: &mut [Point]) {
        skin_every_vertex(character, model, self.skin, self.base, out);
    }

    /// Vertex `v` skinned with `model` (the same arithmetic as
    /// [`SkinPose::skin_all_into`], bit for bit).
    #[inline]
    pub fn skin_vertex(&self, character: &Character, model: SkinningModel, v: usize) -> Point {
        let p = &character.mesh.positions()[v];
        match model {
            SkinningModel::Linear => character.influences.skin_vertex(v, p, self.skin),
            SkinningModel::Paper => {
                character
                    .paper
                    .skin_vertex(&character.skeleton, self.base, v, p, self.skin)
            }
        }
    }
}

/// Every vertex of `character` skinned with `model` into `out`.
fn skin_every_vertex(
    character: &Character,
    model: SkinningModel,
    skin: &[Matrix4<f32>],
    base: &Matrix4<f32>,
    out: &mut [Point],
) {
    let bind = character.mesh.positions();
    match model {
        SkinningModel::Linear => character.influences.skin(bind, skin, out),
        SkinningModel::Paper => character
            .paper
            .skin(&character.skeleton, base, bind, skin, out),
    }
}
