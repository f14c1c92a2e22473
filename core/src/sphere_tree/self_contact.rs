//! What a character's self pass knows from its mesh and skinning, computed
//! once per character tree (ours; the paper does not treat self-collision).
//!
//! **Neighbour rule.** Two triangles that share a corner are never a
//! contact (they always touch there). Corners are compared after welding
//! equal positions, so a glTF seam, which splits a vertex for its normals
//! or UVs, does not hide a shared corner.
//!
//! **Parts one joint moves.** A vertex bound to one joint with full weight
//! is skinned by that joint's matrix alone: `fl(M_j·v)` under both models
//! (the paper's blend at `w = 1` is `M_j` exactly). Two triangles whose six
//! corners all follow one joint `j` are the image of their rest pose under
//! one affine map, so they touch in a pose only if they touch at rest, up to
//! rounding: if their rest distance is `g`, their posed distance is at least
//! `σ_min(M_j)·g − 2e`, with `e` the rounding bound of a skinned corner.
//! Each node of the tree records the one joint moving all its triangles (or
//! none), and two rest distances over non-neighbouring pairs moved by one
//! joint: within its subtree, and from its subtree to the rest of the mesh
//! (a pair across two disjoint nodes is at least the larger of theirs
//! apart). Each frame,
//! [`RigidGaps::update`] gives every joint the least rest distance that
//! proves such a pair apart in this pose ([`RigidGaps::proves_apart`]);
//! the self pass skips a node, or a pair of nodes, one joint moves whose
//! rest distance clears it. A joint whose matrix is singular, or not finite,
//! proves nothing.

use nalgebra::Matrix4;

use crate::character::Character;
use crate::character::skinning::{largest_row_sum, sole_joint_rounding};
use crate::geometry::Sphere;
use crate::geometry::closest_point::triangle_triangle_distance;
use crate::mesh::TriangleId;
use crate::mesh::dedup::weld_positions;

use super::character::CharacterTree;
use super::flat_patches::FlatPatches;
use super::node::{NodeId, SphereTree};
use super::self_traverse::traverse_self;
use super::traverse::{Hierarchy, Workspace};

/// No single joint moves this node's triangles.
pub const MIXED: u16 = u16::MAX;

/// Rest distances are measured up to this share of the character's bind
/// extent; a pair farther apart is recorded at it (a pose would need a
/// matrix distorting lengths a thousandfold to bring it into contact, and
/// then it is tested).
pub const REST_GAP_REACH: f32 = 1e-2;

/// A character tree's self-contact data (see the module doc).
#[derive(Clone, Debug)]
pub struct SelfContactData {
    /// Each mesh triangle's corners, welded.
    welded: Vec<[u32; 3]>,
    /// Per node: the joint moving every corner of its triangles with full
    /// weight, or [`MIXED`].
    node_joint: Vec<u16>,
    /// Per node: the least rest distance from one of its triangles to a
    /// non-neighbouring triangle outside it moved by the same one joint.
    gap_out: Vec<f32>,
    /// Per node: the least rest distance between two of its
    /// non-neighbouring triangles one joint moves.
    gap_within: Vec<f32>,
    /// The largest bind coordinate magnitude, at least 1 (the homogeneous
    /// coordinate): bounds a skinned corner's rounding.
    coordinate_bound: f32,
    /// The disks among its nodes and pairs of nodes (normal-cone culling),
    /// when asked for.
    flat: Option<FlatPatches>,
}

