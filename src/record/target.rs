//! Where a run's recordings go: one recording stream per method.
//!
//! With no `--save`, `--connect`, `--spawn` or `--stdout`, each method is saved
//! to `recordings/<scenario>-<method>.rrd`. `--save PATH` with several methods
//! writes `PATH` with `-<method>` before the extension. `--connect`/`--spawn`
//! send every method to one viewer as separate recordings.

use std::path::{Path, PathBuf};

use super::framing::{self, FramedBlueprint};
use rerun::RecordingStream;

/// What the command line asked for.
#[derive(Clone, Debug)]
pub enum RecordingTarget {
    /// No recording at all (`--no-record`).
    None,
    /// `recordings/<scenario>-<method>.rrd` (nothing asked).
    Default,
    /// `--save PATH`.
    Save(PathBuf),
    /// `--connect`, `--spawn` or `--stdout`: handed to rerun's own arguments.
    Rerun(rerun::clap::RerunArgs, /* stdout */ bool),
}

/// Default directory of recordings, relative to the working directory.
pub const DEFAULT_DIR: &str = "recordings";

/// An opened recording of one method.
pub struct OpenRecording {
    pub stream: RecordingStream,
    /// The file written, for file targets.
    pub path: Option<PathBuf>,
}

impl RecordingTarget {
    /// The file for `method` when saving, if any.
    pub fn file_for(&self, scenario: &str, method: &str, methods: usize) -> Option<PathBuf> {
        match self {
            RecordingTarget::Default => {
                Some(Path::new(DEFAULT_DIR).join(format!("{scenario}-{method}.rrd")))
            }
            RecordingTarget::Save(p) if methods > 1 => {
                let stem = p.file_stem().map(|s| s.to_string_lossy().into_owned());
                let ext = p.extension().map(|s| s.to_string_lossy().into_owned());
                let name = format!(
                    "{}-{method}.{}",
                    stem.unwrap_or_default(),
                    ext.unwrap_or_else(|| "rrd".into())
                );
                Some(p.with_file_name(name))
            }
            RecordingTarget::Save(p) => Some(p.clone()),
            _ => None,
        }
    }

    /// Checks what cannot work before any work is done.
    pub fn check(&self, methods: usize) -> anyhow::Result<()> {
        if let RecordingTarget::Rerun(_, true) = self
            && methods > 1
        {
            anyhow::bail!(
                "--stdout carries one recording; pick one method with --method (got {methods})"
            );
        }
        Ok(())
    }

    /// Opens the recording of `method`.
    pub fn open(
        &self,
        scenario: &str,
        method: &str,
        methods: usize,
        blueprint: FramedBlueprint,
    ) -> anyhow::Result<Option<OpenRecording>> {
        let name = format!("{scenario} / {method}");
        match self {
            RecordingTarget::None => Ok(None),
            RecordingTarget::Rerun(args, _) => {
                let (stream, _guard) = args.init("cornertree")?;
                framing::send(&stream, &blueprint)?;
                stream.send_recording_name(name)?;
                Ok(Some(OpenRecording { stream, path: None }))
            }
            RecordingTarget::Default | RecordingTarget::Save(_) => {
                let path = self
                    .file_for(scenario, method, methods)
                    .expect("file targets name a file");
                if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                    std::fs::create_dir_all(dir).map_err(|e| {
                        anyhow::anyhow!("{}: cannot create the directory: {e}", dir.display())
                    })?;
                }
                // Streamed to the file without rerun's footer: the footer
                // indexes every chunk, and the SDK keeps that index in
                // memory until the end, so a long run's memory would grow
                // with its recording (docs/performance.md, "Long runs"); it
                // is added when the run ends (`record::footer`).
                let cannot = |e: &dyn std::fmt::Display| {
                    anyhow::anyhow!("{}: cannot write the recording: {e}", path.display())
                };
                let sink = rerun::sink::FileSink::with_options(
                    &path,
                    rerun::sink::FileSinkOptions {
                        write_footer: false,
                    },
                )
                .map_err(|e| cannot(&e))?;
                let stream = rerun::RecordingStreamBuilder::new("cornertree")
                    .recording_name(name)
                    .set_sinks((sink,))
                    .map_err(|e| cannot(&e))?;
                framing::send(&stream, &blueprint).map_err(|e| cannot(&e))?;
                Ok(Some(OpenRecording {
                    stream,
                    path: Some(path),
                }))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn file_names() {
        let d = RecordingTarget::Default;
        assert_eq!(
            d.file_for("museum", "plane-sphere", 4),
            Some(PathBuf::from("recordings/museum-plane-sphere.rrd"))
        );
        let s = RecordingTarget::Save(PathBuf::from("out/x.rrd"));
        assert_eq!(
            s.file_for("m", "original", 1),
            Some(PathBuf::from("out/x.rrd"))
        );
        assert_eq!(
            s.file_for("m", "original", 2),
            Some(PathBuf::from("out/x-original.rrd"))
        );
        assert_eq!(RecordingTarget::None.file_for("m", "original", 1), None);
        assert!(
            RecordingTarget::Rerun(
                <rerun::clap::RerunArgs as clap::FromArgMatches>::from_arg_matches(
                    &<rerun::clap::RerunArgs as clap::Args>::augment_args(clap::Command::new("t"))
                        .get_matches_from(["t"])
                )
                .unwrap(),
                true
            )
            .check(2)
            .is_err()
        );
    }
}
