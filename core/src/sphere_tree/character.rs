//! The character's sphere tree (paper §3): one tree per joint over the
//! triangles that joint owns, merged under a root sphere and one sphere per
//! extremity.
//!
//! **Ownership.** A vertex belongs to its joint in the paper's model
//! ([`PaperBinding`](crate::character::PaperBinding)); a triangle to the joint
//! owning most of its vertices (all three different: the first vertex's).
//!
//! **Extremities** (our reading; the paper does not define them). A joint is a
//! *major branch* when at least two of its child subtrees each own at least
//! [`MAJOR_SHARE`] of the triangles. The *trunk* is the root joint(s) plus every
//! joint on a path from a root to a major branch. Each child subtree hanging off
//! the trunk is one extremity (legs, arms, head for a humanoid); the trunk's own
//! joints form one more group (the torso). A group made of a single joint's
//! tree is not wrapped again: that tree's root is the level-2 sphere.
//!
//! Spheres are built in bind space; each node also gets the rule that refits it
//! (see [`refit`](super::refit)).

use crate::character::{Character, JointId, Skeleton, SkinningModel};
use crate::geometry::enclosing::{grow_to_hold, points_sphere};
use crate::geometry::{Point, Sphere};
use crate::mesh::{EdgeDedup, TriangleId};

use super::build::{BuildParams, build_tree};
use super::node::{NodeId, SphereTree};
use super::refit_rules::{Origin, RefitData, RefitRule};

/// Share of triangles a child subtree needs for its parent to be a major branch.
pub const MAJOR_SHARE: f64 = 0.05;

/// A level-2 group: the trunk or one extremity.
#[derive(Clone, Debug, PartialEq)]
pub struct Extremity {
    /// Name of the group's top joint ("trunk" for the trunk).
    pub name: String,
    /// The group's joints, in skeleton order.
    pub joints: Vec<JointId>,
}

/// The merged tree, its refit rules and how it was assembled.
#[derive(Clone, Debug)]
pub struct CharacterTree {
    /// Topology and bind-space (rest) spheres.
    pub tree: SphereTree,
    /// The rule refitting each node to a pose (paper §3, sphere update).
    pub refit: RefitData,
    /// The skinning model the refit rules bound.
    pub model: SkinningModel,
    /// The level-2 groups: the trunk first (when there is one), then one
    /// per extremity.
    pub extremities: Vec<Extremity>,
    /// Owning joint of every mesh triangle.
    pub triangle_joint: Vec<JointId>,
    /// Triangles in the tree (after de-duplication, if any).
    pub triangles: Vec<TriangleId>,
    /// Per mesh triangle: the joint that alone moves its three corners
    /// under [`Self::model`] ([`Character::sole_joint`]), or
    /// [`super::self_contact::MIXED`].
    pub sole_joint: Vec<u16>,
    /// [`Character::bind_coordinate_bound`], which bounds a skinned
    /// corner's rounding.
    pub bind_coordinate_bound: f32,
}

impl CharacterTree {
    /// Builds the tree over the triangles `dedup` keeps, with the paper's
    /// refit rules for `model`.
    pub fn build(
        character: &Character,
        dedup: &EdgeDedup,
        model: SkinningModel,
        params: BuildParams,
    ) -> Self {
        Self::build_with_rule(character, dedup, model, params, RefitRule::PaperCorners)
    }

