//! Edge de-duplication (paper §4, Fig. 1, after Curtis et al.).
//!
//! Every edge of the mesh needs testing once. A triangle whose three edges are
//! already covered by triangles kept for collision detection adds nothing a
//! penetrating edge could not already reveal, so it is left out. The guarantee
//! kept here: **every edge of the mesh lies on at least one kept triangle**.
//! What is given up (the paper says so too): a small triangle piercing a
//! left-out triangle's interior without touching any of its edges is missed.
//!
//! Edges are identified geometrically: vertices at the same position are welded
//! first, so seams where glTF splits vertices (normals, UVs) still share edges.
//!
//! Choice of triangles (ours; the paper does not say), three greedy passes in
//! index order:
//! 1. keep triangles none of whose edges is covered yet (an edge-disjoint set,
//!    each covering three new edges);
//! 2. keep any triangle that still has an uncovered edge;
//! 3. drop again every kept triangle whose edges are all covered by at least
//!    one *other* kept triangle (pass 2 can make earlier choices redundant).
//!
//! On a closed mesh at most half the triangles can go (each kept one covers at
//! most 3 of the 1.5·F edges).

use std::collections::HashMap;

use super::{TriMesh, TriangleId};

/// Which triangles take part in collision detection after de-duplication.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct EdgeDedup {
    kept: Vec<bool>,
    kept_count: usize,
}

impl EdgeDedup {
    /// Keep every triangle (de-duplication off).
    pub fn keep_all(mesh: &TriMesh) -> Self {
        Self {
            kept: vec![true; mesh.triangle_count()],
            kept_count: mesh.triangle_count(),
        }
    }

    /// Whether triangle `id` takes part in collision detection.
    pub fn is_kept(&self, id: TriangleId) -> bool {
        self.kept[id.index()]
    }

    /// Number of triangles kept.
    pub fn kept_count(&self) -> usize {
        self.kept_count
    }

    /// Number of triangles left out.
    pub fn dropped_count(&self) -> usize {
        self.kept.len() - self.kept_count
    }

    /// Fraction of triangles left out, in `[0, 1]`.
    pub fn reduction(&self) -> f64 {
        if self.kept.is_empty() {
            0.0
        } else {
            self.dropped_count() as f64 / self.kept.len() as f64
        }
    }

    /// The kept triangles, in index order.
    pub fn kept(&self) -> impl Iterator<Item = TriangleId> + '_ {
        self.ids(true)
    }

    /// The triangles left out, in index order.
    pub fn dropped(&self) -> impl Iterator<Item = TriangleId> + '_ {
        self.ids(false)
    }

    fn ids(&self, kept: bool) -> impl Iterator<Item = TriangleId> + '_ {
        self.kept
            .iter()
            .enumerate()
            .filter(move |(_, k)| **k == kept)
            .map(|(i, _)| TriangleId(i as u32))
    }
}

/// Vertex ids after welding equal positions (bitwise equal coordinates, with
/// `-0.0` and `0.0` identified).
pub fn weld_positions(mesh: &TriMesh) -> Vec<u32> {
    let mut first: HashMap<[u32; 3], u32> = HashMap::with_capacity(mesh.vertex_count());
    mesh.positions()
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let key = [p.x, p.y, p.z].map(|c| (c + 0.0).to_bits());
            *first.entry(key).or_insert(i as u32)
        })
        .collect()
}

/// Undirected edge between welded vertices.
type Edge = (u32, u32);

/// The distinct geometric edges of triangle `tri` (degenerate edges, between
/// welded-equal vertices, are not edges and are left out).
pub fn triangle_edges(welded: &[u32], tri: &[u32; 3]) -> impl Iterator<Item = Edge> {
    let v = tri.map(|i| welded[i as usize]);
    let e = [(v[0], v[1]), (v[1], v[2]), (v[2], v[0])]
        .map(|(a, b)| (a != b).then(|| (a.min(b), a.max(b))));
    // A repeated vertex makes two of the three edges the same edge.
    let distinct = [
        e[0],
        e[1].filter(|x| Some(*x) != e[0]),
        e[2].filter(|x| Some(*x) != e[0] && Some(*x) != e[1]),
    ];
    distinct.into_iter().flatten()
}

