//! `cornertree scaling`: cost per frame against character size, room size,
//! the number of characters and the depth of contact (docs/performance.md), each configuration
//! measured as `bench` measures (command-line plumbing; the variants are
//! [`cornertree_workbench::bench::variants`]).

use anyhow::Context;
use cornertree::pipeline::Method;
use cornertree_workbench::bench::{Bench, variants};
use cornertree_workbench::report::bench::{Column, scaling_table};
use cornertree_workbench::scenario::{Resolved, load_scenario, scenario_name};
use serde::Serialize;

use super::args::ScenarioArgs;
use super::bench::{measure_with_progress, progress_bar};
use super::play::{DEFAULT_BUDGET_GIB, run_limits};

/// Character sizes of the study: about 3k, 10k, 44k (the paper's) and 100k.
const CHARACTER_VERTICES: [usize; 4] = [3_000, 10_000, 44_345, 100_000];
/// Environment sizes: about 10k, 133k (the paper's living room) and 500k.
const ENVIRONMENT_VERTICES: [usize; 3] = [10_000, 133_139, 500_000];
/// Gaps of the contact sweep (metres): from a near miss 5 cm away to 5 cm
/// deep a centimetre apart, then 10, 15 and 20 cm deep (a character inside
/// furniture).
const CONTACT_GAPS: [f32; 14] = [
    0.05, 0.04, 0.03, 0.02, 0.01, 0.0, -0.01, -0.02, -0.03, -0.04, -0.05, -0.10, -0.15, -0.20,
];

#[derive(clap::Args)]
pub struct ScalingArgs {
    /// Base scenario (its room must be generated for the room study). Frames
    /// per configuration: --frames, default 16.
    #[command(flatten)]
    pub common: ScenarioArgs,
    /// Character sizes (vertices, comma-separated) played in the base room.
    /// Default: 3000,10000,44345,100000, unless --characters-count is given
    /// (then this study runs only when asked).
    #[arg(long, value_delimiter = ',')]
    pub characters: Option<Vec<usize>>,
    /// Room sizes (vertices, comma-separated) with the character of
    /// --character-size. Default: 10000,133139,500000, unless
    /// --characters-count is given.
    #[arg(long, value_delimiter = ',')]
    pub environments: Option<Vec<usize>>,
    /// Character size (vertices) of the room study.
    #[arg(long, default_value_t = 44_345)]
    pub character_size: usize,
    /// Crowd study: this many generated humanoids (comma-separated counts, e.g.
    /// 1,2,4,8,16,32). A base scenario with a `[crowd]` (the plazas) keeps
    /// its layout and spacing at every count, on a plaza sized to it (e.g.
    /// `scaling scenarios/plaza_brushing.toml --characters-count
    /// 64,1024,4096`); any other walks them in free lanes of its room, 0.62 m
    /// apart. Nothing by default.
    #[arg(long, value_delimiter = ',')]
    pub characters_count: Vec<usize>,
    /// Most memory each configuration's bodies and the measured methods'
    /// hierarchies may take, in GiB (estimated before they are built, as
    /// `run` does; docs/robustness.md).
    #[arg(long, value_name = "GIB", default_value_t = DEFAULT_BUDGET_GIB)]
    pub memory_budget: f64,
    /// Contact sweep: the base scenario's character kept 5 cm to -5 cm from
    /// its gap surface (the south wall if it keeps none), a centimetre apart,
    /// then -10, -15 and -20 cm, so the speed-up over parry is seen from near
    /// miss to deep contact.
    #[arg(long)]
    pub contact_sweep: bool,
    /// Gaps of the contact sweep, metres (comma-separated; negative: that
    /// deep into the surface at the deepest), e.g. `--contact-gaps=0.02,0,-0.02`.
    #[arg(long, value_delimiter = ',', allow_hyphen_values = true)]
    pub contact_gaps: Option<Vec<f32>>,
    /// Vertices of each humanoid of the crowd study.
    #[arg(long, default_value_t = 10_000)]
    pub crowd_vertices: usize,
    /// Threads for the methods' frames (0: one per core).
    #[arg(long, default_value_t = 0)]
    pub threads: usize,
}

