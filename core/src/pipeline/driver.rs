//! The per-frame collision pipeline for one method (paper §3–6).
//!
//! Each frame: the character is posed and placed (joint matrices only); the
//! character's tree is traversed against the environment's, refitting each
//! character sphere the first time traversal reaches it (on demand); the
//! overlapping leaf pairs are gathered and then answered by the narrow phase:
//! the triangle-triangle test, or inside a big triangle's corner-tree or
//! quaternary tree the plane-sphere test of the character leaf's sphere against
//! the big triangle's plane. Only the corners of the character triangles the
//! narrow phase tests are skinned ([`OnDemandSkin`]). Counters follow the
//! paper's operation model.
//!
//! Time is split into posing (by the caller), skinning, refit, traversal and
//! narrow phase. Refit runs inside traversal; its share is measured with the
//! CPU's time-stamp counter around each refit (a few nanoseconds each) and
//! taken out of traversal. After the first frame nothing is allocated.
//!
//! On request ([`Pipeline::set_visit_log`]) the same traversal also marks the
//! environment nodes it tests ([`super::visit_log`]); otherwise its log is a
//! zero-sized no-op and the timed code is what it was.

use std::sync::Arc;
use std::time::Instant;

use nalgebra::Matrix4;

use crate::character::{Character, Clip, OnDemandSkin, PoseBuffers, SkinningModel};
use crate::geometry::ops;
use crate::geometry::tri_tri::prepared_intersect;
use crate::mesh::{EdgeDedup, TriMesh, TriangleId, dedup_edges};
use crate::prefetch::prefetch_at;
use crate::sphere_tree::character::CharacterTree;
use crate::sphere_tree::refit::{RefitState, Refitter};
use crate::sphere_tree::traverse::{LeafPair, TraversalStats};
use crate::sphere_tree::{
    BuildParams, Hierarchy, NodeId, PassMarks, SphereTree, Workspace, traverse, traverse_grouped,
    traverse_guarded,
};

use super::prepared_triangles::PreparedTriangles;
use super::visit_log::{NoLog, TestedNodes, VisitLog};
use super::{EnvironmentTree, LeafTest, Method};

/// What one frame cost.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FrameCounters {
    pub sphere_sphere: u64,
    pub tri_tri: u64,
    pub plane_sphere: u64,
    /// Character spheres refit this frame.
    pub refits: u64,
    /// Distinct colliding (character triangle, environment triangle) pairs.
    pub pairs: u64,
    /// Character vertices skinned this frame (corners of triangle-tested
    /// character triangles).
    pub skinned_vertices: u64,
    pub time: FrameTime,
}

/// Milliseconds spent per stage.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct FrameTime {
    /// Joint matrices: clip sampling, world and skin matrices, placement (set
    /// by the caller, who poses once for every method).
    pub pose_ms: f64,
    /// The vertices the narrow phase reads.
    pub skinning_ms: f64,
    pub refit_ms: f64,
    pub traversal_ms: f64,
    pub narrow_ms: f64,
}

impl FrameTime {
    pub fn total_ms(&self) -> f64 {
        self.pose_ms + self.skinning_ms + self.refit_ms + self.traversal_ms + self.narrow_ms
    }
}

impl FrameCounters {
    /// Basic operations in the paper's model: `10·SS + 96·TT + 30·PS` (§6).
    pub fn operations(&self) -> u64 {
        ops::SPHERE_SPHERE * self.sphere_sphere
            + ops::TRI_TRI * self.tri_tri
            + ops::PLANE_SPHERE * self.plane_sphere
    }
}

/// Settings shared by every method of a run.
#[derive(Clone, Copy, Debug)]
pub struct PipelineOptions {
    pub skinning: SkinningModel,
    /// Leave out triangles whose edges are all covered (§4), on the character.
    pub dedup: bool,
    /// Big-triangle threshold in metres.
    pub threshold: f32,
    pub build: BuildParams,
}

