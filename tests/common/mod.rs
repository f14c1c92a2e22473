//! Generated test meshes shared by integration tests.
#![allow(dead_code)]

pub mod glb;
pub mod gltf_builder;
pub mod rrd;

use std::path::PathBuf;

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
            p.push(
                c + nalgebra::Vector3::new(
                    rng.random_range(-size..size),
                    rng.random_range(-size..size),
                    rng.random_range(-size..size),
                ),
            );
        }
    }
    let t = (0..n as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
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
            p.push(
                c + r * nalgebra::Vector3::new(th.sin() * ph.cos(), th.sin() * ph.sin(), th.cos()),
            );
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

use cornertree::character::{Character, Influences, Joint, JointId, Skeleton, Trs};
use nalgebra::{Matrix4, UnitQuaternion, Vector3};

/// A random character: a joint tree of `joints` joints (each joint's parent is
/// an earlier joint), a soup of `triangles` small triangles scattered along the
/// bones, and 1 to 4 random influences per vertex drawn near the owning joint.
pub fn random_character(seed: u64, joints: usize, triangles: usize) -> Character {
    let mut rng = SmallRng::seed_from_u64(seed);
    let mut js: Vec<Joint> = Vec::new();
    let mut world: Vec<Matrix4<f32>> = Vec::new();
    for i in 0..joints {
        let parent = if i == 0 {
            None
        } else {
            Some(JointId(rng.random_range(0..i) as u16))
        };
        let rest = Trs {
            translation: Vector3::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(0.2..1.0),
                rng.random_range(-1.0..1.0),
            ),
            rotation: UnitQuaternion::from_euler_angles(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            ),
            scale: Vector3::new(1.0, 1.0, 1.0),
        };
        let w = match parent {
            Some(p) => world[p.index()] * rest.to_matrix(),
            None => rest.to_matrix(),
        };
        world.push(w);
        js.push(Joint {
            name: format!("j{i}"),
            parent,
            rest,
            inverse_bind: w.try_inverse().unwrap(),
        });
    }
    let skeleton = Skeleton::new(js, Matrix4::identity()).unwrap();
    let mut p = Vec::new();
    let mut infl_j = Vec::new();
    let mut infl_w = Vec::new();
    for _ in 0..triangles {
        let j = rng.random_range(0..joints);
        let origin = world[j].transform_point(&Point::origin());
        let c = origin
            + Vector3::new(
                rng.random_range(-0.3..0.3),
                rng.random_range(-0.3..0.3),
                rng.random_range(-0.3..0.3),
            );
        for _ in 0..3 {
            p.push(
                c + Vector3::new(
                    rng.random_range(-0.05..0.05),
                    rng.random_range(-0.05..0.05),
                    rng.random_range(-0.05..0.05),
                ),
            );
            let k = rng.random_range(1..=4usize);
            let mut jj = [0u16; 4];
            let mut ww = [0.0f32; 4];
            for m in 0..k {
                // Mostly the owning joint, its parent or a random joint.
                jj[m] = match rng.random_range(0..3) {
                    0 => j as u16,
                    1 => skeleton.parent(JointId(j as u16)).map_or(j as u16, |x| x.0),
                    _ => rng.random_range(0..joints) as u16,
                };
                ww[m] = rng.random_range(0.05..1.0);
            }
            infl_j.push(jj);
            infl_w.push(ww);
        }
    }
    let t = (0..triangles as u32)
        .map(|i| [3 * i, 3 * i + 1, 3 * i + 2])
        .collect();
    let mesh = TriMesh::new(p, t).unwrap();
    let influences = Influences::new(infl_j, infl_w, joints).unwrap();
    Character::new(format!("random-{seed}"), skeleton, mesh, influences, vec![])
}

