//! Static glTF 2.0 loading: every triangle of a scene, in world space, as one [`TriMesh`].
//!
//! [`load_static_mesh`] reads `.glb` and `.gltf` (buffers in external files or
//! base64 `data:` URIs). It takes the default scene, else the first scene, else
//! every root node; walks the node trees composing each node's transform (TRS or
//! matrix) into a world transform; and appends every vertex of every triangle
//! primitive of each node's mesh, so a mesh placed by two nodes appears twice.
//! Vertices are not welded: each primitive contributes its whole `POSITION`
//! accessor. Missing indices mean `0..n`.
//!
//! - `TRIANGLES` is taken as stored. `TRIANGLE_STRIP` and `TRIANGLE_FAN` are
//!   converted with the winding the glTF spec defines (odd strip triangles
//!   swap their last two corners); strip/fan triangles that repeat an index
//!   (stitching) are dropped and counted. `POINTS` and `LINES*` primitives are
//!   skipped and listed in [`LoadReport::skipped`].
//! - Skinned nodes: the glTF spec says the transform of the node that carries a
//!   skinned mesh must be ignored (only joint transforms apply). Joints are not
//!   evaluated here, so such a mesh is placed with its positions as stored, the
//!   bind pose. Children of that node still inherit its transform.
//! - Morph targets are ignored (base positions as stored) and noted in
//!   [`LoadReport::notes`].
//! - Compressed files: `KHR_draco_mesh_compression` (primitives decoded by
//!   `draco-core`), `EXT_meshopt_compression` (buffer views decoded by
//!   meshoptimizer) and `KHR_mesh_quantization` (integer positions) are read;
//!   any other entry of `extensionsRequired` is an error.
//! - Leniency: `POSITION` accessors without the spec's `min`/`max` are accepted.
//!   Strictness: a node reached twice (a cycle or shared subtree) is an error.
//!
//! Every [`LoadError`] message is one line naming the file and the problem.
//! Malformed content is an error, never a panic: offsets, counts, strides and
//! node links are checked before use; every node transform on the way to a
//! mesh must be finite, and positions, stored and placed, finite and within
//! [`MAX_COORDINATE`]; the file, its JSON, its buffers and every decoded
//! accessor are charged to a byte budget ([`LoadLimits`]) before they are
//! allocated. [`load_static_mesh_from`] loads from bytes already in memory.

use std::fmt;
use std::io::Read;
use std::path::{Path, PathBuf};

use gltf::buffer::{Data, Source};
use gltf::mesh::{Mode, Semantic};
use gltf::scene::Transform;
use nalgebra::{Matrix4, Point3, Quaternion, UnitQuaternion, Vector3};

use super::gltf_accessor::{self, Buffers};
use super::limits::{Budget, LoadLimits, MAX_COORDINATE};
use super::{gltf_draco, gltf_meshopt};
use crate::geometry::Point;
use crate::mesh::{MeshError, TriMesh};

/// A mesh of the file: index, and name if it has one.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct MeshRef {
    /// Index in the file's `meshes`.
    pub index: usize,
    /// The mesh's `name`, if the file gives one.
    pub name: Option<String>,
}

impl MeshRef {
    pub(crate) fn of(mesh: &gltf::Mesh<'_>) -> Self {
        Self {
            index: mesh.index(),
            name: mesh.name().map(str::to_owned),
        }
    }
}

impl fmt::Display for MeshRef {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.name {
            // Debug formatting quotes and escapes, so the name cannot break the line.
            Some(name) => write!(f, "{} {:?}", self.index, name),
            None => write!(f, "{}", self.index),
        }
    }
}

/// Why a file could not be loaded. Every message is one line that starts with
/// the file's path.
#[derive(Debug, thiserror::Error)]
pub enum LoadError {
    /// The file could not be opened or read.
    #[error("{}: cannot read file: {error}", .path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },

    /// The bytes are neither a GLB container nor glTF JSON, or the asset
    /// version is not 2.x.
    #[error("{}: not a glTF 2.0 file: {reason}", .path.display())]
    NotGltf {
        /// The file.
        path: PathBuf,
        /// What is wrong, on one line.
        reason: String,
    },

