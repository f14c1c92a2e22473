//! Reports: what the commands print, as text and as JSON.
//!
//! | file | what |
//! |---|---|
//! | [`animate`] | clip playback: refit containment, tightness, per-frame costs |
//! | [`inspect`] | static mesh summary: counts, de-duplication, tree shape and bytes |
//! | [`paper`] | the paper's published figures, printed beside ours and labelled |
//! | [`tables`] | Table 1 and the environment hierarchies per method |

pub mod animate;
pub mod inspect;
pub mod paper;
pub mod tables;
