//! Reading CCD query files: elementary continuous collision queries with
//! exact answers, in the CSV format of the benchmark of Wang et al. (ACM
//! TOG 40(5), 2021) described in `assets/ccd-queries/README.md`.
//!
//! A file holds `8·n` rows for `n` queries, 7 integer columns per row:
//! numerator and denominator of x, y and z (exact rationals, up to 112
//! bits: read as `i128`), then the exact answer (1: the primitives touch at
//! some `t ∈ [0, 1]`; 0: never), the same on all 8 rows of a query. The rows
//! of a query are the four points at `t = 0`, then the same four at
//! `t = 1`: `p, a, b, c` for vertex–face (point `p`, triangle `abc`);
//! `a₀, a₁, b₀, b₁` for edge–edge. A file's kind comes from its parent
//! folder's name (`vertex-face`, `edge-edge`) unless given.
//!
//! Errors name the file and the row (1-based line number); blank lines are
//! skipped.

use std::fmt;
use std::path::{Path, PathBuf};

/// Which elementary query a file holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum QueryKind {
    VertexFace,
    EdgeEdge,
}

impl QueryKind {
    /// Both kinds, in report order.
    pub const ALL: [QueryKind; 2] = [QueryKind::VertexFace, QueryKind::EdgeEdge];

    /// The folder name and `--kind` value.
    pub fn name(self) -> &'static str {
        match self {
            QueryKind::VertexFace => "vertex-face",
            QueryKind::EdgeEdge => "edge-edge",
        }
    }

    /// The kind a folder (or `--kind` value) names.
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|k| k.name() == name)
    }
}

impl fmt::Display for QueryKind {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// An exact rational `num / den` (`den ≠ 0`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rational {
    pub num: i128,
    pub den: i128,
}

impl Rational {
    /// The nearest-ish `f64`: `fl(fl(num) / fl(den))`, within a relative
    /// error of `geometry::ccd_root_finder::RATIONAL_ROUNDING` (three
    /// roundings).
    pub fn to_f64(self) -> f64 {
        self.num as f64 / self.den as f64
    }
}

/// One query: eight points (four at `t = 0`, the same four at `t = 1`) and
/// its exact answer.
#[derive(Clone, Debug, PartialEq)]
pub struct CcdQuery {
    pub points: [[Rational; 3]; 8],
    /// Whether the primitives touch during the step (the exact answer).
    pub colliding: bool,
    /// Line number of its first row.
    pub row: usize,
}

impl CcdQuery {
    /// The four points at `t = 0` and at `t = 1`, rounded to `f64`.
    pub fn positions(&self) -> ([[f64; 3]; 4], [[f64; 3]; 4]) {
        let p = |i: usize| self.points[i].map(Rational::to_f64);
        (std::array::from_fn(p), std::array::from_fn(|i| p(i + 4)))
    }
}

/// What can be wrong with query files, with the file and row.
#[derive(Debug, thiserror::Error)]
pub enum CcdQueryError {
    #[error("{path}: {cause}")]
    Io {
        path: PathBuf,
        cause: std::io::Error,
    },
    #[error("{path}: row {row}: expected 7 comma-separated integers, found {found} field(s)")]
    Columns {
        path: PathBuf,
        row: usize,
        found: usize,
    },
    #[error("{path}: row {row}, column {column}: {text:?} is not an integer ({reason})")]
    Integer {
        path: PathBuf,
        row: usize,
        column: usize,
        text: String,
        reason: std::num::ParseIntError,
    },
    #[error("{path}: row {row}, column {column}: denominator 0")]
    ZeroDenominator {
        path: PathBuf,
        row: usize,
        column: usize,
    },
    #[error("{path}: row {row}, column 7: answer {value} is neither 0 nor 1")]
    Answer {
        path: PathBuf,
        row: usize,
        value: i128,
    },
    #[error(
        "{path}: row {row}: answer {value} differs from the answer {first} of the query's first row {first_row}"
    )]
    MixedAnswer {
        path: PathBuf,
        row: usize,
        value: u8,
        first: u8,
        first_row: usize,
    },
    #[error(
        "{path}: row {row}: {rows} rows in all, not a multiple of 8 (8 rows per query; the last query is cut short)"
    )]
    RowCount {
        path: PathBuf,
        row: usize,
        rows: usize,
    },
    #[error("{path}: no queries (empty file)")]
    Empty { path: PathBuf },
    #[error(
        "{path}: unknown query kind: the parent folder {folder:?} is neither vertex-face nor edge-edge (give --kind)"
    )]
    UnknownKind { path: PathBuf, folder: String },
    #[error("{path}: no *.csv files under this directory")]
    NoFiles { path: PathBuf },
}

