//! Which environment spheres a frame's traversal tested.
//!
//! The timed traversal in [`crate::pipeline::driver`] keeps no log (it would
//! cost time in the measured loop). After a frame, the recorder replays the
//! same deterministic traversal: the character side answers with the spheres
//! refit this frame, the environment side marks every node asked for.

use crate::geometry::Sphere;
use crate::sphere_tree::{Hierarchy, NodeId, SphereTree, Workspace, traverse};

/// Character spheres as refit this frame (valid on every node the frame's
/// traversal reached, which are exactly the nodes the replay asks for).
struct Refit<'a> {
    tree: &'a SphereTree,
    spheres: &'a [Sphere],
}

impl Hierarchy for Refit<'_> {
    fn tree(&self) -> &SphereTree {
        self.tree
    }
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.spheres[id.index()]
    }
}

/// The environment tree, marking each node whose sphere is asked for.
struct Marking<'a> {
    tree: &'a SphereTree,
    mark: &'a mut [bool],
}

impl Hierarchy for Marking<'_> {
    fn tree(&self) -> &SphereTree {
        self.tree
    }
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.mark[id.index()] = true;
        self.tree.node(id).sphere
    }
}

/// Reusable marks over the environment tree.
#[derive(Default)]
pub struct Visits {
    pub tested: Vec<bool>,
    workspace: Workspace,
}

impl Visits {
    /// Marks the environment nodes tested when `character` (with this frame's
    /// `spheres`) is traversed against `environment`.
    pub fn replay(&mut self, character: &SphereTree, spheres: &[Sphere], environment: &SphereTree) {
        self.tested.clear();
        self.tested.resize(environment.len(), false);
        let mut a = Refit {
            tree: character,
            spheres,
        };
        let mut b = Marking {
            tree: environment,
            mark: &mut self.tested,
        };
        traverse(&mut a, &mut b, &mut self.workspace, |_| {});
    }
}
