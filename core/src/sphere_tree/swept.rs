//! Swept spheres of a character tree over one frame step (continuous
//! detection, the paper's future work of §7; docs/ccd.md, "Swept
//! hierarchies").
//!
//! Over a step every vertex moves on the straight line between its skinned
//! positions at the two frames. If a node's refit sphere holds its vertices
//! at the start (`S₀`) and at the end (`S₁`), then:
//!
//! * the **interpolated sphere** `S(t) = (c₀ + t(c₁ − c₀), r₀ + t(r₁ − r₀))`
//!   holds them at every `t`: `v(t) − c(t) = (1 − t)(v₀ − c₀) + t(v₁ − c₁)`,
//!   of length at most `(1 − t) r₀ + t r₁`; a triangle is the convex hull of
//!   its corners, and a ball is convex, so it holds the node's triangles too;
//! * the **swept sphere**, the smallest ball holding `S₀` and `S₁`, holds
//!   every `S(t)` (each lies in the convex hull of the two), hence the
//!   node's triangles over the whole step. It is what traversal tests.
//!
//! [`SweptCharacter`] is the character tree as a [`Hierarchy`] of swept
//! spheres: it refits a node at both ends on first request (two
//! [`Refitter`]s, each with its own refit state and pose), and keeps the
//! swept sphere for the rest of the step.

use std::cell::Cell;

use nalgebra::Matrix4;

use crate::geometry::enclosing::round_up;
use crate::geometry::sphere_sweep::F64_SLACK;
pub use crate::geometry::sphere_sweep::{SphereSweep, enclosing_pair};
use crate::geometry::{Point, Sphere};

use super::character::CharacterTree;
use super::node::{NodeId, SphereTree};
use super::refit::Refitter;
use super::traverse::Hierarchy;

/// Low bits of each of a tagged sphere's four numbers that carry its node.
const TAG_BITS: u32 = 5;
const TAG_MASK: u32 = (1 << TAG_BITS) - 1;
/// Nodes a tag can name.
pub const MAX_TAGGED_NODES: usize = 1 << (4 * TAG_BITS);

/// `s` grown a little so that the lowest [`TAG_BITS`] bits of its centre's
/// coordinates and of its radius spell `id`: the centre moves by at most
/// 31 units in the last place of each coordinate, and the radius grows by
/// that shift (measured in `f64`) and up to 31 units in its last place, so
/// the tagged sphere holds `s`.
fn tag(s: &Sphere, id: u32) -> Sphere {
    let part = |k: u32| (id >> (k * TAG_BITS)) & TAG_MASK;
    let set = |x: f32, k: u32| f32::from_bits((x.to_bits() & !TAG_MASK) | part(k));
    let c = Point::new(set(s.center.x, 0), set(s.center.y, 1), set(s.center.z, 2));
    // The centre's move, bounded by its 1-norm.
    let moved = (c.x as f64 - s.center.x as f64).abs()
        + (c.y as f64 - s.center.y as f64).abs()
        + (c.z as f64 - s.center.z as f64).abs();
    let need = round_up((moved + s.radius as f64) * (1.0 + F64_SLACK));
    let bits = need.to_bits();
    let mut r = (bits & !TAG_MASK) | part(3);
    if r < bits {
        r += 1 << TAG_BITS;
    }
    Sphere::new(c, f32::from_bits(r))
}

/// The node a tagged sphere names.
fn untag(s: &Sphere) -> u32 {
    let part = |x: f32, k: u32| (x.to_bits() & TAG_MASK) << (k * TAG_BITS);
    part(s.center.x, 0) | part(s.center.y, 1) | part(s.center.z, 2) | part(s.radius, 3)
}

/// This step's swept spheres and the refit spheres at both ends behind
/// them (a stamp per node, as refit). Shared through `&` (cells), so a
/// traversal's guard can read what its hierarchy computes.
///
/// The swept spheres handed to traversal are **tagged**: grown by a few
/// units in the last place so that their low bits name their node
/// ([`SweptCache::node_of`]). A guard given only a sphere can then use the
/// node's two end spheres, whose interpolation bounds the node far more
/// tightly than the ball around both (a limb moving along a wall sweeps a
/// capsule, not a ball).
#[derive(Debug)]
pub struct SweptCache {
    swept: Vec<Cell<Sphere>>,
    ends: Vec<Cell<SphereSweep>>,
    stamp: Vec<Cell<u32>>,
    step: u32,
}

impl SweptCache {
    /// A cache for a character tree of `nodes` nodes, every sphere stale.
    pub fn new(nodes: usize) -> Self {
        let zero = Sphere::new(Point::origin(), 0.0);
        Self {
            swept: (0..nodes).map(|_| Cell::new(zero)).collect(),
            ends: (0..nodes)
                .map(|_| {
                    Cell::new(SphereSweep {
                        start: zero,
                        end: zero,
                    })
                })
                .collect(),
            stamp: (0..nodes).map(|_| Cell::new(0)).collect(),
            step: 0,
        }
    }

    /// Starts a step: every swept sphere is stale. No allocation.
    pub fn begin_step(&mut self) {
        self.step = self.step.wrapping_add(1);
        if self.step == 0 {
            self.stamp.iter().for_each(|s| s.set(0));
            self.step = 1;
        }
    }

