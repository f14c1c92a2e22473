//! `cornertree compare`: every method on the same frames against the ground
//! truth, no recording (command-line plumbing; the frame loop is
//! [`super::play`]).

use super::args::choice;
use cornertree::character::SkinningModel;
use cornertree::pipeline::Method;
use cornertree_workbench::record::target::RecordingTarget;

use super::args::ScenarioArgs;
use super::play::{DEFAULT_BUDGET_GIB, PlayArgs, Style, play};

#[derive(clap::Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub common: ScenarioArgs,
    /// Print the table as Markdown.
    #[arg(long)]
    pub markdown: bool,
    /// Skinning model, whatever the scenario says: `paper` (§3's one-joint
    /// model) or `linear` (glTF linear blend skinning).
    #[arg(long, value_parser = choice::<SkinningModel>())]
    pub skinning: Option<SkinningModel>,
    /// Threads for the characters and body pairs of a frame (0: one per
    /// core). Counters and pairs do not depend on it.
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Most memory the scenario's bodies, hierarchies and ground truth may
    /// take, in GiB (estimated before they are built; docs/robustness.md).
    #[arg(long, value_name = "GIB", default_value_t = DEFAULT_BUDGET_GIB)]
    pub memory_budget: f64,
}

pub fn compare(mut args: CompareArgs) -> anyhow::Result<String> {
    if args.common.methods.is_empty() {
        args.common.methods = Method::ALL.to_vec();
    }
    play(
        PlayArgs {
            common: args.common,
            skinning: args.skinning,
            no_truth: false,
            dump_frame: None,
            threads: args.threads,
            memory_budget: args.memory_budget,
            ccd: false,
            ccd_substeps: None,
            style: if args.markdown {
                Style::Markdown
            } else {
                Style::Text
            },
        },
        RecordingTarget::None,
    )
}
