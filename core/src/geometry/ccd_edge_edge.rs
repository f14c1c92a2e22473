//! Edge–edge continuous collision detection: two segments, every end moving
//! on a straight line over the step `t ∈ [0, 1]`.
//!
//! Edges `a₀a₁` and `b₀b₁` meet when
//! `F(t, u, v) = a₀ − b₀ + u (a₁ − a₀) + v (b₀ − b₁)` (at time `t`) vanishes
//! for some `u, v ∈ [0, 1]`. Decided by the inclusion-based root finder of
//! Wang et al. (ACM TOG 40(5), 2021; [`super::ccd_root_finder`]), after a
//! swept-extent early-out. Conservative like
//! [`super::ccd_vertex_face`]: `None` only when no contact exists in
//! `[0, 1]`; `Some` carries a lower bound of the time of first contact and
//! how close the edges certainly come. `docs/ccd.md` derives the bounds.
//!
//! Generic over [`Binary64`]: [`edge_edge`] is the `f64` instantiation;
//! [`edge_edge_as`] with [`super::counted::Counted`] counts the operations
//! paid.

use super::ccd_error_bounds::{Binary64, Bounds, max_magnitudes};
use super::ccd_root_finder::{CcdParams, ContactFunction, Domain, Impact, Seek, find_root};
use super::ccd_swept_box::SweptBox;
use super::vec3::V3;

/// Sum of the magnitudes of the points' weights in `F`:
/// `(1 − u) + u + (1 − v) + v = 2`.
const WEIGHT: f64 = 2.0;

/// Whether edges `a₀a₁` and `b₀b₁` meet during the step: `start` and `end`
/// hold `a₀, a₁, b₀, b₁` at `t = 0` and `t = 1`. `f64` arithmetic.
///
/// Conservative (module doc): `None` is certain; `Some` gives a lower bound
/// of the first contact.
///
/// ```
/// use cornertree::geometry::ccd_edge_edge::edge_edge;
/// use cornertree::geometry::ccd_root_finder::CcdParams;
///
/// let params = CcdParams::default();
/// // Edge a along x, falling from z = 1 to z = -1; edge b still along y at
/// // z = 0. They cross at the origin at t = 0.5.
/// let b = [[0.0, -1.0, 0.0], [0.0, 1.0, 0.0]];
/// let start = [[-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], b[0], b[1]];
/// let end = [[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], b[0], b[1]];
/// let hit = edge_edge(&start, &end, &params).unwrap();
/// assert!(hit.resolved && hit.toi <= 0.5 && hit.toi > 0.499);
/// // The same fall at y = 2, beyond b's end at y = 1: no contact.
/// let start = [[-1.0, 2.0, 1.0], [1.0, 2.0, 1.0], b[0], b[1]];
/// let end = [[-1.0, 2.0, -1.0], [1.0, 2.0, -1.0], b[0], b[1]];
/// assert_eq!(edge_edge(&start, &end, &params), None);
/// ```
pub fn edge_edge(start: &[V3<f64>; 4], end: &[V3<f64>; 4], params: &CcdParams) -> Option<Impact> {
    edge_edge_as(start, end, params, 1.0)
}

/// [`edge_edge`] computed in `T`, seeking only contacts that start before
/// `before` (`≤ 1`; boxes of later times are skipped).
///
/// ```
/// use cornertree::geometry::ccd_edge_edge::edge_edge_as;
/// use cornertree::geometry::ccd_root_finder::CcdParams;
///
/// // Crossing at t = 0.5 (as in `edge_edge`'s example).
/// let b = [[0.0, -1.0, 0.0], [0.0, 1.0, 0.0]];
/// let start = [[-1.0, 0.0, 1.0], [1.0, 0.0, 1.0], b[0], b[1]];
/// let end = [[-1.0, 0.0, -1.0], [1.0, 0.0, -1.0], b[0], b[1]];
/// let params = CcdParams::default();
/// assert!(edge_edge_as::<f64>(&start, &end, &params, 0.4).is_none());
/// assert!(edge_edge_as::<f64>(&start, &end, &params, 0.6).is_some());
/// ```
pub fn edge_edge_as<T: Binary64>(
    start: &[V3<T>; 4],
    end: &[V3<T>; 4],
    params: &CcdParams,
    before: f64,
) -> Option<Impact> {
    let bounds = Bounds::new(&max_magnitudes(&[&start[..], &end[..]]), params, WEIGHT);
    let (p, q) = (
        SweptBox::of(&start[..2], &end[..2]),
        SweptBox::of(&start[2..], &end[2..]),
    );
    if p.apart(&q, &bounds.eps) {
        return None;
    }
    let f = ContactFunction::new(start, end, (0, 2), (1, 0), (2, 3));
    find_root(
        &f,
        &bounds,
        Domain::Square,
        Seek::EarliestBefore(before),
        params.max_boxes,
        params.time_tolerance,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn crossing_edges() {
        // a along x at z = 1 → −1; b along y at z = 0.
        let s = [
            [-1.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, -1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let e = [
            [-1.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [0.0, -1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let hit = edge_edge(&s, &e, &CcdParams::default()).unwrap();
        assert!(hit.resolved && hit.toi <= 0.5 && hit.toi > 0.499, "{hit:?}");
    }

    #[test]
    fn passing_beyond_an_end() {
        // a passes below b's line, beyond its end at y = 1.
        let s = [
            [-1.0, 2.0, 1.0],
            [1.0, 2.0, 1.0],
            [0.0, -1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let e = [
            [-1.0, 2.0, -1.0],
            [1.0, 2.0, -1.0],
            [0.0, -1.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        assert_eq!(edge_edge(&s, &e, &CcdParams::default()), None);
    }

    #[test]
    fn parallel_edges_sliding_in_contact() {
        let s = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.5, 0.0, 0.0],
            [2.0, 0.0, 0.0],
        ];
        let e = [
            [1.0, 0.0, 0.0],
            [2.0, 0.0, 0.0],
            [0.5, 0.0, 0.0],
            [2.0, 0.0, 0.0],
        ];
        let hit = edge_edge(&s, &e, &CcdParams::default()).unwrap();
        assert_eq!(hit.toi, 0.0);
    }
}
