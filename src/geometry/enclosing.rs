//! Enclosing spheres. STUB.

use super::{Point, Sphere, Triangle};

pub fn triangle_sphere(_t: &Triangle) -> Sphere { unimplemented!() }
pub fn points_sphere(_p: &[Point]) -> Sphere { unimplemented!() }
pub fn spheres_sphere_paper(_s: &[Sphere]) -> Sphere { unimplemented!() }