/// Everything one method keeps between frames.
pub struct Pipeline {
    pub method: Method,
    pub character_tree: CharacterTree,
    /// The room's hierarchy, shared by every character of a world.
    pub environment: Arc<EnvironmentTree>,
    pub(super) refit: RefitState,
    pub(super) skin: OnDemandSkin,
    pub(super) workspace: Workspace,
    leaf_pairs: Vec<LeafPair>,
    /// Leaf pairs of the last pass against a moving object.
    pub(super) object_leaf_pairs: Vec<LeafPair>,
    /// This frame's colliding pairs with the room, sorted, distinct.
    pub pairs: Vec<(u32, u32)>,
    /// Pairs already tested in this pass (methods that test each pair once).
    pub(super) repeats: PassMarks,
    /// Character spheres already descended against a big triangle in this
    /// traversal (methods that test each pair once).
    pub(super) group_marks: PassMarks,
    /// The narrow phase's triangles prepared for the triangle-triangle test:
    /// the character's, and the room's or a moving object's.
    pub(super) prepared: [PreparedTriangles; 2],
    /// Whether the first frame has sized the buffers.
    warmed_up: bool,
    /// Whether refit time is measured apart from traversal.
    pub(super) time_refit: bool,
    /// The environment nodes this frame's traversal tested, when asked for.
    visits: Option<TestedNodes>,
    pub(super) options: PipelineOptions,
}

/// How many leaf pairs ahead of the one being skinned or tested the
/// vertices and triangles it will read are prefetched (twice as far, the
/// triangle's indices that name them).
const LEAF_PAIRS_AHEAD: usize = 4;

/// While testing leaf pair `k` of `leaf_pairs`: starts loading the repeat
/// mark and the room triangle of pair `k + 2·AHEAD`, and that triangle's
/// corners for pair `k + AHEAD`.
#[inline(always)]
fn prefetch_narrow(leaf_pairs: &[LeafPair], repeats: &PassMarks, k: usize, env: &TriMesh) {
    if let Some(q) = leaf_pairs.get(k + 2 * LEAF_PAIRS_AHEAD) {
        repeats.prefetch(q.primitive_a);
        prefetch_at(env.indices(), q.primitive_b as usize);
    }
    if let Some(q) = leaf_pairs.get(k + LEAF_PAIRS_AHEAD) {
        for v in env.indices()[q.primitive_b as usize] {
            prefetch_at(env.positions(), v as usize);
        }
    }
}

/// [`Hierarchy`] over the character tree that refits on first request and,
/// if `TIMED`, counts the time-stamp ticks spent refitting (two `rdtsc` per
/// refit: a quarter of the traversal's time on a virtual machine, so `bench`
/// turns it off).
pub(super) struct TimedRefit<'a, const TIMED: bool> {
    pub(super) refitter: Refitter<'a>,
    pub(super) base: Matrix4<f32>,
    pub(super) ticks: u64,
}

impl<const TIMED: bool> Hierarchy for TimedRefit<'_, TIMED> {
    fn tree(&self) -> &SphereTree {
        &self.refitter.tree.tree
    }

    #[inline]
    fn sphere(&mut self, id: NodeId) -> crate::geometry::Sphere {
        if self.refitter.state.is_fresh(id) {
            return self.refitter.state.spheres[id.index()];
        }
        // Refit ahead (then only marked asked for), or refit now.
        let base = self.base;
        if !TIMED {
            return self.refitter.fresh(id, &base);
        }
        let t0 = ticks();
        let s = self.refitter.fresh(id, &base);
        self.ticks += ticks().wrapping_sub(t0);
        s
    }

    #[inline]
    fn prefetch(&self, id: NodeId) {
        self.refitter.prefetch(id);
    }
}

#[inline]
pub(super) fn ticks() -> u64 {
    #[cfg(target_arch = "x86_64")]
    {
        // SAFETY: RDTSC has no preconditions on x86_64.
        unsafe { std::arch::x86_64::_rdtsc() }
    }
    #[cfg(not(target_arch = "x86_64"))]
    {
        use std::sync::OnceLock;
        static START: OnceLock<Instant> = OnceLock::new();
        START.get_or_init(Instant::now).elapsed().as_nanos() as u64
    }
}

impl Pipeline {
    /// Builds the character's and the environment's hierarchies for `method`.
    pub fn new(
        character: &Character,
        environment: &TriMesh,
        method: Method,
        options: PipelineOptions,
    ) -> Self {
        let dedup = if options.dedup {
            dedup_edges(&character.mesh)
        } else {
            EdgeDedup::keep_all(&character.mesh)
        };
        let environment = Arc::new(EnvironmentTree::build(
            environment,
            method,
            options.threshold,
            options.build,
        ));
        Self::with_environment(character, environment, method, options, &dedup)
    }

