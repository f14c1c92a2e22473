//! One Rerun recording per method ([`Recorder`]), written to disk every
//! frame so a killed run leaves a recording of every frame before the kill;
//! the files of a run that fails are deleted.

use std::path::PathBuf;

use anyhow::Context;
use cornertree_workbench::record::blueprint::{ccd_blueprint, run_blueprint};
use cornertree_workbench::record::footer::{FOOTER_MAX_BYTES, Footer, finish_file};
use cornertree_workbench::record::framing;
use cornertree_workbench::record::layout;
use cornertree_workbench::record::recorder::{character_paths, object_paths};
use cornertree_workbench::record::target::RecordingTarget;
use cornertree_workbench::record::{RecordOptions, Recorder, SceneInfo};
use cornertree_workbench::session::Session;

use super::{Observer, Seen};

/// Every method's recorder (`None` where the target records nothing).
pub struct Recordings {
    pub recorders: Vec<Option<Recorder>>,
    /// Each recorder's file, for file targets.
    paths: Vec<Option<PathBuf>>,
    /// Files started, deleted if the run fails.
    pub created: Vec<PathBuf>,
}

/// Deletes files of recordings that did not finish (an error, not Ctrl-C).
pub fn discard(paths: &[PathBuf]) {
    for p in paths {
        let _ = std::fs::remove_file(p);
    }
}

impl Recordings {
    /// Opens one recording per method of `session` at `target` and logs the
    /// scene; `markdown` describes the scenario for each method.
    pub fn open(
        session: &mut Session,
        target: &RecordingTarget,
        name: &str,
        ccd: bool,
        markdown: impl Fn(&Session, usize) -> String,
    ) -> anyhow::Result<Self> {
        let scene = &session.scene;
        let options = RecordOptions {
            all_spheres: scene.recording.all_spheres,
            mesh_every: scene.recording.mesh_every,
            spheres_every: scene.recording.spheres_every,
        };
        let (characters, objects) = (character_paths(scene), object_paths(scene));
        let methods = session.worlds().len();
        let mut out = Self {
            recorders: Vec::new(),
            paths: Vec::new(),
            created: Vec::new(),
        };
        // Where the bodies stand at frame 0, for the views' eyes: a frame
        // posed and skinned, so only when something is recorded.
        let first_frame = if ccd || matches!(target, RecordingTarget::None) {
            None
        } else {
            framing::first_frame_bounds(scene)
        };
        for m in 0..methods {
            let w = session.world(m);
            let level = w
                .character(session.character(0))
                .map(|c| layout::display_level(&c.tree().tree))
                .unwrap_or(0);
            let blueprint = if ccd {
                let bodies: Vec<String> = characters.iter().chain(&objects).cloned().collect();
                ccd_blueprint(&bodies).into()
            } else {
                run_blueprint(&characters, &objects, level, first_frame)
            };
            let method = w.method();
            let opened = target
                .open(name, method.name(), methods, blueprint)
                .inspect_err(|_| discard(&out.created))?;
            let Some(o) = opened else {
                out.recorders.push(None);
                out.paths.push(None);
                continue;
            };
            out.paths.push(o.path.clone());
            if let Some(path) = &o.path {
                out.created.push(path.clone());
            }
            let info = SceneInfo {
                scenario: name,
                markdown: markdown(session, m),
            };
            let r = Recorder::new(o.stream, options, &info, session, m)
                .inspect_err(|_| discard(&out.created))?;
            out.recorders.push(Some(r));
        }
        Ok(out)
    }

    /// Method `m`'s stream, if recorded.
    pub fn stream(&self, m: usize) -> Option<&rerun::RecordingStream> {
        self.recorders[m].as_ref().map(Recorder::stream)
    }

    /// Ends every recording with `note`, and gives each file rerun's footer
    /// (`record::footer`); returns the frames each logged.
    pub fn finish(self, session: &Session, note: &str) -> anyhow::Result<Vec<usize>> {
        let mut logged = Vec::new();
        for ((rec, path), w) in self
            .recorders
            .into_iter()
            .zip(self.paths)
            .zip(session.worlds())
        {
            if let Some(rec) = rec {
                rec.finish(note)
                    .with_context(|| format!("finishing the recording of {}", w.method()))?;
                logged.push(rec.frames_logged());
                // The stream closed (its file sink joined) before the file
                // is read back.
                rec.close();
                if let Some(path) = path {
                    match finish_file(&path, FOOTER_MAX_BYTES) {
                        Ok(Footer::Added(_)) => {}
                        Ok(Footer::TooLarge(size)) => eprintln!(
                            "note: {} ({:.0} MB) is left without rerun's footer (added up to {} MiB, \
                             to keep memory bounded); `rerun rrd optimize {0} -o OUT.rrd` adds one",
                            path.display(),
                            size as f64 / 1e6,
                            FOOTER_MAX_BYTES >> 20
                        ),
                        Err(e) => {
                            eprintln!("warning: {e}; the recording opens without rerun's footer")
                        }
                    }
                }
            }
        }
        Ok(logged)
    }

    fn log(&mut self, seen: &Seen<'_>, m: usize) -> anyhow::Result<()> {
        let Some(rec) = &mut self.recorders[m] else {
            return Ok(());
        };
        rec.log_frame(seen.k, seen.t, seen.session)?;
        if let Some(r) = seen.reference {
            rec.log_truth(&r.truth, &r.scores[m].details, seen.session)?;
        }
        rec.stream()
            .flush_blocking()
            .map_err(|e| anyhow::anyhow!("{e}"))
    }
}

impl Observer for Recordings {
    fn needs_skin(&self, _k: usize) -> bool {
        self.recorders.iter().any(Option::is_some)
    }

    fn method(&mut self, seen: &Seen<'_>, m: usize) -> anyhow::Result<()> {
        // Written to disk every frame: a killed run leaves a recording of
        // every frame before the kill.
        self.log(seen, m).map_err(|e| {
            discard(&self.created);
            let method = seen.session.world(m).method();
            e.context(format!("recording frame {} of {method}", seen.k))
        })
    }
}
