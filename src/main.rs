//! `cornertree` command-line front: parse, call into the library, print.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::{Parser, Subcommand};
use cornertree::io::load_static_mesh;
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
    /// Load a mesh, de-duplicate its edges, build and validate its sphere tree,
    /// and print what came out.
    Inspect(InspectArgs),
}

#[derive(clap::Args)]
struct InspectArgs {
    /// A glTF 2.0 file (.gltf or .glb); every triangle of its default scene is
    /// taken in its static pose (skinned meshes in bind pose).
    file: PathBuf,
    /// Print one JSON object on stdout instead of the text summary.
    #[arg(long)]
    json: bool,
    /// Keep every triangle (turn edge de-duplication, paper §4, off).
    #[arg(long)]
    no_dedup: bool,
    /// Collapse a child sphere into its parent when its radius exceeds this
    /// fraction of the parent's (1 keeps the binary tree).
    #[arg(long, default_value_t = BuildParams::default().collapse_ratio, value_parser = parse_ratio)]
    collapse_ratio: f32,
}

fn parse_ratio(s: &str) -> Result<f32, String> {
    let r: f32 = s.parse().map_err(|e| format!("{e}"))?;
    if r.is_finite() && r > 0.0 { Ok(r) } else { Err("must be a positive number".into()) }
}

fn inspect(args: InspectArgs) -> anyhow::Result<()> {
    let (mesh, load) = load_static_mesh(&args.file)?;
    for note in &load.skipped {
        eprintln!("note: {}: {note}", args.file.display());
    }
    let options = InspectOptions {
        dedup: !args.no_dedup,
        build: BuildParams { collapse_ratio: args.collapse_ratio },
    };
    let source = args.file.display().to_string();
    let (report, _tree) = inspect_mesh(&source, &mesh, options)
        .with_context(|| format!("{source}: sphere tree failed validation"))?;
    if args.json {
        println!("{}", serde_json::to_string(&report)?);
    } else {
        print!("{report}");
    }
    Ok(())
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Inspect(args) => inspect(args),
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
