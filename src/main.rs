//! `cornertree` command-line front: parse, call into the library, print.

use std::process::ExitCode;

mod bench_cmd;
mod ccd_queries_cmd;
mod kernels_cmd;
mod run_cmd;
mod scaling_cmd;
mod study_cmd;

use anyhow::Context;
use clap::{Parser, Subcommand};
use cornertree::character::{Character, SkinningModel, generate_humanoid};
use cornertree::io::{CharacterSource, load_character, load_static_mesh};
use cornertree::mesh::TriMesh;
use cornertree::record::target::RecordingTarget;
use cornertree::report::animate::{AnimateOptions, RefitReport, animate};
use cornertree::report::inspect::{InspectOptions, inspect_mesh};
use cornertree::sphere_tree::BuildParams;

/// Research workbench for real-time collision detection of animated virtual
/// characters with sphere trees and corner-trees.
#[derive(Parser)]
#[command(name = "cornertree", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Load a mesh or character, de-duplicate its edges, build and validate its
    /// sphere tree, and print what came out. With --animate, play a clip and
    /// check that refit spheres hold the skinned vertices.
    Inspect(InspectArgs),
    /// Print Table 1 (spheres per level of corner-trees and quaternary trees,
    /// counted on trees built over a real triangle) and, for the museum and the
    /// living room, every method's environment hierarchy: nodes and bytes.
    Tables(TablesArgs),
    /// Play a scenario through each method: per frame, pose and skin the
    /// character, refit its spheres on demand while traversing the
    /// environment's tree, run the narrow phase, and count tests, operations,
    /// refits and time; print the summary table (maximum and mean per frame).
    Run(run_cmd::RunArgs),
    /// Play a scenario through every method on the same frames against the
    /// ground truth (exact pairs on parry's broad phase) and print one table
    /// like the paper's Tables 2-3 plus precision and recall. No recording.
    Compare(run_cmd::CompareArgs),
    /// Measure each method's cost per frame against the baseline a Rust user
    /// would write with parry3d (a TriMesh moved every frame, BVH leaf pairs
    /// against the environment, parry's triangle test), in one run, and print
    /// the ratios. De-duplication is off unless --dedup.
    Bench(bench_cmd::BenchArgs),
    /// Per-frame cost against character size (generated humanoids of about
    /// 3k, 10k, 44k and 100k vertices) and against room size (the base room
    /// re-tessellated to about 10k, 133k and 500k vertices), each method
    /// beside the parry3d baseline as in `bench`; prints the markdown tables
    /// of docs/performance.md.
    Scaling(scaling_cmd::ScalingArgs),
    /// Write recordings that reproduce the paper's Figures 1-3: a triangle left
    /// out by edge de-duplication among its three neighbours; a big triangle's
    /// enclosing sphere and its four sub-spheres; a corner-tree level by level.
    Figures(FiguresArgs),
    /// For each kernel of the paper's operation model (sphere-sphere,
    /// plane-sphere plain and prepared, the Tropp and the edge-crossing
    /// triangle-triangle tests), run on a fixed seeded mix of disjoint,
    /// near-touching and intersecting inputs: the operations the paper
    /// charges, the operations really executed (arithmetic and comparisons,
    /// counted by a counting number type: mean, min, max) and nanoseconds per
    /// test. Then the continuous tests (vertex-face, edge-edge,
    /// triangle-triangle over a step of linear motion; docs/ccd.md) on up to
    /// 5,000 moving pairs, which the paper charges nothing. Timings are only
    /// meaningful in a release build (`cargo run --release -- kernels`).
    Kernels(kernels_cmd::KernelsArgs),
    /// The experiment behind docs/results.md: when does the plane-sphere
    /// method read as §5 writes it (Algorithm 1 where a character leaf meets
    /// a corner-tree leaf) need as few tests as Tables 2-3 report? Plays each
    /// base scenario with one condition changed at a time: where the
    /// character walks along the big surface, how the surface is tessellated,
    /// the big-triangle threshold, edge de-duplication, the gap; prints the
    /// maximum tests and operations per frame and the largest corner-tree
    /// leaf a character leaf met, beside the paper's figures.
    PlaneSphereStudy(study_cmd::StudyArgs),
    /// Continuous collision detection on query files with exact answers
    /// (the format of ../shared/ccd-queries: a vertex and a triangle, or two
    /// edges, every point moving on a straight line over one step): runs the
    /// conservative vertex-face and edge-edge kernels on every query and
    /// prints, per file, per kind and in total, the queries, the positives
    /// (exact answer "contact"), false negatives (contacts missed: there
    /// should be none), false positives (contact answered, none exact) and
    /// nanoseconds per query (release builds only). Each PATH is a CSV file
    /// or a directory walked for *.csv; a file's kind is its parent folder's
    /// name unless --kind is given. A malformed file stops with one line
    /// naming the file and row.
    CcdQueries(ccd_queries_cmd::CcdQueriesArgs),
}

