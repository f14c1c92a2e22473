//! Exact triangle-triangle oracle on adaptive exact predicates.
//!
//! Reference for the floating-point kernel in [`super::tri_tri`]: every
//! decision here is the sign of Shewchuk's adaptive `orient3d`/`orient2d`
//! (the `robust` crate) or an exact comparison of coordinates. `f32`
//! coordinates widen to `f64` exactly, so the answers are exact for every
//! finite input; there is no epsilon anywhere.
//!
//! Classification of two closed triangles ([`Contact`]):
//! * `Disjoint`: no common point;
//! * `Touching`: a common point, but the relative interiors do not meet;
//! * `Overlapping`: the relative interiors share a point (a proper piercing,
//!   or coplanar overlap with positive area).
//!
//! A degenerate triangle (collinear corners, or a single point) is handled as
//! the segment or point it is. It has no two-dimensional interior, so **any
//! contact involving a degenerate triangle is `Touching`**.
//!
//! Method. Two closed (possibly degenerate) triangles meet iff some edge of one
//! meets the other closed triangle (an extreme point of the intersection lies on
//! a boundary), so [`triangles_intersect_exact`] runs exact segment-triangle and,
//! for two degenerate triangles, segment-segment tests. Touching versus
//! overlapping: if one triangle lies weakly on one side of the other's plane the
//! contact is on its boundary; otherwise both cross the common line of the two
//! planes in segments whose open parts are relative-interior points, and the two
//! segments are compared with `orient3d` (strictly for `Overlapping`). Coplanar
//! pairs use a separating-edge test in a projection where both are
//! non-degenerate.

use robust::{Coord, Coord3D, orient2d, orient3d};

use super::Triangle;

/// How two closed triangles meet, decided exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Contact {
    /// No common point.
    Disjoint,
    /// They meet, but only on the boundary of at least one of them.
    Touching,
    /// Their relative interiors share a point.
    Overlapping,
}

type P3 = [f64; 3];
type P2 = [f64; 2];

/// The edges (i, j) of a corner triple.
const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

fn widen(t: &Triangle) -> [P3; 3] {
    t.vertices().map(|p| [p.x as f64, p.y as f64, p.z as f64])
}

fn c3(p: P3) -> Coord3D<f64> {
    Coord3D {
        x: p[0],
        y: p[1],
        z: p[2],
    }
}

fn sign(x: f64) -> i8 {
    if x > 0.0 {
        1
    } else if x < 0.0 {
        -1
    } else {
        0
    }
}

/// Sign of `det[b - a, c - a, d - a]`: positive when `d` lies on the side the
/// normal `(b - a) × (c - a)` points to. (`robust::orient3d` has the opposite sign.)
/// Exact for every finite input: `0` means exactly coplanar.
///
/// ```
/// use cornertree::geometry::exact::orient3;
///
/// let (o, x, y) = ([0.0; 3], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// assert_eq!(orient3(o, x, y, [0.0, 0.0, 1.0]), 1); // above z = 0, normal +z
/// assert_eq!(orient3(o, y, x, [0.0, 0.0, 1.0]), -1); // corners swapped
/// assert_eq!(orient3(o, x, y, [3.0, -2.0, 0.0]), 0); // in the plane
/// // Off the plane by 1e-300: still decided, no epsilon.
/// assert_eq!(orient3(o, x, y, [0.3, 0.7, -1e-300]), -1);
/// ```
pub fn orient3(a: P3, b: P3, c: P3, d: P3) -> i8 {
    -sign(orient3d(c3(a), c3(b), c3(c), c3(d)))
}

/// Sign of the 2D orientation of `(a, b, c)`: positive for counter-clockwise,
/// zero exactly when collinear.
///
/// ```
/// use cornertree::geometry::exact::orient2;
///
/// assert_eq!(orient2([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), 1);
/// assert_eq!(orient2([0.0, 0.0], [0.0, 1.0], [1.0, 0.0]), -1);
/// assert_eq!(orient2([0.0, 0.0], [1.0, 1.0], [3.0, 3.0]), 0);
/// ```
pub fn orient2(a: P2, b: P2, c: P2) -> i8 {
    let c2 = |p: P2| Coord { x: p[0], y: p[1] };
    sign(orient2d(c2(a), c2(b), c2(c)))
}

/// Projection dropping coordinate `axis`.
fn proj(p: P3, axis: usize) -> P2 {
    [p[(axis + 1) % 3], p[(axis + 2) % 3]]
}

/// Whether the corners are collinear (including coincident). Exact: the three
/// components of `(b - a) × (c - a)` are the 2D orientations of the three
/// coordinate projections.
fn is_degenerate(t: &[P3; 3]) -> bool {
    (0..3).all(|k| orient2(proj(t[0], k), proj(t[1], k), proj(t[2], k)) == 0)
}

