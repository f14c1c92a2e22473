//! Which nodes of a character tree, and which pairs of nodes, cover a
//! topological disk of the mesh, with the disk's boundary loop: what the
//! contour test of normal-cone culling needs (ours, after Volino &
//! Magnenat-Thalmann 1994 and Schvartzman et al. 2010).
//!
//! **Why a disk.** Let a patch of triangles be a consistently oriented
//! disk, let every triangle's normal face one direction `d`, and let its
//! boundary loop, seen along `d`, be a simple polygon. Seen along `d`, every
//! triangle is then counterclockwise, interior edges cancel, and a point of
//! the plane is covered by as many triangles as the boundary winds around
//! it: at most once. The projection is one-to-one on the patch, so the
//! patch is embedded, and two of its triangles without a common corner do
//! not meet. The pass then skips the node (or the pair of nodes) whole.
//!
//! The topology is that of the mesh with vertices welded when they have
//! equal bind positions *and* equal skinning influences, so welded copies
//! are posed to the very same point (a glTF seam whose copies are skinned
//! alike is closed; one skinned differently stays a boundary, which no
//! simple contour passes).
//!
//! What is stored is limited to what can pay: nodes and pairs whose rest
//! pose is already flat (their normals face one direction at rest). The
//! runtime test is the proof; this table only says where to try it.

use std::collections::HashMap;

use crate::character::{Character, SkinningModel};
use crate::mesh::TriangleId;

use super::character::CharacterTree;
use super::node::{NodeId, SphereTree};
use super::normal_cones::{NodeCones, NormalCone};
use super::self_contact::Widened;
use super::self_traverse::traverse_self;
use super::traverse::Workspace;

/// A boundary loop's place in [`FlatPatches`]' vertex list.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
struct LoopRange {
    start: u32,
    len: u32,
}

/// The disks of a character tree (see the module doc).
#[derive(Clone, Debug, Default)]
pub struct FlatPatches {
    /// Per node: its boundary loop, or an empty range (not a disk, or not
    /// flat at rest).
    node_loops: Vec<LoopRange>,
    /// Pairs of nodes by their lower id: `pair_first[i] .. pair_first[i +
    /// 1]` index `pair_other` and `pair_loops`.
    pair_first: Vec<u32>,
    pair_other: Vec<u32>,
    pair_loops: Vec<LoopRange>,
    /// Loop corners: mesh vertex indices, each a welded class's first.
    loop_vertices: Vec<u32>,
}

