//! The environment's sphere tree for a method (§3, §5): a tree over every
//! environment triangle, in which the leaf of each big triangle is replaced by
//! that triangle's division (sphere division, quaternary or corner-tree).

use crate::big_triangle::Division;
use crate::big_triangle::hierarchy::MAX_LEVELS;
use crate::geometry::plane_sphere::TrianglePlane;
use crate::geometry::triangle_prism::TrianglePrism;
use crate::geometry::{Real, Sphere};
use crate::mesh::{TriMesh, TriangleId};
use crate::prefetch::prefetch_at;
use crate::sphere_tree::node_boxes::NodeBoxes;
use crate::sphere_tree::{BuildParams, Node, NodeId, SphereTree, build_tree};

use super::{LeafTest, Method};

/// Default big-triangle threshold in metres (ours; the paper gives none): a
/// sub-triangle at most this long has a sphere of a few character leaves.
pub const DEFAULT_THRESHOLD: Real = 0.15;

/// [`EnvironmentTree`]'s mark of a node that is no division leaf.
const NOT_A_DIVISION_LEAF: u32 = u32::MAX;

/// When a triangle is big: its longest edge exceeds this.
#[derive(Clone, Copy, Debug, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Threshold {
    /// In model units (metres).
    Absolute(Real),
    /// A multiple of the character's mean leaf-sphere diameter.
    LeafRelative(Real),
}

impl Threshold {
    /// The threshold in model units, given the character's mean leaf radius.
    pub fn resolve(self, mean_leaf_radius: Real) -> Real {
        match self {
            Threshold::Absolute(t) => t,
            Threshold::LeafRelative(k) => k * 2.0 * mean_leaf_radius,
        }
    }
}

/// The environment hierarchy for one method.
#[derive(Clone, Debug)]
pub struct EnvironmentTree {
    /// The method the tree was built for.
    pub method: Method,
    /// Threshold used, in model units.
    pub threshold: Real,
    /// The hierarchy in the mesh's coordinates, each big triangle's division
    /// grafted in place of its leaf; every leaf holds a mesh triangle index
    /// (a division leaf, its big triangle's).
    pub tree: SphereTree,
    /// Divisions of the big triangles (empty for [`Method::Original`]).
    pub divisions: Vec<Division>,
    /// For every node inside a division: (division, node in that division).
    pub division_node: Vec<Option<(u32, u32)>>,
    /// For every node: its division's index if it is a division leaf, else
    /// [`NOT_A_DIVISION_LEAF`] (4 bytes a node, read on every pair traversal
    /// keeps, so kept apart from the 12-byte `division_node`).
    leaf_division: Vec<u32>,
    /// The plane of each division's big triangle, prepared once.
    planes: Vec<TrianglePlane>,
    /// Each division's root sphere (it holds the whole big triangle).
    division_spheres: Vec<Sphere>,
    /// Each division's big triangle's edge planes, prepared once.
    prisms: Vec<TrianglePrism>,
    /// Whether each environment triangle is big.
    pub big: Vec<bool>,
    /// Whether a division stopped at the level cap somewhere.
    pub capped: bool,
    /// Whether every division is one leaf (its whole big triangle, as
    /// [`Method::UndividedPrunedTriTri`] leaves it): then no (character
    /// triangle, big triangle) pair is reached twice in one traversal, and
    /// the repeat marks are not needed ([`Self::groups_are_single_leaves`]).
    single_leaf_divisions: bool,
    /// Each node's box of its triangles, for the methods that test each
    /// pair once ([`Self::plane_prism_guard`]); empty for the others.
    boxes: NodeBoxes,
}