    /// The file lists extensions in `extensionsRequired` that the loaders do
    /// not read (see [`SUPPORTED_EXTENSIONS`]).
    #[error(
        "{}: requires unsupported glTF extension(s) {}; core glTF 2.0 can be read, with {}",
        .path.display(), .extensions.join(", "), SUPPORTED_EXTENSIONS.join(", ")
    )]
    UnsupportedExtension {
        /// The file.
        path: PathBuf,
        /// The required extensions' names.
        extensions: Vec<String>,
    },

    /// The document fails glTF validation (a dangling index, a missing or
    /// wrongly typed property).
    #[error("{}: invalid glTF: {reason}", .path.display())]
    Invalid {
        /// The file.
        path: PathBuf,
        /// The first few validation errors, with their JSON paths.
        reason: String,
    },

    /// A buffer's bytes cannot be had: missing GLB chunk, bad data URI,
    /// unreadable external file, or fewer bytes than declared.
    #[error("{}: buffer {buffer}: {reason}", .path.display())]
    Buffer {
        /// The file.
        path: PathBuf,
        /// Index in the file's `buffers`.
        buffer: usize,
        /// What is wrong, on one line.
        reason: String,
    },

    /// The nodes do not form a forest: a node is reached twice (it has two
    /// parents, lies on a cycle, or is listed twice as a root).
    #[error("{}: node hierarchy is not a forest: node {node} is reached twice", .path.display())]
    NodeGraph {
        /// The file.
        path: PathBuf,
        /// Index of the node reached twice.
        node: usize,
    },

    /// A node cannot be used: a non-finite or unnormalisable local transform,
    /// or (character loading) a vertex out of range in its joint's frame.
    #[error("{}: node {node}: {reason}", .path.display())]
    Node {
        /// The file.
        path: PathBuf,
        /// Index in the file's `nodes`.
        node: usize,
        /// What is wrong, on one line.
        reason: String,
    },

    /// Loading would go past [`LoadLimits::max_bytes`].
    #[error("{}: {reason}", .path.display())]
    Limit {
        /// The file.
        path: PathBuf,
        /// What was being charged and by how much it goes over.
        reason: String,
    },

    /// A compressed primitive cannot be decoded: a malformed or over-budget
    /// Draco stream, or decoded data that does not fit its accessors.
    #[error("{}: mesh {mesh} primitive {primitive}: {reason}", .path.display())]
    Compressed {
        /// The file.
        path: PathBuf,
        /// The primitive's mesh.
        mesh: MeshRef,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// What is wrong, on one line (starts with the extension's name).
        reason: String,
    },

    /// A triangle primitive has no `POSITION` attribute.
    #[error("{}: mesh {mesh} primitive {primitive} has no POSITION attribute", .path.display())]
    MissingPosition {
        /// The file.
        path: PathBuf,
        /// The primitive's mesh.
        mesh: MeshRef,
        /// Index of the primitive in its mesh.
        primitive: usize,
    },

    /// An accessor of a primitive cannot be read: a type the loader does not
    /// take, data outside its buffer, a non-finite float, or decoding it would
    /// go past the byte budget.
    #[error("{}: mesh {mesh} primitive {primitive}: accessor {accessor}: {reason}", .path.display())]
    Accessor {
        /// The file.
        path: PathBuf,
        /// The primitive's mesh.
        mesh: MeshRef,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// Index in the file's `accessors`.
        accessor: usize,
        /// What is wrong, on one line.
        reason: String,
    },

    #[error(
        "{}: mesh {mesh} primitive {primitive}: index {index} (entry {entry} of accessor {accessor}) is out of range; the primitive has {vertex_count} vertices",
        .path.display()
    )]
    /// A primitive's index names a vertex past the end of its `POSITION` accessor.
    IndexOutOfRange {
        /// The file.
        path: PathBuf,
        /// The primitive's mesh.
        mesh: MeshRef,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// The indices accessor.
        accessor: usize,
        /// Position of the bad index in that accessor.
        entry: usize,
        /// The index read.
        index: u32,
        /// Number of vertices in the primitive's `POSITION` accessor.
        vertex_count: usize,
    },

    #[error(
        "{}: mesh {mesh} primitive {primitive}: accessor {accessor}: vertex {vertex} has a non-finite or out-of-range position ({x}, {y}, {z}); coordinates must be finite and at most {MAX_COORDINATE:e} in magnitude",
        .path.display()
    )]
    /// A stored vertex position is non-finite or beyond [`MAX_COORDINATE`].
    NonFinitePosition {
        /// The file.
        path: PathBuf,
        /// The primitive's mesh.
        mesh: MeshRef,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// The `POSITION` accessor.
        accessor: usize,
        /// Index of the vertex in that accessor.
        vertex: usize,
        /// Its stored x coordinate.
        x: f32,
        /// Its stored y coordinate.
        y: f32,
        /// Its stored z coordinate.
        z: f32,
    },

    /// The world transform composed down to a mesh's node is not finite
    /// (every local transform is, but their product overflows).
    #[error("{}: node {node} has a non-finite world transform", .path.display())]
    NonFiniteTransform {
        /// The file.
        path: PathBuf,
        /// Index of the node placing the mesh.
        node: usize,
    },

    #[error(
        "{}: node {node}, mesh {mesh} primitive {primitive}: vertex {vertex} is non-finite or beyond {MAX_COORDINATE:e} in magnitude after the node's world transform",
        .path.display()
    )]
    /// A vertex is non-finite or beyond [`MAX_COORDINATE`] once its node's
    /// world transform is applied.
    NonFiniteWorldPosition {
        /// The file.
        path: PathBuf,
        /// Index of the node placing the mesh.
        node: usize,
        /// The primitive's mesh.
        mesh: MeshRef,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// Index of the vertex in the primitive's `POSITION` accessor.
        vertex: usize,
    },

    #[error(
        "{}: no triangles in the scene ({primitives} triangle primitive(s) loaded, {skipped} non-triangle primitive(s) skipped)",
        .path.display()
    )]
    /// Nothing loaded holds a triangle.
    NoTriangles {
        /// The file.
        path: PathBuf,
        /// Triangle primitives loaded (all without triangles).
        primitives: usize,
        /// Primitives skipped because they are not triangles.
        skipped: usize,
    },

    /// The loaded vertices would not fit `u32` indices.
    #[error("{}: the scene has more than 2^32 - 1 vertices", .path.display())]
    TooLarge {
        /// The file.
        path: PathBuf,
    },

    /// The assembled mesh is rejected by [`TriMesh::new`].
    #[error("{}: {error}", .path.display())]
    Mesh {
        /// The file.
        path: PathBuf,
        /// Why the mesh was rejected.
        error: MeshError,
    },

    #[error(
        "{}: no skin: the scene has no node with both a mesh and a skin, so there is no character to load",
        .path.display()
    )]
    /// Character loading: no node of the scene has both a mesh and a skin.
    NoSkin {
        /// The file.
        path: PathBuf,
    },

    /// A skin cannot make a skeleton: bad joint list, inverse bind matrices
    /// or joint transforms, or skins that cannot merge into one skeleton.
    #[error("{}: skin {skin}: {reason}", .path.display())]
    Skin {
        /// The file.
        path: PathBuf,
        /// Index in the file's `skins`.
        skin: usize,
        /// What is wrong, on one line.
        reason: String,
    },

    /// A skinned primitive's `JOINTS_n`/`WEIGHTS_n` are missing, unpaired or
    /// out of range, or its weights do not sum to a positive number.
    #[error("{}: mesh {mesh} primitive {primitive}: {reason}", .path.display())]
    Skinning {
        /// The file.
        path: PathBuf,
        /// The primitive's mesh.
        mesh: MeshRef,
        /// Index of the primitive in its mesh.
        primitive: usize,
        /// What is wrong, on one line.
        reason: String,
    },

    /// An animation channel cannot be converted to a clip channel: bad
    /// target, sampler, keyframe times or values.
    #[error("{}: animation {animation} channel {channel}: {reason}", .path.display())]
    Animation {
        /// The file.
        path: PathBuf,
        /// Index in the file's `animations`.
        animation: usize,
        /// Index of the channel in that animation.
        channel: usize,
        /// What is wrong, on one line.
        reason: String,
    },
}

