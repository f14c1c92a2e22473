//! The paper's Figures 1–3 as recordings (`cornertree figures`).
//!
//! - Figure 1 (§4): a triangle left out by edge de-duplication among the three
//!   kept neighbours that cover its edges, on the generated humanoid.
//! - Figure 2 (§5): a big triangle's enclosing sphere and the spheres of its
//!   four sub-triangles.
//! - Figure 3 (§5): a big triangle's corner-tree, one level per step of the
//!   `level` timeline; central sub-triangles stop splitting.

use std::collections::HashMap;
use std::path::{Path, PathBuf};

use rerun::RecordingStream;

use super::blueprint::figure_blueprint;
use super::draw::{mesh3d, soup};
use super::layout::{self, Rgba};
use crate::humanoid::{HumanoidParams, generate_humanoid};
use cornertree::big_triangle::hierarchy::MAX_LEVELS;
use cornertree::big_triangle::{Division, DivisionKind, SubTriangle};
use cornertree::geometry::enclosing::triangle_sphere;
use cornertree::geometry::{Point, Sphere, Triangle};
use cornertree::mesh::dedup::{triangle_edges, weld_positions};
use cornertree::mesh::{TriMesh, TriangleId, dedup_edges};

/// One written figure.
#[derive(Debug, Clone, serde::Serialize)]
pub struct Figure {
    pub name: &'static str,
    pub path: PathBuf,
    /// What it shows, with our numbers.
    pub caption: String,
}

/// Why a figure could not be made.
#[derive(Debug, thiserror::Error)]
pub enum FigureError {
    #[error("{0}: cannot write the recording: {1}")]
    Write(PathBuf, String),
    #[error("{0}")]
    Input(String),
}

const LEFT_OUT: Rgba = [230, 40, 40, 255];
const NEIGHBOURS: [Rgba; 3] = [[60, 170, 220, 255], [90, 200, 90, 255], [240, 190, 40, 255]];
const CONTEXT: Rgba = [150, 150, 155, 255];
const TRIANGLE: Rgba = [200, 200, 205, 255];
const CENTRAL: Rgba = [120, 120, 200, 255];
const EDGE: Rgba = [30, 30, 30, 255];

fn p3(p: &Point) -> [f32; 3] {
    [p.x, p.y, p.z]
}

fn outline(t: &Triangle) -> [[f32; 3]; 4] {
    [p3(&t.a), p3(&t.b), p3(&t.c), p3(&t.a)]
}

fn wire(spheres: &[Sphere], color: Rgba) -> rerun::Ellipsoids3D {
    rerun::Ellipsoids3D::from_centers_and_radii(
        spheres.iter().map(|s| p3(&s.center)),
        spheres.iter().map(|s| s.radius),
    )
    .with_colors([color])
    .with_fill_mode(rerun::FillMode::MajorWireframe)
}

fn open(
    dir: &Path,
    file: &str,
    title: &str,
    timeline: Option<&str>,
) -> Result<(RecordingStream, PathBuf), FigureError> {
    let path = dir.join(file);
    let rec = rerun::RecordingStreamBuilder::new("cornertree")
        .recording_name(title)
        .with_blueprint(figure_blueprint(title, timeline))
        .save(&path)
        .map_err(|e| FigureError::Write(path.clone(), e.to_string()))?;
    rec.log_static(layout::WORLD, &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())
        .map_err(|e| FigureError::Write(path.clone(), e.to_string()))?;
    Ok((rec, path))
}

/// The big triangle of Figures 2 and 3, filled.
fn log_triangle(rec: &RecordingStream, t: &Triangle) -> rerun::RecordingStreamResult<()> {
    rec.log_static(
        "world/triangle",
        &mesh3d(&[t.a, t.b, t.c], &[[0, 1, 2]], TRIANGLE),
    )
}

