//! Running one case through a loader and judging the outcome: no panic, a
//! one-line error naming the file, bounded memory and time; what loads is
//! inspected as `cornertree inspect` does (sphere tree built and validated)
//! and a character plays a few frames of `inspect --animate` too.

use std::collections::HashMap;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::{Path, PathBuf};
use std::sync::Mutex;
use std::sync::atomic::Ordering;
use std::thread::ThreadId;
use std::time::{Duration, Instant};

use cornertree::character::SkinningModel;
use cornertree::io::{LoadError, LoadLimits, load_character_from, load_static_mesh_from};
use cornertree::mesh::TriMesh;
use cornertree_workbench::report::animate::{AnimateOptions, animate};
use cornertree_workbench::report::inspect::{InspectOptions, inspect_mesh};

use super::alloc::{CURRENT, PEAK};
use super::mutate::{Files, file_names};
use super::seeds::Kind;

/// The load budget the fuzzed loaders get (smaller than the default, so an
/// input that reaches it costs little).
pub const LIMITS: LoadLimits = LoadLimits {
    max_bytes: 256 << 20,
};

/// Most bytes one case may have allocated at once beyond what was live
/// before it: the budget plus what loading and animating build on top.
pub const MEMORY_LIMIT: usize = 1 << 30;

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

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Loader {
    Static,
    Character,
}

impl Loader {
    pub fn name(self) -> &'static str {
        match self {
            Loader::Static => "static",
            Loader::Character => "character",
        }
    }
}

/// What a case did.
#[derive(Debug)]
pub enum Outcome {
    Loaded {
        animated: bool,
    },
    /// A clean error (its first words after the path, for the statistics).
    Refused(String),
}

/// Peak bytes allocated during the case, and how long it took.
pub struct Cost {
    pub peak: usize,
    pub time: Duration,
}

/// A case being run, for the watchdog: when it started and its files.
struct Running {
    start: Instant,
    loader: Loader,
    kind: Kind,
    main: Vec<u8>,
    bin: Option<Vec<u8>>,
}

/// The case each test thread is running.
static RUNNING: Mutex<Option<HashMap<ThreadId, Running>>> = Mutex::new(None);

fn set_running(running: Option<Running>) {
    let mut guard = RUNNING.lock().unwrap_or_else(|e| e.into_inner());
    let map = guard.get_or_insert_with(HashMap::new);
    let id = std::thread::current().id();
    match running {
        Some(r) => map.insert(id, r),
        None => map.remove(&id),
    };
}

/// Runs `files` through `loader` from `dir` (where a `.gltf` case's buffer is
/// written). `Err` describes a failure: a panic, a multi-line error, an error
/// that does not name the file, or a case over the memory limit.
pub fn run_case(
    loader: Loader,
    kind: Kind,
    files: &Files,
    dir: &Path,
    paper: bool,
) -> (Result<Outcome, String>, Cost) {
    let (main_name, bin_name) = file_names(kind);
    let path = dir.join(main_name);
    if let (Some(name), Some(bin)) = (bin_name, &files.bin) {
        std::fs::write(dir.join(name), bin).expect("write the case's buffer");
    }
    set_running(Some(Running {
        start: Instant::now(),
        loader,
        kind,
        main: files.main.clone(),
        bin: files.bin.clone(),
    }));
    let before = CURRENT.load(Ordering::Relaxed);
    PEAK.store(before, Ordering::Relaxed);
    let start = Instant::now();
    let result = catch_unwind(AssertUnwindSafe(|| run(loader, &path, &files.main, paper)));
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
            "allocated {} MiB at once, over the {} MiB limit",
            cost.peak >> 20,
            MEMORY_LIMIT >> 20
        )),
        other => other,
    };
    (outcome, cost)
}

/// `cornertree inspect` on a mesh that loaded: `Some` refusal if the tree
/// fails validation (what the command would print, checked to be one line).
fn inspect(path: &Path, mesh: &TriMesh) -> Result<Option<Outcome>, String> {
    let name = path.display().to_string();
    match inspect_mesh(&name, mesh, InspectOptions::default()) {
        Ok(_) => Ok(None),
        Err(e) => {
            let message = format!("{name}: sphere tree failed validation: {e}");
            one_line(&message)?;
            Ok(Some(Outcome::Refused(format!(
                "inspect: tree failed validation: {}",
                head(&e.to_string())
            ))))
        }
    }
}

