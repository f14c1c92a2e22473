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
use cornertree::geometry::{Point, Real, Triangle};
use cornertree::mesh::{TriMesh, TriangleId};

/// Most triangles one object may be split into (`4^times` per triangle).
pub const MAX_SUBDIVIDED_TRIANGLES: usize = 4_000_000;

/// Why an object cannot be re-tessellated.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum SubdivideError {
    #[error("no object named {name:?} in {room}")]
    NoSuchObject { name: String, room: String },
    #[error(
        "splitting {name} ({triangles} triangles) {times} times would make more than {max} triangles",
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
        if self.object(name).is_none() {
            return Err(SubdivideError::NoSuchObject {
                name: name.to_owned(),
                room: self.name.clone(),
            });
        }
        self.subdivide_where(|o, _| if o.name == name { times } else { 0 }, name)
            .map(|mut env| {
                env.name = format!("{} ({name} split {times}x)", self.name);
                env
            })
    }

    /// This room with every triangle whose longest edge exceeds `threshold`
    /// (the big triangles of §4) split four-way until its longest edge is at
    /// most `piece` metres (`piece > 0`); a split triangle's neighbours keep
    /// their edges (the surface is the same, the indexing has T-junctions
    /// there).
    pub fn subdivide_big(
        &self,
        threshold: Real,
        piece: Real,
    ) -> Result<Environment, SubdivideError> {
        let times = |t: &Triangle| {
            let mut k = 0;
            let mut edge = t.longest_edge();
            while edge > threshold && edge > piece && k < 32 {
                edge *= 0.5;
                k += 1;
            }
            k
        };
        self.subdivide_where(|_, t| times(t), "big triangles")
            .map(|mut env| {
                env.name = format!("{} (big triangles split to {piece} m)", self.name);
                env
            })
    }

    /// Splits each triangle the number of times `times_of` gives (0: kept),
    /// object by object.
    fn subdivide_where(
        &self,
        times_of: impl Fn(&EnvObject, &Triangle) -> u32,
        what: &str,
    ) -> Result<Environment, SubdivideError> {
        let (pos, idx) = (self.mesh.positions(), self.mesh.indices());
        let mut times = vec![0u32; idx.len()];
        for o in &self.objects {
            for t in o.triangles.clone() {
                times[t as usize] = times_of(o, &self.mesh.triangle(TriangleId(t)));
            }
        }
        let grown = times
            .iter()
            .filter(|&&k| k > 0)
            .try_fold(0usize, |n, &k| {
                4usize.checked_pow(k).and_then(|f| n.checked_add(f))
            })
            .filter(|&n| n <= MAX_SUBDIVIDED_TRIANGLES);
        if grown.is_none() {
            return Err(SubdivideError::TooMany {
                name: what.to_owned(),
                triangles: times.iter().filter(|&&k| k > 0).count(),
                times: times.iter().copied().max().unwrap_or(0),
            });
        }
        let mut positions: Vec<Point> = Vec::with_capacity(pos.len());
        let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(idx.len());
        let mut objects = Vec::with_capacity(self.objects.len());
        for o in &self.objects {
            let v0 = positions.len() as u32;
            let t0 = triangles.len() as u32;
            let shift = |i: u32| i - o.vertices.start + v0;
            positions.extend_from_slice(&pos[o.vertices.start as usize..o.vertices.end as usize]);
            // Pieces still to split, with how many more times.
            let mut pending: Vec<([u32; 3], u32)> = Vec::new();
            for t in o.triangles.clone() {
                let tri = idx[t as usize].map(shift);
                match times[t as usize] {
                    0 => triangles.push(tri),
                    k => pending.push((tri, k)),
                }
            }
            let mut midpoints = HashMap::new();
            while !pending.is_empty() {
                let mut next = Vec::with_capacity(4 * pending.len());
                for (tri, k) in pending {
                    for piece in split_once(&mut positions, &mut midpoints, tri) {
                        if k > 1 {
                            next.push((piece, k - 1));
                        } else {
                            triangles.push(piece);
                        }
                    }
                }
                pending = next;
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
            name: self.name.clone(),
            mesh,
            objects,
        })
    }
}

/// One four-way midpoint split of `tri`; midpoints are made once per edge
/// (`midpoints`, keyed by the edge's vertex pair) and appended to `positions`.
fn split_once(
    positions: &mut Vec<Point>,
    midpoints: &mut HashMap<(u32, u32), u32>,
    [a, b, c]: [u32; 3],
) -> [[u32; 3]; 4] {
    let mut mid = |a: u32, b: u32| -> u32 {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            let (p, q) = (positions[a as usize], positions[b as usize]);
            positions.push(nalgebra::center(&p, &q));
            (positions.len() - 1) as u32
        })
    };
    let (ab, bc, ca) = (mid(a, b), mid(b, c), mid(c, a));
    [[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]
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
                .map(|t| env.mesh.triangle(cornertree::mesh::TriangleId(t)).area() as f64)
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
                        room.mesh
                            .triangle(cornertree::mesh::TriangleId(ta))
                            .vertices(),
                        split
                            .mesh
                            .triangle(cornertree::mesh::TriangleId(tb))
                            .vertices()
                    );
                }
            }
        }
    }

    #[test]
    fn big_triangles_split_and_small_ones_kept() {
        let room = museum(0);
        let threshold = 0.15;
        let big = crate::environment::big_triangles(&room.mesh, threshold).len();
        let split = room.subdivide_big(threshold, 1.0).unwrap();
        assert!(split.mesh.triangle_count() > room.mesh.triangle_count() + 3 * big);
        // Every piece of a big triangle is at most 1 m; small triangles are
        // kept as they were (so none is longer than the threshold or 1 m).
        let longest = split
            .mesh
            .iter_triangles()
            .map(|(_, t)| t.longest_edge())
            .fold(0.0f32, f32::max);
        assert!(longest <= 1.0, "{longest}");
    }

    #[test]
    fn refuses_unknown_objects_and_huge_splits() {
        let room = museum(0);
        assert!(room.subdivide_object("no such wall", 1).is_err());
        assert!(room.subdivide_object("south wall", 40).is_err());
    }
}
