//! A character against a rigid body (the room, or a moving object in its
//! own frame) in one frame: the method's traversal of the character's tree,
//! refit on demand, against the body's hierarchy with its big triangles'
//! divisions; the corners of the triangles to be tested skinned on demand;
//! then at each leaf pair the method's leaf test (paper §3–5).

use crate::geometry::tri_tri::prepared_intersect;
use crate::mesh::{TriMesh, TriangleId};
use crate::sphere_tree::traverse::LeafPair;
use crate::sphere_tree::{
    Hierarchy, NodeId, PassMarks, SphereTree, Workspace, traverse, traverse_grouped,
    traverse_guarded,
};

use super::character_side::CharacterSide;
use super::counters::FrameCounters;
use super::frame::{Frame, InFrame};
use super::pass::{Pass, PassMarksOf, Traversed};
use super::prepared_triangles::PreparedTriangles;
use super::visit_log::VisitLog;
use super::{EnvironmentTree, LeafTest, Method};

/// A character against a rigid body whose hierarchy `body` and mesh `mesh`
/// are in the body's frame; `to_body` maps the world into it.
pub(crate) struct RigidPass<'a, F: Frame, L: VisitLog> {
    pub(crate) character: CharacterSide<'a>,
    pub(crate) marks: &'a mut PassMarksOf,
    pub(crate) body: &'a EnvironmentTree,
    pub(crate) mesh: &'a TriMesh,
    pub(crate) to_body: F,
    pub(crate) method: Method,
    /// Told of the body's node of every sphere-sphere test.
    pub(crate) log: &'a mut L,
    /// Whether refit time is split from traversal time.
    pub(crate) timed: bool,
    /// Whether every vertex may be skinned in one sweep when that is
    /// cheaper than checking stamps (the room pass; see [`Pass::prepare`]).
    pub(crate) skin_all_when_cheaper: bool,
}

/// A rigid body's static tree as a [`Hierarchy`] through a shared borrow
/// (so the guard can read the body while traversal runs), telling `log` of
/// every sphere-sphere test its nodes take part in.
struct LoggedTree<'a, L> {
    body: &'a EnvironmentTree,
    log: &'a mut L,
}

impl<L: VisitLog> Hierarchy for LoggedTree<'_, L> {
    #[inline]
    fn tree(&self) -> &SphereTree {
        &self.body.tree
    }
    #[inline]
    fn sphere(&mut self, id: NodeId) -> crate::geometry::Sphere {
        self.body.tree.nodes()[id.index()].sphere
    }
    #[inline]
    fn prefetch(&self, id: NodeId) {
        self.body.prefetch(id);
    }
    #[inline]
    fn tested(&mut self, id: NodeId) {
        self.log.tested(id);
    }
}

impl<F: Frame, L: VisitLog> RigidPass<'_, F, L> {
    /// `p`'s answer from its character triangle's bind corners, when one
    /// joint alone moves them ([`super::bind_planes`]): `Some(false)` apart,
    /// `Some(true)` a contact, both the narrow phase's answers, found
    /// without skinning a corner; `None` when the corners must be skinned.
    /// Only in the room's frame (a moving body's frame would add its map's
    /// rounding).
    #[inline]
    fn answer_in_bind_space(&mut self, p: &LeafPair) -> Option<bool> {
        if !F::IDENTITY {
            return None;
        }
        let c = &self.character;
        let joint = c.tree.sole_joint[p.primitive_a as usize];
        if joint == crate::sphere_tree::self_contact::MIXED {
            return None;
        }
        let bind = c.character.mesh.positions();
        let [i, j, k] = c.character.mesh.indices()[p.primitive_a as usize];
        let (mesh, body) = (self.mesh, self.body);
        self.marks.bind_planes.answer(
            p.primitive_b,
            || {
                (
                    mesh.triangle(TriangleId(p.primitive_b)),
                    body.prism_of(p.leaf_b),
                )
            },
            joint,
            &c.pose.skin[joint as usize],
            c.tree.bind_coordinate_bound,
            [&bind[i as usize], &bind[j as usize], &bind[k as usize]],
        )
    }
}

