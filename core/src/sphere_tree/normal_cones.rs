//! Normal cones of a tree's nodes in one pose: for each node, a direction
//! and a half-angle bounding the angle between it and every one of the
//! node's triangle normals (after Volino & Magnenat-Thalmann 1994; the
//! paper does not treat self-collision).
//!
//! A node's direction is its triangles' summed area-weighted normal; its
//! half-angle is the largest, over its children, of the angle from it to a
//! child's direction plus that child's half-angle (the triangle inequality
//! on the sphere of directions). Angles are kept as cosine and sine, so a
//! node costs a few products and one square root per child, no
//! trigonometry. Rounding is covered by margins: a triangle whose normal
//! direction is not resolved by `f64` arithmetic on its corners has the
//! whole sphere of directions, and a cone counts as facing a direction only
//! with [`FACING_MARGIN`] to spare.

use nalgebra::Vector3;

use crate::geometry::Triangle;

use super::node::{NodeId, SphereTree};

/// Radians a cone must stay inside a half-space by to count as facing it:
/// far above the rounding of the few operations per tree level.
pub const FACING_MARGIN: f64 = 1e-6;

/// A triangle whose normal's length is below this share of the product of
/// two of its edges' lengths (the sine of its angle there) gets no
/// direction: its computed normal's direction could be off by more than
/// the cones' margin.
const LEAST_SINE: f64 = 1e-6;

/// Half-angle (its sine) given a resolved triangle's cone: bounds the
/// direction error of its normal computed in `f64` from `f32` corners
/// (about `1e-16 / LEAST_SINE`).
const TRIANGLE_SLACK: f64 = 1e-8;

/// A cone of directions: every normal it bounds is within the half-angle
/// whose cosine and sine are `cos`, `sin` of `axis` (unit), or anything when
/// [`NormalCone::is_everything`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NormalCone {
    /// The cone's direction (unit), zero when it holds every direction.
    pub axis: Vector3<f64>,
    /// The length of the area-weighted normal sum the axis came from.
    pub weight: f64,
    /// Cosine of the half-angle (−1: every direction).
    pub cos: f64,
    /// Sine of the half-angle.
    pub sin: f64,
}

impl NormalCone {
    /// Every direction.
    pub const EVERYTHING: Self = Self {
        axis: Vector3::new(0.0, 0.0, 0.0),
        weight: 0.0,
        cos: -1.0,
        sin: 0.0,
    };

    /// Whether the cone holds every direction (nothing is proved by it).
    #[inline]
    pub fn is_everything(&self) -> bool {
        self.cos <= -1.0
    }

    /// The cone of one triangle's normal.
    pub fn of_triangle(t: &Triangle) -> Self {
        let [a, b, c] = t.vertices().map(|p| p.coords.cast::<f64>());
        let (u, v) = (b - a, c - a);
        let n = u.cross(&v);
        let len = n.norm();
        // Also false for a normal that is not a number.
        let resolved = len > LEAST_SINE * u.norm() * v.norm();
        if !resolved {
            return Self::EVERYTHING;
        }
        Self {
            axis: n / len,
            weight: len,
            cos: 1.0,
            sin: TRIANGLE_SLACK,
        }
    }

    /// The angle from `d` (unit) to the cone's farthest direction, as
    /// (cosine, sine), or `None` when it reaches π.
    #[inline]
    fn reach_from(&self, d: &Vector3<f64>) -> Option<(f64, f64)> {
        if self.is_everything() {
            return None;
        }
        let (c, s) = (d.dot(&self.axis), d.cross(&self.axis).norm());
        // cos and sin of (angle(d, axis) + half-angle), both in [0, π].
        let cos = c * self.cos - s * self.sin;
        let sin = s * self.cos + c * self.sin;
        (sin >= 0.0 || cos > 0.0).then_some((cos, sin))
    }

    /// Whether every direction of the cone makes an angle below `π/2 −`
    /// [`FACING_MARGIN`] with `d` (unit): every normal it bounds faces `d`.
    #[inline]
    pub fn faces(&self, d: &Vector3<f64>) -> bool {
        self.reach_from(d)
            .is_some_and(|(cos, sin)| sin >= 0.0 && cos > FACING_MARGIN)
    }

    /// The direction two cones' normals together face, if any: their
    /// summed area-weighted normals' direction, when both cones face it.
    #[inline]
    pub fn common_facing(a: &Self, b: &Self) -> Option<Vector3<f64>> {
        if a.is_everything() || b.is_everything() {
            return None;
        }
        // Cheap refusal first: axes more than π apart less both half-angles
        // (cos(φ) ≤ −cos(θa + θb)) have no facing direction at all.
        let cos_sum = a.cos * b.cos - a.sin * b.sin;
        if a.axis.dot(&b.axis) <= -cos_sum + FACING_MARGIN {
            return None;
        }
        let d = (a.axis * a.weight + b.axis * b.weight).try_normalize(0.0)?;
        (a.faces(&d) && b.faces(&d)).then_some(d)
    }
}

