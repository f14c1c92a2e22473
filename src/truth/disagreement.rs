//! The pairs two answers differ on, and why.
//!
//! Given a method's pairs and a reference's (say parry's), a pair reported by
//! only one of them is classified ([`Kind`]), in this order:
//!
//! 1. **Touching**: the exact oracle says `Touching`, or the pair is within
//!    [`Tolerances::touching`] of changing its answer: disjoint triangles at a
//!    distance ([`triangle_distance`]) at most the tolerance, or meeting
//!    triangles that a translation no longer than the tolerance separates
//!    ([`separation_depth`]; coplanar overlaps have depth 0). Any `f32` test can
//!    go either way on such pairs.
//! 2. **NearDegenerate**: either triangle's area is below
//!    [`Tolerances::degenerate_ratio`] times its longest edge squared (a needle
//!    or a point; an equilateral triangle has ratio √3/4 ≈ 0.43).
//! 3. **TrueError**: everything else, a real miss or a real false contact.
//!
//! The default tolerance is `1e-6 ×` the scene's size (the environment's
//! bounding-box diagonal): 10 µm in a 10 m room, about ten `f32` steps at
//! 10 m.
//!
//! Distances are ours, in `f64` from the `f32` corners, not parry's (parry's
//! `query::distance` on two triangles is `f32` GJK); the tests compare the two.

use serde::Serialize;

use super::TruthError;
use cornertree::geometry::closest_point::{
    Point64, closest_point_on_segment, point_triangle_distance,
};
use cornertree::geometry::exact::{Contact, classify};
use cornertree::geometry::{Point, Triangle};
use cornertree::mesh::{TriMesh, TriangleId};

/// Why a pair is in one answer and not the other.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
pub enum Kind {
    /// The triangles touch, or are within the tolerance of touching.
    Touching,
    /// One triangle is (nearly) a segment or a point.
    NearDegenerate,
    /// A clear contact missed, or a clear non-contact reported.
    TrueError,
}

/// Thresholds of the classification.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Tolerances {
    /// Distance (or separation depth) up to which a pair counts as touching.
    pub touching: f64,
    /// Area / (longest edge)² below which a triangle is near-degenerate.
    pub degenerate_ratio: f64,
}

impl Tolerances {
    /// Touching tolerance per unit of scene size.
    pub const TOUCHING_PER_SCALE: f64 = 1e-6;
    /// Default area / (longest edge)² threshold.
    pub const DEGENERATE_RATIO: f64 = 1e-7;

    /// Defaults for a scene of size `scale` (e.g. [`TriMesh::size`] of the
    /// environment).
    pub fn for_scale(scale: f64) -> Self {
        Self {
            touching: Self::TOUCHING_PER_SCALE * scale,
            degenerate_ratio: Self::DEGENERATE_RATIO,
        }
    }
}

/// Differences in one direction, classified.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Classified {
    pub touching: usize,
    pub near_degenerate: usize,
    pub true_error: usize,
    /// Every difference: (character triangle, environment triangle, kind), sorted.
    pub items: Vec<(u32, u32, Kind)>,
}

impl Classified {
    fn push(&mut self, c: u32, e: u32, kind: Kind) {
        match kind {
            Kind::Touching => self.touching += 1,
            Kind::NearDegenerate => self.near_degenerate += 1,
            Kind::TrueError => self.true_error += 1,
        }
        self.items.push((c, e, kind));
    }

    pub fn len(&self) -> usize {
        self.items.len()
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }
}

/// How a method's pairs differ from a reference's.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct Disagreement {
    /// Reported by the method only (its false positives, if the reference is right).
    pub extra: Classified,
    /// Reported by the reference only (the method's misses).
    pub missed: Classified,
}

