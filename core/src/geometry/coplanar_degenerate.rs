//! What both triangle-triangle tests ([`super::tropp`],
//! [`super::edge_crossing`]) share: plane offsets snapped within their
//! rounding error, coplanar pairs (a 2D test), and zero-area triangles
//! (segments, points). Generic over [`Scalar`] so the operations can be
//! counted.
//!
//! Robustness: with `f32` inputs, edges, 2D orientations and cross products
//! of edges are exact or singly rounded in `f64`, so zero tests on them are
//! exact. Plane offsets are not, so an offset within its rounding-error bound
//! (`16 ε |u| |v| |w|`, ε = 2⁻⁵²) is snapped to zero. This keeps exact
//! coplanar and corner-on-plane contacts exact; it can only turn a separation
//! below that bound (relative ~1e-15, more for slivers) into a contact.

use super::scalar::Scalar;
use super::vec3::{V3, cross, dot, equal, is_zero, major_axis, norm_squared, sub};

type P2<T> = [T; 2];

/// The edges (i, j) of a corner triple.
pub const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// Rounding-error bound factor for plane offsets (see module docs).
pub(crate) const SNAP: f64 = 16.0 * f64::EPSILON;

/// Offsets `dᵢ = n · wᵢ` of corners from the plane through `a0` with normal
/// `n = u × v`, given `wᵢ = pᵢ - a0`; each snapped to zero within its
/// rounding-error bound.
///
/// ```
/// use cornertree::geometry::coplanar_degenerate::plane_offsets;
/// use cornertree::geometry::vec3::cross;
///
/// // The plane z = 0 through the origin, spanned by u and v.
/// let (u, v) = ([2.0f64, 0.0, 0.0], [0.0, 2.0, 0.0]);
/// let n = cross(&u, &v); // (0, 0, 4)
/// let w = [[1.0, 1.0, 0.5], [3.0, -1.0, -2.0], [5.0, 5.0, 1e-17]];
/// // 1e-17 is within the rounding bound of the third offset: snapped to 0.
/// assert_eq!(plane_offsets(&w, &n, &u, &v), [2.0, -8.0, 0.0]);
/// ```
#[inline(always)]
pub fn plane_offsets<T: Scalar>(w: &[V3<T>; 3], n: &V3<T>, u: &V3<T>, v: &V3<T>) -> [T; 3] {
    plane_offsets_scaled(w, n, edge_scale(u, v))
}

/// `|u|²·|v|²`, the scale of [`plane_offsets`]' snapping bound.
#[inline(always)]
pub fn edge_scale<T: Scalar>(u: &V3<T>, v: &V3<T>) -> T {
    norm_squared(u) * norm_squared(v)
}

/// [`plane_offsets`] with `uv2 = edge_scale(u, v)` given.
#[inline(always)]
pub fn plane_offsets_scaled<T: Scalar>(w: &[V3<T>; 3], n: &V3<T>, uv2: T) -> [T; 3] {
    let snap2 = T::from_f64(SNAP * SNAP);
    w.map(|wi| {
        let d = dot(n, &wi);
        if d * d <= snap2 * uv2 * norm_squared(&wi) {
            T::zero()
        } else {
            d
        }
    })
}

/// All strictly on the same side.
#[inline(always)]
pub fn one_side<T: Scalar>(d: &[T; 3]) -> bool {
    let z = T::zero();
    (d[0] > z && d[1] > z && d[2] > z) || (d[0] < z && d[1] < z && d[2] < z)
}

/// All exactly zero.
#[inline(always)]
pub fn all_zero<T: Scalar>(d: &[T; 3]) -> bool {
    let z = T::zero();
    d[0] == z && d[1] == z && d[2] == z
}

/// Whether the corners are not collinear (exact for `f32` corners).
#[inline(always)]
pub fn has_area<T: Scalar>(p: &[V3<T>; 3]) -> bool {
    !is_zero(&cross(&sub(&p[1], &p[0]), &sub(&p[2], &p[0])))
}

fn proj<T: Scalar>(p: &V3<T>, axis: usize) -> P2<T> {
    [p[(axis + 1) % 3], p[(axis + 2) % 3]]
}