impl LoadError {
    /// The file the error is about.
    pub fn path(&self) -> &Path {
        match self {
            Self::Io { path, .. }
            | Self::NotGltf { path, .. }
            | Self::UnsupportedExtension { path, .. }
            | Self::Invalid { path, .. }
            | Self::Buffer { path, .. }
            | Self::NodeGraph { path, .. }
            | Self::Node { path, .. }
            | Self::Limit { path, .. }
            | Self::Compressed { path, .. }
            | Self::MissingPosition { path, .. }
            | Self::Accessor { path, .. }
            | Self::IndexOutOfRange { path, .. }
            | Self::NonFinitePosition { path, .. }
            | Self::NonFiniteTransform { path, .. }
            | Self::NonFiniteWorldPosition { path, .. }
            | Self::NoTriangles { path, .. }
            | Self::TooLarge { path }
            | Self::Mesh { path, .. }
            | Self::NoSkin { path }
            | Self::Skin { path, .. }
            | Self::Skinning { path, .. }
            | Self::Animation { path, .. } => path,
        }
    }
}

/// A primitive that was not loaded because it is not made of triangles.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SkippedPrimitive {
    /// The node that places the mesh.
    pub node: usize,
    /// The primitive's mesh.
    pub mesh: MeshRef,
    /// Index of the primitive in its mesh.
    pub primitive: usize,
    /// `POINTS`, `LINES`, `LINE_LOOP` or `LINE_STRIP`.
    pub mode: &'static str,
}

impl fmt::Display for SkippedPrimitive {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "node {}, mesh {} primitive {}: {} primitive skipped (not triangles)",
            self.node, self.mesh, self.primitive, self.mode
        )
    }
}

/// What was loaded and what was skipped.
#[derive(Clone, Debug, Default)]
pub struct LoadReport {
    /// The scene loaded; `None` when the file has no scene and every root node was used.
    pub scene: Option<usize>,
    /// Nodes reached from the scene's roots.
    pub nodes_visited: usize,
    /// Nodes with a mesh, i.e. mesh instances placed.
    pub meshes: usize,
    /// Different meshes among those instances.
    pub distinct_meshes: usize,
    /// Instances placed in bind pose because their node is skinned.
    pub skinned_instances: usize,
    /// Triangle primitives loaded (counted per instance).
    pub primitives: usize,
    /// Vertices in the loaded mesh.
    pub vertices: usize,
    /// Triangles in the loaded mesh.
    pub triangles: usize,
    /// Strip/fan triangles dropped because they repeat an index.
    pub degenerate_dropped: usize,
    /// Primitives that are not triangles.
    pub skipped: Vec<SkippedPrimitive>,
    /// Character loading only: nodes whose mesh was left out because it has
    /// no skin and hangs from no joint.
    pub unskinned_meshes: Vec<usize>,
    /// Character loading only: the skins whose joints make the one skeleton,
    /// in order of first use by the scene's skinned nodes.
    pub skins: Vec<usize>,
    /// Character loading only: meshes without a skin below a joint, bound
    /// wholly to that joint.
    pub attached_meshes: Vec<AttachedMesh>,
    /// Character loading only: vertices moved into the bind space of their
    /// joints' first skin (their skin's inverse bind matrices differ).
    pub moved_vertices: usize,
    /// Character loading only: joint slots added for inverse bind matrices
    /// that differ from their joint's first skin per vertex.
    pub added_joint_slots: usize,
    /// Character loading only: animation channels that were not converted.
    pub skipped_channels: Vec<SkippedChannel>,
    /// Other things worth knowing: ignored morph targets, stray indices, used extensions.
    pub notes: Vec<String>,
}

/// A mesh without a skin that the character loader bound rigidly to a joint.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct AttachedMesh {
    /// The mesh's node.
    pub node: usize,
    /// Index in the file's `meshes`.
    pub mesh: usize,
    /// The joint's node and name.
    pub joint_node: usize,
    /// The joint's name (see [`joint_node`](Self::joint_node)).
    pub joint: String,
}

/// An animation channel the character loader did not convert, and why.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SkippedChannel {
    /// Index in the file's `animations`.
    pub animation: usize,
    /// Index of the channel in that animation.
    pub channel: usize,
    /// The node the channel targets.
    pub node: usize,
    /// `translation`, `rotation`, `scale` or `weights`.
    pub property: &'static str,
    /// Why it was skipped.
    pub reason: String,
}