    /// A pipeline for `character` against a room hierarchy already built
    /// for `method` (shared between the characters of a world); `dedup` is
    /// the character's edge de-duplication (keep-all when off).
    pub fn with_environment(
        character: &Character,
        environment: Arc<EnvironmentTree>,
        method: Method,
        options: PipelineOptions,
        dedup: &EdgeDedup,
    ) -> Self {
        let character_tree = CharacterTree::build_with_rule(
            character,
            dedup,
            options.skinning,
            method.character_build(options.build),
            method.refit_rule(),
        );
        let mut refit = RefitState::new(&character_tree, character.skeleton.len());
        refit.set_refit_ahead(method.refits_ahead());
        let group_marks = PassMarks::new(character_tree.tree.len());
        Self {
            method,
            character_tree,
            environment,
            refit,
            skin: OnDemandSkin::new(character.mesh.positions().len()),
            workspace: Workspace::new(),
            leaf_pairs: Vec::new(),
            object_leaf_pairs: Vec::new(),
            pairs: Vec::new(),
            repeats: PassMarks::new(character.mesh.triangle_count()),
            group_marks,
            prepared: Default::default(),
            warmed_up: false,
            time_refit: true,
            visits: None,
            options,
        }
    }

    /// Bytes of both sphere hierarchies (the "Data" row of Tables 2–3).
    pub fn hierarchy_bytes(&self) -> usize {
        self.character_tree.tree.bytes() + self.environment.bytes()
    }

    /// This frame's refit spheres of the character (valid where refit).
    pub fn refit_state(&self) -> &RefitState {
        &self.refit
    }

    /// Runs one frame of `character`, already posed and placed in `buffers`
    /// (its vertices need not be skinned), against the environment triangles
    /// `env` (positions may differ from the build pose only for static
    /// content; moving objects are not re-fit here).
    pub fn detect(
        &mut self,
        buffers: &PoseBuffers,
        character: &Character,
        env: &TriMesh,
    ) -> FrameCounters {
        self.begin_frame(buffers);
        self.detect_room(buffers, character, env)
    }

    /// Starts a frame: every sphere and skinned vertex of the last frame is
    /// stale from here on (refit and skinning then happen on demand in the
    /// passes of this frame, each at most once).
    pub fn begin_frame(&mut self, buffers: &PoseBuffers) {
        self.refit
            .begin_frame_with_base(&buffers.skin, &buffers.base);
        self.skin.begin_frame();
    }

