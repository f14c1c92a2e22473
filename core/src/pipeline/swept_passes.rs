//! The passes of continuous detection over a frame step (docs/ccd.md,
//! "Swept hierarchies"): a character's swept tree against the still room,
//! a moving object's swept tree, or another character's swept tree, with
//! the one skeleton of [`super::pass`].
//!
//! Traversal tests swept spheres. Against the room and between characters
//! its guard refines every pair the swept spheres keep with the node's
//! interpolated spheres (found from its tagged swept sphere): against the
//! other node's sphere, and in the pruned methods against a big triangle's
//! plane at every node of its division. The leaf pairs are answered by
//! [`super::continuous_narrow`].

use nalgebra::Isometry3;

use crate::geometry::ccd_root_finder::CcdParams;
use crate::geometry::ccd_sphere_plane::{StillPlane, sweep_meets_plane};
use crate::geometry::ccd_sphere_sphere::sweeps_meet;
use crate::geometry::ccd_triangles::MovingTriangle;
use crate::geometry::{Point, Sphere};
use crate::mesh::{TriMesh, TriangleId};
use crate::sphere_tree::swept_rigid::{RigidPath, SweptRigid};
use crate::sphere_tree::traverse::LeafPair;
use crate::sphere_tree::{Hierarchy, NodeId, SphereTree, Workspace, traverse, traverse_guarded};

use crate::sphere_tree::character::CharacterTree;
use crate::sphere_tree::self_contact::{RigidGaps, SelfContactData};
use crate::sphere_tree::self_traverse::traverse_self;

use super::continuous_narrow::{CcdCounters, TimedPair, corners, leaf_toi, wide};
use super::counters::FrameCounters;
use super::pass::{Pass, Traversed};
use super::prepared_triangles::PreparedTriangles;
use super::swept_side::SweptSide;
use super::{EnvironmentTree, LeafTest, Method};

/// A static tree as a [`Hierarchy`] through a shared borrow.
struct Still<'a>(&'a SphereTree);

impl Hierarchy for Still<'_> {
    fn tree(&self) -> &SphereTree {
        self.0
    }
    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.0.nodes()[id.index()].sphere
    }
}

/// A big triangle's leaves all name it: one test per triangle pair.
fn distinct_pairs(leaf_pairs: &mut Vec<LeafPair>) {
    leaf_pairs.sort_unstable_by_key(|p| (p.primitive_a, p.primitive_b));
    leaf_pairs.dedup_by_key(|p| (p.primitive_a, p.primitive_b));
}

/// Leaf pair `p` answered by the triangle–triangle kernel on its triangles
/// `a` and `b` over the step (`b_still`: `b` does not move), counted as a
/// triangle test.
fn kernel_hit(
    p: &LeafPair,
    a: &MovingTriangle<f64>,
    b: &MovingTriangle<f64>,
    b_still: bool,
    params: &CcdParams,
    ccd: &mut CcdCounters,
    c: &mut FrameCounters,
) -> Option<TimedPair> {
    c.tri_tri += 1;
    leaf_toi(a, b, b_still, params, ccd).map(|toi| TimedPair {
        a: p.primitive_a,
        b: p.primitive_b,
        toi,
        by_plane: false,
    })
}

/// A character's step against the still room.
pub(crate) struct SweptRoomPass<'a> {
    pub(crate) character: SweptSide<'a>,
    pub(crate) room: &'a EnvironmentTree,
    /// The plane of each division's big triangle ([`room_planes`]).
    pub(crate) planes: &'a [StillPlane],
    pub(crate) mesh: &'a TriMesh,
    pub(crate) method: Method,
    pub(crate) params: &'a CcdParams,
    pub(crate) ccd: &'a mut CcdCounters,
}