impl fmt::Display for SkippedChannel {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "animation {} channel {} ({} of node {}) skipped: {}",
            self.animation, self.channel, self.property, self.node, self.reason
        )
    }
}

/// Every triangle of the default scene (else the first scene, else all root
/// nodes), node transforms applied, as one mesh. See the module docs.
pub fn load_static_mesh(path: &Path) -> Result<(TriMesh, LoadReport), LoadError> {
    load_static_mesh_with(path, &LoadLimits::default())
}

/// [`load_static_mesh`] within `limits`.
pub fn load_static_mesh_with(
    path: &Path,
    limits: &LoadLimits,
) -> Result<(TriMesh, LoadReport), LoadError> {
    let bytes = read_file(path, limits)?;
    load_static_mesh_from(path, &bytes, limits)
}

/// [`load_static_mesh`] of a file already read into `bytes`: `path` names it
/// in messages and locates external buffers (relative to its folder).
pub fn load_static_mesh_from(
    path: &Path,
    bytes: &[u8],
    limits: &LoadLimits,
) -> Result<(TriMesh, LoadReport), LoadError> {
    let budget = Budget::new(limits);
    charge_file(path, &budget, bytes.len())?;
    let (document, blob) = parse(path, bytes, &budget)?;
    let buffers = load_buffers(path, &document, blob, budget)?;
    let mut loader = Loader {
        path,
        buffers: &buffers,
        positions: Vec::new(),
        triangles: Vec::new(),
        report: LoadReport::default(),
    };
    note_extensions(&document, &mut loader.report);
    loader.walk(&document)?;
    let Loader {
        positions,
        triangles,
        mut report,
        ..
    } = loader;
    if triangles.is_empty() {
        return Err(LoadError::NoTriangles {
            path: path.to_owned(),
            primitives: report.primitives,
            skipped: report.skipped.len(),
        });
    }
    report.vertices = positions.len();
    report.triangles = triangles.len();
    let mesh = TriMesh::new(positions, triangles).map_err(|error| LoadError::Mesh {
        path: path.to_owned(),
        error,
    })?;
    Ok((mesh, report))
}

/// The extensions the loaders read when a file requires them.
pub const SUPPORTED_EXTENSIONS: [&str; 3] = [
    super::gltf_draco::EXTENSION,
    super::gltf_meshopt::EXTENSION,
    "KHR_mesh_quantization",
];

/// Notes in `report` the extensions the file uses: decoded, or ignored.
pub(crate) fn note_extensions(document: &gltf::Document, report: &mut LoadReport) {
    for extension in document.extensions_used() {
        report
            .notes
            .push(if SUPPORTED_EXTENSIONS.contains(&extension) {
                format!("extension {extension} is used and read")
            } else {
                format!("extension {extension} is used but not required; its data is ignored")
            });
    }
}

/// The bytes of the file at `path`, refused past the budget before they are
/// read (a path such as `/dev/zero` ends at the budget).
pub(crate) fn read_file(path: &Path, limits: &LoadLimits) -> Result<Vec<u8>, LoadError> {
    let io = |error| LoadError::Io {
        path: path.to_owned(),
        error,
    };
    let file = std::fs::File::open(path).map_err(io)?;
    // Checked on the declared size, then on what was read (which may differ
    // for devices and files that grow).
    let fits = |bytes: usize| charge_file(path, &Budget::new(limits), bytes);
    let declared = file.metadata().map(|m| m.len()).unwrap_or(0);
    fits(usize::try_from(declared).unwrap_or(usize::MAX))?;
    let mut bytes = Vec::new();
    let most = u64::try_from(limits.max_bytes).unwrap_or(u64::MAX);
    file.take(most.saturating_add(1))
        .read_to_end(&mut bytes)
        .map_err(io)?;
    fits(bytes.len())?;
    Ok(bytes)
}

/// Charges a file's `bytes` to `budget` (a file over the budget is refused
/// before it is parsed).
pub(super) fn charge_file(path: &Path, budget: &Budget, bytes: usize) -> Result<(), LoadError> {
    budget
        .charge("the file", bytes, 1)
        .map_err(|reason| LoadError::Limit {
            path: path.to_owned(),
            reason,
        })
}

/// Charges what parsing `json` may allocate. A parsed object takes up to a
/// few hundred bytes (an empty node `{}`, three bytes of text, about 220), so
/// the text's length does not bound it: each `{` and `[` is charged 1 KiB,
/// and every byte 4 (a one-digit index in an array becomes a `u32`, doubled
/// while its vector grows).
fn charge_json(path: &Path, budget: &Budget, json: &[u8]) -> Result<(), LoadError> {
    let brackets = json.iter().filter(|&&b| b == b'{' || b == b'[').count();
    let cost = brackets
        .saturating_mul(1024)
        .saturating_add(json.len().saturating_mul(4));
    budget
        .charge(
            &format!(
                "parsing the JSON ({} bytes, {brackets} objects and arrays)",
                json.len()
            ),
            cost,
            1,
        )
        .map_err(|reason| LoadError::Limit {
            path: path.to_owned(),
            reason,
        })
}

/// Splits GLB or reads JSON, refuses required extensions, validates.
pub(crate) fn parse(
    path: &Path,
    bytes: &[u8],
    budget: &Budget,
) -> Result<(gltf::Document, Option<Vec<u8>>), LoadError> {
    let (root, blob) = parse_root(path, bytes, budget)?;
    validate(path, &root)?;
    Ok((gltf::Document::from_json_without_validation(root), blob))
}

