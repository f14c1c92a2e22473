//! Reports: what the commands print, as text and as JSON.
//!
//! | file | what |
//! |---|---|
//! | [`inspect`] | static mesh summary: counts, de-duplication, tree shape and bytes |

pub mod inspect;