/// Every node's normal cone in one pose.
#[derive(Clone, Debug, Default)]
pub struct NodeCones {
    cones: Vec<NormalCone>,
}

impl NodeCones {
    /// The cones of `tree`'s nodes, whose leaf primitives are triangles
    /// `triangle(t)` in this pose: one sweep from the leaves up.
    pub fn update(&mut self, tree: &SphereTree, triangle: impl Fn(u32) -> Triangle) {
        let nodes = tree.nodes();
        self.cones.clear();
        self.cones.resize(nodes.len(), NormalCone::EVERYTHING);
        // Children are stored after their parent: a reverse sweep meets
        // every child before its parent.
        for i in (0..nodes.len()).rev() {
            self.cones[i] = match nodes[i].primitive() {
                Some(t) => NormalCone::of_triangle(&triangle(t)),
                None => self.around_children(nodes[i].children()),
            };
        }
    }

    fn around_children(&self, children: std::ops::Range<u32>) -> NormalCone {
        let kids = &self.cones[children.start as usize..children.end as usize];
        if kids.iter().any(NormalCone::is_everything) {
            return NormalCone::EVERYTHING;
        }
        let sum = kids
            .iter()
            .fold(Vector3::zeros(), |s, k| s + k.axis * k.weight);
        let weight = sum.norm();
        let has_direction = weight > 0.0;
        if !has_direction {
            return NormalCone::EVERYTHING;
        }
        let axis = sum / weight;
        // The widest child seen from the axis: the smallest cosine.
        let mut widest = (1.0f64, 0.0f64);
        for k in kids {
            match k.reach_from(&axis) {
                Some((cos, sin)) if cos < widest.0 => widest = (cos, sin),
                Some(_) => {}
                None => return NormalCone::EVERYTHING,
            }
        }
        NormalCone {
            axis,
            weight,
            cos: widest.0,
            sin: widest.1,
        }
    }

    /// Node `n`'s cone.
    #[inline]
    pub fn of(&self, n: NodeId) -> &NormalCone {
        &self.cones[n.index()]
    }

    /// Heap bytes held.
    pub fn bytes(&self) -> usize {
        self.cones.capacity() * std::mem::size_of::<NormalCone>()
    }
}

#[cfg(test)]
mod tests {
    use super::{NodeCones, NormalCone};
    use crate::sphere_tree::grouped::tests::{soup, tree};
    use nalgebra::Vector3;

    /// Every triangle normal under a node lies within its cone (checked
    /// directly, angle by angle), on random soups.
    #[test]
    fn cones_hold_their_triangles_normals() {
        for seed in 0..10u64 {
            let mesh = soup(seed, 60, 1.0, 0.2);
            let t = tree(&mesh);
            let mut cones = NodeCones::default();
            cones.update(&t, |p| mesh.triangle(crate::mesh::TriangleId(p)));
            let nodes = t.nodes();
            for i in 0..nodes.len() {
                let cone = cones.of(crate::sphere_tree::NodeId(i as u32));
                if cone.is_everything() {
                    continue;
                }
                let half = cone.sin.atan2(cone.cos);
                let mut stack = vec![i as u32];
                while let Some(k) = stack.pop() {
                    let n = &nodes[k as usize];
                    match n.primitive() {
                        Some(p) => {
                            let tri = mesh.triangle(crate::mesh::TriangleId(p));
                            let [a, b, c] = tri.vertices().map(|p| p.coords.cast::<f64>());
                            let nrm = (b - a).cross(&(c - a)).normalize();
                            let angle = nrm.dot(&cone.axis).clamp(-1.0, 1.0).acos();
                            assert!(
                                angle <= half + 1e-7,
                                "seed {seed} node {i}: {angle} > {half}"
                            );
                        }
                        None => stack.extend(n.children()),
                    }
                }
            }
        }
    }

    #[test]
    fn facing_is_strict_and_common_facing_needs_both() {
        let up = NormalCone {
            axis: Vector3::z(),
            weight: 1.0,
            cos: (1.0f64).cos(),
            sin: (1.0f64).sin(),
        };
        assert!(up.faces(&Vector3::z()));
        // 1 rad + 0.6 rad > π/2.
        let tilted = Vector3::new(0.6f64.sin(), 0.0, 0.6f64.cos());
        assert!(!up.faces(&tilted));
        let side = NormalCone {
            axis: Vector3::x(),
            ..up
        };
        // 90 degrees apart with 1 rad each: no direction within π/2 of both.
        assert!(NormalCone::common_facing(&up, &side).is_none());
        let narrow = |axis: Vector3<f64>| NormalCone {
            axis,
            weight: 1.0,
            cos: 0.2f64.cos(),
            sin: 0.2f64.sin(),
        };
        let d = NormalCone::common_facing(&narrow(Vector3::z()), &narrow(Vector3::x())).unwrap();
        assert!((d - Vector3::new(1.0, 0.0, 1.0).normalize()).norm() < 1e-12);
        assert!(!NormalCone::EVERYTHING.faces(&Vector3::z()));
    }
}