/// For coplanar points, a coordinate to drop so that the projection is
/// injective on their plane (or on their line, if they are collinear).
fn pick_projection(pts: &[P3]) -> usize {
    let n = pts.len();
    for k in 0..3 {
        for i in 0..n {
            for j in i + 1..n {
                for l in j + 1..n {
                    if orient2(proj(pts[i], k), proj(pts[j], k), proj(pts[l], k)) != 0 {
                        return k;
                    }
                }
            }
        }
    }
    // Collinear: any projection that does not collapse the points is injective
    // on their line.
    (0..3)
        .find(|&k| pts.iter().any(|&p| proj(p, k) != proj(pts[0], k)))
        .unwrap_or(0)
}

/// Closed segments `pq` and `rs` in the plane (either may be a point).
fn seg_seg_2d(p: P2, q: P2, r: P2, s: P2) -> bool {
    let (o1, o2) = (orient2(p, q, r), orient2(p, q, s));
    let (o3, o4) = (orient2(r, s, p), orient2(r, s, q));
    if o1 * o2 > 0 || o3 * o4 > 0 {
        return false;
    }
    if o1 == 0 && o2 == 0 && o3 == 0 && o4 == 0 {
        // All on one line (or points): bounding boxes must overlap.
        return (0..2)
            .all(|k| p[k].min(q[k]) <= r[k].max(s[k]) && r[k].min(s[k]) <= p[k].max(q[k]));
    }
    true
}

/// Point in a closed, non-degenerate triangle, in the plane.
fn point_in_tri_2d(p: P2, t: &[P2; 3]) -> bool {
    let s = EDGES.map(|(i, j)| orient2(t[i], t[j], p));
    !(s.contains(&1) && s.contains(&-1))
}

/// Closed segment `pq` against a closed, non-degenerate triangle, in the plane.
fn seg_tri_2d(p: P2, q: P2, t: &[P2; 3]) -> bool {
    point_in_tri_2d(p, t)
        || point_in_tri_2d(q, t)
        || EDGES.iter().any(|&(i, j)| seg_seg_2d(p, q, t[i], t[j]))
}

/// Closed segment `pq` (possibly a point) against a closed, non-degenerate triangle.
fn seg_tri_3d(p: P3, q: P3, t: &[P3; 3]) -> bool {
    let sp = orient3(t[0], t[1], t[2], p);
    let sq = orient3(t[0], t[1], t[2], q);
    if sp * sq > 0 {
        return false;
    }
    if sp == 0 && sq == 0 {
        let k = pick_projection(t);
        let tp = t.map(|v| proj(v, k));
        return seg_tri_2d(proj(p, k), proj(q, k), &tp);
    }
    // The line pq crosses the plane once, at a point of the segment; it lies in
    // the closed triangle iff the line passes weakly on one side of every edge.
    let s = EDGES.map(|(i, j)| orient3(p, q, t[i], t[j]));
    !(s.contains(&1) && s.contains(&-1))
}

/// Closed segments in space (either may be a point).
fn seg_seg_3d(p: P3, q: P3, r: P3, s: P3) -> bool {
    if orient3(p, q, r, s) != 0 {
        return false;
    }
    let k = pick_projection(&[p, q, r, s]);
    seg_seg_2d(proj(p, k), proj(q, k), proj(r, k), proj(s, k))
}

fn closed_intersect(a: &[P3; 3], b: &[P3; 3], deg_a: bool, deg_b: bool) -> bool {
    let edges_vs = |x: &[P3; 3], t: &[P3; 3]| EDGES.iter().any(|&(i, j)| seg_tri_3d(x[i], x[j], t));
    match (deg_a, deg_b) {
        (false, false) => edges_vs(a, b) || edges_vs(b, a),
        // A degenerate triangle is the union of its edges.
        (true, false) => edges_vs(a, b),
        (false, true) => edges_vs(b, a),
        (true, true) => EDGES.iter().any(|&(i, j)| {
            EDGES
                .iter()
                .any(|&(k, l)| seg_seg_3d(a[i], a[j], b[k], b[l]))
        }),
    }
}

