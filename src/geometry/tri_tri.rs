//! Tropp et al. triangle-triangle intersection test (paper §3, narrow phase).
//! STUB: to be implemented.

use super::Triangle;

/// Whether two closed triangles share a point.
pub fn triangles_intersect(_t1: &Triangle, _t2: &Triangle) -> bool {
    unimplemented!("tri_tri")
}