impl FlatPatches {
    /// The disks among `tree`'s nodes, and among the pairs of nodes its
    /// rest walk against itself meets, that are flat at rest.
    pub fn new(character: &Character, tree: &CharacterTree) -> Self {
        let mesh = &character.mesh;
        let weld = weld_posing_alike(character, tree.model);
        let corners = |t: u32| mesh.indices()[t as usize].map(|v| weld[v as usize]);
        let topology = &tree.tree;
        let nodes = topology.nodes();
        let mut rest_cones = NodeCones::default();
        rest_cones.update(topology, |t| mesh.triangle(TriangleId(t)));

        let mut out = Self {
            node_loops: vec![LoopRange::default(); nodes.len()],
            ..Self::default()
        };
        let mut scratch = DiskScratch::default();
        let mut tris = Vec::new();
        for i in 0..nodes.len() {
            let cone = rest_cones.of(NodeId(i as u32));
            if cone.is_everything() || !cone.faces(&cone.axis) {
                continue;
            }
            tris.clear();
            subtree_triangles(topology, NodeId(i as u32), &mut tris);
            if let Some(lp) = scratch.boundary_of_disk(tris.iter().map(|&t| corners(t))) {
                out.node_loops[i] = out.push_loop(lp);
            }
        }

        // Pairs: those the rest walk meets whose two nodes are disks whose
        // union is a disk facing one direction at rest.
        let mut pairs: Vec<(u32, u32, LoopRange)> = Vec::new();
        let mut vertex_scratch = Vec::new();
        let mut rest = Widened {
            tree: topology,
            by: 0.0,
        };
        let loops = out.node_loops.clone();
        traverse_self(
            topology,
            &mut rest,
            &mut Workspace::new(),
            |_| false,
            |_, i, j| {
                let (li, lj) = (loops[i.index()], loops[j.index()]);
                // Two single triangles: their sphere test is cheaper than
                // any proof.
                let leaves = topology.node(i).is_leaf() && topology.node(j).is_leaf();
                if li.len == 0 || lj.len == 0 || leaves {
                    return true;
                }
                let (ci, cj) = (rest_cones.of(i), rest_cones.of(j));
                if NormalCone::common_facing(ci, cj).is_none() {
                    return true;
                }
                // Adjacent: their boundaries share a corner.
                vertex_scratch.clear();
                vertex_scratch.extend_from_slice(out.loop_of(li));
                vertex_scratch.sort_unstable();
                if !out
                    .loop_of(lj)
                    .iter()
                    .any(|v| vertex_scratch.binary_search(v).is_ok())
                {
                    return true;
                }
                tris.clear();
                subtree_triangles(topology, i, &mut tris);
                subtree_triangles(topology, j, &mut tris);
                if let Some(lp) = scratch.boundary_of_disk(tris.iter().map(|&t| corners(t))) {
                    let range = out.push_loop(lp);
                    pairs.push((i.0.min(j.0), i.0.max(j.0), range));
                }
                true
            },
            |_, _| {},
        );
        pairs.sort_unstable_by_key(|&(a, b, _)| (a, b));
        pairs.dedup_by_key(|&mut (a, b, _)| (a, b));
        out.pair_first = vec![0; nodes.len() + 1];
        for &(a, _, _) in &pairs {
            out.pair_first[a as usize + 1] += 1;
        }
        for i in 0..nodes.len() {
            out.pair_first[i + 1] += out.pair_first[i];
        }
        out.pair_other = pairs.iter().map(|p| p.1).collect();
        out.pair_loops = pairs.iter().map(|p| p.2).collect();
        out
    }

    fn push_loop(&mut self, lp: &[u32]) -> LoopRange {
        let start = self.loop_vertices.len() as u32;
        self.loop_vertices.extend_from_slice(lp);
        LoopRange {
            start,
            len: lp.len() as u32,
        }
    }

    fn loop_of(&self, r: LoopRange) -> &[u32] {
        &self.loop_vertices[r.start as usize..(r.start + r.len) as usize]
    }

    /// Node `n`'s boundary loop (mesh vertices, counterclockwise seen from
    /// its normals' side), if it is a disk flat at rest.
    #[inline]
    pub fn node_loop(&self, n: NodeId) -> Option<&[u32]> {
        let r = self.node_loops[n.index()];
        (r.len > 0).then(|| self.loop_of(r))
    }

    /// The boundary loop of nodes `i` and `j` together, if they are a disk
    /// flat at rest.
    #[inline]
    pub fn pair_loop(&self, i: NodeId, j: NodeId) -> Option<&[u32]> {
        let (a, b) = (i.0.min(j.0), i.0.max(j.0));
        let range = self.pair_first[a as usize] as usize..self.pair_first[a as usize + 1] as usize;
        let k = self.pair_other[range.clone()]
            .iter()
            .position(|&o| o == b)?;
        Some(self.loop_of(self.pair_loops[range.start + k]))
    }

    /// Nodes that are disks flat at rest.
    pub fn disk_nodes(&self) -> usize {
        self.node_loops.iter().filter(|r| r.len > 0).count()
    }

    /// Pairs of nodes that are disks flat at rest.
    pub fn disk_pairs(&self) -> usize {
        self.pair_other.len()
    }

    /// Whether any pair of nodes is stored for node `n` (a cheap first look
    /// before [`Self::pair_loop`]).
    #[inline]
    pub fn has_pairs(&self, n: NodeId) -> bool {
        let a = n.index();
        self.pair_first[a] != self.pair_first[a + 1]
    }

    /// Heap bytes held.
    pub fn bytes(&self) -> usize {
        self.node_loops.len() * 8
            + self.pair_first.len() * 4
            + self.pair_other.len() * 4
            + self.pair_loops.len() * 8
            + self.loop_vertices.len() * 4
    }
}

