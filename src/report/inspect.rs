//! `cornertree inspect`: what a mesh becomes in the collision pipeline.

use std::fmt;

use serde::Serialize;

use cornertree::mesh::{EdgeDedup, TriMesh, TriangleId, dedup_edges};
use cornertree::sphere_tree::validate::Checks;
use cornertree::sphere_tree::{BuildParams, SphereTree, TreeError, build_tree};

/// Summary of a mesh and its sphere tree. Field names are the `--json` keys.
#[derive(Clone, Debug, Serialize)]
pub struct InspectReport {
    pub source: String,
    pub vertices: usize,
    pub triangles: usize,
    /// Triangles left for collision detection after edge de-duplication (§4);
    /// equal to `triangles` when de-duplication is off.
    pub triangles_after_dedup: usize,
    pub dedup: bool,
    /// Fraction of triangles left out by de-duplication.
    pub dedup_reduction: f64,
    pub collapse_ratio: f32,
    /// Nodes per level of the sphere tree, root first.
    pub tree_levels: Vec<usize>,
    pub tree_nodes: usize,
    pub tree_leaves: usize,
    /// Bytes held by the tree's nodes.
    pub tree_bytes: usize,
    /// Mean number of children of inner nodes.
    pub mean_branching: f64,
    /// Diagonal of the mesh's bounding box (model units).
    pub model_size: f32,
    /// Whether the validator passed (it is always run).
    pub valid: bool,
}

/// Options of the static inspection.
#[derive(Clone, Copy, Debug)]
pub struct InspectOptions {
    pub dedup: bool,
    pub build: BuildParams,
}

impl Default for InspectOptions {
    fn default() -> Self {
        Self {
            dedup: true,
            build: BuildParams::default(),
        }
    }
}

/// Builds the collision structures of `mesh` and summarises them; the tree is
/// validated (leaf containment, coverage, nesting) and a failure is returned.
pub fn inspect_mesh(
    source: &str,
    mesh: &TriMesh,
    options: InspectOptions,
) -> Result<(InspectReport, SphereTree), TreeError> {
    let dedup = if options.dedup {
        dedup_edges(mesh)
    } else {
        EdgeDedup::keep_all(mesh)
    };
    let kept: Vec<TriangleId> = dedup.kept().collect();
    let tree = build_tree(mesh, &kept, options.build);
    tree.validate(
        mesh,
        Checks {
            triangles: Some(&kept),
            nested: true,
            tolerance: 0.0,
        },
    )?;
    let levels = tree.nodes_per_level();
    let inner = tree.len() - tree.leaf_count();
    let report = InspectReport {
        source: source.to_owned(),
        vertices: mesh.vertex_count(),
        triangles: mesh.triangle_count(),
        triangles_after_dedup: dedup.kept_count(),
        dedup: options.dedup,
        dedup_reduction: dedup.reduction(),
        collapse_ratio: options.build.collapse_ratio,
        tree_nodes: tree.len(),
        tree_leaves: tree.leaf_count(),
        tree_bytes: tree.bytes(),
        mean_branching: if inner == 0 {
            0.0
        } else {
            (tree.len() - 1) as f64 / inner as f64
        },
        tree_levels: levels,
        model_size: mesh.size(),
        valid: true,
    };
    Ok((report, tree))
}

impl fmt::Display for InspectReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(f, "{}", self.source)?;
        writeln!(f, "  vertices               {:>10}", self.vertices)?;
        writeln!(f, "  triangles              {:>10}", self.triangles)?;
        if self.dedup {
            writeln!(
                f,
                "  after edge dedup (§4)  {:>10}   ({:.1}% left out)",
                self.triangles_after_dedup,
                100.0 * self.dedup_reduction
            )?;
        } else {
            writeln!(
                f,
                "  after edge dedup (§4)  {:>10}   (de-duplication off)",
                self.triangles_after_dedup
            )?;
        }
        writeln!(f, "  model size (diagonal)  {:>10.4}", self.model_size)?;
        writeln!(
            f,
            "  sphere tree            {:>10} nodes, {} leaves, depth {}, mean branching {:.2} (collapse ratio {})",
            self.tree_nodes,
            self.tree_leaves,
            self.tree_levels.len(),
            self.mean_branching,
            self.collapse_ratio
        )?;
        writeln!(f, "  tree bytes             {:>10}", self.tree_bytes)?;
        writeln!(
            f,
            "  validator              {:>10}",
            if self.valid { "passed" } else { "FAILED" }
        )?;
        writeln!(f, "  nodes per level (root first):")?;
        for (i, n) in self.tree_levels.iter().enumerate() {
            writeln!(f, "    {:>3} {:>10}", i + 1, n)?;
        }
        Ok(())
    }
}
