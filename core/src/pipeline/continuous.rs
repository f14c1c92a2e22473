//! Continuous detection of one character over a frame step (the paper's
//! future work, §7; docs/ccd.md, "Swept hierarchies"): the character's
//! swept spheres (`sphere_tree::swept`), refit on demand at both ends, are
//! traversed against the room's static tree, a moving object's swept tree
//! or another character's swept tree with the discrete methods' traversal
//! (`sphere_tree::traverse`, `traverse_guarded`). Against the room and
//! between characters its guard refines every pair the swept spheres keep
//! with the node's interpolated spheres (found from its tagged swept
//! sphere): against the other node's sphere, and in the pruned methods
//! against a big triangle's plane at every node of its division. The leaf
//! pairs are answered by [`super::continuous_narrow`].
//!
//! [`CharacterSweep`] keeps what one character needs between steps: refit
//! states and on-demand skinning at both ends. The end of one step is the
//! start of the next, so its states are swapped, not redone; after the first
//! step nothing is allocated.

use nalgebra::Isometry3;

use crate::character::{Character, OnDemandSkin, PoseBuffers, SkinningModel};
use crate::geometry::ccd_root_finder::CcdParams;
use crate::geometry::ccd_sphere_plane::{StillPlane, sweep_meets_plane};
use crate::geometry::ccd_sphere_sphere::sweeps_meet;
use crate::geometry::ccd_triangles::MovingTriangle;
use crate::geometry::{Point, Sphere};
use crate::mesh::{TriMesh, TriangleId};
use crate::sphere_tree::character::CharacterTree;
use crate::sphere_tree::refit::{RefitState, Refitter};
use crate::sphere_tree::swept::{SweptCache, SweptCharacter};
use crate::sphere_tree::swept_rigid::{RigidPath, SweptRigid};
use crate::sphere_tree::traverse::LeafPair;
use crate::sphere_tree::{Hierarchy, NodeId, SphereTree, Workspace, traverse, traverse_guarded};

use super::continuous_narrow::{CcdCounters, TimedPair, corners, leaf_toi, wide};
use super::driver::FrameCounters;
use super::{EnvironmentTree, LeafTest, Method};

/// The poses of one character at the start and the end of a step.
#[derive(Clone, Copy)]
pub struct StepPose<'a> {
    pub start: &'a PoseBuffers,
    pub end: &'a PoseBuffers,
}

/// One character's continuous state for one method.
pub struct CharacterSweep {
    start: RefitState,
    end: RefitState,
    skin_start: OnDemandSkin,
    skin_end: OnDemandSkin,
    cache: SweptCache,
    workspace: Workspace,
    leaf_pairs: Vec<LeafPair>,
    warmed_up: bool,
    /// The start state's refits and skinned vertices when the step began
    /// (carried over from the previous step's end).
    start_refits: u64,
    start_skinned: u64,
}

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

/// Everything a pass reads about the character.
#[derive(Clone, Copy)]
pub struct Body<'a> {
    pub tree: &'a CharacterTree,
    pub character: &'a Character,
    pub model: SkinningModel,
    pub pose: StepPose<'a>,
}

impl CharacterSweep {
    pub fn new(tree: &CharacterTree, character: &Character) -> Self {
        let joints = character.skeleton.len();
        let vertices = character.mesh.positions().len();
        Self {
            start: RefitState::new(tree, joints),
            end: RefitState::new(tree, joints),
            skin_start: OnDemandSkin::new(vertices),
            skin_end: OnDemandSkin::new(vertices),
            cache: SweptCache::new(tree.tree.len()),
            workspace: Workspace::new(),
            leaf_pairs: Vec::new(),
            warmed_up: false,
            start_refits: 0,
            start_skinned: 0,
        }
    }

    /// Starts a step. With `continues`, the last step ended at this step's
    /// start pose: its end states become the start states (nothing refit or
    /// skinned again); otherwise both ends start empty.
    pub fn begin_step(&mut self, pose: StepPose<'_>, continues: bool) {
        if continues {
            std::mem::swap(&mut self.start, &mut self.end);
            std::mem::swap(&mut self.skin_start, &mut self.skin_end);
        } else {
            self.start
                .begin_frame_with_base(&pose.start.skin, &pose.start.base);
            self.skin_start.begin_frame();
        }
        self.end
            .begin_frame_with_base(&pose.end.skin, &pose.end.base);
        self.skin_end.begin_frame();
        self.cache.begin_step();
        self.start_refits = self.start.refits;
        self.start_skinned = self.skin_start.skinned();
    }

