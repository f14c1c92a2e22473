//! What a run may allocate (issue #15): every size a scenario drives — the
//! room and its subdivisions, each character, each moving object, every
//! method's hierarchies over them, the big triangles' divisions and the
//! ground truth — is estimated from the counts it depends on and charged to a
//! [`RunBudget`] *before* it is built. Past [`RunLimits::max_bytes`] the
//! scenario is refused with one line naming the value that drove the size.
//!
//! The estimates are bytes per vertex, triangle or division node, measured
//! with a counting allocator on the shipped rooms and humanoids and rounded
//! up (`tests/run_budget.rs` checks that each is at least what building
//! takes, and not more than a few times it).

use cornertree::big_triangle::hierarchy::{DivisionKind, MAX_LEVELS, division_nodes};
use cornertree::geometry::Real;
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;

/// One GiB.
const GIB: usize = 1 << 30;

/// Limits of one run.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunLimits {
    /// Most bytes the scenario's bodies, hierarchies and ground truth may
    /// take together (estimated before they are built).
    pub max_bytes: usize,
}

impl Default for RunLimits {
    /// 4 GiB: the shipped scenarios need at most a tenth of it (the crowd's
    /// eight humanoids in the living room with four methods, about 0.4 GiB).
    fn default() -> Self {
        Self { max_bytes: 4 * GIB }
    }
}

/// Bytes per element, measured (see the module header).
pub mod cost {
    /// A generated room, per vertex (positions, triangles, objects; the
    /// generator's peak).
    pub const ROOM_PER_VERTEX: usize = 100;
    /// Triangles per vertex of a generated room, at most.
    pub const ROOM_TRIANGLES_PER_VERTEX: usize = 2;
    /// A static mesh (room, object, subdivided room), per triangle.
    pub const MESH_PER_TRIANGLE: usize = 60;
    /// One method's sphere tree over a static mesh, per triangle (the
    /// build's peak).
    pub const TREE_PER_TRIANGLE: usize = 250;
    /// One node of a big triangle's division, in its tree and grafted.
    pub const DIVISION_PER_NODE: usize = 200;
    /// A character, per vertex: mesh, weights, edge de-duplication, pose
    /// buffers (the generator's or the loader's peak).
    pub const CHARACTER_PER_VERTEX: usize = 300;
    /// One method's pipeline over a character, per triangle.
    pub const PIPELINE_PER_TRIANGLE: usize = 320;
    /// The ground truth, per room triangle and character.
    pub const TRUTH_PER_ROOM_TRIANGLE: usize = 220;
    /// The ground truth, per character triangle.
    pub const TRUTH_PER_CHARACTER_TRIANGLE: usize = 100;
    /// A further instance of a character already built, per vertex: its
    /// pose buffers (every vertex skinned for the truth and the baseline)
    /// and, in each method's world, its skinned vertices.
    pub const INSTANCE_PER_VERTEX: usize = 60;
    /// A further instance, per triangle and method: its refit state (the
    /// tree, marks and pass scratch are shared; `core/tests/instance_memory.rs`
    /// measures about 40 bytes per triangle on a 10k-vertex humanoid).
    pub const INSTANCE_PER_TRIANGLE: usize = 50;
}

/// The bytes charged so far against a [`RunLimits`].
#[derive(Debug)]
pub struct RunBudget {
    max: usize,
    used: usize,
}

impl RunBudget {
    pub fn new(limits: &RunLimits) -> Self {
        Self {
            max: limits.max_bytes,
            used: 0,
        }
    }

    /// Bytes charged so far.
    pub fn used(&self) -> usize {
        self.used
    }

    /// Bytes left.
    pub fn remaining(&self) -> usize {
        self.max - self.used
    }

    /// Charges `bytes` (`None`: more than `usize` holds) for `what` (a
    /// phrase naming the value that drives the size), or refuses in one line.
    pub fn charge(
        &mut self,
        bytes: Option<usize>,
        what: impl FnOnce() -> String,
    ) -> Result<(), String> {
        match bytes.and_then(|b| b.checked_add(self.used)) {
            Some(total) if total <= self.max => {
                self.used = total;
                Ok(())
            }
            total => Err(format!(
                "{} needs about {}{}, over the run's memory budget of {} (RunLimits::max_bytes, --memory-budget)",
                what(),
                bytes.map_or("more than 2^64 bytes".into(), show_bytes),
                match total {
                    Some(t) if self.used > 0 => format!(", {} in all", show_bytes(t)),
                    _ => String::new(),
                },
                show_bytes(self.max)
            )),
        }
    }
}