#[derive(clap::Args)]
struct FiguresArgs {
    /// Directory to write figure1_dedup.rrd, figure2_sphere_division.rrd and
    /// figure3_corner_tree.rrd into (created if needed).
    #[arg(long, default_value = "recordings/figures")]
    out: std::path::PathBuf,
}

#[derive(clap::Args)]
struct TablesArgs {
    /// Print one JSON object on stdout instead of the tables.
    #[arg(long)]
    json: bool,
    /// A triangle is big when its longest edge exceeds this many metres; big
    /// triangles get sphere division, quaternary or corner-tree hierarchies.
    #[arg(long, default_value_t = cornertree::pipeline::DEFAULT_THRESHOLD, value_parser = parse_positive)]
    threshold: f32,
    /// Seed of the generated rooms.
    #[arg(long, default_value_t = 0)]
    seed: u64,
    /// Also cost a static glTF scene of your own (every mesh, node transforms
    /// applied; degenerate triangles are reported and left out).
    #[arg(long)]
    scene: Option<std::path::PathBuf>,
}

#[derive(clap::Args)]
struct InspectArgs {
    /// A glTF 2.0 file (.gltf or .glb), or a generated character:
    /// `generated:humanoid` or `generated:humanoid?vertices=N&seed=S`
    /// (default 44345 vertices, the paper's avatar). Without --animate every
    /// triangle is taken in its static pose (skinned meshes in bind pose).
    source: CharacterSource,
    /// Print one JSON object on stdout instead of the text summary.
    #[arg(long)]
    json: bool,
    /// Keep every triangle (turn edge de-duplication, paper §4, off).
    #[arg(long)]
    no_dedup: bool,
    /// Collapse a child sphere into its parent when its radius exceeds this
    /// fraction of the parent's (1 keeps the binary tree).
    #[arg(long, default_value_t = BuildParams::default().collapse_ratio, value_parser = parse_positive)]
    collapse_ratio: f32,
    /// Play a clip: skin every frame, refit every sphere of the character's
    /// tree, check containment and tightness, time the refit strategies.
    #[arg(long)]
    animate: bool,
    /// Clip to play (default: the first).
    #[arg(long, requires = "animate")]
    clip: Option<String>,
    /// Frames per second to sample the clip at.
    #[arg(long, default_value_t = 30.0, requires = "animate", value_parser = parse_positive)]
    fps: f32,
    /// Skinning model: glTF linear blend skinning, or the paper's one-joint model.
    #[arg(long, value_enum, default_value = "linear", requires = "animate")]
    skinning: SkinningArg,
    /// Measure tightness (a minimal sphere per node) and the cost of a rebuild
    /// from scratch on every N-th frame; 0 picks about ten frames over the clip.
    #[arg(long, default_value_t = 0, requires = "animate")]
    sample_every: usize,
    /// Place the character at this translation (metres) on every frame, e.g.
    /// 10000,0,0 to check refit 10 km from the origin.
    #[arg(long, value_name = "X,Y,Z", default_value = "0,0,0", requires = "animate",
          allow_hyphen_values = true, value_parser = parse_offset)]
    offset: [f32; 3],
}

#[derive(Clone, Copy, clap::ValueEnum)]
enum SkinningArg {
    Linear,
    Paper,
}

impl From<SkinningArg> for SkinningModel {
    fn from(s: SkinningArg) -> Self {
        match s {
            SkinningArg::Linear => SkinningModel::Linear,
            SkinningArg::Paper => SkinningModel::Paper,
        }
    }
}

fn parse_positive(s: &str) -> Result<f32, String> {
    let r: f32 = s.parse().map_err(|e| format!("{e}"))?;
    if r.is_finite() && r > 0.0 {
        Ok(r)
    } else {
        Err("must be a positive number".into())
    }
}