impl EnvironmentTree {
    /// Builds the hierarchy of `mesh` for `method`.
    pub fn build(mesh: &TriMesh, method: Method, threshold: Real, params: BuildParams) -> Self {
        let all: Vec<TriangleId> = (0..mesh.triangle_count() as u32).map(TriangleId).collect();
        let base = build_tree(mesh, &all, params);
        let big: Vec<bool> = all
            .iter()
            .map(|&t| mesh.triangle(t).longest_edge() > threshold)
            .collect();
        let Some(kind) = method.division() else {
            let n = base.len();
            let boxes = Self::boxes_for(method, &base, mesh);
            return Self {
                boxes,
                method,
                threshold,
                tree: base,
                divisions: vec![],
                division_node: vec![None; n],
                leaf_division: vec![NOT_A_DIVISION_LEAF; n],
                planes: vec![],
                division_spheres: vec![],
                prisms: vec![],
                big,
                capped: false,
                single_leaf_divisions: true,
            };
        };
        let mut divisions = Vec::new();
        let mut division_of = vec![u32::MAX; mesh.triangle_count()];
        for &t in &all {
            if big[t.index()] {
                division_of[t.index()] = divisions.len() as u32;
                divisions.push(Division::build(
                    &mesh.triangle(t),
                    t,
                    kind,
                    threshold,
                    MAX_LEVELS,
                ));
            }
        }
        let capped = divisions.iter().any(|d| d.capped);
        let single_leaf_divisions = divisions.iter().all(|d| d.tree.len() == 1);

        // Breadth-first graft: a base leaf of a big triangle continues into its
        // division (whose root replaces the leaf).
        #[derive(Clone, Copy)]
        enum From {
            Base(u32),
            Div(u32, u32),
        }
        let resolve = |f: From| -> (Node, From) {
            match f {
                From::Base(i) => {
                    let n = *base.node(NodeId(i));
                    match n.primitive() {
                        Some(p) if division_of[p as usize] != u32::MAX => {
                            let d = division_of[p as usize];
                            (
                                *divisions[d as usize].tree.node(NodeId::ROOT),
                                From::Div(d, 0),
                            )
                        }
                        _ => (n, f),
                    }
                }
                From::Div(d, i) => (*divisions[d as usize].tree.node(NodeId(i)), f),
            }
        };
        let (tree, order) = SphereTree::breadth_first(From::Base(0), |f, kids| {
            let (src, from) = resolve(f);
            kids.extend(src.children().map(|c| match from {
                From::Base(_) => From::Base(c),
                From::Div(d, _) => From::Div(d, c),
            }));
            (src.sphere, src.primitive())
        });
        let division_node: Vec<Option<(u32, u32)>> = order
            .iter()
            .map(|&f| match resolve(f).1 {
                From::Div(d, k) => Some((d, k)),
                From::Base(_) => None,
            })
            .collect();
        let leaf_division = division_node
            .iter()
            .zip(tree.nodes())
            .map(|(d, n)| match d {
                Some((d, _)) if n.is_leaf() => *d,
                _ => NOT_A_DIVISION_LEAF,
            })
            .collect();
        let planes = divisions
            .iter()
            .map(|d| TrianglePlane::new(&mesh.triangle(d.original)))
            .collect();
        let prisms = divisions
            .iter()
            .map(|d| TrianglePrism::new(&mesh.triangle(d.original)))
            .collect();
        let division_spheres = divisions
            .iter()
            .map(|d| d.tree.node(NodeId::ROOT).sphere)
            .collect();
        let boxes = Self::boxes_for(method, &tree, mesh);
        Self {
            boxes,
            method,
            threshold,
            tree,
            divisions,
            division_node,
            leaf_division,
            planes,
            division_spheres,
            prisms,
            big,
            capped,
            single_leaf_divisions,
        }
    }

    /// The node boxes of `tree` over `mesh` if `method` guards with them.
    fn boxes_for(method: Method, tree: &SphereTree, mesh: &TriMesh) -> NodeBoxes {
        if !method.tests_each_pair_once() {
            return NodeBoxes::default();
        }
        NodeBoxes::build(tree, |p| {
            let t = mesh.triangle(TriangleId(p));
            [t.a, t.b, t.c]
        })
    }

    /// Whether the sphere `s` meets the plane of the big triangle whose
    /// division leaf is `id` (Algorithm 1), or `None` if `id` is no division
    /// leaf.
    #[inline]
    pub fn leaf_meets_plane(&self, id: NodeId, s: &Sphere) -> Option<bool> {
        match self.leaf_division[id.index()] {
            NOT_A_DIVISION_LEAF => None,
            d => Some(self.planes[d as usize].meets(s)),
        }
    }

