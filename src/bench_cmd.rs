//! `cornertree bench`: per-frame cost of each method against the baseline a
//! Rust user would write with parry3d, measured in one run (command-line
//! plumbing; the work is in the library).
//!
//! Per frame the character is posed once (joint matrices), which every side
//! needs and is charged with. Each method then runs its `detect` (refit on
//! demand, traversal, skinning only the vertices its narrow phase reads, the
//! narrow phase). The baseline skins every vertex (parry's BVH needs them
//! all), moves parry's character `TriMesh` (`update_vertices`, which refits
//! its BVH), walks `Bvh::leaf_pairs` against the environment's and runs
//! parry3d's `intersection_test` on every candidate. Frames are interleaved,
//! so machine noise hits every side alike; each side's time per frame is the
//! median over frames.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::Context;
use cornertree::character::PoseBuffers;
use cornertree::pipeline::Method;
use cornertree::pipeline::driver::{Pipeline, PipelineOptions};
use cornertree::scenario::{Resolved, open_scenario, scenario_name};
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
pub struct MethodBench {
    pub method: Method,
    pub ms_per_frame: f64,
    pub speedup_vs_parry: f64,
    pub operations_per_frame: f64,
    /// Median of the method's own skinning (the vertices it tested).
    pub skinning_ms_per_frame: f64,
    pub skinned_vertices_per_frame: f64,
    /// Frames whose pairs differ from the baseline's.
    pub frames_with_other_pairs_than_parry: usize,
}

#[derive(Serialize)]
pub struct Bench {
    pub scenario: String,
    pub frames: usize,
    pub dedup: bool,
    pub environment_vertices: usize,
    pub parry_ms_per_frame: f64,
    /// Posing (joint matrices), in every side's time.
    pub pose_ms_per_frame: f64,
    /// Skinning every vertex, in the baseline's time.
    pub skinning_all_ms_per_frame: f64,
    pub vertices: usize,
    pub methods: Vec<MethodBench>,
}

fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return 0.0;
    }
    v.sort_by(|a, b| a.total_cmp(b));
    v[v.len() / 2]
}

/// Plays `frames` frames of a resolved scenario through `methods` and the
/// parry3d baseline, interleaved, and returns the medians. `dedup` keeps the
/// scenario's edge de-duplication (off otherwise). Ticks `progress` per frame.
pub fn measure(
    resolved: &Resolved,
    name: &str,
    methods: &[Method],
    frames: usize,
    dedup: bool,
    progress: &indicatif::ProgressBar,
) -> anyhow::Result<Bench> {
    if resolved.characters.len() > 1 || !resolved.objects.is_empty() {
        anyhow::bail!(
            "{name}: bench measures one character in a static room; worlds with several \
             characters or moving objects are not benchmarked yet (use `compare` for their counters and times)"
        );
    }
    let first = resolved.first();
    let dedup = dedup && resolved.dedup;
    let options = PipelineOptions {
        dedup,
        ..resolved.pipeline_options(first)
    };
    let character = &first.character;
    let env = &resolved.environment.mesh;
    let mut pipes: Vec<Pipeline> = methods
        .iter()
        .map(|&m| {
            let mut p = Pipeline::new(character, env, m, options);
            // Refit is timed with traversal: splitting it costs time.
            p.set_refit_timing(false);
            p
        })
        .collect();
    let mut parry =
        ParryReference::new(env, character.mesh.indices()).context("building parry's meshes")?;
    let mut buffers = PoseBuffers::new(character);
    let mut parry_pairs = Vec::new();
    let mut pose_ms = Vec::with_capacity(frames);
    let mut skin_all_ms = Vec::with_capacity(frames);
    let mut parry_ms = Vec::with_capacity(frames);
    let mut method_ms = vec![Vec::with_capacity(frames); pipes.len()];
    let mut method_skin_ms = vec![Vec::with_capacity(frames); pipes.len()];
    let mut ops = vec![0u64; pipes.len()];
    let mut skinned = vec![0u64; pipes.len()];
    let mut differ = vec![0usize; pipes.len()];
    for k in 0..frames {
        let (pose, skin_all) = first.pose_and_skin_frame(&mut buffers, k);
        pose_ms.push(pose);
        skin_all_ms.push(skin_all);
        let t0 = Instant::now();
        parry.update(&buffers.positions)?;
        parry.pairs_f32(&mut parry_pairs);
        parry_ms.push(pose + skin_all + t0.elapsed().as_secs_f64() * 1e3);
        for (i, p) in pipes.iter_mut().enumerate() {
            let mut c = p.detect(&buffers, character, env);
            c.time.pose_ms = pose;
            method_ms[i].push(c.time.total_ms());
            method_skin_ms[i].push(c.time.skinning_ms);
            ops[i] += c.operations();
            skinned[i] += c.skinned_vertices;
            if p.pairs != parry_pairs {
                differ[i] += 1;
            }
        }
        progress.inc(1);
    }
    let parry_median = median(&mut parry_ms);
    let result = Bench {
        scenario: name.to_string(),
        environment_vertices: env.positions().len(),
        frames,
        dedup,
        parry_ms_per_frame: parry_median,
        pose_ms_per_frame: median(&mut pose_ms),
        skinning_all_ms_per_frame: median(&mut skin_all_ms),
        vertices: character.mesh.positions().len(),
        methods: pipes
            .iter()
            .zip(method_ms.iter_mut().zip(&mut method_skin_ms))
            .enumerate()
            .map(|(i, (p, (ms, skin_ms)))| {
                let m = median(ms);
                let per_frame = |n: u64| n as f64 / frames.max(1) as f64;
                MethodBench {
                    method: p.method,
                    ms_per_frame: m,
                    speedup_vs_parry: if m > 0.0 { parry_median / m } else { 0.0 },
                    operations_per_frame: per_frame(ops[i]),
                    skinning_ms_per_frame: median(skin_ms),
                    skinned_vertices_per_frame: per_frame(skinned[i]),
                    frames_with_other_pairs_than_parry: differ[i],
                }
            })
            .collect(),
    };
    Ok(result)
}

