//! Skinned glTF 2.0 characters: skeleton, bind-pose mesh, influences and clips
//! as one [`Character`].
//!
//! [`load_character`] reads `.glb`/`.gltf` with the static loader's checked
//! parsing, buffer loading and accessor reading, and:
//!
//! - **Mesh.** Every node of the default scene (else the first scene, else all
//!   root nodes) that has both a mesh and a skin, whatever its skin. Their
//!   triangle primitives are concatenated into one [`TriMesh`] with positions
//!   as stored (bind space: the spec says the skinned node's own transform is
//!   ignored), or moved into the bind space of their joints' first skin when
//!   their skin's inverse bind matrices differ (module `gltf_bind`). A
//!   mesh node without a skin at or below a joint (a prop in a hand) is bound
//!   wholly to that joint, placed by the node transforms from the joint down
//!   ([`LoadReport::attached_meshes`]); other meshes without a skin are left
//!   out and listed in [`LoadReport::unskinned_meshes`]. Non-triangle
//!   primitives are listed in [`LoadReport::skipped`]; morph targets are
//!   ignored (base positions) with a note. No skinned node at all is
//!   [`LoadError::NoSkin`].
//! - **Skeleton.** One skeleton for all skins: the union of the `joints` of
//!   every skin the skinned nodes use ([`LoadReport::skins`]; a joint listed by
//!   several skins is one joint), in order of first listing, reordered so
//!   parents come before children (the file's order is kept where it already
//!   does); `JOINTS_n` are remapped accordingly, per skin. A joint's parent is
//!   its nearest ancestor node that is a joint of some skin; a non-joint node
//!   between two joints must have the identity transform (else an error).
//!   Rest pose = each joint node's local TRS; a `matrix` is decomposed (shear,
//!   projection or zero scale is an error). The transforms of joints and of
//!   every node above them must be finite (named by node and component).
//!   Inverse bind matrices come from each skin's accessor (identity when
//!   absent) and must be finite and affine; fewer than joints is an error,
//!   extra ones are noted. A joint takes the matrices of the first skin that
//!   lists it; where another skin's differ and its vertices cannot be moved,
//!   the joint gets added slots that follow it (module `gltf_bind`,
//!   [`LoadReport::added_joint_slots`]). The base is the world transform of
//!   the root joints' parent node (identity for a scene root); root joints
//!   whose parents have different world transforms are an error. Errors about
//!   a joint name the first skin that lists it.
//! - **Influences.** `JOINTS_n`/`WEIGHTS_n` in every core format (joints u8 or
//!   u16; weights float or normalized u8/u16). With more than one set, each
//!   vertex keeps its four largest weights (renormalised by [`Influences`]);
//!   vertices that lost a non-zero weight are counted in a note. A skinned
//!   primitive without `JOINTS_0`/`WEIGHTS_0` is an error, as are joint indices
//!   out of range of its skin, non-finite weights (named by accessor and element) or
//!   weights that do not sum to a positive number (named by mesh, primitive
//!   and the primitive's own vertex index).
//! - **Clips.** One per animation (`name`, else `"animation N"`). Translation,
//!   rotation and scale channels of joints become [`Channel`]s with their
//!   interpolation (STEP, LINEAR, CUBICSPLINE); rotations in float or any
//!   normalized integer format are converted per the spec. Channels on other
//!   nodes (a rigid mesh's own node included) and morph-weight channels are skipped and listed in
//!   [`LoadReport::skipped_channels`]. A channel targeting a node that does not
//!   exist, or a sampler whose output count does not match its input, is an
//!   error. So is damaged keyframe data in a channel that is converted: a time
//!   or value that is not finite, or times that do not strictly increase (the
//!   spec's rule), named by animation, channel, sampler, accessor and
//!   element. Such a channel is not skipped: the file is damaged, and playing
//!   the rest of it would hide that.
//!
//! Every [`LoadError`] is one line naming the file; malformed data is an error,
//! never a panic. What the file makes the loader allocate is charged to a
//! byte budget first ([`LoadLimits`]); walks over the node graph are
//! iterative and visit each node a bounded number of times.
//! [`load_character_from`] loads from bytes already in memory.

use std::path::Path;

use gltf::animation::{Interpolation as GltfInterpolation, Property};
use gltf::mesh::{Mode, Semantic};
use gltf::scene::Transform;
use nalgebra::{Matrix3, Matrix4, Point3, Quaternion, Rotation3, UnitQuaternion, Vector3};

use super::gltf_accessor::{self, Buffers};
use super::gltf_bind::{Attachments, JointSlots, place};
use super::gltf_static::{
    AttachedMesh, LoadError, LoadReport, MeshRef, SkippedChannel, TrianglePrimitive, assemble,
    charge_file, check_node_transform, load_buffers, local_matrix, note_extensions, one_line,
    parse_root, read_file, read_triangle_primitive, scene_roots, validate,
};
use super::limits::{Budget, LoadLimits, MAX_COORDINATE};
use crate::character::skeleton::exactly_affine;
use crate::character::skinning::SkinError;
use crate::character::{
    Channel, ChannelValues, Character, Clip, Influences, Interpolation, Joint, JointId, Skeleton,
    SkeletonError, Trs,
};
use crate::geometry::Point;
use crate::mesh::TriMesh;

/// Tolerance for "is the identity" and "is a rotation" checks on stored matrices.
const MATRIX_TOLERANCE: f64 = 1e-4;

/// The skinned character of a glTF file's default scene. See the module docs.
pub fn load_character(path: &Path) -> Result<(Character, LoadReport), LoadError> {
    load_character_with(path, &LoadLimits::default())
}

/// [`load_character`] within `limits`.
pub fn load_character_with(
    path: &Path,
    limits: &LoadLimits,
) -> Result<(Character, LoadReport), LoadError> {
    let bytes = read_file(path, limits)?;
    load_character_from(path, &bytes, limits)
}

