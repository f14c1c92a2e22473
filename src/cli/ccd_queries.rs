//! `cornertree ccd-queries`: the elementary CCD kernels on query files with
//! exact answers (command-line plumbing; reading is in
//! `io::ccd_queries`, the work and the report in `report::ccd_queries`).

use std::path::PathBuf;

use anyhow::Context;

use cornertree::geometry::ccd_root_finder::DEFAULT_TOLERANCE;
use cornertree_workbench::io::ccd_queries::{QueryKind, find_query_files, read_queries};
use cornertree_workbench::report::ccd_queries::{QueryFile, evaluate};

#[derive(clap::Args)]
pub struct CcdQueriesArgs {
    /// Query files (CSV) or directories, walked for *.csv files (e.g.
    /// assets/ccd-queries).
    #[arg(required = true)]
    pub paths: Vec<PathBuf>,
    /// The report as JSON: `{"tolerance", "files": [{path, kind, queries,
    /// positives, false_negatives, false_positives, unresolved,
    /// false_positive_within, ns_per_query}, ...], "kinds": [...], "total":
    /// {...}}`. Written to FILE (the table still printed), or, without FILE,
    /// printed on stdout instead of the table. Put it after the PATHs.
    #[arg(long, value_name = "FILE", num_args = 0..=1)]
    pub json: Option<Option<PathBuf>>,
    /// Query kind of every file (default: the name of each file's parent
    /// folder, vertex-face or edge-edge).
    #[arg(long, value_parser = parse_kind)]
    pub kind: Option<QueryKind>,
    /// Tolerance δ (length): a positive answer certifies that the
    /// primitives come within δ of each other in every coordinate.
    #[arg(long, default_value_t = DEFAULT_TOLERANCE, value_parser = parse_tolerance)]
    pub tolerance: f64,
}

fn parse_kind(s: &str) -> Result<QueryKind, String> {
    QueryKind::from_name(s).ok_or_else(|| format!("{s:?}: expected vertex-face or edge-edge"))
}

fn parse_tolerance(s: &str) -> Result<f64, String> {
    match s.parse::<f64>() {
        Ok(x) if x.is_finite() && x > 0.0 => Ok(x),
        Ok(_) => Err("must be a positive number".into()),
        Err(e) => Err(format!("{e}")),
    }
}

pub fn ccd_queries(args: CcdQueriesArgs) -> anyhow::Result<String> {
    let mut files = Vec::new();
    for (path, kind) in find_query_files(&args.paths, args.kind)? {
        let queries = read_queries(&path)?;
        files.push(QueryFile {
            path,
            kind,
            queries,
        });
    }
    let report = evaluate(&files, args.tolerance);
    match &args.json {
        Some(None) => Ok(serde_json::to_string(&report)? + "\n"),
        Some(Some(path)) => {
            std::fs::write(path, serde_json::to_string(&report)? + "\n")
                .with_context(|| format!("{}: cannot write the report", path.display()))?;
            Ok(report.to_string())
        }
        None => Ok(report.to_string()),
    }
}
