//! The pipeline's narrow-phase triangle-triangle test (paper §3).
//!
//! A facade: [`triangles_intersect`] is whichever of the two kernels is
//! faster on the pipeline's narrow phase, measured:
//! * [`super::tropp`]: the test of Tropp, Tal and Shimshoni (2006) the paper
//!   names, the other triangle reduced to a segment in the first one's
//!   parameter plane;
//! * [`super::edge_crossing`]: every crossing edge of each triangle against
//!   the other.
//!
//! Tropp's test, in nanoseconds per test of the narrow phase (release, best of
//! four alternated runs of `cornertree run`, 8 frames): living room
//! `original` 34.6 against 36.3, `sphere-division` 29.7 against 31.4; museum
//! 35.8 against 37.8 and 29.4 against 31.2. On synthetic pairs the two are
//! even (`cornertree kernels`: 55.0 against 54.9; `benches/kernels.rs`: 23.3
//! against 22.6). Method and the full table: `docs/kernels.md`.
//!
//! Both give the same answers as the exact oracle except on pairs that touch
//! (`tests/tri_tri_agreement.rs`); the operation model (§6) charges either 96.
//!
//! Closed triangles, `f32` corners, `f64` arithmetic inside: touching counts.
//!
//! ```
//! use cornertree::geometry::tri_tri::{Prepared, prepared_intersect, triangles_intersect};
//! use cornertree::geometry::{Point, Triangle};
//!
//! let tri = |a: [f32; 3], b: [f32; 3], c: [f32; 3]| {
//!     Triangle::new(Point::from(a), Point::from(b), Point::from(c))
//! };
//! // The unit right triangle in the plane z = 0.
//! let floor = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
//! // A triangle in the plane x = y whose vertical edge pierces the floor at
//! // (0.25, 0.25, 0): they cross along the segment (0.25, 0.25, 0)–(0.5, 0.5, 0).
//! let piercing = tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [2.0, 2.0, 0.0]);
//! assert!(triangles_intersect(&floor, &piercing));
//! assert!(triangles_intersect(&piercing, &floor));
//! // The same triangle moved along the floor to x = y = 0.75: it crosses the
//! // floor's plane on x + y ≥ 1.5, beyond the hypotenuse x + y = 1.
//! let beside = tri([0.75, 0.75, -1.0], [0.75, 0.75, 1.0], [2.0, 2.0, 0.0]);
//! assert!(!triangles_intersect(&floor, &beside));
//! // A corner resting exactly on the floor's face: touching counts.
//! let resting = tri([0.25, 0.25, 0.0], [0.75, 0.25, 1.0], [0.25, 0.75, 1.0]);
//! assert!(triangles_intersect(&floor, &resting));
//! // Lifted by 0.001: apart.
//! let lifted = tri([0.25, 0.25, 0.001], [0.75, 0.25, 1.0], [0.25, 0.75, 1.0]);
//! assert!(!triangles_intersect(&floor, &lifted));
//!
//! // Prepared once each, the same answers.
//! let f = Prepared::<f64>::new(&floor);
//! for (other, meets) in [(piercing, true), (beside, false), (resting, true), (lifted, false)] {
//!     assert_eq!(prepared_intersect(&f, &Prepared::new(&other)), meets);
//! }
//! ```

pub use super::tropp::triangles_intersect;
/// The same test on triangles prepared once each (as the pipeline's narrow
/// phase does for a triangle that meets several others).
pub use super::tropp::{Prepared, prepared_intersect};

/// The name of the kernel behind [`triangles_intersect`], as
/// `cornertree kernels` prints it.
pub const NARROW_PHASE_KERNEL: &str = "tri-tri-tropp";