fn done(rec: RecordingStream, path: &Path) -> Result<(), FigureError> {
    rec.flush_blocking()
        .map_err(|e| FigureError::Write(path.to_path_buf(), e.to_string()))
}

fn caption(rec: &RecordingStream, text: &str) -> rerun::RecordingStreamResult<()> {
    rec.log_static(
        layout::INFO,
        &rerun::TextDocument::new(text).with_media_type(rerun::MediaType::markdown()),
    )
}

/// Writes the three figures into `dir` (created if needed).
pub fn write_figures(dir: &Path) -> Result<Vec<Figure>, FigureError> {
    std::fs::create_dir_all(dir)
        .map_err(|e| FigureError::Write(dir.to_path_buf(), e.to_string()))?;
    Ok(vec![figure1(dir)?, figure2(dir)?, figure3(dir)?])
}

/// A left-out triangle whose three edges are each covered by a different kept
/// neighbour, with those neighbours (Figure 1).
pub fn dedup_example(mesh: &TriMesh) -> Option<(TriangleId, [TriangleId; 3])> {
    let dedup = dedup_edges(mesh);
    let welded = weld_positions(mesh);
    let mut by_edge: HashMap<(u32, u32), Vec<u32>> = HashMap::new();
    for (t, tri) in mesh.indices().iter().enumerate() {
        for e in triangle_edges(&welded, tri) {
            by_edge.entry(e).or_default().push(t as u32);
        }
    }
    dedup.dropped().find_map(|t| {
        let edges: Vec<_> = triangle_edges(&welded, &mesh.indices()[t.index()]).collect();
        if edges.len() != 3 {
            return None;
        }
        let mut found = Vec::new();
        for e in &edges {
            let n = by_edge[e]
                .iter()
                .copied()
                .find(|&o| o != t.0 && dedup.is_kept(TriangleId(o)) && !found.contains(&o))?;
            found.push(n);
        }
        Some((t, [found[0], found[1], found[2]].map(TriangleId)))
    })
}

fn figure1(dir: &Path) -> Result<Figure, FigureError> {
    let title = "Figure 1: edge de-duplication";
    let character = generate_humanoid(&HumanoidParams {
        vertices: 3000,
        seed: 1,
    })
    .map_err(|e| FigureError::Input(e.to_string()))?;
    let mesh = &character.mesh;
    let (t, n) = dedup_example(mesh).ok_or_else(|| {
        FigureError::Input("no left-out triangle with three kept neighbours".into())
    })?;
    let dedup = dedup_edges(mesh);
    // Context: triangles sharing a vertex with the four.
    let verts: Vec<u32> = [t, n[0], n[1], n[2]]
        .iter()
        .flat_map(|x| mesh.indices()[x.index()])
        .collect();
    let context: Vec<u32> = (0..mesh.triangle_count() as u32)
        .filter(|&o| o != t.0 && !n.iter().any(|x| x.0 == o))
        .filter(|&o| mesh.indices()[o as usize].iter().any(|v| verts.contains(v)))
        .collect();
    let (rec, path) = open(dir, "figure1_dedup.rrd", title, None)?;
    let w = |e: rerun::RecordingStreamError| FigureError::Write(path.clone(), e.to_string());
    let pos = mesh.positions();
    let idx = mesh.indices();
    rec.log_static("world/left_out", &soup(pos, idx, &[t.0], LEFT_OUT))
        .map_err(w)?;
    for (k, x) in n.iter().enumerate() {
        rec.log_static(
            format!("world/kept_neighbour_{}", k + 1),
            &soup(pos, idx, &[x.0], NEIGHBOURS[k]),
        )
        .map_err(w)?;
    }
    rec.log_static("world/context", &soup(pos, idx, &context, CONTEXT))
        .map_err(w)?;
    let strips: Vec<[[f32; 3]; 4]> = std::iter::once(t)
        .chain(n)
        .chain(context.iter().map(|&o| TriangleId(o)))
        .map(|x| outline(&mesh.triangle(x)))
        .collect();
    rec.log_static(
        "world/edges",
        &rerun::LineStrips3D::new(strips)
            .with_colors([EDGE])
            .with_radii([rerun::Radius::new_ui_points(1.5)]),
    )
    .map_err(w)?;
    let centroid = |x: TriangleId| {
        let tr = mesh.triangle(x);
        p3(&Point::from(
            (tr.a.coords + tr.b.coords + tr.c.coords) / 3.0,
        ))
    };
    let labels =
        std::iter::once("left out".to_string()).chain((1..=3).map(|k| format!("kept {k}")));
    rec.log_static(
        "world/labels",
        &rerun::Points3D::new(std::iter::once(t).chain(n).map(centroid))
            .with_labels(labels)
            .with_radii([rerun::Radius::new_ui_points(3.0)])
            .with_colors([EDGE]),
    )
    .map_err(w)?;
    let text = format!(
        "## {title}\n\nOn the generated humanoid ({} vertices, {} triangles), edge \
         de-duplication (§4) keeps {} triangles and leaves out {} ({:.1}%).\n\n\
         Triangle {} (red) is left out: each of its three edges is an edge of a \
         kept neighbour (triangles {}, {} and {}), so any triangle crossing it also \
         crosses one of them. Grey: triangles around them.",
        mesh.vertex_count(),
        mesh.triangle_count(),
        dedup.kept_count(),
        dedup.dropped_count(),
        100.0 * dedup.reduction(),
        t.0,
        n[0].0,
        n[1].0,
        n[2].0
    );
    caption(&rec, &text).map_err(w)?;
    done(rec, &path)?;
    Ok(Figure {
        name: "figure1",
        path,
        caption: text,
    })
}

