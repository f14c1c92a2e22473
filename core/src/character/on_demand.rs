//! Skinning on demand: only the vertices a frame's narrow phase reads.
//!
//! Refit needs no vertex (the paper's spheres follow joints, §3), and the
//! narrow phase reads the corners of the few character triangles left in leaf
//! pairs: a few hundred of a 44,345-vertex character near a wall. Skinning
//! every vertex would cost more than the rest of the frame. Each vertex is
//! skinned the first time it is asked for in a frame and kept until the next;
//! a frame stamp per vertex says which are current, so starting a frame costs
//! nothing and nothing is allocated after construction. When a frame asks for
//! nearly everything (the original method tests every character triangle),
//! [`OnDemandSkin::skin_all`] skins every vertex in order instead, which is
//! cheaper than checking stamps millions of times.

use crate::geometry::{Point, Triangle};

use super::{Character, SkinPose, SkinningModel};

/// Posed positions of the vertices asked for this frame.
#[derive(Clone, Debug)]
pub struct OnDemandSkin {
    positions: Vec<Point>,
    /// The frame each vertex was last skinned in (0: never).
    stamp: Vec<u32>,
    frame: u32,
    skinned: u64,
    /// Every vertex was skinned this frame.
    all: bool,
}

impl OnDemandSkin {
    /// Room for a mesh of `vertices` vertices, none skinned yet.
    pub fn new(vertices: usize) -> Self {
        Self {
            positions: vec![Point::origin(); vertices],
            stamp: vec![0; vertices],
            frame: 0,
            skinned: 0,
            all: false,
        }
    }

    /// Forgets the previous frame's positions.
    pub fn begin_frame(&mut self) {
        self.skinned = 0;
        self.all = false;
        self.frame = self.frame.wrapping_add(1);
        if self.frame == 0 {
            // After 2³² − 1 frames the stamps wrap: clear them once.
            self.stamp.fill(0);
            self.frame = 1;
        }
    }

    /// Skins vertex `v` for this frame's pose unless already done.
    #[inline(always)]
    pub fn ensure(
        &mut self,
        pose: SkinPose<'_>,
        character: &Character,
        model: SkinningModel,
        v: u32,
    ) {
        let i = v as usize;
        if !self.all && self.stamp[i] != self.frame {
            self.stamp[i] = self.frame;
            self.positions[i] = pose.skin_vertex(character, model, i);
            self.skinned += 1;
        }
    }

    /// Skins every vertex for this frame's pose ([`SkinPose::skin_all_into`]'s
    /// arithmetic, which is [`OnDemandSkin::ensure`]'s).
    pub fn skin_all(&mut self, pose: SkinPose<'_>, character: &Character, model: SkinningModel) {
        pose.skin_all_into(character, model, &mut self.positions);
        self.skinned = self.positions.len() as u64;
        self.all = true;
    }

    /// Vertex `v`'s position, skinned this frame by [`OnDemandSkin::ensure`].
    #[inline]
    pub fn position(&self, v: u32) -> Point {
        debug_assert!(self.is_current(v), "vertex {v} not skinned this frame");
        self.positions[v as usize]
    }

    /// The triangle of corners `[i, j, k]`, each skinned this frame.
    #[inline]
    pub fn triangle(&self, [i, j, k]: [u32; 3]) -> Triangle {
        Triangle::new(self.position(i), self.position(j), self.position(k))
    }

    /// Whether vertex `v` was skinned this frame.
    pub fn is_current(&self, v: u32) -> bool {
        self.all || (self.frame != 0 && self.stamp[v as usize] == self.frame)
    }

    /// Vertices skinned this frame.
    pub fn skinned(&self) -> u64 {
        self.skinned
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::character::PoseBuffers;
    use crate::humanoid::{HumanoidParams, generate_humanoid};
    use nalgebra::{Matrix4, Vector3};

    /// Every vertex asked for equals full skinning bit for bit, under both
    /// models and a placement; the others stay stale.
    #[test]
    fn equals_full_skinning_where_asked() {
        let c = generate_humanoid(&HumanoidParams {
            vertices: 2000,
            ..HumanoidParams::default()
        })
        .unwrap();
        let clip = c.clip(Some("walk")).unwrap();
        let mut pose = PoseBuffers::new(&c);
        let n = c.mesh.positions().len() as u32;
        let mut lazy = OnDemandSkin::new(n as usize);
        let placement = Matrix4::new_translation(&Vector3::new(3.0, 0.5, -2.0))
            * Matrix4::from_euler_angles(0.0, 0.7, 0.0);
        for (k, model) in [SkinningModel::Linear, SkinningModel::Paper]
            .into_iter()
            .enumerate()
        {
            pose.pose(&c, Some(clip), 0.3 + k as f32 * 0.2);
            pose.place(&placement);
            pose.skin_all(&c, model);
            lazy.begin_frame();
            for v in (0..n).step_by(7) {
                lazy.ensure(pose.skin_pose(), &c, model, v);
                lazy.ensure(pose.skin_pose(), &c, model, v);
            }
            assert_eq!(lazy.skinned(), u64::from(n.div_ceil(7)));
            for v in 0..n {
                assert_eq!(lazy.is_current(v), v % 7 == 0, "vertex {v}");
                if v % 7 == 0 {
                    assert_eq!(lazy.position(v), pose.positions[v as usize], "vertex {v}");
                }
            }
            // Everything at once: the same positions, all current; the next
            // frame starts empty again.
            lazy.begin_frame();
            lazy.skin_all(pose.skin_pose(), &c, model);
            lazy.ensure(pose.skin_pose(), &c, model, 3);
            assert_eq!(lazy.skinned(), u64::from(n));
            for v in 0..n {
                assert_eq!(lazy.position(v), pose.positions[v as usize], "vertex {v}");
            }
            lazy.begin_frame();
            assert!(!lazy.is_current(0));
        }
    }
}
