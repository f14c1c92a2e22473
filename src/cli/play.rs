//! The frame loop `run` and `compare` share: a [`Session`] plays the
//! scenario, one world per method fed the same poses, and the observers of
//! [`super::observe`] read each step (the ground truth, the continuous
//! detection of `--ccd`, the report, the recordings, a frame dump, the
//! progress bar); none of them changes the measured work.

use std::path::Path;
use std::time::Instant;

use anyhow::Context;
use cornertree::character::SkinningModel;
use cornertree::pipeline::Method;
use cornertree::world::PairKind;
use cornertree_workbench::record::target::RecordingTarget;
use cornertree_workbench::report::run::{Summary, SummaryBuilder, SummaryTable};
use cornertree_workbench::scenario::budget::RunBudget;
use cornertree_workbench::scenario::ranges::MAX_FRAMES;
use cornertree_workbench::scenario::{Resolved, RunLimits, open_scenario_within, scenario_name};
use cornertree_workbench::session::Session;

use super::args::ScenarioArgs;
use super::observe::continuous::ContinuousObserver;
use super::observe::dump::Dump;
use super::observe::progress::Progress;
use super::observe::recording::{Recordings, discard};
use super::observe::reference::Reference;
use super::observe::report::Report;
use super::observe::{Observer, Seen};

/// `--memory-budget` by default: [`RunLimits::default`] in GiB.
pub const DEFAULT_BUDGET_GIB: f64 = 4.0;

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

/// `--memory-budget` as limits.
pub(super) fn run_limits(gib: f64) -> anyhow::Result<RunLimits> {
    if !(gib.is_finite() && gib > 0.0 && gib <= 1e6) {
        anyhow::bail!("--memory-budget: must be GiB from above 0 to 1e6, not {gib}");
    }
    Ok(RunLimits {
        max_bytes: (gib * f64::from(1u32 << 30)) as usize,
    })
}

/// The run's scenario, read and checked with everything else that can be
/// wrong with the input, before any file is created.
struct Opened {
    resolved: Resolved,
    name: String,
    frames: usize,
    limits: RunLimits,
    dump: Option<Dump>,
}

fn open(args: &PlayArgs) -> anyhow::Result<Opened> {
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
    let frames = args.common.frames.map_or(resolved.frames(), |f| f as usize);
    resolved.frames = frames;
    if args.common.json.is_some() {
        // The JSON report keeps every frame's record (pairs come on top).
        let mut budget = RunBudget::new(&limits);
        let charged = budget.charge(Some(resolved.estimated_bytes), String::new);
        let n = resolved.methods.len();
        let records = frames.checked_mul(n).and_then(|x| {
            x.checked_mul(std::mem::size_of::<
                cornertree_workbench::report::run::FrameRecord,
            >())
        });
        charged
            .and_then(|()| {
                budget.charge(records, || {
                    format!("--json: the report of {frames} frames of {n} methods")
                })
            })
            .map_err(|e| anyhow::anyhow!("{}: frames: {e}", args.common.scenario.display()))?;
    }
    let name = scenario_name(&args.common.scenario);
    let dump = match &args.dump_frame {
        Some(_) if resolved.is_world() => anyhow::bail!(
            "--dump-frame: only for a scenario with one character and no moving objects"
        ),
        Some(v) => Some(Dump::parse(v, frames, &name)?),
        None => None,
    };
    Ok(Opened {
        resolved,
        name,
        frames,
        limits,
        dump,
    })
}

/// Charges continuous detection's state to the budget, before any file is
/// created.
fn charge_continuous(session: &Session, limits: &RunLimits, scenario: &Path) -> anyhow::Result<()> {
    let mut budget = RunBudget::new(limits);
    budget
        .charge(Some(session.scene.estimated_bytes), String::new)
        .and_then(|()| {
            budget.charge(session.continuous_estimated_bytes(), || {
                "continuous detection (both ends of every step, per method and character)".into()
            })
        })
        .map_err(|e| anyhow::anyhow!("{}: ccd: {e}", scenario.display()))
}

