//! The frame loop `run` and `compare` observe: a [`World`] plays the
//! scenario, and the ground truth, the JSON report, the recordings, frame
//! dumps and the progress bar read each frame's outcome (none of them
//! changes the measured work).

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use anyhow::Context;
use cornertree::character::SkinningModel;
use cornertree::pipeline::LeafTest;
use cornertree::pipeline::Method;
use cornertree::pipeline::driver::Pipeline;
use cornertree_workbench::record::blueprint::{ccd_blueprint, run_blueprint, world_blueprint};
use cornertree_workbench::record::layout;
use cornertree_workbench::record::target::RecordingTarget;
use cornertree_workbench::record::world_recorder;
use cornertree_workbench::record::{RecordOptions, RunRecorder, SceneInfo, WorldRecorder};
use cornertree_workbench::report::run::TruthRecord;
use cornertree_workbench::report::run::{
    FrameRecord, MethodRun, Summary, SummaryBuilder, SummaryTable, WorldFrameRecord,
};
use cornertree_workbench::scenario::budget::RunBudget;
use cornertree_workbench::scenario::ranges::MAX_FRAMES;
use cornertree_workbench::scenario::{Resolved, RunLimits, open_scenario_within, scenario_name};
use cornertree_workbench::truth::WorldTruth;
use cornertree_workbench::truth::{FrameTruth, MethodContext};
use cornertree_workbench::world::{ContinuousWorld, World};

use super::args::ScenarioArgs;
use super::play_ccd::ContinuousObserver;

/// `--memory-budget` by default: [`RunLimits::default`] in GiB.
pub const DEFAULT_BUDGET_GIB: f64 = 4.0;

/// `--memory-budget` as limits.
fn run_limits(gib: f64) -> anyhow::Result<RunLimits> {
    if !(gib.is_finite() && gib > 0.0 && gib <= 1e6) {
        anyhow::bail!("--memory-budget: must be GiB from above 0 to 1e6, not {gib}");
    }
    Ok(RunLimits {
        max_bytes: (gib * f64::from(1u32 << 30)) as usize,
    })
}

/// One method's recording: of one character in a room, or of a world.
enum Recorder {
    One(Box<RunRecorder>),
    World(WorldRecorder),
}

impl Recorder {
    fn stream(&self) -> &rerun::RecordingStream {
        match self {
            Recorder::One(r) => r.stream(),
            Recorder::World(r) => r.stream(),
        }
    }

    fn finish(&self, note: &str) -> Result<(), rerun::sink::SinkFlushError> {
        match self {
            Recorder::One(r) => r.finish(note),
            Recorder::World(r) => r.finish(note),
        }
    }

    fn frames_logged(&self) -> usize {
        match self {
            Recorder::One(r) => r.frames_logged(),
            Recorder::World(r) => r.frames_logged(),
        }
    }
}

/// What `run` and `compare` ask of the frame loop.
pub struct PlayArgs {
    pub common: ScenarioArgs,
    pub skinning: Option<SkinningModel>,
    pub no_truth: bool,
    pub dump_frame: Option<Vec<String>>,
    pub threads: usize,
    pub style: Style,
    /// `--memory-budget`, GiB.
    pub memory_budget: f64,
    /// `--ccd`: continuous detection of every frame step (also on with the
    /// scenario's `ccd = true`), its reference's sub-steps (`--ccd-substeps`).
    pub ccd: bool,
    pub ccd_substeps: Option<u32>,
}

