//! Generated test meshes shared by integration tests.
#![allow(dead_code)]

use cornertree::geometry::Point;
use cornertree::mesh::TriMesh;
use rand::{Rng, SeedableRng, rngs::SmallRng};

/// `n` random triangles of size about `size` inside a cube of side `extent`.
pub fn soup(seed: u64, n: usize, extent: f32, size: f32) -> TriMesh {
    let mut rng = SmallRng::seed_from_u64(seed);
    let mut p = Vec::with_capacity(3 * n);
    for _ in 0..n {
        let c = Point::new(
            rng.random_range(0.0..extent),
            rng.random_range(0.0..extent),
            rng.random_range(0.0..extent),
        );
        for _ in 0..3 {
            p.push(c + nalgebra::Vector3::new(
                rng.random_range(-size..size),
                rng.random_range(-size..size),
                rng.random_range(-size..size),
            ));
        }
    }
    let t = (0..n as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]).collect();
    TriMesh::new(p, t).unwrap()
}

/// A closed UV sphere of radius `r` around `c` with `rings`×`segments` quads
/// (shared vertices, poles included).
pub fn uv_sphere(c: Point, r: f32, rings: u32, segments: u32) -> TriMesh {
    let mut p = vec![c + nalgebra::Vector3::new(0.0, 0.0, r)];
    for i in 1..rings {
        let th = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..segments {
            let ph = 2.0 * std::f32::consts::PI * j as f32 / segments as f32;
            p.push(c + r * nalgebra::Vector3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()));
        }
    }
    p.push(c + nalgebra::Vector3::new(0.0, 0.0, -r));
    let south = p.len() as u32 - 1;
    let at = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
    let mut t = Vec::new();
    for j in 0..segments {
        t.push([0, at(1, j), at(1, j + 1)]);
        t.push([south, at(rings - 1, j + 1), at(rings - 1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            t.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            t.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    TriMesh::new(p, t).unwrap()
}