impl SelfContactData {
    /// Computes the data of `tree`, built for `character`: welds, joints
    /// per node, and rest distances by one walk of the rest tree against
    /// itself with spheres widened by [`REST_GAP_REACH`]; with
    /// `with_flat_patches`, also its disks for normal-cone culling
    /// ([`FlatPatches`]).
    pub fn new(character: &Character, tree: &CharacterTree, with_flat_patches: bool) -> Self {
        let mesh = &character.mesh;
        let weld = weld_positions(mesh);
        let welded: Vec<[u32; 3]> = mesh
            .indices()
            .iter()
            .map(|t| t.map(|v| weld[v as usize]))
            .collect();
        let nodes = tree.tree.nodes();
        let mut node_joint = vec![MIXED; nodes.len()];
        // Children after parents: a reverse sweep meets children first.
        for i in (0..nodes.len()).rev() {
            node_joint[i] = match nodes[i].primitive() {
                Some(t) => tree.sole_joint[t as usize],
                None => {
                    let mut js = nodes[i].children().map(|c| node_joint[c as usize]);
                    let first = js.next().unwrap_or(MIXED);
                    if js.all(|j| j == first) { first } else { MIXED }
                }
            }
        }
        let coordinate_bound = tree.bind_coordinate_bound;
        let cap = REST_GAP_REACH * mesh.size().max(f32::MIN_POSITIVE);

        let mut gap_across = vec![cap; nodes.len()];
        let mut gap_out = vec![cap; nodes.len()];
        let parents = tree.tree.parents();
        let mut rest = Widened {
            tree: &tree.tree,
            by: 0.5 * cap,
        };
        let topology = &tree.tree;
        let mut out = Self {
            welded,
            node_joint,
            gap_out: Vec::new(),
            gap_within: Vec::new(),
            coordinate_bound,
            flat: with_flat_patches.then(|| FlatPatches::new(character, tree)),
        };
        let same = |out: &Self, i: NodeId, j: NodeId| {
            let (a, b) = (out.node_joint[i.index()], out.node_joint[j.index()]);
            a == MIXED || b == MIXED || a == b
        };
        traverse_self(
            topology,
            &mut rest,
            &mut Workspace::new(),
            |_| false,
            // Below two nodes moved by different joints, no pair is moved
            // by one joint.
            |_, i, j| same(&out, i, j),
            |n, p| {
                let (ta, tb) = (p.primitive_a, p.primitive_b);
                let ja = out.node_joint[p.leaf_a.index()];
                if ja == MIXED || ja != out.node_joint[p.leaf_b.index()] || out.neighbours(ta, tb) {
                    return;
                }
                let d = triangle_triangle_distance(
                    &mesh.triangle(TriangleId(ta)),
                    &mesh.triangle(TriangleId(tb)),
                ) as f32;
                // Rounded down: a recorded distance is never above the true one.
                let d = d.next_down().max(0.0);
                let g = &mut gap_across[n.index()];
                *g = g.min(d);
                // Every node from each leaf up to (not with) `n` holds one
                // triangle of the pair and not the other.
                for leaf in [p.leaf_a, p.leaf_b] {
                    let mut k = leaf.0;
                    while k != n.0 {
                        let g = &mut gap_out[k as usize];
                        *g = g.min(d);
                        k = parents[k as usize];
                    }
                }
            },
        );
        let mut gap_within = gap_across.clone();
        for i in (0..nodes.len()).rev() {
            for c in nodes[i].children() {
                gap_within[i] = gap_within[i].min(gap_within[c as usize]);
            }
        }
        out.gap_out = gap_out;
        out.gap_within = gap_within;
        out
    }

    /// Whether triangles `a` and `b` share a corner (after welding): never
    /// a contact.
    #[inline]
    pub fn neighbours(&self, a: u32, b: u32) -> bool {
        let (a, b) = (&self.welded[a as usize], &self.welded[b as usize]);
        a.iter().any(|v| b.contains(v))
    }

    /// The joint moving all of node `n`'s triangles, if one does.
    #[inline]
    pub fn joint_of(&self, n: NodeId) -> Option<u16> {
        let j = self.node_joint[n.index()];
        (j != MIXED).then_some(j)
    }

    /// Whether node `n`'s own pairs are all proved apart this frame: one
    /// joint moves its triangles and their rest distance clears `gaps`.
    #[inline]
    pub fn skips_node(&self, gaps: &RigidGaps, n: NodeId) -> bool {
        let j = self.node_joint[n.index()];
        j != MIXED && gaps.proves_apart(j, self.gap_within[n.index()])
    }

    /// Whether the pairs between the disjoint nodes `i` and `j` are all
    /// proved apart this frame (one joint moves both).
    #[inline]
    pub fn skips_pair(&self, gaps: &RigidGaps, i: NodeId, j: NodeId) -> bool {
        let ji = self.node_joint[i.index()];
        ji != MIXED
            && ji == self.node_joint[j.index()]
            && gaps.proves_apart(ji, self.gap_out[i.index()].max(self.gap_out[j.index()]))
    }

    /// The bound on bind coordinates the rounding estimate uses.
    pub fn coordinate_bound(&self) -> f32 {
        self.coordinate_bound
    }

    /// Nodes one joint moves, of all nodes.
    pub fn one_joint_nodes(&self) -> usize {
        self.node_joint.iter().filter(|&&j| j != MIXED).count()
    }

    /// Nodes one joint moves whose own pairs all lie more than `gap`
    /// apart at rest (those a frame whose joints need a gap of at most
    /// `gap` skips whole).
    pub fn one_joint_nodes_apart_by(&self, gap: f32) -> usize {
        self.node_joint
            .iter()
            .zip(&self.gap_within)
            .filter(|&(&j, &g)| j != MIXED && g > gap)
            .count()
    }

    /// The disks among its nodes and pairs of nodes, flat at rest: where
    /// normal-cone culling is tried (when it was asked for).
    pub fn flat(&self) -> Option<&FlatPatches> {
        self.flat.as_ref()
    }