/// Three finite numbers separated by commas.
fn parse_offset(s: &str) -> Result<[f32; 3], String> {
    let parts: Vec<&str> = s.split(',').collect();
    if parts.len() != 3 {
        return Err(format!(
            "expected three numbers X,Y,Z separated by commas, got {} value(s)",
            parts.len()
        ));
    }
    let mut out = [0.0f32; 3];
    for (o, (p, axis)) in out.iter_mut().zip(parts.iter().zip(["X", "Y", "Z"])) {
        let x: f32 = p
            .trim()
            .parse()
            .map_err(|e| format!("{axis} = {:?}: {e}", p.trim()))?;
        if !x.is_finite() {
            return Err(format!("{axis} = {:?} is not a finite number", p.trim()));
        }
        *o = x;
    }
    Ok(out)
}

fn load(source: &CharacterSource) -> anyhow::Result<Character> {
    match source {
        CharacterSource::File(path) => {
            let (c, report) = load_character(path)?;
            let p = path.display();
            for s in &report.skipped {
                eprintln!("note: {p}: skipped {s}");
            }
            for node in &report.unskinned_meshes {
                eprintln!("note: {p}: node {node}: mesh left out (not skinned)");
            }
            if !report.skipped_channels.is_empty() {
                eprintln!(
                    "note: {p}: {} animation channels not used (first: {})",
                    report.skipped_channels.len(),
                    report.skipped_channels[0]
                );
            }
            for n in &report.notes {
                eprintln!("note: {p}: {n}");
            }
            Ok(c)
        }
        CharacterSource::Humanoid(p) => {
            Ok(generate_humanoid(p).with_context(|| source.to_string())?)
        }
    }
}

fn static_mesh(source: &CharacterSource) -> anyhow::Result<TriMesh> {
    match source {
        CharacterSource::File(path) => {
            let (mesh, report) = load_static_mesh(path)?;
            for s in &report.skipped {
                eprintln!("note: {}: skipped {s}", path.display());
            }
            for n in &report.notes {
                eprintln!("note: {}: {n}", path.display());
            }
            Ok(mesh)
        }
        CharacterSource::Humanoid(_) => Ok(load(source)?.mesh),
    }
}

fn inspect(args: InspectArgs) -> anyhow::Result<()> {
    let name = args.source.to_string();
    let options = InspectOptions {
        dedup: !args.no_dedup,
        build: BuildParams {
            collapse_ratio: args.collapse_ratio,
        },
    };
    // With --animate the character is loaded once and its bind mesh inspected.
    let character = if args.animate {
        Some(load(&args.source)?)
    } else {
        None
    };
    let loaded;
    let mesh = match &character {
        Some(c) => &c.mesh,
        None => {
            loaded = static_mesh(&args.source)?;
            &loaded
        }
    };
    let (report, _tree) = inspect_mesh(&name, mesh, options)
        .with_context(|| format!("{name}: sphere tree failed validation"))?;
    let mut json = serde_json::to_value(&report)?;
    let mut out = String::new();
    if let Some(character) = &character {
        let opts = AnimateOptions {
            model: args.skinning.into(),
            clip: args.clip.clone(),
            fps: args.fps,
            dedup: options.dedup,
            build: options.build,
            sample_every: args.sample_every,
            offset: args.offset,
            ..AnimateOptions::default()
        };
        let refit = animate(character, &opts).with_context(|| name.clone())?;
        json["joints"] = character.skeleton.len().into();
        json["clips"] = character
            .clips
            .iter()
            .map(|c| c.name.clone())
            .collect::<Vec<_>>()
            .into();
        json["refit"] = serde_json::to_value(&refit)?;
        if !args.json {
            out = format!("{report}{}", refit_text(character, &refit));
        }
    } else if !args.json {
        out = report.to_string();
    }
    if args.json {
        out = serde_json::to_string(&json)? + "\n";
    }
    emit(&out)
}

fn tables(args: TablesArgs) -> anyhow::Result<()> {
    use cornertree::environment::{living_room, museum};
    let (m, l) = (museum(args.seed), living_room(args.seed));
    let scene = match &args.scene {
        Some(path) => {
            let (env, report) = cornertree::environment::load_scene(path)?;
            if report.degenerate_removed > 0 {
                eprintln!(
                    "note: {}: {} degenerate triangles left out (first: {:?})",
                    path.display(),
                    report.degenerate_removed,
                    report.first_degenerate
                );
            }
            Some(env)
        }
        None => None,
    };
    let mut rooms = vec![("museum", &m), ("living_room", &l)];
    if let Some(env) = &scene {
        rooms.push(("scene", env));
    }
    let report = cornertree::report::tables::tables(&rooms, args.threshold, BuildParams::default());
    if args.json {
        emit(&(serde_json::to_string(&report)? + "\n"))
    } else {
        emit(&report.to_string())
    }
}