/// Splits GLB or reads JSON and refuses required extensions, without
/// validating: callers may check things first to give a more specific error.
pub(crate) fn parse_root(
    path: &Path,
    bytes: &[u8],
    budget: &Budget,
) -> Result<(gltf::json::Root, Option<Vec<u8>>), LoadError> {
    let not_gltf = |reason: String| LoadError::NotGltf {
        path: path.to_owned(),
        reason: one_line(&reason),
    };
    let (root, blob): (gltf::json::Root, Option<Vec<u8>>) = if bytes.starts_with(b"glTF") {
        // gltf's GLB reader subtracts 12 from the declared length unchecked.
        let declared = bytes
            .get(8..12)
            .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]));
        if !matches!(declared, Some(n) if n >= 12) {
            return Err(not_gltf("truncated or corrupt GLB header".into()));
        }
        let glb = gltf::Glb::from_slice(bytes)
            .map_err(|e| not_gltf(format!("bad GLB container: {e}")))?;
        charge_json(path, budget, &glb.json)?;
        let root = gltf::json::deserialize::from_slice(&glb.json)
            .map_err(|e| not_gltf(format!("bad JSON chunk: {e}")))?;
        (root, glb.bin.map(|b| b.into_owned()))
    } else {
        charge_json(path, budget, bytes)?;
        let root = gltf::json::deserialize::from_slice(bytes)
            .map_err(|e| not_gltf(format!("neither GLB nor glTF JSON ({e})")))?;
        (root, None)
    };
    if !root.asset.version.starts_with("2.") {
        return Err(not_gltf(format!(
            "asset version {:?} is not 2.x",
            root.asset.version
        )));
    }
    let unsupported: Vec<String> = root
        .extensions_required
        .iter()
        .filter(|e| !SUPPORTED_EXTENSIONS.contains(&e.as_str()))
        .map(|e| one_line(e))
        .collect();
    if !unsupported.is_empty() {
        return Err(LoadError::UnsupportedExtension {
            path: path.to_owned(),
            extensions: unsupported,
        });
    }
    Ok((root, blob))
}

/// gltf's validation, which makes every index in the document safe to follow,
/// minus the checks of what gltf-json does not know (the compression
/// extensions in `extensionsRequired`, accessors a Draco stream fills) and
/// two checks this loader does not need: `min`/`max` on `POSITION`
/// accessors (often missing in the wild) and a missing `POSITION` (reported
/// later with mesh and primitive, and harmless on skipped primitives).
pub(crate) fn validate(path: &Path, root: &gltf::json::Root) -> Result<(), LoadError> {
    use gltf::json::validation::{Checked, Error, Validate};
    let invalid = |reason: String| LoadError::Invalid {
        path: path.to_owned(),
        reason: one_line(&reason),
    };
    // gltf's own validation indexes the accessor list with POSITION unchecked.
    for (m, mesh) in root.meshes.iter().enumerate() {
        for (p, primitive) in mesh.primitives.iter().enumerate() {
            let position = primitive
                .attributes
                .get(&Checked::Valid(gltf::json::mesh::Semantic::Positions));
            if let Some(accessor) = position.filter(|a| a.value() >= root.accessors.len()) {
                return Err(invalid(format!(
                    "mesh {m} primitive {p}: POSITION refers to accessor {}, which does not exist",
                    accessor.value()
                )));
            }
        }
    }
    // Accessors whose data a Draco stream holds have no buffer view.
    let mut from_draco = vec![false; root.accessors.len()];
    for primitive in root.meshes.iter().flat_map(|m| &m.primitives) {
        let draco = primitive
            .extensions
            .as_ref()
            .is_some_and(|e| e.others.contains_key(gltf_draco::EXTENSION));
        if draco {
            let accessors = primitive.attributes.values().chain(&primitive.indices);
            for accessor in accessors {
                if let Some(flag) = from_draco.get_mut(accessor.value()) {
                    *flag = true;
                }
            }
        }
    }
    let draco_accessor = |at: &str| {
        at.strip_prefix("accessors[")
            .and_then(|rest| rest.strip_suffix("].bufferView"))
            .and_then(|i| i.parse::<usize>().ok())
            .is_some_and(|i| from_draco.get(i).copied().unwrap_or(false))
    };
    let mut errors: Vec<String> = Vec::new();
    root.validate(
        root,
        gltf::json::Path::new,
        &mut |at: &dyn Fn() -> gltf::json::Path, error: Error| {
            let at = at();
            let at = at.as_str();
            let tolerated = at.ends_with("[\"POSITION\"].min")
                || at.ends_with("[\"POSITION\"].max")
                || (at.ends_with("attributes[\"POSITION\"]") && error == Error::Missing)
                // gltf-json knows none of the compression extensions; parse_root
                // refused every required extension the loaders do not read.
                || (at.starts_with("extensionsRequired[") && error == Error::Unsupported)
                || (draco_accessor(at) && error == Error::Missing);
            if !tolerated {
                errors.push(format!("{at}: {error}"));
            }
        },
    );
    if errors.is_empty() {
        return Ok(());
    }
    let more = errors.len().saturating_sub(3);
    errors.truncate(3);
    if more > 0 {
        errors.push(format!("and {more} more"));
    }
    Err(invalid(errors.join("; ")))
}

