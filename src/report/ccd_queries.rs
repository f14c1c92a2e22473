//! `cornertree ccd-queries`: the elementary CCD kernels
//! (`geometry::ccd_vertex_face`, `geometry::ccd_edge_edge`) on query files
//! with exact answers, counted against those answers and timed.
//!
//! Each query's rationals are rounded to `f64` once, before timing
//! ([`CcdParams::input_error`] set to the rounding's bound, so the kernels
//! stay conservative for the exact queries). Per file: queries, positives
//! (exact answer 1), false negatives, false positives and nanoseconds per
//! query (best of [`ROUNDS`] passes over the file); then per kind and in
//! total.

use std::fmt;
use std::hint::black_box;
use std::path::PathBuf;
use std::time::Instant;

use serde::Serialize;

use crate::io::ccd_queries::{CcdQuery, QueryKind};
use cornertree::geometry::ccd_edge_edge::edge_edge;
use cornertree::geometry::ccd_root_finder::{CcdParams, Impact, RATIONAL_ROUNDING};
use cornertree::geometry::ccd_vertex_face::vertex_face;

/// Timed passes per file; the best is kept (load only ever adds time).
pub const ROUNDS: usize = 5;

/// A file of queries, read.
pub struct QueryFile {
    pub path: PathBuf,
    pub kind: QueryKind,
    pub queries: Vec<CcdQuery>,
}

/// Counts over a set of queries.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct Tally {
    pub queries: usize,
    /// Queries whose exact answer is "contact".
    pub positives: usize,
    /// Contacts the kernel missed (must be 0).
    pub false_negatives: usize,
    /// "Contact" answers where the exact answer is none.
    pub false_positives: usize,
    /// Positive answers given at the search's limits (budget or finest
    /// boxes) rather than by an accepted box.
    pub unresolved: usize,
    /// The largest certified bound over the false positives: each false
    /// positive's primitives come within it of each other in every
    /// coordinate at some time of the step (0 without false positives).
    pub false_positive_within: f64,
    /// Nanoseconds per query (best pass).
    pub ns_per_query: f64,
    /// The best pass's total, nanoseconds (to sum tallies).
    #[serde(skip)]
    ns_total: f64,
}

impl Tally {
    fn add(&mut self, o: &Tally) {
        self.queries += o.queries;
        self.positives += o.positives;
        self.false_negatives += o.false_negatives;
        self.false_positives += o.false_positives;
        self.unresolved += o.unresolved;
        self.false_positive_within = self.false_positive_within.max(o.false_positive_within);
        self.ns_total += o.ns_total;
        self.ns_per_query = self.ns_total / self.queries.max(1) as f64;
    }

    /// Queries whose exact answer is "no contact".
    pub fn negatives(&self) -> usize {
        self.queries - self.positives
    }
}

/// One file's counts.
#[derive(Clone, Debug, Serialize)]
pub struct FileTally {
    pub path: String,
    pub kind: &'static str,
    #[serde(flatten)]
    pub tally: Tally,
}

/// One kind's counts over all files.
#[derive(Clone, Debug, Serialize)]
pub struct KindTally {
    pub kind: &'static str,
    #[serde(flatten)]
    pub tally: Tally,
}

/// The whole report.
#[derive(Clone, Debug, Serialize)]
pub struct CcdQueriesReport {
    pub tolerance: f64,
    pub files: Vec<FileTally>,
    /// Per kind present.
    pub kinds: Vec<KindTally>,
    pub total: Tally,
}

/// The kernels' parameters for exact rational queries at this tolerance.
pub fn params_for(tolerance: f64) -> CcdParams {
    CcdParams {
        tolerance,
        input_error: RATIONAL_ROUNDING,
        ..CcdParams::default()
    }
}

/// The kernel of a query kind on rounded positions.
pub fn answer(
    kind: QueryKind,
    start: &[[f64; 3]; 4],
    end: &[[f64; 3]; 4],
    params: &CcdParams,
) -> Option<Impact> {
    match kind {
        QueryKind::VertexFace => vertex_face(start, end, params),
        QueryKind::EdgeEdge => edge_edge(start, end, params),
    }
}

