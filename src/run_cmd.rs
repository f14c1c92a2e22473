//! `cornertree run`: a scenario through every chosen method, frame by frame,
//! recorded to Rerun. (Kept beside `main.rs`: command-line plumbing only; the
//! work is in the library.)

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Context;
use clap::parser::ValueSource;
use cornertree::character::SkinningModel;
use cornertree::pipeline::driver::Pipeline;
use cornertree::pipeline::{LeafTest, Method};
use cornertree::record::blueprint::run_blueprint;
use cornertree::record::layout;
use cornertree::record::target::RecordingTarget;
use cornertree::record::{RecordOptions, RunRecorder, SceneInfo};
use cornertree::report::run::TruthRecord;
use cornertree::report::run::{
    FrameRecord, MethodRun, Summary, SummaryBuilder, SummaryTable, WorldFrameRecord,
};
use cornertree::scenario::budget::RunBudget;
use cornertree::scenario::ranges::MAX_FRAMES;
use cornertree::scenario::{Resolved, RunLimits, open_scenario_within, scenario_name};
use cornertree::truth::WorldTruth;
use cornertree::truth::{FrameTruth, MethodContext};
use cornertree::world::World;

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
    /// Turn edge de-duplication off, whatever the scenario says.
    #[arg(long)]
    pub no_dedup: bool,
    /// Skinning model, whatever the scenario says: `paper` (§3's one-joint
    /// model) or `linear` (glTF linear blend skinning).
    #[arg(long, value_enum)]
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
    #[command(flatten)]
    pub rerun: rerun::clap::RerunArgs,
}

/// `--memory-budget` by default: [`RunLimits::default`] in GiB.
const DEFAULT_BUDGET_GIB: f64 = 4.0;

/// `--memory-budget` as limits.
fn run_limits(gib: f64) -> anyhow::Result<RunLimits> {
    if !(gib.is_finite() && gib > 0.0 && gib <= 1e6) {
        anyhow::bail!("--memory-budget: must be GiB from above 0 to 1e6, not {gib}");
    }
    Ok(RunLimits {
        max_bytes: (gib * f64::from(1u32 << 30)) as usize,
    })
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

/// Set by Ctrl-C: the frame loop stops after the current frame.
fn interrupt_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let f = flag.clone();
    // A second handler cannot be installed (only one run per process); a run
    // without it still works, Ctrl-C then ends it the default way.
    let _ = ctrlc::set_handler(move || f.store(true, Ordering::SeqCst));
    flag
}

fn scenario_markdown(name: &str, r: &Resolved, frames: usize, method: Method) -> String {
    let first = r.first();
    let mut s = format!(
        "## {name}: {}\n\n| | |\n|---|---|\n| character | {} ({} vertices, {} triangles) |\n\
         | environment | {} ({} triangles) |\n| frames | {frames} at {} fps |\n\
         | skinning | {:?} |\n| edge de-duplication | {} |\n| big-triangle threshold | {} m |\n",
        method.name(),
        first.character.name,
        first.character.mesh.vertex_count(),
        first.character.mesh.triangle_count(),
        r.environment.name,
        r.environment.mesh.triangle_count(),
        r.fps,
        first.skinning,
        if r.dedup { "on" } else { "off" },
        r.threshold,
    );
    if let Some(g) = &first.gap {
        s += &format!(
            "| placement | gap {:.4} m from {} (closest at frame {}) |\n",
            g.achieved, g.surface, g.closest_frame
        );
    }
    s
}

/// Deletes files of recordings that did not finish (an error, not Ctrl-C).
fn discard(paths: &[PathBuf]) {
    for p in paths {
        let _ = std::fs::remove_file(p);
    }
}

