//! Geometric primitives and the kernels of the paper's operation model (§6).
//!
//! | file | what | paper |
//! |---|---|---|
//! | [`sphere`] | [`Sphere`] and the sphere-sphere test (10 operations) | §2, §6 |
//! | [`triangle`] | [`Triangle`] | |
//! | [`plane_sphere`] | Algorithm 1, the plane-sphere test (30 operations) | §5 |
//! | [`tri_tri`] | the narrow phase's triangle-triangle test: the faster of the two below (96 operations) | §3 narrow phase |
//! | [`leveled_box`] | a box kept in six bytes around a moving node's sphere, rebuilt each frame and tested against another (ours; a character's posed node boxes) | |
//! | [`sphere_box`] | a sphere against an axis-aligned box kept in six bytes around a static node's sphere (ours; the room's node boxes) | |
//! | [`triangle_prism`] | whether a sphere can reach a triangle, by its three edge planes (before the triangle-triangle test of a big triangle; ours) | |
//! | [`tropp`] | Tropp, Tal and Shimshoni's triangle-triangle test | §3 narrow phase |
//! | [`edge_crossing`] | edge-crossing triangle-triangle test (crossing edges of each against the other) | |
//! | [`coplanar_degenerate`] | what both share: snapped plane offsets, coplanar pairs, zero-area triangles | |
//! | [`scalar`] | [`scalar::Scalar`], the number type the kernels are generic over | §6 |
//! | [`counted`] | [`counted::Counted`]: an `f64` counting the operations paid | §6 |
//! | [`vec3`] | `[T; 3]` vectors over a `Scalar` | |
//! | [`exact`] | exact triangle-triangle oracle on adaptive predicates | (reference) |
//! | [`ccd_vertex_face`] | vertex–face continuous collision detection (linear motion over a step) | §7 (future work) |
//! | [`ccd_edge_edge`] | edge–edge continuous collision detection | §7 |
//! | [`ccd_triangles`] | triangle–triangle CCD: contact at the start, 6 vertex–face and 9 edge–edge tests | §7 |
//! | [`ccd_sphere_plane`] | a sphere interpolated over a step against a still triangle's plane (Algorithm 1, continuous) | §5, §7 |
//! | [`ccd_sphere_sphere`] | two spheres interpolated over a step: do they meet (sphere-sphere, continuous) | §2, §7 |
//! | [`ccd_root_finder`] | the conservative inclusion-based root finder both elementary tests run (Wang et al. 2021) | §7 |
//! | [`ccd_swept_box`] | boxes of points over a step: the CCD early-out | §7 |
//! | [`ccd_error_bounds`] | the root finder's certified rounding bounds (inputs' rounding included) | §7 |
//! | [`ccd_param_box`] | dyadic boxes of the root finder's parameters `(t, u, v)` | §7 |
//! | [`query_shapes`] | rays, balls and capsules an engine asks about: against a sphere (conservative) and a triangle (watertight ray test) | (queries) |
//! | [`closest_point`] | closest point on a triangle, `f64` (plane-sphere false-positive reference) | (reference) |
//! | [`enclosing`] | minimal enclosing spheres; the paper's sphere of spheres | §3 |
//!
//! Storage is `f32` (as a real-time engine would keep it); kernels that decide
//! contact widen to `f64` internally, where products of `f32` inputs are exact.

pub mod ccd_edge_edge;
pub mod ccd_error_bounds;
pub mod ccd_param_box;
pub mod ccd_params;
pub mod ccd_root_finder;
pub mod ccd_sphere_plane;
pub mod ccd_sphere_sphere;
pub mod ccd_swept_box;
pub mod ccd_triangles;
pub mod ccd_vertex_face;
pub mod closest_point;
pub mod coplanar_degenerate;
pub mod counted;
pub mod edge_crossing;
pub mod enclosing;
pub mod exact;
pub mod intersection_segment;
pub mod leveled_box;
pub mod plane_sphere;
pub mod query_shapes;
pub mod scalar;
pub mod sphere;
pub mod sphere_box;
pub mod sphere_sweep;
pub mod star_contour;
pub mod tri_tri;
pub mod triangle;
pub mod triangle_prism;
pub mod tropp;
pub mod vec3;

pub use sphere::Sphere;
pub use triangle::Triangle;

/// Scalar used for stored geometry.
pub type Real = f32;
/// A point in model or world space.
pub type Point = nalgebra::Point3<Real>;
/// A displacement.
pub type Vector = nalgebra::Vector3<Real>;

/// Axis-aligned extent `(min, max)` of `points`; `None` when there are none.
///
/// ```
/// use cornertree::geometry::{Point, bounds_of};
///
/// let b = bounds_of([Point::new(1.0, -2.0, 0.0), Point::new(-1.0, 3.0, 0.5)]);
/// assert_eq!(b, Some((Point::new(-1.0, -2.0, 0.0), Point::new(1.0, 3.0, 0.5))));
/// assert_eq!(bounds_of([]), None);
/// ```
pub fn bounds_of(points: impl IntoIterator<Item = Point>) -> Option<(Point, Point)> {
    let mut it = points.into_iter();
    let first = it.next()?;
    Some(it.fold((first, first), |(lo, hi), p| (lo.inf(&p), hi.sup(&p))))
}

/// Basic operations (additions and multiplications) charged per test in the
/// paper's cost model (§6). The "Operations" column of Tables 2–3 is
/// `10·SS + 96·TT + 30·PS`.
pub mod ops {
    /// Sphere-sphere overlap test.
    pub const SPHERE_SPHERE: u64 = 10;
    /// Triangle-triangle test (the paper's figure for Tropp et al.; charged
    /// to either kernel, [`super::tropp`] or [`super::edge_crossing`]).
    pub const TRI_TRI: u64 = 96;
    /// Plane-sphere test of Algorithm 1.
    pub const PLANE_SPHERE: u64 = 30;
    /// A sphere against a room node's box (ours; not in the paper's model:
    /// the operations it pays, counted in [`super::sphere_box`]'s tests).
    pub const SPHERE_BOX: u64 = super::sphere_box::SPHERE_BOX;
    /// Two posed character node boxes (ours; not in the paper's model:
    /// [`super::leveled_box::BOX_BOX`]).
    pub const BOX_BOX: u64 = super::leveled_box::BOX_BOX;
}
