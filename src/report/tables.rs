//! `cornertree tables`: Table 1 counted on built trees, and what each method's
//! environment hierarchy costs in the museum and the living room.

use std::collections::BTreeMap;
use std::fmt;

use serde::Serialize;

use crate::environment::Environment;
use cornertree::big_triangle::hierarchy::table1;
use cornertree::geometry::Real;
use cornertree::pipeline::{EnvironmentTree, Method};
use cornertree::sphere_tree::BuildParams;

use super::paper;

/// Table 1 as measured.
#[derive(Clone, Debug, Serialize)]
pub struct Table1 {
    /// Where the counted trees were built: room, triangle index, longest edge.
    pub triangle: String,
    pub corner_tree: Vec<usize>,
    pub quaternary: Vec<usize>,
}

/// One method's environment hierarchy.
#[derive(Clone, Debug, Serialize)]
pub struct MethodCost {
    pub nodes: usize,
    pub bytes: usize,
    /// Nodes inside big-triangle divisions.
    pub division_nodes: usize,
    /// Whether some division hit the level cap.
    pub capped: bool,
}

/// One room.
#[derive(Clone, Debug, Serialize)]
pub struct EnvironmentCosts {
    pub vertices: usize,
    pub triangles: usize,
    pub big_triangles: usize,
    /// Big-triangle threshold in metres.
    pub threshold: Real,
    /// Per method name.
    #[serde(flatten)]
    pub methods: BTreeMap<String, MethodCost>,
}

#[derive(Clone, Debug, Serialize)]
pub struct TablesReport {
    pub table1: Table1,
    pub environments: BTreeMap<String, EnvironmentCosts>,
}

/// Table 1 over the room's largest triangle, then every method's hierarchy
/// for every room, at `threshold`.
pub fn tables(
    rooms: &[(&str, &Environment)],
    threshold: Real,
    params: BuildParams,
) -> TablesReport {
    let (name, first) = rooms[0];
    let (id, t) = first
        .mesh
        .iter_triangles()
        .max_by(|a, b| a.1.longest_edge().total_cmp(&b.1.longest_edge()))
        .expect("rooms have triangles");
    let (corner_tree, quaternary) = table1(&t, 7);
    let table1 = Table1 {
        triangle: format!(
            "{name} triangle {} (longest edge {:.2} m)",
            id.0,
            t.longest_edge()
        ),
        corner_tree,
        quaternary,
    };
    let environments = rooms
        .iter()
        .map(|(name, env)| {
            let methods = Method::ALL
                .iter()
                .map(|&m| {
                    let et = EnvironmentTree::build(&env.mesh, m, threshold, params);
                    let division_nodes = et.division_node.iter().filter(|d| d.is_some()).count();
                    (
                        m.name().to_string(),
                        MethodCost {
                            nodes: et.tree.len(),
                            bytes: et.bytes(),
                            division_nodes,
                            capped: et.capped,
                        },
                    )
                })
                .collect();
            let big = env
                .mesh
                .iter_triangles()
                .filter(|(_, t)| t.longest_edge() > threshold)
                .count();
            (
                name.to_string(),
                EnvironmentCosts {
                    vertices: env.mesh.vertex_count(),
                    triangles: env.mesh.triangle_count(),
                    big_triangles: big,
                    threshold,
                    methods,
                },
            )
        })
        .collect();
    TablesReport {
        table1,
        environments,
    }
}

fn mib(bytes: usize) -> f64 {
    bytes as f64 / (1024.0 * 1024.0)
}

impl fmt::Display for TablesReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "Table 1 — spheres on level n (ours: counted on trees built over {})",
            self.table1.triangle
        )?;
        write!(f, "  {:<26}", "level")?;
        for n in 1..=7 {
            write!(f, "{n:>7}")?;
        }
        writeln!(f)?;
        let row = |f: &mut fmt::Formatter<'_>, label: &str, v: &[usize]| -> fmt::Result {
            write!(f, "  {label:<26}")?;
            for x in v {
                write!(f, "{x:>7}")?;
            }
            writeln!(f)
        };
        row(f, "corner-tree (ours)", &self.table1.corner_tree)?;
        row(f, "corner-tree (paper)", &paper::TABLE1_CORNER_TREE)?;
        row(f, "quaternary (ours)", &self.table1.quaternary)?;
        row(f, "quaternary (paper)", &paper::TABLE1_QUATERNARY)?;
        for (name, e) in &self.environments {
            writeln!(f)?;
            writeln!(
                f,
                "{name}: {} vertices, {} triangles, {} big (longest edge > {} m)",
                e.vertices, e.triangles, e.big_triangles, e.threshold
            )?;
            writeln!(
                f,
                "  {:<26}{:>12}{:>16}{:>12}",
                "method", "nodes", "inside big", "MiB"
            )?;
            for m in Method::ALL {
                let c = &e.methods[m.name()];
                writeln!(
                    f,
                    "  {:<26}{:>12}{:>16}{:>12.2}{}",
                    m.name(),
                    c.nodes,
                    c.division_nodes,
                    mib(c.bytes),
                    if c.capped { "  (level cap hit)" } else { "" }
                )?;
            }
        }
        Ok(())
    }
}