/// `cornertree compare`: every method on the same frames, no recording.
#[derive(clap::Args)]
pub struct CompareArgs {
    /// A scenario file (TOML; see docs/scenarios.md and scenarios/).
    pub scenario: PathBuf,
    /// Play this many frames instead of the scenario's.
    #[arg(long, value_parser = clap::value_parser!(u64).range(1..))]
    pub frames: Option<u64>,
    /// Write every method's per-frame report as JSON (as `run --json`).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Print the table as Markdown.
    #[arg(long)]
    pub markdown: bool,
    /// Turn edge de-duplication off, whatever the scenario says.
    #[arg(long)]
    pub no_dedup: bool,
    /// Skinning model, whatever the scenario says: `paper` (§3's one-joint
    /// model) or `linear` (glTF linear blend skinning).
    #[arg(long, value_enum)]
    pub skinning: Option<SkinningModel>,
    /// Most memory the scenario may take, in GiB (as `run --memory-budget`).
    #[arg(long, value_name = "GIB", default_value_t = DEFAULT_BUDGET_GIB)]
    pub memory_budget: f64,
}

/// How the summary table is printed.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Text,
    Markdown,
}

pub fn compare(args: CompareArgs) -> anyhow::Result<String> {
    use clap::{Args, FromArgMatches};
    let no_rerun = rerun::clap::RerunArgs::from_arg_matches(
        &rerun::clap::RerunArgs::augment_args(clap::Command::new("compare"))
            .get_matches_from(["compare"]),
    )?;
    let run_args = RunArgs {
        scenario: args.scenario,
        methods: Method::ALL.to_vec(),
        frames: args.frames,
        json: args.json,
        no_dedup: args.no_dedup,
        skinning: args.skinning,
        no_truth: false,
        dump_frame: None,
        no_record: true,
        threads: 0,
        memory_budget: args.memory_budget,
        rerun: no_rerun,
    };
    let style = if args.markdown {
        Style::Markdown
    } else {
        Style::Text
    };
    play(run_args, RecordingTarget::None, style)
}

pub fn run(args: RunArgs, target: RecordingTarget) -> anyhow::Result<String> {
    play(args, target, Style::Text)
}

