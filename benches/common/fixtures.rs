//! Shared bench fixtures: the shipped scenarios, loaded by each bench function.
//! Everything is deterministic (the scenarios fix their seeds; random inputs
//! use fixed seeds).

#![allow(dead_code)]

use std::path::Path;

use cornertree_workbench::scenario::{Resolved, open_scenario};

/// `scenarios/<name>.toml` of this repository, resolved (assets loaded,
/// placement solved).
pub fn scenario(name: &str) -> Resolved {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(format!("{name}.toml"));
    open_scenario(&path).unwrap_or_else(|e| panic!("{}: {e}", path.display()))
}

/// Frames of a scenario played in turn by a bench loop, so a measurement
/// covers the whole clip rather than one pose.
pub struct FrameCycle {
    next: usize,
    frames: usize,
}

impl FrameCycle {
    pub fn new(frames: usize) -> Self {
        Self { next: 0, frames }
    }

    pub fn next_frame(&mut self) -> usize {
        let k = self.next;
        self.next = (self.next + 1) % self.frames;
        k
    }
}