/// How the summary table is printed.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Style {
    Text,
    Markdown,
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
    let world = r.characters.len() > 1 || !r.objects.is_empty();
    let mut s = format!("## {name}: {}\n\n| | |\n|---|---|\n", method.name());
    if !world {
        s += &format!(
            "| character | {} ({} vertices, {} triangles) |\n",
            first.character.name,
            first.character.mesh.vertex_count(),
            first.character.mesh.triangle_count(),
        );
    }
    s += &format!(
        "| environment | {} ({} triangles) |\n| frames | {frames} at {} fps |\n\
         | skinning | {:?} |\n| edge de-duplication | {} |\n| big-triangle threshold | {} m |\n",
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
    if world {
        s += "\n| character | source | vertices | triangles |\n|---|---|---:|---:|\n";
        for a in &r.characters {
            s += &format!(
                "| {} | {} | {} | {} |\n",
                a.name,
                a.character.name,
                a.character.mesh.vertex_count(),
                a.character.mesh.triangle_count()
            );
        }
        if !r.objects.is_empty() {
            s += "\n| moving object | triangles |\n|---|---:|\n";
            for o in &r.objects {
                s += &format!("| {} | {} |\n", o.name, o.mesh.triangle_count());
            }
        }
    }
    s
}

/// Deletes files of recordings that did not finish (an error, not Ctrl-C).
fn discard(paths: &[PathBuf]) {
    for p in paths {
        let _ = std::fs::remove_file(p);
    }
}

