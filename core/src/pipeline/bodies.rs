//! A character against the other bodies of a world: a moving rigid object,
//! and another character.
//!
//! * **Object.** The object's hierarchy is built once in its own frame, for
//!   the method, big triangles included ([`EnvironmentTree`]); nothing of it
//!   is refit. Each frame the character's spheres are brought into the
//!   object's frame by the inverse of its pose as traversal asks for them
//!   (refit on demand as against the room, and shared with the room pass of
//!   the same frame), and so are the corners of the character triangles the
//!   narrow phase tests. The paper's claim that refit is "applicable to any
//!   object, without dependency on … its dynamic/static behavior" (§1) is
//!   taken literally the other way round: the static hierarchy stays, the
//!   query moves.
//! * **Character.** Both trees are refit on demand during one simultaneous
//!   traversal (§3's traversal, with two deforming trees); leaves are
//!   triangles on both sides, answered by the triangle-triangle test.

use std::time::Instant;

use nalgebra::Isometry3;

use crate::character::Character;
use crate::character::PoseBuffers;
use crate::geometry::tri_tri::prepared_intersect;
use crate::geometry::{Sphere, Triangle};
use crate::mesh::{TriMesh, TriangleId};
use crate::sphere_tree::refit::Refitter;
use crate::sphere_tree::traverse::{LeafPair, TraversalStats};
use crate::sphere_tree::{
    Hierarchy, NodeId, SphereTree, Workspace, traverse, traverse_grouped, traverse_guarded,
};

use super::EnvironmentTree;
use super::driver::{FrameCounters, Pipeline, TimedRefit, ticks};
use super::prepared_triangles::PreparedTriangles;

/// Relative slack added to a sphere's radius when it changes frame: a rigid
/// transform in `f32` moves a point by a few units in the last place of its
/// coordinates and of the translation; eight is generous.
const FRAME_CHANGE_SLACK: f32 = 8.0 * f32::EPSILON;

/// `s` in the frame `to` maps into, grown to cover the rounding of the
/// transform.
#[inline]
pub fn sphere_in_frame(s: &Sphere, to: &Isometry3<f32>) -> Sphere {
    let c = to * s.center;
    let pad =
        FRAME_CHANGE_SLACK * (s.center.coords.norm() + to.translation.vector.norm() + s.radius);
    Sphere::new(c, s.radius + pad)
}

/// A hierarchy seen from another frame: its spheres moved by `to`.
struct InFrame<H> {
    inner: H,
    to: Isometry3<f32>,
}

impl<H: Hierarchy> Hierarchy for InFrame<H> {
    fn tree(&self) -> &SphereTree {
        self.inner.tree()
    }
    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        sphere_in_frame(&self.inner.sphere(id), &self.to)
    }
    #[inline]
    fn prefetch(&self, id: NodeId) {
        self.inner.prefetch(id);
    }
}

/// A static tree as a [`Hierarchy`] through a shared borrow.
struct Fixed<'a>(&'a SphereTree);

impl Hierarchy for Fixed<'_> {
    fn tree(&self) -> &SphereTree {
        self.0
    }
    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.0.nodes()[id.index()].sphere
    }
}

impl Pipeline {
    /// The character's root sphere this frame (refit now if not yet), in
    /// world coordinates: what a world's broad phase tests.
    pub fn root_sphere(&mut self, buffers: &PoseBuffers) -> Option<Sphere> {
        if self.character_tree.tree.is_empty() {
            return None;
        }
        let mut r = Refitter {
            tree: &self.character_tree,
            skin: &buffers.skin,
            state: &mut self.refit,
        };
        Some(r.fresh(NodeId::ROOT, &buffers.base))
    }

