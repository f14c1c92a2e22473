//! A world recorded to Rerun, in the style of Rerun's own examples: the
//! command line of [`rerun::clap::RerunArgs`] (`--save FILE`, `--connect`,
//! `--spawn`, `--stdout`), one stream, a blueprint, and a `run` function
//! that logs.
//!
//! The scenario's bodies play one method of the collision library in a
//! [`Session`]; every frame, the workbench's [`Recorder`] logs the bodies,
//! the spheres the step refit, the colliding triangles by pair kind and the
//! counters, and against the ground truth the false positives and
//! negatives.
//!
//! `cargo run --release --example record_world -- scenarios/handshake.toml --save handshake.rrd`

use std::path::{Path, PathBuf};

use cornertree::choice::parse_choice;
use cornertree::pipeline::Method;
use cornertree_workbench::record::blueprint::run_blueprint;
use cornertree_workbench::record::framing::{self, FramedBlueprint, first_frame_bounds};
use cornertree_workbench::record::layout::display_level;
use cornertree_workbench::record::recorder::{character_paths, object_paths};
use cornertree_workbench::record::{RecordOptions, Recorder, SceneInfo};
use cornertree_workbench::scenario::open_scenario;
use cornertree_workbench::session::Session;
use cornertree_workbench::truth::Truth;

/// Plays a scenario through one method of the collision library and records
/// it to Rerun (a file, a viewer it spawns or one it connects to).
#[derive(Debug, clap::Parser)]
#[clap(author, version)]
struct Args {
    /// The scenario to play.
    #[arg(default_value = "scenarios/handshake.toml")]
    scenario: PathBuf,
    /// The method of the collision library to play it with.
    #[arg(long, default_value = "undivided-pruned-tri-tri", value_parser = parse_choice::<Method>)]
    method: Method,
    /// Frames to play (at most the scenario's).
    #[arg(long, default_value_t = 30)]
    frames: usize,
    #[command(flatten)]
    rerun: rerun::clap::RerunArgs,
}

/// The scenario at `path` with `method` alone, `frames` frames at most.
fn session(path: &Path, method: Method, frames: usize) -> anyhow::Result<Session> {
    let mut r = open_scenario(path)?;
    r.methods = vec![method];
    r.frames = r.frames.min(frames);
    Ok(Session::new(r, 0)?)
}

/// The blueprint the recording opens on, its spheres view looking at the
/// characters' first frame.
fn blueprint(session: &Session) -> FramedBlueprint {
    let view = session.world(0).character(session.character(0));
    let level = view.map(|v| display_level(&v.tree().tree)).unwrap_or(0);
    run_blueprint(
        &character_paths(&session.scene),
        &object_paths(&session.scene),
        level,
        first_frame_bounds(&session.scene),
    )
}

/// Plays every frame of `session` into `rec`; returns the frames logged.
fn run(rec: rerun::RecordingStream, mut session: Session) -> anyhow::Result<usize> {
    let info = SceneInfo {
        scenario: "record_world",
        markdown: format!(
            "## {} characters, {} moving objects\n\nmethod: {}",
            session.scene.characters.len(),
            session.scene.objects.len(),
            session.world(0).method()
        ),
    };
    let mut recorder = Recorder::new(rec, RecordOptions::default(), &info, &mut session, 0)?;
    let mut truth = Truth::new(&session.scene)?;
    for k in 0..session.frames() {
        session.pose(k);
        // Every vertex, for the recording and the truth (not the method's
        // work: it skins only what it tests).
        session.skin_all();
        session.detect(0);
        truth.update(&session.scene, &session.buffers, &session.object_poses)?;
        recorder.log_frame(k, session.scene.world_time(k), &session)?;
        recorder.log_truth(&truth, &[], &session)?;
    }
    recorder.finish("finished")?;
    Ok(recorder.frames_logged())
}

fn main() -> anyhow::Result<()> {
    use clap::Parser as _;
    let args = Args::parse();
    let session = session(&args.scenario, args.method, args.frames)?;
    let (rec, _serve_guard) = args.rerun.init("cornertree_example_record_world")?;
    framing::send(&rec, &blueprint(&session))?;
    let frames = run(rec, session)?;
    eprintln!("{}: {frames} frames recorded", args.scenario.display());
    Ok(())
}

/// The tests' reader of recordings (this example uses part of it).
#[cfg(test)]
#[path = "../tests/common/rrd.rs"]
#[allow(dead_code)]
mod rrd;

#[cfg(test)]
mod tests {
    use super::*;

    /// The handshake recorded to a file and read back: every body, the
    /// character pairs' colliding triangles, one frame per step.
    #[test]
    fn the_handshake_is_recorded_frame_by_frame() {
        let root = Path::new(env!("CARGO_MANIFEST_DIR"));
        let out = std::env::temp_dir().join(format!("record_world-{}.rrd", std::process::id()));
        let frames = 6;
        let s = session(
            &root.join("scenarios/handshake.toml"),
            Method::UndividedPrunedTriTri,
            frames,
        )
        .unwrap();
        let rec = rerun::RecordingStreamBuilder::new("cornertree_example_record_world")
            .save(&out)
            .unwrap();
        assert_eq!(run(rec, s).unwrap(), frames);
        let rrd = super::rrd::read_rrd(&out);
        let _ = std::fs::remove_file(&out);
        assert_eq!(rrd.error, None);
        let paths = rrd.entity_paths();
        for p in [
            "world/characters/00_ada/mesh",
            "world/characters/01_ben/skeleton",
            "cd/colliding/characters/bodies",
            "stats/by_kind/pairs/characters",
        ] {
            assert!(paths.contains(p), "{p} missing from {paths:?}");
        }
        let logged = rrd.frames("stats/pairs");
        assert_eq!(logged, (0..frames as i64).collect());
    }
}