/// A random pose: every joint rotated, translated and uniformly scaled.
pub fn random_pose(seed: u64, skeleton: &Skeleton, max_scale: f32) -> Vec<Trs> {
    let mut rng = SmallRng::seed_from_u64(seed);
    skeleton
        .rest_pose()
        .into_iter()
        .map(|r| {
            let s = if max_scale > 1.0 {
                rng.random_range(1.0 / max_scale..max_scale)
            } else {
                1.0
            };
            Trs {
                translation: r.translation
                    + Vector3::new(
                        rng.random_range(-0.3..0.3),
                        rng.random_range(-0.3..0.3),
                        rng.random_range(-0.3..0.3),
                    ),
                rotation: r.rotation
                    * UnitQuaternion::from_euler_angles(
                        rng.random_range(-2.0..2.0),
                        rng.random_range(-2.0..2.0),
                        rng.random_range(-2.0..2.0),
                    ),
                scale: Vector3::new(s, s, s),
            }
        })
        .collect()
}

/// A random pose with non-uniform scales: every joint rotated, translated and
/// scaled by a factor in `[1/max_scale, max_scale]` per axis (so skin matrices
/// shear through the hierarchy).
pub fn random_pose_nonuniform(seed: u64, skeleton: &Skeleton, max_scale: f32) -> Vec<Trs> {
    let mut rng = SmallRng::seed_from_u64(seed);
    let uniform = random_pose(rng.random(), skeleton, 1.0);
    uniform
        .into_iter()
        .map(|t| Trs {
            scale: Vector3::new(
                rng.random_range(1.0 / max_scale..max_scale),
                rng.random_range(1.0 / max_scale..max_scale),
                rng.random_range(1.0 / max_scale..max_scale),
            ),
            ..t
        })
        .collect()
}

/// Independent containment reference: every leaf's triangle against the leaf
/// and all its ancestors (vertices counted once per triangle and node).
/// Returns (violations, worst excess).
pub fn ancestor_walk_violations(
    tree: &cornertree::sphere_tree::SphereTree,
    spheres: &[cornertree::geometry::Sphere],
    positions: &[Point],
    indices: &[[u32; 3]],
    tolerance: f64,
) -> (u64, f64) {
    let parents = tree.parents();
    let (mut violations, mut worst) = (0u64, 0.0f64);
    for (i, n) in tree.nodes().iter().enumerate() {
        let Some(t) = n.primitive() else { continue };
        let mut a = i;
        loop {
            let s = spheres[a];
            for &v in &indices[t as usize] {
                let p = positions[v as usize];
                let d = ((p.x as f64 - s.center.x as f64).powi(2)
                    + (p.y as f64 - s.center.y as f64).powi(2)
                    + (p.z as f64 - s.center.z as f64).powi(2))
                .sqrt()
                    - s.radius as f64;
                worst = worst.max(d);
                violations += (d > tolerance) as u64;
            }
            if a == 0 {
                break;
            }
            a = parents[a] as usize;
        }
    }
    (violations, worst)
}

/// A fresh directory under the system temp dir, removed on drop.
pub struct Scratch(pub PathBuf);

impl Scratch {
    pub fn new(test: &str) -> Self {
        let dir = std::env::temp_dir().join(format!("cornertree-{}-{test}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).expect("create temp dir");
        Self(dir)
    }

    pub fn dir(&self) -> &std::path::Path {
        &self.0
    }

    pub fn path(&self, name: &str) -> PathBuf {
        self.0.join(name)
    }

    pub fn write(&self, name: &str, contents: impl AsRef<[u8]>) -> PathBuf {
        let path = self.0.join(name);
        std::fs::write(&path, contents).expect("write temp file");
        path
    }
}

impl Drop for Scratch {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// Standard base64 with padding, for `data:` URIs in hand-built glTF files.
pub fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut out = String::new();
    for chunk in bytes.chunks(3) {
        let b = [
            chunk[0],
            *chunk.get(1).unwrap_or(&0),
            *chunk.get(2).unwrap_or(&0),
        ];
        let n = (u32::from(b[0]) << 16) | (u32::from(b[1]) << 8) | u32::from(b[2]);
        for k in 0..4 {
            if k <= chunk.len() {
                out.push(ALPHABET[(n >> (18 - 6 * k) & 63) as usize] as char);
            } else {
                out.push('=');
            }
        }
    }
    out
}