pub fn play(args: PlayArgs, target: RecordingTarget) -> anyhow::Result<String> {
    let started = Instant::now();
    let opened = open(&args)?;
    target.check(opened.resolved.methods.len())?;
    let Opened {
        resolved,
        name,
        frames,
        limits,
        mut dump,
    } = opened;
    let progress = Progress::new(&name, frames);
    let mut session = Session::new(resolved, args.threads)?;
    let ccd_on = args.ccd || session.scene.ccd;
    if ccd_on {
        charge_continuous(&session, &limits, &args.common.scenario)?;
    }
    let mut reference = if args.no_truth {
        None
    } else {
        Some(Reference::new(&session)?)
    };
    let mut recordings = Recordings::open(&mut session, &target, &name, ccd_on, |s, m| {
        scenario_markdown(&name, &s.scene, frames, s.world(m).method())
    })?;
    let mut ccd = ccd_on.then(|| {
        let substeps = args.ccd_substeps.unwrap_or(session.scene.ccd_substeps);
        let recorded: Vec<bool> = recordings.recorders.iter().map(Option::is_some).collect();
        ContinuousObserver::new(&mut session, substeps, !args.no_truth, &recorded)
    });
    let mut report = Report::new(&session, &name, args.common.json.is_some());
    let mut progress_observer = progress;
    progress_observer.start();
    let played = {
        let streams: Vec<Option<rerun::RecordingStream>> = (0..session.worlds().len())
            .map(|m| recordings.stream(m).cloned())
            .collect();
        let mut observers: Vec<&mut dyn Observer> = vec![&mut report, &mut recordings];
        if let Some(d) = dump.as_mut() {
            observers.push(d);
        }
        let interrupted = progress_observer.interrupted_flag();
        observers.push(&mut progress_observer);
        let mut frame_loop = FrameLoop {
            session: &mut session,
            reference: reference.as_mut(),
            ccd: ccd.as_mut(),
            streams,
            scenario: &args.common.scenario,
        };
        frame_loop.run(frames, &mut observers, || {
            interrupted.load(std::sync::atomic::Ordering::SeqCst)
        })
    }
    .inspect_err(|_| discard(&recordings.created))?;
    progress_observer.finish();

    let stopped = played < frames;
    let note = if stopped {
        format!("interrupted (Ctrl-C) after {played} of {frames} frames")
    } else {
        format!("finished {frames} frames")
    };
    let created = recordings.created.clone();
    let recorded = recordings.finish(&session, &note)?;
    if let Some(c) = &ccd {
        for (r, t) in report.runs.iter_mut().zip(&c.totals) {
            r.continuous = Some(t.clone());
        }
    }
    if let Some(path) = &args.common.json {
        for (r, b) in report.runs.iter_mut().zip(&report.summing) {
            r.summary = Some(b.summary());
        }
        let runs = &report.runs;
        let text = match runs.as_slice() {
            [one] => serde_json::to_string(one)?,
            _ => serde_json::to_string(&serde_json::json!({ "scenario": name, "runs": runs }))?,
        };
        std::fs::write(path, text)
            .with_context(|| format!("{}: cannot write the report", path.display()))?;
    }
    let mut out = header(&name, &session, played, stopped.then_some(note.as_str()));
    out += &tables(
        &session,
        &report,
        ccd.as_ref(),
        args.style,
        reference.is_some(),
    );
    out += &format!(
        "{played} frames, {} methods in {:.1} s (hierarchies, frames{})\n",
        session.worlds().len(),
        started.elapsed().as_secs_f64(),
        if reference.is_some() {
            ", ground truth"
        } else {
            ""
        }
    );
    if let Some(path) = &args.common.json {
        out += &format!("report: {}\n", path.display());
    }
    if let Some(d) = &dump
        && d.frame < played
    {
        out += &d.files();
    }
    for path in &created {
        out += &format!("recording: {} ({})\n", path.display(), file_size(path));
    }
    if matches!(target, RecordingTarget::Rerun(..)) && !recorded.is_empty() {
        out += "recording: sent to the Rerun viewer\n";
    }
    Ok(out)
}

