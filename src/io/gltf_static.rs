//! Static glTF loading. STUB: to be implemented.

use std::path::{Path, PathBuf};

use crate::mesh::TriMesh;

/// Why a file could not be loaded. Every variant names the file.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    #[error("{path}: {message}")]
    Other { path: PathBuf, message: String },
}

/// What was loaded and what was skipped.
#[derive(Clone, Debug, Default)]
pub struct LoadReport {
    pub meshes: usize,
    pub primitives: usize,
    /// Human-readable notes on content that was skipped.
    pub skipped: Vec<String>,
}

/// Every triangle of the default scene, node transforms applied.
pub fn load_static_mesh(path: &Path) -> Result<(TriMesh, LoadReport), LoadError> {
    Err(LoadError::Other { path: path.to_owned(), message: "not implemented".into() })
}