    /// Heap bytes held.
    pub fn bytes(&self) -> usize {
        self.welded.len() * 12
            + self.node_joint.len() * 2
            + self.gap_out.len() * 8
            + self.flat.as_ref().map_or(0, FlatPatches::bytes)
    }
}

/// The rest tree with every sphere widened by `by`: two spheres overlap
/// when their triangles may lie within `2·by` of each other.
pub(super) struct Widened<'a> {
    pub(super) tree: &'a SphereTree,
    pub(super) by: f32,
}

impl Hierarchy for Widened<'_> {
    fn tree(&self) -> &SphereTree {
        self.tree
    }
    fn sphere(&mut self, id: NodeId) -> Sphere {
        let s = self.tree.node(id).sphere;
        Sphere::new(s.center, s.radius + self.by)
    }
}

/// A joint's skin matrix `m`: a lower bound of its linear part's least
/// stretch, `2·|det A| / ‖A‖_F²`, and the rounding bound `e` of a corner it
/// skins (bind coordinates at most `coordinate_bound`; see
/// [`RigidGaps::update`]).
fn joint_bounds(m: &Matrix4<f32>, coordinate_bound: f32) -> (f64, f64) {
    let a = m.fixed_view::<3, 3>(0, 0).into_owned().cast::<f64>();
    let sigma_min = 2.0 * a.determinant().abs() / a.norm_squared();
    (sigma_min, sole_joint_rounding(m, coordinate_bound))
}

/// The least rest gap a pair must have to stay farther apart than `slack`
/// under a map shrinking no length below `sigma_min`, with a factor 4 of
/// margin; infinite (nothing proved) for a map that may collapse.
fn least_gap(sigma_min: f64, slack: f64) -> f32 {
    let least = 4.0 * slack / sigma_min;
    if least.is_finite() && sigma_min > 0.0 {
        least as f32
    } else {
        f32::INFINITY
    }
}

/// Per joint, this frame: the least rest distance that proves two
/// triangles that joint moves apart ([`SelfContactData`]'s module doc).
#[derive(Clone, Debug, Default)]
pub struct RigidGaps {
    least: Vec<f32>,
}

impl RigidGaps {
    /// From this frame's skin matrices (`skin[j]`, placed). A corner at
    /// bind position `v` (coordinates at most `c` in magnitude, the
    /// homogeneous 1 included) is skinned to `fl(M·v)`, off `M·v` by at most
    /// `γ₈·Σ_k |M_ik|·c` per coordinate (eight roundings, the most of either
    /// model: `skinning::LINEAR_ROUNDINGS`), so by `e = √3·γ₈·r·c` with `r`
    /// the largest row sum. `M` shrinks no length below `σ_min ≥
    /// 2·|det A| / ‖A‖_F²` (`A` its linear part). Two triangles `g` apart
    /// at rest are at least `σ_min·g − 2e` apart posed: proved apart when
    /// `g > 2e / σ_min`, asked here with a factor 4 of margin.
    pub fn update(&mut self, skin: &[Matrix4<f32>], coordinate_bound: f32) {
        self.least.clear();
        self.least.extend(skin.iter().map(|m| {
            let (sigma_min, e) = joint_bounds(m, coordinate_bound);
            least_gap(sigma_min, 2.0 * e)
        }));
    }

    /// The same over a frame step (continuous detection), from the skin
    /// matrices at its start and end: in between, a corner `v` one joint
    /// moves follows `(1 − t)·fl(M₀·v) + t·fl(M₁·v)`, the affine map
    /// `M(t) = (1 − t)·M₀ + t·M₁` off by at most the larger end's rounding
    /// `e`. `M(t)`'s linear part shrinks no length below `σ_min(A₀) −
    /// t·‖A₁ − A₀‖` nor below `σ_min(A₁) − (1 − t)·‖A₁ − A₀‖`, so below
    /// `(σ₀ + σ₁ − ‖A₁ − A₀‖_F) / 2` at any `t`. A pair is proved apart
    /// when it stays farther than the kernel's tolerance `√3·δ` as well
    /// (the kernel may report a pair that close).
    pub fn update_over_step(
        &mut self,
        start: &[Matrix4<f32>],
        end: &[Matrix4<f32>],
        coordinate_bound: f32,
        tolerance: f64,
    ) {
        // The kernel raises δ to 16ε where that is larger, ε about 1.4e-14
        // times the query's largest coordinate (at most the largest row
        // sum times the bind bound, at either end).
        let largest = start
            .iter()
            .chain(end)
            .map(largest_row_sum)
            .fold(0.0f64, f64::max)
            * f64::from(coordinate_bound);
        let tolerance = tolerance.max(16.0 * 1.5e-14 * largest);
        self.least.clear();
        self.least.extend(start.iter().zip(end).map(|(m0, m1)| {
            let (s0, e0) = joint_bounds(m0, coordinate_bound);
            let (s1, e1) = joint_bounds(m1, coordinate_bound);
            let a0 = m0.fixed_view::<3, 3>(0, 0).into_owned().cast::<f64>();
            let a1 = m1.fixed_view::<3, 3>(0, 0).into_owned().cast::<f64>();
            let sigma_min = 0.5 * (s0 + s1 - (a1 - a0).norm());
            least_gap(sigma_min, 2.0 * e0.max(e1) + 3f64.sqrt() * tolerance)
        }));
    }

