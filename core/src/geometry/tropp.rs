//! The triangle-triangle test of Tropp, Tal and Shimshoni (paper §3, narrow
//! phase; charged 96 operations in §6).
//!
//! O. Tropp, A. Tal, I. Shimshoni, "A fast triangle to triangle intersection
//! test for collision detection", *Computer Animation and Virtual Worlds*
//! 17(5), 2006. The paper's narrow phase runs it on the triangles under two
//! colliding leaf spheres, "all the redundant operations to calculate
//! determinants" discarded.
//!
//! Their idea, as implemented here (in `f64` from the `f32` corners, closed
//! triangles):
//! 1. Parametrise the plane of the first triangle `A` as
//!    `a0 + α u + β v` (`u = a1 - a0`, `v = a2 - a0`). `A` itself is the
//!    canonical triangle `{α ≥ 0, β ≥ 0, α + β ≤ 1}` of that parameter plane.
//! 2. An edge `qₖ → qᵢ` of the other triangle `B` meets the plane where
//!    `α u + β v - t (qᵢ - qₖ) = wₖ` (`wₖ = qₖ - a0`): a 3×3 system, solved by
//!    Cramer's rule. Its determinant is `dₖ - dᵢ`, with `dᵢ = (u × v) · wᵢ`
//!    the corner's offset from the plane; the offsets are computed once and
//!    also decide, by their signs, whether `B` reaches the plane at all
//!    (all strictly on one side: no contact, the cheap early exit). We take
//!    that exit both ways (`A`'s corners against `B`'s plane too) before
//!    solving anything: in the pipeline a small character triangle usually
//!    lies on one side of a big environment triangle's plane while that
//!    plane cuts the small triangle's.
//! 3. Determinants shared between the edges. The three systems are strongly
//!    related: their determinants are differences of the same three offsets
//!    (they sum to zero, so the third edge's follows from the other two), and
//!    the Cramer numerators of α and β are *linear* in the far corner:
//!    `α·det = (v × wₖ) · wᵢ`, `β·det = (wₖ × u) · wᵢ`. We take as `qₖ` the
//!    corner alone on its side of the plane; the two edges that reach the
//!    plane both start at it, so the two cross products `v × wₖ`, `wₖ × u`
//!    serve both edges (four dot products in all), and the edge that stays
//!    on one side is never solved. `t` is not needed: the choice of edges
//!    guarantees `t ∈ [0, 1]`.
//! 4. `B ∩ plane(A)` is then the segment between two points `(α, β)`, held
//!    homogeneously as `(α·det, β·det, det)` with `det > 0` (the order of the
//!    cross products is picked so, at the cost of one comparison). The test
//!    becomes segment against the canonical triangle, division-free: contact
//!    if an end is inside (`α ≥ 0`, `β ≥ 0`, `α + β ≤ 1`, compared against
//!    `det`); otherwise no contact iff both ends are beyond one side of the
//!    triangle, or all three corners `(0,0), (1,0), (0,1)` are strictly on
//!    one side of the segment's line (three 3×3 determinants of homogeneous
//!    points, sharing one term). These are the four separating directions of
//!    a triangle and a segment in the plane, so the test is exact in exact
//!    arithmetic; the ends are checked first because, for a segment shrunk
//!    to a point, its line is rounding noise.
//! 5. Coplanar pairs (all offsets zero): the 2D test of
//!    [`super::coplanar_degenerate`]. A zero-area `A` swaps the roles (when
//!    `B` has area); two zero-area triangles are tested edge against edge.
//!    A zero-area `B` needs nothing special: its crossing points give a
//!    (possibly one-point) segment. Corners lying on the plane give
//!    crossing points at those corners (`t = 0` or `1`), so contacts at
//!    corners and edges count, as for closed triangles they must.
//! 6. Roles swapped on a miss, where it matters (our addition). Seen from
//!    `A`'s plane the test is asymmetric: a contact exactly at a corner or
//!    an edge of `A` lying on `B` (a foot's corner resting on a floor) is on
//!    the canonical triangle's boundary, where crossing points computed from
//!    `B`'s edges fall on either side by rounding. So when `B`'s segment
//!    misses `A` and a corner of `A` lies on `B`'s plane (its offset, known
//!    from the exit of step 2, is zero), the test runs once more in `B`'s
//!    parameter plane, where that corner or edge of `A` is a section point
//!    inside `B`. On `tests/tri_tri_agreement.rs` this brings the touching
//!    pairs decided against the oracle from 26,524 to 7,193 (of 309,727;
//!    the edge-crossing test: 2,931; swapping on every miss: 2,734, but 13 %
//!    slower on `benches/kernels.rs`), and the living-room scenario's
//!    foot-on-floor contacts back to parry's pairs.
//!
//! Offsets within their rounding error are snapped to zero
//! ([`super::coplanar_degenerate`]); `tests/tri_tri_agreement.rs` checks the
//! answers against the exact oracle [`super::exact`]: only touching pairs
//! may differ.
//!
//! Generic over [`Scalar`]: [`triangles_intersect`] is the `f64`
//! instantiation; [`triangles_intersect_as`] with
//! [`super::counted::Counted`] counts the operations paid.

