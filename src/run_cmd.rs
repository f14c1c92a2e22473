//! `cornertree run`: a scenario through every chosen method, frame by frame.
//! (Kept beside `main.rs`: command-line plumbing only; the work is in the library.)

use std::io::IsTerminal;
use std::path::PathBuf;

use anyhow::Context;
use cornertree::character::PoseBuffers;
use cornertree::pipeline::Method;
use cornertree::pipeline::driver::{Pipeline, PipelineOptions, pose_frame};
use cornertree::report::run::{FrameRecord, MethodRun, Summary, SummaryTable};
use cornertree::scenario::{load_scenario, resolve};
use cornertree::sphere_tree::BuildParams;

#[derive(clap::Args)]
pub struct RunArgs {
    /// A scenario file (TOML; see docs/scenarios.md and scenarios/).
    pub scenario: PathBuf,
    /// Run only this method (repeat for several); default: the scenario's methods.
    #[arg(long = "method", value_enum)]
    pub methods: Vec<Method>,
    /// Play this many frames instead of the scenario's.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Write the per-frame report as JSON to this file: with one method, an
    /// object with `scenario`, `method`, `hierarchy_bytes` and `frames`; with
    /// several, `{"scenario", "runs": [those objects]}`.
    #[arg(long)]
    pub json: Option<PathBuf>,
}

pub fn run(args: RunArgs) -> anyhow::Result<String> {
    let scenario = load_scenario(&args.scenario)?;
    let base_dir = args
        .scenario
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default();
    let mut resolved = resolve(&scenario, &base_dir)?;
    if !args.methods.is_empty() {
        resolved.methods = args.methods.clone();
    }
    let frames = args.frames.map_or(resolved.frames(), |f| f as usize);
    let name = args
        .scenario
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default();
    let options = PipelineOptions {
        skinning: resolved.skinning,
        dedup: resolved.dedup,
        threshold: resolved.threshold,
        build: BuildParams::default(),
    };
    let character = &resolved.character;
    let env = &resolved.environment.mesh;
    let mut pipes: Vec<Pipeline> = resolved
        .methods
        .iter()
        .map(|&m| Pipeline::new(character, env, m, options))
        .collect();
    let mut runs: Vec<MethodRun> = pipes
        .iter()
        .map(|p| MethodRun {
            scenario: name.clone(),
            method: p.method,
            dedup: resolved.dedup,
            hierarchy_bytes: p.hierarchy_bytes(),
            frames: Vec::with_capacity(frames),
        })
        .collect();
    let mut buffers = PoseBuffers::new(character);
    let progress = std::io::stderr().is_terminal();
    let clip = resolved.clip();
    for k in 0..frames {
        let placement = resolved.placement_at(k).to_homogeneous();
        let (base, skin_ms) = pose_frame(
            &mut buffers,
            character,
            clip,
            resolved.time_at(k),
            &placement,
            resolved.skinning,
        );
        for (p, r) in pipes.iter_mut().zip(&mut runs) {
            let mut c = p.detect(&buffers, &base, &character.mesh, env);
            c.time.skinning_ms = skin_ms;
            r.frames.push(FrameRecord::new(k, &c, &p.pairs));
        }
        if progress {
            eprint!("\r{name}: frame {}/{frames}", k + 1);
        }
    }
    if progress {
        eprintln!();
    }
    let summaries: Vec<Summary> = runs.iter().map(MethodRun::summary).collect();
    if let Some(path) = &args.json {
        let text = match runs.as_slice() {
            [one] => serde_json::to_string(one)?,
            _ => serde_json::to_string(&serde_json::json!({ "scenario": name, "runs": runs }))?,
        };
        std::fs::write(path, text)
            .with_context(|| format!("{}: cannot write the report", path.display()))?;
    }
    let mut out = format!(
        "{name}: {} ({} vertices) in {} ({} triangles), {frames} frames at {} fps, {} skinning{}\n",
        character.name,
        character.mesh.vertex_count(),
        resolved.environment.name,
        env.triangle_count(),
        resolved.fps,
        match resolved.skinning {
            cornertree::character::SkinningModel::Linear => "linear blend",
            cornertree::character::SkinningModel::Paper => "paper-model",
        },
        if resolved.dedup {
            ", edge de-duplication on"
        } else {
            ""
        },
    );
    if let Some(g) = &resolved.gap {
        out += &format!(
            "placement: gap {:.4} m from {} (asked {:.4} m; closest at frame {})\n",
            g.achieved, g.surface, g.metres, g.closest_frame
        );
    }
    out += &SummaryTable(&summaries).to_string();
    if let Some(path) = &args.json {
        out += &format!("report: {}\n", path.display());
    }
    Ok(out)
}
