//! Triangle–triangle continuous collision detection: two triangles, every
//! corner moving on a straight line over the step `t ∈ [0, 1]`.
//!
//! Two closed triangles first touch either at `t = 0` (they already meet)
//! or, later, at a vertex–face or an edge–edge contact: at the first time
//! `t* > 0` some edge of one meets the other triangle, and if that contact
//! were an edge crossing the other's relative interior away from both
//! boundaries, it would have existed a moment earlier (a transversal
//! crossing persists; an edge lying in the other's plane meets it in a
//! segment whose ends are vertex–face or edge–edge contacts). So:
//! 1. swept boxes apart (the two triangles' boxes over the step): `None`;
//! 2. do they meet at `t = 0`? Six static edge–triangle tests, each the
//!    vertex–face search with the "point" moving along the edge and the
//!    triangle still (so the same conservative bounds hold): `Some(0)`;
//! 3. otherwise the 6 vertex–face ([`super::ccd_vertex_face`]) and 9
//!    edge–edge ([`super::ccd_edge_edge`]) tests, each with its own
//!    swept-box early-out, each seeking only contacts earlier than the best
//!    found so far: the earliest lower bound.
//!
//! Conservative like its parts: `None` only when the triangles never touch
//! during the step; otherwise a lower bound of the first contact, with the
//! elementary contact that gave it.

use super::ccd_edge_edge::edge_edge_as;
use super::ccd_error_bounds::{Binary64, Bounds, max_magnitudes};
use super::ccd_root_finder::{CcdParams, Impact, Seek};
use super::ccd_swept_box::SweptBox;
use super::ccd_vertex_face::{search as vertex_face_search, vertex_face_as};
use super::vec3::V3;

/// A triangle's corners at the start (`t = 0`) and end (`t = 1`) of a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MovingTriangle<T> {
    /// Corners at `t = 0`.
    pub start: [V3<T>; 3],
    /// The same corners, in the same order, at `t = 1`; each moves on a
    /// straight line in between.
    pub end: [V3<T>; 3],
}

/// The elementary contact behind a triangle pair's time of impact.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Feature {
    /// The triangles meet at `t = 0`: edge `edge` (corners `edge`,
    /// `edge + 1 mod 3`) of the first (`first`) or second triangle meets the
    /// other.
    AtStart {
        /// Whether the edge is the first triangle's.
        first: bool,
        /// The edge's index, 0 to 2.
        edge: usize,
    },
    /// Corner `vertex` of the first (`first`) or second triangle against
    /// the other's face.
    VertexFace {
        /// Whether the corner is the first triangle's.
        first: bool,
        /// The corner's index, 0 to 2.
        vertex: usize,
    },
    /// Edge `a` of the first triangle against edge `b` of the second.
    EdgeEdge {
        /// The first triangle's edge (corners `a`, `a + 1 mod 3`).
        a: usize,
        /// The second triangle's edge (corners `b`, `b + 1 mod 3`).
        b: usize,
    },
}

/// A possible contact of two moving triangles.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TriangleImpact {
    /// A lower bound of the time of first contact, in `[0, 1)`.
    pub toi: f64,
    /// Which elementary contact gave [`TriangleImpact::toi`].
    pub feature: Feature,
    /// The elementary test's answer (its `toi` is the edge parameter for
    /// [`Feature::AtStart`]).
    pub impact: Impact,
}

/// Whether two moving triangles touch during the step (`f64` arithmetic).
///
/// Conservative (module doc): `None` is certain; `Some` gives a lower bound
/// of the first contact and the elementary contact behind it.
///
/// ```
/// use cornertree::geometry::ccd_root_finder::CcdParams;
/// use cornertree::geometry::ccd_triangles::{Feature, MovingTriangle, triangles};
///
/// let moving = |start: [[f64; 3]; 3], d: [f64; 3]| MovingTriangle {
///     start,
///     end: start.map(|p| [p[0] + d[0], p[1] + d[1], p[2] + d[2]]),
/// };
/// let floor = moving([[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [-1.0, 2.0, 0.0]], [0.0; 3]);
/// let params = CcdParams::default();
/// // Falling by 1 with its lowest corner (corner 0) at z = 0.5: that corner
/// // reaches the floor first, at t = 0.5.
/// let corners = [[0.2, 0.2, 0.5], [0.6, 0.2, 1.0], [0.2, 0.6, 1.0]];
/// let hit = triangles(&moving(corners, [0.0, 0.0, -1.0]), &floor, &params).unwrap();
/// assert!(hit.toi <= 0.5 && hit.toi > 0.499);
/// assert_eq!(hit.feature, Feature::VertexFace { first: true, vertex: 0 });
/// // Falling only 0.4: it stops 0.1 short.
/// assert_eq!(triangles(&moving(corners, [0.0, 0.0, -0.4]), &floor, &params), None);
/// // Already through the floor at the start: contact at t = 0.
/// let pin = [[0.0, 0.0, -1.0], [0.0, 0.1, 1.0], [0.1, 0.0, 1.0]];
/// let hit = triangles(&moving(pin, [0.1, 0.1, 0.0]), &floor, &params).unwrap();
/// assert_eq!(hit.toi, 0.0);
/// assert!(matches!(hit.feature, Feature::AtStart { .. }));
/// ```
pub fn triangles(
    a: &MovingTriangle<f64>,
    b: &MovingTriangle<f64>,
    params: &CcdParams,
) -> Option<TriangleImpact> {
    triangles_as(a, b, params)
}