use super::Triangle;
use super::coplanar_degenerate::{
    coplanar, degenerate_pair, edge_scale, one_side, plane_offsets_scaled,
};
use super::scalar::Scalar;
use super::vec3::{V3, cross, dot, is_zero, sub, widen_triangle};

/// Whether two closed triangles share a point (`f64` arithmetic from the
/// `f32` corners; touching counts).
///
/// ```
/// use cornertree::geometry::tropp::triangles_intersect;
/// use cornertree::geometry::{Point, Triangle};
///
/// let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
///     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
/// };
/// let floor = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// // An edge along z through (0.25, 0.25, 0), inside the floor.
/// let piercing = tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [-1.0, 0.25, 0.5]);
/// assert!(triangles_intersect(&floor, &piercing) && triangles_intersect(&piercing, &floor));
/// // The same edge through (0.75, 0.75, 0), beyond the hypotenuse.
/// let beside = tri([0.75, 0.75, -1.0], [0.75, 0.75, 1.0], [2.0, 0.75, 0.5]);
/// assert!(!triangles_intersect(&floor, &beside) && !triangles_intersect(&beside, &floor));
/// // Edge on edge: a triangle standing on the floor's edge y = 0,
/// // touching it along (0.25, 0, 0)–(0.75, 0, 0).
/// let standing = tri([0.25, 0.0, 0.0], [0.75, 0.0, 0.0], [0.5, -0.5, 1.0]);
/// assert!(triangles_intersect(&floor, &standing) && triangles_intersect(&standing, &floor));
/// // Coplanar, overlapping, and coplanar, apart.
/// let overlapping = tri([0.5, 0.5, 0.0], [-0.5, 0.5, 0.0], [0.5, -0.5, 0.0]);
/// let apart = tri([1.0, 1.0, 0.0], [2.0, 1.0, 0.0], [1.0, 2.0, 0.0]);
/// assert!(triangles_intersect(&floor, &overlapping));
/// assert!(!triangles_intersect(&floor, &apart));
/// ```
pub fn triangles_intersect(t1: &Triangle, t2: &Triangle) -> bool {
    triangles_intersect_as::<f64>(t1, t2)
}

/// [`triangles_intersect`] computed in `T`: with
/// [`Counted`](super::counted::Counted), the operations this input pays
/// (an early exit pays less than a full test).
///
/// ```
/// use cornertree::geometry::counted::{Counted, count_operations};
/// use cornertree::geometry::tropp::{triangles_intersect, triangles_intersect_as};
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
/// assert_eq!(hit, triangles_intersect(&floor, &piercing));
/// // `above` lies on one side of the floor's plane: the plane-side exit.
/// assert!(exit < full, "{exit} < {full}");
/// ```
pub fn triangles_intersect_as<T: Scalar>(t1: &Triangle, t2: &Triangle) -> bool {
    prepared_intersect(&Prepared::<T>::new(t1), &Prepared::<T>::new(t2))
}

/// What the test computes from one triangle alone, in `T`: its corners,
/// the edges `u`, `v` from its first corner, their cross product `n` (the
/// plane's normal; exactly zero iff the corners are collinear) and, when
/// `n` is not zero, `|u|²·|v|²` (the scale of the snapping bound of offsets
/// from its plane). A narrow phase whose triangles meet several others
/// (each triangle of two brushing characters meets about seven) prepares
/// each once; [`prepared_intersect`] on two prepared triangles is the very
/// arithmetic of [`triangles_intersect_as`], which prepares both, so the
/// answers are the same bit for bit.
///
/// ```
/// use cornertree::geometry::tropp::{Prepared, prepared_intersect, triangles_intersect};
/// use cornertree::geometry::{Point, Triangle};
///
/// let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
///     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
/// };
/// let floor = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// let others = [
///     tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [-1.0, 0.25, 0.5]), // piercing
///     tri([0.75, 0.75, -1.0], [0.75, 0.75, 1.0], [2.0, 0.75, 0.5]),  // beside
///     tri([0.25, 0.25, 0.0], [0.75, 0.25, 1.0], [0.25, 0.75, 1.0]),  // resting on it
/// ];
/// let floor_once = Prepared::<f64>::new(&floor);
/// let answers = others.map(|t| prepared_intersect(&floor_once, &Prepared::new(&t)));
/// assert_eq!(answers, [true, false, true]);
/// assert_eq!(answers, others.map(|t| triangles_intersect(&floor, &t)));
/// ```
#[derive(Clone, Copy, Debug)]
pub struct Prepared<T> {
    p: [V3<T>; 3],
    u: V3<T>,
    v: V3<T>,
    n: V3<T>,
    flat: bool,
    uv2: T,
}