#[derive(Serialize)]
struct Scaling {
    base_scenario: String,
    frames: u64,
    /// Threads of the methods' frames and of the baseline.
    threads: usize,
    /// The base scenario's crowd spacing, when the crowd study kept its
    /// layout.
    #[serde(skip)]
    crowd_spacing: Option<[f32; 2]>,
    by_character: Vec<Bench>,
    by_environment: Vec<Bench>,
    by_characters_count: Vec<Bench>,
    by_contact_gap: Vec<Bench>,
}

enum Study {
    Character(usize),
    Environment(usize),
    Crowd(usize),
    Contact(f32),
}

/// Metres shown in signed centimetres (`-` when absent).
fn cm(x: Option<f32>) -> String {
    x.map_or(String::from("-"), |m| format!("{:+.1}", m * 100.0))
}

pub fn scaling(args: ScalingArgs) -> anyhow::Result<String> {
    let common = &args.common;
    let methods = common.methods_or_all();
    let frames = common.frames.unwrap_or(16);
    let studies = studies(&args)?;
    let result = measure_studies(&args, &studies, &methods, frames)?;
    let mut out = tables(&args, &result, &methods);
    if let Some(path) = &common.json {
        std::fs::write(path, serde_json::to_string(&result)?)
            .with_context(|| format!("{}: cannot write the report", path.display()))?;
        out += &format!("\nreport: {}\n", path.display());
    }
    Ok(out)
}

/// The configurations the arguments ask for, checked.
fn studies(args: &ScalingArgs) -> anyhow::Result<Vec<Study>> {
    let gaps: Vec<f32> = match (&args.contact_gaps, args.contact_sweep) {
        (Some(g), _) => g.clone(),
        (None, true) => CONTACT_GAPS.to_vec(),
        (None, false) => Vec::new(),
    };
    if let Some(g) = gaps.iter().find(|g| !g.is_finite() || g.abs() > 1.0) {
        anyhow::bail!("--contact-gaps: {g}: a gap must be finite and within ±1 m");
    }
    if let Some(&n) = args.characters_count.iter().find(|&&n| n == 0) {
        anyhow::bail!("--characters-count: {n}: a crowd needs at least one character");
    }
    let crowd_only = !args.characters_count.is_empty() || !gaps.is_empty();
    let default = |sizes: &[usize]| {
        if crowd_only {
            Vec::new()
        } else {
            sizes.to_vec()
        }
    };
    let characters = args
        .characters
        .clone()
        .unwrap_or_else(|| default(&CHARACTER_VERTICES));
    let environments = args
        .environments
        .clone()
        .unwrap_or_else(|| default(&ENVIRONMENT_VERTICES));
    Ok(characters
        .iter()
        .map(|&c| Study::Character(c))
        .chain(environments.iter().map(|&e| Study::Environment(e)))
        .chain(args.characters_count.iter().map(|&n| Study::Crowd(n)))
        .chain(gaps.iter().map(|&g| Study::Contact(g)))
        .collect())
}

/// Measures every study, `frames` frames each, grouped by kind.
fn measure_studies(
    args: &ScalingArgs,
    studies: &[Study],
    methods: &[Method],
    frames: u64,
) -> anyhow::Result<Scaling> {
    let common = &args.common;
    let name = scenario_name(&common.scenario);
    // The methods measured are set before resolving: the budget charges
    // their hierarchies alone.
    let limits = run_limits(args.memory_budget)?;
    let mut base = load_scenario(&common.scenario)?;
    base.methods = methods.to_vec();
    let progress = progress_bar(studies.len() as u64 * frames);
    let mut by = [Vec::new(), Vec::new(), Vec::new(), Vec::new()];
    for study in studies {
        let (label, slot, scene): (String, usize, anyhow::Result<Resolved>) = match *study {
            Study::Character(c) => (
                format!("{name}, humanoid of {c} vertices"),
                0,
                variants::sized(&common.scenario, &base, c, None, &limits).map_err(Into::into),
            ),
            Study::Environment(e) => (
                format!(
                    "{name}, room of {e} vertices, humanoid of {}",
                    args.character_size
                ),
                1,
                variants::sized(
                    &common.scenario,
                    &base,
                    args.character_size,
                    Some(e),
                    &limits,
                )
                .map_err(Into::into),
            ),
            Study::Crowd(n) => (
                format!("{name}, {n} humanoids of {} vertices", args.crowd_vertices),
                2,
                variants::crowd(&common.scenario, &base, n, args.crowd_vertices, &limits)
                    .map_err(Into::into),
            ),
            Study::Contact(g) => (
                format!("{name}, gap {:+.1} cm", g * 100.0),
                3,
                variants::at_gap(&common.scenario, &base, g, &limits).map_err(Into::into),
            ),
        };
        progress.set_message(label.clone());
        let mut scene = scene.with_context(|| label.clone())?;
        common.apply(&mut scene, Some(false));
        scene.methods = methods.to_vec();
        by[slot].push(measure_with_progress(
            scene,
            &label,
            frames as usize,
            args.threads,
            &progress,
        )?);
    }
    progress.finish_and_clear();
    let [
        by_character,
        by_environment,
        by_characters_count,
        by_contact_gap,
    ] = by;
    let threads = [
        &by_character,
        &by_environment,
        &by_characters_count,
        &by_contact_gap,
    ]
    .iter()
    .find_map(|v| v.first())
    .map_or(args.threads, |b| b.threads);
    Ok(Scaling {
        base_scenario: name,
        frames,
        threads,
        crowd_spacing: base.crowd.as_ref().map(|c| c.spacing),
        by_character,
        by_environment,
        by_characters_count,
        by_contact_gap,
    })
}