    /// The guard of the methods that test the plane on the way down: a
    /// sphere paired with a big triangle's division leaf must meet that
    /// triangle's plane (Algorithm 1), or the pair is dropped with everything
    /// under it. A triangle crossing the big triangle has corners on both
    /// sides of its plane, so every sphere holding it meets the plane, and no
    /// contact is lost. Each plane test made adds one to `tests`.
    #[inline]
    pub fn plane_guard<'a>(
        &'a self,
        tests: &'a mut u64,
    ) -> impl FnMut(NodeId, &Sphere) -> bool + 'a {
        move |j, s| match self.leaf_meets_plane(j, s) {
            None => true,
            Some(meets) => {
                *tests += 1;
                meets
            }
        }
    }

    /// For a leaf of a big triangle's division: the division's index and its
    /// root sphere, which holds the big triangle (the leaf groups of
    /// `sphere_tree::grouped`).
    #[inline]
    pub fn leaf_group(&self, id: NodeId) -> Option<(u32, Sphere)> {
        match self.leaf_division[id.index()] {
            NOT_A_DIVISION_LEAF => None,
            d => Some((d, self.division_spheres[d as usize])),
        }
    }

    /// The guard of the methods that test each pair once. At a big
    /// triangle's division leaf, [`Self::plane_guard`]'s plane test, then
    /// the triangle's edge planes ([`TrianglePrism`]): a sphere wholly
    /// outside one holds no point of the triangle, so no character triangle
    /// under it meets the triangle. With `sphere_tree::grouped` descents,
    /// which test spheres against a whole division's root sphere, this keeps
    /// them to the big triangle's prism. At every other node, the node's box
    /// of its triangles ([`NodeBoxes`]): a sphere wholly outside it holds
    /// no point of them. Each sphere tested counts one plane-sphere test
    /// for the plane and one for the edge planes, if it gets there, in
    /// `plane_tests`; each box test one in `box_tests`.
    #[inline]
    pub fn plane_prism_guard<'a>(
        &'a self,
        plane_tests: &'a mut u64,
        box_tests: &'a mut u64,
    ) -> impl FnMut(NodeId, &Sphere) -> bool + 'a {
        move |j, s| match self.leaf_division[j.index()] {
            NOT_A_DIVISION_LEAF => self.box_may_meet(j, s, box_tests),
            d => {
                *plane_tests += 1;
                if !self.planes[d as usize].meets(s) {
                    return false;
                }
                *plane_tests += 1;
                self.prisms[d as usize].may_meet(s)
            }
        }
    }

    /// Whether the sphere `s` may reach the triangles under node `j` by the
    /// node's box ([`NodeBoxes`]): `true` where this tree keeps no boxes
    /// (the methods that do not test each pair once) and at a big
    /// triangle's division leaf (its plane and edge planes guard it). Each
    /// box test made counts one in `tests`.
    #[inline]
    pub fn box_may_meet(&self, j: NodeId, s: &Sphere, tests: &mut u64) -> bool {
        if self.boxes.is_empty() || self.leaf_division[j.index()] != NOT_A_DIVISION_LEAF {
            return true;
        }
        *tests += 1;
        self.boxes.may_meet(&self.tree, j, s)
    }

    /// Starts loading what a traversal reads of node `id`: the node and its
    /// division mark (a hint; see `crate::prefetch`).
    #[inline(always)]
    pub fn prefetch(&self, id: NodeId) {
        prefetch_at(self.tree.nodes(), id.index());
        prefetch_at(&self.leaf_division, id.index());
    }

    /// The edge planes of the big triangle whose division leaf is `id`,
    /// where this tree keeps them (the methods that test each pair once).
    #[inline]
    pub fn prism_of(&self, id: NodeId) -> Option<&TrianglePrism> {
        match self.leaf_division[id.index()] {
            NOT_A_DIVISION_LEAF => None,
            d => self.prisms.get(d as usize),
        }
    }

    /// Whether node `id` is a leaf of a big triangle's division.
    #[inline]
    pub fn is_division_leaf(&self, id: NodeId) -> bool {
        self.leaf_division[id.index()] != NOT_A_DIVISION_LEAF
    }

    /// Whether every big triangle's division is a single leaf. A traversal
    /// reaches each pair of nodes at most once (the side it opens is a
    /// function of the pair, so the path from the roots to a pair is
    /// unique); with one leaf per big triangle, each (character triangle,
    /// big triangle) pair is then reached at most once, and neither the
    /// group marks of `sphere_tree::grouped` nor the narrow phase's repeat
    /// marks can drop anything.
    #[inline]
    pub fn groups_are_single_leaves(&self) -> bool {
        self.single_leaf_divisions
    }

    /// Whether `method` answers a leaf pair whose second leaf is `leaf` of
    /// this tree by the plane-sphere test (a big triangle's division leaf,
    /// in a plane-sphere method) rather than by the triangle-triangle test.
    #[inline]
    pub fn answers_by_plane(&self, method: Method, leaf: NodeId) -> bool {
        self.is_division_leaf(leaf) && method.big_leaf_test() == LeafTest::PlaneSphere
    }

    /// Number of big triangles.
    pub fn big_count(&self) -> usize {
        self.big.iter().filter(|b| **b).count()
    }

    /// Bytes of the sphere hierarchy (nodes) and its node boxes.
    pub fn bytes(&self) -> usize {
        self.tree.bytes() + self.boxes.bytes()
    }
}
