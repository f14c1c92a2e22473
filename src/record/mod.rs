//! Rerun recordings: what `run` and `figures` write (docs/recordings.md).
//!
//! | file | what |
//! |---|---|
//! | [`layout`] | entity paths, colours, the per-level split of a tree |
//! | [`blueprint`] | the layout a recording opens on |
//! | [`run_recorder`] | the scene once, then every frame of one method |
//! | [`world_recorder`] | the scene once, then every frame of one method playing a world |
//! | [`ccd_recorder`] | continuous detection's part of a run's recording: swept spheres, bodies at a time of impact, touching pairs |
//! | [`figures`] | the paper's Figures 1–3 as recordings |
//! | [`target`] | where recordings go (files, a viewer) |
//!
//! One entity per batch (a level's spheres, the colliding triangles), never
//! one per sphere: the viewer stays fast with tens of thousands of spheres.

pub mod blueprint;
pub mod ccd_recorder;
pub mod figures;
pub mod layout;
pub mod run_recorder;
pub mod target;
pub mod world_recorder;

pub use run_recorder::{RecordOptions, RunRecorder, SceneInfo};
pub use world_recorder::WorldRecorder;
