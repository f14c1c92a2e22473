//! # cornertree
//!
//! A research workbench for real-time collision detection (CD) of animated,
//! skinned virtual characters with sphere trees, after *Real time accurate
//! collision detection for virtual characters* (the paper).
//!
//! | module | what | paper |
//! |---|---|---|
//! | [`bench`] | cost per frame against the parry3d baseline, in one run; scaling variants | (performance) |
//! | [`geometry`] | points, spheres, triangles; the tests of the operation model; enclosing spheres; exact oracle | §2, §3, §5, §6 |
//! | [`mesh`] | indexed triangle meshes; edge de-duplication | §4 |
//! | [`sphere_tree`] | sphere-tree build, n-ary collapse, validation, simultaneous traversal | §3 |
//! | [`big_triangle`] | sphere division, corner-trees and quaternary trees inside big triangles | §4–5 |
//! | [`character`] | skeletons, clips, skinning models | §3 |
//! | [`io`] | glTF loading | |
//! | [`environment`] | generated rooms (museum, living room) of big and small triangles, moving doors; static glTF scenes | §4, §6 |
//! | [`pipeline`] | methods, the environment hierarchy per method | §5–6 |
//! | [`record`] | Rerun recordings of runs and of the paper's figures | §3–6, Figs. 1–3 |
//! | [`report`] | what the commands print (text and JSON) | §6 |
//! | [`scenario`] | scenario files (TOML): character, clip, room, placement (start, path, gap to a surface), methods | §6 |
//! | [`study`] | experiments that vary one condition at a time (where the plane-sphere method reaches the paper's counts) | §5–6 |
//! | [`truth`] | ground truth from parry3d (BVH leaf pairs, triangle-triangle test); disagreements classified; precision and recall | (reference) |
//!
//! `docs/architecture.md` maps every section of the paper to the code.

pub mod bench;
pub mod environment;
pub mod humanoid;
pub mod io;
pub mod record;
pub mod report;
pub mod scenario;
pub mod session;
pub mod study;
pub mod truth;
