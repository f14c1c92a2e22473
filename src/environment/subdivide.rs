//! Re-tessellating one object of a room: every triangle split into four at
//! its edge midpoints, `times` times (`4^times` triangles each).
//!
//! This changes the *model*, which §5 says is not always possible ("it is not
//! always possible to manipulate the model received"); it exists for the
//! experiment of docs/results.md that asks how the plane-sphere method's cost
//! depends on how a big wall is tessellated (two triangles against many).
//! Midpoints shared by two triangles of the object are made once, so the
//! re-tessellated object stays watertight where it was.

use std::collections::HashMap;

use super::{EnvObject, Environment};
use crate::geometry::Point;
use crate::mesh::TriMesh;

/// Most triangles one object may be split into (`4^times` per triangle).
pub const MAX_SUBDIVIDED_TRIANGLES: usize = 4_000_000;

/// Why an object cannot be re-tessellated.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SubdivideError {
    #[error("no object named {name:?} in {room}")]
    NoSuchObject { name: String, room: String },
    #[error(
        "splitting {name:?} ({triangles} triangles) {times} times would make more than {max} triangles",
        max = MAX_SUBDIVIDED_TRIANGLES
    )]
    TooMany {
        name: String,
        triangles: usize,
        times: u32,
    },
}

impl Environment {
    /// This room with object `name`'s triangles each split into four at the
    /// edge midpoints, `times` times. Objects keep their order, names, kinds
    /// and motions; vertex and triangle ranges are renumbered.
    pub fn subdivide_object(&self, name: &str, times: u32) -> Result<Environment, SubdivideError> {
        let Some(target) = self.objects.iter().position(|o| o.name == name) else {
            return Err(SubdivideError::NoSuchObject {
                name: name.to_owned(),
                room: self.name.clone(),
            });
        };
        let count = self.objects[target].triangles.len();
        let grown = 4usize
            .checked_pow(times)
            .and_then(|f| f.checked_mul(count))
            .filter(|&n| n <= MAX_SUBDIVIDED_TRIANGLES);
        if grown.is_none() {
            return Err(SubdivideError::TooMany {
                name: name.to_owned(),
                triangles: count,
                times,
            });
        }
        let (pos, idx) = (self.mesh.positions(), self.mesh.indices());
        let mut positions: Vec<Point> = Vec::with_capacity(pos.len());
        let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(idx.len());
        let mut objects = Vec::with_capacity(self.objects.len());
        for (k, o) in self.objects.iter().enumerate() {
            let v0 = positions.len() as u32;
            let t0 = triangles.len() as u32;
            let shift = |i: u32| i - o.vertices.start + v0;
            positions.extend_from_slice(&pos[o.vertices.start as usize..o.vertices.end as usize]);
            let own = idx[o.triangles.start as usize..o.triangles.end as usize]
                .iter()
                .map(|t| t.map(shift));
            if k == target {
                let mut tris: Vec<[u32; 3]> = own.collect();
                for _ in 0..times {
                    tris = split_once(&mut positions, &tris);
                }
                triangles.extend(tris);
            } else {
                triangles.extend(own);
            }
            objects.push(EnvObject {
                vertices: v0..positions.len() as u32,
                triangles: t0..triangles.len() as u32,
                ..o.clone()
            });
        }
        let mesh = TriMesh::new(positions, triangles)
            .expect("splitting a valid mesh keeps indices in range and positions finite");
        Ok(Environment {
            name: format!("{} ({name} split {times}x)", self.name),
            mesh,
            objects,
        })
    }
}

/// One four-way midpoint split of `tris`, new midpoints appended to `positions`.
fn split_once(positions: &mut Vec<Point>, tris: &[[u32; 3]]) -> Vec<[u32; 3]> {
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut mid = |a: u32, b: u32, positions: &mut Vec<Point>| -> u32 {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let (p, q) = (positions[a as usize], positions[b as usize]);
            positions.push(nalgebra::center(&p, &q));
            (positions.len() - 1) as u32
        })
    };
    let mut out = Vec::with_capacity(4 * tris.len());
    for &[a, b, c] in tris {
        let ab = mid(a, b, positions);
        let bc = mid(b, c, positions);
        let ca = mid(c, a, positions);
        out.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
    }
    out
}

#[cfg(test)]
mod tests {
    use crate::environment::museum;

    #[test]
    fn splits_only_the_named_object_and_keeps_its_area() {
        let room = museum(0);
        let wall = room.object("south wall").unwrap().clone();
        let split = room.subdivide_object("south wall", 3).unwrap();
        let new_wall = split.object("south wall").unwrap();
        assert_eq!(new_wall.triangles.len(), 64 * wall.triangles.len());
        assert_eq!(
            split.mesh.triangle_count(),
            room.mesh.triangle_count() + 63 * wall.triangles.len()
        );
        let area = |env: &crate::environment::Environment, o: &crate::environment::EnvObject| {
            o.triangles
                .clone()
                .map(|t| env.mesh.triangle(crate::mesh::TriangleId(t)).area() as f64)
                .sum::<f64>()
        };
        assert!((area(&room, &wall) - area(&split, new_wall)).abs() < 1e-3);
        // Every other object is the same triangles, renumbered.
        for (a, b) in room.objects.iter().zip(&split.objects) {
            assert_eq!(a.name, b.name);
            if a.name != "south wall" {
                assert_eq!(a.triangles.len(), b.triangles.len());
                for (ta, tb) in a.triangles.clone().zip(b.triangles.clone()) {
                    assert_eq!(
                        room.mesh.triangle(crate::mesh::TriangleId(ta)).vertices(),
                        split.mesh.triangle(crate::mesh::TriangleId(tb)).vertices()
                    );
                }
            }
        }
    }

    #[test]
    fn refuses_unknown_objects_and_huge_splits() {
        let room = museum(0);
        assert!(room.subdivide_object("no such wall", 1).is_err());
        assert!(room.subdivide_object("south wall", 40).is_err());
    }
}
