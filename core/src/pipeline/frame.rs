//! Where a pass takes place: in the frame of its second body.
//!
//! A rigid body's hierarchy is built once in its own frame and never refit;
//! against it, the character's spheres and triangles are moved into that
//! frame as the pass asks for them (the query moves, the static hierarchy
//! stays: the paper's refit "applicable to any object, without dependency on
//! … its dynamic/static behavior", §1, taken the other way round). The room
//! is a rigid body whose frame is the world's: [`Identity`] moves nothing
//! and compiles to nothing, so the room pass is the plain one.

use nalgebra::Isometry3;

use crate::geometry::{Sphere, Triangle};
use crate::sphere_tree::{Hierarchy, NodeId, SphereTree};

/// A map from world coordinates into a body's frame.
pub trait Frame: Copy {
    /// Whether the map is the identity (the room's frame): a triangle in
    /// the world is the very triangle in the body's frame.
    const IDENTITY: bool = false;
    /// A sphere of the world in the body's frame, grown to cover rounding.
    fn sphere(&self, s: &Sphere) -> Sphere;
    /// A triangle of the world in the body's frame.
    fn triangle(&self, t: Triangle) -> Triangle;
}

/// The world's own frame (the room's): nothing moves.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Identity;

impl Frame for Identity {
    const IDENTITY: bool = true;

    #[inline(always)]
    fn sphere(&self, s: &Sphere) -> Sphere {
        *s
    }

    #[inline(always)]
    fn triangle(&self, t: Triangle) -> Triangle {
        t
    }
}

/// World → body: the inverse of the body's pose.
impl Frame for Isometry3<f32> {
    #[inline]
    fn sphere(&self, s: &Sphere) -> Sphere {
        s.in_frame(self)
    }

    #[inline]
    fn triangle(&self, t: Triangle) -> Triangle {
        let [i, j, k] = t.vertices();
        Triangle::new(self * i, self * j, self * k)
    }
}

/// A hierarchy seen from a body's frame: its spheres moved by `to`.
pub(crate) struct InFrame<H, F> {
    pub(crate) inner: H,
    pub(crate) to: F,
}

impl<H: Hierarchy, F: Frame> Hierarchy for InFrame<H, F> {
    #[inline]
    fn tree(&self) -> &SphereTree {
        self.inner.tree()
    }

    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.to.sphere(&self.inner.sphere(id))
    }

    #[inline]
    fn prefetch(&self, id: NodeId) {
        self.inner.prefetch(id);
    }

    #[inline]
    fn refit_ticks(&self) -> u64 {
        self.inner.refit_ticks()
    }
}