/// The bytes of every buffer: the GLB binary chunk, a `data:` URI, or a file
/// relative to the glTF file.
/// Each buffer's bytes are charged to `budget` before they are read (the
/// binary chunk is a copy of part of the file; a data URI decodes to 3/4 of
/// its length, charged whole; an external file is read no further than the
/// buffer's declared length), which is returned with them for decoding
/// accessors.
pub(crate) fn load_buffers(
    path: &Path,
    document: &gltf::Document,
    mut blob: Option<Vec<u8>>,
    budget: Budget,
) -> Result<Buffers, LoadError> {
    let base = path.parent().unwrap_or(Path::new("."));
    let mut buffers = Vec::new();
    for buffer in document.buffers() {
        let fail = |reason: String| LoadError::Buffer {
            path: path.to_owned(),
            buffer: buffer.index(),
            reason: one_line(&reason),
        };
        if gltf_meshopt::is_fallback(&buffer) {
            // Room for meshopt-decoded views only: its bytes, if it has any
            // (a URI), are never read.
            buffers.push(Data(Vec::new()));
            continue;
        }
        let data = match buffer.source() {
            Source::Bin => {
                let bin = blob.take().ok_or_else(|| {
                    fail("refers to the GLB binary chunk, which is missing".into())
                })?;
                budget
                    .charge("the binary chunk", bin.len(), 1)
                    .map_err(&fail)?;
                bin
            }
            Source::Uri(uri) if uri.starts_with("data:") => {
                // Decoding: about 3/4 of the URI's length.
                budget
                    .charge("decoding the data URI", uri.len(), 1)
                    .map_err(&fail)?;
                Data::from_source(Source::Uri(uri), None)
                    .map_err(|e| fail(format!("bad data URI: {e}")))?
                    .0
            }
            Source::Uri(uri) => {
                let file = if let Some(rest) = uri
                    .strip_prefix("file://")
                    .or_else(|| uri.strip_prefix("file:"))
                {
                    PathBuf::from(rest)
                } else if uri.contains(':') {
                    return Err(fail(format!("unsupported URI scheme in {uri:?}")));
                } else {
                    let relative = percent_decode(uri)
                        .ok_or_else(|| fail(format!("bad percent-encoding in URI {uri:?}")))?;
                    base.join(relative)
                };
                budget
                    .charge("reading the buffer", buffer.length(), 1)
                    .map_err(&fail)?;
                let mut data = Vec::new();
                std::fs::File::open(&file)
                    .and_then(|f| f.take(buffer.length() as u64).read_to_end(&mut data))
                    .map_err(|e| fail(format!("cannot read {}: {e}", file.display())))?;
                data
            }
        };
        if data.len() < buffer.length() {
            return Err(fail(format!(
                "declares {} bytes but has {}",
                buffer.length(),
                data.len()
            )));
        }
        buffers.push(Data(data));
    }
    Ok(Buffers::new(buffers, budget, document))
}