/// Vertex ids after welding vertices with equal bind positions and equal
/// skinning influences (so welded copies are posed to one point): each
/// vertex's class is named by its first member.
pub fn weld_posing_alike(character: &Character, model: SkinningModel) -> Vec<u32> {
    let mesh = &character.mesh;
    let mut first: HashMap<Vec<u32>, u32> = HashMap::with_capacity(mesh.vertex_count());
    let mut key = Vec::new();
    (0..mesh.vertex_count())
        .map(|v| {
            let p = mesh.positions()[v];
            key.clear();
            key.extend([p.x, p.y, p.z].map(|c| (c + 0.0).to_bits()));
            match model {
                SkinningModel::Linear => {
                    for (j, w) in character.influences.of(v) {
                        key.extend([u32::from(j.0), w.to_bits()]);
                    }
                }
                SkinningModel::Paper => {
                    key.extend([
                        u32::from(character.paper.joint(v).0),
                        character.paper.weight(v).to_bits(),
                    ]);
                }
            }
            *first.entry(key.clone()).or_insert(v as u32)
        })
        .collect()
}

/// Appends the triangles under node `n` to `out`.
fn subtree_triangles(tree: &SphereTree, n: NodeId, out: &mut Vec<u32>) {
    let mut stack = vec![n.0];
    while let Some(k) = stack.pop() {
        let node = tree.node(NodeId(k));
        match node.primitive() {
            Some(t) => out.push(t),
            None => stack.extend(node.children()),
        }
    }
}

/// Working memory of [`DiskScratch::boundary_of_disk`].
#[derive(Default)]
pub(crate) struct DiskScratch {
    edges: Vec<(u32, u32, u32)>,
    boundary: Vec<(u32, u32)>,
    vertices: Vec<u32>,
    parent: Vec<u32>,
    boundary_loop: Vec<u32>,
}

impl DiskScratch {
    /// If the triangles (welded corners, in their winding) form one
    /// consistently oriented topological disk, its boundary loop in the
    /// triangles' winding direction; `None` otherwise.
    ///
    /// A disk: no triangle repeats a corner; no directed edge twice (two
    /// triangles at most on an edge, in opposite directions); connected
    /// across edges; one boundary loop, each boundary corner leaving it
    /// once; Euler characteristic `V − E + F = 1`.
    pub(crate) fn boundary_of_disk(
        &mut self,
        triangles: impl Iterator<Item = [u32; 3]>,
    ) -> Option<&[u32]> {
        self.edges.clear();
        let mut f = 0u32;
        for [a, b, c] in triangles {
            if a == b || b == c || a == c {
                return None;
            }
            self.edges.extend([(a, b, f), (b, c, f), (c, a, f)]);
            f += 1;
        }
        if f == 0 {
            return None;
        }
        self.edges.sort_unstable();
        if self
            .edges
            .windows(2)
            .any(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1))
        {
            return None;
        }
        // Union-find over triangles across interior edges.
        self.parent.clear();
        self.parent.extend(0..f);
        fn root(parent: &mut [u32], mut x: u32) -> u32 {
            while parent[x as usize] != x {
                parent[x as usize] = parent[parent[x as usize] as usize];
                x = parent[x as usize];
            }
            x
        }
        self.boundary.clear();
        for k in 0..self.edges.len() {
            let (a, b, t) = self.edges[k];
            match self.edges.binary_search_by(|e| (e.0, e.1).cmp(&(b, a))) {
                Ok(r) => {
                    let (x, y) = (
                        root(&mut self.parent, t),
                        root(&mut self.parent, self.edges[r].2),
                    );
                    self.parent[x as usize] = y;
                }
                Err(_) => self.boundary.push((a, b)),
            }
        }
        let r0 = root(&mut self.parent, 0);
        if (1..f).any(|t| root(&mut self.parent, t) != r0) {
            return None;
        }
        self.vertices.clear();
        self.vertices.extend(self.edges.iter().map(|e| e.0));
        self.vertices.sort_unstable();
        self.vertices.dedup();
        let (v, d, b) = (
            self.vertices.len() as i64,
            self.edges.len() as i64,
            self.boundary.len() as i64,
        );
        // Interior edges are met twice as directed edges, boundary edges once.
        let e = (d + b) / 2;
        if b < 3 || v - e + i64::from(f) != 1 {
            return None;
        }
        // One loop: boundary edges by their start, each start once, walked
        // from the first back to it through every boundary edge.
        self.boundary.sort_unstable();
        if self.boundary.windows(2).any(|w| w[0].0 == w[1].0) {
            return None;
        }
        self.boundary_loop.clear();
        let start = self.boundary[0].0;
        let mut at = start;
        loop {
            self.boundary_loop.push(at);
            let k = self.boundary.binary_search_by(|e| e.0.cmp(&at)).ok()?;
            at = self.boundary[k].1;
            if at == start || self.boundary_loop.len() > self.boundary.len() {
                break;
            }
        }
        (at == start && self.boundary_loop.len() == self.boundary.len())
            .then_some(&self.boundary_loop[..])
    }
}