/// The session's frame loop and what is not an [`Observer`]: the ground
/// truth every observer reads, and continuous detection, which steps the
/// worlds itself.
struct FrameLoop<'a> {
    session: &'a mut Session,
    reference: Option<&'a mut Reference>,
    ccd: Option<&'a mut ContinuousObserver>,
    /// Each method's recording stream, for continuous detection's part.
    streams: Vec<Option<rerun::RecordingStream>>,
    scenario: &'a Path,
}

impl FrameLoop<'_> {
    /// Plays frames `0..frames` until `stop` says so; returns the frames
    /// played.
    fn run(
        &mut self,
        frames: usize,
        observers: &mut [&mut dyn Observer],
        stop: impl Fn() -> bool,
    ) -> anyhow::Result<usize> {
        let methods = self.session.worlds().len();
        let mut continuous = vec![None; methods];
        let mut played = 0;
        for k in 0..frames {
            if stop() {
                break;
            }
            self.pose(k, observers)?;
            let scene = &self.session.scene;
            // Clip time of one character, the world's time otherwise.
            let t = if scene.is_world() {
                scene.world_time(k)
            } else {
                scene.first().time_at(k)
            };
            for m in 0..methods {
                self.session.detect(m);
                if let Some(c) = self.ccd.as_deref_mut() {
                    continuous[m] = c
                        .method(self.session, k, m, self.streams[m].as_ref())
                        .with_context(|| format!("continuous detection of frame {k}"))?;
                }
                if let Some(r) = self.reference.as_deref_mut() {
                    r.score(self.session, k, m)?;
                }
                let seen = self.seen(k, t, &continuous);
                for o in observers.iter_mut() {
                    o.method(&seen, m)?;
                }
            }
            let seen = self.seen(k, t, &continuous);
            for o in observers.iter_mut() {
                o.frame_end(&seen)?;
            }
            if let Some(c) = self.ccd.as_deref_mut() {
                c.end_frame(self.session);
            }
            played = k + 1;
        }
        Ok(played)
    }

    /// Poses frame `k`, skins every vertex when an observer (or the ground
    /// truth) reads them (not part of any method's time: methods skin only
    /// what they test), and updates the ground truth.
    fn pose(&mut self, k: usize, observers: &[&mut dyn Observer]) -> anyhow::Result<()> {
        let session = &mut *self.session;
        session.pose(k);
        if let Some((c, reach)) = session.out_of_range() {
            anyhow::bail!(
                "{}",
                pose_out_of_range(self.scenario, &session.scene, c, reach, k)
            );
        }
        if self.reference.is_some()
            || self.ccd.as_ref().is_some_and(|c| c.wants_skin())
            || observers.iter().any(|o| o.needs_skin(k))
        {
            session.skin_all();
        }
        if let Some(c) = self.ccd.as_deref_mut() {
            c.begin_frame(session, k);
        }
        if let Some(r) = self.reference.as_deref_mut() {
            r.update(session, k)?;
        }
        Ok(())
    }

    fn seen<'s>(
        &'s self,
        k: usize,
        t: f32,
        continuous: &'s [Option<cornertree_workbench::report::continuous::ContinuousFrameRecord>],
    ) -> Seen<'s> {
        Seen {
            session: self.session,
            k,
            t,
            reference: self.reference.as_deref(),
            continuous,
        }
    }
}

/// The characters by name and size: each one, or for more than 8 the first
/// and last with their count per size (a crowd of a thousand is one line).
fn character_list(scene: &cornertree_workbench::scenario::Resolved) -> String {
    let one = |a: &cornertree_workbench::scenario::Actor| {
        format!("{}: {} vertices", a.name, a.character.mesh.vertex_count())
    };
    let cs = &scene.characters;
    if cs.len() <= 8 {
        return cs.iter().map(one).collect::<Vec<_>>().join(", ");
    }
    let mut sizes: Vec<(usize, usize)> = Vec::new();
    for a in cs {
        let v = a.character.mesh.vertex_count();
        match sizes.iter_mut().find(|(s, _)| *s == v) {
            Some((_, n)) => *n += 1,
            None => sizes.push((v, 1)),
        }
    }
    let by_size = sizes
        .iter()
        .map(|(v, n)| format!("{n} of {v} vertices"))
        .collect::<Vec<_>>()
        .join(", ");
    format!("{} … {}: {by_size}", cs[0].name, cs[cs.len() - 1].name)
}

