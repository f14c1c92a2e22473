//! Tropp et al. triangle-triangle intersection test (paper §3, narrow phase).
//!
//! The paper's narrow phase runs the test of Tropp, Tal and Shimshoni (2006)
//! on the triangles under two colliding leaf spheres ("all the redundant
//! operations to calculate determinants are discarded"); its operation model
//! (§6) charges it 96 basic operations.
//!
//! Our version, in `f64` from the `f32` corners, for closed triangles:
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
//! Robustness: with `f32` inputs, edges, 2D orientations and cross products
//! of edges are exact or singly rounded in `f64`, so zero tests on them are
//! exact. Plane offsets are not, so an offset within its rounding-error bound
//! (`16 ε |u| |v| |w|`, ε = 2⁻⁵²) is snapped to zero. This keeps exact
//! coplanar and corner-on-plane contacts exact; it can only turn a separation
//! below that bound (relative ~1e-15, more for slivers) into a contact. The
//! remaining rounding affects only pairs at (or within rounding of) touching;
//! `tests/tri_tri_agreement.rs` measures this against [`super::exact`].

use nalgebra::Vector3;

use super::Triangle;

type V = Vector3<f64>;
type P2 = [f64; 2];

/// The edges (i, j) of a corner triple.
const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// Rounding-error bound factor for plane offsets (see module docs).
const SNAP: f64 = 16.0 * f64::EPSILON;

fn widen(t: &Triangle) -> [V; 3] {
    t.vertices().map(|p| p.coords.cast::<f64>())
}

/// Whether two closed triangles share a point.
pub fn triangles_intersect(t1: &Triangle, t2: &Triangle) -> bool {
    let (a, b) = (widen(t1), widen(t2));
    let (ua, va) = (a[1] - a[0], a[2] - a[0]);
    let (ub, vb) = (b[1] - b[0], b[2] - b[0]);
    let (na, nb) = (ua.cross(&va), ub.cross(&vb));
    // Exactly zero iff collinear: edge products are exact, one rounding each.
    let (deg_a, deg_b) = (na == V::zeros(), nb == V::zeros());
    match (deg_a, deg_b) {
        (false, false) => {
            let db = offsets(&b, &a[0], &na, &ua, &va);
            if one_side(&db) {
                return false;
            }
            let da = offsets(&a, &b[0], &nb, &ub, &vb);
            if one_side(&da) {
                return false;
            }
            if db == [0.0; 3] {
                return coplanar(&a, &b, &na, true);
            }
            if da == [0.0; 3] {
                // Only possible for slivers, where the snap bounds differ.
                return coplanar(&b, &a, &nb, true);
            }
            edges_hit(&b, &db, &a[0], &ua, &va) || edges_hit(&a, &da, &b[0], &ub, &vb)
        }
        (true, false) => segments_vs_triangle(&a, &b, &ub, &vb, &nb),
        (false, true) => segments_vs_triangle(&b, &a, &ua, &va, &na),
        (true, true) => EDGES.iter().any(|&(i, j)| {
            EDGES
                .iter()
                .any(|&(k, l)| seg_seg_3d(&a[i], &a[j], &b[k], &b[l]))
        }),
    }
}

/// Offsets `n · (pᵢ - a0)` of the corners `p` from the plane `(a0, n = u × v)`,
/// snapped to zero within their rounding-error bound.
fn offsets(p: &[V; 3], a0: &V, n: &V, u: &V, v: &V) -> [f64; 3] {
    let uv2 = u.norm_squared() * v.norm_squared();
    p.map(|pi| {
        let w = pi - a0;
        let d = n.dot(&w);
        if d * d <= SNAP * SNAP * uv2 * w.norm_squared() {
            0.0
        } else {
            d
        }
    })
}

/// All strictly on the same side.
fn one_side(d: &[f64; 3]) -> bool {
    d.iter().all(|&x| x > 0.0) || d.iter().all(|&x| x < 0.0)
}