/// [`load_character`] of a file already read into `bytes`: `path` names it in
/// messages and locates external buffers (relative to its folder).
pub fn load_character_from(
    path: &Path,
    bytes: &[u8],
    limits: &LoadLimits,
) -> Result<(Character, LoadReport), LoadError> {
    let budget = Budget::new(limits);
    charge_file(path, &budget, bytes.len())?;
    let (root, blob) = parse_root(path, bytes, &budget)?;
    check_channel_targets(path, &root)?;
    validate(path, &root)?;
    let document = gltf::Document::from_json_without_validation(root);
    let buffers = load_buffers(path, &document, blob, budget)?;
    let mut loader = CharacterLoader {
        path,
        buffers: &buffers,
        report: LoadReport::default(),
    };
    note_extensions(&document, &mut loader.report);
    let character = loader.load(&document)?;
    Ok((character, loader.report))
}

/// The gltf crate's validation reports a channel on a missing node as a generic
/// index error, and does not look at a channel's target path at all (reading
/// an unknown one panics); this names both.
fn check_channel_targets(path: &Path, root: &gltf::json::Root) -> Result<(), LoadError> {
    let nodes = root.nodes.len();
    for (a, animation) in root.animations.iter().enumerate() {
        for (c, channel) in animation.channels.iter().enumerate() {
            let node = channel.target.node.value();
            if !matches!(
                channel.target.path,
                gltf::json::validation::Checked::Valid(_)
            ) {
                return Err(LoadError::Animation {
                    path: path.to_owned(),
                    animation: a,
                    channel: c,
                    reason: "target path is not one of translation, rotation, scale, weights"
                        .into(),
                });
            }
            if node >= nodes {
                return Err(LoadError::Animation {
                    path: path.to_owned(),
                    animation: a,
                    channel: c,
                    reason: format!(
                        "channel targeting no node: node {node} does not exist (the file has {nodes} nodes)"
                    ),
                });
            }
        }
    }
    Ok(())
}

/// One `JOINTS_n`/`WEIGHTS_n` pair of a primitive.
type InfluenceSet = (Vec<[u16; 4]>, Vec<[f32; 4]>);

/// Where a primitive's vertices start in the concatenated mesh.
struct PrimitiveRange {
    start: usize,
    mesh: MeshRef,
    primitive: usize,
}

struct CharacterLoader<'a> {
    path: &'a Path,
    buffers: &'a Buffers,
    report: LoadReport,
}