    /// The pass against the room, after [`Self::begin_frame`]: fills
    /// [`Self::pairs`]. Refits and skinned vertices are counted from the
    /// frame's start.
    pub fn detect_room(
        &mut self,
        buffers: &PoseBuffers,
        character: &Character,
        env: &TriMesh,
    ) -> FrameCounters {
        let mut c = FrameCounters::default();
        // Last frame's nodes first, when the method refits ahead (timed
        // only then: two clock reads the other methods need not pay).
        let ahead_ms = if self.refit.refits_ahead_on() {
            let t0 = Instant::now();
            Refitter {
                tree: &self.character_tree,
                skin: &buffers.skin,
                state: &mut self.refit,
            }
            .refit_ahead(&buffers.base);
            t0.elapsed().as_secs_f64() * 1e3
        } else {
            0.0
        };
        let t0 = Instant::now();
        let tick0 = ticks();
        let (stats, guard_tests, refit_ticks) = match (self.time_refit, self.visits.take()) {
            (true, None) => self.broad_phase::<true, _>(buffers, &mut NoLog),
            (false, None) => self.broad_phase::<false, _>(buffers, &mut NoLog),
            (timed, Some(mut log)) => {
                log.begin_frame();
                let out = if timed {
                    self.broad_phase::<true, _>(buffers, &mut log)
                } else {
                    self.broad_phase::<false, _>(buffers, &mut log)
                };
                self.visits = Some(log);
                out
            }
        };
        let elapsed = t0.elapsed().as_secs_f64() * 1e3;
        if self.time_refit {
            let total_ticks = ticks().wrapping_sub(tick0).max(1);
            let on_demand = elapsed * (refit_ticks as f64 / total_ticks as f64).min(1.0);
            c.time.refit_ms = on_demand + ahead_ms;
            c.time.traversal_ms = elapsed - on_demand;
        } else {
            c.time.traversal_ms = elapsed + ahead_ms;
        }
        c.sphere_sphere = stats.sphere_tests;
        c.plane_sphere = guard_tests;
        c.refits = self.refit.refits;

        // Skinning: the corners of every character triangle to be tested,
        // or every vertex when stamp checks would cost more (three per
        // triangle test, about a quarter of skinning a vertex): when every
        // leaf pair is a triangle test and there are more than 4/3 as many as
        // vertices (the original method: 531,732 tests a frame).
        let t0 = Instant::now();
        let model = self.options.skinning;
        let indices = character.mesh.indices();
        let all_tri_tri = self.method.big_leaf_test() == LeafTest::TriTri;
        // Prefetching ahead pays where leaf pairs are few and each reads new
        // memory: the methods that test each pair once. The others meet the
        // same triangles over and over (thousands of pairs), which stay
        // cached, and the hints would only cost (docs/performance.md,
        // "Cold caches").
        let ahead = self.method.tests_each_pair_once();
        if all_tri_tri && 3 * self.leaf_pairs.len() > 4 * character.mesh.positions().len() {
            self.skin.skin_all(buffers, character, model);
        } else {
            for (k, p) in self.leaf_pairs.iter().enumerate() {
                if ahead {
                    self.prefetch_skinning(k, character);
                }
                if !self.environment.answers_by_plane(self.method, p.leaf_b) {
                    for v in indices[p.primitive_a as usize] {
                        self.skin.ensure(buffers, character, model, v);
                    }
                }
            }
        }
        c.skinned_vertices = self.skin.skinned();
        c.time.skinning_ms = t0.elapsed().as_secs_f64() * 1e3;

        // Narrow phase.
        let t0 = Instant::now();
        self.pairs.clear();
        let once = self.method.tests_each_pair_once();
        if once {
            self.repeats.begin_pass();
        }
        let [prepared_c, prepared_e] = &mut self.prepared;
        prepared_c.clear();
        prepared_e.clear();
        for (k, p) in self.leaf_pairs.iter().enumerate() {
            if ahead {
                prefetch_narrow(&self.leaf_pairs, &self.repeats, k, env);
            }
            if once
                && self.environment.is_division_leaf(p.leaf_b)
                && !self.repeats.first_time(p.primitive_a, p.primitive_b)
            {
                continue;
            }
            let hit = if self.environment.answers_by_plane(self.method, p.leaf_b) {
                if self.method.prunes_at_plane() {
                    // Already tested on the way down.
                    true
                } else {
                    c.plane_sphere += 1;
                    let s = &self.refit.spheres[p.leaf_a.index()];
                    self.environment.leaf_meets_plane(p.leaf_b, s) == Some(true)
                }
            } else {
                c.tri_tri += 1;
                let ct = prepared_c.get(p.primitive_a, || {
                    self.skin.triangle(indices[p.primitive_a as usize])
                });
                let et = prepared_e.get(p.primitive_b, || env.triangle(TriangleId(p.primitive_b)));
                prepared_intersect(ct, et)
            };
            if hit {
                self.pairs.push((p.primitive_a, p.primitive_b));
            }
        }
        // Hits before removing repeats (a big triangle's leaves all name it).
        let hits = self.pairs.len();
        self.pairs.sort_unstable();
        self.pairs.dedup();
        c.pairs = self.pairs.len() as u64;
        if !self.warmed_up {
            // After the first frame, room for twice its work, so that later
            // frames of a similar pose do not grow the buffers.
            self.warmed_up = true;
            self.leaf_pairs.reserve(self.leaf_pairs.len().max(64));
            self.pairs.reserve((2 * hits).max(64));
            self.workspace.reserve_headroom();
        }
        c.time.narrow_ms = t0.elapsed().as_secs_f64() * 1e3;
        c
    }

    /// Traversal with on-demand refit (paper §3): fills `leaf_pairs` and
    /// tells `log` the environment node of every sphere-sphere test; returns
    /// the traversal's counters, the plane-sphere tests made on the way down
    /// and, if `TIMED`, the time-stamp ticks spent refitting.
    fn broad_phase<const TIMED: bool, L: VisitLog>(
        &mut self,
        buffers: &PoseBuffers,
        log: &mut L,
    ) -> (TraversalStats, u64, u64) {
        let mut od = TimedRefit::<TIMED> {
            refitter: Refitter {
                tree: &self.character_tree,
                skin: &buffers.skin,
                state: &mut self.refit,
            },
            base: buffers.base,
            ticks: 0,
        };
        self.leaf_pairs.clear();
        let leaf_pairs = &mut self.leaf_pairs;
        let envt = &self.environment;
        let mut env_side = LoggedTree { env: envt, log };
        let mut guard_tests = 0u64;
        let stats = if self.method.tests_each_pair_once() {
            let guard = envt.plane_prism_guard(&mut guard_tests);
            traverse_grouped(
                &mut od,
                &mut env_side,
                &mut self.workspace,
                &mut self.group_marks,
                |j| envt.leaf_group(j),
                guard,
                |p| leaf_pairs.push(p),
            )
        } else if self.method.prunes_at_plane() {
            let guard = envt.plane_guard(&mut guard_tests);
            traverse_guarded(&mut od, &mut env_side, &mut self.workspace, guard, |p| {
                leaf_pairs.push(p)
            })
        } else {
            traverse(&mut od, &mut env_side, &mut self.workspace, |p| {
                leaf_pairs.push(p)
            })
        };
        (stats, guard_tests, od.ticks)
    }

