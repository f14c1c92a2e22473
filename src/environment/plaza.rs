//! A plaza: an open floor for crowds, sized to them (`kind = "plaza"`).
//!
//! The floor spans `x ∈ [0, W]`, `z ∈ [0, D]` at `y = 0`, cut into square
//! cells of at most [`CELL`] metres, two triangles each: every triangle is
//! bigger than a character (the paper's big triangles, §4), so the floor is
//! one big-triangle hierarchy however large the crowd. Nothing else stands
//! on it: what a crowd on a plaza costs is the crowd.

use cornertree::mesh::TriMesh;

use super::{EnvObject, Environment, ObjectKind};
use cornertree::geometry::Point;

/// Longest side of a floor cell, metres.
pub const CELL: f32 = 4.0;

/// The largest plaza side accepted, metres (a crowd of a million at 1 m
/// spacing fits in 1 km).
pub const MAX_SIDE: f32 = 10_000.0;

/// A `width` × `depth` metre floor (each side positive and at most
/// [`MAX_SIDE`]; the caller checks).
pub fn plaza(width: f32, depth: f32) -> Environment {
    let nx = (width / CELL).ceil().max(1.0) as u32;
    let nz = (depth / CELL).ceil().max(1.0) as u32;
    let mut positions = Vec::with_capacity(((nx + 1) * (nz + 1)) as usize);
    for k in 0..=nz {
        for i in 0..=nx {
            positions.push(Point::new(
                width * i as f32 / nx as f32,
                0.0,
                depth * k as f32 / nz as f32,
            ));
        }
    }
    let at = |i: u32, k: u32| k * (nx + 1) + i;
    let mut triangles = Vec::with_capacity((2 * nx * nz) as usize);
    for k in 0..nz {
        for i in 0..nx {
            // Counter-clockwise seen from above (+y).
            let (a, b, c, d) = (at(i, k), at(i + 1, k), at(i + 1, k + 1), at(i, k + 1));
            triangles.push([a, c, b]);
            triangles.push([a, d, c]);
        }
    }
    let (v, t) = (positions.len() as u32, triangles.len() as u32);
    let mesh = TriMesh::new(positions, triangles).expect("a plaza has finite cells");
    Environment {
        name: "plaza".into(),
        mesh,
        objects: vec![EnvObject {
            name: "floor".into(),
            kind: ObjectKind::Floor,
            vertices: 0..v,
            triangles: 0..t,
            motion: None,
        }],
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_floor_of_big_upward_cells_covering_the_plaza() {
        let p = plaza(10.0, 3.0);
        let m = &p.mesh;
        // 3 × 1 cells of 3.33 m × 3 m.
        assert_eq!(m.triangle_count(), 6);
        let mut area = 0.0;
        for t in m.indices() {
            let [a, b, c] = t.map(|i| m.positions()[i as usize]);
            let n = (b - a).cross(&(c - a));
            assert!(n.y > 0.0, "faces up");
            area += n.norm() / 2.0;
            for q in [a, b, c] {
                assert_eq!(q.y, 0.0);
                assert!((0.0..=10.0).contains(&q.x) && (0.0..=3.0).contains(&q.z));
            }
        }
        assert!((area - 30.0).abs() < 1e-4, "{area}");
    }
}