impl CharacterLoader<'_> {
    fn load(&mut self, document: &gltf::Document) -> Result<Character, LoadError> {
        let parents = self.node_parents(document)?;

        // Mesh instances of the scene.
        let (scene, roots) = scene_roots(document);
        self.report.scene = scene;
        let mut reached = vec![false; document.nodes().len()];
        let mut stack: Vec<gltf::Node> = roots.into_iter().rev().collect();
        for node in &stack {
            self.reach(&mut reached, node.index())?;
        }
        let mut skinned: Vec<(gltf::Node, gltf::Mesh, gltf::Skin)> = Vec::new();
        let mut unskinned: Vec<(gltf::Node, gltf::Mesh)> = Vec::new();
        let mut meshes_seen = vec![false; document.meshes().len()];
        while let Some(node) = stack.pop() {
            self.report.nodes_visited += 1;
            if let Some(mesh) = node.mesh() {
                self.report.meshes += 1;
                if let Some(seen) = meshes_seen.get_mut(mesh.index())
                    && !*seen
                {
                    *seen = true;
                    self.report.distinct_meshes += 1;
                }
                match node.skin() {
                    Some(skin) => skinned.push((node.clone(), mesh, skin)),
                    None => unskinned.push((node.clone(), mesh)),
                }
            }
            let children: Vec<gltf::Node> = node.children().collect();
            for child in children.into_iter().rev() {
                self.reach(&mut reached, child.index())?;
                stack.push(child);
            }
        }
        if skinned.is_empty() {
            return Err(LoadError::NoSkin {
                path: self.path.to_owned(),
            });
        }
        // The skins of the skinned nodes, in order of first use.
        let mut skins: Vec<gltf::Skin> = Vec::new();
        let mut position_of_skin: Vec<Option<usize>> = vec![None; document.skins().len()];
        let mut skin_of_node: Vec<usize> = Vec::with_capacity(skinned.len());
        for (_, _, skin) in &skinned {
            let mut add = || {
                skins.push(skin.clone());
                skins.len() - 1
            };
            // The index was validated; a missing slot would only lose sharing.
            let s = match position_of_skin.get_mut(skin.index()) {
                Some(slot) => *slot.get_or_insert_with(add),
                None => add(),
            };
            skin_of_node.push(s);
        }
        self.report.skinned_instances = skinned.len();
        self.report.skins = skins.iter().map(|s| s.index()).collect();

        let skel = self.skeleton(document, &skins, &parents)?;

        // Mesh and influences: skinned meshes, then rigid meshes below a joint.
        let mut slots = JointSlots::new(&skel.skeleton);
        let mut data = MeshData::default();
        for ((node, mesh, _), &s) in skinned.iter().zip(&skin_of_node) {
            self.add_skinned_mesh(node.index(), mesh, &skel, s, &mut slots, &mut data)?;
        }
        let nodes: Vec<gltf::Node> = document.nodes().collect();
        let mut attachments = Attachments::new(nodes.len());
        let is_joint = |n: usize| skel.skin_index.get(n).is_some_and(Option::is_some);
        let path = self.path;
        let mut local = |n: usize| -> Result<Matrix4<f64>, LoadError> {
            check_node_transform(&nodes[n]).map_err(|reason| LoadError::Node {
                path: path.to_owned(),
                node: n,
                reason,
            })?;
            Ok(local_matrix(&nodes[n]))
        };
        for (node, mesh) in &unskinned {
            match attachments.of(node.index(), &parents, &is_joint, &mut local)? {
                Some((joint_node, frame)) => self.add_rigid_mesh(
                    node.index(),
                    mesh,
                    joint_node,
                    &frame,
                    &skel,
                    &mut slots,
                    &mut data,
                )?,
                None => {
                    self.report.unskinned_meshes.push(node.index());
                    self.report.notes.push(format!(
                        "node {}: mesh {} is not skinned and hangs from no joint; left out of the character",
                        node.index(),
                        mesh.index()
                    ));
                }
            }
        }
        if data.triangles.is_empty() {
            return Err(LoadError::NoTriangles {
                path: self.path.to_owned(),
                primitives: self.report.primitives,
                skipped: self.report.skipped.len(),
            });
        }
        self.report.vertices = data.positions.len();
        self.report.triangles = data.triangles.len();
        self.report.added_joint_slots = slots.added();
        let skeleton = slots
            .finish(skel.skeleton.clone())
            .map_err(|e| self.skin_error(&skins[0], e.to_string()))?;
        if skins.len() > 1 {
            self.report.notes.push(format!(
                "{} merged into one skeleton of {} joints",
                skins_label(&self.report.skins),
                skel.skeleton.len()
            ));
        }
        if self.report.moved_vertices > 0 {
            self.report.notes.push(format!(
                "{} vertices moved into the bind space of their joints' first skin (their own skin's inverse bind matrices differ from it by one transform)",
                self.report.moved_vertices
            ));
        }
        if slots.added() > 0 {
            self.report.notes.push(format!(
                "{} joint slot(s) added for inverse bind matrices that differ from their joint's first skin (each follows its joint)",
                slots.added()
            ));
        }
        let joint_count = skeleton.len();
        let MeshData {
            positions,
            triangles,
            joints,
            weights,
            ranges,
        } = data;
        let influences = Influences::new(joints, weights, joint_count)
            .map_err(|error| self.influence_error(&ranges, &skins[0], joint_count, error))?;
        let mesh = TriMesh::new(positions, triangles).map_err(|error| LoadError::Mesh {
            path: self.path.to_owned(),
            error,
        })?;

        let clips = self.clips(document, &skel, &parents, joint_count)?;
        let name = self
            .path
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "character".to_owned());
        Ok(Character::new(name, skeleton, mesh, influences, clips))
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

    /// The parent of every node of the file; a node with two parents, or a
    /// cycle, is an error, so walking up always ends.
    fn node_parents(&self, document: &gltf::Document) -> Result<Vec<Option<usize>>, LoadError> {
        let n = document.nodes().len();
        let graph_error = |node| LoadError::NodeGraph {
            path: self.path.to_owned(),
            node,
        };
        let mut parents: Vec<Option<usize>> = vec![None; n];
        for node in document.nodes() {
            for child in node.children() {
                let slot = parents
                    .get_mut(child.index())
                    .ok_or(graph_error(child.index()))?;
                if slot.is_some() {
                    return Err(graph_error(child.index()));
                }
                *slot = Some(node.index());
            }
        }
        // 0 = not seen, 1 = on the current upward walk, 2 = known to end at a root.
        let mut state = vec![0u8; n];
        for start in 0..n {
            let mut chain = Vec::new();
            let mut cur = Some(start);
            while let Some(c) = cur {
                match state[c] {
                    2 => break,
                    1 => return Err(graph_error(c)),
                    _ => {
                        state[c] = 1;
                        chain.push(c);
                        cur = parents[c];
                    }
                }
            }
            for c in chain {
                state[c] = 2;
            }
        }
        Ok(parents)
    }

    fn skin_error(&self, skin: &gltf::Skin<'_>, reason: String) -> LoadError {
        LoadError::Skin {
            path: self.path.to_owned(),
            skin: skin.index(),
            reason: one_line(&reason),
        }
    }

    /// The one skeleton of `skins` (the skins of the skinned nodes, in order
    /// of first use): the union of their joints.
    fn skeleton(
        &mut self,
        document: &gltf::Document,
        skins: &[gltf::Skin<'_>],
        parents: &[Option<usize>],
    ) -> Result<SkeletonMap, LoadError> {
        let nodes: Vec<gltf::Node> = document.nodes().collect();
        // The union of the skins' joints in order of first listing: node →
        // union index, and which (skin, entry) listed each joint first.
        let mut skin_index: Vec<Option<usize>> = vec![None; nodes.len()];
        let mut joint_nodes: Vec<usize> = Vec::new();
        let mut first_listed: Vec<(usize, usize)> = Vec::new();
        let mut listed_in: Vec<Option<(usize, usize)>> = vec![None; nodes.len()];
        let mut skin_entries: Vec<Vec<usize>> = Vec::with_capacity(skins.len());
        for (s, skin) in skins.iter().enumerate() {
            let entries: Vec<usize> = skin.joints().map(|n| n.index()).collect();
            if entries.is_empty() {
                return Err(self.skin_error(skin, "has no joints".into()));
            }
            if entries.len() > u16::MAX as usize {
                return Err(self.skin_error(
                    skin,
                    format!("has {} joints; at most 65535 are supported", entries.len()),
                ));
            }
            let mut unions = Vec::with_capacity(entries.len());
            for (k, &node) in entries.iter().enumerate() {
                let slot = listed_in.get_mut(node).ok_or_else(|| {
                    self.skin_error(
                        skin,
                        format!("joint {k} is node {node}, which does not exist"),
                    )
                })?;
                if let Some((s0, first)) = *slot
                    && s0 == s
                {
                    return Err(self.skin_error(
                        skin,
                        format!("node {node} is listed twice in joints (entries {first} and {k})"),
                    ));
                }
                *slot = Some((s, k));
                let u = match skin_index[node] {
                    Some(u) => u,
                    None => {
                        skin_index[node] = Some(joint_nodes.len());
                        joint_nodes.push(node);
                        first_listed.push((s, k));
                        joint_nodes.len() - 1
                    }
                };
                unions.push(u);
            }
            skin_entries.push(unions);
        }
        if joint_nodes.len() > u16::MAX as usize {
            return Err(self.skin_error(
                &skins[0],
                format!(
                    "{} together have {} joints; at most 65535 are supported",
                    skins_label(&self.report.skins),
                    joint_nodes.len()
                ),
            ));
        }
        // The skin named in errors about a joint of the union: its first.
        let skin_of = |u: usize| &skins[first_listed[u].0];

        // The skeleton reads the transforms of the joints and of every node
        // above them: each is checked once, and its local matrix kept.
        let mut local: Vec<Option<Matrix4<f64>>> = vec![None; nodes.len()];
        for &node in &joint_nodes {
            let mut cur = Some(node);
            while let Some(c) = cur
                && local[c].is_none()
            {
                check_node_transform(&nodes[c]).map_err(|reason| LoadError::Node {
                    path: self.path.to_owned(),
                    node: c,
                    reason,
                })?;
                local[c] = Some(local_matrix(&nodes[c]));
                cur = parents[c];
            }
        }
        let local_of = |n: usize| local[n].unwrap_or_else(Matrix4::identity);

        // For each node above a joint: its nearest joint ancestor, and the
        // nearest non-joint node with a non-identity transform between the
        // two. Filled top-down along each upward chain, so every node is
        // computed once.
        let mut above: Vec<Option<(Option<usize>, Option<usize>)>> = vec![None; nodes.len()];
        for &node in &joint_nodes {
            let mut chain = Vec::new();
            let mut cur = Some(node);
            while let Some(c) = cur
                && above[c].is_none()
            {
                chain.push(c);
                cur = parents[c];
            }
            for &c in chain.iter().rev() {
                above[c] = Some(match parents[c] {
                    None => (None, None),
                    Some(p) if skin_index[p].is_some() => (Some(p), None),
                    Some(p) => {
                        let (joint, bad) = above[p].unwrap_or((None, None));
                        let bad = if is_identity(&local_of(p)) {
                            bad
                        } else {
                            Some(p)
                        };
                        (joint, bad)
                    }
                });
            }
        }

        // World transforms (rest) of the nodes root joints hang from, each
        // node's computed once from its parent's.
        let mut world: Vec<Option<Matrix4<f64>>> = vec![None; nodes.len()];
        let mut world_of = |node: usize| -> Matrix4<f64> {
            let mut chain = Vec::new();
            let mut cur = Some(node);
            while let Some(c) = cur
                && world[c].is_none()
            {
                chain.push(c);
                cur = parents[c];
            }
            let mut m = cur.and_then(|c| world[c]).unwrap_or_else(Matrix4::identity);
            for &c in chain.iter().rev() {
                m *= local_of(c);
                world[c] = Some(m);
            }
            m
        };

        // Nearest joint ancestor of each joint, and the parent node of each root joint.
        let mut parent_joint: Vec<Option<usize>> = vec![None; joint_nodes.len()];
        let mut base: Option<(usize, Option<usize>, Matrix4<f64>)> = None;
        for (k, &node) in joint_nodes.iter().enumerate() {
            let (joint, bad) = above[node].unwrap_or((None, None));
            if let Some(j) = joint {
                parent_joint[k] = skin_index[j];
                if let Some(b) = bad {
                    return Err(self.skin_error(
                        skin_of(k),
                        format!(
                            "node {b} lies between joint nodes {j} and {node} but is not a joint of the skin and has a non-identity transform (not supported)"
                        ),
                    ));
                }
            } else {
                let parent = parents[node];
                let world = match parent {
                    Some(p) => world_of(p),
                    None => Matrix4::identity(),
                };
                match &base {
                    None => base = Some((node, parent, world)),
                    Some((first, first_parent, first_world)) => {
                        let scale = first_world.abs().max().max(world.abs().max()).max(1.0);
                        // Not `>`: an overflowing world transform gives NaN.
                        let close = (first_world - world).abs().max() <= MATRIX_TOLERANCE * scale;
                        if !close {
                            return Err(self.skin_error(
                                skin_of(k),
                                format!(
                                    "root joints node {first} and node {node} hang from nodes {} and {} with different world transforms; one skeleton base is supported",
                                    node_name(*first_parent),
                                    node_name(parent)
                                ),
                            ));
                        }
                    }
                }
            }
        }
        let (_, _, base) = base.ok_or_else(|| {
            self.skin_error(&skins[0], "has no root joint (joints form a cycle)".into())
        })?;

        // Parents-first order, keeping the file's order where it allows.
        let mut order: Vec<usize> = Vec::with_capacity(joint_nodes.len());
        let mut joint_id: Vec<Option<u16>> = vec![None; joint_nodes.len()];
        for k in 0..joint_nodes.len() {
            let mut chain = Vec::new();
            let mut cur = Some(k);
            while let Some(c) = cur {
                if joint_id[c].is_some() {
                    break;
                }
                chain.push(c);
                cur = parent_joint[c];
            }
            for &c in chain.iter().rev() {
                joint_id[c] = Some(order.len() as u16);
                order.push(c);
            }
        }
        let joint_id: Vec<u16> = joint_id.into_iter().map(|j| j.unwrap_or(0)).collect();

        // Inverse bind matrices of every skin; a joint takes its first skin's.
        let mut inverse_binds: Vec<Vec<Matrix4<f32>>> = Vec::with_capacity(skins.len());
        for (skin, entries) in skins.iter().zip(&skin_entries) {
            inverse_binds.push(self.inverse_binds(skin, entries.len())?);
        }

        let mut joints = Vec::with_capacity(order.len());
        for &k in &order {
            let node = &nodes[joint_nodes[k]];
            let rest = node_trs(node).map_err(|e| {
                self.skin_error(skin_of(k), format!("joint node {}: {e}", node.index()))
            })?;
            let (s, entry) = first_listed[k];
            joints.push(Joint {
                name: node
                    .name()
                    .map(str::to_owned)
                    .unwrap_or_else(|| format!("node {}", node.index())),
                parent: parent_joint[k].map(|p| JointId(joint_id[p])),
                rest,
                inverse_bind: inverse_binds[s][entry],
            });
        }
        let base32: Matrix4<f32> = base.cast();
        if !base32.iter().all(|c| c.is_finite()) {
            return Err(self.skin_error(
                &skins[0],
                "the skeleton base transform is not finite".into(),
            ));
        }
        let skeleton = Skeleton::new(joints, base32).map_err(|e| {
            let skin = skeleton_error_joint(&e)
                .and_then(|i| order.get(i))
                .map_or(&skins[0], |&k| skin_of(k));
            self.skin_error(skin, e.to_string())
        })?;
        if order.iter().enumerate().any(|(i, &k)| i != k) {
            self.report.notes.push(format!(
                "{}: joints reordered so parents come before children",
                skins_label(&self.report.skins)
            ));
        }
        let skins = skins
            .iter()
            .zip(skin_entries)
            .zip(inverse_binds)
            .map(|((skin, entries), inverse_binds)| SkinJoints {
                index: skin.index(),
                joints: entries.iter().map(|&u| joint_id[u]).collect(),
                inverse_binds,
            })
            .collect();
        Ok(SkeletonMap {
            skeleton,
            joint_nodes,
            joint_id,
            skin_index,
            skins,
        })
    }

    /// The inverse bind matrices of `skin` (`joints` entries; identity when
    /// absent), each with an exact `[0, 0, 0, 1]` fourth row.
    fn inverse_binds(
        &mut self,
        skin: &gltf::Skin<'_>,
        joints: usize,
    ) -> Result<Vec<Matrix4<f32>>, LoadError> {
        let Some(accessor) = skin.inverse_bind_matrices() else {
            return Ok(vec![Matrix4::identity(); joints]);
        };
        let a = accessor.index();
        let m = gltf_accessor::read_mat4_f32(&accessor, self.buffers, "inverseBindMatrices")
            .map_err(|e| self.skin_error(skin, format!("accessor {a}: {e}")))?;
        if m.len() < joints {
            return Err(self.skin_error(
                skin,
                format!(
                    "inverseBindMatrices accessor {a} has {} matrices for {joints} joints",
                    m.len(),
                ),
            ));
        }
        if m.len() > joints {
            self.report.notes.push(format!(
                "skin {}: inverseBindMatrices has {} matrices for {joints} joints; extra ignored",
                skin.index(),
                m.len(),
            ));
        }
        m.iter()
            .take(joints)
            .enumerate()
            .map(|(k, c)| {
                let m = Matrix4::from_column_slice(c);
                exactly_affine(m).ok_or_else(|| {
                    self.skin_error(
                        skin,
                        format!(
                            "inverseBindMatrices accessor {a} element {k}: the fourth row is {:?}, not [0, 0, 0, 1]",
                            [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)]]
                        ),
                    )
                })
            })
            .collect()
    }

    /// The triangle primitives of skinned node `node` (skin `skel.skins[s]`).
    fn add_skinned_mesh(
        &mut self,
        node: usize,
        mesh: &gltf::Mesh<'_>,
        skel: &SkeletonMap,
        s: usize,
        slots: &mut JointSlots,
        data: &mut MeshData,
    ) -> Result<(), LoadError> {
        let mesh_ref = MeshRef::of(mesh);
        let skin = &skel.skins[s];
        let identity = Matrix4::identity();
        let origin = || format!("skin {}", skin.index);
        for primitive in mesh.primitives() {
            let p = primitive.index();
            let base = data.positions.len();
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
            let accessor_error = |accessor: usize, reason: String| LoadError::Accessor {
                path: self.path.to_owned(),
                mesh: mesh_ref.clone(),
                primitive: p,
                accessor,
                reason: one_line(&reason),
            };
            let skinning_error = |reason: String| LoadError::Skinning {
                path: self.path.to_owned(),
                mesh: mesh_ref.clone(),
                primitive: p,
                reason: one_line(&reason),
            };

            // Influence sets 0, 1, ... while present.
            let mut sets: Vec<InfluenceSet> = Vec::new();
            for set in 0u32.. {
                let (j, w) = (
                    primitive.get(&Semantic::Joints(set)),
                    primitive.get(&Semantic::Weights(set)),
                );
                let (j, w) = match (j, w) {
                    (None, None) if set == 0 => {
                        return Err(skinning_error(
                            "skinned primitive has neither JOINTS_0 nor WEIGHTS_0".into(),
                        ));
                    }
                    (None, None) => break,
                    (Some(_), None) => {
                        return Err(skinning_error(format!(
                            "has JOINTS_{set} but no WEIGHTS_{set}"
                        )));
                    }
                    (None, Some(_)) => {
                        return Err(skinning_error(format!(
                            "has WEIGHTS_{set} but no JOINTS_{set}"
                        )));
                    }
                    (Some(j), Some(w)) => (j, w),
                };
                let jv = gltf_accessor::read_joints(&j, self.buffers, &format!("JOINTS_{set}"))
                    .map_err(|reason| accessor_error(j.index(), reason))?;
                let wv = gltf_accessor::read_weights(&w, self.buffers, &format!("WEIGHTS_{set}"))
                    .map_err(|reason| accessor_error(w.index(), reason))?;
                for (what, accessor, len) in [("JOINTS", &j, jv.len()), ("WEIGHTS", &w, wv.len())] {
                    if len != stored.len() {
                        return Err(accessor_error(
                            accessor.index(),
                            format!(
                                "{what}_{set} has {len} elements but POSITION has {}",
                                stored.len()
                            ),
                        ));
                    }
                }
                sets.push((jv, wv));
            }

            // Merge the sets (the four largest weights of each vertex), check
            // the skin's joint indices, and bind to the skeleton's joint slots.
            let joint_count = skin.joints.len();
            let mut truncated = 0usize;
            for (v, position) in stored.iter().enumerate() {
                let (jj, ww) = if sets.len() == 1 {
                    (sets[0].0[v], sets[0].1[v])
                } else {
                    let mut all: Vec<(u16, f32)> = sets
                        .iter()
                        .flat_map(|(j, w)| j[v].into_iter().zip(w[v]))
                        .collect();
                    all.sort_by(|a, b| b.1.total_cmp(&a.1));
                    if all[4..].iter().any(|(_, w)| *w != 0.0) {
                        truncated += 1;
                    }
                    let mut jj = [0u16; 4];
                    let mut ww = [0f32; 4];
                    for (k, (j, w)) in all.into_iter().take(4).enumerate() {
                        jj[k] = j;
                        ww[k] = w;
                    }
                    (jj, ww)
                };
                if let Some(j) = (0..4)
                    .find(|&k| ww[k] > 0.0 && jj[k] as usize >= joint_count)
                    .map(|k| jj[k])
                {
                    return Err(skinning_error(format!(
                        "vertex {v}: joint index {j} (with non-zero weight) is out of range; skin {} has {joint_count} joints",
                        skin.index
                    )));
                }
                // Indices of zero weights are not used (Influences drops them).
                let ids = jj.map(|j| skin.joints.get(j as usize).copied().unwrap_or(0));
                let binds = jj.map(|j| skin.inverse_binds.get(j as usize).unwrap_or(&identity));
                let [x, y, z] = *position;
                let at = Point3::new(f64::from(x), f64::from(y), f64::from(z));
                let bound = slots
                    .bind(ids, binds, ww, &at, &origin)
                    .map_err(&skinning_error)?;
                if bound.moved.is_some() {
                    self.report.moved_vertices += 1;
                }
                data.joints.push(bound.slots);
                data.weights.push(ww);
                data.positions
                    .push(bound.moved.unwrap_or_else(|| Point::new(x, y, z)));
            }
            if sets.len() > 1 {
                self.report.notes.push(format!(
                    "node {node}, mesh {mesh_ref} primitive {p}: {} influence sets merged to the 4 largest weights; {truncated} vertices lost a non-zero weight (renormalised)",
                    sets.len()
                ));
            }
            self.add_triangles(node, &mesh_ref, p, mode, &indices, base, data);
        }
        Ok(())
    }

    /// The triangle primitives of node `node`, which has no skin and hangs
    /// from joint node `joint_node` by the transform `frame`: bound wholly
    /// to that joint (see [`super::gltf_bind`]).
    #[allow(clippy::too_many_arguments)]
    fn add_rigid_mesh(
        &mut self,
        node: usize,
        mesh: &gltf::Mesh<'_>,
        joint_node: usize,
        frame: &Matrix4<f64>,
        skel: &SkeletonMap,
        slots: &mut JointSlots,
        data: &mut MeshData,
    ) -> Result<(), LoadError> {
        let mesh_ref = MeshRef::of(mesh);
        let joint = skel.skin_index[joint_node].map_or(0, |u| skel.joint_id[u]);
        let identity = Matrix4::identity();
        let origin = || "rigid meshes".to_owned();
        for primitive in mesh.primitives() {
            let p = primitive.index();
            let base = data.positions.len();
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
            let node_error = |reason: String| LoadError::Node {
                path: self.path.to_owned(),
                node,
                reason: one_line(&format!("mesh {mesh_ref} primitive {p}: {reason}")),
            };
            for (v, position) in stored.iter().enumerate() {
                let at = place(frame, *position);
                if !at
                    .coords
                    .iter()
                    .all(|c| c.abs() <= f64::from(MAX_COORDINATE))
                {
                    return Err(node_error(format!(
                        "vertex {v} is non-finite or beyond {MAX_COORDINATE:e} in magnitude in the frame of joint node {joint_node}"
                    )));
                }
                let bound = slots
                    .bind(
                        [joint, 0, 0, 0],
                        [&identity; 4],
                        [1.0, 0.0, 0.0, 0.0],
                        &at,
                        &origin,
                    )
                    .map_err(&node_error)?;
                data.joints.push(bound.slots);
                data.weights.push([1.0, 0.0, 0.0, 0.0]);
                data.positions
                    .push(bound.moved.unwrap_or_else(|| at.cast::<f32>()));
            }
            self.add_triangles(node, &mesh_ref, p, mode, &indices, base, data);
        }
        let name = skel.skeleton.joint(JointId(joint)).name.clone();
        self.report.notes.push(format!(
            "node {node}: mesh {} has no skin; bound rigidly to joint {name:?} (node {joint_node})",
            mesh.index()
        ));
        self.report.attached_meshes.push(AttachedMesh {
            node,
            mesh: mesh.index(),
            joint_node,
            joint: name,
        });
        Ok(())
    }

    /// The triangles of primitive `p` (its vertices start at `base`).
    #[allow(clippy::too_many_arguments)]
    fn add_triangles(
        &mut self,
        node: usize,
        mesh_ref: &MeshRef,
        p: usize,
        mode: Mode,
        indices: &[u32],
        base: usize,
        data: &mut MeshData,
    ) {
        data.ranges.push(PrimitiveRange {
            start: base,
            mesh: mesh_ref.clone(),
            primitive: p,
        });
        let before = data.triangles.len();
        let offset = base as u32;
        let (leftover, degenerate) = assemble(mode, indices, |t| {
            data.triangles
                .push([t[0] + offset, t[1] + offset, t[2] + offset]);
        });
        self.report.degenerate_dropped += degenerate;
        if leftover > 0 {
            self.report.notes.push(format!(
                "node {node}, mesh {mesh_ref} primitive {p}: {} indices is not a multiple of 3; last {leftover} ignored",
                indices.len()
            ));
        }
        if data.triangles.len() == before {
            self.report.notes.push(format!(
                "node {node}, mesh {mesh_ref} primitive {p}: no triangles"
            ));
        }
        self.report.primitives += 1;
    }

    /// An [`Influences::new`] error, with the global vertex index turned back
    /// into mesh, primitive and the primitive's own vertex index.
    fn influence_error(
        &self,
        ranges: &[PrimitiveRange],
        skin: &gltf::Skin<'_>,
        joint_count: usize,
        error: SkinError,
    ) -> LoadError {
        let (vertex, what) = match &error {
            SkinError::JointOutOfRange { vertex, joint, .. } => (
                *vertex,
                format!(
                    "joint slot {joint} (with non-zero weight) is out of range; the skeleton has {joint_count} joint slots"
                ),
            ),
            SkinError::BadWeights { vertex, sum } => (
                *vertex,
                format!("weights sum to {sum}, not a positive finite number"),
            ),
            SkinError::Length { .. } => {
                return self.skin_error(skin, error.to_string());
            }
        };
        let r = ranges
            .partition_point(|r| r.start <= vertex)
            .saturating_sub(1);
        match ranges.get(r) {
            Some(range) => LoadError::Skinning {
                path: self.path.to_owned(),
                mesh: range.mesh.clone(),
                primitive: range.primitive,
                reason: format!("vertex {}: {what}", vertex - range.start),
            },
            None => self.skin_error(skin, error.to_string()),
        }
    }

    /// The clips of the file's animations, for a skeleton of `joint_count`
    /// joint slots (joints, then added slots).
    fn clips(
        &mut self,
        document: &gltf::Document,
        skel: &SkeletonMap,
        parents: &[Option<usize>],
        joint_count: usize,
    ) -> Result<Vec<Clip>, LoadError> {
        // Nodes above the skeleton: animating them would move the (static) base.
        let mut above = vec![false; document.nodes().len()];
        for &node in &skel.joint_nodes {
            if skel.skin_index[node].is_some() {
                let mut cur = parents[node];
                // A node marked before had its ancestors up to the next
                // joint marked too: stopping there keeps this linear.
                while let Some(p) = cur {
                    if skel.skin_index[p].is_some() || above[p] {
                        break;
                    }
                    above[p] = true;
                    cur = parents[p];
                }
            }
        }
        let mut attached = vec![false; document.nodes().len()];
        for mesh in &self.report.attached_meshes {
            attached[mesh.node] = true;
        }
        let mut clips = Vec::new();
        for animation in document.animations() {
            let a = animation.index();
            let name = animation
                .name()
                .map(str::to_owned)
                .unwrap_or_else(|| format!("animation {a}"));
            let mut channels = Vec::new();
            let mut sources = Vec::new();
            for channel in animation.channels() {
                let c = channel.index();
                let target = channel.target();
                let node = target.node().index();
                let property = target.property();
                let property_name = match property {
                    Property::Translation => "translation",
                    Property::Rotation => "rotation",
                    Property::Scale => "scale",
                    Property::MorphTargetWeights => "weights",
                };
                let skip = |reason: &str| SkippedChannel {
                    animation: a,
                    channel: c,
                    node,
                    property: property_name,
                    reason: reason.to_owned(),
                };
                if property == Property::MorphTargetWeights {
                    self.report
                        .skipped_channels
                        .push(skip("morph target weights are not supported"));
                    continue;
                }
                let Some(k) = skel.skin_index.get(node).copied().flatten() else {
                    let reason = if above.get(node).copied().unwrap_or(false) {
                        "the node is above the skeleton; the skeleton base is static"
                    } else if attached.get(node).copied().unwrap_or(false) {
                        "the node is not a joint; its rigid mesh follows the joint it hangs from"
                    } else {
                        "the node is not a joint of the skin"
                    };
                    self.report.skipped_channels.push(skip(reason));
                    continue;
                };
                let joint = JointId(skel.joint_id[k]);
                channels.push(self.channel(a, c, &channel, joint, property)?);
                sources.push(c);
            }
            let clip = Clip::new(name, channels, joint_count).map_err(|e| {
                let channel = match &e {
                    crate::character::clip::ChannelError::Empty { channel }
                    | crate::character::clip::ChannelError::BadTimes { channel }
                    | crate::character::clip::ChannelError::ValueCount { channel, .. }
                    | crate::character::clip::ChannelError::JointOutOfRange { channel, .. } => {
                        sources.get(*channel).copied().unwrap_or(*channel)
                    }
                };
                LoadError::Animation {
                    path: self.path.to_owned(),
                    animation: a,
                    channel,
                    reason: one_line(&e.to_string()),
                }
            })?;
            if clip.channels.is_empty() {
                self.report.notes.push(format!(
                    "animation {a} ({:?}) animates no joint of the skeleton; its clip is empty",
                    clip.name
                ));
            }
            clips.push(clip);
        }
        Ok(clips)
    }

    fn channel(
        &self,
        a: usize,
        c: usize,
        channel: &gltf::animation::Channel<'_>,
        joint: JointId,
        property: Property,
    ) -> Result<Channel, LoadError> {
        let error = |reason: String| LoadError::Animation {
            path: self.path.to_owned(),
            animation: a,
            channel: c,
            reason: one_line(&reason),
        };
        let sampler = channel.sampler();
        let s = sampler.index();
        let (input, output) = (sampler.input(), sampler.output());
        let times = gltf_accessor::read_scalars_f32(&input, self.buffers, "keyframe time")
            .map_err(|e| error(format!("sampler {s} input accessor {}: {e}", input.index())))?;
        if times.is_empty() {
            return Err(error(format!("sampler {s} has no keyframes")));
        }
        // Finite: checked by the reader.
        if let Some(k) = times.windows(2).position(|w| w[1] <= w[0]) {
            return Err(error(format!(
                "sampler {s} input accessor {}: time {} ({}) is not after time {k} ({}); keyframe times must strictly increase",
                input.index(),
                k + 1,
                times[k + 1],
                times[k]
            )));
        }
        let interpolation = match sampler.interpolation() {
            GltfInterpolation::Step => Interpolation::Step,
            GltfInterpolation::Linear => Interpolation::Linear,
            GltfInterpolation::CubicSpline => Interpolation::CubicSpline,
        };
        let per_key = if interpolation == Interpolation::CubicSpline {
            3
        } else {
            1
        };
        let expected = per_key * times.len();
        if output.count() != expected {
            return Err(error(format!(
                "sampler {s}: input has {} keyframes but output has {} values ({interpolation:?} needs {expected})",
                times.len(),
                output.count()
            )));
        }
        let out_error = |e: String| {
            error(format!(
                "sampler {s} output accessor {}: {e}",
                output.index()
            ))
        };
        let vec3 = |v: Vec<[f32; 3]>| v.into_iter().map(Vector3::from).collect::<Vec<_>>();
        let values = match property {
            Property::Translation => ChannelValues::Translation(vec3(
                gltf_accessor::read_vec3_f32(&output, self.buffers, "translation output")
                    .map_err(out_error)?,
            )),
            Property::Scale => ChannelValues::Scale(vec3(
                gltf_accessor::read_vec3_f32(&output, self.buffers, "scale output")
                    .map_err(out_error)?,
            )),
            Property::Rotation => ChannelValues::Rotation(
                gltf_accessor::read_rotations(&output, self.buffers, "rotation output")
                    .map_err(out_error)?
                    .into_iter()
                    .map(|[x, y, z, w]| Quaternion::new(w, x, y, z))
                    .collect(),
            ),
            Property::MorphTargetWeights => {
                return Err(error("morph target weights are not supported".into()));
            }
        };
        Ok(Channel {
            joint,
            interpolation,
            times,
            values,
        })
    }
}

