//! `cornertree figures`: recordings of the paper's Figures 1-3 (the work is
//! in `record::figures`).

use super::emit;

#[derive(clap::Args)]
pub struct FiguresArgs {
    /// Directory to write figure1_dedup.rrd, figure2_sphere_division.rrd and
    /// figure3_corner_tree.rrd into (created if needed).
    #[arg(long, default_value = "recordings/figures")]
    pub out: std::path::PathBuf,
}

pub fn figures(args: FiguresArgs) -> anyhow::Result<()> {
    let written = cornertree_workbench::record::figures::write_figures(&args.out)?;
    let mut out = String::new();
    for f in &written {
        out += &format!("{}: {}\n", f.name, f.path.display());
    }
    emit(&out)
}