    /// [`CharacterTree::build`] with `rule` refitting the nodes (joint
    /// balls: every node, root and extremities included).
    pub fn build_with_rule(
        character: &Character,
        dedup: &EdgeDedup,
        model: SkinningModel,
        params: BuildParams,
        rule: RefitRule,
    ) -> Self {
        let mesh = &character.mesh;
        let skeleton = &character.skeleton;
        let triangle_joint: Vec<JointId> = mesh
            .indices()
            .iter()
            .map(|t| {
                let j = t.map(|v| character.paper.joint(v as usize));
                if j[1] == j[2] { j[1] } else { j[0] }
            })
            .collect();
        let triangles: Vec<TriangleId> = dedup.kept().collect();

        // Per-joint trees.
        let mut per_joint: Vec<Vec<TriangleId>> = vec![Vec::new(); skeleton.len()];
        for &t in &triangles {
            per_joint[triangle_joint[t.index()].index()].push(t);
        }
        let joint_trees: Vec<(JointId, SphereTree)> = per_joint
            .iter()
            .enumerate()
            .filter(|(_, ts)| !ts.is_empty())
            .map(|(j, ts)| (JointId(j as u16), build_tree(mesh, ts, params)))
            .collect();

        let counts: Vec<usize> = per_joint.iter().map(Vec::len).collect();
        let extremities = extremities(skeleton, &counts);

        // Groups of joint-tree indices.
        let tree_of_joint = |j: JointId| joint_trees.iter().position(|(k, _)| *k == j);
        let groups: Vec<Vec<usize>> = extremities
            .iter()
            .map(|e| {
                e.joints
                    .iter()
                    .filter_map(|&j| tree_of_joint(j))
                    .collect::<Vec<_>>()
            })
            .filter(|g: &Vec<usize>| !g.is_empty())
            .collect();
        // A joint tree no extremity holds (a damaged skeleton's joints can
        // escape the trunk-and-branches reading) is a group of its own.
        let mut held = vec![false; joint_trees.len()];
        groups.iter().flatten().for_each(|&t| held[t] = true);
        let groups: Vec<Vec<usize>> = groups
            .into_iter()
            .chain(
                (0..joint_trees.len())
                    .filter(|&t| !held[t])
                    .map(|t| vec![t]),
            )
            .collect();

        let (tree, origin) = assemble(character, &joint_trees, &per_joint, &groups);
        let refit = RefitData::new(character, model, &tree, &origin, &joint_trees, rule);
        Self {
            tree,
            refit,
            model,
            extremities,
            triangle_joint,
            triangles,
            sole_joint: sole_joints(character, model),
            bind_coordinate_bound: character.bind_coordinate_bound(),
        }
    }
}

/// Per mesh triangle, the joint that alone moves its corners under `model`,
/// or [`super::self_contact::MIXED`].
pub fn sole_joints(character: &Character, model: SkinningModel) -> Vec<u16> {
    let joint = |v: u32| {
        character
            .sole_joint(model, v as usize)
            .map_or(super::self_contact::MIXED, |j| j.0)
    };
    character
        .mesh
        .indices()
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(joint);
            if a == b && b == c {
                a
            } else {
                super::self_contact::MIXED
            }
        })
        .collect()
}

/// The trunk and extremities of a skeleton, given triangles owned per joint.
pub fn extremities(skeleton: &Skeleton, owned: &[usize]) -> Vec<Extremity> {
    let n = skeleton.len();
    let children = skeleton.children();
    // Triangles in each joint's subtree (children come after parents).
    let mut subtree = owned.to_vec();
    for i in (0..n).rev() {
        if let Some(p) = skeleton.parent(JointId(i as u16)) {
            subtree[p.index()] += subtree[i];
        }
    }
    let total: usize = owned.iter().sum::<usize>().max(1);
    let big = |j: &JointId| subtree[j.index()] as f64 >= MAJOR_SHARE * total as f64;
    let mut trunk = vec![false; n];
    let roots: Vec<JointId> = (0..n as u16)
        .map(JointId)
        .filter(|&j| skeleton.parent(j).is_none())
        .collect();
    let several_roots = roots.iter().filter(|r| big(r)).count() >= 2;
    if !several_roots {
        for &r in &roots {
            trunk[r.index()] = true;
        }
    }
    for (j, kids) in children.iter().enumerate() {
        if kids.iter().filter(|c| big(c)).count() >= 2 {
            // Mark the path from this major branch up to its root.
            let mut k = Some(JointId(j as u16));
            while let Some(x) = k {
                trunk[x.index()] = true;
                k = skeleton.parent(x);
            }
        }
    }
    let mut out = Vec::new();
    let trunk_joints: Vec<JointId> = (0..n as u16)
        .map(JointId)
        .filter(|j| trunk[j.index()])
        .collect();
    if !trunk_joints.is_empty() {
        out.push(Extremity {
            name: "trunk".into(),
            joints: trunk_joints,
        });
    }
    // Each non-trunk child of a trunk joint (or each root, with several roots)
    // heads one extremity.
    let heads: Vec<JointId> = (0..n as u16)
        .map(JointId)
        .filter(|&j| !trunk[j.index()])
        .filter(|&j| match skeleton.parent(j) {
            Some(p) => trunk[p.index()],
            None => true,
        })
        .collect();
    for h in heads {
        let joints: Vec<JointId> = (0..n as u16)
            .map(JointId)
            .filter(|&j| skeleton.is_ancestor_or_self(h, j))
            .collect();
        out.push(Extremity {
            name: skeleton.joint(h).name.clone(),
            joints,
        });
    }
    out
}

