//! `cornertree ccd-queries`: the documented JSON on a directory of query
//! files, kinds from folders or `--kind`, and one-line errors naming the
//! file and row for bad input.

use std::path::{Path, PathBuf};
use std::process::Command;

fn ccd_queries(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_cornertree"))
        .arg("ccd-queries")
        .args(args)
        .output()
        .unwrap()
}

fn temp_dir(test: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("cornertree-ccd-{test}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(path: &Path, text: &str) {
    std::fs::create_dir_all(path.parent().unwrap()).unwrap();
    std::fs::write(path, text).unwrap();
}

/// One vertex–face query: a point falling from z = 1 to z = -1 through the
/// unit right triangle at `(x, y)` (inside when `x + y ≤ 1`).
fn falling_point(x: &str, y: &str, answer: u8) -> String {
    let row = |p: [&str; 3]| format!("{},{},{},{answer}\n", p[0], p[1], p[2]);
    let tri = ["0,1,0,1,0,1", "1,1,0,1,0,1", "0,1,1,1,0,1"];
    let mut s = row([x, y, "1,1"]);
    for t in tri {
        s += &format!("{t},{answer}\n");
    }
    s += &row([x, y, "-1,1"]);
    for t in tri {
        s += &format!("{t},{answer}\n");
    }
    s
}

/// One edge–edge query: an edge along x falling through an edge along y.
fn crossing_edges(answer: u8) -> String {
    let rows = [
        "-1,1,0,1,1,1",
        "1,1,0,1,1,1",
        "0,1,-1,1,0,1",
        "0,1,1,1,0,1",
        "-1,1,0,1,-1,1",
        "1,1,0,1,-1,1",
        "0,1,-1,1,0,1",
        "0,1,1,1,0,1",
    ];
    rows.iter().map(|r| format!("{r},{answer}\n")).collect()
}

fn stderr(o: &std::process::Output) -> String {
    String::from_utf8_lossy(&o.stderr).into_owned()
}

#[test]
fn json_per_file_and_total() {
    let dir = temp_dir("json");
    let vf = falling_point("1,4", "1,4", 1) + &falling_point("3,4", "3,4", 0);
    write(&dir.join("set/vertex-face/data.csv"), &vf);
    write(&dir.join("set/edge-edge/data.csv"), &crossing_edges(1));
    write(&dir.join("set/notes.txt"), "not a query file");
    let o = ccd_queries(&[dir.to_str().unwrap(), "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    let files = v["files"].as_array().unwrap();
    assert_eq!(files.len(), 2, "{v}");
    // Walked in path order: edge-edge before vertex-face.
    assert_eq!(files[0]["kind"], "edge-edge");
    assert_eq!(files[1]["kind"], "vertex-face");
    assert_eq!(
        (files[1]["queries"].as_u64(), files[1]["positives"].as_u64()),
        (Some(2), Some(1))
    );
    let t = &v["total"];
    for key in [
        "queries",
        "positives",
        "false_negatives",
        "false_positives",
        "ns_per_query",
    ] {
        assert!(t[key].is_number(), "{key} missing: {t}");
    }
    assert_eq!(
        (t["queries"].as_u64(), t["positives"].as_u64()),
        (Some(3), Some(2))
    );
    assert_eq!(
        (t["false_negatives"].as_u64(), t["false_positives"].as_u64()),
        (Some(0), Some(0))
    );
    assert!(t["ns_per_query"].as_f64().unwrap() > 0.0);

    // A wrong answer in the file shows as a false negative / positive.
    let wrong = falling_point("1,4", "1,4", 0) + &falling_point("3,4", "3,4", 1);
    let f = dir.join("wrong.csv");
    write(&f, &wrong);
    let o = ccd_queries(&[f.to_str().unwrap(), "--kind", "vertex-face", "--json"]);
    assert!(o.status.success(), "{}", stderr(&o));
    let v: serde_json::Value = serde_json::from_slice(&o.stdout).unwrap();
    assert_eq!(v["total"]["false_positives"], 1, "{v}");
    assert_eq!(v["total"]["false_negatives"], 1, "{v}");

    // The text table; with `--json FILE` the same report goes to FILE.
    let report = dir.join("R");
    let set = dir.join("set");
    let o = ccd_queries(&[set.to_str().unwrap(), "--json", report.to_str().unwrap()]);
    let text = String::from_utf8_lossy(&o.stdout);
    assert!(
        o.status.success() && text.contains("vertex-face") && text.contains("total"),
        "{text}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    assert_eq!(v["total"]["queries"], 3, "{v}");
    assert_eq!(v["files"].as_array().unwrap().len(), 2, "{v}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every bad input: exit status 1, one line on stderr naming the file (and
/// the row where there is one), no panic.
#[test]
fn bad_input_gives_one_line_naming_file_and_row() {
    let dir = temp_dir("bad");
    let good = falling_point("1,4", "1,4", 1);
    let cases: Vec<(&str, String, Vec<&str>)> = vec![
        (
            "malformed/vertex-face/q.csv",
            good.replacen("1,4,1,4,1,1,1", "1,4,1,4,1,1", 1),
            vec!["row 1", "7"],
        ),
        (
            "short/vertex-face/q.csv",
            good.clone() + "0,1,0,1,0,1,1\n",
            vec!["row 9", "multiple of 8"],
        ),
        (
            "zero/vertex-face/q.csv",
            good.replacen("1,1,0,1,0,1,1", "1,0,0,1,0,1,1", 1),
            vec!["row 3", "column 2", "denominator 0"],
        ),
        (
            "integer/vertex-face/q.csv",
            good.replacen("0,1,1,1", "0,1,1.5,1", 1),
            vec!["row 4", "\"1.5\""],
        ),
        (
            "huge/vertex-face/q.csv",
            good.replacen(
                "1,4,1,4",
                "1,4,1,999999999999999999999999999999999999999999",
                1,
            ),
            vec!["row 1", "column 4"],
        ),
        (
            "unknown/other/q.csv",
            good.clone(),
            vec!["\"other\"", "--kind"],
        ),
        (
            "answer/vertex-face/q.csv",
            good.replacen(",1\n", ",7\n", 1),
            vec!["row 1", "neither 0 nor 1"],
        ),
        ("empty/vertex-face/q.csv", String::new(), vec!["no queries"]),
    ];
    for (name, text, expected) in &cases {
        let path = dir.join(name);
        write(&path, text);
        let o = ccd_queries(&[path.to_str().unwrap()]);
        let err = stderr(&o);
        assert_eq!(o.status.code(), Some(1), "{name}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{name}: {err}");
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(err.contains(path.to_str().unwrap()), "{name}: {err}");
        for e in expected {
            assert!(err.contains(e), "{name}: expected {e:?} in {err}");
        }
    }
    // A missing path, an empty directory, an unknown --kind.
    let missing = dir.join("missing.csv");
    let o = ccd_queries(&[missing.to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    let err = stderr(&o);
    assert!(
        err.contains("missing.csv") && err.trim_end().lines().count() == 1,
        "{err}"
    );
    // The cause once, not repeated by the error chain.
    assert_eq!(err.matches("os error").count(), 1, "{err}");
    std::fs::create_dir_all(dir.join("nothing")).unwrap();
    let o = ccd_queries(&[dir.join("nothing").to_str().unwrap()]);
    assert_eq!(o.status.code(), Some(1));
    assert!(stderr(&o).contains("no *.csv"), "{}", stderr(&o));
    let o = ccd_queries(&[dir.to_str().unwrap(), "--kind", "face-face"]);
    assert!(
        !o.status.success() && stderr(&o).contains("face-face"),
        "{}",
        stderr(&o)
    );
    let o = ccd_queries(&[dir.to_str().unwrap(), "--tolerance", "0"]);
    assert!(
        !o.status.success() && stderr(&o).contains("positive"),
        "{}",
        stderr(&o)
    );
    let _ = std::fs::remove_dir_all(&dir);
}