    /// Spheres refit this step, at both ends (the start's refits of the
    /// previous step, whose end it was, not counted).
    pub fn refits(&self) -> u64 {
        self.start.refits - self.start_refits + self.end.refits
    }

    /// Vertices skinned this step, at both ends (likewise).
    pub fn skinned(&self) -> u64 {
        self.skin_start.skinned() - self.start_skinned + self.skin_end.skinned()
    }

    /// The refit states at the start and the end (valid where refit).
    pub fn refit_states(&self) -> (&RefitState, &RefitState) {
        (&self.start, &self.end)
    }

    /// The root's swept sphere this step (refit at both ends if not yet).
    pub fn root_sphere(&mut self, body: &Body<'_>) -> Option<Sphere> {
        if body.tree.tree.is_empty() {
            return None;
        }
        Some(swept(&mut self.start, &mut self.end, &self.cache, body).sphere(NodeId::ROOT))
    }

    /// The leaf pairs of the last pass.
    pub fn leaf_pairs(&self) -> &[LeafPair] {
        &self.leaf_pairs
    }

    /// Leaf `id`'s refit spheres at both ends (fresh after a pass reached it).
    fn leaf_sweep(&self, id: NodeId) -> (Sphere, Sphere) {
        let e = self.cache.ends(id);
        (e.start, e.end)
    }

    /// Character triangle `t` at both ends, skinning its corners on demand.
    fn moving_triangle(&mut self, body: &Body<'_>, t: u32) -> MovingTriangle<f64> {
        let idx = body.character.mesh.indices()[t as usize];
        let at = |skin: &mut OnDemandSkin, pose: &PoseBuffers| {
            idx.map(|v| {
                skin.ensure(pose, body.character, body.model, v);
                wide(&skin.position(v))
            })
        };
        let start = at(&mut self.skin_start, body.pose.start);
        let end = at(&mut self.skin_end, body.pose.end);
        MovingTriangle { start, end }
    }

    fn sort_leaf_pairs(&mut self) {
        // A big triangle's leaves all name it: one test per triangle pair.
        self.leaf_pairs
            .sort_unstable_by_key(|p| (p.primitive_a, p.primitive_b));
        self.leaf_pairs
            .dedup_by_key(|p| (p.primitive_a, p.primitive_b));
    }

    fn warm_up(&mut self, out: &mut Vec<TimedPair>) {
        if !self.warmed_up {
            // Room for twice the first step's work (as the discrete driver).
            self.warmed_up = true;
            self.leaf_pairs.reserve(self.leaf_pairs.len().max(64));
            out.reserve((2 * out.len()).max(64));
            self.workspace.reserve_headroom();
        }
    }