impl<T: Scalar> Prepared<T> {
    /// Prepares `t` in `T`: corners, edges from the first corner, normal,
    /// whether the corners are collinear, and the snapping scale.
    #[inline(always)]
    pub fn new(t: &Triangle) -> Self {
        let p = widen_triangle::<T>(t);
        let (u, v) = (sub(&p[1], &p[0]), sub(&p[2], &p[0]));
        // Exactly zero iff collinear (edge products are exact, one rounding each).
        let n = cross(&u, &v);
        let flat = is_zero(&n);
        let uv2 = if flat { T::zero() } else { edge_scale(&u, &v) };
        Self {
            p,
            u,
            v,
            n,
            flat,
            uv2,
        }
    }

    /// The plane-side exit's plane: the first corner, the normal (the
    /// edges' cross product, not made a unit vector) and the snapping scale
    /// `|u|²·|v|²` with which [`Self::plane_has_on_one_side`] and
    /// [`prepared_intersect`] snap an offset `d = n·(x − p₀)` to zero where
    /// `d² ≤ (16ε)²·|u|²·|v|²·|x − p₀|²`; `None` for a zero-area triangle.
    #[inline]
    pub fn plane(&self) -> Option<(V3<T>, V3<T>, T)> {
        (!self.flat).then_some((self.p[0], self.n, self.uv2))
    }

    /// Whether `t`'s corners lie strictly on one side of this triangle's
    /// plane, decided by the very arithmetic of [`prepared_intersect`]'s
    /// plane-side exit (`t` widened, its corners' offsets from this
    /// triangle's first corner along its normal, snapped alike): when it is
    /// `true`, `prepared_intersect` of `Prepared::new(t)` with `self` is
    /// `false` either way round. Costs `t`'s corners and three offsets, not
    /// `t`'s preparation: a small triangle tested against a big one usually
    /// lies on one side of the big one's plane (a sole above the floor).
    /// `false` for a zero-area `self` (no plane).
    ///
    /// ```
    /// use cornertree::geometry::tropp::{Prepared, prepared_intersect};
    /// use cornertree::geometry::{Point, Triangle};
    ///
    /// let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
    ///     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
    /// };
    /// let floor = Prepared::<f64>::new(&tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]));
    /// let above = tri([0.2, 0.2, 0.1], [0.5, 0.2, 1.0], [0.2, 0.5, 0.3]);
    /// let resting = tri([0.2, 0.2, 0.0], [0.5, 0.2, 1.0], [0.2, 0.5, 0.3]);
    /// assert!(floor.plane_has_on_one_side(&above));
    /// assert!(!prepared_intersect(&Prepared::new(&above), &floor));
    /// // A corner on the plane: not strictly on one side (and touching).
    /// assert!(!floor.plane_has_on_one_side(&resting));
    /// assert!(prepared_intersect(&Prepared::new(&resting), &floor));
    /// ```
    #[inline]
    pub fn plane_has_on_one_side(&self, t: &Triangle) -> bool {
        if self.flat {
            return false;
        }
        let w = from_corner(&widen_triangle::<T>(t), &self.p[0]);
        one_side(&plane_offsets_scaled(&w, &self.n, self.uv2))
    }
}