impl<F: Frame, L: VisitLog> Pass for RigidPass<'_, F, L> {
    type Hit = (u32, u32);

    fn work(&self) -> (u64, u64) {
        self.character.work()
    }

    fn timed(&self) -> bool {
        self.timed
    }

    /// The method's traversal (paper §3, with our pruned variants' guard):
    /// grouped leaves and the plane and edge-plane guard for the methods
    /// that test each pair once, the plane guard for the other pruned
    /// methods, plain traversal for the paper's.
    fn traverse<const TIMED: bool>(
        &mut self,
        ws: &mut Workspace,
        leaf_pairs: &mut Vec<LeafPair>,
    ) -> Traversed {
        let mut a = InFrame {
            inner: self.character.hierarchy::<TIMED>(),
            to: self.to_body,
        };
        let body = self.body;
        let mut b = LoggedTree {
            body,
            log: &mut *self.log,
        };
        let (mut plane_tests, mut box_tests) = (0u64, 0u64);
        let push = |p| leaf_pairs.push(p);
        let stats = if self.method.tests_each_pair_once() {
            let guard = body.plane_prism_guard(&mut plane_tests, &mut box_tests);
            let marks = (!body.groups_are_single_leaves()).then_some(&mut self.marks.groups);
            traverse_grouped(
                &mut a,
                &mut b,
                ws,
                marks,
                |j| body.leaf_group(j),
                guard,
                push,
            )
        } else if self.method.prunes_at_plane() {
            let guard = body.plane_guard(&mut plane_tests);
            traverse_guarded(&mut a, &mut b, ws, guard, push)
        } else {
            traverse(&mut a, &mut b, ws, push)
        };
        Traversed {
            stats,
            guard_sphere_tests: 0,
            plane_tests,
            box_tests,
            refit_ticks: a.refit_ticks(),
            leaf_tests: 0,
        }
    }

    /// Skins the corners of every character triangle to be tested against
    /// a triangle, or every vertex when stamp checks would cost more (three
    /// per triangle test, about a quarter of skinning a vertex): when every
    /// leaf pair is a triangle test and there are more than 4/3 as many as
    /// vertices (the original method: 531,732 tests a frame). The methods
    /// that test each pair once skin nothing here but in that case: each
    /// triangle is skinned as it is first tested, unless its bind corners
    /// answer first ([`super::bind_planes`]).
    fn prepare(&mut self, leaf_pairs: &[LeafPair]) {
        // The planes kept belong to another pass (another character or pose).
        self.marks.bind_planes.begin_pass();
        let all_tri_tri = self.method.big_leaf_test() == LeafTest::TriTri;
        let vertices = self.character.character.mesh.positions().len();
        if self.skin_all_when_cheaper && all_tri_tri && 3 * leaf_pairs.len() > 4 * vertices {
            let c = &mut self.character;
            c.skin.skin_all(c.pose, c.character, c.model);
            return;
        }
        if self.method.tests_each_pair_once() {
            return;
        }
        for p in leaf_pairs {
            if !self.body.answers_by_plane(self.method, p.leaf_b) {
                self.character.ensure_triangle(p.primitive_a);
            }
        }
    }

    fn begin_narrow(&mut self) {
        if self.method.tests_each_pair_once() {
            self.marks.repeats.begin_pass();
        }
    }

    #[inline]
    fn test(
        &mut self,
        leaf_pairs: &[LeafPair],
        k: usize,
        prepared: &mut [PreparedTriangles; 2],
        c: &mut FrameCounters,
    ) -> Option<(u32, u32)> {
        let p = leaf_pairs[k];
        let (body, method) = (self.body, self.method);
        if method.tests_each_pair_once()
            && !body.groups_are_single_leaves()
            && body.is_division_leaf(p.leaf_b)
            && !first_time(&mut self.marks.repeats, &p)
        {
            return None;
        }
        let hit = if body.answers_by_plane(method, p.leaf_b) {
            if method.prunes_at_plane() {
                // Already tested on the way down.
                true
            } else {
                c.plane_sphere += 1;
                let s = self
                    .to_body
                    .sphere(&self.character.refit.spheres[p.leaf_a.index()]);
                body.leaf_meets_plane(p.leaf_b, &s) == Some(true)
            }
        } else {
            c.tri_tri += 1;
            // The methods that test each pair once skin a character
            // triangle here, as it is first tested, unless its bind
            // corners answer (one joint moves it): then it is not skinned.
            if method.tests_each_pair_once() && !prepared[0].holds(p.primitive_a) {
                if let Some(hit) = self.answer_in_bind_space(&p) {
                    return hit.then_some((p.primitive_a, p.primitive_b));
                }
                self.character.ensure_triangle(p.primitive_a);
            }
            let [pc, pb] = prepared;
            let bt = pb.get(p.primitive_b, || {
                self.mesh.triangle(TriangleId(p.primitive_b))
            });
            // Before the character triangle is prepared (the larger half of
            // a test that ends early), two answers a big triangle gives
            // from its corners alone:
            // - the test's own plane-side exit (its corners strictly on one
            //   side of the body triangle's plane): no contact, bit for bit
            //   the test's answer;
            // - not so, and every corner surely inside the big triangle's
            //   edge planes: the triangle reaches the plane inside the big
            //   triangle, a contact (exact; the test's answer too, up to
            //   its snapping of pairs that touch).
            let character_triangle = || {
                self.to_body
                    .triangle(self.character.triangle(p.primitive_a))
            };
            let ct = if pc.holds(p.primitive_a) {
                pc.get(p.primitive_a, character_triangle)
            } else {
                let t = character_triangle();
                if bt.plane_has_on_one_side(&t) {
                    return None;
                }
                if let Some(prism) = body.prism_of(p.leaf_b)
                    && prism.holds_inside(&t)
                {
                    return Some((p.primitive_a, p.primitive_b));
                }
                pc.get(p.primitive_a, || t)
            };
            prepared_intersect(ct, bt)
        };
        hit.then_some((p.primitive_a, p.primitive_b))
    }

    /// A big triangle's leaves all name it: repeats removed.
    fn finish(hits: &mut Vec<(u32, u32)>) {
        super::pass::sort_pairs(hits);
        hits.dedup();
    }
}

/// Whether `p`'s (character triangle, big triangle) pair is met for the
/// first time in this pass.
#[inline]
fn first_time(repeats: &mut PassMarks, p: &LeafPair) -> bool {
    repeats.first_time(p.primitive_a, p.primitive_b)
}