    /// The pass against a moving object whose hierarchy `object` and mesh
    /// `mesh` are in its own frame and whose pose this frame is `pose`
    /// (object frame → world), after [`Pipeline::begin_frame`]. Fills
    /// `pairs` with the colliding `(character triangle, object triangle)`
    /// pairs, sorted and distinct.
    pub fn detect_object(
        &mut self,
        buffers: &PoseBuffers,
        character: &Character,
        object: &EnvironmentTree,
        mesh: &TriMesh,
        pose: &Isometry3<f32>,
        pairs: &mut Vec<(u32, u32)>,
    ) -> FrameCounters {
        let mut c = FrameCounters::default();
        let to_object = pose.inverse();
        let refits_before = self.refit.refits;
        let skinned_before = self.skin.skinned();
        let t0 = Instant::now();
        let tick0 = ticks();
        let mut a = InFrame {
            inner: TimedRefit::<true> {
                refitter: Refitter {
                    tree: &self.character_tree,
                    skin: &buffers.skin,
                    state: &mut self.refit,
                },
                base: buffers.base,
                ticks: 0,
            },
            to: to_object,
        };
        self.object_leaf_pairs.clear();
        let leaf_pairs = &mut self.object_leaf_pairs;
        let mut b = Fixed(&object.tree);
        let mut guard_tests = 0u64;
        let stats = if self.method.tests_each_pair_once() {
            let guard = object.plane_prism_guard(&mut guard_tests);
            traverse_grouped(
                &mut a,
                &mut b,
                &mut self.workspace,
                &mut self.group_marks,
                |j| object.leaf_group(j),
                guard,
                |p| leaf_pairs.push(p),
            )
        } else if self.method.prunes_at_plane() {
            let guard = object.plane_guard(&mut guard_tests);
            traverse_guarded(&mut a, &mut b, &mut self.workspace, guard, |p| {
                leaf_pairs.push(p)
            })
        } else {
            traverse(&mut a, &mut b, &mut self.workspace, |p| leaf_pairs.push(p))
        };
        let refit_ticks = a.inner.ticks;
        let elapsed = t0.elapsed().as_secs_f64() * 1e3;
        let total_ticks = ticks().wrapping_sub(tick0).max(1);
        c.time.refit_ms = elapsed * (refit_ticks as f64 / total_ticks as f64).min(1.0);
        c.time.traversal_ms = elapsed - c.time.refit_ms;
        c.sphere_sphere = stats.sphere_tests;
        c.plane_sphere = guard_tests;

        let model = self.options.skinning;
        let indices = character.mesh.indices();
        let t0 = Instant::now();
        for p in &self.object_leaf_pairs {
            if !object.answers_by_plane(self.method, p.leaf_b) {
                for v in indices[p.primitive_a as usize] {
                    self.skin.ensure(buffers, character, model, v);
                }
            }
        }
        c.time.skinning_ms = t0.elapsed().as_secs_f64() * 1e3;

        let t0 = Instant::now();
        pairs.clear();
        let once = self.method.tests_each_pair_once();
        if once {
            self.repeats.begin_pass();
        }
        let [prepared_c, prepared_o] = &mut self.prepared;
        prepared_c.clear();
        prepared_o.clear();
        for p in &self.object_leaf_pairs {
            if once
                && object.is_division_leaf(p.leaf_b)
                && !self.repeats.first_time(p.primitive_a, p.primitive_b)
            {
                continue;
            }
            let hit = if object.answers_by_plane(self.method, p.leaf_b) {
                if self.method.prunes_at_plane() {
                    true
                } else {
                    c.plane_sphere += 1;
                    let s = sphere_in_frame(&self.refit.spheres[p.leaf_a.index()], &to_object);
                    object.leaf_meets_plane(p.leaf_b, &s) == Some(true)
                }
            } else {
                c.tri_tri += 1;
                let ct = prepared_c.get(p.primitive_a, || {
                    let [i, j, k] = self
                        .skin
                        .triangle(indices[p.primitive_a as usize])
                        .vertices();
                    Triangle::new(to_object * i, to_object * j, to_object * k)
                });
                let ot = prepared_o.get(p.primitive_b, || mesh.triangle(TriangleId(p.primitive_b)));
                prepared_intersect(ct, ot)
            };
            if hit {
                pairs.push((p.primitive_a, p.primitive_b));
            }
        }
        // A big triangle's leaves all name it: repeats removed.
        pairs.sort_unstable();
        pairs.dedup();
        c.pairs = pairs.len() as u64;
        c.refits = self.refit.refits - refits_before;
        c.skinned_vertices = self.skin.skinned() - skinned_before;
        c.time.narrow_ms = t0.elapsed().as_secs_f64() * 1e3;
        c
    }
}

