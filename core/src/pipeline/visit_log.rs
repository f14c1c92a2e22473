//! Which environment nodes a frame's traversal tested, logged by the timed
//! traversal itself (docs/recordings.md, "Tested spheres").
//!
//! The broad phase is generic over a [`VisitLog`]: [`NoLog`], a zero-sized
//! type whose calls compile to nothing, in the measured path; [`TestedNodes`]
//! when a recorder asks for it ([`crate::world::CollisionWorld::set_visit_log`]).
//! Either way it is the same traversal, so what a recording calls *tested* is
//! what was measured.
//!
//! An environment node is *tested* in a frame when its sphere took part in a
//! sphere-sphere test of the frame's traversal (the root pair's test
//! included). Each sphere-sphere test involves exactly one environment node,
//! so the log sees as many tests as `FrameCounters::sphere_sphere` counts.
//! Plane-sphere tests (the guard of the pruned methods on the way down, the
//! leaf test of the others) are not logged: each is made on an environment
//! node right after that node's sphere-sphere test passed, so its node is
//! already marked.

use crate::sphere_tree::NodeId;

/// Told of the environment node of every sphere-sphere test.
pub trait VisitLog {
    /// Environment node `env`'s sphere took part in one more sphere-sphere
    /// test.
    fn tested(&mut self, env: NodeId);
}

/// The measured path's log: nothing.
pub struct NoLog;

impl VisitLog for NoLog {
    #[inline(always)]
    fn tested(&mut self, _env: NodeId) {}
}

/// The environment nodes tested this frame, with a frame stamp per node (no
/// clearing between frames, no allocation after construction).
#[derive(Clone, Debug)]
pub struct TestedNodes {
    stamp: Vec<u32>,
    frame: u32,
    tests: u64,
}

impl TestedNodes {
    /// A log over an environment tree of `nodes` nodes.
    pub fn new(nodes: usize) -> Self {
        Self {
            stamp: vec![0; nodes],
            // Nothing tested before the first frame.
            frame: 1,
            tests: 0,
        }
    }

    /// Starts a frame: no node is tested yet.
    pub fn begin_frame(&mut self) {
        self.frame = self.frame.wrapping_add(1).max(1);
        if self.frame == 1 {
            self.stamp.fill(0);
        }
        self.tests = 0;
    }

    /// Whether node `id` was tested this frame.
    #[inline]
    pub fn is_tested(&self, id: NodeId) -> bool {
        self.stamp[id.index()] == self.frame
    }

    /// The nodes tested this frame, in index order.
    pub fn tested_nodes(&self) -> impl Iterator<Item = NodeId> + '_ {
        let frame = self.frame;
        self.stamp
            .iter()
            .enumerate()
            .filter(move |&(_, &s)| s == frame)
            .map(|(i, _)| NodeId(i as u32))
    }

    /// Sphere-sphere tests seen this frame.
    pub fn sphere_tests(&self) -> u64 {
        self.tests
    }
}

impl VisitLog for TestedNodes {
    #[inline]
    fn tested(&mut self, env: NodeId) {
        self.stamp[env.index()] = self.frame;
        self.tests += 1;
    }
}