/// The run's first lines: what was played, and the placements.
fn header(name: &str, session: &Session, played: usize, stopped: Option<&str>) -> String {
    let scene = &session.scene;
    let env = &scene.environment.mesh;
    let first = scene.first();
    let dedup = if scene.dedup {
        ", edge de-duplication on"
    } else {
        ""
    };
    let mut out = if scene.is_world() {
        format!(
            "{name}: {} characters ({}), {} moving objects in {} ({} triangles), {played} frames at {} fps on {} threads{dedup}\n",
            scene.characters.len(),
            character_list(scene),
            scene.objects.len(),
            scene.environment.name,
            env.triangle_count(),
            scene.fps,
            session.threads(),
        )
    } else {
        let skinning = match first.skinning {
            SkinningModel::Linear => "linear blend",
            SkinningModel::Paper => "paper-model",
        };
        format!(
            "{name}: {} ({} vertices) in {} ({} triangles), {played} frames at {} fps, {skinning} skinning{dedup}\n",
            first.character.name,
            first.character.mesh.vertex_count(),
            scene.environment.name,
            env.triangle_count(),
            scene.fps,
        )
    };
    if let Some(note) = stopped {
        out += &format!("{note}: the summary covers the frames played\n");
    }
    for a in &scene.characters {
        if let Some(g) = &a.gap {
            let who = if scene.is_world() {
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
    out
}

/// The summary table, the per-kind table of a world, continuous
/// detection's lines.
fn tables(
    session: &Session,
    report: &Report,
    ccd: Option<&ContinuousObserver>,
    style: Style,
    with_truth: bool,
) -> String {
    let summaries: Vec<Summary> = report.summing.iter().map(SummaryBuilder::summary).collect();
    let mut out = match style {
        Style::Text => SummaryTable(&summaries).to_string(),
        Style::Markdown => SummaryTable(&summaries).markdown(),
    };
    if session.scene.is_world() {
        out += &world_kind_table(&report.summing, with_truth);
    }
    if let Some(c) = ccd {
        out += &c.summary(session);
    }
    out
}

/// The scenario as a recording's `info` document, for `method`.
fn scenario_markdown(name: &str, r: &Resolved, frames: usize, method: Method) -> String {
    let first = r.first();
    let world = r.is_world();
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

/// Per pair kind: each method's pairs over the run and, with the truth,
/// precision and recall.
fn world_kind_table(runs: &[SummaryBuilder], with_truth: bool) -> String {
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
                    " ({:.3} / {:.3}",
                    k.accuracy.precision(),
                    k.accuracy.recall()
                );
                if k.removed_by_dedup > 0 {
                    out += &format!(
                        "; {} lost to de-dup, recall {:.3} over kept triangles",
                        k.removed_by_dedup,
                        k.recall_over_kept_triangles()
                    );
                }
                out += ")";
            }
            out += ";";
        }
        out += "\n";
    }
    if with_truth && let Some(r) = runs.first() {
        let lost: u64 = PairKind::ALL
            .iter()
            .map(|&k| r.by_kind.get(k).removed_by_dedup)
            .sum();
        if lost > 0 {
            let all: u64 = PairKind::ALL
                .iter()
                .map(|&k| {
                    let a = r.by_kind.get(k).accuracy;
                    a.tp + a.fn_
                })
                .sum();
            out += &format!(
                "{lost} of {all} exact pairs involve character triangles removed by edge \
                 de-duplication (paper §4; `--no-dedup` keeps them): no method reports them.\n"
            );
        }
    }
    out
}

/// The one-line refusal of a frame whose pose takes character `c` out of
/// the coordinate range (see [`Session::pose`]).
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
