//! `cornertree plane-sphere-study`: the experiment's rows as a table per
//! scenario, the paper's plane-sphere column beside them (labelled).

use std::fmt;

use crate::study::StudyRow;

use super::paper::{PaperColumn, TABLE2_MUSEUM, TABLE3_LIVING_ROOM};

/// The rows of [`crate::study::run_study`], printable.
pub struct StudyTable<'a>(pub &'a [StudyRow]);

const HEADER: [&str; 12] = [
    "factor",
    "setting",
    "surface triangles",
    "method",
    "Sph-Sph",
    "Pla-Sph",
    "Tri-Tri",
    "operations (max)",
    "operations (mean)",
    "refits",
    "largest leaf met (m)",
    "its object",
];

/// The paper's plane-sphere column for a scenario named like the shipped
/// museum or living room, if any.
fn paper_plane_sphere(scenario: &str) -> Option<(&'static str, PaperColumn)> {
    let table = if scenario.contains("museum") {
        ("Table 2", &TABLE2_MUSEUM)
    } else if scenario.contains("living") {
        ("Table 3", &TABLE3_LIVING_ROOM)
    } else {
        return None;
    };
    let column = table.1.iter().find(|(m, _)| *m == "plane-sphere")?.1;
    Some((table.0, column))
}

fn approx(n: Option<u64>) -> String {
    n.map_or_else(|| "—".into(), |n| format!("≈{}", thousands(n)))
}

/// `1234567` as `1,234,567`.
pub fn thousands(n: u64) -> String {
    let s = n.to_string();
    let mut out = String::new();
    for (i, ch) in s.chars().enumerate() {
        if i > 0 && (s.len() - i).is_multiple_of(3) {
            out.push(',');
        }
        out.push(ch);
    }
    out
}

impl StudyTable<'_> {
    fn cells(r: &StudyRow) -> [String; 12] {
        [
            format!("{:?}", r.factor).to_lowercase(),
            r.setting.clone(),
            thousands(r.surface_triangles as u64),
            r.method.name().into(),
            thousands(r.sphere_sphere_max),
            thousands(r.plane_sphere_max),
            thousands(r.tri_tri_max),
            thousands(r.operations_max),
            thousands(r.operations_mean.round() as u64),
            thousands(r.refits_max),
            format!("{:.2}", r.largest_division_leaf_met),
            if r.largest_leaf_object.is_empty() {
                "—".into()
            } else {
                r.largest_leaf_object.clone()
            },
        ]
    }

    /// Scenarios in order of first appearance, each with its rows and the
    /// paper's line.
    #[allow(clippy::type_complexity)]
    fn groups(&self) -> Vec<(&str, Vec<[String; 12]>, Option<[String; 12]>)> {
        let mut names: Vec<&str> = Vec::new();
        for r in self.0 {
            if !names.contains(&r.scenario.as_str()) {
                names.push(&r.scenario);
            }
        }
        names
            .into_iter()
            .map(|name| {
                let rows = self
                    .0
                    .iter()
                    .filter(|r| r.scenario == name)
                    .map(Self::cells)
                    .collect();
                let paper = paper_plane_sphere(name).map(|(table, c)| {
                    [
                        "paper".into(),
                        format!("{table}, maximum"),
                        "—".into(),
                        "plane-sphere".into(),
                        approx(Some(c.sphere_sphere)),
                        approx(c.plane_sphere),
                        approx(c.tri_tri),
                        approx(Some(c.operations)),
                        "—".into(),
                        "—".into(),
                        "—".into(),
                        "—".into(),
                    ]
                });
                (name, rows, paper)
            })
            .collect()
    }

    pub fn markdown(&self) -> String {
        let mut out = String::new();
        for (name, rows, paper) in self.groups() {
            out += &format!("### {name}\n\n| {} |\n|", HEADER.join(" | "));
            out += &"---|".repeat(HEADER.len());
            out += "\n";
            for r in rows.iter().chain(paper.as_ref()) {
                out += &format!("| {} |\n", r.join(" | "));
            }
            out += "\n";
        }
        out
    }
}

impl fmt::Display for StudyTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        for (name, rows, paper) in self.groups() {
            writeln!(f, "{name}")?;
            let all: Vec<&[String; 12]> = rows.iter().chain(paper.as_ref()).collect();
            let width: Vec<usize> = (0..HEADER.len())
                .map(|i| {
                    all.iter()
                        .map(|r| r[i].chars().count())
                        .chain([HEADER[i].len()])
                        .max()
                        .unwrap_or(0)
                })
                .collect();
            let line = |f: &mut fmt::Formatter<'_>, cells: &[&str]| -> fmt::Result {
                for (i, c) in cells.iter().enumerate() {
                    let pad = width[i] - c.chars().count();
                    if i < 4 {
                        write!(f, "{c}{}  ", " ".repeat(pad))?;
                    } else {
                        write!(f, "{}{c}  ", " ".repeat(pad))?;
                    }
                }
                writeln!(f)
            };
            line(f, &HEADER)?;
            for r in &all {
                let cells: Vec<&str> = r.iter().map(String::as_str).collect();
                line(f, &cells)?;
            }
            writeln!(f)?;
        }
        Ok(())
    }
}