/// [`triangles_intersect_exact`] on `f64` corners (the same predicates,
/// exact for every finite `f64` input): sub-steps of a continuous step.
///
/// ```
/// use cornertree::geometry::exact::corners_intersect_exact;
///
/// let floor = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// // A corner exactly on the hypotenuse x + y = 1, at coordinates no f32
/// // holds; the rest of the triangle above the floor.
/// let (x, y) = (0.75 + 2f64.powi(-40), 0.25 - 2f64.powi(-40));
/// let on_edge = [[x, y, 0.0], [x, y, 1.0], [2.0, 2.0, 1.0]];
/// assert!(corners_intersect_exact(&floor, &on_edge));
/// // The next f64 beyond it: apart.
/// let beyond = [[x, y.next_up(), 0.0], [x, y, 1.0], [2.0, 2.0, 1.0]];
/// assert!(!corners_intersect_exact(&floor, &beyond));
/// ```
pub fn corners_intersect_exact(a: &[[f64; 3]; 3], b: &[[f64; 3]; 3]) -> bool {
    closed_intersect(a, b, is_degenerate(a), is_degenerate(b))
}

/// Whether the two closed triangles share a point, exactly (touching
/// counts; [`classify`] tells touching from overlapping).
///
/// ```
/// use cornertree::geometry::exact::triangles_intersect_exact;
/// use cornertree::geometry::{Point, Triangle};
///
/// let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
///     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
/// };
/// let floor = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// // Crossing the floor through (0.25, 0.25, 0).
/// let piercing = tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [-1.0, 0.25, 0.5]);
/// assert!(triangles_intersect_exact(&floor, &piercing));
/// // Beyond the hypotenuse.
/// let beside = tri([0.75, 0.75, -1.0], [0.75, 0.75, 1.0], [2.0, 0.75, 0.5]);
/// assert!(!triangles_intersect_exact(&floor, &beside));
/// // A corner on the face, then the smallest f32 step above it.
/// let resting = tri([0.25, 0.25, 0.0], [0.75, 0.25, 1.0], [0.25, 0.75, 1.0]);
/// let lifted = tri([0.25, 0.25, f32::MIN_POSITIVE], [0.75, 0.25, 1.0], [0.25, 0.75, 1.0]);
/// assert!(triangles_intersect_exact(&floor, &resting));
/// assert!(!triangles_intersect_exact(&floor, &lifted));
/// ```
pub fn triangles_intersect_exact(t1: &Triangle, t2: &Triangle) -> bool {
    classify(t1, t2) != Contact::Disjoint
}

/// Whether signs include both a strictly positive and a strictly negative one.
fn straddles(s: &[i8; 3]) -> bool {
    s.contains(&1) && s.contains(&-1)
}

/// Index of a corner strictly on one side with the other two weakly on the
/// other side (exists when [`straddles`]).
fn lone(s: &[i8; 3]) -> usize {
    (0..3)
        .find(|&i| s[i] != 0 && (0..3).all(|j| j == i || s[j] != s[i]))
        .expect("straddling signs have a lone corner")
}

/// Corners rotated so that corner `i` comes first (orientation kept).
fn rotate(t: &[P3; 3], i: usize) -> [P3; 3] {
    [t[i], t[(i + 1) % 3], t[(i + 2) % 3]]
}