/// The plane of every division's big triangle of `room` (whose mesh is
/// `mesh`), prepared once for the continuous room pass.
pub fn room_planes(room: &EnvironmentTree, mesh: &TriMesh) -> Vec<StillPlane> {
    room.divisions
        .iter()
        .map(|d| StillPlane::new(&mesh.triangle(d.original)))
        .collect()
}

impl Pass for SweptRoomPass<'_> {
    type Hit = TimedPair;

    fn work(&self) -> (u64, u64) {
        self.character.work()
    }

    fn traverse<const TIMED: bool>(
        &mut self,
        ws: &mut Workspace,
        leaf_pairs: &mut Vec<LeafPair>,
    ) -> Traversed {
        let (room, planes) = (self.room, self.planes);
        let prunes = self.method.prunes_at_plane();
        let nodes = room.tree.nodes();
        let (mut plane_tests, mut sphere_tests, mut box_tests) = (0u64, 0u64, 0u64);
        let (mut a, cache) = self.character.hierarchy();
        let mut b = Still(&room.tree);
        // First the node's box (a swept sphere holds the node's triangles
        // over the whole step). Untagged, the rest is the discrete guard.
        let guard = |j: NodeId, s: &Sphere| {
            room.box_may_meet(j, s, &mut box_tests)
                && match cache.node_of(s) {
                    Some(id) => {
                        let e = cache.ends(id);
                        if prunes && let Some((d, _)) = room.division_node[j.index()] {
                            plane_tests += 1;
                            if planes[d as usize].sweep_toi(&e.start, &e.end).is_none() {
                                return false;
                            }
                        }
                        let sj = nodes[j.index()].sphere;
                        sphere_tests += 1;
                        sweeps_meet(&e.start, &e.end, &sj, &sj)
                    }
                    None if prunes && room.is_division_leaf(j) => {
                        plane_tests += 1;
                        room.leaf_meets_plane(j, s) == Some(true)
                    }
                    None => true,
                }
        };
        let stats = traverse_guarded(&mut a, &mut b, ws, guard, |p| leaf_pairs.push(p));
        distinct_pairs(leaf_pairs);
        Traversed {
            stats,
            guard_sphere_tests: sphere_tests,
            plane_tests,
            box_tests,
            refit_ticks: 0,
            leaf_tests: 0,
        }
    }

    fn test(
        &mut self,
        leaf_pairs: &[LeafPair],
        k: usize,
        _prepared: &mut [PreparedTriangles; 2],
        c: &mut FrameCounters,
    ) -> Option<TimedPair> {
        let p = leaf_pairs[k];
        let plane_leaf = self.method.big_leaf_test() == LeafTest::PlaneSphere
            && self.room.is_division_leaf(p.leaf_b);
        let big = self.mesh.triangle(TriangleId(p.primitive_b));
        let (s0, s1) = self.character.leaf_sweep(p.leaf_a);
        c.plane_sphere += 1;
        let Some(plane_toi) = sweep_meets_plane(&s0, &s1, &big) else {
            if !plane_leaf {
                self.ccd.plane_side_skips += 1;
            }
            return None;
        };
        let hit = |toi, by_plane| TimedPair {
            a: p.primitive_a,
            b: p.primitive_b,
            toi,
            by_plane,
        };
        if plane_leaf {
            return Some(hit(plane_toi, true));
        }
        let a = self.character.moving_triangle(p.primitive_a);
        let still = corners(&big);
        let b = MovingTriangle {
            start: still,
            end: still,
        };
        kernel_hit(&p, &a, &b, true, self.params, self.ccd, c)
    }

    /// Distinct leaf pairs in order give hits in order.
    fn finish(_hits: &mut Vec<TimedPair>) {}
}

/// A character's step against a moving rigid object (its tree in its own
/// frame, swept along `path` in world coordinates). Its big triangles move,
/// so their leaves are answered by the triangle–triangle kernel in every
/// method (a plane test would need the plane's motion).
pub(crate) struct SweptObjectPass<'a> {
    pub(crate) character: SweptSide<'a>,
    pub(crate) object: &'a EnvironmentTree,
    pub(crate) mesh: &'a TriMesh,
    pub(crate) path: &'a RigidPath,
    pub(crate) params: &'a CcdParams,
    pub(crate) ccd: &'a mut CcdCounters,
}