/// Lays the merged tree out breadth first; returns it with each node's origin.
fn assemble(
    character: &Character,
    joint_trees: &[(JointId, SphereTree)],
    per_joint: &[Vec<TriangleId>],
    groups: &[Vec<usize>],
) -> (SphereTree, Vec<Origin>) {
    if groups.is_empty() {
        // No triangle kept (every one degenerate or left out): no tree.
        return (SphereTree::default(), Vec::new());
    }
    let mesh = &character.mesh;
    let tree_root = |t: usize| joint_trees[t].1.node(NodeId::ROOT).sphere;
    // Minimal sphere of the trees' vertices, grown to hold the children's spheres.
    let enclose = |trees: &mut dyn Iterator<Item = usize>, kids: &[Sphere]| -> Sphere {
        let vertices: Vec<Point> = trees
            .flat_map(|t| per_joint[joint_trees[t].0.index()].iter())
            .flat_map(|&tri| mesh.triangle(tri).vertices())
            .collect();
        let mut s = points_sphere(&vertices);
        for k in kids {
            grow_to_hold(&mut s, k);
        }
        s
    };
    let group_spheres: Vec<Sphere> = groups
        .iter()
        .map(|g| {
            enclose(
                &mut g.iter().copied(),
                &g.iter().map(|&t| tree_root(t)).collect::<Vec<_>>(),
            )
        })
        .collect();
    // A group of a single joint tree is that tree's root.
    let level2: Vec<Origin> = groups
        .iter()
        .enumerate()
        .map(|(g, trees)| {
            if trees.len() == 1 {
                Origin::Joint(trees[0], NodeId::ROOT)
            } else {
                Origin::Group(g)
            }
        })
        .collect();
    let root_sphere = (level2.len() > 1).then(|| {
        let kids: Vec<Sphere> = level2
            .iter()
            .map(|&o| match o {
                Origin::Group(g) => group_spheres[g],
                Origin::Joint(t, _) => tree_root(t),
                Origin::Root => unreachable!("the root is nobody's child"),
            })
            .collect();
        enclose(&mut (0..joint_trees.len()), &kids)
    });
    let root = root_sphere.map_or(level2[0], |_| Origin::Root);
    SphereTree::breadth_first(root, |o, kids| match o {
        Origin::Root => {
            kids.extend_from_slice(&level2);
            (
                root_sphere.expect("a root sphere when there is a root"),
                None,
            )
        }
        Origin::Group(g) => {
            kids.extend(groups[g].iter().map(|&t| Origin::Joint(t, NodeId::ROOT)));
            (group_spheres[g], None)
        }
        Origin::Joint(t, n) => {
            let src = joint_trees[t].1.node(n);
            kids.extend(src.children().map(|c| Origin::Joint(t, NodeId(c))));
            (src.sphere, src.primitive())
        }
    })
}