#[cfg(test)]
mod tests {
    use super::DiskScratch;

    /// A `w × h` grid of quads, two triangles each, counterclockwise seen
    /// from +z; vertex `x + (w + 1)·y`.
    fn grid(w: u32, h: u32) -> Vec<[u32; 3]> {
        let v = |x: u32, y: u32| x + (w + 1) * y;
        let mut t = Vec::new();
        for y in 0..h {
            for x in 0..w {
                t.push([v(x, y), v(x + 1, y), v(x + 1, y + 1)]);
                t.push([v(x, y), v(x + 1, y + 1), v(x, y + 1)]);
            }
        }
        t
    }

    #[test]
    fn a_grid_is_a_disk_with_its_outline_counterclockwise() {
        let mut s = DiskScratch::default();
        let lp = s.boundary_of_disk(grid(3, 2).into_iter()).unwrap().to_vec();
        assert_eq!(lp.len(), 10);
        // Counterclockwise: (0,0) → (1,0) along the bottom row.
        let at = lp.iter().position(|&v| v == 0).unwrap();
        assert_eq!(lp[(at + 1) % lp.len()], 1);
    }

    #[test]
    fn not_disks() {
        let mut s = DiskScratch::default();
        // A flipped triangle: inconsistent orientation.
        let mut g = grid(2, 2);
        g[3] = [g[3][0], g[3][2], g[3][1]];
        assert!(s.boundary_of_disk(g.into_iter()).is_none());
        // Two grids not connected.
        let mut two = grid(1, 1);
        two.extend(grid(1, 1).into_iter().map(|t| t.map(|v| v + 100)));
        assert!(s.boundary_of_disk(two.into_iter()).is_none());
        // An annulus: a 3×3 grid without its middle quad.
        let ring: Vec<_> = grid(3, 3)
            .into_iter()
            .enumerate()
            .filter(|(k, _)| *k / 2 != 4)
            .map(|(_, t)| t)
            .collect();
        assert!(s.boundary_of_disk(ring.into_iter()).is_none());
        // Two quads touching at one corner only (a bow tie).
        let v = |x: u32, y: u32| x + 3 * y;
        let bow = vec![
            [v(0, 0), v(1, 0), v(1, 1)],
            [v(0, 0), v(1, 1), v(0, 1)],
            [v(1, 1), v(2, 1), v(2, 2)],
            [v(1, 1), v(2, 2), v(1, 2)],
        ];
        assert!(s.boundary_of_disk(bow.into_iter()).is_none());
        // A closed surface (a tetrahedron) has no boundary.
        let tet = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
        assert!(s.boundary_of_disk(tet.into_iter()).is_none());
        // A disk and a separate closed tetrahedron: χ = 1 + 2, refused; a
        // degenerate triangle, refused.
        let mut dt = grid(1, 1);
        dt.extend([[10, 12, 11], [10, 11, 13], [11, 12, 13], [10, 13, 12]]);
        assert!(s.boundary_of_disk(dt.into_iter()).is_none());
        assert!(s.boundary_of_disk([[0, 1, 1]].into_iter()).is_none());
    }
}
