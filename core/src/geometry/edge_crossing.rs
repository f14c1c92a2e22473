//! Edge-crossing triangle-triangle test: every edge of each triangle that
//! crosses the other's plane is intersected with the other triangle.
//!
//! This was the project's first narrow-phase kernel. It is not the test of
//! Tropp, Tal and Shimshoni (that one is [`super::tropp`]): it solves one
//! edge-triangle system per crossing edge, for both triangles, without
//! reducing the problem to a segment in one triangle's parameter plane. The
//! operation model (§6) charges it like any triangle-triangle test, 96.
//!
//! In `f64` from the `f32` corners, for closed triangles:
//! 1. Plane sides. `n = u × v` (u, v: edges of triangle `A` at `a0`) and the
//!    offsets `dᵢ = n · wᵢ`, `wᵢ = pᵢ - a0`, of the other triangle's corners;
//!    all strictly on one side means no contact. Same the other way round.
//! 2. Edge against triangle. An edge `pᵢpⱼ` crossing the plane meets `A` at
//!    `a0 + βu + γv = pᵢ + t(pⱼ - pᵢ)`. By Cramer's rule, with `c = wᵢ × wⱼ`:
//!    `det = dᵢ - dⱼ`, `t = dᵢ / det`, `β = v · c / det`, `γ = -u · c / det`.
//!    The system determinant comes free from step 1, `u`, `v` and the `wᵢ` are
//!    shared by the three edges, and the test is kept division-free by
//!    comparing numerators with `|det|`. Edges that do not cross are skipped.
//!    Both triangles' edges are tested against the other.
//! 3. Coplanar pairs (all offsets zero): 2D test in the projection dropping
//!    the largest normal component: edge crossings, or a corner inside the
//!    other triangle.
//! 4. A zero-area triangle is tested as the segment (or point) it is: its
//!    edges against the other triangle, or segment against segment when both
//!    are degenerate. No divisions, so no NaN.
//!
//! Robustness (offsets snapped within their rounding error) is described in
//! [`super::coplanar_degenerate`]; the remaining rounding affects only pairs
//! at (or within rounding of) touching. `tests/tri_tri_agreement.rs`
//! measures this against [`super::exact`].
//!
//! Generic over [`Scalar`]: [`triangles_intersect`] is the `f64`
//! instantiation; [`triangles_intersect_as`] with
//! [`super::counted::Counted`] counts the operations paid.

use super::Triangle;
use super::coplanar_degenerate::{
    EDGES, all_zero, coplanar, degenerate_pair, one_side, plane_offsets,
};
use super::scalar::Scalar;
use super::vec3::{V3, cross, dot, is_zero, sub, widen_triangle};

/// Whether two closed triangles share a point (`f64` arithmetic from the
/// `f32` corners; touching counts).
///
/// ```
/// use cornertree::geometry::edge_crossing::triangles_intersect;
/// use cornertree::geometry::{Point, Triangle};
///
/// let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
///     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
/// };
/// let floor = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// // An edge along z crossing the floor at (0.25, 0.25, 0).
/// let piercing = tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [-1.0, 0.25, 0.5]);
/// assert!(triangles_intersect(&floor, &piercing) && triangles_intersect(&piercing, &floor));
/// // The same edge at (0.75, 0.75, 0), beyond the hypotenuse x + y = 1.
/// let beside = tri([0.75, 0.75, -1.0], [0.75, 0.75, 1.0], [2.0, 0.75, 0.5]);
/// assert!(!triangles_intersect(&floor, &beside) && !triangles_intersect(&beside, &floor));
/// // A corner resting exactly on the face touches; 0.001 higher it does not.
/// let resting = tri([0.25, 0.25, 0.0], [0.75, 0.25, 1.0], [0.25, 0.75, 1.0]);
/// let lifted = tri([0.25, 0.25, 0.001], [0.75, 0.25, 1.0], [0.25, 0.75, 1.0]);
/// assert!(triangles_intersect(&floor, &resting));
/// assert!(!triangles_intersect(&floor, &lifted));
/// // Coplanar triangles sharing only the corner (1, 0, 0) touch.
/// let corner = tri([1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0]);
/// assert!(triangles_intersect(&floor, &corner));
/// ```
pub fn triangles_intersect(t1: &Triangle, t2: &Triangle) -> bool {
    triangles_intersect_as::<f64>(t1, t2)
}