/// The big triangle of Figures 2 and 3: a 2 m wall triangle (longest edge 2.5 m).
pub fn example_big_triangle() -> Triangle {
    Triangle::new(
        Point::new(0.0, 0.0, 0.0),
        Point::new(2.5, 0.0, 0.0),
        Point::new(0.9, 2.0, 0.0),
    )
}

fn figure2(dir: &Path) -> Result<Figure, FigureError> {
    let title = "Figure 2: sphere division";
    let t = example_big_triangle();
    let whole = SubTriangle::whole(t);
    let parts = whole.split();
    let big = triangle_sphere(&t);
    let small: Vec<Sphere> = parts.iter().map(|p| triangle_sphere(&p.triangle)).collect();
    let (rec, path) = open(dir, "figure2_sphere_division.rrd", title, None)?;
    let w = |e: rerun::RecordingStreamError| FigureError::Write(path.clone(), e.to_string());
    log_triangle(&rec, &t).map_err(w)?;
    rec.log_static(
        "world/sub_triangles",
        &rerun::LineStrips3D::new(parts.iter().map(|p| outline(&p.triangle)))
            .with_colors([EDGE])
            .with_radii([rerun::Radius::new_ui_points(2.0)]),
    )
    .map_err(w)?;
    rec.log_static("world/spheres/enclosing", &wire(&[big], [230, 80, 60, 255]))
        .map_err(w)?;
    rec.log_static("world/spheres/sub", &wire(&small, [60, 170, 220, 255]))
        .map_err(w)?;
    let sum: f32 = small.iter().map(|s| s.radius).sum();
    let text = format!(
        "## {title}\n\nA big triangle (longest edge {:.2} m) split at its edge \
         midpoints into four sub-triangles (§5). Red: its enclosing sphere, radius \
         {:.3} m. Blue: the four sub-spheres, radii {:.3}, {:.3}, {:.3} and {:.3} m \
         (each about half the parent's; sum {:.3} m).",
        t.longest_edge(),
        big.radius,
        small[0].radius,
        small[1].radius,
        small[2].radius,
        small[3].radius,
        sum
    );
    caption(&rec, &text).map_err(w)?;
    done(rec, &path)?;
    Ok(Figure {
        name: "figure2",
        path,
        caption: text,
    })
}

