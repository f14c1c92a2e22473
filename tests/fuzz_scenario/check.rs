//! Running one scenario text as `cornertree run` does before and at its
//! first frames, and judging the outcome: no panic, a one-line error naming
//! the file, memory within the run's budget, bounded time.
//!
//! A case is read (`Scenario::parse`), resolved within [`LIMITS`] (bodies
//! loaded or generated, placements worked out), every method's hierarchies
//! are built (`Session::new`), the ground truth is set up, and the first and
//! last frames are played through every method and the truth; with
//! `ccd = true`, the last step is also detected continuously.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::Ordering;
use std::thread::ThreadId;
use std::time::{Duration, Instant};

use cornertree_workbench::scenario::{RunLimits, Scenario, resolve_with};
use cornertree_workbench::session::Session;
use cornertree_workbench::truth::Truth;

use super::alloc::{CURRENT, PEAK};

/// The run budget the fuzzed scenarios get (half the default, so a
/// case that reaches it costs less; the shipped worlds fit).
pub const LIMITS: RunLimits = RunLimits { max_bytes: 2 << 30 };

/// Most bytes one case may have allocated at once beyond what was live
/// before it: the budget, which the estimates must not undershoot.
pub const MEMORY_LIMIT: usize = LIMITS.max_bytes;

/// Most frames a case plays the placement over (a run's time is linear in
/// its frames; the frame range itself is checked at load).
pub const FRAMES: usize = 8;

/// Longest one case may take before the watchdog saves it and ends the run.
/// Wall time a case may take by default (`FUZZ_TIME_LIMIT` seconds
/// overrides it: a loaded machine starves a case without it being slow).
pub const DEFAULT_TIME_LIMIT: Duration = Duration::from_secs(120);

/// The wall-time limit of one case.
pub fn time_limit() -> Duration {
    std::env::var("FUZZ_TIME_LIMIT")
        .ok()
        .and_then(|v| v.parse().ok())
        .map_or(DEFAULT_TIME_LIMIT, Duration::from_secs)
}

/// What a case did.
#[derive(Debug)]
pub enum Outcome {
    /// Resolved, built and played.
    Played,
    /// A clean error (its field and first words, for the statistics).
    Refused(String),
}

/// Peak bytes allocated during the case, and how long it took.
pub struct Cost {
    pub peak: usize,
    pub time: Duration,
}

/// The case each test thread is running, for the watchdog.
static RUNNING: Mutex<Option<HashMap<ThreadId, (Instant, String)>>> = Mutex::new(None);

fn set_running(running: Option<(Instant, String)>) {
    let mut guard = RUNNING.lock().unwrap_or_else(|e| e.into_inner());
    let map = guard.get_or_insert_with(HashMap::new);
    let id = std::thread::current().id();
    match running {
        Some(r) => map.insert(id, r),
        None => map.remove(&id),
    };
}

/// Where a case's file is said to be: in `scenarios/`, so the shipped
/// relative asset paths resolve.
pub fn case_path(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("scenarios")
        .join(format!("{name}.toml"))
}

/// Runs `text` as the scenario file `path`. `Err` describes a failure: a
/// panic, a multi-line error, an error that does not name the file, or a
/// case over the memory limit.
pub fn run_case(text: &str, path: &Path) -> (Result<Outcome, String>, Cost) {
    set_running(Some((Instant::now(), text.to_owned())));
    let before = CURRENT.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let start = Instant::now();
    let result = catch_unwind(AssertUnwindSafe(|| run(text, path)));
    let cost = Cost {
        peak: PEAK.load(Ordering::Relaxed).saturating_sub(before),
        time: start.elapsed(),
    };
    set_running(None);
    let outcome = match result {
        Err(panic) => Err(format!("panic: {}", panic_message(&panic))),
        Ok(r) => r,
    };
    let outcome = match outcome {
        _ if cost.peak > MEMORY_LIMIT => Err(format!(
            "allocated {} MiB at once, over the {} MiB budget",
            cost.peak >> 20,
            MEMORY_LIMIT >> 20
        )),
        other => other,
    };
    (outcome, cost)
}

