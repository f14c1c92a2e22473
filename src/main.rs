//! `cornertree` command-line front: parse, call into the library, print.

use std::process::ExitCode;

mod cli;

use clap::{Parser, Subcommand};
use cli::emit;
use cornertree_workbench::record::target::RecordingTarget;

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
    /// Load a mesh or character, de-duplicate its edges, build and validate its
    /// sphere tree, and print what came out. With --animate, play a clip and
    /// check that refit spheres hold the skinned vertices.
    Inspect(cli::inspect::InspectArgs),
    /// Print Table 1 (spheres per level of corner-trees and quaternary trees,
    /// counted on trees built over a real triangle) and, for the museum and the
    /// living room, every method's environment hierarchy: nodes and bytes.
    Tables(cli::tables::TablesArgs),
    /// Play a scenario through each method: per frame, pose and skin the
    /// character, refit its spheres on demand while traversing the
    /// environment's tree, run the narrow phase, and count tests, operations,
    /// refits and time; print the summary table (maximum and mean per frame).
    Run(cli::run::RunArgs),
    /// Play a scenario through every method on the same frames against the
    /// ground truth (exact pairs on parry's broad phase) and print one table
    /// like the paper's Tables 2-3 plus precision and recall. No recording.
    Compare(cli::compare::CompareArgs),
    /// Measure each method's cost per frame against the baseline a Rust user
    /// would write with parry3d (a TriMesh moved every frame, BVH leaf pairs
    /// against the environment, parry's triangle test), in one run, and print
    /// the ratios. De-duplication is off unless --dedup.
    Bench(cli::bench::BenchArgs),
    /// Per-frame cost against character size (generated humanoids of about
    /// 3k, 10k, 44k and 100k vertices) and against room size (the base room
    /// re-tessellated to about 10k, 133k and 500k vertices), each method
    /// beside the parry3d baseline as in `bench`; prints the markdown tables
    /// of docs/performance-journal.md ("Scaling").
    Scaling(cli::scaling::ScalingArgs),
    /// Write recordings that reproduce the paper's Figures 1-3: a triangle left
    /// out by edge de-duplication among its three neighbours; a big triangle's
    /// enclosing sphere and its four sub-spheres; a corner-tree level by level.
    Figures(cli::figures::FiguresArgs),
    /// For each kernel of the paper's operation model (sphere-sphere,
    /// plane-sphere plain and prepared, the Tropp and the edge-crossing
    /// triangle-triangle tests), run on a fixed seeded mix of disjoint,
    /// near-touching and intersecting inputs: the operations the paper
    /// charges, the operations really executed (arithmetic and comparisons,
    /// counted by a counting number type: mean, min, max) and nanoseconds per
    /// test. Then the continuous tests (vertex-face, edge-edge,
    /// triangle-triangle over a step of linear motion; docs/ccd.md) on up to
    /// 5,000 moving pairs, which the paper charges nothing. Timings are only
    /// meaningful in a release build (`cargo run --release -- kernels`).
    Kernels(cli::kernels::KernelsArgs),
    /// The experiment behind docs/results.md: when does the plane-sphere
    /// method read as §5 writes it (Algorithm 1 where a character leaf meets
    /// a corner-tree leaf) need as few tests as Tables 2-3 report? Plays each
    /// base scenario with one condition changed at a time: where the
    /// character walks along the big surface, how the surface is tessellated,
    /// the big-triangle threshold, edge de-duplication, the gap; prints the
    /// maximum tests and operations per frame and the largest corner-tree
    /// leaf a character leaf met, beside the paper's figures.
    PlaneSphereStudy(cli::study::StudyArgs),
    /// Continuous collision detection on query files with exact answers
    /// (the format of assets/ccd-queries: a vertex and a triangle, or two
    /// edges, every point moving on a straight line over one step): runs the
    /// conservative vertex-face and edge-edge kernels on every query and
    /// prints, per file, per kind and in total, the queries, the positives
    /// (exact answer "contact"), false negatives (contacts missed: there
    /// should be none), false positives (contact answered, none exact) and
    /// nanoseconds per query (release builds only). Each PATH is a CSV file
    /// or a directory walked for *.csv; a file's kind is its parent folder's
    /// name unless --kind is given. A malformed file stops with one line
    /// naming the file and row.
    CcdQueries(cli::ccd_queries::CcdQueriesArgs),
    /// Cast rays against a scenario's posed characters frame by frame (a
    /// hit-scan fan swept across them, a picking grid over the first):
    /// each ray's first hit from the library's query, refit and skinned on
    /// demand, checked against an exact brute-force reference, timed against
    /// parry3d (skin every vertex, update_vertices, cast) and against
    /// skinning everything and testing every triangle; one thread each. The
    /// rays, hits and the spheres refit on their way are recorded.
    Rays(cli::rays::RaysArgs),
}

fn main() -> ExitCode {
    use clap::{CommandFactory, FromArgMatches};
    let matches = Cli::command().get_matches();
    let cli = match Cli::from_arg_matches(&matches) {
        Ok(cli) => cli,
        Err(e) => e.exit(),
    };
    let result = match cli.command {
        Command::Inspect(args) => cli::inspect::inspect(args),
        Command::Tables(args) => cli::tables::tables(args),
        Command::Run(args) => {
            let sub = matches
                .subcommand_matches("run")
                .expect("the run subcommand was parsed");
            let target = cli::run::recording_target(&args, sub);
            // With --stdout the recording owns standard output; the summary
            // goes to standard error.
            let to_stderr = matches!(target, RecordingTarget::Rerun(_, true));
            cli::run::run(args, target).and_then(|out| {
                if to_stderr {
                    eprint!("{out}");
                    Ok(())
                } else {
                    emit(&out)
                }
            })
        }
        Command::Figures(args) => cli::figures::figures(args),
        Command::Bench(args) => cli::bench::bench(args).and_then(|out| emit(&out)),
        Command::Scaling(args) => cli::scaling::scaling(args).and_then(|out| emit(&out)),
        Command::Compare(args) => cli::compare::compare(args).and_then(|out| emit(&out)),
        Command::Kernels(args) => cli::kernels::kernels(args).and_then(|out| emit(&out)),
        Command::PlaneSphereStudy(args) => cli::study::study(args).and_then(|out| emit(&out)),
        Command::Rays(args) => cli::rays::rays(args).and_then(|out| emit(&out)),
        Command::CcdQueries(args) => cli::ccd_queries::ccd_queries(args).and_then(|out| emit(&out)),
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
