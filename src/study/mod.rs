//! Experiments that explain a measurement by varying its conditions.
//!
//! | file | what | paper |
//! |---|---|---|
//! | [`plane_sphere`] | when the plane-sphere method (§5 as written) reaches Tables 2–3's counts: position along the big triangle, tessellation, threshold, de-duplication, gap | §5, §6 |

pub mod plane_sphere;

pub use plane_sphere::{Condition, Factor, StudyError, StudyRow, conditions, run_study};
