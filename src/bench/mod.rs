//! Cost per frame: every method's world of one [`crate::session::Session`] against the
//! parry3d baseline ([`crate::truth::ParryWorld`]), measured in one run, and
//! the scenario variants of the scaling studies.
//!
//! | file | what |
//! |---|---|
//! | [`measure`](mod@measure) | [`measure::measure`]: frames interleaved between parry, each method on all threads and on one |
//! | [`continuous`] | [`continuous::measure_ccd`]: continuous detection beside discrete per method, and discrete at `k` sub-steps (`bench --ccd`) |
//! | [`variants`] | a base scenario with another character size, room size or number of characters |

pub mod continuous;
pub mod measure;
pub mod rays;
pub mod variants;

pub use measure::{Bench, MethodBench, measure};