/// The simultaneous traversal of two characters' trees, refitting both on
/// demand; returns its counters and the time-stamp ticks spent refitting
/// (0 unless `TIMED`).
fn traverse_pair<const TIMED: bool>(
    a: &mut Pipeline,
    ba: &PoseBuffers,
    b: &mut Pipeline,
    bb: &PoseBuffers,
    workspace: &mut Workspace,
    leaf_pairs: &mut Vec<LeafPair>,
) -> (TraversalStats, u64) {
    let mut ha = TimedRefit::<TIMED> {
        refitter: Refitter {
            tree: &a.character_tree,
            skin: &ba.skin,
            state: &mut a.refit,
        },
        base: ba.base,
        ticks: 0,
    };
    let mut hb = TimedRefit::<TIMED> {
        refitter: Refitter {
            tree: &b.character_tree,
            skin: &bb.skin,
            state: &mut b.refit,
        },
        base: bb.base,
        ticks: 0,
    };
    let stats = traverse(&mut ha, &mut hb, workspace, |p| leaf_pairs.push(p));
    (stats, ha.ticks + hb.ticks)
}

/// What [`detect_characters`] keeps between calls so that it allocates
/// nothing once grown.
#[derive(Clone, Debug, Default)]
pub struct CharacterPairScratch {
    leaf_pairs: Vec<LeafPair>,
    workspace: Workspace,
    /// Each side's triangles prepared for the triangle-triangle test.
    prepared: [PreparedTriangles; 2],
}

/// Two characters of a world against each other, after both pipelines'
/// [`Pipeline::begin_frame`]: one simultaneous traversal refitting both
/// trees on demand, then the triangle-triangle test at every overlapping
/// leaf pair, each side's triangles prepared once for it. Fills `pairs`
/// with the colliding `(triangle of a, triangle of b)` pairs, sorted and
/// distinct.
#[allow(clippy::too_many_arguments)]
pub fn detect_characters(
    a: &mut Pipeline,
    ca: &Character,
    ba: &PoseBuffers,
    b: &mut Pipeline,
    cb: &Character,
    bb: &PoseBuffers,
    scratch: &mut CharacterPairScratch,
    pairs: &mut Vec<(u32, u32)>,
) -> FrameCounters {
    let CharacterPairScratch {
        leaf_pairs,
        workspace,
        prepared: [prepared_a, prepared_b],
    } = scratch;
    let mut c = FrameCounters::default();
    let refits_before = a.refit.refits + b.refit.refits;
    let skinned_before = a.skin.skinned() + b.skin.skinned();
    let t0 = Instant::now();
    let tick0 = ticks();
    leaf_pairs.clear();
    // Refits timed apart only when both pipelines ask for it (`bench` does
    // not: two time-stamp reads per refit).
    let (stats, refit_ticks) = if a.time_refit || b.time_refit {
        traverse_pair::<true>(a, ba, b, bb, workspace, leaf_pairs)
    } else {
        traverse_pair::<false>(a, ba, b, bb, workspace, leaf_pairs)
    };
    let elapsed = t0.elapsed().as_secs_f64() * 1e3;
    let total_ticks = ticks().wrapping_sub(tick0).max(1);
    c.time.refit_ms = elapsed * (refit_ticks as f64 / total_ticks as f64).min(1.0);
    c.time.traversal_ms = elapsed - c.time.refit_ms;
    c.sphere_sphere = stats.sphere_tests;

    let t0 = Instant::now();
    let (ia, ib) = (ca.mesh.indices(), cb.mesh.indices());
    let (ma, mb) = (a.options.skinning, b.options.skinning);
    for p in leaf_pairs.iter() {
        for v in ia[p.primitive_a as usize] {
            a.skin.ensure(ba, ca, ma, v);
        }
        for v in ib[p.primitive_b as usize] {
            b.skin.ensure(bb, cb, mb, v);
        }
    }
    c.time.skinning_ms = t0.elapsed().as_secs_f64() * 1e3;

    let t0 = Instant::now();
    pairs.clear();
    prepared_a.clear();
    prepared_b.clear();
    for p in leaf_pairs.iter() {
        c.tri_tri += 1;
        let ta = prepared_a.get(p.primitive_a, || {
            a.skin.triangle(ia[p.primitive_a as usize])
        });
        let tb = prepared_b.get(p.primitive_b, || {
            b.skin.triangle(ib[p.primitive_b as usize])
        });
        if prepared_intersect(ta, tb) {
            pairs.push((p.primitive_a, p.primitive_b));
        }
    }
    // Leaves are distinct triangles on both sides: no repeats to remove.
    pairs.sort_unstable();
    c.pairs = pairs.len() as u64;
    c.refits = a.refit.refits + b.refit.refits - refits_before;
    c.skinned_vertices = a.skin.skinned() + b.skin.skinned() - skinned_before;
    c.time.narrow_ms = t0.elapsed().as_secs_f64() * 1e3;
    c
}
