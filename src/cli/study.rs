//! `cornertree plane-sphere-study`: command-line plumbing for
//! [`cornertree_workbench::study::run_study`].

use std::path::PathBuf;

use super::args::choice;
use anyhow::Context;
use cornertree::pipeline::Method;
use cornertree_workbench::report::study::StudyTable;
use cornertree_workbench::study::run_study;

#[derive(clap::Args)]
pub struct StudyArgs {
    /// Base scenarios with a gap placement (default: the paper-scale museum
    /// and living room).
    #[arg(default_values = ["scenarios/museum.toml", "scenarios/living_room.toml"])]
    pub scenarios: Vec<PathBuf>,
    /// Methods to play under every condition (repeat for several).
    #[arg(long = "method", value_parser = choice::<Method>(), default_values = ["plane-sphere", "plane-sphere-pruned"])]
    pub methods: Vec<Method>,
    /// Play this many frames of each condition instead of the scenario's.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Write every row as JSON (`{"rows": [...]}`) to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Print the tables as Markdown.
    #[arg(long)]
    pub markdown: bool,
}

pub fn study(args: StudyArgs) -> anyhow::Result<String> {
    let started = std::time::Instant::now();
    let mut rows = Vec::new();
    for base in &args.scenarios {
        let progress = indicatif::ProgressBar::new(0);
        progress.set_style(
            indicatif::ProgressStyle::with_template(
                "{prefix} [{bar:30}] {pos}/{len} conditions, {elapsed}",
            )
            .expect("valid template")
            .progress_chars("=> "),
        );
        progress.set_prefix(base.display().to_string());
        let got = run_study(
            base,
            &args.methods,
            args.frames.map(|f| f as usize),
            |done, total| {
                progress.set_length(total as u64);
                progress.set_position(done as u64);
            },
        )
        .with_context(|| format!("{}: experiment failed", base.display()))?;
        progress.finish_and_clear();
        rows.extend(got);
    }
    if let Some(path) = &args.json {
        let text = serde_json::to_string(&serde_json::json!({ "rows": rows }))?;
        std::fs::write(path, text)
            .with_context(|| format!("{}: cannot write the report", path.display()))?;
    }
    let table = StudyTable(&rows);
    let mut out = if args.markdown {
        table.markdown()
    } else {
        table.to_string()
    };
    out += &format!(
        "{} rows in {:.1} s (maxima over the frames; the paper's line is its published figure)\n",
        rows.len(),
        started.elapsed().as_secs_f64()
    );
    Ok(out)
}
