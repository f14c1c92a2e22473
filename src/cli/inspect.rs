//! `cornertree inspect`: a mesh's or character's sphere tree and, with
//! `--animate`, refit checked over a clip (command-line plumbing; the work is
//! in `report::inspect` and `report::animate`).

use super::args::choice;
use anyhow::Context;
use cornertree::character::{Character, SkinningModel};
use cornertree::io::{load_character, load_static_mesh};
use cornertree::mesh::TriMesh;
use cornertree::sphere_tree::BuildParams;
use cornertree::sphere_tree::refit::RefitRule;
use cornertree_workbench::humanoid::generate_humanoid;
use cornertree_workbench::io::CharacterSource;
use cornertree_workbench::report::animate::{AnimateOptions, RefitReport, animate};
use cornertree_workbench::report::inspect::{InspectOptions, inspect_mesh};

use super::args::{parse_offset, parse_positive};
use super::emit;

#[derive(clap::Args)]
pub struct InspectArgs {
    /// A glTF 2.0 file (.gltf or .glb), or a generated character:
    /// `generated:humanoid` or `generated:humanoid?vertices=N&seed=S`
    /// (default 44345 vertices, the paper's avatar). Without --animate every
    /// triangle is taken in its static pose (skinned meshes in bind pose).
    pub source: CharacterSource,
    /// Print one JSON object on stdout instead of the text summary.
    #[arg(long)]
    pub json: bool,
    /// Keep every triangle (turn edge de-duplication, paper §4, off).
    #[arg(long)]
    pub no_dedup: bool,
    /// Collapse a child sphere into its parent when its radius exceeds this
    /// fraction of the parent's (1 keeps the binary tree).
    #[arg(long, default_value_t = BuildParams::default().collapse_ratio, value_parser = parse_positive)]
    pub collapse_ratio: f32,
    /// Play a clip: skin every frame, refit every sphere of the character's
    /// tree, check containment and tightness, time the refit strategies.
    #[arg(long)]
    pub animate: bool,
    /// Clip to play (default: the first).
    #[arg(long, requires = "animate")]
    pub clip: Option<String>,
    /// Frames per second to sample the clip at.
    #[arg(long, default_value_t = 30.0, requires = "animate", value_parser = parse_positive)]
    pub fps: f32,
    /// Skinning model: glTF linear blend skinning, or the paper's one-joint model.
    #[arg(long, value_parser = choice::<SkinningModel>(), default_value = "linear", requires = "animate")]
    pub skinning: SkinningModel,
    /// How spheres are refit: the paper's corner rule (§3), joint balls
    /// (ours: a ball per joint over the vertices it moves, moved by that
    /// joint), or blended balls (ours: those balls blended by the corners
    /// of the node's weight ranges; what pruned-tri-tri and
    /// undivided-pruned-tri-tri use).
    #[arg(
        long,
        value_parser = choice::<RefitRule>(),
        default_value = "paper-corners",
        requires = "animate"
    )]
    pub refit_rule: RefitRule,
    /// Measure tightness (a minimal sphere per node) and the cost of a rebuild
    /// from scratch on every N-th frame; 0 picks about ten frames over the clip.
    #[arg(long, default_value_t = 0, requires = "animate")]
    pub sample_every: usize,
    /// Place the character at this translation (metres) on every frame, e.g.
    /// 10000,0,0 to check refit 10 km from the origin.
    #[arg(long, value_name = "X,Y,Z", default_value = "0,0,0", requires = "animate",
          allow_hyphen_values = true, value_parser = parse_offset)]
    pub offset: [f32; 3],
}

/// Loads a character, printing what the loader left out.
pub fn load(source: &CharacterSource) -> anyhow::Result<Character> {
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

pub fn inspect(args: InspectArgs) -> anyhow::Result<()> {
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
            model: args.skinning,
            refit_rule: args.refit_rule,
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
        "  refit: clip {:?}, {:?} skinning, {:?} rule, {} frames at {} fps, {} nodes",
        r.clip, r.model, r.refit_rule, r.frames, r.fps, r.nodes
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
