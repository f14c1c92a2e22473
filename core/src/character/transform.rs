//! Translation-rotation-scale transforms, as glTF nodes and animation channels
//! store them.

use nalgebra::{Matrix4, UnitQuaternion, Vector3};

/// `T · R · S` (applied to a point: scale, then rotate, then translate).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Trs {
    /// Translation, in the parent's space and units.
    pub translation: Vector3<f32>,
    /// Rotation, applied after the scale.
    pub rotation: UnitQuaternion<f32>,
    /// Scale factor along each local axis, applied first.
    pub scale: Vector3<f32>,
}

impl Default for Trs {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Trs {
    /// No translation, no rotation, unit scale.
    pub const IDENTITY: Trs = Trs {
        translation: Vector3::new(0.0, 0.0, 0.0),
        rotation: UnitQuaternion::new_unchecked(nalgebra::Quaternion::new(1.0, 0.0, 0.0, 0.0)),
        scale: Vector3::new(1.0, 1.0, 1.0),
    };

    /// A pure translation by `t`.
    pub fn from_translation(t: Vector3<f32>) -> Self {
        Self {
            translation: t,
            ..Self::IDENTITY
        }
    }

    /// The affine matrix `T · R · S`.
    pub fn to_matrix(&self) -> Matrix4<f32> {
        let mut m = self.rotation.to_homogeneous();
        for c in 0..3 {
            for r in 0..3 {
                m[(r, c)] *= self.scale[c];
            }
        }
        m[(0, 3)] = self.translation.x;
        m[(1, 3)] = self.translation.y;
        m[(2, 3)] = self.translation.z;
        m
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn matrix_is_t_r_s() {
        let t = Trs {
            translation: Vector3::new(1.0, 2.0, 3.0),
            rotation: UnitQuaternion::from_euler_angles(0.3, -0.2, 1.1),
            scale: Vector3::new(2.0, 0.5, 1.5),
        };
        let expected = Matrix4::new_translation(&t.translation)
            * t.rotation.to_homogeneous()
            * Matrix4::new_nonuniform_scaling(&t.scale);
        assert!((t.to_matrix() - expected).norm() < 1e-5);
        assert_eq!(Trs::IDENTITY.to_matrix(), Matrix4::identity());
    }
}