/// A lower bound of the time two moving triangles first touch, given their
/// corners at the start and end of the step; `None` when they never touch.
///
/// ```
/// use cornertree::geometry::ccd_root_finder::CcdParams;
/// use cornertree::geometry::ccd_triangles::time_of_impact;
///
/// // A sliver swept across x = 0 between two frames, through a small still
/// // triangle it misses at both frames; they first touch at t = 0.5.
/// let pole_start = [[-1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, 0.0, 1.0]];
/// let pole_end = pole_start.map(|p| [p[0] + 2.0, p[1], p[2]]);
/// let tri = [[0.0, -0.1, 0.0], [0.0, 0.1, 0.0], [0.1, 0.0, 0.0]];
/// let params = CcdParams::default();
/// let toi = time_of_impact(&pole_start, &pole_end, &tri, &tri, &params).unwrap();
/// assert!(toi <= 0.5 && toi > 0.49);
/// // Stopping short of the triangle: no contact.
/// let short = pole_start.map(|p| [p[0] + 0.9, p[1], p[2]]);
/// assert_eq!(time_of_impact(&pole_start, &short, &tri, &tri, &params), None);
/// ```
pub fn time_of_impact(
    a_start: &[V3<f64>; 3],
    a_end: &[V3<f64>; 3],
    b_start: &[V3<f64>; 3],
    b_end: &[V3<f64>; 3],
    params: &CcdParams,
) -> Option<f64> {
    let a = MovingTriangle {
        start: *a_start,
        end: *a_end,
    };
    let b = MovingTriangle {
        start: *b_start,
        end: *b_end,
    };
    triangles(&a, &b, params).map(|i| i.toi)
}

/// The edges as corner pairs.
const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];

