//! `cornertree run`: a scenario through its methods, frame by frame, recorded
//! to Rerun (command-line plumbing; the frame loop is [`super::play`]).

use std::path::PathBuf;

use super::args::choice;
use clap::parser::ValueSource;
use cornertree::character::SkinningModel;
use cornertree_workbench::record::target::RecordingTarget;

use super::args::ScenarioArgs;
use super::play::{DEFAULT_BUDGET_GIB, PlayArgs, Style, play};

#[derive(clap::Args)]
pub struct RunArgs {
    #[command(flatten)]
    pub common: ScenarioArgs,
    /// Skinning model, whatever the scenario says: `paper` (§3's one-joint
    /// model) or `linear` (glTF linear blend skinning).
    #[arg(long, value_parser = choice::<SkinningModel>())]
    pub skinning: Option<SkinningModel>,
    /// Skip the ground truth (exact pairs on parry's broad phase, and parry's
    /// own answer) and the accuracy columns; faster on big scenes.
    #[arg(long)]
    pub no_truth: bool,
    /// Write frame K's posed character and environment to DIR/avatar.ply and
    /// DIR/environment.ply (face i is triangle i of every report) and
    /// DIR/pairs.json with `reported` (the first method's pairs), `reference`
    /// (the exact pairs), `parry` and `reported_by_method`.
    #[arg(long, num_args = 2, value_names = ["K", "DIR"])]
    pub dump_frame: Option<Vec<String>>,
    /// Write no recording (by default each method is saved to
    /// recordings/<scenario>-<method>.rrd unless --save, --connect, --spawn or
    /// --stdout says otherwise; see docs/recordings.md).
    #[arg(long, conflicts_with_all = ["save", "connect", "stdout"])]
    pub no_record: bool,
    /// Threads for the characters and body pairs of a frame (0: one per
    /// core). Counters and pairs do not depend on it.
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Most memory the scenario's bodies, hierarchies and ground truth may
    /// take, in GiB (estimated before they are built; docs/robustness.md).
    #[arg(long, value_name = "GIB", default_value_t = DEFAULT_BUDGET_GIB)]
    pub memory_budget: f64,
    /// Continuous detection of every frame step beside the discrete frames
    /// (as the scenario's `ccd = true`): the pairs touching during each
    /// step with their times of impact, those the discrete frames missed,
    /// and recall against the exact oracle on sub-steps (docs/ccd.md).
    #[arg(long)]
    pub ccd: bool,
    /// Sub-steps per frame step of `--ccd`'s reference (default: the
    /// scenario's `ccd_substeps`, 256).
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub ccd_substeps: Option<u32>,
    #[command(flatten)]
    pub rerun: rerun::clap::RerunArgs,
}

/// Where recordings go, from what was actually typed: rerun's arguments
/// default to spawning a viewer, ours to saving a file.
pub fn recording_target(args: &RunArgs, matches: &clap::ArgMatches) -> RecordingTarget {
    let typed = |id: &str| matches.value_source(id) == Some(ValueSource::CommandLine);
    if args.no_record {
        RecordingTarget::None
    } else if typed("stdout") {
        RecordingTarget::Rerun(args.rerun.clone(), true)
    } else if let Some(path) = matches.get_one::<PathBuf>("save") {
        RecordingTarget::Save(path.clone())
    } else if typed("connect") || typed("spawn") {
        RecordingTarget::Rerun(args.rerun.clone(), false)
    } else {
        RecordingTarget::Default
    }
}

pub fn run(args: RunArgs, target: RecordingTarget) -> anyhow::Result<String> {
    play(
        PlayArgs {
            common: args.common,
            skinning: args.skinning,
            no_truth: args.no_truth,
            dump_frame: args.dump_frame,
            threads: args.threads,
            memory_budget: args.memory_budget,
            style: Style::Text,
            ccd: args.ccd,
            ccd_substeps: args.ccd_substeps,
        },
        target,
    )
}