/// Whether the closed triangles `a` and `b` share a point
/// ([`triangles_intersect_as`] on prepared triangles).
///
/// ```
/// use cornertree::geometry::tropp::{Prepared, prepared_intersect};
/// use cornertree::geometry::{Point, Triangle};
///
/// let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
///     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
/// };
/// let floor = Prepared::<f64>::new(&tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]));
/// // Zero-area triangles are the segments they span: a vertical segment
/// // through (0.5, 0.25, 0) meets the floor, the one through (0.5, 0.75, 0) does not.
/// let inside = Prepared::new(&tri([0.5, 0.25, -1.0], [0.5, 0.25, 1.0], [0.5, 0.25, 0.0]));
/// let outside = Prepared::new(&tri([0.5, 0.75, -1.0], [0.5, 0.75, 1.0], [0.5, 0.75, 0.0]));
/// assert!(prepared_intersect(&floor, &inside) && prepared_intersect(&inside, &floor));
/// assert!(!prepared_intersect(&floor, &outside) && !prepared_intersect(&outside, &floor));
/// ```
#[inline]
pub fn prepared_intersect<T: Scalar>(a: &Prepared<T>, b: &Prepared<T>) -> bool {
    match (a.flat, b.flat) {
        (false, false) => {
            // Plane-side exits both ways.
            let wb = from_corner(&b.p, &a.p[0]);
            let db = plane_offsets_scaled(&wb, &a.n, a.uv2);
            if one_side(&db) {
                return false;
            }
            let wa = from_corner(&a.p, &b.p[0]);
            let da = plane_offsets_scaled(&wa, &b.n, b.uv2);
            if one_side(&da) {
                return false;
            }
            // B's section of A's plane against A; on a miss with a corner of
            // A on B's plane, A's section of B's plane against B.
            match section_meets(&a.p, &a.u, &a.v, &a.n, &b.p, &wb, &db, true) {
                Some(hit) => hit,
                None => {
                    let z = T::zero();
                    (da[0] == z || da[1] == z || da[2] == z)
                        && section_meets(&b.p, &b.u, &b.v, &b.n, &a.p, &wa, &da, true) == Some(true)
                }
            }
        }
        // A segment (or point) against a triangle: its section of the plane
        // is all of it.
        (false, true) => {
            let wb = from_corner(&b.p, &a.p[0]);
            let db = plane_offsets_scaled(&wb, &a.n, a.uv2);
            !one_side(&db)
                && section_meets(&a.p, &a.u, &a.v, &a.n, &b.p, &wb, &db, false) == Some(true)
        }
        (true, false) => {
            let wa = from_corner(&a.p, &b.p[0]);
            let da = plane_offsets_scaled(&wa, &b.n, b.uv2);
            !one_side(&da)
                && section_meets(&b.p, &b.u, &b.v, &b.n, &a.p, &wa, &da, false) == Some(true)
        }
        (true, true) => degenerate_pair(&a.p, &b.p),
    }
}

/// `qᵢ - c0` for the corners `q`.
#[inline(always)]
fn from_corner<T: Scalar>(q: &[V3<T>; 3], c0: &V3<T>) -> [V3<T>; 3] {
    [sub(&q[0], c0), sub(&q[1], c0), sub(&q[2], c0)]
}

/// Whether `B`'s section of the plane of the non-degenerate `A`
/// (`a0 + α u + β v`, normal `n`) meets `A`, given `B`'s corners as
/// `wᵢ = qᵢ - a0` and their offsets `d` from the plane, not all strictly on
/// one side: `Some` answer, or `None` when the section is a segment that
/// misses `A`. `b_has_area` is for the coplanar case.
#[allow(clippy::too_many_arguments)]
fn section_meets<T: Scalar>(
    a: &[V3<T>; 3],
    u: &V3<T>,
    v: &V3<T>,
    n: &V3<T>,
    b: &[V3<T>; 3],
    w: &[V3<T>; 3],
    d: &[T; 3],
    b_has_area: bool,
) -> Option<bool> {
    let Some((k, i, j)) = apex(&signs(d)) else {
        // All offsets zero: coplanar.
        return Some(coplanar(b, a, n, b_has_area));
    };
    // Cramer numerators of the edges qₖqᵢ and qₖqⱼ, oriented so det > 0.
    let (g, h, det_i, det_j) = if d[k] > d[i] {
        (cross(v, &w[k]), cross(&w[k], u), d[k] - d[i], d[k] - d[j])
    } else {
        (cross(&w[k], v), cross(u, &w[k]), d[i] - d[k], d[j] - d[k])
    };
    let p = [dot(&g, &w[i]), dot(&h, &w[i]), det_i];
    let q = [dot(&g, &w[j]), dot(&h, &w[j]), det_j];
    segment_meets_canonical_triangle(&p, &q).then_some(true)
}