/// The markdown tables of `result`, one per kind of study.
fn tables(args: &ScalingArgs, result: &Scaling, methods: &[Method]) -> String {
    let sizes: [Column; 2] = [
        ("character vertices", |b| b.vertices.to_string()),
        ("room vertices", |b| b.environment_vertices.to_string()),
    ];
    let crowd: [Column; 4] = [
        ("characters", |b| b.characters.to_string()),
        ("vertices", |b| b.vertices.to_string()),
        ("ms per character, 1 thread (fastest)", |b| {
            let best = b
                .methods
                .iter()
                .map(|m| m.ms_per_frame_one_thread)
                .fold(f64::INFINITY, f64::min);
            format!("{:.4}", best / b.characters.max(1) as f64)
        }),
        ("work/span (fastest)", |b| {
            b.methods
                .iter()
                .min_by(|x, y| x.ms_per_frame.total_cmp(&y.ms_per_frame))
                .map_or(String::new(), |m| format!("{:.1}", m.available_parallelism))
        }),
    ];
    let mut out = format!(
        "Median ms per frame over {} frames of {} on {} threads (de-duplication {}; speed-up over parry3d on the same threads in brackets)\n",
        result.frames,
        result.base_scenario,
        result.threads,
        match args.common.dedup_override() {
            Some(true) => "on",
            _ => "off",
        }
    );
    if !result.by_character.is_empty() {
        out += "\n### Against character size (the room at its own size)\n\n";
        out += &scaling_table(&result.by_character, methods, &sizes);
    }
    if !result.by_environment.is_empty() {
        out += &format!(
            "\n### Against environment size (humanoid of {} vertices)\n\n",
            args.character_size
        );
        out += &scaling_table(&result.by_environment, methods, &sizes);
    }
    if !result.by_characters_count.is_empty() {
        out += &format!(
            "\n### Against the number of characters (humanoids of {} vertices, {})\n\n",
            args.crowd_vertices,
            match &result.crowd_spacing {
                Some([x, z]) =>
                    format!("walking in place in the base scenario's crowd grid, {x} m × {z} m"),
                None => format!("walking in free lanes {} m apart", variants::LANE_SPACING),
            }
        );
        out += &scaling_table(&result.by_characters_count, methods, &crowd);
    }
    if !result.by_contact_gap.is_empty() {
        let contact: [Column; 3] = [
            ("gap (cm)", |b| cm(b.gap_metres)),
            ("deepest (cm)", |b| cm(b.deepest_metres)),
            ("pairs (fastest)", |b| {
                let best = b
                    .methods
                    .iter()
                    .min_by(|x, y| x.ms_per_frame.total_cmp(&y.ms_per_frame));
                best.map_or(String::new(), |m| format!("{:.0}", m.pairs_per_frame))
            }),
        ];
        out += "\n### Against the depth of contact (negative gap: that deep into the surface at the deepest)\n\n";
        out += &scaling_table(&result.by_contact_gap, methods, &contact);
    }
    out
}