/// The skeleton (joints of every skin, without added slots) and how the
/// file's nodes and skin joints map onto it.
struct SkeletonMap {
    skeleton: Skeleton,
    /// Node of each joint of the union, in order of first listing.
    joint_nodes: Vec<usize>,
    /// Our joint index of each joint of the union.
    joint_id: Vec<u16>,
    /// Index in the union of each node of the file that is a joint.
    skin_index: Vec<Option<usize>>,
    /// The skins, in order of first use.
    skins: Vec<SkinJoints>,
}

/// One skin of the character: its entries as joints of the skeleton.
struct SkinJoints {
    /// The skin's index in the file.
    index: usize,
    /// Our joint index of each entry of the skin's `joints`.
    joints: Vec<u16>,
    /// The skin's inverse bind matrix of each entry (fourth row exact).
    inverse_binds: Vec<Matrix4<f32>>,
}

/// Vertices, triangles and influences of the character, as they are added.
#[derive(Default)]
struct MeshData {
    positions: Vec<Point>,
    triangles: Vec<[u32; 3]>,
    joints: Vec<[u16; 4]>,
    weights: Vec<[f32; 4]>,
    ranges: Vec<PrimitiveRange>,
}

/// `"skin 0"` or `"skins 0, 2"`.
fn skins_label(skins: &[usize]) -> String {
    let list: Vec<String> = skins.iter().map(usize::to_string).collect();
    match list.len() {
        1 => format!("skin {}", list[0]),
        _ => format!("skins {}", list.join(", ")),
    }
}