fn run(text: &str, path: &Path) -> Result<Outcome, String> {
    let mut scenario = match Scenario::parse(text, path) {
        Ok(s) => s,
        Err(e) => return judge_error(path, &e.to_string()),
    };
    scenario.frames = scenario.frames.map(|f| f.min(FRAMES));
    let base = path.parent().unwrap_or(Path::new(""));
    let resolved = match resolve_with(&scenario, base, &LIMITS) {
        Ok(r) => r,
        Err(e) => return judge_error(path, &e.to_string()),
    };
    let frames = resolved.frames;
    let mut world = Session::new(resolved, 1).map_err(|e| format!("session: {e}"))?;
    // The ground truth as `run` sets it up; its errors are failures here
    // (every input it could refuse was refused at load).
    let mut truth = Truth::new(&world.scene).map_err(|e| format!("ground truth: {e}"))?;
    let mut played = vec![0, frames - 1];
    played.dedup();
    for k in played {
        world.pose(k);
        if let Some((c, reach)) = world.out_of_range() {
            // What `run` prints then.
            return judge_error(
                path,
                &format!(
                    "{}: character {:?}: frame {k}: its clip takes vertices up to {reach:e} m from the origin",
                    path.display(),
                    world.scene.characters[c].name
                ),
            );
        }
        world.skin_all();
        truth
            .update(&world.scene, &world.buffers, &world.object_poses)
            .map_err(|e| format!("ground truth of frame {k}: {e}"))?;
        world.detect_all();
    }
    // `ccd = true`: continuous detection of the last step (posing its start).
    if world.scene.ccd && frames > 1 {
        world.enable_continuous(cornertree::geometry::ccd_root_finder::CcdParams::default());
        for m in 0..world.worlds().len() {
            world
                .sweep(m, frames - 1)
                .map_err(|e| format!("continuous detection: {e}"))?;
        }
    }
    Ok(Outcome::Played)
}

/// A clean refusal: one line, starting with the file's path.
fn judge_error(path: &Path, message: &str) -> Result<Outcome, String> {
    if message.contains('\n') || message.contains('\r') {
        return Err(format!("multi-line error: {message:?}"));
    }
    let shown = path.display().to_string();
    let Some(rest) = message.strip_prefix(&shown) else {
        return Err(format!(
            "error does not start with the file's path: {message}"
        ));
    };
    if std::env::var_os("FUZZ_LOG").is_some() {
        eprintln!("{message}");
    }
    Ok(Outcome::Refused(head(rest)))
}

/// The field and first words of a message, without numbers or quoted
/// names: a rough kind of error.
fn head(rest: &str) -> String {
    // Drop `:line:column`.
    let rest = rest.trim_start_matches(|c: char| c == ':' || c.is_ascii_digit());
    rest.split_whitespace()
        .filter(|w| {
            !w.chars()
                .any(|c| c.is_ascii_digit() || c == '"' || c == '`')
        })
        .take(5)
        .collect::<Vec<_>>()
        .join(" ")
}

fn panic_message(panic: &Box<dyn std::any::Any + Send>) -> String {
    let message = if let Some(s) = panic.downcast_ref::<&str>() {
        (*s).to_owned()
    } else if let Some(s) = panic.downcast_ref::<String>() {
        s.clone()
    } else {
        "(non-string payload)".to_owned()
    };
    let at = PANIC_AT.with(|at| at.take()).unwrap_or_default();
    format!("{message} (at {at})")
}

thread_local! {
    /// Where the last panic on this thread happened (set by the hook).
    static PANIC_AT: std::cell::RefCell<Option<String>> = const { std::cell::RefCell::new(None) };
}

/// Replaces the panic hook with one that notes where a panic happened and
/// prints one line.
fn quiet_panics() {
    std::panic::set_hook(Box::new(|info| {
        let at = info
            .location()
            .map(|l| format!("{}:{}", l.file(), l.line()))
            .unwrap_or_default();
        let message = info.payload_as_str().unwrap_or("(non-string payload)");
        eprintln!(
            "fuzz_scenario: panic at {at}: {}",
            message.lines().next().unwrap_or("")
        );
        PANIC_AT.with(|p| *p.borrow_mut() = Some(at));
    }));
}

/// Where crashing inputs are kept, one folder each.
pub fn regressions_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-regressions")
}

/// Saves a failing case as `tests/fuzz-regressions/scenario-<hash>/case.toml`
/// with a `failure.txt`; returns the folder.
pub fn save_failure(text: &str, why: &str) -> PathBuf {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    for &b in text.as_bytes() {
        hash = (hash ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
    }
    let dir = regressions_dir().join(format!("scenario-{hash:016x}"));
    let _ = std::fs::create_dir_all(&dir);
    let _ = std::fs::write(dir.join("case.toml"), text);
    let _ = std::fs::write(dir.join("failure.txt"), format!("{why}\n"));
    dir
}

/// Ends the process if a case runs past [`time_limit`], after saving it.
pub fn start_watchdog() {
    static STARTED: Mutex<bool> = Mutex::new(false);
    let mut started = STARTED.lock().unwrap_or_else(|e| e.into_inner());
    if *started {
        return;
    }
    *started = true;
    quiet_panics();
    let limit = time_limit();
    std::thread::spawn(move || {
        loop {
            std::thread::sleep(Duration::from_secs(1));
            let guard = RUNNING.lock().unwrap_or_else(|e| e.into_inner());
            let stuck = guard
                .iter()
                .flat_map(|map| map.values())
                .find(|(start, _)| start.elapsed() > limit);
            if let Some((_, text)) = stuck {
                let dir = save_failure(text, &format!("ran longer than {} s", limit.as_secs()));
                eprintln!(
                    "fuzz_scenario: a case ran longer than {} s; saved in {}",
                    limit.as_secs(),
                    dir.display()
                );
                std::process::exit(3);
            }
        }
    });
}