/// Pairs in `a` and not in `b`, and in `b` and not in `a`, into `only_a` and
/// `only_b` (cleared first). Inputs may be in any order and repeat pairs;
/// outputs are sorted and distinct.
pub fn differences(
    a: &[(u32, u32)],
    b: &[(u32, u32)],
    only_a: &mut Vec<(u32, u32)>,
    only_b: &mut Vec<(u32, u32)>,
) {
    let mut a = a.to_vec();
    let mut b = b.to_vec();
    for v in [&mut a, &mut b] {
        v.sort_unstable();
        v.dedup();
    }
    only_a.clear();
    only_b.clear();
    let (mut i, mut j) = (0, 0);
    while i < a.len() || j < b.len() {
        match (a.get(i), b.get(j)) {
            (Some(x), Some(y)) if x == y => {
                i += 1;
                j += 1;
            }
            (Some(x), Some(y)) if x < y => {
                only_a.push(*x);
                i += 1;
            }
            (Some(x), None) => {
                only_a.push(*x);
                i += 1;
            }
            (_, Some(y)) => {
                only_b.push(*y);
                j += 1;
            }
            (None, None) => break,
        }
    }
}

/// Classifies every pair on which `method` and `reference` differ. Character
/// triangles are `character_indices` over the posed `character` positions.
pub fn compare(
    method: &[(u32, u32)],
    reference: &[(u32, u32)],
    character: &[Point],
    character_indices: &[[u32; 3]],
    environment: &TriMesh,
    tolerances: &Tolerances,
) -> Result<Disagreement, TruthError> {
    let (mut extra, mut missed) = (Vec::new(), Vec::new());
    differences(method, reference, &mut extra, &mut missed);
    let pair = |c: u32, e: u32| -> Result<(Triangle, Triangle), TruthError> {
        let out = TruthError::PairOutOfRange {
            character: c,
            environment: e,
        };
        let tri = character_indices.get(c as usize).ok_or(out.clone())?;
        let corner = |k: usize| character.get(tri[k] as usize).copied().ok_or(out.clone());
        let tc = Triangle::new(corner(0)?, corner(1)?, corner(2)?);
        if e as usize >= environment.triangle_count() {
            return Err(out);
        }
        Ok((tc, environment.triangle(TriangleId(e))))
    };
    let mut result = Disagreement::default();
    for (list, into) in [(&extra, &mut result.extra), (&missed, &mut result.missed)] {
        for &(c, e) in list {
            let (tc, te) = pair(c, e)?;
            into.push(c, e, classify_pair(&tc, &te, tolerances));
        }
    }
    Ok(result)
}

/// The [`Kind`] of one pair two answers disagree on (see the module doc for
/// the order of the rules).
pub fn classify_pair(t1: &Triangle, t2: &Triangle, tolerances: &Tolerances) -> Kind {
    let near = match classify(t1, t2) {
        Contact::Touching => true,
        Contact::Disjoint => triangle_distance(t1, t2) <= tolerances.touching,
        Contact::Overlapping => separation_depth(t1, t2) <= tolerances.touching,
    };
    if near {
        Kind::Touching
    } else if degeneracy(t1) < tolerances.degenerate_ratio
        || degeneracy(t2) < tolerances.degenerate_ratio
    {
        Kind::NearDegenerate
    } else {
        Kind::TrueError
    }
}

fn corners64(t: &Triangle) -> [Point64; 3] {
    t.vertices().map(|p| p.cast::<f64>())
}

/// Area over longest edge squared, in `f64`; 0 for a point.
pub fn degeneracy(t: &Triangle) -> f64 {
    let [a, b, c] = corners64(t);
    let area = 0.5 * (b - a).cross(&(c - a)).norm();
    let longest2 = [(b - a), (c - b), (a - c)]
        .iter()
        .map(|e| e.norm_squared())
        .fold(0.0, f64::max);
    if longest2 > 0.0 { area / longest2 } else { 0.0 }
}

