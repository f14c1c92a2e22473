//! `cornertree tables`: Table 1 and each method's environment hierarchy
//! (command-line plumbing; the work is in `report::tables`).

use cornertree::sphere_tree::BuildParams;

use super::args::parse_positive;
use super::emit;

#[derive(clap::Args)]
pub struct TablesArgs {
    /// Print one JSON object on stdout instead of the tables.
    #[arg(long)]
    pub json: bool,
    /// A triangle is big when its longest edge exceeds this many metres; big
    /// triangles get sphere division, quaternary or corner-tree hierarchies.
    #[arg(long, default_value_t = cornertree::pipeline::DEFAULT_THRESHOLD, value_parser = parse_positive)]
    pub threshold: f32,
    /// Seed of the generated rooms.
    #[arg(long, default_value_t = 0)]
    pub seed: u64,
    /// Also cost a static glTF scene of your own (every mesh, node transforms
    /// applied; degenerate triangles are reported and left out).
    #[arg(long)]
    pub scene: Option<std::path::PathBuf>,
}

pub fn tables(args: TablesArgs) -> anyhow::Result<()> {
    use cornertree_workbench::environment::{living_room, museum};
    let (m, l) = (museum(args.seed), living_room(args.seed));
    let scene = match &args.scene {
        Some(path) => {
            let (env, report) = cornertree_workbench::environment::load_scene(path)?;
            if report.degenerate_removed > 0 {
                eprintln!(
                    "note: {}: {} degenerate triangles left out (first: {:?})",
                    path.display(),
                    report.degenerate_removed,
                    report.first_degenerate
                );
            }
            Some(env)
        }
        None => None,
    };
    let mut rooms = vec![("museum", &m), ("living_room", &l)];
    if let Some(env) = &scene {
        rooms.push(("scene", env));
    }
    let report = cornertree_workbench::report::tables::tables(
        &rooms,
        args.threshold,
        BuildParams::default(),
    );
    if args.json {
        emit(&(serde_json::to_string(&report)? + "\n"))
    } else {
        emit(&report.to_string())
    }
}