pub fn play(args: PlayArgs, target: RecordingTarget) -> anyhow::Result<String> {
    let started = std::time::Instant::now();
    // Everything that can be wrong with the input fails here, before any file
    // is created.
    let style = args.style;
    let limits = run_limits(args.memory_budget)?;
    if let Some(f) = args.common.frames
        && f > MAX_FRAMES
    {
        anyhow::bail!("--frames: must be a whole number from 1 to {MAX_FRAMES}, not {f}");
    }
    let mut resolved = open_scenario_within(&args.common.scenario, &limits, |s| {
        if let Some(model) = args.skinning {
            for c in &mut s.characters {
                c.character.skinning = model;
            }
        }
        if !args.common.methods.is_empty() {
            s.methods = args.common.methods.clone();
        }
    })?;
    args.common.apply(&mut resolved, None);
    let is_world = resolved.characters.len() > 1 || !resolved.objects.is_empty();
    target.check(resolved.methods.len())?;
    let frames = args.common.frames.map_or(resolved.frames(), |f| f as usize);
    resolved.frames = frames;
    if args.common.json.is_some() {
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
            .map_err(|e| anyhow::anyhow!("{}: frames: {e}", args.common.scenario.display()))?;
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
    let name = scenario_name(&args.common.scenario);
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
    let ccd_on = args.ccd || world.scene.ccd;
    // Continuous detection's state (`--ccd`, `ccd = true`), charged to the
    // budget before any file is created.
    if ccd_on {
        let mut budget = RunBudget::new(&limits);
        budget
            .charge(Some(world.scene.estimated_bytes), String::new)
            .and_then(|()| {
                budget.charge(ContinuousWorld::estimated_bytes(&world), || {
                    "continuous detection (both ends of every step, per method and character)"
                        .into()
                })
            })
            .map_err(|e| anyhow::anyhow!("{}: ccd: {e}", args.common.scenario.display()))?;
    }

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
    let mut recorders: Vec<Option<Recorder>> = Vec::new();
    let methods = world.methods.len();
    {
        let World {
            scene,
            methods: mws,
            ..
        } = &mut world;
        let character_paths: Vec<String> = scene
            .characters
            .iter()
            .enumerate()
            .map(|(i, a)| {
                format!(
                    "{}/{}",
                    layout::WORLD_CHARACTERS,
                    world_recorder::body_entity(i, &a.name)
                )
            })
            .collect();
        let object_paths: Vec<String> = scene
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| {
                format!(
                    "{}/{}",
                    layout::WORLD_OBJECTS,
                    world_recorder::body_entity(i, &o.name)
                )
            })
            .collect();
        for mw in mws.iter_mut() {
            let method = mw.method;
            let level = layout::display_level(&mw.pipeline(0).character_tree.tree);
            let blueprint = if ccd_on {
                let bodies: Vec<String> = character_paths
                    .iter()
                    .chain(&object_paths)
                    .cloned()
                    .collect();
                ccd_blueprint(&bodies)
            } else if is_world {
                world_blueprint(&character_paths, &object_paths, level)
            } else {
                run_blueprint(level)
            };
            let opened = target
                .open(&name, method.name(), methods, blueprint)
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
            let r = if is_world {
                WorldRecorder::new(o.stream, record_options, &info, mw, scene).map(Recorder::World)
            } else {
                let first = scene.first();
                RunRecorder::new(
                    o.stream,
                    record_options,
                    &info,
                    mw.pipeline(0),
                    &first.character,
                    &scene.environment.mesh,
                )
                .map(|r| Recorder::One(Box::new(r)))
            }
            .inspect_err(|_| discard(&created))?;
            recorders.push(Some(r));
        }
    }

    // Continuous detection of every step (`--ccd`, `ccd = true`).
    let mut ccd = ccd_on.then(|| {
        let substeps = args.ccd_substeps.unwrap_or(world.scene.ccd_substeps);
        let recorded: Vec<bool> = recorders.iter().map(Option::is_some).collect();
        ContinuousObserver::new(&world, substeps, !args.no_truth, &recorded)
    });

    // Per-frame records are summed as they come; they are kept only for the
    // JSON report, so a long run's memory stays flat.
    let keep_frames = args.common.json.is_some();
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
            continuous: None,
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
        // Clip time of one character, the world's time otherwise.
        let t = if is_world {
            world.scene.world_time(k)
        } else {
            world.scene.first().time_at(k)
        };
        // Every vertex is skinned for the ground truth, the recording and a
        // dump, when any of them is on (not part of any method's time:
        // methods skin only what they test).
        world.pose(k);
        if let Some((c, reach)) = world.out_of_range() {
            discard(&created);
            anyhow::bail!(
                "{}",
                pose_out_of_range(&args.common.scenario, &world.scene, c, reach, k)
            );
        }
        let dumped = dump.as_ref().is_some_and(|(dk, _)| *dk == k);
        if truth.is_some()
            || world_truth.is_some()
            || recorders.iter().any(Option::is_some)
            || ccd.as_ref().is_some_and(ContinuousObserver::wants_skin)
            || dumped
        {
            world.skin_all();
        }
        if let Some(c) = ccd.as_mut() {
            c.begin_frame(&world, k);
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
            let continuous = match ccd.as_mut() {
                Some(c) => c
                    .method(
                        &mut world,
                        k,
                        i,
                        recorders[i].as_ref().map(Recorder::stream),
                    )
                    .inspect_err(|_| discard(&created))
                    .with_context(|| format!("continuous detection of frame {k}"))?,
                None => None,
            };
            let World {
                scene,
                methods: mws,
                buffers,
                object_poses,
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
            record.continuous = continuous;
            summing[i].add(&record);
            if keep_frames {
                runs[i].frames.push(record);
            }
            if let Some(rec) = &mut recorders[i] {
                // Written to disk every frame: a killed run leaves a recording
                // of every frame before the kill.
                let logged = match rec {
                    Recorder::One(rec) => {
                        let p = mw.pipeline(0);
                        rec.log_frame(k, t, p, &buffers[0], character, env, &c)
                            .and_then(|()| match &scored {
                                Some((mt, n)) => {
                                    rec.log_truth(mt, *n, &buffers[0].positions, character, env)
                                }
                                None => Ok(()),
                            })
                    }
                    Recorder::World(rec) => rec
                        .log_frame(k, t, mw, scene, buffers, object_poses)
                        .and_then(|()| match &world_truth {
                            Some(wt) => {
                                rec.log_truth(&wt.exact, &mw.outcome, scene, buffers, object_poses)
                            }
                            None => Ok(()),
                        }),
                }
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
        if let Some(c) = ccd.as_mut() {
            c.end_frame(&world, k);
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
    if let Some(c) = &ccd {
        for (r, t) in runs.iter_mut().zip(&c.totals) {
            r.continuous = Some(t.clone());
        }
    }
    if let Some(path) = &args.common.json {
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
    if let Some(c) = &ccd {
        out += &c.summary(&world);
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
    if let Some(path) = &args.common.json {
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
        cornertree_workbench::scenario::ranges::show_f32(reach),
        cornertree_workbench::scenario::ranges::show_f32(cornertree::io::limits::MAX_COORDINATE)
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
    use cornertree_workbench::io::ply::write_ply;
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
