//! # cornertree-workbench
//!
//! The research workbench on top of the collision library (the package
//! `cornertree` in `core/`, after *Real time accurate collision detection
//! for virtual characters*, the paper): scenario files, generated rooms and
//! characters, ground truth, recordings, reports and the `cornertree`
//! command. It uses the library through its public API like any engine.
//!
//! | module | what | paper |
//! |---|---|---|
//! | [`scenario`] | scenario files (TOML): characters, clips, rooms, objects, placements, methods; resolved into bodies | §6 |
//! | [`session`] | [`session::Session`]: one `CollisionWorld` per method, all fed the same poses; the frame loop every command drives | §6 |
//! | [`environment`] | generated rooms (museum, living room) of big and small triangles, moving doors; static glTF scenes | §4, §6 |
//! | [`humanoid`] | the generated skinned humanoid of any size | §6 |
//! | [`io`] | PLY dumps, continuous-collision query files, where a character comes from | |
//! | [`truth`] | ground truth (exact pairs over parry3d's BVH leaf pairs), parry3d's answer and the parry3d baseline world; disagreements classified; precision and recall | (reference) |
//! | [`record`] | Rerun recordings of runs and of the paper's figures | §3–6, Figs. 1–3 |
//! | [`report`] | what the commands print (text and JSON) | §6 |
//! | [`bench`](mod@bench) | cost per frame against the parry3d baseline, in one run; scaling variants | (performance) |
//! | [`study`] | experiments that vary one condition at a time (where the plane-sphere method reaches the paper's counts) | §5–6 |
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