/// Writes to stdout; a reader that went away (`| head`) ends the program quietly.
fn emit(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    let mut stdout = std::io::stdout().lock();
    match stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
    {
        Err(e) if e.kind() == std::io::ErrorKind::BrokenPipe => Ok(()),
        other => Ok(other?),
    }
}

fn refit_text(c: &Character, r: &RefitReport) -> String {
    use std::fmt::Write;
    let clips: Vec<String> = c
        .clips
        .iter()
        .map(|k| format!("{} ({:.2} s)", k.name, k.duration()))
        .collect();
    let mut s = String::new();
    let _ = writeln!(s, "  joints                 {:>10}", c.skeleton.len());
    let _ = writeln!(s, "  clips                  {}", clips.join(", "));
    let _ = writeln!(
        s,
        "  refit: clip {:?}, {:?} skinning, {} frames at {} fps, {} nodes",
        r.clip, r.model, r.frames, r.fps, r.nodes
    );
    let [x, y, z] = r.offset;
    let _ = writeln!(
        s,
        "    placed at            ({x}, {y}, {z}) m; rounding margin {:.3e} per unit of joint reach",
        r.rounding_coefficient
    );
    let _ = writeln!(
        s,
        "    containment          {} violations in {} checks (tolerance {:.3e}, worst excess {:.3e})",
        r.violations, r.checks, r.tolerance, r.worst_excess
    );
    let _ = writeln!(
        s,
        "    tightness            mean {:.3}, max {:.3} (refit radius / minimal radius, {} sampled frames)",
        r.tightness_mean, r.tightness_max, r.sampled_frames
    );
    let _ = writeln!(
        s,
        "    per frame            skinning {:.3} ms",
        r.skinning_ms_per_frame
    );
    let _ = writeln!(
        s,
        "                         full refit {:.3} ms",
        r.full_refit_ms_per_frame
    );
    let _ = writeln!(
        s,
        "                         on-demand refit + traversal vs a floor {:.3} ms ({:.0} nodes refit)",
        r.on_demand_ms_per_frame, r.on_demand_refits_mean
    );
    let _ = writeln!(
        s,
        "                         rebuild from scratch {:.3} ms",
        r.rebuild_ms_per_frame
    );
    s
}

fn figures(args: FiguresArgs) -> anyhow::Result<()> {
    let written = cornertree::record::figures::write_figures(&args.out)?;
    let mut out = String::new();
    for f in &written {
        out += &format!("{}: {}\n", f.name, f.path.display());
    }
    emit(&out)
}

fn main() -> ExitCode {
    use clap::{CommandFactory, FromArgMatches};
    let matches = Cli::command().get_matches();
    let cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    let result = match cli.command {
        Command::Inspect(args) => inspect(args),
        Command::Tables(args) => tables(args),
        Command::Run(args) => {
            let sub = matches
                .subcommand_matches("run")
                .expect("the run subcommand was parsed");
            let target = run_cmd::recording_target(&args, sub);
            // With --stdout the recording owns standard output; the summary
            // goes to standard error.
            let to_stderr = matches!(target, RecordingTarget::Rerun(_, true));
            run_cmd::run(args, target).and_then(|out| {
                if to_stderr {
                    eprint!("{out}");
                    Ok(())
                } else {
                    emit(&out)
                }
            })
        }
        Command::Figures(args) => figures(args),
        Command::Bench(args) => bench_cmd::bench(args).and_then(|out| emit(&out)),
        Command::Scaling(args) => scaling_cmd::scaling(args).and_then(|out| emit(&out)),
        Command::Compare(args) => run_cmd::compare(args).and_then(|out| emit(&out)),
        Command::Kernels(args) => kernels_cmd::kernels(args).and_then(|out| emit(&out)),
        Command::PlaneSphereStudy(args) => study_cmd::study(args).and_then(|out| emit(&out)),
        Command::CcdQueries(args) => ccd_queries_cmd::ccd_queries(args).and_then(|out| emit(&out)),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            // One line: the error and its causes joined by ": ".
            eprintln!("error: {e:#}");
            ExitCode::FAILURE
        }
    }
}
