//! Vertex–face continuous collision detection: a point and a triangle, every
//! corner moving on a straight line over the step `t ∈ [0, 1]`.
//!
//! The point `p(t)` meets the closed triangle `a(t) b(t) c(t)` when
//! `F(t, u, v) = p − a + u (a − b) + v (a − c)` (at time `t`) vanishes for
//! some `u, v ≥ 0`, `u + v ≤ 1`. Decided by the inclusion-based root finder
//! of Wang et al. (ACM TOG 40(5), 2021; [`super::ccd_root_finder`]), after
//! a swept-extent early-out. Conservative: `None` only when no contact
//! exists in `[0, 1]` (true inputs, rounding of the inputs included through
//! [`CcdParams::input_error`]); `Some` carries a lower bound of the time of
//! first contact and a certificate of how close the two come
//! ([`Impact::within`]). `docs/ccd.md` derives the bounds.
//!
//! Generic over [`Binary64`]: [`vertex_face`] is the `f64`
//! instantiation; [`vertex_face_as`] with
//! [`super::counted::Counted`] counts the operations paid.

use super::ccd_error_bounds::{Binary64, Bounds, max_magnitudes};
use super::ccd_root_finder::{CcdParams, ContactFunction, Domain, Impact, Seek, find_root};
use super::ccd_swept_box::SweptBox;
use super::vec3::V3;

/// Sum of the magnitudes of the points' weights in `F` over `[0, 1]³`:
/// `|1| + |1 − u − v| + u + v ≤ 4` (bounds the effect of input rounding).
const WEIGHT: f64 = 4.0;

/// Whether point `p` meets triangle `abc` during the step: `start` and
/// `end` hold `p, a, b, c` at `t = 0` and `t = 1`. `f64` arithmetic.
///
/// Conservative (module doc): `None` is certain; `Some` gives a lower bound
/// of the first contact.
///
/// ```
/// use cornertree::geometry::ccd_root_finder::CcdParams;
/// use cornertree::geometry::ccd_vertex_face::vertex_face;
///
/// let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let [a, b, c] = tri;
/// let params = CcdParams::default();
/// // A point falling from z = 1 to z = -1 through (0.25, 0.25, 0): it
/// // crosses the still triangle at t = 0.5.
/// let hit = vertex_face(
///     &[[0.25, 0.25, 1.0], a, b, c],
///     &[[0.25, 0.25, -1.0], a, b, c],
///     &params,
/// )
/// .unwrap();
/// assert!(hit.resolved && hit.toi <= 0.5 && hit.toi > 0.499);
/// // The same fall beside the hypotenuse, through (0.75, 0.75, 0): no contact.
/// let miss = vertex_face(
///     &[[0.75, 0.75, 1.0], a, b, c],
///     &[[0.75, 0.75, -1.0], a, b, c],
///     &params,
/// );
/// assert_eq!(miss, None);
/// // The triangle rising to meet a still point at z = 0.25: contact at t = 0.25.
/// let up = tri.map(|q| [q[0], q[1], q[2] + 1.0]);
/// let p = [0.25, 0.25, 0.25];
/// let hit = vertex_face(&[p, a, b, c], &[p, up[0], up[1], up[2]], &params).unwrap();
/// assert!(hit.toi <= 0.25 && hit.toi > 0.249);
/// ```
pub fn vertex_face(start: &[V3<f64>; 4], end: &[V3<f64>; 4], params: &CcdParams) -> Option<Impact> {
    vertex_face_as(start, end, params, 1.0)
}

/// [`vertex_face`] computed in `T`, seeking only contacts that start before
/// `before` (`≤ 1`; boxes of later times are skipped).
///
/// ```
/// use cornertree::geometry::ccd_root_finder::CcdParams;
/// use cornertree::geometry::ccd_vertex_face::vertex_face_as;
///
/// let [a, b, c] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
/// let start = [[0.25, 0.25, 1.0], a, b, c];
/// let end = [[0.25, 0.25, -1.0], a, b, c];
/// let params = CcdParams::default();
/// // The contact at t = 0.5 is not before 0.4, but is before 0.6.
/// assert!(vertex_face_as::<f64>(&start, &end, &params, 0.4).is_none());
/// let hit = vertex_face_as::<f64>(&start, &end, &params, 0.6).unwrap();
/// assert!(hit.toi <= 0.5 && hit.toi > 0.499);
/// ```
pub fn vertex_face_as<T: Binary64>(
    start: &[V3<T>; 4],
    end: &[V3<T>; 4],
    params: &CcdParams,
    before: f64,
) -> Option<Impact> {
    search(start, end, params, Seek::EarliestBefore(before))
}

/// The search behind both entries (also used, with [`Seek::Any`], for
/// static edge–triangle tests: the "point" moving along an edge).
pub(super) fn search<T: Binary64>(
    start: &[V3<T>; 4],
    end: &[V3<T>; 4],
    params: &CcdParams,
    seek: Seek,
) -> Option<Impact> {
    let bounds = Bounds::new(&max_magnitudes(&[&start[..], &end[..]]), params, WEIGHT);
    let (p, q) = (
        SweptBox::of(&start[..1], &end[..1]),
        SweptBox::of(&start[1..], &end[1..]),
    );
    if p.apart(&q, &bounds.eps) {
        return None;
    }
    let f = ContactFunction::new(start, end, (0, 1), (1, 2), (1, 3));
    find_root(
        &f,
        &bounds,
        Domain::Triangle,
        seek,
        params.max_boxes,
        params.time_tolerance,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn still(p: [f64; 3], tri: [[f64; 3]; 3]) -> [V3<f64>; 4] {
        [p, tri[0], tri[1], tri[2]]
    }

    const TRI: [[f64; 3]; 3] = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];

    #[test]
    fn point_falling_through_the_face() {
        let s = still([0.25, 0.25, 1.0], TRI);
        let e = still([0.25, 0.25, -1.0], TRI);
        let hit = vertex_face(&s, &e, &CcdParams::default()).unwrap();
        assert!(hit.resolved);
        // First contact at t = 0.5: a lower bound, close below it.
        assert!(hit.toi <= 0.5 && hit.toi > 0.5 - 1e-3, "{hit:?}");
    }

    #[test]
    fn point_passing_beside_the_face() {
        let s = still([0.75, 0.75, 1.0], TRI);
        let e = still([0.75, 0.75, -1.0], TRI);
        assert_eq!(vertex_face(&s, &e, &CcdParams::default()), None);
        // Beside the hypotenuse by 1e-3: clear of δ = 1e-6.
        let s = still([0.5005, 0.5005, 1.0], TRI);
        let e = still([0.5005, 0.5005, -1.0], TRI);
        assert_eq!(vertex_face(&s, &e, &CcdParams::default()), None);
    }

    #[test]
    fn touching_at_a_corner_at_the_end() {
        let s = still([1.0, 0.0, 1.0], TRI);
        let e = still([1.0, 0.0, 0.0], TRI);
        let hit = vertex_face(&s, &e, &CcdParams::default()).unwrap();
        assert!(hit.toi <= 1.0 && hit.toi > 0.99, "{hit:?}");
    }

    #[test]
    fn earlier_contacts_only() {
        let s = still([0.25, 0.25, 1.0], TRI);
        let e = still([0.25, 0.25, -1.0], TRI);
        let p = CcdParams::default();
        assert!(vertex_face_as::<f64>(&s, &e, &p, 0.4).is_none());
        assert!(vertex_face_as::<f64>(&s, &e, &p, 0.6).is_some());
    }
}
