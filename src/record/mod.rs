//! Rerun recordings: what `run` and `figures` write (docs/recordings.md).
//!
//! | file | what |
//! |---|---|
//! | [`layout`] | entity paths, colours, the per-level split of a tree |
//! | [`blueprint`] | the layout a recording opens on |
//! | [`recorder`] | [`Recorder`]: the scene once, then every frame of one method, one character or many |
//! | [`ccd_recorder`] | continuous detection's part of a run's recording: swept spheres, bodies at a time of impact, touching pairs |
//! | [`figures`] | the paper's Figures 1–3 as recordings |
//! | [`draw`] | points, meshes, triangle soups, spheres per level, body names and colours |
//! | [`target`] | where recordings go (files, a viewer) |
//! | [`footer`] | rerun's footer added to a recording when its run ends (streamed without it) |
//!
//! One entity per batch (a level's spheres, the colliding triangles), never
//! one per sphere: the viewer stays fast with tens of thousands of spheres.

pub mod blueprint;
pub mod ccd_recorder;
pub mod draw;
pub mod figures;
pub mod footer;
pub mod framing;
pub mod layout;
pub mod rays;
pub mod recorder;
pub mod target;

pub use recorder::{RecordOptions, Recorder, SceneInfo};