/// Object triangle `t` posed at both ends (`f32` world positions, as the
/// discrete passes and the reference pose them).
pub fn posed_triangle(
    mesh: &TriMesh,
    t: u32,
    from: &Isometry3<f32>,
    to: &Isometry3<f32>,
) -> MovingTriangle<f64> {
    let tri = mesh.triangle(TriangleId(t));
    let at = |pose: &Isometry3<f32>| tri.vertices().map(|p: Point| wide(&(pose * p)));
    MovingTriangle {
        start: at(from),
        end: at(to),
    }
}

impl Pass for SweptObjectPass<'_> {
    type Hit = TimedPair;

    fn work(&self) -> (u64, u64) {
        self.character.work()
    }

    fn traverse<const TIMED: bool>(
        &mut self,
        ws: &mut Workspace,
        leaf_pairs: &mut Vec<LeafPair>,
    ) -> Traversed {
        let (mut a, _) = self.character.hierarchy();
        let mut b = SweptRigid {
            tree: &self.object.tree,
            path: *self.path,
        };
        let stats = traverse(&mut a, &mut b, ws, |p| leaf_pairs.push(p));
        distinct_pairs(leaf_pairs);
        Traversed {
            stats,
            ..Traversed::default()
        }
    }

    fn test(
        &mut self,
        leaf_pairs: &[LeafPair],
        k: usize,
        _prepared: &mut [PreparedTriangles; 2],
        c: &mut FrameCounters,
    ) -> Option<TimedPair> {
        let p = leaf_pairs[k];
        let a = self.character.moving_triangle(p.primitive_a);
        let b = posed_triangle(self.mesh, p.primitive_b, &self.path.from, &self.path.to);
        kernel_hit(&p, &a, &b, false, self.params, self.ccd, c)
    }

    /// Distinct leaf pairs in order give hits in order.
    fn finish(_hits: &mut Vec<TimedPair>) {}
}

/// Two characters over a step: one traversal of both swept trees (the
/// guard refining a pair by both nodes' interpolated spheres, as against
/// the room), then the triangle–triangle kernel at every leaf pair.
pub(crate) struct SweptPairPass<'a> {
    pub(crate) a: SweptSide<'a>,
    pub(crate) b: SweptSide<'a>,
    pub(crate) params: &'a CcdParams,
    pub(crate) ccd: &'a mut CcdCounters,
}

impl Pass for SweptPairPass<'_> {
    type Hit = TimedPair;

    fn work(&self) -> (u64, u64) {
        let (ra, sa) = self.a.work();
        let (rb, sb) = self.b.work();
        (ra + rb, sa + sb)
    }

    fn traverse<const TIMED: bool>(
        &mut self,
        ws: &mut Workspace,
        leaf_pairs: &mut Vec<LeafPair>,
    ) -> Traversed {
        let (mut ha, ca) = self.a.hierarchy();
        let (mut hb, cb) = self.b.hierarchy();
        let mut sphere_tests = 0u64;
        let guard = |j: NodeId, s: &Sphere| match ca.node_of(s) {
            Some(id) if cb.is_fresh(j) => {
                sphere_tests += 1;
                let (ea, eb) = (ca.ends(id), cb.ends(j));
                sweeps_meet(&ea.start, &ea.end, &eb.start, &eb.end)
            }
            _ => true,
        };
        let stats = traverse_guarded(&mut ha, &mut hb, ws, guard, |p| leaf_pairs.push(p));
        Traversed {
            stats,
            guard_sphere_tests: sphere_tests,
            ..Traversed::default()
        }
    }

    fn test(
        &mut self,
        leaf_pairs: &[LeafPair],
        k: usize,
        _prepared: &mut [PreparedTriangles; 2],
        c: &mut FrameCounters,
    ) -> Option<TimedPair> {
        let p = leaf_pairs[k];
        let ta = self.a.moving_triangle(p.primitive_a);
        let tb = self.b.moving_triangle(p.primitive_b);
        kernel_hit(&p, &ta, &tb, false, self.params, self.ccd, c)
    }

    fn finish(hits: &mut Vec<TimedPair>) {
        hits.sort_unstable_by_key(|p| (p.a, p.b));
    }
}

