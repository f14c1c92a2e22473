//! An indexed triangle mesh.

use crate::geometry::{Point, Triangle};

/// Index of a triangle in its mesh, the one used in every report and recording.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct TriangleId(pub u32);

impl TriangleId {
    /// The id as an index into the mesh's triangle list.
    #[inline]
    pub fn index(self) -> usize {
        self.0 as usize
    }
}

/// Why a set of positions and indices is not a usable mesh.
#[derive(Clone, Debug, thiserror::Error, PartialEq)]
pub enum MeshError {
    /// The triangle list is empty.
    #[error("mesh has no triangles")]
    NoTriangles,
    /// A vertex position has a NaN or infinite coordinate.
    #[error("vertex {vertex} has a non-finite position ({x}, {y}, {z})")]
    NonFinitePosition {
        /// Index of the offending vertex.
        vertex: usize,
        /// Its x coordinate.
        x: f32,
        /// Its y coordinate.
        y: f32,
        /// Its z coordinate.
        z: f32,
    },
    /// A triangle names a vertex past the end of the positions.
    #[error(
        "triangle {triangle} refers to vertex {index}, but there are only {vertex_count} vertices"
    )]
    IndexOutOfRange {
        /// Index of the offending triangle.
        triangle: usize,
        /// The vertex index it names.
        index: u32,
        /// How many positions there are.
        vertex_count: usize,
    },
    /// More triangles than a [`TriangleId`] can number (the count is given).
    #[error("mesh has {0} triangles; at most 2^32 - 1 are supported")]
    TooManyTriangles(usize),
}

/// Positions plus index triples. Every index is in range and every position
/// finite (checked by [`TriMesh::new`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriMesh {
    positions: Vec<Point>,
    triangles: Vec<[u32; 3]>,
}

impl TriMesh {
    /// Checks indices and positions; an empty triangle list is an error.
    pub fn new(positions: Vec<Point>, triangles: Vec<[u32; 3]>) -> Result<Self, MeshError> {
        if triangles.is_empty() {
            return Err(MeshError::NoTriangles);
        }
        if triangles.len() >= u32::MAX as usize {
            return Err(MeshError::TooManyTriangles(triangles.len()));
        }
        if let Some((vertex, p)) = positions
            .iter()
            .enumerate()
            .find(|(_, p)| !p.iter().all(|c| c.is_finite()))
        {
            return Err(MeshError::NonFinitePosition {
                vertex,
                x: p.x,
                y: p.y,
                z: p.z,
            });
        }
        for (triangle, tri) in triangles.iter().enumerate() {
            if let Some(&index) = tri.iter().find(|&&i| i as usize >= positions.len()) {
                return Err(MeshError::IndexOutOfRange {
                    triangle,
                    index,
                    vertex_count: positions.len(),
                });
            }
        }
        Ok(Self {
            positions,
            triangles,
        })
    }

    /// Vertex positions, indexed by the entries of [`TriMesh::indices`].
    pub fn positions(&self) -> &[Point] {
        &self.positions
    }

    /// Mutable positions, for posing a character in place (indices never change).
    pub fn positions_mut(&mut self) -> &mut [Point] {
        &mut self.positions
    }

    /// The three vertex indices of every triangle, indexed by [`TriangleId`].
    pub fn indices(&self) -> &[[u32; 3]] {
        &self.triangles
    }

    /// Number of vertices (positions), used by a triangle or not.
    pub fn vertex_count(&self) -> usize {
        self.positions.len()
    }

    /// Number of triangles.
    pub fn triangle_count(&self) -> usize {
        self.triangles.len()
    }

    /// The corners of triangle `id`.
    #[inline]
    pub fn triangle(&self, id: TriangleId) -> Triangle {
        let [a, b, c] = self.triangles[id.index()];
        Triangle::new(
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        )
    }

    /// Every triangle with its id.
    pub fn iter_triangles(&self) -> impl Iterator<Item = (TriangleId, Triangle)> + '_ {
        (0..self.triangles.len() as u32).map(|i| (TriangleId(i), self.triangle(TriangleId(i))))
    }

    /// Axis-aligned extent `(min, max)` of the vertices used by triangles.
    pub fn bounds(&self) -> (Point, Point) {
        let mut min = Point::new(f32::INFINITY, f32::INFINITY, f32::INFINITY);
        let mut max = Point::new(f32::NEG_INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY);
        for tri in &self.triangles {
            for &i in tri {
                let p = self.positions[i as usize];
                min = min.inf(&p);
                max = max.sup(&p);
            }
        }
        (min, max)
    }

    /// Length of the bounding-box diagonal: the "model size" tolerances scale with.
    pub fn size(&self) -> f32 {
        let (min, max) = self.bounds();
        (max - min).norm()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rejects_bad_input() {
        let p = vec![
            Point::origin(),
            Point::new(1.0, 0.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
        ];
        assert_eq!(TriMesh::new(p.clone(), vec![]), Err(MeshError::NoTriangles));
        assert_eq!(
            TriMesh::new(p.clone(), vec![[0, 1, 3]]),
            Err(MeshError::IndexOutOfRange {
                triangle: 0,
                index: 3,
                vertex_count: 3
            })
        );
        let mut q = p.clone();
        q[1].y = f32::NAN;
        assert!(matches!(
            TriMesh::new(q, vec![[0, 1, 2]]),
            Err(MeshError::NonFinitePosition { vertex: 1, .. })
        ));
        let m = TriMesh::new(p, vec![[0, 1, 2]]).unwrap();
        assert_eq!(m.triangle(TriangleId(0)).area(), 0.5);
    }
}
