//! The progress bar of a run and Ctrl-C: the frame loop stops after the
//! current frame, and the run ends with the summary of the frames played
//! and complete recordings.

use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use super::{Observer, Seen};

/// A run's progress.
pub struct Progress {
    bar: indicatif::ProgressBar,
    interrupted: Arc<AtomicBool>,
}

impl Progress {
    /// A bar of `frames` frames labelled `name`, saying `building
    /// hierarchies` until the first frame.
    pub fn new(name: &str, frames: usize) -> Self {
        let bar = indicatif::ProgressBar::new(frames as u64);
        bar.set_style(
            indicatif::ProgressStyle::with_template(
                "{prefix} [{bar:30}] {pos}/{len} frames, {elapsed} (eta {eta}) {msg}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        bar.set_prefix(name.to_string());
        bar.set_message("building hierarchies");
        let interrupted = Arc::new(AtomicBool::new(false));
        let flag = interrupted.clone();
        // A second handler cannot be installed (only one run per process); a
        // run without it still works, Ctrl-C then ends it the default way.
        let _ = ctrlc::set_handler(move || flag.store(true, Ordering::SeqCst));
        Self { bar, interrupted }
    }

    /// The frames start.
    pub fn start(&self) {
        self.bar.set_message("");
    }

    /// Set when Ctrl-C is pressed.
    pub fn interrupted_flag(&self) -> Arc<AtomicBool> {
        self.interrupted.clone()
    }

    /// The bar is removed.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Observer for Progress {
    fn frame_end(&mut self, _seen: &Seen<'_>) -> anyhow::Result<()> {
        self.bar.inc(1);
        Ok(())
    }
}