/// Euclidean distance between two closed triangles, ours in `f64`.
///
/// 0 when the exact oracle says they meet. Otherwise the smallest of the six
/// corner-to-triangle and nine edge-to-edge distances: for disjoint triangles
/// a closest pair of points always has a corner of one triangle against the
/// other triangle, or lies on an edge of each (if both closest points were
/// inside the faces, the faces would be parallel and a corner would do as
/// well).
pub fn triangle_distance(t1: &Triangle, t2: &Triangle) -> f64 {
    if classify(t1, t2) != Contact::Disjoint {
        return 0.0;
    }
    let (a, b) = (corners64(t1), corners64(t2));
    let corners = a
        .iter()
        .map(|p| point_triangle_distance(p, t2))
        .chain(b.iter().map(|p| point_triangle_distance(p, t1)));
    let edges = (0..3).flat_map(|i| {
        (0..3).map(move |j| segment_distance(&a[i], &a[(i + 1) % 3], &b[j], &b[(j + 1) % 3]))
    });
    corners.chain(edges).fold(f64::INFINITY, f64::min)
}

/// Distance between closed segments `pq` and `rs` (either may be a point).
///
/// The squared distance is a convex quadratic in the two segment parameters;
/// its minimum over the unit square is either the unconstrained minimum (when
/// that lies inside) or on the square's boundary, i.e. with an endpoint of one
/// segment against the other segment.
fn segment_distance(p: &Point64, q: &Point64, r: &Point64, s: &Point64) -> f64 {
    let ends = [
        (closest_point_on_segment(p, r, s) - p).norm(),
        (closest_point_on_segment(q, r, s) - q).norm(),
        (closest_point_on_segment(r, p, q) - r).norm(),
        (closest_point_on_segment(s, p, q) - s).norm(),
    ]
    .into_iter()
    .fold(f64::INFINITY, f64::min);
    // Stationary point of |p + u·d1 − r − v·d2|²: the normal equations
    // [d1·d1, −d1·d2; d1·d2, −d2·d2] (u, v) = (−d1·w, −d2·w), w = p − r.
    let (d1, d2, w) = (q - p, s - r, p - r);
    let (a, b, c) = (d1.dot(&d1), d1.dot(&d2), d2.dot(&d2));
    let (d, e) = (d1.dot(&w), d2.dot(&w));
    let det = a * c - b * b;
    if det > 0.0 {
        let u = (b * e - c * d) / det;
        let v = (a * e - b * d) / det;
        if (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v) {
            return ends.min(((p + d1 * u) - (r + d2 * v)).norm());
        }
    }
    ends
}

/// Shortest translation that separates two triangles that meet (0 if they do
/// not), by separating axes in `f64`: the smallest overlap of their
/// projections on the two face normals and the nine edge-edge cross products.
/// Those are the facet normals of `t1 ⊕ (−t2)`, so this is the penetration
/// depth for non-degenerate triangles; axes that vanish are skipped, and if
/// all do the answer is 0. Coplanar triangles have depth 0 (their extent
/// along the common normal is zero).
pub fn separation_depth(t1: &Triangle, t2: &Triangle) -> f64 {
    let (a, b) = (corners64(t1), corners64(t2));
    let edge = |t: &[Point64; 3], i: usize| t[(i + 1) % 3] - t[i];
    let normal = |t: &[Point64; 3]| edge(t, 0).cross(&edge(t, 1));
    let axes = [normal(&a), normal(&b)]
        .into_iter()
        .chain((0..3).flat_map(|i| (0..3).map(move |j| edge(&a, i).cross(&edge(&b, j)))));
    let mut depth = f64::INFINITY;
    for axis in axes {
        let len = axis.norm();
        if len == 0.0 || !len.is_finite() {
            continue;
        }
        let u = axis / len;
        let span = |t: &[Point64; 3]| {
            t.iter()
                .map(|p| p.coords.dot(&u))
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), x| {
                    (lo.min(x), hi.max(x))
                })
        };
        let ((lo1, hi1), (lo2, hi2)) = (span(&a), span(&b));
        let overlap = (hi1 - lo2).min(hi2 - lo1);
        if overlap < 0.0 {
            return 0.0;
        }
        depth = depth.min(overlap);
    }
    if depth.is_finite() { depth } else { 0.0 }
}