    /// The pass against the still room, after [`Self::begin_step`]: fills
    /// `out` with the pairs `(character triangle, room triangle)` that touch
    /// during the step, sorted by pair, distinct. `planes` are the planes
    /// of the room's divisions' big triangles ([`room_planes`]).
    #[allow(clippy::too_many_arguments)]
    pub fn detect_room(
        &mut self,
        body: &Body<'_>,
        room: &EnvironmentTree,
        planes: &[StillPlane],
        mesh: &TriMesh,
        method: Method,
        params: &CcdParams,
        ccd: &mut CcdCounters,
        out: &mut Vec<TimedPair>,
    ) -> FrameCounters {
        let mut c = FrameCounters::default();
        let refits = self.refits();
        let skinned = self.skinned();
        let t0 = std::time::Instant::now();
        let (mut guard_tests, mut capsule_tests) = (0u64, 0u64);
        {
            self.leaf_pairs.clear();
            let leaf_pairs = &mut self.leaf_pairs;
            let mut a = swept(&mut self.start, &mut self.end, &self.cache, body);
            let ws = &mut self.workspace;
            let mut b = Still(&room.tree);
            // Traversal tests swept spheres; the guard refines each pair it
            // keeps with the character node's interpolated spheres (found
            // from its tagged swept sphere): against the room node's sphere
            // and, in the pruned methods, against the plane of a big
            // triangle for every node of its division (all its leaves name
            // that triangle). Untagged, it is the discrete guard.
            let cache = &self.cache;
            let prunes = method.prunes_at_plane();
            let nodes = room.tree.nodes();
            let (tests, spheres) = (&mut guard_tests, &mut capsule_tests);
            let guard = |j: NodeId, s: &Sphere| match cache.node_of(s) {
                Some(id) => {
                    let e = cache.ends(id);
                    if prunes && let Some((d, _)) = room.division_node[j.index()] {
                        *tests += 1;
                        if planes[d as usize].sweep_toi(&e.start, &e.end).is_none() {
                            return false;
                        }
                    }
                    let sj = nodes[j.index()].sphere;
                    *spheres += 1;
                    sweeps_meet(&e.start, &e.end, &sj, &sj)
                }
                None if prunes && room.is_division_leaf(j) => {
                    *tests += 1;
                    room.leaf_meets_plane(j, s) == Some(true)
                }
                None => true,
            };
            let stats = traverse_guarded(&mut a, &mut b, ws, guard, |p| leaf_pairs.push(p));
            c.sphere_sphere = stats.sphere_tests + capsule_tests;
        }
        c.time.traversal_ms = t0.elapsed().as_secs_f64() * 1e3;
        c.plane_sphere = guard_tests;

        let t0 = std::time::Instant::now();
        self.sort_leaf_pairs();
        out.clear();
        let plane_leaves = method.big_leaf_test() == LeafTest::PlaneSphere;
        for i in 0..self.leaf_pairs.len() {
            let p = self.leaf_pairs[i];
            let big = mesh.triangle(TriangleId(p.primitive_b));
            let (s0, s1) = self.leaf_sweep(p.leaf_a);
            c.plane_sphere += 1;
            let Some(plane_toi) = sweep_meets_plane(&s0, &s1, &big) else {
                if !(plane_leaves && room.is_division_leaf(p.leaf_b)) {
                    ccd.plane_side_skips += 1;
                }
                continue;
            };
            if plane_leaves && room.is_division_leaf(p.leaf_b) {
                out.push(TimedPair {
                    a: p.primitive_a,
                    b: p.primitive_b,
                    toi: plane_toi,
                    by_plane: true,
                });
                continue;
            }
            c.tri_tri += 1;
            let a = self.moving_triangle(body, p.primitive_a);
            let still = corners(&big);
            let b = MovingTriangle {
                start: still,
                end: still,
            };
            if let Some(toi) = leaf_toi(&a, &b, true, params, ccd) {
                out.push(TimedPair {
                    a: p.primitive_a,
                    b: p.primitive_b,
                    toi,
                    by_plane: false,
                });
            }
        }
        c.pairs = out.len() as u64;
        c.refits = self.refits() - refits;
        c.skinned_vertices = self.skinned() - skinned;
        self.warm_up(out);
        c.time.narrow_ms = t0.elapsed().as_secs_f64() * 1e3;
        c
    }

    /// The pass against a moving rigid object (its tree in its own frame,
    /// swept along `path` in world coordinates): fills `out` with the pairs
    /// `(character triangle, object triangle)` touching during the step,
    /// every object vertex moving from `path.from · x` to `path.to · x`.
    /// Its big triangles move, so their leaves are answered by the
    /// triangle–triangle kernel in every method (a plane test would need
    /// the plane's motion).
    #[allow(clippy::too_many_arguments)]
    pub fn detect_object(
        &mut self,
        body: &Body<'_>,
        object: &EnvironmentTree,
        mesh: &TriMesh,
        path: &RigidPath,
        params: &CcdParams,
        ccd: &mut CcdCounters,
        out: &mut Vec<TimedPair>,
    ) -> FrameCounters {
        let mut c = FrameCounters::default();
        let refits = self.refits();
        let skinned = self.skinned();
        let t0 = std::time::Instant::now();
        {
            self.leaf_pairs.clear();
            let leaf_pairs = &mut self.leaf_pairs;
            let mut a = swept(&mut self.start, &mut self.end, &self.cache, body);
            let ws = &mut self.workspace;
            let mut b = SweptRigid {
                tree: &object.tree,
                path: *path,
            };
            let stats = traverse(&mut a, &mut b, ws, |p| leaf_pairs.push(p));
            c.sphere_sphere = stats.sphere_tests;
        }
        c.time.traversal_ms = t0.elapsed().as_secs_f64() * 1e3;
        let t0 = std::time::Instant::now();
        self.sort_leaf_pairs();
        out.clear();
        for i in 0..self.leaf_pairs.len() {
            let p = self.leaf_pairs[i];
            c.tri_tri += 1;
            let a = self.moving_triangle(body, p.primitive_a);
            let b = posed_triangle(mesh, p.primitive_b, &path.from, &path.to);
            if let Some(toi) = leaf_toi(&a, &b, false, params, ccd) {
                out.push(TimedPair {
                    a: p.primitive_a,
                    b: p.primitive_b,
                    toi,
                    by_plane: false,
                });
            }
        }
        c.pairs = out.len() as u64;
        c.refits = self.refits() - refits;
        c.skinned_vertices = self.skinned() - skinned;
        self.warm_up(out);
        c.time.narrow_ms = t0.elapsed().as_secs_f64() * 1e3;
        c
    }
}