fn play(args: RunArgs, target: RecordingTarget, style: Style) -> anyhow::Result<String> {
    let started = std::time::Instant::now();
    // Everything that can be wrong with the input fails here, before any file
    // is created.
    let limits = run_limits(args.memory_budget)?;
    if let Some(f) = args.frames
        && f > MAX_FRAMES
    {
        anyhow::bail!("--frames: must be a whole number from 1 to {MAX_FRAMES}, not {f}");
    }
    let mut resolved = open_scenario_within(&args.scenario, &limits, |s| {
        if let Some(model) = args.skinning {
            for c in &mut s.characters {
                c.character.skinning = model;
            }
        }
        if !args.methods.is_empty() {
            s.methods = args.methods.clone();
        }
    })?;
    if args.no_dedup {
        resolved.dedup = false;
    }
    let is_world = resolved.characters.len() > 1 || !resolved.objects.is_empty();
    let mut notes = Vec::new();
    let target = match (is_world, target) {
        (false, t) => t,
        (true, RecordingTarget::None) => RecordingTarget::None,
        (true, RecordingTarget::Default) => {
            notes.push(
                "recording: not written (recordings of worlds with several characters or \
                 moving objects are not implemented yet)"
                    .to_string(),
            );
            RecordingTarget::None
        }
        (true, _) => anyhow::bail!(
            "{}: recordings of worlds with several characters or moving objects are not \
             implemented yet; run with --no-record",
            args.scenario.display()
        ),
    };
    target.check(resolved.methods.len())?;
    let frames = args.frames.map_or(resolved.frames(), |f| f as usize);
    resolved.frames = frames;
    if args.json.is_some() {
        // The JSON report keeps every frame's record (pairs come on top).
        let mut budget = RunBudget::new(&limits);
        let charged = budget.charge(Some(resolved.estimated_bytes), String::new);
        let records = frames
            .checked_mul(resolved.methods.len())
            .and_then(|n| n.checked_mul(std::mem::size_of::<FrameRecord>()));
        charged
            .and_then(|()| {
                budget.charge(records, || {
                    format!(
                        "--json: the report of {frames} frames of {} methods",
                        resolved.methods.len()
                    )
                })
            })
            .map_err(|e| anyhow::anyhow!("{}: frames: {e}", args.scenario.display()))?;
    }
    let dump = match &args.dump_frame {
        Some(_) if is_world => anyhow::bail!(
            "--dump-frame: only for a scenario with one character and no moving objects"
        ),
        Some(v) => {
            let k: usize = v[0].parse().map_err(|_| {
                anyhow::anyhow!(
                    "--dump-frame: the frame must be a whole number, not {:?}",
                    v[0]
                )
            })?;
            if k >= frames {
                anyhow::bail!(
                    "--dump-frame: frame {k} is past the last frame ({})",
                    frames - 1
                );
            }
            Some((k, PathBuf::from(&v[1])))
        }
        None => None,
    };
    let name = scenario_name(&args.scenario);
    let progress = indicatif::ProgressBar::new(frames as u64);
    progress.set_style(
        indicatif::ProgressStyle::with_template(
            "{prefix} [{bar:30}] {pos}/{len} frames, {elapsed} (eta {eta}) {msg}",
        )
        .expect("valid template")
        .progress_chars("=> "),
    );
    progress.set_prefix(name.clone());
    progress.set_message("building hierarchies");
    let mut world = World::new(resolved, args.threads)?;

    // The ground truth, shared by every method.
    let mut truth = if args.no_truth || is_world {
        None
    } else {
        let first = world.scene.first();
        Some(
            FrameTruth::new(
                &world.scene.environment.mesh,
                first.character.mesh.indices(),
            )
            .context("setting up the ground truth")?,
        )
    };
    let mut world_truth = if args.no_truth || !is_world {
        None
    } else {
        Some(WorldTruth::new(&world.scene).context("setting up the ground truth")?)
    };
    let kept: Vec<Vec<bool>> = world
        .methods
        .iter_mut()
        .map(|m| {
            let p = m.pipeline(0);
            let mut kept = vec![false; p.character_tree.triangle_joint.len()];
            for t in &p.character_tree.triangles {
                kept[t.index()] = true;
            }
            kept
        })
        .collect();

    // One recording per method (one character in a static room).
    let record_options = RecordOptions {
        all_spheres: world.scene.recording.all_spheres,
        mesh_every: world.scene.recording.mesh_every,
        spheres_every: world.scene.recording.spheres_every,
    };
    let mut created: Vec<PathBuf> = Vec::new();
    let mut recorders: Vec<Option<RunRecorder>> = Vec::new();
    let methods = world.methods.len();
    {
        let World {
            scene,
            methods: mws,
            ..
        } = &mut world;
        for mw in mws.iter_mut() {
            let method = mw.method;
            let p = mw.pipeline(0);
            let opened = target
                .open(
                    &name,
                    method.name(),
                    methods,
                    run_blueprint(layout::display_level(&p.character_tree.tree)),
                )
                .inspect_err(|_| discard(&created))?;
            let Some(o) = opened else {
                recorders.push(None);
                continue;
            };
            if let Some(path) = &o.path {
                created.push(path.clone());
            }
            let info = SceneInfo {
                scenario: &name,
                markdown: scenario_markdown(&name, scene, frames, method),
            };
            let first = scene.first();
            let r = RunRecorder::new(
                o.stream,
                record_options,
                &info,
                p,
                &first.character,
                &scene.environment.mesh,
            )
            .inspect_err(|_| discard(&created))?;
            recorders.push(Some(r));
        }
    }

    // Per-frame records are summed as they come; they are kept only for the
    // JSON report, so a long run's memory stays flat.
    let keep_frames = args.json.is_some();
    let mut runs: Vec<MethodRun> = world
        .methods
        .iter_mut()
        .map(|m| MethodRun {
            scenario: name.clone(),
            method: m.method,
            dedup: world.scene.dedup,
            hierarchy_bytes: if is_world {
                m.hierarchy_bytes()
            } else {
                m.pipeline(0).hierarchy_bytes()
            },
            frames: Vec::new(),
        })
        .collect();
    let mut summing: Vec<SummaryBuilder> = runs
        .iter()
        .map(|r| SummaryBuilder::new(r.method, r.hierarchy_bytes))
        .collect();
    let interrupted = interrupt_flag();
    progress.set_message("");
    let mut played = 0;
    for k in 0..frames {
        if interrupted.load(Ordering::SeqCst) {
            break;
        }
        let t = world.scene.first().time_at(k);
        // Every vertex is skinned for the ground truth, the recording and a
        // dump, when any of them is on (not part of any method's time:
        // methods skin only what they test).
        world.pose(k);
        if let Some((c, reach)) = world.out_of_range() {
            discard(&created);
            anyhow::bail!(
                "{}",
                pose_out_of_range(&args.scenario, &world.scene, c, reach, k)
            );
        }
        let dumped = dump.as_ref().is_some_and(|(dk, _)| *dk == k);
        if truth.is_some()
            || world_truth.is_some()
            || recorders.iter().any(Option::is_some)
            || dumped
        {
            world.skin_all();
        }
        if let Some(t) = truth.as_mut() {
            let first = world.scene.first();
            t.update(
                &world.buffers[0].positions,
                first.character.mesh.indices(),
                &world.scene.environment.mesh,
            )
            .inspect_err(|_| discard(&created))
            .with_context(|| format!("ground truth of frame {k}"))?;
        }
        if let Some(t) = world_truth.as_mut() {
            t.update(&world.scene, &world.buffers, &world.object_poses)
                .with_context(|| format!("ground truth of frame {k}"))?;
        }
        for i in 0..world.methods.len() {
            world.detect_method(i);
            let World {
                scene,
                methods: mws,
                buffers,
                ..
            } = &mut world;
            let mw = &mut mws[i];
            let method = mw.method;
            let c = mw.outcome.total;
            let env = &scene.environment.mesh;
            let first = scene.first();
            let character = &first.character;
            let indices = character.mesh.indices();
            let mut record = if is_world {
                let mut r = FrameRecord::new(k, &c, &[]);
                let mut w = WorldFrameRecord::new(&mw.outcome);
                if let Some(t) = world_truth.as_ref() {
                    w.accuracy_by_kind = Some(t.score(&mw.outcome));
                    w.parry_accuracy_by_kind = Some(t.parry_score());
                }
                r.world = Some(w);
                r
            } else {
                FrameRecord::new(k, &c, &mw.pipeline(0).pairs)
            };
            let p = mw.pipeline(0);
            let scored = match truth.as_mut() {
                Some(t) => {
                    let ctx = MethodContext {
                        kept: &kept[i],
                        big: &p.environment.big,
                        plane_sphere: p.method.big_leaf_test() == LeafTest::PlaneSphere,
                    };
                    let mt = t
                        .score(&p.pairs, &buffers[0].positions, indices, env, &ctx)
                        .inspect_err(|_| discard(&created))
                        .with_context(|| format!("scoring frame {k} of {method}"))?;
                    record.truth = Some(TruthRecord::new(
                        &mt,
                        t.exact.len(),
                        &t.parry_vs_exact,
                        t.parry_extra_max_distance,
                    ));
                    Some((mt, t.exact.len()))
                }
                None => None,
            };
            summing[i].add(&record);
            if keep_frames {
                runs[i].frames.push(record);
            }
            if let Some(rec) = &mut recorders[i] {
                // Written to disk every frame: a killed run leaves a recording
                // of every frame before the kill.
                let logged = rec
                    .log_frame(k, t, p, &buffers[0], character, env, &c)
                    .and_then(|()| match &scored {
                        Some((mt, n)) => {
                            rec.log_truth(mt, *n, &buffers[0].positions, character, env)
                        }
                        None => Ok(()),
                    })
                    .map_err(anyhow::Error::from)
                    .and_then(|()| {
                        rec.stream()
                            .flush_blocking()
                            .map_err(|e| anyhow::anyhow!("{e}"))
                    });
                if let Err(e) = logged {
                    discard(&created);
                    return Err(e.context(format!("recording frame {k} of {method}")));
                }
            }
        }
        if let Some((dk, dir)) = &dump
            && *dk == k
        {
            let World {
                scene,
                methods: mws,
                buffers,
                ..
            } = &mut world;
            let pipes: Vec<&Pipeline> = mws.iter_mut().map(|m| &*m.pipeline(0)).collect();
            dump_frame(
                dir,
                k,
                &name,
                &pipes,
                &buffers[0].positions,
                &scene.first().character,
                &scene.environment.mesh,
                truth.as_mut(),
            )
            .with_context(|| format!("{}: cannot dump frame {k}", dir.display()))?;
        }
        played = k + 1;
        progress.inc(1);
    }
    progress.finish_and_clear();
    let stopped = played < frames;
    let note = if stopped {
        format!("interrupted (Ctrl-C) after {played} of {frames} frames")
    } else {
        format!("finished {frames} frames")
    };
    let mut recorded = Vec::new();
    for (rec, m) in recorders.into_iter().zip(&world.methods) {
        if let Some(rec) = rec {
            rec.finish(&note)
                .with_context(|| format!("finishing the recording of {}", m.method))?;
            recorded.push(rec.frames_logged());
            drop(rec);
        }
    }

    let summaries: Vec<Summary> = summing.iter().map(SummaryBuilder::summary).collect();
    if let Some(path) = &args.json {
        let text = match runs.as_slice() {
            [one] => serde_json::to_string(one)?,
            _ => serde_json::to_string(&serde_json::json!({ "scenario": name, "runs": runs }))?,
        };
        std::fs::write(path, text)
            .with_context(|| format!("{}: cannot write the report", path.display()))?;
    }
    let scene = &world.scene;
    let env = &scene.environment.mesh;
    let first = scene.first();
    let skinning_name = |m: SkinningModel| match m {
        SkinningModel::Linear => "linear blend",
        SkinningModel::Paper => "paper-model",
    };
    let mut out = if is_world {
        format!(
            "{name}: {} characters ({}), {} moving objects in {} ({} triangles), {played} frames at {} fps on {} threads{}\n",
            scene.characters.len(),
            scene
                .characters
                .iter()
                .map(|a| format!("{}: {} vertices", a.name, a.character.mesh.vertex_count()))
                .collect::<Vec<_>>()
                .join(", "),
            scene.objects.len(),
            scene.environment.name,
            env.triangle_count(),
            scene.fps,
            world.threads(),
            if scene.dedup {
                ", edge de-duplication on"
            } else {
                ""
            },
        )
    } else {
        format!(
            "{name}: {} ({} vertices) in {} ({} triangles), {played} frames at {} fps, {} skinning{}\n",
            first.character.name,
            first.character.mesh.vertex_count(),
            scene.environment.name,
            env.triangle_count(),
            scene.fps,
            skinning_name(first.skinning),
            if scene.dedup {
                ", edge de-duplication on"
            } else {
                ""
            },
        )
    };
    if stopped {
        out += &format!("{note}: the summary covers the frames played\n");
    }
    for a in &scene.characters {
        if let Some(g) = &a.gap {
            let who = if is_world {
                format!(" {}", a.name)
            } else {
                String::new()
            };
            out += &format!(
                "placement{who}: gap {:.4} m from {} (asked {:.4} m; closest at frame {})\n",
                g.achieved, g.surface, g.metres, g.closest_frame
            );
        }
    }
    out += &match style {
        Style::Text => SummaryTable(&summaries).to_string(),
        Style::Markdown => SummaryTable(&summaries).markdown(),
    };
    if is_world {
        out += &world_kind_table(&summing, world_truth.is_some());
    }
    out += &format!(
        "{played} frames, {} methods in {:.1} s (hierarchies, frames{})\n",
        world.methods.len(),
        started.elapsed().as_secs_f64(),
        if truth.is_some() || world_truth.is_some() {
            ", ground truth"
        } else {
            ""
        }
    );
    if let Some(path) = &args.json {
        out += &format!("report: {}\n", path.display());
    }
    if let Some((k, dir)) = &dump
        && *k < played
    {
        out += &format!(
            "frame {k}: {dir}/avatar.ply, {dir}/environment.ply, {dir}/pairs.json\n",
            dir = dir.display()
        );
    }
    for path in &created {
        out += &format!("recording: {} ({})\n", path.display(), file_size(path));
    }
    for n in &notes {
        out += &format!("{n}\n");
    }
    if matches!(target, RecordingTarget::Rerun(..)) && !recorded.is_empty() {
        out += "recording: sent to the Rerun viewer\n";
    }
    Ok(out)
}