/// [`triangles_intersect`] computed in `T`: with
/// [`Counted`](super::counted::Counted), the operations this input pays.
///
/// ```
/// use cornertree::geometry::counted::{Counted, count_operations};
/// use cornertree::geometry::edge_crossing::triangles_intersect_as;
/// use cornertree::geometry::{Point, Triangle};
///
/// let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
///     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
/// };
/// let floor = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// let piercing = tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [-1.0, 0.25, 0.5]);
/// let above = tri([0.25, 0.25, 0.5], [0.75, 0.25, 1.0], [0.25, 0.75, 1.0]);
/// let (hit, full) = count_operations(|| triangles_intersect_as::<Counted>(&floor, &piercing));
/// let (miss, exit) = count_operations(|| triangles_intersect_as::<Counted>(&floor, &above));
/// assert!(hit && !miss);
/// assert!(triangles_intersect_as::<f64>(&floor, &piercing));
/// // `above` is rejected by the plane-side exit, before any edge is solved.
/// assert!(exit < full, "{exit} < {full}");
/// ```
pub fn triangles_intersect_as<T: Scalar>(t1: &Triangle, t2: &Triangle) -> bool {
    let (a, b) = (widen_triangle::<T>(t1), widen_triangle::<T>(t2));
    let (ua, va) = (sub(&a[1], &a[0]), sub(&a[2], &a[0]));
    let (ub, vb) = (sub(&b[1], &b[0]), sub(&b[2], &b[0]));
    let (na, nb) = (cross(&ua, &va), cross(&ub, &vb));
    // Exactly zero iff collinear: edge products are exact, one rounding each.
    let (deg_a, deg_b) = (is_zero(&na), is_zero(&nb));
    match (deg_a, deg_b) {
        (false, false) => {
            let wb = offsets_from(&b, &a[0]);
            let db = plane_offsets(&wb, &na, &ua, &va);
            if one_side(&db) {
                return false;
            }
            let wa = offsets_from(&a, &b[0]);
            let da = plane_offsets(&wa, &nb, &ub, &vb);
            if one_side(&da) {
                return false;
            }
            if all_zero(&db) {
                return coplanar(&a, &b, &na, true);
            }
            if all_zero(&da) {
                // Only possible for slivers, where the snap bounds differ.
                return coplanar(&b, &a, &nb, true);
            }
            edges_hit(&wb, &db, &ua, &va) || edges_hit(&wa, &da, &ub, &vb)
        }
        (true, false) => segments_vs_triangle(&a, &b, &ub, &vb, &nb),
        (false, true) => segments_vs_triangle(&b, &a, &ua, &va, &na),
        (true, true) => degenerate_pair(&a, &b),
    }
}

/// `pᵢ - a0` for the corners `p`.
#[inline(always)]
fn offsets_from<T: Scalar>(p: &[V3<T>; 3], a0: &V3<T>) -> [V3<T>; 3] {
    [sub(&p[0], a0), sub(&p[1], a0), sub(&p[2], a0)]
}

/// Whether an edge of `p` (corners `wᵢ = pᵢ - a0`, offsets `d` from the plane
/// of the triangle `a0 + βu + γv`) meets that closed triangle. Edges lying in
/// the plane are skipped: their contacts are also found through a crossing
/// edge (or the caller uses the coplanar test).
fn edges_hit<T: Scalar>(w: &[V3<T>; 3], d: &[T; 3], u: &V3<T>, v: &V3<T>) -> bool {
    let z = T::zero();
    EDGES.iter().any(|&(i, j)| {
        let (di, dj) = (d[i], d[j]);
        if (di > z && dj > z) || (di < z && dj < z) || (di == z && dj == z) {
            return false;
        }
        // Cramer numerators for β and γ; t ∈ [0, 1] holds by the sign test.
        let c = cross(&w[i], &w[j]);
        let (mut det, mut beta, mut gamma) = (di - dj, dot(v, &c), -dot(u, &c));
        if det < z {
            (det, beta, gamma) = (-det, -beta, -gamma);
        }
        beta >= z && gamma >= z && beta + gamma <= det
    })
}

/// A degenerate triangle `s` (a segment or point: the union of its edges)
/// against the non-degenerate triangle `t`.
fn segments_vs_triangle<T: Scalar>(
    s: &[V3<T>; 3],
    t: &[V3<T>; 3],
    u: &V3<T>,
    v: &V3<T>,
    n: &V3<T>,
) -> bool {
    let w = offsets_from(s, &t[0]);
    let d = plane_offsets(&w, n, u, v);
    if one_side(&d) {
        return false;
    }
    if all_zero(&d) {
        return coplanar(s, t, n, false);
    }
    edges_hit(&w, &d, u, v)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
        Triangle::new(Point::from(a), Point::from(b), Point::from(c))
    }

    #[test]
    fn piercing_and_separated() {
        let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let pierce = tri([0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.5, 2.0, 0.0]);
        let above = tri([0.2, 0.2, 0.1], [0.2, 0.2, 1.0], [0.5, 2.0, 0.1]);
        assert!(triangles_intersect(&t, &pierce) && triangles_intersect(&pierce, &t));
        assert!(!triangles_intersect(&t, &above) && !triangles_intersect(&above, &t));
    }
}
