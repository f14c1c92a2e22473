//! Mutation fuzzing of the glTF loaders (issue #15): damaged copies of the
//! shipped characters and of a small generated one go through the static and
//! the character loader from memory; each must load or give a one-line error
//! naming the file, without panicking, within a memory and a time limit; what
//! loads is inspected (sphere tree built and validated), and a character also
//! plays a few frames of `inspect --animate`.
//! proptest generates the mutations (`mutate.rs`) and runs the cases.
//!
//! | file | what |
//! |---|---|
//! | `main.rs` | the tests: short and long runs per loader, seeds, replay of saved failures |
//! | `seeds.rs` | the seeds: `CesiumMan.glb`, `BrainStem.glb`, a small character as GLB and as `.gltf` + `.bin` |
//! | `mutate.rs` | mutations of the JSON, the buffer and the packed file, and their strategies |
//! | `check.rs` | one case through a loader, judged; saving failures; the watchdog |
//! | `alloc.rs` | the allocator that measures each case's peak memory |
//!
//! Short runs are part of `cargo test` (fixed RNG seed). Long runs:
//! `FUZZ_CASES=100000 cargo test --release --test fuzz_gltf -- --ignored --nocapture`
//! (`FUZZ_SEED` fixes the RNG seed, else it is random and printed). A failing
//! case is saved under `tests/fuzz-regressions/`, replayed by
//! `saved_failures_stay_fixed`. See `docs/robustness.md`.

mod alloc;
mod check;
mod mutate;
mod seeds;

use std::cell::RefCell;
use std::collections::BTreeMap;
use std::path::Path;
use std::time::{Duration, Instant};

use proptest::test_runner::{Config, RngSeed, TestCaseError, TestError, TestRunner};

use check::{Loader, Outcome, run_case, save_failure};
use mutate::Files;
use seeds::Kind;

#[global_allocator]
static GLOBAL: alloc::Tracking = alloc::Tracking;

/// Seed weights of long runs: small GLB, small `.gltf`, CesiumMan, BrainStem
/// (the large one takes 20 times longer, so it is picked least), then the
/// compressed CesiumMan: Draco, meshopt, gltfpack, quantized.
const WEIGHTS: [u32; 8] = [4, 3, 3, 1, 2, 2, 2, 1];

/// Seed weights and cases per loader in `cargo test` (about 30 s).
const SHORT_WEIGHTS: [u32; 8] = [5, 4, 4, 1, 2, 2, 2, 1];
const SHORT_CASES: u32 = 1_000;

#[derive(Default)]
struct Stats {
    cases: u64,
    loaded: u64,
    animated: u64,
    refused: BTreeMap<String, u64>,
    peak: usize,
    slowest: Duration,
    per_seed: [u64; WEIGHTS.len()],
}

impl Stats {
    fn report(&self, loader: Loader, elapsed: Duration, seed: u64) -> String {
        let mut kinds: Vec<(&String, &u64)> = self.refused.iter().collect();
        kinds.sort_by(|a, b| b.1.cmp(a.1));
        let refused: u64 = self.refused.values().sum();
        let mut s = format!(
            "fuzz_gltf {}: {} cases in {:.1} s (RNG seed {seed}; per seed {:?}): {} loaded ({} animated), {refused} refused; slowest case {:.0} ms, largest peak {:.1} MiB\n",
            loader.name(),
            self.cases,
            elapsed.as_secs_f64(),
            self.per_seed,
            self.loaded,
            self.animated,
            self.slowest.as_secs_f64() * 1e3,
            self.peak as f64 / f64::from(1u32 << 20),
        );
        for (kind, n) in kinds.iter().take(12) {
            s += &format!("  {n:>7} {kind}\n");
        }
        s
    }
}

/// A scratch folder per test (`purpose`) and loader: tests of this binary
/// run at once, and a `.gltf` seed's `.bin` written by one must not be
/// overwritten by another's mutation.
fn scratch(loader: Loader, purpose: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "cornertree-fuzz-{}-{}-{purpose}",
        std::process::id(),
        loader.name()
    ));
    std::fs::create_dir_all(&dir).expect("create the scratch folder");
    dir
}