/// Per pair kind: each method's pairs over the run and, with the truth,
/// precision and recall.
fn world_kind_table(runs: &[SummaryBuilder], with_truth: bool) -> String {
    use cornertree::world::PairKind;
    let mut out = String::from(
        "per pair kind (pairs over the run; precision / recall against the exact pairs):\n",
    );
    for r in runs {
        out += &format!("  {:32}", r.method().name());
        for kind in PairKind::ALL {
            let k = r.by_kind.get(kind);
            out += &format!(
                " {}: {} pairs, max {} ops",
                kind.name(),
                k.pairs,
                k.max_operations
            );
            if with_truth {
                out += &format!(
                    " ({:.3} / {:.3})",
                    k.accuracy.precision(),
                    k.accuracy.recall()
                );
            }
            out += ";";
        }
        out += "\n";
    }
    out
}

/// The one-line refusal of a frame whose pose takes character `c` out of
/// the coordinate range (see `World::pose`).
pub fn pose_out_of_range(
    scenario: &Path,
    scene: &Resolved,
    c: usize,
    reach: f32,
    k: usize,
) -> String {
    format!(
        "{}: character {:?}: frame {k}: its clip takes vertices up to {} m from the origin, beyond the {} accepted for coordinates",
        scenario.display(),
        scene.characters[c].name,
        cornertree::scenario::ranges::show_f32(reach),
        cornertree::scenario::ranges::show_f32(cornertree::io::limits::MAX_COORDINATE)
    )
}