/// The joint a [`SkeletonError`] is about, if any.
fn skeleton_error_joint(error: &SkeletonError) -> Option<usize> {
    match error {
        SkeletonError::ParentNotBefore { joint, .. }
        | SkeletonError::NonFinite { joint, .. }
        | SkeletonError::NotAffine { joint, .. } => Some(*joint),
        SkeletonError::Empty | SkeletonError::TooMany(_) | SkeletonError::BaseNotAffine(_) => None,
    }
}

fn node_name(node: Option<usize>) -> String {
    match node {
        Some(n) => format!("node {n}"),
        None => "the scene root".to_owned(),
    }
}

fn is_identity(m: &Matrix4<f64>) -> bool {
    (m - Matrix4::identity()).abs().max() <= MATRIX_TOLERANCE
}

/// A node's local transform as TRS; a `matrix` is decomposed. The node passed
/// `check_node_transform`.
fn node_trs(node: &gltf::Node<'_>) -> Result<Trs, String> {
    match node.transform() {
        Transform::Decomposed {
            translation,
            rotation: [x, y, z, w],
            scale,
        } => {
            // Normalised in f64: the components are finite and not all zero
            // (checked by `check_node_transform`), but their f32 norm may overflow.
            let q = Quaternion::new(w, x, y, z).cast::<f64>();
            Ok(Trs {
                translation: Vector3::from(translation),
                rotation: UnitQuaternion::from_quaternion(q).cast(),
                scale: Vector3::from(scale),
            })
        }
        Transform::Matrix { matrix } => decompose(&matrix),
    }
}

