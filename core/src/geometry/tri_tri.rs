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

pub use super::tropp::triangles_intersect;
/// The same test on triangles prepared once each
/// ([`crate::pipeline::prepared_triangles`]).
pub use super::tropp::{Prepared, prepared_intersect};

/// The name of the kernel behind [`triangles_intersect`], as
/// `cornertree kernels` prints it.
pub const NARROW_PHASE_KERNEL: &str = "tri-tri-tropp";