/// [`triangles`] computed in `T` (`f64`, or
/// [`Counted`](super::counted::Counted) to count the operations paid).
///
/// ```
/// use cornertree::geometry::ccd_root_finder::CcdParams;
/// use cornertree::geometry::ccd_triangles::{MovingTriangle, triangles, triangles_as};
/// use cornertree::geometry::counted::{Counted, count_operations};
/// use cornertree::geometry::scalar::Scalar;
///
/// let falling = MovingTriangle {
///     start: [[0.2, 0.2, 0.5], [0.6, 0.2, 1.0], [0.2, 0.6, 1.0]],
///     end: [[0.2, 0.2, -0.5], [0.6, 0.2, 0.0], [0.2, 0.6, 0.0]],
/// };
/// let floor = [[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [-1.0, 2.0, 0.0]];
/// let floor = MovingTriangle { start: floor, end: floor };
/// let params = CcdParams::default();
/// let wide = |m: &MovingTriangle<f64>| MovingTriangle {
///     start: m.start.map(|p| p.map(Counted::from_f64)),
///     end: m.end.map(|p| p.map(Counted::from_f64)),
/// };
/// let (counted, ops) =
///     count_operations(|| triangles_as(&wide(&falling), &wide(&floor), &params));
/// // The same answer as in f64, at some cost.
/// assert_eq!(counted, triangles(&falling, &floor, &params));
/// assert!(counted.is_some_and(|i| i.toi <= 0.5 && i.toi > 0.499));
/// assert!(ops > 0);
/// ```
pub fn triangles_as<T: Binary64>(
    a: &MovingTriangle<T>,
    b: &MovingTriangle<T>,
    params: &CcdParams,
) -> Option<TriangleImpact> {
    // 1. Swept boxes, apart by more than the inputs' rounding (ε covers it).
    let m = max_magnitudes(&[&a.start[..], &a.end[..], &b.start[..], &b.end[..]]);
    let margin = Bounds::new(&m, params, 4.0).eps;
    if SweptBox::of(&a.start, &a.end).apart(&SweptBox::of(&b.start, &b.end), &margin) {
        return None;
    }
    // 2. Already meeting at t = 0.
    for (first, (x, y)) in [(true, (a, b)), (false, (b, a))] {
        for (edge, (i, j)) in EDGES.into_iter().enumerate() {
            let s = &y.start;
            let from = [x.start[i], s[0], s[1], s[2]];
            let to = [x.start[j], s[0], s[1], s[2]];
            if let Some(impact) = vertex_face_search(&from, &to, params, Seek::Any) {
                return Some(TriangleImpact {
                    toi: 0.0,
                    feature: Feature::AtStart { first, edge },
                    impact,
                });
            }
        }
    }
    // 3. The 15 elementary tests, each seeking earlier contacts only.
    let mut best: Option<TriangleImpact> = None;
    let before = |best: &Option<TriangleImpact>| best.map_or(1.0, |b| b.toi);
    for (first, (x, y)) in [(true, (a, b)), (false, (b, a))] {
        for vertex in 0..3 {
            let s = [x.start[vertex], y.start[0], y.start[1], y.start[2]];
            let e = [x.end[vertex], y.end[0], y.end[1], y.end[2]];
            if let Some(impact) = vertex_face_as(&s, &e, params, before(&best)) {
                best = Some(TriangleImpact {
                    toi: impact.toi,
                    feature: Feature::VertexFace { first, vertex },
                    impact,
                });
            }
        }
    }
    for (ea, (i, j)) in EDGES.into_iter().enumerate() {
        for (eb, (k, l)) in EDGES.into_iter().enumerate() {
            let s = [a.start[i], a.start[j], b.start[k], b.start[l]];
            let e = [a.end[i], a.end[j], b.end[k], b.end[l]];
            if let Some(impact) = edge_edge_as(&s, &e, params, before(&best)) {
                best = Some(TriangleImpact {
                    toi: impact.toi,
                    feature: Feature::EdgeEdge { a: ea, b: eb },
                    impact,
                });
            }
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn moving(start: [V3<f64>; 3], shift: V3<f64>) -> MovingTriangle<f64> {
        MovingTriangle {
            start,
            end: start.map(|p| [p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]]),
        }
    }

    const FLOOR: [V3<f64>; 3] = [[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [-1.0, 2.0, 0.0]];

    #[test]
    fn falling_corner_first() {
        let floor = moving(FLOOR, [0.0; 3]);
        let tri = moving(
            [[0.2, 0.2, 0.5], [0.6, 0.2, 1.0], [0.2, 0.6, 1.0]],
            [0.0, 0.0, -1.0],
        );
        let hit = triangles(&tri, &floor, &CcdParams::default()).unwrap();
        assert!(hit.toi <= 0.5 && hit.toi > 0.499, "{hit:?}");
        assert_eq!(
            hit.feature,
            Feature::VertexFace {
                first: true,
                vertex: 0
            }
        );
    }

    #[test]
    fn tunnelling_through_a_thin_pole_between_frames() {
        // A sliver standing across x = 0 swept from x = -1 to x = 1 through
        // a small triangle: disjoint at both ends, touching in between.
        let pole = moving(
            [[-1.0, -1.0, -1.0], [-1.0, 1.0, -1.0], [-1.0, 0.0, 1.0]],
            [2.0, 0.0, 0.0],
        );
        let tri = moving(
            [[0.0, -0.1, 0.0], [0.0, 0.1, 0.0], [0.1, 0.0, 0.0]],
            [0.0; 3],
        );
        let toi = time_of_impact(
            &pole.start,
            &pole.end,
            &tri.start,
            &tri.end,
            &CcdParams::default(),
        );
        assert!(toi.is_some_and(|t| t <= 0.5 && t > 0.49), "{toi:?}");
    }

    #[test]
    fn piercing_from_the_start() {
        // An edge through the floor's interior all along: no vertex–face or
        // edge–edge contact, but they meet at t = 0.
        let floor = moving(FLOOR, [0.0; 3]);
        let pin = moving(
            [[0.0, 0.0, -1.0], [0.0, 0.1, 1.0], [0.1, 0.0, 1.0]],
            [0.1, 0.1, 0.0],
        );
        let hit = triangles(&pin, &floor, &CcdParams::default()).unwrap();
        assert_eq!(hit.toi, 0.0);
        assert!(matches!(hit.feature, Feature::AtStart { .. }), "{hit:?}");
    }

    #[test]
    fn passing_by() {
        let floor = moving(FLOOR, [0.0; 3]);
        let tri = moving(
            [[0.2, 0.2, 0.5], [0.6, 0.2, 1.0], [0.2, 0.6, 1.0]],
            [3.0, 0.0, -0.4],
        );
        assert_eq!(triangles(&tri, &floor, &CcdParams::default()), None);
    }
}
