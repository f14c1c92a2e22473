//! `cornertree bench`: each method's cost per frame against the parry3d
//! baseline, in one run (command-line plumbing; the work is in
//! [`cornertree_workbench::bench`]).

use anyhow::Context;
use cornertree_workbench::bench::continuous::measure_ccd;
use cornertree_workbench::bench::{Bench, measure};
use cornertree_workbench::report::bench::BenchTable;
use cornertree_workbench::report::ccd_bench::CcdBenchTable;
use cornertree_workbench::scenario::{Resolved, open_scenario_within, scenario_name};

use super::args::ScenarioArgs;
use super::play::{DEFAULT_BUDGET_GIB, run_limits};

#[derive(clap::Args)]
pub struct BenchArgs {
    #[command(flatten)]
    pub common: ScenarioArgs,
    /// Threads for the methods' frames (0: one per core); each method is also
    /// measured on one thread in the same run (`parallel_speedup`).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
    /// Continuous detection instead of parry: each method's continuous step
    /// beside its discrete frame, and discrete detection at the fewest
    /// sub-steps per step that finds every contact of the sub-stepped
    /// reference (docs/ccd.md, "Cost").
    #[arg(long)]
    pub ccd: bool,
    /// With `--ccd`: the most sub-steps per step tried.
    #[arg(long, value_name = "K", default_value_t = 256, value_parser = clap::value_parser!(u32).range(1..=65536))]
    pub ccd_max_substeps: u32,
    /// Most memory the scenario's bodies and the measured methods'
    /// hierarchies may take, in GiB (estimated before they are built, as
    /// `run` does; docs/robustness.md).
    #[arg(long, value_name = "GIB", default_value_t = DEFAULT_BUDGET_GIB)]
    pub memory_budget: f64,
}

/// A progress bar over `len` frames.
pub fn progress_bar(len: u64) -> indicatif::ProgressBar {
    let p = indicatif::ProgressBar::new(len);
    p.set_style(
        indicatif::ProgressStyle::with_template(
            "[{bar:30}] {pos}/{len} frames, {elapsed} (eta {eta}) {msg}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    p
}

/// Measures `scene` (methods and de-duplication already chosen).
pub fn measure_with_progress(
    scene: Resolved,
    name: &str,
    frames: usize,
    threads: usize,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Bench> {
    measure(scene, name, frames, threads, || progress.inc(1))
        .with_context(|| format!("{name}: measuring"))
}

pub fn bench(args: BenchArgs) -> anyhow::Result<String> {
    let common = &args.common;
    // The methods measured are set before resolving: the budget charges
    // their hierarchies alone.
    let limits = run_limits(args.memory_budget)?;
    let mut scene = open_scenario_within(&common.scenario, &limits, |s| {
        s.methods = common.methods_or_all();
    })?;
    common.apply(&mut scene, Some(false));
    let frames = common.frames.map_or(scene.frames(), |f| f as usize);
    let progress = progress_bar(frames as u64);
    let name = scenario_name(&common.scenario);
    if args.ccd {
        let result = measure_ccd(
            scene,
            &name,
            frames,
            args.threads,
            args.ccd_max_substeps,
            || progress.inc(1),
        )
        .with_context(|| format!("{name}: measuring"))?;
        progress.finish_and_clear();
        let mut out = CcdBenchTable(&result).to_string();
        if let Some(path) = &common.json {
            std::fs::write(path, serde_json::to_string(&result)?)
                .with_context(|| format!("{}: cannot write the report", path.display()))?;
            out += &format!("report: {}\n", path.display());
        }
        return Ok(out);
    }
    let result = measure_with_progress(scene, &name, frames, args.threads, &progress)?;
    progress.finish_and_clear();
    let mut out = BenchTable(&result).to_string();
    if let Some(path) = &common.json {
        std::fs::write(path, serde_json::to_string(&result)?)
            .with_context(|| format!("{}: cannot write the report", path.display()))?;
        out += &format!("report: {}\n", path.display());
    }
    Ok(out)
}