/// `%XX` escapes decoded; `None` if an escape is malformed or the result is not UTF-8.
fn percent_decode(uri: &str) -> Option<String> {
    let bytes = uri.as_bytes();
    let mut out = Vec::with_capacity(bytes.len());
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'%' {
            let hex = std::str::from_utf8(bytes.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
}

pub(crate) fn one_line(s: &str) -> String {
    s.split_whitespace().collect::<Vec<_>>().join(" ")
}

/// The scene to load (the default scene, else the first scene) and its root
/// nodes; with no scene, `None` and every node that is nobody's child.
pub(crate) fn scene_roots(document: &gltf::Document) -> (Option<usize>, Vec<gltf::Node<'_>>) {
    let scene = document
        .default_scene()
        .or_else(|| document.scenes().next());
    let roots: Vec<gltf::Node> = match &scene {
        Some(scene) => scene.nodes().collect(),
        None => {
            let mut is_child = vec![false; document.nodes().len()];
            for node in document.nodes() {
                for child in node.children() {
                    if let Some(flag) = is_child.get_mut(child.index()) {
                        *flag = true;
                    }
                }
            }
            document
                .nodes()
                .filter(|n| !is_child.get(n.index()).copied().unwrap_or(false))
                .collect()
        }
    };
    (scene.map(|s| s.index()), roots)
}

/// What both loaders read from a triangle primitive: its mode, its stored
/// positions (checked finite) and its indices (checked in range; `0..n` when
/// absent).
pub(crate) struct TrianglePrimitive {
    pub mode: Mode,
    pub positions: Vec<[f32; 3]>,
    pub indices: Vec<u32>,
}

/// Reads a primitive of mesh `mesh_ref` placed by `node`. `Ok(None)` for a
/// primitive that is not made of triangles (listed in `report.skipped`);
/// morph targets are noted. `vertices_before` is how many vertices the loader
/// holds already (the total must fit in `u32`).
pub(crate) fn read_triangle_primitive(
    path: &Path,
    buffers: &Buffers,
    node: usize,
    mesh_ref: &MeshRef,
    primitive: &gltf::Primitive<'_>,
    vertices_before: usize,
    report: &mut LoadReport,
) -> Result<Option<TrianglePrimitive>, LoadError> {
    let p = primitive.index();
    let mode = match primitive.mode() {
        m @ (Mode::Triangles | Mode::TriangleStrip | Mode::TriangleFan) => m,
        other => {
            let mode = match other {
                Mode::Points => "POINTS",
                Mode::Lines => "LINES",
                Mode::LineLoop => "LINE_LOOP",
                _ => "LINE_STRIP",
            };
            report.skipped.push(SkippedPrimitive {
                node,
                mesh: mesh_ref.clone(),
                primitive: p,
                mode,
            });
            return Ok(None);
        }
    };
    let accessor_error = |accessor: usize, reason: String| LoadError::Accessor {
        path: path.to_owned(),
        mesh: mesh_ref.clone(),
        primitive: p,
        accessor,
        reason: one_line(&reason),
    };
    let position_accessor =
        primitive
            .get(&Semantic::Positions)
            .ok_or_else(|| LoadError::MissingPosition {
                path: path.to_owned(),
                mesh: mesh_ref.clone(),
                primitive: p,
            })?;
    let draco_indices = gltf_draco::decode_primitive(primitive, buffers).map_err(|reason| {
        LoadError::Compressed {
            path: path.to_owned(),
            mesh: mesh_ref.clone(),
            primitive: p,
            reason: one_line(&reason),
        }
    })?;
    let stored = gltf_accessor::read_positions(&position_accessor, buffers)
        .map_err(|reason| accessor_error(position_accessor.index(), reason))?;
    if let Some((vertex, &[x, y, z])) = stored
        .iter()
        .enumerate()
        .find(|(_, v)| !v.iter().all(|c| c.abs() <= MAX_COORDINATE))
    {
        return Err(LoadError::NonFinitePosition {
            path: path.to_owned(),
            mesh: mesh_ref.clone(),
            primitive: p,
            accessor: position_accessor.index(),
            vertex,
            x,
            y,
            z,
        });
    }
    if vertices_before + stored.len() > u32::MAX as usize {
        return Err(LoadError::TooLarge {
            path: path.to_owned(),
        });
    }
    // The first index past the primitive's vertices: `(entry, index)`.
    let out_of_range = |indices: &[u32]| {
        indices
            .iter()
            .enumerate()
            .find(|(_, i)| **i as usize >= stored.len())
            .map(|(entry, &index)| (entry, index))
    };
    let indices = match (draco_indices, primitive.indices()) {
        (Some(indices), _) => {
            if let Some((entry, index)) = out_of_range(&indices) {
                return Err(LoadError::Compressed {
                    path: path.to_owned(),
                    mesh: mesh_ref.clone(),
                    primitive: p,
                    reason: format!(
                        "{}: decoded index {index} (entry {entry}) is out of range; the stream has {} points",
                        gltf_draco::EXTENSION,
                        stored.len()
                    ),
                });
            }
            indices
        }
        (None, Some(accessor)) => {
            let indices = gltf_accessor::read_indices(&accessor, buffers)
                .map_err(|reason| accessor_error(accessor.index(), reason))?;
            if let Some((entry, index)) = out_of_range(&indices) {
                return Err(LoadError::IndexOutOfRange {
                    path: path.to_owned(),
                    mesh: mesh_ref.clone(),
                    primitive: p,
                    accessor: accessor.index(),
                    entry,
                    index,
                    vertex_count: stored.len(),
                });
            }
            indices
        }
        // Fits: vertices_before + stored.len() <= u32::MAX was checked above.
        (None, None) => (0..stored.len() as u32).collect(),
    };
    let targets = primitive.morph_targets().len();
    if targets > 0 {
        report.notes.push(format!(
            "node {node}, mesh {mesh_ref} primitive {p}: {targets} morph target(s) ignored, positions as stored"
        ));
    }
    Ok(Some(TrianglePrimitive {
        mode,
        positions: stored,
        indices,
    }))
}

struct Loader<'a> {
    path: &'a Path,
    buffers: &'a Buffers,
    positions: Vec<Point>,
    triangles: Vec<[u32; 3]>,
    report: LoadReport,
}

impl Loader<'_> {
    /// Depth-first over the chosen roots, parents before children, in file order.
    fn walk(&mut self, document: &gltf::Document) -> Result<(), LoadError> {
        let (scene, roots) = scene_roots(document);
        self.report.scene = scene;
        // Marking nodes when pushed rejects cycles and shared subtrees, and bounds the work.
        let mut reached = vec![false; document.nodes().len()];
        let mut stack: Vec<(gltf::Node, Matrix4<f64>)> = Vec::new();
        for node in roots.into_iter().rev() {
            self.reach(&mut reached, node.index())?;
            stack.push((node, Matrix4::identity()));
        }
        let mut meshes_seen = vec![false; document.meshes().len()];
        while let Some((node, parent)) = stack.pop() {
            self.report.nodes_visited += 1;
            check_node_transform(&node).map_err(|reason| LoadError::Node {
                path: self.path.to_owned(),
                node: node.index(),
                reason,
            })?;
            let world = parent * local_matrix(&node);
            if let Some(mesh) = node.mesh() {
                if let Some(seen) = meshes_seen.get_mut(mesh.index())
                    && !*seen
                {
                    *seen = true;
                    self.report.distinct_meshes += 1;
                }
                self.report.meshes += 1;
                let placement = if node.skin().is_some() {
                    self.report.skinned_instances += 1;
                    Matrix4::identity()
                } else {
                    world
                };
                if !placement.iter().all(|c| c.is_finite()) {
                    return Err(LoadError::NonFiniteTransform {
                        path: self.path.to_owned(),
                        node: node.index(),
                    });
                }
                self.add_mesh(node.index(), &mesh, &placement)?;
            }
            let children: Vec<gltf::Node> = node.children().collect();
            for child in children.into_iter().rev() {
                self.reach(&mut reached, child.index())?;
                stack.push((child, world));
            }
        }
        Ok(())
    }

    fn reach(&self, reached: &mut [bool], node: usize) -> Result<(), LoadError> {
        match reached.get_mut(node) {
            Some(flag) if !*flag => {
                *flag = true;
                Ok(())
            }
            _ => Err(LoadError::NodeGraph {
                path: self.path.to_owned(),
                node,
            }),
        }
    }

    fn add_mesh(
        &mut self,
        node: usize,
        mesh: &gltf::Mesh<'_>,
        placement: &Matrix4<f64>,
    ) -> Result<(), LoadError> {
        let mesh_ref = MeshRef::of(mesh);
        for primitive in mesh.primitives() {
            let p = primitive.index();
            let base = self.positions.len();
            let Some(TrianglePrimitive {
                mode,
                positions: stored,
                indices,
            }) = read_triangle_primitive(
                self.path,
                self.buffers,
                node,
                &mesh_ref,
                &primitive,
                base,
                &mut self.report,
            )?
            else {
                continue;
            };
            for (vertex, v) in stored.iter().enumerate() {
                let w = placement.transform_point(&Point3::new(
                    f64::from(v[0]),
                    f64::from(v[1]),
                    f64::from(v[2]),
                ));
                let w = Point::new(w.x as f32, w.y as f32, w.z as f32);
                if !w.iter().all(|c| c.abs() <= MAX_COORDINATE) {
                    return Err(LoadError::NonFiniteWorldPosition {
                        path: self.path.to_owned(),
                        node,
                        mesh: mesh_ref.clone(),
                        primitive: p,
                        vertex,
                    });
                }
                self.positions.push(w);
            }
            let before = self.triangles.len();
            let offset = base as u32;
            let (leftover, degenerate) = assemble(mode, &indices, |t| {
                self.triangles
                    .push([t[0] + offset, t[1] + offset, t[2] + offset]);
            });
            self.report.degenerate_dropped += degenerate;
            if leftover > 0 {
                self.report.notes.push(format!(
                    "node {node}, mesh {mesh_ref} primitive {p}: {} indices is not a multiple of 3; last {leftover} ignored",
                    indices.len()
                ));
            }
            if self.triangles.len() == before {
                self.report.notes.push(format!(
                    "node {node}, mesh {mesh_ref} primitive {p}: no triangles"
                ));
            }
            self.report.primitives += 1;
        }
        Ok(())
    }
}

