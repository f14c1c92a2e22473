//! A box 40 cm on a side around its origin, twelve triangles: the moving
//! object of the library's world tests (declared with `#[path]` by them).

use cornertree::geometry::Point;
use cornertree::mesh::TriMesh;

pub fn box_mesh() -> TriMesh {
    let p: Vec<Point> = (0..8)
        .map(|i| {
            let c = |bit: usize| if i & bit == 0 { -0.2 } else { 0.2 };
            Point::new(c(1), c(2), c(4))
        })
        .collect();
    let mut t = Vec::new();
    for [a, b, c, d] in [
        [0, 1, 3, 2],
        [4, 6, 7, 5],
        [0, 4, 5, 1],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 5, 7, 3],
    ] {
        t.push([a, b, c]);
        t.push([a, c, d]);
    }
    TriMesh::new(p, t).unwrap()
}
