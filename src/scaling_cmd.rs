//! `cornertree scaling`: per-frame cost against character size and against
//! environment size (docs/performance.md), by running `bench`'s measurement
//! on a base scenario whose character is swapped for the generated humanoid
//! of each size, and whose generated room is re-tessellated to each size
//! (same layout, same placement rule). Command-line plumbing; the work is in
//! [`crate::bench_cmd::measure`] and the library.

use std::path::{Path, PathBuf};

use anyhow::{Context, bail};
use cornertree::character::HumanoidParams;
use cornertree::io::CharacterSource;
use cornertree::pipeline::Method;
use cornertree::scenario::{EnvironmentSection, Scenario, load_scenario, resolve, scenario_name};
use serde::Serialize;

use crate::bench_cmd::{Bench, measure};

/// Character sizes of the study: about 3k, 10k, 44k (the paper's) and 100k.
const CHARACTER_VERTICES: [usize; 4] = [3_000, 10_000, 44_345, 100_000];
/// Environment sizes: about 10k, 133k (the paper's living room) and 500k.
const ENVIRONMENT_VERTICES: [usize; 3] = [10_000, 133_139, 500_000];

#[derive(clap::Args)]
pub struct ScalingArgs {
    /// Base scenario: its room must be generated (museum or living room) and
    /// its character is replaced by the generated humanoid of each size.
    #[arg(default_value = "scenarios/living_room.toml")]
    pub scenario: PathBuf,
    /// Measure only this method (repeat for several); default: all.
    #[arg(long = "method", value_enum)]
    pub methods: Vec<Method>,
    /// Frames played per configuration.
    #[arg(long, default_value_t = 16, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: u64,
    /// Character sizes (vertices, comma-separated) played in the base room.
    #[arg(long, value_delimiter = ',', default_values_t = CHARACTER_VERTICES)]
    pub characters: Vec<usize>,
    /// Room sizes (vertices, comma-separated) with the base character size
    /// (--character-size).
    #[arg(long, value_delimiter = ',', default_values_t = ENVIRONMENT_VERTICES)]
    pub environments: Vec<usize>,
    /// Character size (vertices) of the environment study.
    #[arg(long, default_value_t = 44_345)]
    pub character_size: usize,
    /// Write every configuration's measurement as JSON.
    #[arg(long)]
    pub json: Option<PathBuf>,
}

#[derive(Serialize)]
struct Scaling {
    base_scenario: String,
    frames: u64,
    by_character: Vec<Bench>,
    by_environment: Vec<Bench>,
}

/// The base scenario `s` (read from `base`) with another humanoid size and
/// room size.
fn variant(
    base: &Path,
    s: &Scenario,
    character_vertices: usize,
    environment_vertices: Option<usize>,
) -> anyhow::Result<cornertree::scenario::Resolved> {
    let mut s = s.clone();
    let seed = match &s.first_character_mut().character.source {
        CharacterSource::Humanoid(h) => h.seed,
        CharacterSource::File(_) => 0,
    };
    s.first_character_mut().character.source = CharacterSource::Humanoid(HumanoidParams {
        vertices: character_vertices,
        seed,
    });
    if s.first_character_mut().character.clip.is_none() {
        s.first_character_mut().character.clip = Some("walk".into());
    }
    if let Some(n) = environment_vertices {
        match &mut s.environment {
            EnvironmentSection::Museum { vertices, .. }
            | EnvironmentSection::LivingRoom { vertices, .. } => *vertices = Some(n),
            EnvironmentSection::Gltf { .. } => bail!(
                "{}: the environment study needs a generated room (kind = \"museum\" or \"living-room\"), not a glTF scene",
                base.display()
            ),
        }
    }
    let dir = base.parent().unwrap_or(Path::new(""));
    Ok(resolve(&s, dir)?)
}

pub fn scaling(args: ScalingArgs) -> anyhow::Result<String> {
    let methods = if args.methods.is_empty() {
        Method::ALL.to_vec()
    } else {
        args.methods.clone()
    };
    let name = scenario_name(&args.scenario);
    let frames = args.frames as usize;
    let configs: Vec<(usize, Option<usize>)> = args
        .characters
        .iter()
        .map(|&c| (c, None))
        .chain(
            args.environments
                .iter()
                .map(|&e| (args.character_size, Some(e))),
        )
        .collect();
    let base = load_scenario(&args.scenario)?;
    let progress = indicatif::ProgressBar::new((configs.len() * frames) as u64);
    let mut results = Vec::with_capacity(configs.len());
    for &(c, e) in &configs {
        let label = match e {
            None => format!("{name}, humanoid of {c} vertices"),
            Some(e) => format!("{name}, room of {e} vertices, humanoid of {c}"),
        };
        progress.set_message(label.clone());
        let resolved = variant(&args.scenario, &base, c, e).with_context(|| label.clone())?;
        results.push(measure(
            &resolved, &label, &methods, frames, false, &progress,
        )?);
    }
    progress.finish_and_clear();
    let by_environment = results.split_off(args.characters.len());
    let result = Scaling {
        base_scenario: name,
        frames: args.frames,
        by_character: results,
        by_environment,
    };
    if let Some(path) = &args.json {
        std::fs::write(path, serde_json::to_string(&result)?)
            .with_context(|| format!("{}: cannot write the report", path.display()))?;
    }
    let mut out = format!(
        "Median ms per frame over {} frames of {} (de-duplication off; speed-up over parry3d in brackets)\n\n",
        result.frames, result.base_scenario
    );
    out += "### Against character size (the room at its own size)\n\n";
    out += &table(&result.by_character, &methods);
    out += &format!(
        "\n### Against environment size (humanoid of {} vertices)\n\n",
        args.character_size
    );
    out += &table(&result.by_environment, &methods);
    if let Some(path) = &args.json {
        out += &format!("\nreport: {}\n", path.display());
    }
    Ok(out)
}

/// One markdown row per configuration: sizes, the baseline, each method.
fn table(rows: &[Bench], methods: &[Method]) -> String {
    let mut out = String::from("| character vertices | room vertices | parry3d |");
    for m in methods {
        out += &format!(" {} |", m.name());
    }
    out += "\n|---:|---:|---:|";
    out += &"---:|".repeat(methods.len());
    out += "\n";
    for b in rows {
        out += &format!(
            "| {} | {} | {:.3} |",
            b.vertices, b.environment_vertices, b.parry_ms_per_frame
        );
        for m in &b.methods {
            // Two significant digits below 1×, one decimal above.
            let digits = if m.speedup_vs_parry < 1.0 { 2 } else { 1 };
            out += &format!(
                " {:.3} ({:.*}×) |",
                m.ms_per_frame, digits, m.speedup_vs_parry
            );
        }
        out += "\n";
    }
    out
}