/// A character's step against itself: its swept tree walked against
/// itself ([`traverse_self`]), each pair the swept spheres keep refined by
/// both nodes' interpolated spheres, pairs sharing a welded corner dropped
/// (the neighbour rule of the discrete self pass), parts one joint moves
/// skipped where their rest gap proves them apart over the whole step
/// ([`RigidGaps::update_over_step`]), then the triangle–triangle kernel at
/// every leaf pair.
pub(crate) struct SweptSelfPass<'a> {
    pub(crate) character: SweptSide<'a>,
    pub(crate) data: &'a SelfContactData,
    /// This step's gaps per joint (updated by the pass when culling).
    pub(crate) gaps: &'a mut RigidGaps,
    /// Whether parts one joint moves are skipped.
    pub(crate) cull_rigid: bool,
    pub(crate) params: &'a CcdParams,
    pub(crate) ccd: &'a mut CcdCounters,
}

impl Pass for SweptSelfPass<'_> {
    /// `a < b`.
    type Hit = TimedPair;

    fn work(&self) -> (u64, u64) {
        self.character.work()
    }

    fn traverse<const TIMED: bool>(
        &mut self,
        ws: &mut Workspace,
        leaf_pairs: &mut Vec<LeafPair>,
    ) -> Traversed {
        let data = self.data;
        let cull = self.cull_rigid;
        if cull {
            let pose = self.character.pose;
            self.gaps.update_over_step(
                pose.start.skin,
                pose.end.skin,
                data.coordinate_bound(),
                self.params.tolerance,
            );
        }
        let gaps = &*self.gaps;
        let tree: &CharacterTree = self.character.tree;
        let (mut h, cache) = self.character.hierarchy();
        let mut sphere_tests = 0u64;
        let stats = traverse_self(
            &tree.tree,
            &mut h,
            ws,
            |n| cull && data.skips_node(gaps, n),
            |_, i, j| {
                if cull && data.skips_pair(gaps, i, j) {
                    false
                } else if cache.is_fresh(i) && cache.is_fresh(j) {
                    sphere_tests += 1;
                    let (ea, eb) = (cache.ends(i), cache.ends(j));
                    sweeps_meet(&ea.start, &ea.end, &eb.start, &eb.end)
                } else {
                    true
                }
            },
            |_, p| {
                if !data.neighbours(p.primitive_a, p.primitive_b) {
                    leaf_pairs.push(p);
                }
            },
        );
        Traversed {
            stats,
            guard_sphere_tests: sphere_tests,
            ..Traversed::default()
        }
    }

    fn test(
        &mut self,
        leaf_pairs: &[LeafPair],
        k: usize,
        _prepared: &mut [PreparedTriangles; 2],
        c: &mut FrameCounters,
    ) -> Option<TimedPair> {
        let p = leaf_pairs[k];
        let ta = self.character.moving_triangle(p.primitive_a);
        let tb = self.character.moving_triangle(p.primitive_b);
        kernel_hit(&p, &ta, &tb, false, self.params, self.ccd, c).map(|h| TimedPair {
            a: h.a.min(h.b),
            b: h.a.max(h.b),
            ..h
        })
    }

    fn finish(hits: &mut Vec<TimedPair>) {
        hits.sort_unstable_by_key(|p| (p.a, p.b));
    }
}