    /// Whether two triangles joint `j` moves, `rest_gap` apart at rest, are
    /// apart this frame.
    #[inline]
    pub fn proves_apart(&self, j: u16, rest_gap: f32) -> bool {
        self.least
            .get(j as usize)
            .is_some_and(|&least| rest_gap > least)
    }
}

#[cfg(test)]
mod tests {
    use super::{RigidGaps, joint_bounds};
    use nalgebra::{Matrix3, Matrix4, Rotation3, Vector3};

    /// A skin matrix: rotation about `axis` by `angle`, scaled per axis by
    /// `scale`, sheared by `shear`, translated.
    fn skin(axis: Vector3<f32>, angle: f32, scale: Vector3<f32>, shear: f32) -> Matrix4<f32> {
        let r = Rotation3::from_axis_angle(&nalgebra::Unit::new_normalize(axis), angle);
        let mut s = Matrix3::from_diagonal(&scale);
        s[(0, 1)] = shear;
        let a = r.matrix() * s;
        let mut m = a.to_homogeneous();
        m[(0, 3)] = 0.3;
        m[(1, 3)] = -1.2;
        m[(2, 3)] = 0.7;
        m
    }

    fn sigma_min(a: &Matrix3<f64>) -> f64 {
        a.singular_values().min()
    }

    /// The least-stretch bounds against nalgebra's singular values, at one
    /// pose and at every sampled instant between two (the bound over a
    /// step).
    #[test]
    fn least_stretch_bounds_are_below_the_singular_values() {
        let mut next = crate::test_rng::unit_floats(0x2545_f491_4f6c_dd1d);
        let mut random = || {
            let axis = Vector3::new(next() - 0.5, next() - 0.5, next() + 0.1);
            let scale = Vector3::new(0.5 + next(), 0.5 + next(), 0.5 + next());
            skin(axis, 6.0 * next() - 3.0, scale, next() - 0.5)
        };
        let linear = |m: &Matrix4<f32>| m.fixed_view::<3, 3>(0, 0).into_owned().cast::<f64>();
        for _ in 0..500 {
            let (m0, m1) = (random(), random());
            let (s0, _) = joint_bounds(&m0, 1.0);
            assert!(s0 <= sigma_min(&linear(&m0)) * (1.0 + 1e-12));
            let (s1, _) = joint_bounds(&m1, 1.0);
            let over_step = 0.5 * (s0 + s1 - (linear(&m1) - linear(&m0)).norm());
            for k in 0..=64 {
                let t = k as f64 / 64.0;
                let a = linear(&m0) * (1.0 - t) + linear(&m1) * t;
                assert!(
                    over_step <= sigma_min(&a) * (1.0 + 1e-12) + 1e-12,
                    "t = {t}"
                );
            }
        }
    }

    #[test]
    fn gaps_prove_rigid_motion_apart_and_collapse_nothing() {
        let turn = skin(Vector3::z(), 0.3, Vector3::new(1.0, 1.0, 1.0), 0.0);
        let other = skin(Vector3::x(), -0.2, Vector3::new(1.0, 1.0, 1.0), 0.0);
        let mut g = RigidGaps::default();
        g.update(&[turn], 2.0);
        assert!(g.proves_apart(0, 1e-4) && !g.proves_apart(0, 0.0));
        // An unknown joint proves nothing.
        assert!(!g.proves_apart(1, 1.0));
        g.update_over_step(&[turn], &[other], 2.0, 1e-6);
        assert!(g.proves_apart(0, 1e-3) && !g.proves_apart(0, 1e-6));
        // A step through a mirror image passes through a singular map: the
        // pair may collapse onto itself, nothing is proved.
        let mirror = skin(Vector3::z(), 0.0, Vector3::new(-1.0, 1.0, 1.0), 0.0);
        g.update_over_step(&[turn], &[mirror], 2.0, 1e-6);
        assert!(!g.proves_apart(0, 1e6));
        // A singular pose proves nothing either.
        let flat = skin(Vector3::z(), 0.3, Vector3::new(1.0, 1.0, 0.0), 0.0);
        g.update(&[flat], 2.0);
        assert!(!g.proves_apart(0, 1e6));
    }
}
