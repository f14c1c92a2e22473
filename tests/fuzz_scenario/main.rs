//! Mutation fuzzing of scenario files (issue #15): damaged copies of every
//! shipped scenario (`scenarios/*.toml`: single characters and worlds) are
//! read, resolved within a memory budget, built as `cornertree run` builds
//! them (every method's hierarchies, the ground truth) and played for their
//! first and last frames; each must run or give a one-line error naming the
//! file, without panicking, within the budget and a time limit.
//! proptest generates the mutations (`mutate.rs`) and runs the cases.
//!
//! | file | what |
//! |---|---|
//! | `main.rs` | the tests: short and long runs, seeds, replay of saved failures |
//! | `mutate.rs` | mutations of the TOML text and their strategies |
//! | `check.rs` | one case run and judged; saving failures; the watchdog |
//! | `../fuzz_gltf/alloc.rs` | the allocator that measures each case's peak memory |
//!
//! Seeds: each shipped scenario as it is, and a light copy of it (humanoids
//! of 1,000 vertices, the room at 5,000, two methods) that builds in a
//! fraction of the time, picked more often (only they in `cargo test`).
//! Short runs are part of `cargo test` (fixed RNG seed). Long runs:
//! `FUZZ_CASES=100000 cargo test --release --test fuzz_scenario -- --ignored --nocapture`
//! (`FUZZ_SEED` fixes the RNG seed, else it is random and printed). A failing
//! case is saved under `tests/fuzz-regressions/scenario-*/`, replayed by
//! `saved_failures_stay_fixed`. See `docs/robustness.md`.

#[path = "../fuzz_gltf/alloc.rs"]
mod alloc;
mod check;
mod mutate;

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::time::{Duration, Instant};

use proptest::test_runner::{Config, RngSeed, TestCaseError, TestError, TestRunner};

use check::{Outcome, case_path, run_case, save_failure};

#[global_allocator]
static GLOBAL: alloc::Tracking = alloc::Tracking;

/// Vertices of the light seeds' humanoids and rooms.
const LIGHT_HUMANOID: usize = 1_000;
const LIGHT_ROOM: usize = 5_000;
/// Characters of a light seed's crowd, and of a shipped seed's.
const LIGHT_CROWD: usize = 6;
const SHIPPED_CROWD: usize = 100;
const LIGHT_METHODS: &str = "[\"original\", \"pruned-tri-tri\"]";

/// Weight of a shipped seed and of its light copy, long and short runs.
const WEIGHTS: (u32, u32) = (1, 24);
const SHORT_WEIGHTS: (u32, u32) = (0, 1);
const SHORT_CASES: u32 = 1_000;

/// A seed: its name and text.
struct Seed {
    name: String,
    text: String,
}

/// Every shipped scenario, then a light copy of each.
fn seeds() -> Vec<Seed> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("scenarios/")
        .flatten()
        .map(|e| e.path())
        .filter(|p| p.extension().is_some_and(|e| e == "toml"))
        .collect();
    files.sort();
    // A shipped crowd of a thousand is past the fuzzer's budget (LIMITS):
    // its seed keeps [`SHIPPED_CROWD`] of them.
    let shipped: Vec<Seed> = files
        .iter()
        .map(|p| Seed {
            name: p.file_stem().unwrap().to_string_lossy().into_owned(),
            text: crowd_of(
                &std::fs::read_to_string(p).expect("read a scenario"),
                SHIPPED_CROWD,
            ),
        })
        .collect();
    let light: Vec<Seed> = shipped
        .iter()
        .map(|s| Seed {
            name: format!("{}-light", s.name),
            text: lighten(&s.text),
        })
        .collect();
    shipped.into_iter().chain(light).collect()
}

/// `text` with its `[crowd]` count (if any) set to `count`.
fn crowd_of(text: &str, count: usize) -> String {
    match text.find("\ncount = ") {
        Some(at) => {
            let from = at + "\ncount = ".len();
            let digits = text[from..]
                .find(|c: char| !c.is_ascii_digit())
                .unwrap_or(0);
            format!("{}{count}{}", &text[..from], &text[from + digits..])
        }
        None => text.to_owned(),
    }
}

/// The scenario with small humanoids, a crowd of [`LIGHT_CROWD`] and, for a
/// generated room, the room at [`LIGHT_ROOM`] vertices.
fn lighten(text: &str) -> String {
    let text = &crowd_of(text, LIGHT_CROWD);
    let mut out = String::new();
    let mut rest = text.as_str();
    while let Some(i) = rest.find("vertices=") {
        out += &rest[..i];
        out += &format!("vertices={LIGHT_HUMANOID}");
        rest = rest[i + "vertices=".len()..].trim_start_matches(|c: char| c.is_ascii_digit());
    }
    out += rest;
    let generated = ["kind = \"museum\"", "kind = \"living-room\""];
    for kind in generated {
        out = out.replace(kind, &format!("{kind}\nvertices = {LIGHT_ROOM}"));
    }
    // Two methods: the plain tree and a corner-tree one (mutations insert others).
    let methods = format!("methods = {LIGHT_METHODS}");
    match out.find("\nmethods = [") {
        Some(at) => {
            let end = at + out[at..].find(']').expect("a methods list ends") + 1;
            format!("{}\n{methods}{}", &out[..at], &out[end..])
        }
        None => format!("{methods}\n{out}"),
    }
}

#[derive(Default)]
struct Stats {
    cases: u64,
    played: u64,
    refused: BTreeMap<String, u64>,
    peak: usize,
    slowest: Duration,
    per_seed: Vec<u64>,
}

