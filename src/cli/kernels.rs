//! `cornertree kernels`: operations charged and paid per kernel, and time per
//! test (command-line plumbing; the work is in `report::kernels`).

use cornertree_workbench::report::kernels::measure_kernels;

#[derive(clap::Args)]
pub struct KernelsArgs {
    /// Inputs per kernel (a third each disjoint, near touching, intersecting).
    #[arg(long, default_value_t = 100_000, value_parser = parse_pairs)]
    pub pairs: usize,
    /// Print `{"kernels": [{name, charged_operations (null for the
    /// continuous kernels), inputs, paid_operations_mean,
    /// paid_operations_min, paid_operations_max, paid_arithmetic_mean,
    /// paid_comparisons_mean, ns_per_test, positives}, ...]}` (plus `pairs`,
    /// `seed`, `narrow_phase`) on stdout instead of the table.
    #[arg(long)]
    pub json: bool,
}

fn parse_pairs(s: &str) -> Result<usize, String> {
    match s.parse::<usize>() {
        Ok(0) => Err("must be at least 1".into()),
        Ok(n) => Ok(n),
        Err(e) => Err(format!("{e}")),
    }
}

pub fn kernels(args: KernelsArgs) -> anyhow::Result<String> {
    let report = measure_kernels(args.pairs).map_err(anyhow::Error::msg)?;
    if args.json {
        Ok(serde_json::to_string(&report)? + "\n")
    } else {
        Ok(report.to_string())
    }
}