/// Chooses the triangles to keep (see the module doc).
pub fn dedup_edges(mesh: &TriMesh) -> EdgeDedup {
    let welded = weld_positions(mesh);
    let mut covered: HashMap<Edge, ()> = HashMap::with_capacity(mesh.triangle_count() * 2);
    let mut kept = vec![false; mesh.triangle_count()];
    let tris = mesh.indices();

    // Pass 1: triangles that cover only new edges.
    for (t, tri) in tris.iter().enumerate() {
        if triangle_edges(&welded, tri).all(|e| !covered.contains_key(&e)) {
            kept[t] = true;
            covered.extend(triangle_edges(&welded, tri).map(|e| (e, ())));
        }
    }
    // Pass 2: whatever still brings an uncovered edge.
    for (t, tri) in tris.iter().enumerate() {
        if !kept[t] && triangle_edges(&welded, tri).any(|e| !covered.contains_key(&e)) {
            kept[t] = true;
            covered.extend(triangle_edges(&welded, tri).map(|e| (e, ())));
        }
    }
    // Pass 3: drop kept triangles made redundant, keeping coverage counts.
    let mut uses: HashMap<Edge, u32> = HashMap::with_capacity(covered.len());
    for (t, tri) in tris.iter().enumerate() {
        if kept[t] {
            for e in triangle_edges(&welded, tri) {
                *uses.entry(e).or_insert(0) += 1;
            }
        }
    }
    for (t, tri) in tris.iter().enumerate() {
        if kept[t] && triangle_edges(&welded, tri).all(|e| uses[&e] >= 2) {
            kept[t] = false;
            for e in triangle_edges(&welded, tri) {
                *uses.get_mut(&e).unwrap() -= 1;
            }
        }
    }
    let kept_count = kept.iter().filter(|k| **k).count();
    EdgeDedup { kept, kept_count }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;
    use std::collections::HashSet;

    /// Independent check: the set of edges of all triangles equals the set of
    /// edges of kept triangles.
    fn assert_edges_covered(mesh: &TriMesh, d: &EdgeDedup) {
        let w = weld_positions(mesh);
        let all: HashSet<Edge> = mesh
            .indices()
            .iter()
            .flat_map(|t| triangle_edges(&w, t))
            .collect();
        let kept: HashSet<Edge> = d
            .kept()
            .flat_map(|id| triangle_edges(&w, &mesh.indices()[id.index()]))
            .collect();
        assert_eq!(all, kept);
    }

    /// A regular grid of `n`×`n` quads, each split into two triangles.
    fn grid(n: u32) -> TriMesh {
        let p = (0..=n)
            .flat_map(|j| (0..=n).map(move |i| Point::new(i as f32, j as f32, 0.0)))
            .collect();
        let at = |i: u32, j: u32| j * (n + 1) + i;
        let t = (0..n)
            .flat_map(|j| {
                (0..n).flat_map(move |i| {
                    [
                        [at(i, j), at(i + 1, j), at(i + 1, j + 1)],
                        [at(i, j), at(i + 1, j + 1), at(i, j + 1)],
                    ]
                })
            })
            .collect();
        TriMesh::new(p, t).unwrap()
    }

    #[test]
    fn figure_1_the_middle_triangle_goes() {
        // A triangle whose three neighbours come first: all its edges are covered.
        let p = vec![
            Point::new(0.0, 0.0, 0.0),
            Point::new(2.0, 0.0, 0.0),
            Point::new(1.0, 2.0, 0.0),
            Point::new(1.0, -1.0, 0.0),
            Point::new(2.5, 1.5, 0.0),
            Point::new(-0.5, 1.5, 0.0),
        ];
        let m = TriMesh::new(p, vec![[0, 3, 1], [1, 4, 2], [2, 5, 0], [0, 1, 2]]).unwrap();
        let d = dedup_edges(&m);
        assert_eq!(d.dropped().collect::<Vec<_>>(), vec![TriangleId(3)]);
        assert_edges_covered(&m, &d);
    }

    #[test]
    fn grid_keeps_every_edge_and_drops_a_good_share() {
        let m = grid(20);
        let d = dedup_edges(&m);
        assert_edges_covered(&m, &d);
        // Lower bound: each kept triangle covers at most 3 edges.
        let w = weld_positions(&m);
        let edges: HashSet<Edge> = m
            .indices()
            .iter()
            .flat_map(|t| triangle_edges(&w, t))
            .collect();
        assert!(d.kept_count() * 3 >= edges.len());
        assert!(d.reduction() > 0.25, "reduction {}", d.reduction());
    }

    #[test]
    fn welding_joins_split_vertices() {
        // Two triangles sharing an edge through duplicated vertices.
        let p = vec![
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, -0.0),
            Point::new(1.0, 1.0, 0.0),
        ];
        let m = TriMesh::new(p, vec![[0, 1, 2], [3, 5, 4]]).unwrap();
        let w = weld_positions(&m);
        assert_eq!(w[3], 1);
        assert_eq!(w[4], 2);
        let d = dedup_edges(&m);
        assert_eq!(d.kept_count(), 2, "each has an edge of its own");
        assert_edges_covered(&m, &d);
    }

    #[test]
    fn random_soups_stay_covered() {
        use proptest::prelude::*;
        proptest!(|(tris in prop::collection::vec(prop::array::uniform3(0u32..12), 1..60))| {
            let p = (0..12).map(|i| Point::new((i % 4) as f32, (i / 4) as f32, (i * i % 5) as f32)).collect();
            let m = TriMesh::new(p, tris).unwrap();
            let d = dedup_edges(&m);
            assert_edges_covered(&m, &d);
        });
    }
}
