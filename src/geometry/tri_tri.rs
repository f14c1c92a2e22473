//! The pipeline's narrow-phase triangle-triangle test (paper §3).
//!
//! A facade: [`triangles_intersect`] is whichever of the two kernels is
//! faster, measured (figures in `docs/kernels.md`):
//! * [`super::tropp`]: the test of Tropp, Tal and Shimshoni (2006) the paper
//!   names, the other triangle reduced to a segment in the first one's
//!   parameter plane;
//! * [`super::edge_crossing`]: every crossing edge of each triangle against
//!   the other.
//!
//! Both give the same answers as the exact oracle except on pairs that touch
//! (`tests/tri_tri_agreement.rs`); the operation model (§6) charges either 96.

pub use super::tropp::triangles_intersect;

/// The name of the kernel behind [`triangles_intersect`], as
/// `cornertree kernels` prints it.
pub const NARROW_PHASE_KERNEL: &str = "tri-tri-tropp";