/// `matrix[column][row]` as translation · rotation · scale. A negative
/// determinant becomes a negative x scale; shear, projection or a zero scale
/// is an error.
fn decompose(matrix: &[[f32; 4]; 4]) -> Result<Trs, String> {
    let m = Matrix4::from_fn(|r, c| f64::from(matrix[c][r]));
    if !m.iter().all(|v| v.is_finite()) {
        return Err("matrix is not finite".into());
    }
    let bottom = [m[(3, 0)], m[(3, 1)], m[(3, 2)], m[(3, 3)] - 1.0];
    if bottom.iter().any(|v| v.abs() > MATRIX_TOLERANCE) {
        return Err("matrix has a projective bottom row; not a TRS transform".into());
    }
    let linear: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).into_owned();
    let mut scale = Vector3::new(
        linear.column(0).norm(),
        linear.column(1).norm(),
        linear.column(2).norm(),
    );
    if scale.iter().any(|s| *s < 1e-12) {
        return Err("matrix has a zero scale; cannot decompose into TRS".into());
    }
    if linear.determinant() < 0.0 {
        scale.x = -scale.x;
    }
    let r = Matrix3::from_fn(|i, j| linear[(i, j)] / scale[j]);
    let off = (r.transpose() * r - Matrix3::identity()).abs().max();
    if off > MATRIX_TOLERANCE {
        return Err(format!(
            "matrix has shear (columns off-orthogonal by {off:.2e}); cannot decompose into TRS"
        ));
    }
    let rotation = UnitQuaternion::from_rotation_matrix(&Rotation3::from_matrix_unchecked(r));
    Ok(Trs {
        translation: Vector3::new(m[(0, 3)], m[(1, 3)], m[(2, 3)]).cast(),
        rotation: rotation.cast(),
        scale: scale.cast(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn decompose_round_trips_and_rejects_shear() {
        let t = Trs {
            translation: Vector3::new(1.0, -2.0, 3.0),
            rotation: UnitQuaternion::from_euler_angles(0.3, -1.2, 2.0),
            scale: Vector3::new(-2.0, 0.5, 1.5),
        };
        let m = t.to_matrix();
        let cols: [[f32; 4]; 4] = std::array::from_fn(|c| std::array::from_fn(|r| m[(r, c)]));
        let back = decompose(&cols).expect("TRS matrix decomposes");
        assert!((back.to_matrix() - m).abs().max() < 1e-5);
        let mut shear = cols;
        shear[1][0] = 0.7;
        assert!(decompose(&shear).unwrap_err().contains("shear"));
        let mut zero = cols;
        zero[2] = [0.0; 4];
        assert!(decompose(&zero).unwrap_err().contains("zero scale"));
    }
}
