//! The exact reference of ray queries: every skinned triangle of every
//! character, brute force, in `f64`, with exact predicates where the answer
//! is borderline.
//!
//! Each triangle is tested with the Möller–Trumbore formulas in `f64` (a
//! different formulation from the library's sheared, watertight test). Where
//! the barycentric coordinates or the determinant lie within a margin of
//! their decision thresholds — a ray through or beside an edge or a corner,
//! or grazing the plane — hit or miss is decided by Shewchuk's adaptive
//! `orient3d` on the segment from the origin to a far point of the ray:
//! the signs of the three edges seen along the ray, and the two ends'
//! sides of the triangle's plane. The distance is then the plane's.
//!
//! The first hit is the nearest; the triangles whose distance equals it to
//! within a billionth (a ray through a shared edge or corner meets all of
//! them there) are all first hits.

use cornertree::geometry::Point;
use cornertree::geometry::query_shapes::Ray;
use nalgebra::Vector3;

/// Margin on barycentric coordinates (and on the determinant, relatively)
/// inside which the exact predicates decide.
const BORDERLINE: f64 = 1e-9;

/// Relative difference of distances within which two hits are tied.
pub const TIE: f64 = 1e-9;

/// A body's triangles as the reference reads them.
#[derive(Clone, Copy)]
pub struct Mesh<'a> {
    /// Posed vertex positions.
    pub positions: &'a [Point],
    /// Triangles' corner indices.
    pub indices: &'a [[u32; 3]],
}

/// One triangle a ray meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReferenceHit {
    /// Index of the mesh among those given.
    pub mesh: usize,
    pub triangle: u32,
    pub distance: f64,
}

/// The first hits of a ray: the nearest, and every other triangle tied with it.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct FirstHits {
    /// Nearest first; empty: the ray meets nothing.
    pub tied: Vec<ReferenceHit>,
    /// Triangles decided by the exact predicates (borderline in `f64`).
    pub exact_decisions: u64,
}

impl FirstHits {
    /// The nearest hit.
    pub fn first(&self) -> Option<&ReferenceHit> {
        self.tied.first()
    }

    /// Whether `(mesh, triangle)` is a first hit.
    pub fn accepts(&self, mesh: usize, triangle: u32) -> bool {
        self.tied
            .iter()
            .any(|h| (h.mesh, h.triangle) == (mesh, triangle))
    }
}