/// Bytes as messages show them: `3.2 GiB`, `120 MiB`, `512 bytes`.
pub fn show_bytes(b: usize) -> String {
    let b = b as f64;
    if b >= GIB as f64 {
        format!("{:.1} GiB", b / GIB as f64)
    } else if b >= (1 << 20) as f64 {
        format!("{:.0} MiB", b / f64::from(1 << 20))
    } else {
        format!("{b} bytes")
    }
}

/// `a * b`, `None` past `usize`.
fn mul(a: usize, b: usize) -> Option<usize> {
    a.checked_mul(b)
}

/// A static mesh of `triangles` and every method's tree over it (the room,
/// a moving object), with the ground truth of `characters` against it.
pub fn static_mesh_bytes(triangles: usize, methods: usize, characters: usize) -> Option<usize> {
    let per = cost::MESH_PER_TRIANGLE
        + methods * cost::TREE_PER_TRIANGLE
        + characters * cost::TRUTH_PER_ROOM_TRIANGLE;
    mul(triangles, per)
}

/// A character of `vertices` and `triangles`, every method's pipeline over
/// it, and its ground truth.
pub fn character_bytes(vertices: usize, triangles: usize, methods: usize) -> Option<usize> {
    let per_triangle = methods * cost::PIPELINE_PER_TRIANGLE + cost::TRUTH_PER_CHARACTER_TRIANGLE;
    mul(vertices, cost::CHARACTER_PER_VERTEX)?.checked_add(mul(triangles, per_triangle)?)
}

/// One more instance of a character of `vertices` and `triangles` whose
/// source is already built: what it holds alone in every method's world, and
/// its ground truth.
pub fn instance_bytes(vertices: usize, triangles: usize, methods: usize) -> Option<usize> {
    let per_triangle = methods * cost::INSTANCE_PER_TRIANGLE + cost::TRUTH_PER_CHARACTER_TRIANGLE;
    mul(vertices, cost::INSTANCE_PER_VERTEX)?.checked_add(mul(triangles, per_triangle)?)
}

/// Nodes of the big triangles' divisions in `mesh` over `methods`, at `threshold`.
pub fn division_node_count(mesh: &TriMesh, methods: &[Method], threshold: Real) -> u64 {
    let kinds: Vec<DivisionKind> = methods.iter().filter_map(|m| m.division()).collect();
    if kinds.is_empty() {
        return 0;
    }
    let mut nodes = 0u64;
    for t in 0..mesh.triangle_count() {
        let longest = mesh
            .triangle(cornertree::mesh::TriangleId(t as u32))
            .longest_edge();
        if longest > threshold {
            for &k in &kinds {
                nodes = nodes.saturating_add(division_nodes(longest, threshold, k, MAX_LEVELS));
            }
        }
    }
    nodes
}

/// Bytes of `nodes` division nodes.
pub fn division_bytes(nodes: u64) -> Option<usize> {
    usize::try_from(nodes)
        .ok()
        .and_then(|n| mul(n, cost::DIVISION_PER_NODE))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn charges_up_to_the_budget_then_refuses_in_one_line() {
        let mut b = RunBudget::new(&RunLimits { max_bytes: 3 << 30 });
        b.charge(Some(2 << 30), || "a room".into()).unwrap();
        assert_eq!(b.used(), 2 << 30);
        let e = b
            .charge(Some(1536 << 20), || "a character".into())
            .unwrap_err();
        assert_eq!(
            e,
            "a character needs about 1.5 GiB, 3.5 GiB in all, over the run's memory budget of 3.0 GiB (RunLimits::max_bytes, --memory-budget)"
        );
        assert_eq!(b.used(), 2 << 30, "a refused charge is not kept");
        let e = b.charge(None, || "x".into()).unwrap_err();
        assert!(e.contains("more than 2^64 bytes"), "{e}");
        assert_eq!(show_bytes(512), "512 bytes");
        assert_eq!(show_bytes(120 << 20), "120 MiB");
    }
}
