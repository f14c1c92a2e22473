//! Reports: what the commands print, as text and as JSON.
//!
//! | file | what |
//! |---|---|
//! | [`animate`] | clip playback: refit containment, tightness, per-frame costs |
//! | [`inspect`] | static mesh summary: counts, de-duplication, tree shape and bytes |

pub mod animate;
pub mod inspect;