pub fn bench(args: BenchArgs) -> anyhow::Result<String> {
    let resolved = open_scenario(&args.scenario)?;
    let methods = if args.methods.is_empty() {
        Method::ALL.to_vec()
    } else {
        args.methods.clone()
    };
    let frames = args.frames.map_or(resolved.frames(), |f| f as usize);
    let progress = indicatif::ProgressBar::new(frames as u64);
    let result = measure(
        &resolved,
        &scenario_name(&args.scenario),
        &methods,
        frames,
        args.dedup,
        &progress,
    )?;
    progress.finish_and_clear();
    if let Some(path) = &args.json {
        std::fs::write(path, serde_json::to_string(&result)?)
            .with_context(|| format!("{}: cannot write the report", path.display()))?;
    }
    let mut out = format!(
        "{}: {} frames, de-duplication {}, median ms per frame; every row includes posing \
         ({:.3} ms); parry skins all {} vertices ({:.3} ms), each method only those it tests\n",
        result.scenario,
        result.frames,
        if result.dedup { "on" } else { "off" },
        result.pose_ms_per_frame,
        result.vertices,
        result.skinning_all_ms_per_frame,
    );
    out += &format!(
        "{:<26}{:>12}{:>12}{:>16}{:>12}{:>22}\n",
        "", "ms/frame", "vs parry", "operations", "skinned", "frames ≠ parry pairs"
    );
    out += &format!(
        "{:<26}{:>12.3}{:>12}{:>16}{:>12}{:>22}\n",
        "parry3d baseline", result.parry_ms_per_frame, "1.00×", "-", result.vertices, "-"
    );
    for m in &result.methods {
        out += &format!(
            "{:<26}{:>12.3}{:>11.2}×{:>16.0}{:>12.0}{:>22}\n",
            m.method.name(),
            m.ms_per_frame,
            m.speedup_vs_parry,
            m.operations_per_frame,
            m.skinned_vertices_per_frame,
            m.frames_with_other_pairs_than_parry
        );
    }
    if let Some(path) = &args.json {
        out += &format!("report: {}\n", path.display());
    }
    Ok(out)
}
