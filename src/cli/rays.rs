//! `cornertree rays`: ray casts against a scenario's posed characters,
//! checked against the exact reference and timed against parry3d
//! (command-line plumbing; the work is in [`cornertree_workbench::bench::rays`]).

use std::path::PathBuf;

use anyhow::Context;
use cornertree::pipeline::Method;
use cornertree_workbench::bench::rays::{RayPattern, RaysConfig, measure_rays};
use cornertree_workbench::record::blueprint::rays_blueprint;
use cornertree_workbench::record::rays::{LEVELS, RaysRecording, character_entity};
use cornertree_workbench::report::rays::RaysTable;
use cornertree_workbench::scenario::{open_scenario_within, scenario_name};

use super::args::choice;
use super::bench::progress_bar;
use super::play::{DEFAULT_BUDGET_GIB, run_limits};

#[derive(clap::Args)]
pub struct RaysArgs {
    /// A scenario file (TOML; docs/scenarios.md). Its characters are cast
    /// against (every triangle: edge de-duplication is off); its room and
    /// objects are not.
    #[arg(default_value = "scenarios/living_room.toml")]
    pub scenario: PathBuf,
    /// The method whose sphere trees answer the rays.
    #[arg(long, value_parser = choice::<Method>(), default_value = "undivided-pruned-tri-tri")]
    pub method: Method,
    /// Frames to play (at most the scenario's).
    #[arg(long, default_value_t = 10, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: u64,
    /// Rays cast per frame.
    #[arg(long, default_value_t = 100, value_parser = clap::value_parser!(u64).range(1..=1_000_000))]
    pub rays: u64,
    /// Which rays: a hit-scan fan swept across the characters, a picking
    /// grid over the first character, or half of each.
    #[arg(long, value_enum, default_value = "both")]
    pub pattern: RayPattern,
    /// Write the report as JSON to this file (fields: docs/performance.md,
    /// "Rays").
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Where the recording goes (default recordings/<scenario>-rays.rrd).
    #[arg(long)]
    pub save: Option<PathBuf>,
    /// No recording.
    #[arg(long, conflicts_with = "save")]
    pub no_record: bool,
    /// Most memory the scenario's bodies and hierarchies may take, in GiB.
    #[arg(long, value_name = "GIB", default_value_t = DEFAULT_BUDGET_GIB)]
    pub memory_budget: f64,
}

pub fn rays(args: RaysArgs) -> anyhow::Result<String> {
    let limits = run_limits(args.memory_budget)?;
    let method = args.method;
    let scene = open_scenario_within(&args.scenario, &limits, |s| {
        s.methods = vec![method];
    })?;
    let name = scenario_name(&args.scenario);
    let frames = (args.frames as usize).min(scene.frames).max(1);
    let path = (!args.no_record).then(|| {
        args.save
            .clone()
            .unwrap_or_else(|| PathBuf::from("recordings").join(format!("{name}-rays.rrd")))
    });
    let mut rec = match &path {
        Some(p) => {
            if let Some(dir) = p.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir)
                    .with_context(|| format!("{}: cannot create the directory", dir.display()))?;
            }
            Some({
                let names: Vec<String> = scene
                    .characters
                    .iter()
                    .enumerate()
                    .map(|(i, a)| character_entity(i, &a.name))
                    .collect();
                let rec = rerun::RecordingStreamBuilder::new("cornertree")
                    .recording_name(format!("{name} / rays"))
                    .with_blueprint(rays_blueprint(&names, 3, LEVELS))
                    .save(p)
                    .with_context(|| format!("{}: cannot write the recording", p.display()))?;
                RaysRecording::begin(rec)?
            })
        }
        None => None,
    };
    let config = RaysConfig {
        method,
        frames,
        rays_per_frame: args.rays as usize,
        pattern: args.pattern,
    };
    let progress = progress_bar(frames as u64);
    let report = measure_rays(scene, &name, &config, |session, frame| {
        if let Some(rec) = &mut rec {
            rec.log_frame(session, frame)?;
        }
        progress.inc(1);
        Ok(())
    })
    .with_context(|| format!("{name}: casting rays"))?;
    progress.finish_and_clear();
    if let Some(rec) = rec {
        rec.stream().flush_blocking()?;
    }
    let mut out = RaysTable(&report).to_string();
    if let Some(p) = &path {
        out += &format!("recording: {}\n", p.display());
    }
    if let Some(p) = &args.json {
        std::fs::write(p, serde_json::to_string(&report)?)
            .with_context(|| format!("{}: cannot write the report", p.display()))?;
        out += &format!("report: {}\n", p.display());
    }
    Ok(out)
}