/// Runs every file's queries at `tolerance`.
pub fn evaluate(files: &[QueryFile], tolerance: f64) -> CcdQueriesReport {
    let params = params_for(tolerance);
    let mut report = CcdQueriesReport {
        tolerance,
        files: Vec::with_capacity(files.len()),
        kinds: Vec::new(),
        total: Tally::default(),
    };
    for file in files {
        let tally = evaluate_file(file, &params);
        report.total.add(&tally);
        let kind = file.kind.name();
        match report.kinds.iter_mut().find(|k| k.kind == kind) {
            Some(k) => k.tally.add(&tally),
            None => {
                let mut t = Tally::default();
                t.add(&tally);
                report.kinds.push(KindTally { kind, tally: t });
            }
        }
        report.files.push(FileTally {
            path: file.path.display().to_string(),
            kind,
            tally,
        });
    }
    report
        .kinds
        .sort_by_key(|k| QueryKind::ALL.iter().position(|q| q.name() == k.kind));
    report
}

fn evaluate_file(file: &QueryFile, params: &CcdParams) -> Tally {
    let inputs: Vec<_> = file
        .queries
        .iter()
        .map(|q| (q.positions(), q.colliding))
        .collect();
    let mut t = Tally {
        queries: inputs.len(),
        ..Tally::default()
    };
    for ((start, end), colliding) in &inputs {
        let a = answer(file.kind, start, end, params);
        t.positives += *colliding as usize;
        match (a, colliding) {
            (None, true) => t.false_negatives += 1,
            (Some(i), false) => {
                t.false_positives += 1;
                t.false_positive_within = t.false_positive_within.max(i.within);
            }
            _ => {}
        }
        t.unresolved += a.is_some_and(|i| !i.resolved) as usize;
    }
    let mut best = f64::INFINITY;
    for _ in 0..ROUNDS {
        let t0 = Instant::now();
        let mut n = 0usize;
        for ((start, end), _) in &inputs {
            n += answer(file.kind, black_box(start), black_box(end), params).is_some() as usize;
        }
        black_box(n);
        best = best.min(t0.elapsed().as_nanos() as f64);
    }
    t.ns_total = best;
    t.ns_per_query = best / t.queries.max(1) as f64;
    t
}

impl fmt::Display for CcdQueriesReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "CCD queries against their exact answers; tolerance {:e} (a positive answer certifies \
             the primitives come within it in every coordinate, unless unresolved)",
            self.tolerance
        )?;
        let width = self
            .files
            .iter()
            .map(|x| x.path.chars().count())
            .max()
            .unwrap_or(0)
            .max(11);
        let row = |f: &mut fmt::Formatter<'_>, name: &str, kind: &str, t: &Tally| {
            writeln!(
                f,
                "{:<width$} {:<11} {:>8} {:>9} {:>5} {:>6} {:>10} {:>10.1}",
                name,
                kind,
                t.queries,
                t.positives,
                t.false_negatives,
                t.false_positives,
                t.unresolved,
                t.ns_per_query
            )
        };
        writeln!(
            f,
            "{:<width$} {:<11} {:>8} {:>9} {:>5} {:>6} {:>10} {:>10}",
            "file", "kind", "queries", "positives", "FN", "FP", "unresolved", "ns/query"
        )?;
        for x in &self.files {
            row(f, &x.path, x.kind, &x.tally)?;
        }
        for k in &self.kinds {
            row(f, "all files", k.kind, &k.tally)?;
        }
        row(f, "total", "", &self.total)?;
        let t = &self.total;
        writeln!(
            f,
            "false negatives {} of {} positives; false positives {} of {} negatives ({:.2}%), \
             each within {:.3e} in every coordinate",
            t.false_negatives,
            t.positives,
            t.false_positives,
            t.negatives(),
            100.0 * t.false_positives as f64 / t.negatives().max(1) as f64,
            t.false_positive_within
        )?;
        writeln!(
            f,
            "positives: exact answer 1; FN/FP against the exact answers; unresolved: positive \
             answers at the search's limits; ns/query: best of {ROUNDS} passes, meaningful in a \
             release build only"
        )
    }
}
