//! `cornertree bench`: per-frame cost of each method against the baseline a
//! Rust user would write with parry3d, measured in one run (command-line
//! plumbing; the work is in the library).
//!
//! Per frame the character is posed and skinned once; then each method runs
//! its `detect` (refit on demand, traversal, narrow phase), and the baseline
//! moves parry's character `TriMesh` (`update_vertices`, which refits its
//! BVH), walks `Bvh::leaf_pairs` against the environment's and runs parry3d's
//! `intersection_test` on every candidate. Skinning is common to both and is
//! added to both. Frames are interleaved, so machine noise hits every side
//! alike; each side's time per frame is the median over frames.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use cornertree::character::PoseBuffers;
use cornertree::pipeline::Method;
use cornertree::pipeline::driver::{Pipeline, PipelineOptions};
use cornertree::scenario::{open_scenario, scenario_name};
use cornertree::truth::ParryReference;
use serde::Serialize;

#[derive(clap::Args)]
pub struct BenchArgs {
    /// A scenario file (TOML; see docs/scenarios.md and scenarios/).
    pub scenario: PathBuf,
    /// Measure only this method (repeat for several); default: all.
    #[arg(long = "method", value_enum)]
    pub methods: Vec<Method>,
    /// Play this many frames instead of the scenario's.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Write the result as JSON: `parry_ms_per_frame` and `methods`, an array
    /// of `{method, ms_per_frame, speedup_vs_parry, ...}`.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Keep the scenario's edge de-duplication (by default it is turned off,
    /// so the triangle-triangle methods find exactly parry's pairs).
    #[arg(long)]
    pub dedup: bool,
}

#[derive(Serialize)]
struct MethodBench {
    method: Method,
    ms_per_frame: f64,
    speedup_vs_parry: f64,
    operations_per_frame: f64,
    /// Frames whose pairs differ from the baseline's.
    frames_with_other_pairs_than_parry: usize,
}

#[derive(Serialize)]
struct Bench {
    scenario: String,
    frames: usize,
    dedup: bool,
    parry_ms_per_frame: f64,
    skinning_ms_per_frame: f64,
    methods: Vec<MethodBench>,
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

pub fn bench(args: BenchArgs) -> anyhow::Result<String> {
    let resolved = open_scenario(&args.scenario)?;
    let methods = if args.methods.is_empty() {
        Method::ALL.to_vec()
    } else {
        args.methods.clone()
    };
    let dedup = args.dedup && resolved.dedup;
    let frames = args.frames.map_or(resolved.frames(), |f| f as usize);
    let name = scenario_name(&args.scenario);
    let options = PipelineOptions {
        dedup,
        ..resolved.pipeline_options()
    };
    let character = &resolved.character;
    let env = &resolved.environment.mesh;
    let mut pipes: Vec<Pipeline> = methods
        .iter()
        .map(|&m| Pipeline::new(character, env, m, options))
        .collect();
    let mut parry =
        ParryReference::new(env, character.mesh.indices()).context("building parry's meshes")?;
    let progress = indicatif::ProgressBar::new(frames as u64);
    let mut buffers = PoseBuffers::new(character);
    let mut parry_pairs = Vec::new();
    let mut skin_ms = Vec::with_capacity(frames);
    let mut parry_ms = Vec::with_capacity(frames);
    let mut method_ms = vec![Vec::with_capacity(frames); pipes.len()];
    let mut ops = vec![0u64; pipes.len()];
    let mut differ = vec![0usize; pipes.len()];
    for k in 0..frames {
        let (base, skin) = resolved.pose_frame(&mut buffers, k);
        skin_ms.push(skin);
        let t0 = Instant::now();
        parry.update(&buffers.positions)?;
        parry.pairs_f32(&mut parry_pairs);
        parry_ms.push(skin + t0.elapsed().as_secs_f64() * 1e3);
        for (i, p) in pipes.iter_mut().enumerate() {
            let c = p.detect(&buffers, &base, &character.mesh, env);
            method_ms[i].push(skin + c.time.total_ms());
            ops[i] += c.operations();
            if p.pairs != parry_pairs {
                differ[i] += 1;
            }
        }
        progress.inc(1);
    }
    progress.finish_and_clear();
    let parry_median = median(&mut parry_ms);
    let result = Bench {
        scenario: name.clone(),
        frames,
        dedup,
        parry_ms_per_frame: parry_median,
        skinning_ms_per_frame: median(&mut skin_ms),
        methods: pipes
            .iter()
            .zip(&mut method_ms)
            .enumerate()
            .map(|(i, (p, ms))| {
                let m = median(ms);
                MethodBench {
                    method: p.method,
                    ms_per_frame: m,
                    speedup_vs_parry: if m > 0.0 { parry_median / m } else { 0.0 },
                    operations_per_frame: ops[i] as f64 / frames.max(1) as f64,
                    frames_with_other_pairs_than_parry: differ[i],
                }
            })
            .collect(),
    };
    if let Some(path) = &args.json {
        std::fs::write(path, serde_json::to_string(&result)?)
            .with_context(|| format!("{}: cannot write the report", path.display()))?;
    }
    let mut out = format!(
        "{name}: {frames} frames, de-duplication {}, median ms per frame (skinning {:.3} ms included)\n",
        if dedup { "on" } else { "off" },
        result.skinning_ms_per_frame
    );
    out += &format!(
        "{:<26}{:>12}{:>12}{:>16}{:>22}\n",
        "", "ms/frame", "vs parry", "operations", "frames ≠ parry pairs"
    );
    out += &format!(
        "{:<26}{:>12.3}{:>12}{:>16}{:>22}\n",
        "parry3d baseline", parry_median, "1.00×", "-", "-"
    );
    for m in &result.methods {
        out += &format!(
            "{:<26}{:>12.3}{:>11.2}×{:>16.0}{:>22}\n",
            m.method.name(),
            m.ms_per_frame,
            m.speedup_vs_parry,
            m.operations_per_frame,
            m.frames_with_other_pairs_than_parry
        );
    }
    if let Some(path) = &args.json {
        out += &format!("report: {}\n", path.display());
    }
    Ok(out)
}