/// 2D orientation; exact sign for `f32`-valued coordinates.
fn orient2<T: Scalar>(a: P2<T>, b: P2<T>, c: P2<T>) -> T {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Whether the closed intervals `[min(p, q), max(p, q)]` and
/// `[min(r, s), max(r, s)]` meet.
fn intervals_meet<T: Scalar>(p: T, q: T, r: T, s: T) -> bool {
    p.min_of(q) <= r.max_of(s) && r.min_of(s) <= p.max_of(q)
}

/// Closed segments in the plane (either may be a point).
fn seg_seg_2d<T: Scalar>(p: P2<T>, q: P2<T>, r: P2<T>, s: P2<T>) -> bool {
    let z = T::zero();
    let (o1, o2) = (orient2(p, q, r), orient2(p, q, s));
    let (o3, o4) = (orient2(r, s, p), orient2(r, s, q));
    if (o1 > z && o2 > z) || (o1 < z && o2 < z) {
        return false;
    }
    if (o3 > z && o4 > z) || (o3 < z && o4 < z) {
        return false;
    }
    if o1 == z && o2 == z && o3 == z && o4 == z {
        return (0..2).all(|k| intervals_meet(p[k], q[k], r[k], s[k]));
    }
    true
}

/// Point in the closed, non-degenerate triangle `t`, in the plane.
fn point_in_tri_2d<T: Scalar>(p: P2<T>, t: &[P2<T>; 3]) -> bool {
    let z = T::zero();
    let s = EDGES.map(|(i, j)| orient2(t[i], t[j], p));
    !(s.iter().any(|&x| x > z) && s.iter().any(|&x| x < z))
}

/// Coplanar test: `t` is non-degenerate with normal `n`; `s` may be
/// degenerate (`s_has_area == false`). Contact iff edges cross or a corner of
/// one lies in the other (closed triangles).
///
/// ```
/// use cornertree::geometry::coplanar_degenerate::coplanar;
///
/// let t = [[0.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let n = [0.0, 0.0, 1.0];
/// // Inside t entirely (no edges cross): a corner inside decides.
/// let inner = [[0.1, 0.1, 0.0], [0.3, 0.1, 0.0], [0.1, 0.3, 0.0]];
/// assert!(coplanar(&inner, &t, &n, true));
/// // t inside a big triangle: a corner of t inside s decides.
/// let big = [[-5.0, -5.0, 0.0], [10.0, -5.0, 0.0], [-5.0, 10.0, 0.0]];
/// assert!(coplanar(&big, &t, &n, true));
/// // Sharing the corner (1, 0, 0) only: touching counts.
/// let corner = [[1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0]];
/// assert!(coplanar(&corner, &t, &n, true));
/// // Beyond the hypotenuse.
/// let apart = [[1.0, 1.0, 0.0], [2.0, 1.0, 0.0], [1.0, 2.0, 0.0]];
/// assert!(!coplanar(&apart, &t, &n, true));
/// ```
pub fn coplanar<T: Scalar>(s: &[V3<T>; 3], t: &[V3<T>; 3], n: &V3<T>, s_has_area: bool) -> bool {
    let k = major_axis(n);
    let (s2, t2) = (s.map(|p| proj(&p, k)), t.map(|p| proj(&p, k)));
    EDGES.iter().any(|&(i, j)| {
        EDGES
            .iter()
            .any(|&(k, l)| seg_seg_2d(s2[i], s2[j], t2[k], t2[l]))
    }) || point_in_tri_2d(s2[0], &t2)
        || (s_has_area && point_in_tri_2d(t2[0], &s2))
}

/// Closed segments `pq` and `rs` in space (either may be a point).
///
/// ```
/// use cornertree::geometry::coplanar_degenerate::seg_seg_3d;
///
/// let o = [0.0f64; 3];
/// // The diagonals of a square cross at (1, 1, 0).
/// assert!(seg_seg_3d(&o, &[2.0, 2.0, 0.0], &[2.0, 0.0, 0.0], &[0.0, 2.0, 0.0]));
/// // The second lifted by 1: skew, no contact.
/// assert!(!seg_seg_3d(&o, &[2.0, 2.0, 0.0], &[2.0, 0.0, 1.0], &[0.0, 2.0, 1.0]));
/// // Collinear, sharing the end (1, 1, 1); then apart on the same line.
/// assert!(seg_seg_3d(&o, &[1.0, 1.0, 1.0], &[1.0, 1.0, 1.0], &[3.0, 3.0, 3.0]));
/// assert!(!seg_seg_3d(&o, &[1.0, 1.0, 1.0], &[2.0, 2.0, 2.0], &[3.0, 3.0, 3.0]));
/// // A point on a segment.
/// let p = [0.5, 0.5, 0.5];
/// assert!(seg_seg_3d(&p, &p, &o, &[1.0, 1.0, 1.0]));
/// ```
pub fn seg_seg_3d<T: Scalar>(p: &V3<T>, q: &V3<T>, r: &V3<T>, s: &V3<T>) -> bool {
    let (e, f, g) = (sub(q, p), sub(s, r), sub(r, p));
    let n = cross(&e, &f);
    if !is_zero(&n) {
        // Not parallel: coplanar (within rounding), then 2D.
        let vol = dot(&n, &g);
        let snap2 = T::from_f64(SNAP * SNAP);
        if vol * vol > snap2 * norm_squared(&e) * norm_squared(&f) * norm_squared(&g) {
            return false;
        }
        let k = major_axis(&n);
        return seg_seg_2d(proj(p, k), proj(q, k), proj(r, k), proj(s, k));
    }
    // Parallel, or one is a point: collinear, then 1D overlap on the major axis.
    let (dir, off) = if !is_zero(&e) { (e, g) } else { (f, sub(p, r)) };
    if is_zero(&dir) {
        return equal(p, r);
    }
    if !is_zero(&cross(&dir, &off)) {
        return false;
    }
    let k = major_axis(&dir);
    intervals_meet(p[k], q[k], r[k], s[k])
}

/// Two zero-area triangles (the unions of their edges): some pair of edges meets.
///
/// ```
/// use cornertree::geometry::coplanar_degenerate::degenerate_pair;
///
/// // Two collinear-cornered "triangles": segments along x and along y.
/// let along_x = [[-1.0f64, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]];
/// let along_y = [[0.0, -1.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.5, 0.0]];
/// assert!(degenerate_pair(&along_x, &along_y)); // crossing at the origin
/// let above = along_y.map(|p| [p[0], p[1], 0.5]);
/// assert!(!degenerate_pair(&along_x, &above));
/// ```
pub fn degenerate_pair<T: Scalar>(a: &[V3<T>; 3], b: &[V3<T>; 3]) -> bool {
    EDGES.iter().any(|&(i, j)| {
        EDGES
            .iter()
            .any(|&(k, l)| seg_seg_3d(&a[i], &a[j], &b[k], &b[l]))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn skew_and_collinear_segments() {
        let v = |x: f64, y: f64, z: f64| [x, y, z];
        let o = v(0.0, 0.0, 0.0);
        assert!(seg_seg_3d(
            &o,
            &v(2.0, 2.0, 0.0),
            &v(2.0, 0.0, 0.0),
            &v(0.0, 2.0, 0.0)
        ));
        assert!(!seg_seg_3d(
            &o,
            &v(2.0, 2.0, 0.0),
            &v(2.0, 0.0, 1.0),
            &v(0.0, 2.0, 1.0)
        ));
        assert!(seg_seg_3d(
            &o,
            &v(2.0, 2.0, 2.0),
            &v(1.0, 1.0, 1.0),
            &v(3.0, 3.0, 3.0)
        ));
        assert!(!seg_seg_3d(
            &o,
            &v(1.0, 1.0, 1.0),
            &v(2.0, 2.0, 2.0),
            &v(3.0, 3.0, 3.0)
        ));
        assert!(seg_seg_3d(
            &v(1.0, 1.0, 1.0),
            &v(1.0, 1.0, 1.0),
            &o,
            &v(2.0, 2.0, 2.0)
        ));
    }
}
