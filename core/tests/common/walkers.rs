//! Walkers in a world: generated humanoids on a floor with a box crossing
//! them, every world built the same way (declared with `#[path]` by the
//! library's world tests).

use std::sync::Arc;

use cornertree::character::{Character, PoseBuffers, SkinningModel};
use cornertree::geometry::Point;
use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;
use cornertree::world::{CharacterModel, CollisionWorld, WorldSettings};
use nalgebra::{Isometry3, Matrix4, Translation3, UnitQuaternion, Vector3};

use super::box_mesh::box_mesh;
use super::humanoid;

/// Walkers a scene poses.
pub const WALKERS: usize = 4;

/// A floor of big triangles.
pub fn floor() -> TriMesh {
    TriMesh::new(
        vec![
            Point::new(-4.0, 0.0, -4.0),
            Point::new(4.0, 0.0, -4.0),
            Point::new(4.0, 0.0, 4.0),
            Point::new(-4.0, 0.0, 4.0),
        ],
        vec![[0, 2, 1], [0, 3, 2]],
    )
    .unwrap()
}

pub struct Scene {
    pub character: Arc<Character>,
    pub model: Arc<CharacterModel>,
    pub object: Arc<TriMesh>,
    pub poses: Vec<PoseBuffers>,
}

impl Scene {
    pub fn new() -> Self {
        let character = Arc::new(
            humanoid::generate_humanoid(&humanoid::HumanoidParams {
                vertices: 1500,
                seed: 5,
            })
            .unwrap(),
        );
        let model =
            Arc::new(CharacterModel::new(character.clone(), SkinningModel::Linear).unwrap());
        let poses = (0..WALKERS).map(|_| PoseBuffers::new(&character)).collect();
        Self {
            character,
            model,
            object: Arc::new(box_mesh()),
            poses,
        }
    }

    /// A world of the floor, the box (if `object`) and the walkers `walkers`.
    pub fn world(&self, walkers: usize, object: bool) -> CollisionWorld {
        self.world_with(walkers, object, true)
    }

    /// The same, each walker tested against itself as it is added if
    /// `self_collision`.
    pub fn world_with(&self, walkers: usize, object: bool, self_collision: bool) -> CollisionWorld {
        let settings = WorldSettings {
            self_collision,
            ..WorldSettings::default()
        };
        let mut w = CollisionWorld::with_settings(Method::UndividedPrunedTriTri, settings);
        w.add_room(Arc::new(floor())).unwrap();
        if object {
            w.add_object(self.object.clone(), Isometry3::identity())
                .unwrap();
        }
        for _ in 0..walkers {
            w.add_character(self.model.clone()).unwrap();
        }
        w.enable_continuous(CcdParams::default());
        w
    }

    /// Frame `k`'s poses: the walkers 0.4 m apart (their arms brush), each
    /// at its own phase of the walk; `far` sends walker 1 20 m away (a
    /// pooled instance posed where nothing is).
    pub fn pose(&mut self, k: usize, far: bool) {
        let clip = &self.character.clips[0];
        for (c, pose) in self.poses.iter_mut().enumerate() {
            let t = clip.start() + clip.duration() * ((3 * k + 5 * c) % 30) as f32 / 30.0;
            pose.pose(&self.character, Some(clip), t);
            let x = if far && c == 1 {
                20.0
            } else {
                0.4 * c as f32 - 0.6
            };
            let place = Matrix4::new_translation(&Vector3::new(x, 0.0, 0.05 * k as f32))
                * Matrix4::from_euler_angles(0.0, 0.1 * c as f32, 0.0);
            pose.place(&place);
        }
    }

    /// The box's pose at frame `k`: crossing the walkers at hip height.
    pub fn object_pose(k: usize) -> Isometry3<f32> {
        Isometry3::from_parts(
            Translation3::new(-0.9 + 0.25 * k as f32, 0.9, 0.1),
            UnitQuaternion::from_euler_angles(0.3, 0.2 * k as f32, 0.0),
        )
    }
}