/// Runs `cases` mutated inputs through `loader`; panics with the failing
/// input (also saved under `tests/fuzz-regressions/`) if one fails.
fn fuzz(loader: Loader, cases: u32, rng_seed: u64, weights: &[u32; 8]) {
    check::start_watchdog();
    let seeds = seeds::all();
    let dir = scratch(loader, "fuzz");
    let stats = RefCell::new(Stats::default());
    let config = Config {
        cases,
        rng_seed: RngSeed::Fixed(rng_seed),
        failure_persistence: None,
        max_shrink_iters: 256,
        ..Config::default()
    };
    let mut runner = TestRunner::new(config);
    let start = Instant::now();
    let result = runner.run(&mutate::input(weights), |input| {
        let seed = &seeds[input.seed];
        let files = mutate::apply(seed, &input);
        let (outcome, cost) = run_case(loader, seed.kind, &files, &dir, input.paper);
        let mut s = stats.borrow_mut();
        s.cases += 1;
        if s.cases % 10_000 == 0 {
            eprintln!(
                "fuzz_gltf {}: {} cases, {:.0} s",
                loader.name(),
                s.cases,
                start.elapsed().as_secs_f64()
            );
        }
        s.per_seed[input.seed] += 1;
        s.peak = s.peak.max(cost.peak);
        s.slowest = s.slowest.max(cost.time);
        match outcome {
            Ok(Outcome::Loaded { animated }) => {
                s.loaded += 1;
                s.animated += u64::from(animated);
                Ok(())
            }
            Ok(Outcome::Refused(kind)) => {
                *s.refused.entry(kind).or_default() += 1;
                Ok(())
            }
            Err(why) => Err(TestCaseError::fail(why)),
        }
    });
    eprint!(
        "{}",
        stats.borrow().report(loader, start.elapsed(), rng_seed)
    );
    let _ = std::fs::remove_dir_all(&dir);
    if let Err(error) = result {
        let message = match &error {
            TestError::Fail(why, input) => {
                let seed = &seeds[input.seed];
                let Files { main, bin } = mutate::apply(seed, input);
                let saved = save_failure(loader, seed.kind, &main, bin.as_deref(), why.message());
                format!(
                    "{why}; smallest failing input ({}: {:?}) saved in {}",
                    seed.name,
                    input.mutations,
                    saved.display()
                )
            }
            other => other.to_string(),
        };
        panic!("fuzz_gltf {}: {message}", loader.name());
    }
}

fn env_or<T: std::str::FromStr>(name: &str, default: T) -> T {
    std::env::var(name)
        .ok()
        .and_then(|v| v.replace('_', "").parse().ok())
        .unwrap_or(default)
}

fn long_seed() -> u64 {
    env_or(
        "FUZZ_SEED",
        std::time::SystemTime::now()
            .duration_since(std::time::UNIX_EPOCH)
            .map(|d| d.as_nanos() as u64)
            .unwrap_or(1),
    )
}

#[test]
fn fuzz_static_loader_short() {
    fuzz(
        Loader::Static,
        env_or("FUZZ_CASES", SHORT_CASES),
        15,
        &SHORT_WEIGHTS,
    );
}

#[test]
fn fuzz_character_loader_short() {
    fuzz(
        Loader::Character,
        env_or("FUZZ_CASES", SHORT_CASES),
        16,
        &SHORT_WEIGHTS,
    );
}

#[test]
#[ignore = "long run: FUZZ_CASES (default 100000) inputs"]
fn fuzz_static_loader_long() {
    fuzz(
        Loader::Static,
        env_or("FUZZ_CASES", 100_000),
        long_seed(),
        &WEIGHTS,
    );
}

#[test]
#[ignore = "long run: FUZZ_CASES (default 100000) inputs"]
fn fuzz_character_loader_long() {
    fuzz(
        Loader::Character,
        env_or("FUZZ_CASES", 100_000),
        long_seed(),
        &WEIGHTS,
    );
}

/// The seeds load and animate unmutated, so mutations start from good files.
#[test]
fn seeds_load_and_animate() {
    let dir = scratch(Loader::Character, "seeds");
    for seed in seeds::all() {
        let files = mutate::apply(
            &seed,
            &mutate::Input {
                seed: 0,
                mutations: Vec::new(),
                paper: false,
            },
        );
        for loader in [Loader::Static, Loader::Character] {
            let (outcome, _) = run_case(loader, seed.kind, &files, &dir, false);
            let loaded = matches!(outcome, Ok(Outcome::Loaded { .. }));
            assert!(loaded, "{} ({}): {outcome:?}", seed.name, loader.name());
            if loader == Loader::Character {
                assert!(
                    matches!(outcome, Ok(Outcome::Loaded { animated: true })),
                    "{}",
                    seed.name
                );
            }
        }
    }
}

/// Every input saved under `tests/fuzz-regressions/` goes through both
/// loaders cleanly.
#[test]
fn saved_failures_stay_fixed() {
    let Ok(entries) = std::fs::read_dir(check::regressions_dir()) else {
        return;
    };
    let mut failures = Vec::new();
    let mut replayed = 0;
    for entry in entries.flatten() {
        let dir = entry.path();
        for (name, kind) in [("case.glb", Kind::Glb), ("case.gltf", Kind::Gltf)] {
            let Ok(main) = std::fs::read(dir.join(name)) else {
                continue;
            };
            let bin = std::fs::read(dir.join(seeds::BIN_NAME)).ok();
            let files = Files { main, bin };
            let scratch_dir = scratch(Loader::Static, "replay").join(replay_name(&dir));
            std::fs::create_dir_all(&scratch_dir).unwrap();
            for loader in [Loader::Static, Loader::Character] {
                for paper in [false, true] {
                    replayed += 1;
                    if let (Err(why), _) = run_case(loader, kind, &files, &scratch_dir, paper) {
                        failures.push(format!("{} ({}): {why}", dir.display(), loader.name()));
                    }
                }
            }
        }
    }
    eprintln!("replayed {replayed} saved inputs");
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn replay_name(dir: &Path) -> String {
    dir.file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default()
}