impl Stats {
    fn report(&self, elapsed: Duration, seed: u64) -> String {
        let mut kinds: Vec<(&String, &u64)> = self.refused.iter().collect();
        kinds.sort_by(|a, b| b.1.cmp(a.1));
        let refused: u64 = self.refused.values().sum();
        let mut s = format!(
            "fuzz_scenario: {} cases in {:.1} s (RNG seed {seed}; per seed {:?}): {} played, {refused} refused; slowest case {:.0} ms, largest peak {:.1} MiB\n",
            self.cases,
            elapsed.as_secs_f64(),
            self.per_seed,
            self.played,
            self.slowest.as_secs_f64() * 1e3,
            self.peak as f64 / f64::from(1u32 << 20),
        );
        for (kind, n) in kinds.iter().take(16) {
            s += &format!("  {n:>7} {kind}\n");
        }
        s
    }
}

/// Runs `cases` mutated scenarios; panics with the failing input (also
/// saved under `tests/fuzz-regressions/`) if one fails.
fn fuzz(cases: u32, rng_seed: u64, weights: (u32, u32)) {
    check::start_watchdog();
    let seeds = seeds();
    let half = seeds.len() / 2;
    let weights: Vec<u32> = (0..seeds.len())
        .map(|i| if i < half { weights.0 } else { weights.1 })
        .collect();
    let stats = RefCell::new(Stats {
        per_seed: vec![0; seeds.len()],
        ..Stats::default()
    });
    let config = Config {
        cases,
        rng_seed: RngSeed::Fixed(rng_seed),
        failure_persistence: None,
        max_shrink_iters: 256,
        ..Config::default()
    };
    let mut runner = TestRunner::new(config);
    let start = Instant::now();
    let result = runner.run(&mutate::input(&weights), |input| {
        let seed = &seeds[input.seed];
        let text = mutate::apply(&seed.text, &input);
        let (outcome, cost) = run_case(&text, &case_path(&seed.name));
        let mut s = stats.borrow_mut();
        s.cases += 1;
        if s.cases.is_multiple_of(10_000) {
            eprintln!(
                "fuzz_scenario: {} cases, {:.0} s",
                s.cases,
                start.elapsed().as_secs_f64()
            );
        }
        s.per_seed[input.seed] += 1;
        s.peak = s.peak.max(cost.peak);
        s.slowest = s.slowest.max(cost.time);
        match outcome {
            Ok(Outcome::Played) => {
                s.played += 1;
                Ok(())
            }
            Ok(Outcome::Refused(kind)) => {
                *s.refused.entry(kind).or_default() += 1;
                Ok(())
            }
            Err(why) => Err(TestCaseError::fail(why)),
        }
    });
    eprint!("{}", stats.borrow().report(start.elapsed(), rng_seed));
    if let Err(error) = result {
        let message = match &error {
            TestError::Fail(why, input) => {
                let seed = &seeds[input.seed];
                let text = mutate::apply(&seed.text, input);
                let saved = save_failure(&text, why.message());
                format!(
                    "{why}; smallest failing input ({}: {:?}) saved in {}",
                    seed.name,
                    input.mutations,
                    saved.display()
                )
            }
            other => other.to_string(),
        };
        panic!("fuzz_scenario: {message}");
    }
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.replace('_', "").parse().ok())
        .unwrap_or(default)
}

#[test]
fn fuzz_scenarios_short() {
    fuzz(env_or("FUZZ_CASES", SHORT_CASES), 15, SHORT_WEIGHTS);
}

#[test]
#[ignore = "long run: FUZZ_CASES (default 100000) inputs"]
fn fuzz_scenarios_long() {
    let seed = env_or(
        "FUZZ_SEED",
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos() as u64)
            .unwrap_or(1),
    );
    fuzz(env_or("FUZZ_CASES", 100_000), seed, WEIGHTS);
}

/// The seeds run unmutated, so mutations start from good scenarios (the
/// shipped ones are resolved only here: their runs are tested elsewhere).
#[test]
fn seeds_run() {
    for seed in seeds() {
        let path = case_path(&seed.name);
        if !seed.name.ends_with("-light") {
            let s = cornertree_workbench::scenario::Scenario::parse(&seed.text, &path).unwrap();
            cornertree_workbench::scenario::resolve_with(
                &s,
                path.parent().unwrap(),
                &check::LIMITS,
            )
            .unwrap_or_else(|e| panic!("{e}"));
            continue;
        }
        let (outcome, cost) = run_case(&seed.text, &path);
        eprintln!(
            "{}: {:?} in {:.0} ms, peak {:.0} MiB",
            seed.name,
            outcome,
            cost.time.as_secs_f64() * 1e3,
            cost.peak as f64 / f64::from(1u32 << 20)
        );
        assert!(
            matches!(outcome, Ok(Outcome::Played)),
            "{}: {outcome:?}",
            seed.name
        );
    }
}

/// Every scenario saved under `tests/fuzz-regressions/scenario-*/` runs or
/// is refused cleanly.
#[test]
fn saved_failures_stay_fixed() {
    let Ok(entries) = std::fs::read_dir(check::regressions_dir()) else {
        return;
    };
    let mut failures = Vec::new();
    let mut replayed = 0;
    for entry in entries.flatten() {
        let dir = entry.path();
        let Ok(text) = std::fs::read_to_string(dir.join("case.toml")) else {
            continue;
        };
        replayed += 1;
        let name = dir.file_name().unwrap().to_string_lossy().into_owned();
        if let (Err(why), _) = run_case(&text, &case_path(&name)) {
            failures.push(format!("{}: {why}", dir.display()));
        }
    }
    eprintln!("replayed {replayed} saved scenarios");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