fn run(loader: Loader, path: &Path, bytes: &[u8], paper: bool) -> Result<Outcome, String> {
    match loader {
        Loader::Static => match load_static_mesh_from(path, bytes, &LIMITS) {
            Ok((mesh, _)) => match inspect(path, &mesh)? {
                Some(refused) => Ok(refused),
                None => Ok(Outcome::Loaded { animated: false }),
            },
            Err(e) => judge_error(path, &e),
        },
        Loader::Character => match load_character_from(path, bytes, &LIMITS) {
            Ok((character, _)) => {
                if let Some(refused) = inspect(path, &character.mesh)? {
                    return Ok(refused);
                }
                let Some(clip) = character.clips.first() else {
                    return Ok(Outcome::Loaded { animated: false });
                };
                // About three frames whatever the clip's length; the first
                // frame's tightness and rebuild only.
                let duration = clip.duration();
                let fps = 2.0 / duration;
                let options = AnimateOptions {
                    model: if paper {
                        SkinningModel::Paper
                    } else {
                        SkinningModel::Linear
                    },
                    fps: if fps.is_finite() && fps > 0.0 {
                        fps
                    } else {
                        30.0
                    },
                    sample_every: usize::MAX,
                    max_frames: 8,
                    ..AnimateOptions::default()
                };
                match animate(&character, &options) {
                    Ok(_) => Ok(Outcome::Loaded { animated: true }),
                    Err(e) => {
                        // What `inspect` prints: the file, then the error.
                        let message = format!("{}: {e}", path.display());
                        one_line(&message)?;
                        Ok(Outcome::Refused(format!(
                            "animate: {}",
                            head(&e.to_string())
                        )))
                    }
                }
            }
            Err(e) => judge_error(path, &e),
        },
    }
}

/// A clean refusal: one line, starting with the file's path, `path()` the file.
fn judge_error(path: &Path, e: &LoadError) -> Result<Outcome, String> {
    let message = e.to_string();
    one_line(&message)?;
    let shown = path.display().to_string();
    let Some(rest) = message.strip_prefix(&shown) else {
        return Err(format!(
            "error does not start with the file's path: {message}"
        ));
    };
    if e.path() != path {
        return Err(format!(
            "error's path() is {}: {message}",
            e.path().display()
        ));
    }
    if std::env::var_os("FUZZ_LOG").is_some() {
        eprintln!("{message}");
    }
    Ok(Outcome::Refused(head(rest.trim_start_matches(": "))))
}

fn one_line(message: &str) -> Result<(), String> {
    if message.contains('\n') || message.contains('\r') {
        Err(format!("multi-line error: {message:?}"))
    } else {
        Ok(())
    }
}

/// The first words of a message, without numbers: a rough kind of error.
fn head(message: &str) -> String {
    message
        .split_whitespace()
        .filter(|w| !w.chars().any(|c| c.is_ascii_digit()))
        .take(4)
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
/// prints one line (thousands of cases may panic while a failure shrinks).
pub fn quiet_panics() {
    std::panic::set_hook(Box::new(|info| {
        let at = info
            .location()
            .map(|l| format!("{}:{}", l.file(), l.line()))
            .unwrap_or_default();
        let message = info.payload_as_str().unwrap_or("(non-string payload)");
        eprintln!(
            "fuzz_gltf: panic at {at}: {}",
            message.lines().next().unwrap_or("")
        );
        PANIC_AT.with(|p| *p.borrow_mut() = Some(at));
    }));
}

/// Where crashing inputs are kept, one folder each.
pub fn regressions_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/fuzz-regressions")
}

/// Saves a failing case as `tests/fuzz-regressions/<loader>-<hash>/` with its
/// files and a `failure.txt`; returns the folder.
pub fn save_failure(
    loader: Loader,
    kind: Kind,
    main: &[u8],
    bin: Option<&[u8]>,
    why: &str,
) -> PathBuf {
    let mut hash = 0xcbf2_9ce4_8422_2325_u64;
    for &b in main.iter().chain(bin.unwrap_or(&[])) {
        hash = (hash ^ u64::from(b)).wrapping_mul(0x100_0000_01b3);
    }
    let dir = regressions_dir().join(format!("{}-{hash:016x}", loader.name()));
    let _ = std::fs::create_dir_all(&dir);
    let (main_name, bin_name) = file_names(kind);
    let _ = std::fs::write(dir.join(main_name), main);
    if let (Some(name), Some(bin)) = (bin_name, bin) {
        let _ = std::fs::write(dir.join(name), bin);
    }
    let _ = std::fs::write(dir.join("failure.txt"), format!("{why}\n"));
    dir
}

/// Ends the process if a case runs past [`time_limit`], after saving it: a
/// loop that never ends cannot be caught any other way.
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
                .find(|r| r.start.elapsed() > limit);
            if let Some(Running {
                loader,
                kind,
                main,
                bin,
                ..
            }) = stuck
            {
                let dir = save_failure(
                    *loader,
                    *kind,
                    main,
                    bin.as_deref(),
                    &format!("ran longer than {} s", limit.as_secs()),
                );
                eprintln!(
                    "fuzz_gltf: a {} case ran longer than {} s; saved in {}",
                    loader.name(),
                    limit.as_secs(),
                    dir.display()
                );
                std::process::exit(3);
            }
        }
    });
}