/// Reads and parses one query file.
pub fn read_queries(path: &Path) -> Result<Vec<CcdQuery>, CcdQueryError> {
    let text = std::fs::read_to_string(path).map_err(|cause| CcdQueryError::Io {
        path: path.to_owned(),
        cause,
    })?;
    parse_queries(&text, path)
}

/// Parses the text of a query file (`path` names it in errors).
pub fn parse_queries(text: &str, path: &Path) -> Result<Vec<CcdQuery>, CcdQueryError> {
    let mut queries = Vec::new();
    let mut rows: Vec<(usize, [Rational; 3], u8)> = Vec::with_capacity(8);
    let mut last_row = 0;
    let mut count = 0;
    for (i, line) in text.lines().enumerate() {
        let row = i + 1;
        if line.trim().is_empty() {
            continue;
        }
        let (point, answer) = parse_row(line, row, path)?;
        if let Some(&(first_row, _, first)) = rows.first()
            && answer != first
        {
            return Err(CcdQueryError::MixedAnswer {
                path: path.to_owned(),
                row,
                value: answer,
                first,
                first_row,
            });
        }
        rows.push((row, point, answer));
        last_row = row;
        count += 1;
        if rows.len() == 8 {
            queries.push(CcdQuery {
                points: std::array::from_fn(|k| rows[k].1),
                colliding: rows[0].2 == 1,
                row: rows[0].0,
            });
            rows.clear();
        }
    }
    if !rows.is_empty() {
        return Err(CcdQueryError::RowCount {
            path: path.to_owned(),
            row: last_row,
            rows: count,
        });
    }
    if queries.is_empty() {
        return Err(CcdQueryError::Empty {
            path: path.to_owned(),
        });
    }
    Ok(queries)
}

/// One row: a point (three rationals) and the answer.
fn parse_row(line: &str, row: usize, path: &Path) -> Result<([Rational; 3], u8), CcdQueryError> {
    let fields: Vec<&str> = line.split(',').map(str::trim).collect();
    if fields.len() != 7 {
        return Err(CcdQueryError::Columns {
            path: path.to_owned(),
            row,
            found: fields.len(),
        });
    }
    let mut values = [0i128; 7];
    for (column, (v, text)) in values.iter_mut().zip(&fields).enumerate() {
        *v = text.parse().map_err(|reason| CcdQueryError::Integer {
            path: path.to_owned(),
            row,
            column: column + 1,
            text: text.to_string(),
            reason,
        })?;
    }
    for column in [2, 4, 6] {
        if values[column - 1] == 0 {
            return Err(CcdQueryError::ZeroDenominator {
                path: path.to_owned(),
                row,
                column,
            });
        }
    }
    let answer = match values[6] {
        0 => 0,
        1 => 1,
        value => {
            return Err(CcdQueryError::Answer {
                path: path.to_owned(),
                row,
                value,
            });
        }
    };
    let r = |k: usize| Rational {
        num: values[2 * k],
        den: values[2 * k + 1],
    };
    Ok(([r(0), r(1), r(2)], answer))
}

/// The query files named by `paths` (files, or directories walked for
/// `*.csv`, in path order), each with its kind: `kind` if given, else its
/// parent folder's name.
pub fn find_query_files(
    paths: &[PathBuf],
    kind: Option<QueryKind>,
) -> Result<Vec<(PathBuf, QueryKind)>, CcdQueryError> {
    let mut out = Vec::new();
    for path in paths {
        let meta = std::fs::metadata(path).map_err(|cause| CcdQueryError::Io {
            path: path.clone(),
            cause,
        })?;
        let files = if meta.is_dir() {
            let mut files = Vec::new();
            walk_csv(path, &mut files)?;
            if files.is_empty() {
                return Err(CcdQueryError::NoFiles { path: path.clone() });
            }
            files.sort();
            files
        } else {
            vec![path.clone()]
        };
        for file in files {
            let k = match kind {
                Some(k) => k,
                None => kind_of(&file)?,
            };
            out.push((file, k));
        }
    }
    Ok(out)
}

