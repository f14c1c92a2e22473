//! Plane-sphere test, the paper's Algorithm 1 (§5).
//! STUB: to be implemented.

use super::{Sphere, Triangle};

/// Whether the sphere meets the plane of the triangle.
pub fn sphere_meets_plane(_s: &Sphere, _t: &Triangle) -> bool {
    unimplemented!("plane_sphere")
}
