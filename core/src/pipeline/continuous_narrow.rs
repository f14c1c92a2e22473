//! The leaf tests of continuous detection (docs/ccd.md, "Swept
//! hierarchies"): what a pair of leaves that meet over a step is answered
//! with, and its time of impact.
//!
//! * A character leaf inside a big triangle's division, in a plane-sphere
//!   method: its interpolated sphere against the big triangle's plane
//!   (`geometry::ccd_sphere_plane`), the conservative answer as in discrete
//!   mode (a sphere meeting the plane may hold no triangle touching the big
//!   triangle).
//! * Otherwise triangle against triangle, exactly:
//!   1. against a still triangle (the room), the leaf's interpolated sphere
//!      staying strictly on one side of its plane over the step rules the
//!      pair out before any vertex is skinned, and so do the six corners
//!      (both ends) lying strictly on one side (exact predicates);
//!   2. the exact oracle at the start (`geometry::exact`): touching then,
//!      the time of impact is 0;
//!   3. the triangle–triangle CCD kernel (`geometry::ccd_triangles`).

use crate::geometry::ccd_root_finder::CcdParams;
use crate::geometry::ccd_triangles::{MovingTriangle, triangles};
use crate::geometry::exact::{corners_intersect_exact, orient3};
use crate::geometry::{Point, Triangle};

/// Counters of the continuous leaf tests (beside `FrameCounters`, whose
/// `tri_tri` counts triangle pairs tested and `plane_sphere` every sphere
/// against a plane).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct CcdCounters {
    /// Triangle pairs ruled out by the leaf's sphere (no vertex skinned) or
    /// the triangle's corners at both ends staying on one side of a still
    /// triangle's plane.
    pub plane_side_skips: u64,
    /// Triangle pairs already touching at the start (time of impact 0).
    pub at_start: u64,
    /// Triangle pairs handed to the CCD kernel.
    pub kernel_tests: u64,
    /// Of those, the positive answers.
    pub kernel_contacts: u64,
    /// Positive kernel answers that stopped at a budget (conservative).
    pub unresolved: u64,
}

impl CcdCounters {
    /// Adds `o`'s counts to these.
    pub fn add(&mut self, o: &CcdCounters) {
        self.plane_side_skips += o.plane_side_skips;
        self.at_start += o.at_start;
        self.kernel_tests += o.kernel_tests;
        self.kernel_contacts += o.kernel_contacts;
        self.unresolved += o.unresolved;
    }
}

/// A pair found touching during a step: `(a, b)` triangle indices, the
/// lower bound of its time of impact, and whether a plane test answered it.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct TimedPair {
    /// The first side's triangle (a character's), as a mesh index.
    pub a: u32,
    /// The other side's triangle (the room's, an object's or the second
    /// character's); the big triangle itself where a plane test answered.
    pub b: u32,
    /// A lower bound of the time of impact, as a fraction of the step in
    /// `[0, 1]` (0 at its start).
    pub toi: f64,
    /// Whether the big triangle's plane (plane-sphere methods), not a
    /// triangle-triangle test, answered the pair.
    pub by_plane: bool,
}

#[inline]
pub(crate) fn wide(p: &Point) -> [f64; 3] {
    [p.x as f64, p.y as f64, p.z as f64]
}

/// A triangle's corners as `f64`.
#[inline]
pub(crate) fn corners(t: &Triangle) -> [[f64; 3]; 3] {
    [wide(&t.a), wide(&t.b), wide(&t.c)]
}

/// Two triangles moving linearly over the step (corners at both ends):
/// the time of impact (a lower bound), or `None` when they never touch.
pub fn triangle_pair_toi(
    a: &MovingTriangle<f64>,
    b: &MovingTriangle<f64>,
    params: &CcdParams,
    c: &mut CcdCounters,
) -> Option<f64> {
    if corners_intersect_exact(&a.start, &b.start) {
        c.at_start += 1;
        return Some(0.0);
    }
    c.kernel_tests += 1;
    let hit = triangles(a, b, params)?;
    c.kernel_contacts += 1;
    if !hit.impact.resolved {
        c.unresolved += 1;
    }
    Some(hit.toi)
}

/// Whether all six corners of `a` (both ends) lie strictly on one side of
/// the still triangle `t`'s plane (exact predicates): then `a`, which stays
/// in their convex hull over the step, never meets `t`.
pub fn strictly_one_side(a: &MovingTriangle<f64>, t: &[[f64; 3]; 3]) -> bool {
    let mut side = 0i8;
    for p in a.start.iter().chain(&a.end) {
        let s = orient3(t[0], t[1], t[2], *p);
        if s == 0 || (side != 0 && s != side) {
            return false;
        }
        side = s;
    }
    true
}

/// The leaf test of a triangle pair (module doc, steps 1–3 without the
/// sphere): `b` still (the room) or moving. The pipeline answers its pairs
/// with exactly this.
pub fn leaf_toi(
    a: &MovingTriangle<f64>,
    b: &MovingTriangle<f64>,
    b_still: bool,
    params: &CcdParams,
    c: &mut CcdCounters,
) -> Option<f64> {
    if b_still && strictly_one_side(a, &b.start) {
        c.plane_side_skips += 1;
        return None;
    }
    triangle_pair_toi(a, b, params, c)
}