/// The kind named by a file's parent folder.
fn kind_of(file: &Path) -> Result<QueryKind, CcdQueryError> {
    let folder = file
        .parent()
        .and_then(Path::file_name)
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_default();
    QueryKind::from_name(&folder).ok_or_else(|| CcdQueryError::UnknownKind {
        path: file.to_owned(),
        folder,
    })
}

/// Every `*.csv` file under `dir`.
fn walk_csv(dir: &Path, out: &mut Vec<PathBuf>) -> Result<(), CcdQueryError> {
    let io = |cause| CcdQueryError::Io {
        path: dir.to_owned(),
        cause,
    };
    for entry in std::fs::read_dir(dir).map_err(io)? {
        let path = entry.map_err(io)?.path();
        if path.is_dir() {
            walk_csv(&path, out)?;
        } else if path.extension().is_some_and(|e| e == "csv") {
            out.push(path);
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Vec<CcdQuery>, CcdQueryError> {
        parse_queries(text, Path::new("q.csv"))
    }

    fn query_text(answer: u8) -> String {
        (0..8)
            .map(|i| format!("{i},1,-{i},3,1,2,{answer}\n"))
            .collect()
    }

    #[test]
    fn reads_two_queries() {
        let text = query_text(1) + "\n" + &query_text(0);
        let q = parse(&text).unwrap();
        assert_eq!(q.len(), 2);
        assert!(q[0].colliding && !q[1].colliding);
        assert_eq!((q[0].row, q[1].row), (1, 10));
        let (s, e) = q[0].positions();
        assert_eq!(s[1], [1.0, -1.0 / 3.0, 0.5]);
        assert_eq!(e[3], [7.0, -7.0 / 3.0, 0.5]);
    }

    #[test]
    fn big_numerators_are_exact_integers() {
        let big = "5192296858534827628530496329220095";
        let text = (0..8)
            .map(|_| format!("{big},1,1,{big},0,1,0\n"))
            .collect::<String>();
        let q = parse(&text).unwrap();
        assert_eq!(q[0].points[0][0].num, 5192296858534827628530496329220095);
    }

    #[test]
    fn errors_name_the_row() {
        let msg = |t: &str| parse(t).unwrap_err().to_string();
        let mut t = query_text(0);
        t = t.replacen("3,1,2,0\n", "0,1,2,0\n", 1);
        assert_eq!(msg(&t), "q.csv: row 1, column 4: denominator 0");
        let t = query_text(0).replacen("1,2,0\n", "1,2\n", 1);
        assert!(msg(&t).contains("row 1: expected 7"), "{}", msg(&t));
        let t = query_text(0).replacen("-1,3", "-1x,3", 1);
        assert!(
            msg(&t).starts_with("q.csv: row 2, column 3: \"-1x\""),
            "{}",
            msg(&t)
        );
        let t = query_text(0) + &query_text(0)[..15];
        assert!(msg(&t).contains("row 9: 9 rows in all"), "{}", msg(&t));
        let t = query_text(0)
            .replacen(",0\n", ",1\n", 2)
            .replacen(",1\n", ",0\n", 1);
        assert!(msg(&t).contains("row 2: answer 1 differs"), "{}", msg(&t));
        let t = query_text(2);
        assert!(msg(&t).contains("answer 2 is neither"), "{}", msg(&t));
        assert_eq!(msg(""), "q.csv: no queries (empty file)");
    }

    #[test]
    fn kinds_from_folders() {
        let f = |p: &str| kind_of(Path::new(p)).map_err(|e| e.to_string());
        assert_eq!(f("x/vertex-face/a.csv"), Ok(QueryKind::VertexFace));
        assert_eq!(f("edge-edge/a.csv"), Ok(QueryKind::EdgeEdge));
        assert!(f("x/other/a.csv").unwrap_err().contains("\"other\""));
    }
}
