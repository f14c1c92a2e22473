//! The CCD kernels on the queries with exact answers of
//! `assets/ccd-queries` (Wang et al.'s benchmark, handcrafted part): no
//! contact missed, at most 5 % of the non-contacts reported, and every
//! false positive within the certified tolerance.

use std::path::PathBuf;

use cornertree::geometry::ccd_root_finder::DEFAULT_TOLERANCE;
use cornertree_workbench::io::ccd_queries::{QueryKind, find_query_files, read_queries};
use cornertree_workbench::report::ccd_queries::{QueryFile, answer, evaluate, params_for};

fn queries_dir() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/ccd-queries")
}

fn read_all() -> Vec<QueryFile> {
    let dir = queries_dir();
    assert!(dir.is_dir(), "{} is missing", dir.display());
    find_query_files(&[dir], None)
        .unwrap()
        .into_iter()
        .map(|(path, kind)| QueryFile {
            queries: read_queries(&path).unwrap(),
            path,
            kind,
        })
        .collect()
}

/// Exact answers counted straight from the files' last column.
fn colliding_rows(files: &[QueryFile]) -> usize {
    files
        .iter()
        .map(|f| {
            let text = std::fs::read_to_string(&f.path).unwrap();
            text.lines().filter(|l| l.trim().ends_with(",1")).count()
        })
        .sum()
}

#[test]
fn no_contact_missed_and_few_false_positives() {
    let files = read_all();
    assert!(files.iter().any(|f| f.kind == QueryKind::VertexFace));
    assert!(files.iter().any(|f| f.kind == QueryKind::EdgeEdge));
    let report = evaluate(&files, DEFAULT_TOLERANCE);
    let t = &report.total;
    assert_eq!(
        t.queries,
        files.iter().map(|f| f.queries.len()).sum::<usize>()
    );
    assert_eq!(8 * t.positives, colliding_rows(&files));
    assert!(t.positives > 0);
    assert_eq!(t.false_negatives, 0, "{report}");
    assert!(
        t.false_positives * 20 <= t.negatives(),
        "{} false positives of {} negatives\n{report}",
        t.false_positives,
        t.negatives()
    );
    // Every false positive certified within the tolerance.
    assert_eq!(t.unresolved, 0, "{report}");
    assert!(t.false_positive_within <= DEFAULT_TOLERANCE, "{report}");
    // Per-kind tallies add up to the total.
    let sum: usize = report.kinds.iter().map(|k| k.tally.false_positives).sum();
    assert_eq!(sum, t.false_positives);
}

/// The time of impact is a lower bound of the first contact, so it is not
/// after the last contact: the reversed step (end to start) first touches
/// at `1 − last`, so its own lower bound `r` gives `toi ≤ 1 − r` on every
/// colliding query.
#[test]
fn time_of_impact_is_not_after_the_last_contact() {
    let params = params_for(DEFAULT_TOLERANCE);
    let mut checked = 0;
    for f in read_all() {
        for q in f.queries.iter().filter(|q| q.colliding) {
            let (start, end) = q.positions();
            let first = answer(f.kind, &start, &end, &params).expect("no miss");
            let reversed = answer(f.kind, &end, &start, &params).expect("no miss");
            assert!(
                first.toi <= 1.0 - reversed.toi,
                "{}: row {}: first contact bound {} after the last contact bound {}",
                f.path.display(),
                q.row,
                first.toi,
                1.0 - reversed.toi
            );
            checked += 1;
        }
    }
    assert!(checked > 0);
}