/// Every triangle of `meshes` that `ray` meets, with its distance, by brute
/// force; `exact` counts the borderline decisions.
pub fn all_hits(ray: &Ray, meshes: &[Mesh<'_>], exact: &mut u64) -> Vec<ReferenceHit> {
    let mut out = Vec::new();
    for (m, mesh) in meshes.iter().enumerate() {
        for (t, tri) in mesh.indices.iter().enumerate() {
            let [a, b, c] = tri.map(|v| mesh.positions[v as usize]);
            if let Some(d) = ray_meets(ray, &a, &b, &c, exact) {
                out.push(ReferenceHit {
                    mesh: m,
                    triangle: t as u32,
                    distance: d,
                });
            }
        }
    }
    out
}

/// The first hits of `ray` among every triangle of `meshes`.
pub fn first_hits(ray: &Ray, meshes: &[Mesh<'_>]) -> FirstHits {
    let mut exact = 0;
    let mut hits = all_hits(ray, meshes, &mut exact);
    hits.sort_by(|x, y| x.distance.total_cmp(&y.distance));
    let tied = match hits.first() {
        Some(first) => {
            let limit = first.distance + TIE * first.distance.max(1.0);
            hits.into_iter()
                .take_while(|h| h.distance <= limit)
                .collect()
        }
        None => Vec::new(),
    };
    FirstHits {
        tied,
        exact_decisions: exact,
    }
}

/// The distance at which `ray` meets the closed triangle `a b c`, if it
/// does; a ray in the triangle's plane meets it nowhere (as the library's
/// test says).
pub fn ray_meets(ray: &Ray, a: &Point, b: &Point, c: &Point, exact: &mut u64) -> Option<f64> {
    let o = ray.origin.cast::<f64>();
    let d = ray.direction.cast::<f64>();
    let [a, b, c] = [a, b, c].map(|p| p.cast::<f64>());
    let (e1, e2) = (b - a, c - a);
    let p = d.cross(&e2);
    let det = e1.dot(&p);
    let scale = e1.norm() * e2.norm();
    let plane_distance = |n: &Vector3<f64>| {
        let dn = d.dot(n);
        (dn != 0.0).then(|| (a - o).dot(n) / dn)
    };
    let decided = if det.abs() > BORDERLINE * scale {
        let s = o - a;
        let u = s.dot(&p) / det;
        let q = s.cross(&e1);
        let v = d.dot(&q) / det;
        let t = e2.dot(&q) / det;
        let m = BORDERLINE;
        if u < -m || v < -m || u + v > 1.0 + m || t < -m * t.abs().max(1.0) {
            Some(None)
        } else if u > m && v > m && u + v < 1.0 - m && t > m * t.abs().max(1.0) {
            Some(Some(t))
        } else {
            None
        }
    } else {
        None
    };
    let t = match decided {
        Some(answer) => answer,
        None => {
            *exact += 1;
            if !exact_meets(&o, &d, &a, &b, &c) {
                return None;
            }
            plane_distance(&e1.cross(&e2))
        }
    }?;
    (t <= f64::from(ray.max_distance)).then_some(t.max(0.0))
}

/// Whether the segment from `o` to a far point along `d` meets the closed
/// triangle `a b c`, by exact orientation tests (a segment in the plane:
/// no).
fn exact_meets(
    o: &nalgebra::Point3<f64>,
    d: &Vector3<f64>,
    a: &nalgebra::Point3<f64>,
    b: &nalgebra::Point3<f64>,
    c: &nalgebra::Point3<f64>,
) -> bool {
    // Far enough to pass every triangle: a power of two past the farthest
    // corner, so `d·L` is exact.
    let reach = [a, b, c]
        .iter()
        .map(|p| (*p - o).norm())
        .fold(1.0f64, f64::max);
    let l = (2.0 * reach).log2().ceil().exp2();
    let far = o + d * l;
    let co = |p: &nalgebra::Point3<f64>| robust::Coord3D {
        x: p.x,
        y: p.y,
        z: p.z,
    };
    let (o3, f3, a3, b3, c3) = (co(o), co(&far), co(a), co(b), co(c));
    let s_o = robust::orient3d(a3, b3, c3, o3);
    let s_f = robust::orient3d(a3, b3, c3, f3);
    if (s_o > 0.0 && s_f > 0.0) || (s_o < 0.0 && s_f < 0.0) || (s_o == 0.0 && s_f == 0.0) {
        return false;
    }
    let e = [
        robust::orient3d(o3, f3, a3, b3),
        robust::orient3d(o3, f3, b3, c3),
        robust::orient3d(o3, f3, c3, a3),
    ];
    e.iter().all(|x| *x >= 0.0) || e.iter().all(|x| *x <= 0.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use cornertree::geometry::{Triangle, Vector};

    /// On clear cases both formulations agree with the library's test; on
    /// rays aimed exactly at shared corners and edges of a grid, the
    /// reference finds a hit and the exact predicates decided it.
    #[test]
    fn agrees_with_the_library_and_decides_edges_exactly() {
        let quad = [
            Point::new(0.0, 0.0, 0.0),
            Point::new(1.0, 0.0, 0.0),
            Point::new(1.0, 1.0, 0.0),
            Point::new(0.0, 1.0, 0.0),
        ];
        let indices = [[0u32, 1, 2], [0, 2, 3]];
        let mesh = Mesh {
            positions: &quad,
            indices: &indices,
        };
        // Straight down the shared diagonal and onto a corner.
        for (x, y) in [(0.5f32, 0.5f32), (0.25, 0.25), (0.0, 0.0), (1.0, 1.0)] {
            let r = Ray::new(Point::new(x, y, 2.0), Vector::new(0.0, 0.0, -1.0), 10.0).unwrap();
            let f = first_hits(&r, &[mesh]);
            assert!(f.exact_decisions > 0, "({x}, {y}) decided in f64");
            assert!(!f.tied.is_empty(), "({x}, {y}) missed");
            assert!((f.first().unwrap().distance - 2.0).abs() < 1e-12);
        }
        // Beside the quad: no hit, decided exactly.
        let r = Ray::new(
            Point::new(1.0, 0.5, 2.0),
            Vector::new(1e-3, 0.0, -1.0),
            10.0,
        )
        .unwrap();
        assert!(first_hits(&r, &[mesh]).tied.is_empty());
        // Random rays: the same answer as the library's kernel.
        use rand::{Rng, SeedableRng, rngs::SmallRng};
        let mut rng = SmallRng::seed_from_u64(9);
        let mut p = || {
            Point::new(
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
                rng.random_range(-1.0..1.0),
            )
        };
        let mut hits = 0;
        for _ in 0..20_000 {
            let (a, b, c) = (p(), p(), p());
            let o = p() * 3.0;
            let r = Ray::new(o, p() - o, f32::INFINITY).unwrap();
            let mut exact = 0;
            let ours = r.triangle_hit(&Triangle::new(a, b, c));
            let reference = ray_meets(&r, &a, &b, &c, &mut exact);
            if exact == 0 {
                assert_eq!(ours.is_some(), reference.is_some());
            }
            if let (Some(x), Some(y)) = (ours, reference) {
                hits += 1;
                assert!((x.distance - y).abs() <= 1e-9 * y.max(1.0));
            }
        }
        assert!(hits > 1000);
    }
}
