//! What watches the frame loop of `run` and `compare` ([`super::play`]):
//! each observer reads a step's contacts and the session's state, and none
//! changes the measured work.
//!
//! | file | observer |
//! |---|---|
//! | [`reference`] | the ground truth: the exact pairs of the frame, each method scored against them |
//! | [`continuous`] | `--ccd`: continuous detection of every method over each frame step, its reference and recording |
//! | [`report`] | the summary table and the JSON report |
//! | [`recording`] | one Rerun recording per method |
//! | [`dump`] | `--dump-frame`: one frame's meshes as PLY and its pairs as JSON |
//! | [`progress`] | the progress bar and Ctrl-C |
//!
//! Per frame the loop poses the bodies, has every vertex skinned when an
//! observer needs them, updates the [`reference::Reference`], then steps each
//! method and hands the step to the continuous observer and to every
//! [`Observer`] in turn.

pub mod continuous;
pub mod dump;
pub mod progress;
pub mod recording;
pub mod reference;
pub mod report;

use cornertree_workbench::report::continuous::ContinuousFrameRecord;
use cornertree_workbench::session::Session;

use reference::Reference;

/// A frame as the observers see it.
pub struct Seen<'a> {
    pub session: &'a Session,
    pub k: usize,
    /// The clip time of one character, the world's time otherwise.
    pub t: f32,
    /// The ground truth of the frame and each method's score (absent with
    /// `--no-truth`).
    pub reference: Option<&'a Reference>,
    /// Per method: its continuous step ending at this frame (with `--ccd`,
    /// from frame 1 on).
    pub continuous: &'a [Option<ContinuousFrameRecord>],
}

/// One observer of the frame loop.
pub trait Observer {
    /// Whether frame `k` needs every vertex of every character skinned.
    fn needs_skin(&self, _k: usize) -> bool {
        false
    }

    /// Method `m` has stepped on the frame.
    fn method(&mut self, _seen: &Seen<'_>, _m: usize) -> anyhow::Result<()> {
        Ok(())
    }

    /// Every method has stepped on the frame.
    fn frame_end(&mut self, _seen: &Seen<'_>) -> anyhow::Result<()> {
        Ok(())
    }
}