    /// Whether to split refit time from traversal time (on by default). The
    /// split costs two time-stamp reads per refit sphere; with it off,
    /// `refit_ms` is 0 and traversal includes refit.
    pub fn set_refit_timing(&mut self, on: bool) {
        self.time_refit = on;
    }

    /// Whether the traversal marks the environment nodes it tests (off by
    /// default; a recorder turns it on). The counters are the same either
    /// way; the traversal's time then includes one store per test.
    pub fn set_visit_log(&mut self, on: bool) {
        if !on {
            self.visits = None;
        } else if self.visits.is_none() {
            self.visits = Some(TestedNodes::new(self.environment.tree.len()));
        }
    }

    /// The environment nodes the last frame's traversal tested, if
    /// [`Self::set_visit_log`] is on.
    pub fn visit_log(&self) -> Option<&TestedNodes> {
        self.visits.as_ref()
    }

    /// While skinning for leaf pair `k`: starts loading the character
    /// triangle of pair `k + 2·AHEAD` and the vertices of pair `k + AHEAD`'s
    /// (whose triangle has arrived by then); see [`crate::prefetch`]. Its
    /// callers (the methods that test each pair once) answer every leaf
    /// pair by the triangle test, so every pair's vertices will be read.
    #[inline(always)]
    fn prefetch_skinning(&self, k: usize, character: &Character) {
        let indices = character.mesh.indices();
        if let Some(q) = self.leaf_pairs.get(k + 2 * LEAF_PAIRS_AHEAD) {
            prefetch_at(indices, q.primitive_a as usize);
        }
        if let Some(q) = self.leaf_pairs.get(k + LEAF_PAIRS_AHEAD) {
            for v in indices[q.primitive_a as usize] {
                self.skin.prefetch(character, self.options.skinning, v);
            }
        }
    }

    /// This frame's overlapping leaf pairs, as traversal handed them to the
    /// narrow phase.
    pub fn leaf_pairs(&self) -> &[LeafPair] {
        &self.leaf_pairs
    }

    /// This frame's skinned vertices (those the narrow phase read).
    pub fn skinned(&self) -> &OnDemandSkin {
        &self.skin
    }

    /// Refits every character sphere for this frame's pose, overwriting the
    /// frame's on-demand refit state (the whole-tree refit the `skinning`
    /// bench measures; recordings never call it).
    pub fn refit_all(&mut self, buffers: &PoseBuffers) {
        Refitter {
            tree: &self.character_tree,
            skin: &buffers.skin,
            state: &mut self.refit,
        }
        .refit_all(&buffers.base);
    }

    pub fn options(&self) -> &PipelineOptions {
        &self.options
    }
}

/// A static tree as a [`Hierarchy`] through a shared borrow (so the leaf
/// guard can read the environment while traversal runs), telling `log` of
/// every sphere-sphere test its nodes take part in.
struct LoggedTree<'a, L> {
    env: &'a EnvironmentTree,
    log: &'a mut L,
}

impl<L: VisitLog> Hierarchy for LoggedTree<'_, L> {
    #[inline]
    fn tree(&self) -> &SphereTree {
        &self.env.tree
    }
    #[inline]
    fn sphere(&mut self, id: NodeId) -> crate::geometry::Sphere {
        self.env.tree.nodes()[id.index()].sphere
    }
    #[inline]
    fn prefetch(&self, id: NodeId) {
        self.env.prefetch(id);
    }
    #[inline]
    fn tested(&mut self, id: NodeId) {
        self.log.tested(id);
    }
}

/// Poses and places a character for one frame (joint matrices; no vertex is
/// skinned), returning the milliseconds it took.
pub fn pose_frame(
    buffers: &mut PoseBuffers,
    character: &Character,
    clip: Option<&Clip>,
    t: f32,
    placement: &Matrix4<f32>,
) -> f64 {
    let t0 = Instant::now();
    buffers.pose(character, clip, t);
    buffers.place(placement);
    t0.elapsed().as_secs_f64() * 1e3
}
