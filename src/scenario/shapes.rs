//! Meshes of the generated rigid objects a scenario can put in a world
//! (`[[objects]] kind`), each in its own frame.

use cornertree::geometry::Point;
use cornertree::mesh::TriMesh;

/// A box of full extents `size`, centred on the origin (12 triangles).
pub fn box_mesh(size: [f32; 3]) -> TriMesh {
    let [hx, hy, hz] = size.map(|s| 0.5 * s);
    slab(-hx, hx, -hy, hy, -hz, hz)
}

/// A door leaf: width along +X from its hinge edge on the Y axis, height
/// along +Y from 0, thickness centred on z = 0 (12 triangles).
pub fn door_mesh(size: [f32; 3]) -> TriMesh {
    let [w, h, t] = size;
    slab(0.0, w, 0.0, h, -0.5 * t, 0.5 * t)
}

/// A thin rectangle in the plane z = 0, `size[0]` wide (X, centred) and
/// `size[1]` high (Y from 0): two triangles, both big at any useful size.
pub fn panel_mesh(size: [f32; 2]) -> TriMesh {
    let [w, h] = size;
    let hw = 0.5 * w;
    let positions = vec![
        Point::new(-hw, 0.0, 0.0),
        Point::new(hw, 0.0, 0.0),
        Point::new(hw, h, 0.0),
        Point::new(-hw, h, 0.0),
    ];
    TriMesh::new(positions, vec![[0, 1, 2], [0, 2, 3]]).expect("a valid rectangle")
}

/// A sphere of `radius` centred on the origin: an icosahedron split
/// `subdivisions` times (20·4ⁿ triangles), vertices pushed onto the sphere.
pub fn ball_mesh(radius: f32, subdivisions: u32) -> TriMesh {
    let g = (1.0 + 5f32.sqrt()) / 2.0;
    let mut v: Vec<[f32; 3]> = vec![
        [-1.0, g, 0.0],
        [1.0, g, 0.0],
        [-1.0, -g, 0.0],
        [1.0, -g, 0.0],
        [0.0, -1.0, g],
        [0.0, 1.0, g],
        [0.0, -1.0, -g],
        [0.0, 1.0, -g],
        [g, 0.0, -1.0],
        [g, 0.0, 1.0],
        [-g, 0.0, -1.0],
        [-g, 0.0, 1.0],
    ];
    let mut t: Vec<[u32; 3]> = vec![
        [0, 11, 5],
        [0, 5, 1],
        [0, 1, 7],
        [0, 7, 10],
        [0, 10, 11],
        [1, 5, 9],
        [5, 11, 4],
        [11, 10, 2],
        [10, 7, 6],
        [7, 1, 8],
        [3, 9, 4],
        [3, 4, 2],
        [3, 2, 6],
        [3, 6, 8],
        [3, 8, 9],
        [4, 9, 5],
        [2, 4, 11],
        [6, 2, 10],
        [8, 6, 7],
        [9, 8, 1],
    ];
    for _ in 0..subdivisions {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::with_capacity(t.len() * 4);
        let mut midpoint = |a: u32, b: u32, v: &mut Vec<[f32; 3]>| -> u32 {
            *mid.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let (p, q) = (v[a as usize], v[b as usize]);
                v.push([0, 1, 2].map(|i| 0.5 * (p[i] + q[i])));
                (v.len() - 1) as u32
            })
        };
        for &[a, b, c] in &t {
            let ab = midpoint(a, b, &mut v);
            let bc = midpoint(b, c, &mut v);
            let ca = midpoint(c, a, &mut v);
            next.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        t = next;
    }
    let positions = v
        .iter()
        .map(|p| {
            let n = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
            Point::new(p[0] / n * radius, p[1] / n * radius, p[2] / n * radius)
        })
        .collect();
    TriMesh::new(positions, t).expect("a valid icosphere")
}

/// The axis-aligned box `[x0, x1] × [y0, y1] × [z0, z1]`, faces outward.
fn slab(x0: f32, x1: f32, y0: f32, y1: f32, z0: f32, z1: f32) -> TriMesh {
    let positions: Vec<Point> = (0..8)
        .map(|i| {
            Point::new(
                if i & 1 == 0 { x0 } else { x1 },
                if i & 2 == 0 { y0 } else { y1 },
                if i & 4 == 0 { z0 } else { z1 },
            )
        })
        .collect();
    let quads = [
        [0, 2, 3, 1], // z0
        [4, 5, 7, 6], // z1
        [0, 1, 5, 4], // y0
        [2, 6, 7, 3], // y1
        [0, 4, 6, 2], // x0
        [1, 3, 7, 5], // x1
    ];
    let triangles = quads
        .iter()
        .flat_map(|&[a, b, c, d]| [[a, b, c], [a, c, d]])
        .collect();
    TriMesh::new(positions, triangles).expect("a valid box")
}
