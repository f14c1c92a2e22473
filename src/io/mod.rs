//! The workbench's files: character sources, PLY dumps, CCD query files
//! (the library's glTF loaders are `cornertree::io`).
//!
//! | file | what |
//! |---|---|
//! | [`source`] | a character source: a glTF file or `generated:humanoid?vertices=N&seed=S` |
//! | [`ply`] | writing triangle meshes as PLY (`run --dump-frame`) |
//! | [`ccd_queries`] | CCD query files with exact answers (CSV of exact rationals; `cornertree ccd-queries`) |

pub mod ccd_queries;
pub mod ply;
pub mod source;

pub use source::{CharacterSource, SourceError};