/// Exact classification of a triangle pair (see [`Contact`]).
///
/// ```
/// use cornertree::geometry::exact::{Contact, classify};
/// use cornertree::geometry::{Point, Triangle};
///
/// let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
///     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
/// };
/// let floor = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// // An edge through the floor's interior: the interiors cross.
/// let piercing = tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [-1.0, 0.25, 0.5]);
/// assert_eq!(classify(&floor, &piercing), Contact::Overlapping);
/// // A corner resting on the face: only a boundary point is shared.
/// let resting = tri([0.25, 0.25, 0.0], [0.75, 0.25, 1.0], [0.25, 0.75, 1.0]);
/// assert_eq!(classify(&floor, &resting), Contact::Touching);
/// // Each crosses the other's plane, but an edge of one meets the other only
/// // at the floor's boundary point (0.5, 0.5, 0): touching.
/// let edge_on_edge = tri([0.75, 0.75, 1.0], [0.25, 0.25, -1.0], [1.75, 1.75, -1.0]);
/// assert_eq!(classify(&floor, &edge_on_edge), Contact::Touching);
/// // Coplanar, sharing only the hypotenuse: touching; overlapping: overlapping.
/// let mirror = tri([1.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]);
/// assert_eq!(classify(&floor, &mirror), Contact::Touching);
/// let shifted = tri([0.5, 0.0, 0.0], [1.5, 0.0, 0.0], [0.5, 1.0, 0.0]);
/// assert_eq!(classify(&floor, &shifted), Contact::Overlapping);
/// // Beyond the hypotenuse.
/// let beside = tri([0.75, 0.75, -1.0], [0.75, 0.75, 1.0], [2.0, 0.75, 0.5]);
/// assert_eq!(classify(&floor, &beside), Contact::Disjoint);
/// // Any contact with a zero-area triangle is touching.
/// let needle = tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [0.25, 0.25, 0.0]);
/// assert_eq!(classify(&floor, &needle), Contact::Touching);
/// ```
pub fn classify(t1: &Triangle, t2: &Triangle) -> Contact {
    let (a, b) = (widen(t1), widen(t2));
    let (deg_a, deg_b) = (is_degenerate(&a), is_degenerate(&b));
    if !closed_intersect(&a, &b, deg_a, deg_b) {
        return Contact::Disjoint;
    }
    if deg_a || deg_b {
        return Contact::Touching;
    }
    // Sides of b's corners w.r.t. a's plane, and of a's w.r.t. b's.
    let sb = b.map(|p| orient3(a[0], a[1], a[2], p));
    if sb == [0, 0, 0] {
        return if coplanar_interiors_meet(&a, &b) {
            Contact::Overlapping
        } else {
            Contact::Touching
        };
    }
    let sa = a.map(|p| orient3(b[0], b[1], b[2], p));
    if !straddles(&sa) || !straddles(&sb) {
        // One triangle meets the other's plane only in a corner or an edge.
        return Contact::Touching;
    }
    // Both cross the common line L of the planes. Put the lone corner first
    // (p1, p2) and orient the planes so that p1 is above b's plane and p2 above
    // a's. Then a ∩ L = [j, i] and b ∩ L = [k, l] run in opposite directions
    // along L, with i on p1q1, j on p1r1, k on p2q2, l on p2r2; orient3 of
    // (p1, q1, p2, q2) compares i with k, and of (p1, r1, r2, p2) j with l.
    let (la, lb) = (lone(&sa), lone(&sb));
    let mut a = rotate(&a, la);
    let mut b = rotate(&b, lb);
    if sa[la] < 0 {
        b.swap(1, 2);
    }
    if sb[lb] < 0 {
        a.swap(1, 2);
    }
    let s_ik = orient3(a[0], a[1], b[0], b[1]);
    let s_jl = orient3(a[0], a[2], b[2], b[0]);
    debug_assert!(
        s_ik <= 0 && s_jl <= 0,
        "interval test disagrees with edge tests"
    );
    if s_ik < 0 && s_jl < 0 {
        Contact::Overlapping
    } else {
        Contact::Touching
    }
}

/// Coplanar, non-degenerate triangles already known to meet: whether the
/// intersection has positive area. The interiors are disjoint iff some edge
/// line has one triangle weakly on each side (separating axes of a convex
/// polygon pair are its edge normals).
fn coplanar_interiors_meet(a: &[P3; 3], b: &[P3; 3]) -> bool {
    let k = pick_projection(a);
    let (a2, b2) = (a.map(|p| proj(p, k)), b.map(|p| proj(p, k)));
    let separates = |x: &[P2; 3], y: &[P2; 3]| {
        (0..3).any(|i| {
            let (u, v, w) = (x[i], x[(i + 1) % 3], x[(i + 2) % 3]);
            let inner = orient2(u, v, w);
            y.iter().all(|&q| orient2(u, v, q) * inner <= 0)
        })
    };
    !separates(&a2, &b2) && !separates(&b2, &a2)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orient3_sign_convention() {
        let o = [0.0; 3];
        let (x, y, z) = ([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]);
        assert_eq!(orient3(o, x, y, z), 1);
        assert_eq!(orient3(o, y, x, z), -1);
        assert_eq!(orient3(o, x, y, [3.0, -2.0, 0.0]), 0);
        assert_eq!(orient2([0.0, 0.0], [1.0, 0.0], [0.0, 1.0]), 1);
    }

    #[test]
    fn collinear_corners_are_degenerate() {
        assert!(is_degenerate(&[[0.0; 3], [1.0, 2.0, 3.0], [2.0, 4.0, 6.0]]));
        assert!(is_degenerate(&[[1.0; 3]; 3]));
        assert!(!is_degenerate(&[
            [0.0; 3],
            [1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0]
        ]));
    }

    #[test]
    fn segments_2d() {
        let (o, x, y, xy) = ([0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0]);
        assert!(seg_seg_2d(o, xy, x, y)); // crossing
        assert!(seg_seg_2d(o, x, x, xy)); // shared end
        assert!(!seg_seg_2d(o, x, y, xy)); // parallel
        assert!(seg_seg_2d(o, [2.0, 0.0], x, [3.0, 0.0])); // collinear overlap
        assert!(!seg_seg_2d(o, x, [2.0, 0.0], [3.0, 0.0])); // collinear apart
        assert!(seg_seg_2d([0.5, 0.0], [0.5, 0.0], o, x)); // point on segment
        assert!(!seg_seg_2d([0.5, 0.1], [0.5, 0.1], o, x));
    }
}