    /// Whether node `id`'s swept sphere was computed this step.
    #[inline]
    pub fn is_fresh(&self, id: NodeId) -> bool {
        self.stamp[id.index()].get() == self.step
    }

    /// Node `id`'s refit spheres at both ends (valid where fresh).
    #[inline]
    pub fn ends(&self, id: NodeId) -> SphereSweep {
        self.ends[id.index()].get()
    }

    /// Node `id`'s swept sphere, as handed to traversal (valid where fresh).
    #[inline]
    pub fn swept(&self, id: NodeId) -> Sphere {
        self.swept[id.index()].get()
    }

    /// The node whose swept sphere this step is exactly `s`, if any.
    #[inline]
    pub fn node_of(&self, s: &Sphere) -> Option<NodeId> {
        let id = untag(s) as usize;
        let same = |a: &Sphere| {
            a.center.x.to_bits() == s.center.x.to_bits()
                && a.center.y.to_bits() == s.center.y.to_bits()
                && a.center.z.to_bits() == s.center.z.to_bits()
                && a.radius.to_bits() == s.radius.to_bits()
        };
        (id < self.swept.len() && self.stamp[id].get() == self.step && same(&self.swept[id].get()))
            .then_some(NodeId(id as u32))
    }

    fn store(&self, id: NodeId, ends: SphereSweep) -> Sphere {
        let i = id.index();
        let plain = ends.swept();
        let s = if self.swept.len() <= MAX_TAGGED_NODES {
            tag(&plain, id.0)
        } else {
            plain
        };
        self.swept[i].set(s);
        self.ends[i].set(ends);
        self.stamp[i].set(self.step);
        s
    }
}

/// A character tree over a step: each node's swept sphere, refitting it at
/// both ends on first request (the paper's on-demand refit, §3, done twice).
pub struct SweptCharacter<'a> {
    /// The refit at the start of the step (the previous frame's pose).
    pub start: Refitter<'a>,
    /// The skeleton's base frame at the start of the step (see
    /// [`OnDemand::base`](super::refit::OnDemand::base)).
    pub start_base: Matrix4<f32>,
    /// The refit at the end (this frame's pose).
    pub end: Refitter<'a>,
    /// The skeleton's base frame at the end of the step.
    pub end_base: Matrix4<f32>,
    /// This step's swept spheres, shared with the traversal's guard.
    pub cache: &'a SweptCache,
}

impl SweptCharacter<'_> {
    /// Node `id`'s refit spheres at both ends (refit now where stale).
    #[inline]
    pub fn sweep(&mut self, id: NodeId) -> SphereSweep {
        SphereSweep {
            start: fresh(&mut self.start, id, &self.start_base),
            end: fresh(&mut self.end, id, &self.end_base),
        }
    }

    /// The character tree.
    pub fn character_tree(&self) -> &CharacterTree {
        self.end.tree
    }
}

#[inline]
fn fresh(r: &mut Refitter<'_>, id: NodeId, base: &Matrix4<f32>) -> Sphere {
    if r.state.is_fresh(id) {
        r.state.spheres[id.index()]
    } else {
        r.refit_node(id, base)
    }
}

impl Hierarchy for SweptCharacter<'_> {
    fn tree(&self) -> &SphereTree {
        &self.end.tree.tree
    }

    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        if self.cache.is_fresh(id) {
            return self.cache.swept(id);
        }
        let ends = self.sweep(id);
        self.cache.store(id, ends)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn s(x: f32, y: f32, z: f32, r: f32) -> Sphere {
        Sphere::new(Point::new(x, y, z), r)
    }

    #[test]
    fn interpolated_spheres_stay_in_the_swept_one() {
        let sweep = SphereSweep {
            start: s(0.0, 0.0, 0.0, 0.1),
            end: s(1.0, 0.5, 0.0, 0.3),
        };
        let w = sweep.swept();
        for i in 0..=64 {
            let t = i as f64 / 64.0;
            assert!(w.contains_sphere(&sweep.at(t), 1e-6), "t = {t}");
        }
        assert_eq!(sweep.at(0.0).center, sweep.start.center);
    }

    #[test]
    fn tags_name_their_node_and_hold_the_sphere() {
        for (i, sphere) in [
            s(0.0, 0.0, 0.0, 0.0),
            s(1.5, -2.25, 3.0, 0.01),
            s(-1e3, 5e-3, 7.0, 2.0),
            s(1e-30, -0.0, 1e5, 1e-20),
        ]
        .into_iter()
        .enumerate()
        {
            for id in [0u32, 1, 31, 32, 12345, (MAX_TAGGED_NODES - 1) as u32] {
                let t = tag(&sphere, id);
                assert_eq!(untag(&t), id, "{i}");
                assert!(
                    t.contains_sphere(&sphere, 0.0),
                    "{i} {id}: {t:?} {sphere:?}"
                );
                let grown = t.radius as f64 - sphere.radius as f64;
                assert!(
                    grown
                        <= 1e-4 * (1.0 + sphere.center.coords.norm() as f64 + sphere.radius as f64)
                );
            }
        }
    }
}