/// Whether an edge of `p` (corner offsets `d` from the plane of the triangle
/// `a0 + βu + γv`) meets that closed triangle. Edges lying in the plane are
/// skipped: their contacts are also found through a crossing edge (or the
/// caller uses the coplanar test).
fn edges_hit(p: &[V; 3], d: &[f64; 3], a0: &V, u: &V, v: &V) -> bool {
    let w = p.map(|pi| pi - a0);
    EDGES.iter().any(|&(i, j)| {
        let (di, dj) = (d[i], d[j]);
        if (di > 0.0 && dj > 0.0) || (di < 0.0 && dj < 0.0) || (di == 0.0 && dj == 0.0) {
            return false;
        }
        // Cramer numerators for β and γ; t ∈ [0, 1] holds by the sign test.
        let c = w[i].cross(&w[j]);
        let (mut det, mut beta, mut gamma) = (di - dj, v.dot(&c), -u.dot(&c));
        if det < 0.0 {
            (det, beta, gamma) = (-det, -beta, -gamma);
        }
        beta >= 0.0 && gamma >= 0.0 && beta + gamma <= det
    })
}

/// A degenerate triangle `s` (a segment or point: the union of its edges)
/// against the non-degenerate triangle `t`.
fn segments_vs_triangle(s: &[V; 3], t: &[V; 3], u: &V, v: &V, n: &V) -> bool {
    let d = offsets(s, &t[0], n, u, v);
    if one_side(&d) {
        return false;
    }
    if d == [0.0; 3] {
        return coplanar(s, t, n, false);
    }
    edges_hit(s, &d, &t[0], u, v)
}

/// Coordinate with the largest magnitude.
fn major_axis(n: &V) -> usize {
    n.iamax()
}

fn proj(p: &V, axis: usize) -> P2 {
    [p[(axis + 1) % 3], p[(axis + 2) % 3]]
}

/// 2D orientation; exact sign for `f32`-valued coordinates.
fn orient2(a: P2, b: P2, c: P2) -> f64 {
    (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
}

/// Closed segments in the plane (either may be a point).
fn seg_seg_2d(p: P2, q: P2, r: P2, s: P2) -> bool {
    let (o1, o2) = (orient2(p, q, r), orient2(p, q, s));
    let (o3, o4) = (orient2(r, s, p), orient2(r, s, q));
    if (o1 > 0.0 && o2 > 0.0) || (o1 < 0.0 && o2 < 0.0) {
        return false;
    }
    if (o3 > 0.0 && o4 > 0.0) || (o3 < 0.0 && o4 < 0.0) {
        return false;
    }
    if o1 == 0.0 && o2 == 0.0 && o3 == 0.0 && o4 == 0.0 {
        return (0..2)
            .all(|k| p[k].min(q[k]) <= r[k].max(s[k]) && r[k].min(s[k]) <= p[k].max(q[k]));
    }
    true
}

/// Point in the closed, non-degenerate triangle `t`, in the plane.
fn point_in_tri_2d(p: P2, t: &[P2; 3]) -> bool {
    let s = EDGES.map(|(i, j)| orient2(t[i], t[j], p));
    !(s.iter().any(|&x| x > 0.0) && s.iter().any(|&x| x < 0.0))
}

/// Coplanar test: `t` is non-degenerate with normal `n`; `s` may be
/// degenerate (`s_has_area == false`). Contact iff edges cross or a corner of
/// one lies in the other.
fn coplanar(s: &[V; 3], t: &[V; 3], n: &V, s_has_area: bool) -> bool {
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
fn seg_seg_3d(p: &V, q: &V, r: &V, s: &V) -> bool {
    let (e, f, g) = (q - p, s - r, r - p);
    let n = e.cross(&f);
    if n != V::zeros() {
        // Not parallel: coplanar (within rounding), then 2D.
        let vol = n.dot(&g);
        if vol * vol > SNAP * SNAP * e.norm_squared() * f.norm_squared() * g.norm_squared() {
            return false;
        }
        let k = major_axis(&n);
        return seg_seg_2d(proj(p, k), proj(q, k), proj(r, k), proj(s, k));
    }
    // Parallel, or one is a point: collinear, then 1D overlap on the major axis.
    let (dir, off) = if e != V::zeros() { (e, g) } else { (f, p - r) };
    if dir == V::zeros() {
        return p == r;
    }
    if dir.cross(&off) != V::zeros() {
        return false;
    }
    let k = major_axis(&dir);
    p[k].min(q[k]) <= r[k].max(s[k]) && r[k].min(s[k]) <= p[k].max(q[k])
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

    #[test]
    fn skew_and_collinear_segments() {
        let v = |x: f64, y: f64, z: f64| V::new(x, y, z);
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