/// Signs of the offsets (at most two comparisons each; the rest of the
/// bookkeeping is on integers).
#[inline(always)]
fn signs<T: Scalar>(d: &[T; 3]) -> [i8; 3] {
    let z = T::zero();
    d.map(|x| {
        if x > z {
            1
        } else if x < z {
            -1
        } else {
            0
        }
    })
}

/// The corner `k` whose two edges `(k, i)`, `(k, j)` span `B ∩ plane`, given
/// the offsets' signs, not all on one side: a corner off the plane with no
/// other corner strictly on its side, or, when the two others are strictly
/// on one side, the corner on the plane. `None` when all signs are zero.
#[inline(always)]
fn apex(s: &[i8; 3]) -> Option<(usize, usize, usize)> {
    let is_apex = |k: usize, i: usize, j: usize| {
        if s[k] != 0 {
            s[k] * s[i] <= 0 && s[k] * s[j] <= 0
        } else {
            s[i] != 0 && s[i] == s[j]
        }
    };
    [(0, 1, 2), (1, 2, 0), (2, 0, 1)]
        .into_iter()
        .find(|&(k, i, j)| is_apex(k, i, j))
}

/// Whether the segment between the homogeneous points `p = (a₁, b₁, D₁)`,
/// `q = (a₂, b₂, D₂)` (`D > 0`, point `(a/D, b/D)`) meets the closed
/// triangle `{α ≥ 0, β ≥ 0, α + β ≤ 1}`.
#[inline(always)]
fn segment_meets_canonical_triangle<T: Scalar>(p: &[T; 3], q: &[T; 3]) -> bool {
    let z = T::zero();
    let ([a1, b1, d1], [a2, b2, d2]) = (*p, *q);
    let (s1, s2) = (a1 + b1, a2 + b2);
    // An end inside. (Decided here, not by the line below: for a segment
    // shrunk to a point that line is rounding noise.)
    if (a1 >= z && b1 >= z && s1 <= d1) || (a2 >= z && b2 >= z && s2 <= d2) {
        return true;
    }
    // Both ends beyond one side of the triangle.
    if (a1 < z && a2 < z) || (b1 < z && b2 < z) || (s1 > d1 && s2 > d2) {
        return false;
    }
    // The triangle's corners strictly on one side of the segment's line:
    // det[p; q; corner] for (0,0), (1,0), (0,1).
    let c = a1 * b2 - a2 * b1;
    let c1 = c + b1 * d2 - b2 * d1;
    let c2 = c + a2 * d1 - a1 * d2;
    !((c > z && c1 > z && c2 > z) || (c < z && c1 < z && c2 < z))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use crate::geometry::coplanar_degenerate::plane_offsets;
    use crate::geometry::triangle_prism::TrianglePrism;

    fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
        Triangle::new(Point::from(a), Point::from(b), Point::from(c))
    }

    /// `plane_has_on_one_side` claims only pairs the full test rejects,
    /// both ways round, and does claim some: random small triangles about
    /// the planes of random big ones, corners on the plane included. And
    /// a pair it does not claim whose small triangle lies inside the big
    /// one's edge planes ([`TrianglePrism::holds_inside`]) is one the test
    /// says meets.
    #[test]
    fn one_side_of_the_plane_only_where_the_test_says_apart() {
        let mut r = crate::test_rng::unit_floats(17);
        let (mut claimed, mut apart, mut inside) = (0, 0, 0);
        for _ in 0..20_000 {
            let big = tri(
                [r() * 8.0 - 4.0, 0.0, r() * 8.0 - 4.0],
                [
                    r() * 8.0 - 4.0,
                    if r() < 0.5 { 0.0 } else { r() * 0.5 },
                    r() * 8.0 - 4.0,
                ],
                [r() * 8.0 - 4.0, 0.0, r() * 8.0 - 4.0],
            );
            let c = [r() - 0.5, r() * 0.2 - 0.1, r() - 0.5];
            let mut corner = || {
                let on_plane = r() < 0.2;
                [
                    c[0] + r() * 0.1,
                    if on_plane {
                        0.0
                    } else {
                        c[1] + r() * 0.1 - 0.05
                    },
                    c[2] + r() * 0.1,
                ]
            };
            let small = tri(corner(), corner(), corner());
            let (pb, ps) = (Prepared::<f64>::new(&big), Prepared::<f64>::new(&small));
            let meets = prepared_intersect(&ps, &pb);
            assert_eq!(meets, prepared_intersect(&pb, &ps), "{small:?} {big:?}");
            apart += !meets as u32;
            if pb.plane_has_on_one_side(&small) {
                claimed += 1;
                assert!(!meets, "claimed apart, but they meet: {small:?} {big:?}");
            } else if TrianglePrism::new(&big).holds_inside(&small) {
                // The rigid pass's second shortcut: reaching the plane
                // inside the edge planes is a contact.
                inside += 1;
                assert!(
                    meets,
                    "inside and reaching the plane, but apart: {small:?} {big:?}"
                );
            }
        }
        assert!(claimed > 5_000, "claimed {claimed} of {apart} apart");
        assert!(inside > 500, "{inside} inside");
    }

    #[test]
    fn piercing_and_separated() {
        let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let pierce = tri([0.2, 0.2, -1.0], [0.2, 0.2, 1.0], [0.5, 2.0, 0.0]);
        let above = tri([0.2, 0.2, 0.1], [0.2, 0.2, 1.0], [0.5, 2.0, 0.1]);
        let beside = tri([2.0, 2.0, -1.0], [2.0, 2.0, 1.0], [3.0, 1.0, 0.0]);
        assert!(triangles_intersect(&t, &pierce) && triangles_intersect(&pierce, &t));
        assert!(!triangles_intersect(&t, &above) && !triangles_intersect(&above, &t));
        assert!(!triangles_intersect(&t, &beside) && !triangles_intersect(&beside, &t));
    }

    #[test]
    fn crossing_points_in_parameter_plane() {
        // A: the unit right triangle at z = 0, so (α, β) = (x, y).
        let (a0, u, v) = ([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
        let n = cross(&u, &v);
        let b = [[0.25, 0.5, 1.0], [0.25, 0.5, -1.0], [0.75, 0.5, -1.0]];
        let w = b.map(|q| sub(&q, &a0));
        let d = plane_offsets(&w, &n, &u, &v);
        assert_eq!(apex(&signs(&d)), Some((0, 1, 2)));
        let (g, h) = (cross(&v, &w[0]), cross(&w[0], &u));
        let det = d[0] - d[1];
        // Edge q0q1 crosses at (0.25, 0.5), edge q0q2 at (0.5, 0.5).
        assert_eq!((dot(&g, &w[1]) / det, dot(&h, &w[1]) / det), (0.25, 0.5));
        let det2 = d[0] - d[2];
        assert_eq!((dot(&g, &w[2]) / det2, dot(&h, &w[2]) / det2), (0.5, 0.5));
    }

    #[test]
    fn apex_of_each_sign_pattern() {
        let f = |d: [f64; 3]| apex(&signs(&d)).map(|(k, _, _)| k);
        assert_eq!(f([1.0, 1.0, -1.0]), Some(2));
        assert_eq!(f([-1.0, 1.0, 1.0]), Some(0));
        assert_eq!(f([1.0, 1.0, 0.0]), Some(2));
        assert_eq!(f([0.0, 0.0, 1.0]), Some(2));
        assert_eq!(f([1.0, -1.0, 0.0]), Some(0));
        // A corner on the plane, the others on either side: not the apex.
        assert_eq!(f([0.0, -1.0, 1.0]), Some(1));
        assert_eq!(f([1.0, 0.0, -1.0]), Some(0));
        assert_eq!(f([0.0, 0.0, 0.0]), None);
    }

    #[test]
    fn segment_against_canonical_triangle() {
        let h = |a: f64, b: f64| [a, b, 1.0];
        let meets = |p, q| segment_meets_canonical_triangle(&p, &q);
        assert!(meets(h(0.2, 0.2), h(0.3, 0.3))); // inside
        assert!(meets(h(-1.0, 0.5), h(2.0, 0.25))); // across
        assert!(meets(h(0.5, 0.5), h(2.0, 2.0))); // ends on the hypotenuse
        assert!(!meets(h(-1.0, 0.5), h(-0.1, 3.0))); // α < 0
        assert!(!meets(h(0.6, 0.6), h(2.0, -0.5))); // beside the hypotenuse's corner
        assert!(!meets(h(1.0, 0.5), h(0.5, 1.0)));
        // Only the segment's line separates: it passes beside the corner (1, 0).
        assert!(!meets(h(0.8, -0.5), h(1.5, 0.3)));
        assert!(meets(h(0.8, -0.5), h(0.9, 0.3)));
        // Scaled homogeneous coordinates give the same answer.
        assert!(meets([0.4, 0.4, 2.0], [3.0, 3.0, 10.0]));
        assert!(!meets([2.0, 1.0, 2.0], [1.5, 3.0, 3.0]));
    }
}