fn file_size(path: &Path) -> String {
    match std::fs::metadata(path) {
        Ok(m) => format!("{:.1} MB", m.len() as f64 / 1e6),
        Err(_) => "size unknown".into(),
    }
}

/// Writes frame `k` for external tools: both meshes as PLY (face `i` is
/// triangle `i`), and the reported, exact and parry pairs as JSON.
#[allow(clippy::too_many_arguments)]
fn dump_frame(
    dir: &Path,
    k: usize,
    scenario: &str,
    pipes: &[&Pipeline],
    positions: &[cornertree::geometry::Point],
    character: &cornertree::character::Character,
    env: &cornertree::mesh::TriMesh,
    truth: Option<&mut FrameTruth>,
) -> anyhow::Result<()> {
    use cornertree::io::ply::write_ply;
    std::fs::create_dir_all(dir)?;
    write_ply(&dir.join("avatar.ply"), positions, character.mesh.indices())?;
    write_ply(&dir.join("environment.ply"), env.positions(), env.indices())?;
    // The truth of this frame (computed here when the run skips it).
    let mut own;
    let truth = match truth {
        Some(t) => t,
        None => {
            own = FrameTruth::new(env, character.mesh.indices())?;
            own.update(positions, character.mesh.indices(), env)?;
            &mut own
        }
    };
    let as_arrays = |v: &[(u32, u32)]| v.iter().map(|&(a, b)| [a, b]).collect::<Vec<_>>();
    let by_method: serde_json::Map<String, serde_json::Value> = pipes
        .iter()
        .map(|p| {
            (
                p.method.name().to_string(),
                serde_json::json!(as_arrays(&p.pairs)),
            )
        })
        .collect();
    let json = serde_json::json!({
        "scenario": scenario,
        "frame": k,
        "method": pipes.first().map(|p| p.method.name()),
        "reported": pipes.first().map(|p| as_arrays(&p.pairs)).unwrap_or_default(),
        "reference": as_arrays(&truth.exact),
        "parry": as_arrays(&truth.parry),
        "reported_by_method": by_method,
    });
    std::fs::write(dir.join("pairs.json"), serde_json::to_string_pretty(&json)?)?;
    Ok(())
}