fn figure3(dir: &Path) -> Result<Figure, FigureError> {
    let title = "Figure 3: corner-tree";
    let t = example_big_triangle();
    let threshold = 0.15;
    let d = Division::build(
        &t,
        TriangleId(0),
        DivisionKind::Corner,
        threshold,
        MAX_LEVELS,
    );
    let full = Division::build(&t, TriangleId(0), DivisionKind::Full, threshold, MAX_LEVELS);
    let levels = layout::node_levels(&d.tree);
    let level_count = levels.iter().map(|&l| l as usize + 1).max().unwrap_or(0);
    let (rec, path) = open(dir, "figure3_corner_tree.rrd", title, Some("level"))?;
    let w = |e: rerun::RecordingStreamError| FigureError::Write(path.clone(), e.to_string());
    log_triangle(&rec, &t).map_err(w)?;
    let per_level = d.nodes_per_level();
    let mut lines = Vec::new();
    for level in 0..level_count {
        rec.set_time_sequence("level", level as i64);
        let nodes = d.tree.nodes();
        // The partition at this level: its nodes plus the leaves above it.
        let shown: Vec<usize> = (0..nodes.len())
            .filter(|&i| {
                let l = levels[i] as usize;
                l == level || (l < level && nodes[i].is_leaf())
            })
            .collect();
        let central: Vec<Point> = shown
            .iter()
            .filter(|&&i| (levels[i] as usize) < level)
            .flat_map(|&i| {
                // Lifted 2 mm off the triangle's plane so it does not z-fight.
                let tr = d.pieces[i].triangle;
                let lift = nalgebra::Vector3::new(0.0, 0.0, 0.002);
                [tr.a + lift, tr.b + lift, tr.c + lift]
            })
            .collect();
        let central_idx: Vec<[u32; 3]> = (0..central.len() as u32 / 3)
            .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
            .collect();
        rec.log("world/settled", &mesh3d(&central, &central_idx, CENTRAL))
            .map_err(w)?;
        rec.log(
            "world/sub_triangles",
            &rerun::LineStrips3D::new(shown.iter().map(|&i| outline(&d.pieces[i].triangle)))
                .with_colors([EDGE])
                .with_radii([rerun::Radius::new_ui_points(1.0)]),
        )
        .map_err(w)?;
        let spheres: Vec<Sphere> = (0..nodes.len())
            .filter(|&i| levels[i] as usize == level)
            .map(|i| nodes[i].sphere)
            .collect();
        rec.log(
            "world/spheres",
            &wire(&spheres, layout::level_color(level, level_count)),
        )
        .map_err(w)?;
        rec.log(
            "stats/nodes_at_level",
            &rerun::Scalars::single(spheres.len() as f64),
        )
        .map_err(w)?;
        lines.push(format!(
            "| {level} | {} | {} |",
            per_level.get(level).copied().unwrap_or(0),
            full.nodes_per_level().get(level).copied().unwrap_or(0)
        ));
    }
    let text = format!(
        "## {title}\n\nThe big triangle of Figure 2 divided into a corner-tree (§5) \
         down to sub-triangles under {threshold} m, one level per step of the \
         `level` timeline. Only sub-triangles with an edge on the original boundary \
         split again; central ones (blue, filled) stay leaves. Spheres: the nodes \
         of the current level.\n\n| level | corner-tree nodes | full quaternary tree nodes |\n\
         |---|---|---|\n{}\n\nTotal: {} nodes against {} for the full tree.",
        lines.join("\n"),
        d.tree.len(),
        full.tree.len()
    );
    caption(&rec, &text).map_err(w)?;
    done(rec, &path)?;
    Ok(Figure {
        name: "figure3",
        path,
        caption: text,
    })
}