/// The plane of every division's big triangle of `room` (whose mesh is
/// `mesh`), prepared once for [`CharacterSweep::detect_room`].
pub fn room_planes(room: &EnvironmentTree, mesh: &TriMesh) -> Vec<StillPlane> {
    room.divisions
        .iter()
        .map(|d| StillPlane::new(&mesh.triangle(d.original)))
        .collect()
}

/// The swept hierarchy of a step over one character's states.
fn swept<'a>(
    start: &'a mut RefitState,
    end: &'a mut RefitState,
    cache: &'a SweptCache,
    body: &Body<'a>,
) -> SweptCharacter<'a> {
    SweptCharacter {
        start: Refitter {
            tree: body.tree,
            skin: &body.pose.start.skin,
            state: start,
        },
        start_base: body.pose.start.base,
        end: Refitter {
            tree: body.tree,
            skin: &body.pose.end.skin,
            state: end,
        },
        end_base: body.pose.end.base,
        cache,
    }
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

/// Two characters over a step, after both sweeps' [`CharacterSweep::begin_step`]:
/// one traversal of both swept trees, then the triangle–triangle kernel at
/// every leaf pair. Fills `out` with the pairs `(triangle of a, triangle of
/// b)` touching during the step, sorted.
#[allow(clippy::too_many_arguments)]
pub fn detect_characters(
    a: &mut CharacterSweep,
    body_a: &Body<'_>,
    b: &mut CharacterSweep,
    body_b: &Body<'_>,
    params: &CcdParams,
    leaf_pairs: &mut Vec<LeafPair>,
    workspace: &mut Workspace,
    ccd: &mut CcdCounters,
    out: &mut Vec<TimedPair>,
) -> FrameCounters {
    let mut c = FrameCounters::default();
    let refits = a.refits() + b.refits();
    let skinned = a.skinned() + b.skinned();
    let t0 = std::time::Instant::now();
    {
        let mut ha = swept(&mut a.start, &mut a.end, &a.cache, body_a);
        let mut hb = swept(&mut b.start, &mut b.end, &b.cache, body_b);
        leaf_pairs.clear();
        // Both nodes' interpolated spheres, as against the room.
        let (ca, cb) = (&a.cache, &b.cache);
        let mut capsule_tests = 0u64;
        let guard = |j: NodeId, s: &Sphere| match ca.node_of(s) {
            Some(id) if cb.is_fresh(j) => {
                capsule_tests += 1;
                let (ea, eb) = (ca.ends(id), cb.ends(j));
                sweeps_meet(&ea.start, &ea.end, &eb.start, &eb.end)
            }
            _ => true,
        };
        let stats = traverse_guarded(&mut ha, &mut hb, workspace, guard, |p| leaf_pairs.push(p));
        c.sphere_sphere = stats.sphere_tests + capsule_tests;
    }
    c.time.traversal_ms = t0.elapsed().as_secs_f64() * 1e3;
    let t0 = std::time::Instant::now();
    out.clear();
    for p in leaf_pairs.iter() {
        c.tri_tri += 1;
        let ta = a.moving_triangle(body_a, p.primitive_a);
        let tb = b.moving_triangle(body_b, p.primitive_b);
        if let Some(toi) = leaf_toi(&ta, &tb, false, params, ccd) {
            out.push(TimedPair {
                a: p.primitive_a,
                b: p.primitive_b,
                toi,
                by_plane: false,
            });
        }
    }
    out.sort_unstable_by_key(|p| (p.a, p.b));
    c.pairs = out.len() as u64;
    c.refits = a.refits() + b.refits() - refits;
    c.skinned_vertices = a.skinned() + b.skinned() - skinned;
    c.time.narrow_ms = t0.elapsed().as_secs_f64() * 1e3;
    c
}
