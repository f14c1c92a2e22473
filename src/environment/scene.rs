//! A static glTF scene as an environment.

use std::path::{Path, PathBuf};

use super::{EnvObject, Environment, ObjectKind};
use cornertree::io::{LoadError, LoadLimits, LoadReport, load_static_mesh_with};
use cornertree::mesh::{MeshError, TriMesh};

/// How many removed triangles [`SceneReport::first_degenerate`] lists.
pub const LISTED_DEGENERATE: usize = 8;

/// What [`load_scene`] loaded and removed.
#[derive(Clone, Debug, Default)]
pub struct SceneReport {
    /// The loader's report (meshes, primitives, skipped primitives, notes).
    pub load: LoadReport,
    /// Triangles removed because they repeat a vertex index or have zero area.
    pub degenerate_removed: usize,
    /// Indices (in the loaded, unfiltered triangle list) of the first
    /// [`LISTED_DEGENERATE`] removed triangles.
    pub first_degenerate: Vec<usize>,
}

/// Why a scene could not be used. Every message is one line naming the file.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error(transparent)]
    Load(#[from] LoadError),
    #[error(
        "{}: no usable triangles: all {removed} triangle(s) are degenerate (repeated index or zero area)",
        .path.display()
    )]
    OnlyDegenerate { path: PathBuf, removed: usize },
    #[error("{}: {error}", .path.display())]
    Mesh { path: PathBuf, error: MeshError },
}

/// Whether a triangle repeats an index or has zero area: its doubled area
/// (computed in `f64`) is at most a few ulps of its squared longest edge.
pub fn is_degenerate(mesh: &TriMesh, t: [u32; 3]) -> bool {
    if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
        return true;
    }
    let q = |i: u32| mesh.positions()[i as usize].map(f64::from);
    let (a, b, c) = (q(t[0]), q(t[1]), q(t[2]));
    let cross = (b - a).cross(&(c - a)).norm();
    let longest = (b - a)
        .norm_squared()
        .max((c - b).norm_squared())
        .max((a - c).norm_squared());
    cross <= 4.0 * f64::EPSILON * longest
}

/// Every triangle of the scene in `path` (see [`load_static_mesh`](cornertree::io::load_static_mesh): every
/// mesh, node transforms applied) as one static object, degenerate triangles
/// removed and reported. A scene with no triangles, or only degenerate ones,
/// is an error.
pub fn load_scene(path: &Path) -> Result<(Environment, SceneReport), SceneError> {
    load_scene_with(path, &LoadLimits::default())
}

/// [`load_scene`] within `limits`.
pub fn load_scene_with(
    path: &Path,
    limits: &LoadLimits,
) -> Result<(Environment, SceneReport), SceneError> {
    let (mesh, load) = load_static_mesh_with(path, limits)?;
    let mut report = SceneReport {
        load,
        ..SceneReport::default()
    };
    let mut kept = Vec::with_capacity(mesh.triangle_count());
    for (i, &t) in mesh.indices().iter().enumerate() {
        if is_degenerate(&mesh, t) {
            report.degenerate_removed += 1;
            if report.first_degenerate.len() < LISTED_DEGENERATE {
                report.first_degenerate.push(i);
            }
        } else {
            kept.push(t);
        }
    }
    if kept.is_empty() {
        return Err(SceneError::OnlyDegenerate {
            path: path.to_owned(),
            removed: report.degenerate_removed,
        });
    }
    let triangles = kept.len() as u32;
    let mesh = TriMesh::new(mesh.positions().to_vec(), kept).map_err(|error| SceneError::Mesh {
        path: path.to_owned(),
        error,
    })?;
    let name = path
        .file_stem()
        .map_or_else(|| "scene".to_owned(), |s| s.to_string_lossy().into_owned());
    let object = EnvObject {
        name: name.clone(),
        kind: ObjectKind::Scene,
        vertices: 0..mesh.vertex_count() as u32,
        triangles: 0..triangles,
        motion: None,
    };
    Ok((
        Environment {
            name,
            mesh,
            objects: vec![object],
        },
        report,
    ))
}