/// A node's local transform must be finite, and a rotation must be a
/// quaternion that can be normalised (not zero, no overflowing length).
pub(crate) fn check_node_transform(node: &gltf::Node<'_>) -> Result<(), String> {
    let refuse =
        |what: String, x: f32| Err(format!("{what} is {x}; only finite numbers are accepted"));
    match node.transform() {
        Transform::Matrix { matrix } => {
            for (c, column) in matrix.iter().enumerate() {
                for (r, &x) in column.iter().enumerate() {
                    if !x.is_finite() {
                        return refuse(
                            format!("matrix entry {} (column {c}, row {r})", 4 * c + r),
                            x,
                        );
                    }
                }
            }
        }
        Transform::Decomposed {
            translation,
            rotation,
            scale,
        } => {
            for (what, values) in [
                ("translation", &translation[..]),
                ("rotation", &rotation[..]),
                ("scale", &scale[..]),
            ] {
                if let Some((i, &x)) = values.iter().enumerate().find(|(_, x)| !x.is_finite()) {
                    return refuse(format!("{what} component {i}"), x);
                }
            }
            let norm = rotation
                .iter()
                .map(|&x| f64::from(x).powi(2))
                .sum::<f64>()
                .sqrt();
            if norm == 0.0 {
                return Err(format!(
                    "rotation {rotation:?} is the zero quaternion, not a rotation"
                ));
            }
        }
    }
    Ok(())
}

/// A node's local transform (checked by [`check_node_transform`]). Rotations
/// are normalised (the spec requires unit quaternions).
pub(crate) fn local_matrix(node: &gltf::Node<'_>) -> Matrix4<f64> {
    match node.transform() {
        // glTF matrices are column-major: matrix[column][row].
        Transform::Matrix { matrix } => Matrix4::from_fn(|r, c| f64::from(matrix[c][r])),
        Transform::Decomposed {
            translation: t,
            rotation: q,
            scale: s,
        } => {
            let v = |a: [f32; 3]| Vector3::new(f64::from(a[0]), f64::from(a[1]), f64::from(a[2]));
            let rotation = UnitQuaternion::from_quaternion(Quaternion::new(
                f64::from(q[3]),
                f64::from(q[0]),
                f64::from(q[1]),
                f64::from(q[2]),
            ));
            Matrix4::new_translation(&v(t))
                * rotation.to_homogeneous()
                * Matrix4::new_nonuniform_scaling(&v(s))
        }
    }
}

/// Emits the triangles of `indices` under `mode` (a triangle mode) with the
/// glTF winding. Returns (indices left over in `TRIANGLES`, strip/fan
/// triangles dropped for repeating an index).
pub(crate) fn assemble(
    mode: Mode,
    indices: &[u32],
    mut emit: impl FnMut([u32; 3]),
) -> (usize, usize) {
    if !matches!(mode, Mode::TriangleStrip | Mode::TriangleFan) {
        let chunks = indices.chunks_exact(3);
        let leftover = chunks.remainder().len();
        for t in chunks {
            emit([t[0], t[1], t[2]]);
        }
        return (leftover, 0);
    }
    let mut degenerate = 0;
    let mut keep = |t: [u32; 3]| {
        if t[0] == t[1] || t[1] == t[2] || t[0] == t[2] {
            degenerate += 1;
        } else {
            emit(t);
        }
    };
    if mode == Mode::TriangleStrip {
        // Spec: triangle i is (v_i, v_{i+1+i%2}, v_{i+2-i%2}).
        for (i, w) in indices.windows(3).enumerate() {
            keep(if i % 2 == 0 {
                [w[0], w[1], w[2]]
            } else {
                [w[0], w[2], w[1]]
            });
        }
    } else if let Some((&first, rest)) = indices.split_first() {
        // Spec: triangle i is (v_{i+1}, v_{i+2}, v_0).
        for w in rest.windows(2) {
            keep([w[0], w[1], first]);
        }
    }
    (0, degenerate)
}
