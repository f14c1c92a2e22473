//! The methods compared throughout (paper §5–6), one name for everything.
//!
//! Each variant's doc says which sentence of the paper it rests on; the
//! variants marked *ours* are extensions the paper does not describe
//! (docs/results.md, "Reading the plane-sphere method").

use std::fmt;
use std::str::FromStr;

use crate::choice::{Choice, UnknownName, parse_choice, show};

use crate::big_triangle::DivisionKind;
use crate::sphere_tree::BuildParams;
use crate::sphere_tree::refit::RefitRule;

/// The collapse ratio of our methods' character trees
/// ([`Method::character_build`], [`BuildParams::WIDE`]): on touching, crowd
/// and handshake the frame was fastest at 0.6 of the ratios 0.4–0.9 tried,
/// with the living room level (docs/performance-journal.md, "A wider character
/// tree").
pub const WIDE_CHARACTER_COLLAPSE: f32 = BuildParams::WIDE.collapse_ratio;

/// How the environment's big triangles are handled.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum Method {
    /// Every environment triangle is one leaf, answered by the
    /// triangle-triangle test. §3: "Once the algorithm finds two colliding
    /// leaf-nodes ... the exact intersection test between primitives is
    /// called."
    Original,
    /// Big triangles get a full four-way hierarchy whose leaves run the
    /// triangle-triangle test against the big triangle. §5, Sphere Division:
    /// "the triangle is divided in four new triangles joining the
    /// intermediate points of the edges ... the leaf-nodes ... point to the
    /// big triangle T."
    SphereDivision,
    /// Big triangles get a corner-tree; where a character leaf sphere meets a
    /// corner-tree leaf, Algorithm 1 (the plane-sphere test) replaces the
    /// triangle-triangle test. §5: "when the collision detection algorithm
    /// reaches leaf-nodes and calls the plane-sphere test, we can be sure
    /// that the sphere is in front of T"; "only triangles that have an edge
    /// that matches one of T's edges are divided ... Corner-tree".
    PlaneSphere,
    /// A full quaternary tree instead of the corner-tree, plane-sphere test
    /// at leaf pairs as `plane-sphere`. §5: "we can create a
    /// quaternary tree inside the enclosing sphere S_T. Then, when the
    /// collision detection algorithm reaches leaf-nodes and calls the
    /// plane-sphere test ..." (the alternative the corner-tree improves on).
    QuaternaryPlaneSphere,
    /// Ours: `plane-sphere` plus every character sphere (not only
    /// leaves) paired with a corner-tree leaf tested against the big
    /// triangle's plane on the way down; a limb whose sphere misses the
    /// plane is not descended. No sentence of the paper describes it; §6
    /// ("decreases the number of tests made in both the broad phase and the
    /// narrow phase") is what it tries to reproduce.
    PlaneSpherePruned,
    /// Ours: `quaternary-plane-sphere` with the pruning of
    /// `plane-sphere-pruned`: checks §5's claim that the corner-tree
    /// beats the quaternary tree ("one plane-sphere test (30 operations)"
    /// against "four sphere-sphere tests") once both prune at the plane.
    QuaternaryPlaneSpherePruned,
    /// Ours: corner-trees pruned at the plane as `plane-sphere-pruned`,
    /// with the triangle-triangle test at the leaves (§3's narrow phase):
    /// the exact pairs of `original` at a fraction of the cost. A character
    /// sphere is descended once per big triangle (against the division's
    /// root sphere, within the triangle's plane and edge planes) and each
    /// (triangle, big triangle) pair is tested once
    /// ([`Method::tests_each_pair_once`]). Elsewhere in a static body's tree,
    /// a character sphere must also reach the node's box of its triangles
    /// (`sphere_tree::node_boxes`; docs/performance-journal.md, "Room node
    /// boxes").
    PrunedTriTri,
    /// Ours: `pruned-tri-tri` with big triangles left whole
    /// ([`DivisionKind::Whole`]): a big triangle is one leaf, and a character
    /// sphere reaching it is descended within the triangle's plane and edge
    /// planes, as `pruned-tri-tri` descends it against a corner-tree's root.
    /// Those planes, not the corner-tree's spheres, decide which character
    /// spheres go on, so without the corner-tree the same pairs (`original`'s)
    /// cost fewer tests (docs/performance-journal.md, "Big triangles left whole").
    UndividedPrunedTriTri,
}

/// The exact test run where a character leaf meets an environment leaf.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum LeafTest {
    /// Triangle-triangle test (96 operations in the paper's model).
    TriTri,
    /// Character leaf sphere against the big triangle's plane (30 operations).
    PlaneSphere,
}

impl Method {
    /// Every method: the paper's four, then ours.
    pub const ALL: [Method; 8] = [
        Method::Original,
        Method::SphereDivision,
        Method::PlaneSphere,
        Method::QuaternaryPlaneSphere,
        Method::PlaneSpherePruned,
        Method::QuaternaryPlaneSpherePruned,
        Method::PrunedTriTri,
        Method::UndividedPrunedTriTri,
    ];

    /// The hierarchy built inside big triangles, if any.
    pub fn division(self) -> Option<DivisionKind> {
        match self {
            Method::Original => None,
            Method::SphereDivision
            | Method::QuaternaryPlaneSphere
            | Method::QuaternaryPlaneSpherePruned => Some(DivisionKind::Full),
            Method::PlaneSphere | Method::PlaneSpherePruned | Method::PrunedTriTri => {
                Some(DivisionKind::Corner)
            }
            Method::UndividedPrunedTriTri => Some(DivisionKind::Whole),
        }
    }

    /// The test at leaves inside a big triangle's hierarchy. Leaves of small
    /// triangles always run the triangle-triangle test.
    pub fn big_leaf_test(self) -> LeafTest {
        match self {
            Method::Original
            | Method::SphereDivision
            | Method::PrunedTriTri
            | Method::UndividedPrunedTriTri => LeafTest::TriTri,
            Method::PlaneSphere
            | Method::QuaternaryPlaneSphere
            | Method::PlaneSpherePruned
            | Method::QuaternaryPlaneSpherePruned => LeafTest::PlaneSphere,
        }
    }

    /// Whether character spheres meeting a big triangle's leaf are tested
    /// against its plane during traversal (not only at character leaves).
    pub fn prunes_at_plane(self) -> bool {
        matches!(
            self,
            Method::PlaneSpherePruned
                | Method::QuaternaryPlaneSpherePruned
                | Method::PrunedTriTri
                | Method::UndividedPrunedTriTri
        )
    }

    /// Whether a character sphere meeting several leaves of one big
    /// triangle's division is descended once (`sphere_tree::grouped`, with
    /// the plane and edge-plane guard of
    /// [`super::EnvironmentTree::plane_prism_guard`]) and a (character
    /// triangle, big triangle) pair reached twice is tested once
    /// (`sphere_tree::PassMarks`); the paper's methods descend and test
    /// every leaf pair.
    pub fn tests_each_pair_once(self) -> bool {
        matches!(self, Method::PrunedTriTri | Method::UndividedPrunedTriTri)
    }

    /// Whether the character nodes asked for last frame are refit at the
    /// frame's start, before traversal
    /// ([`Refitter::refit_ahead`](crate::sphere_tree::refit::Refitter::refit_ahead));
    /// the paper's methods refit on demand only, so their refit counts
    /// stay those of §3.
    pub fn refits_ahead(self) -> bool {
        matches!(self, Method::PrunedTriTri | Method::UndividedPrunedTriTri)
    }

    /// How the character's spheres are refit: the paper's corner rule (§3)
    /// for the paper's methods, so that their spheres and counts stay §3's;
    /// blended balls ([`RefitRule::BlendedBalls`]: a ball per joint, moved
    /// by that joint, blended by the corners of the node's weight ranges)
    /// for ours, whose spheres hug a bent limb and ignore a far joint's
    /// small weight (docs/performance-journal.md, "Joint balls" and
    /// "Blended balls").
    pub fn refit_rule(self) -> RefitRule {
        match self {
            Method::PrunedTriTri | Method::UndividedPrunedTriTri => RefitRule::BlendedBalls,
            _ => RefitRule::PaperCorners,
        }
    }

    /// How the character's tree is built from `paper`, the build of the
    /// paper's methods (our reading of §3's "similar" spheres: a child
    /// more than 0.9 of its parent's radius is collapsed into it). Ours
    /// collapse a child over [`WIDE_CHARACTER_COLLAPSE`] of its parent's: a
    /// wider, shallower tree, with fewer inner spheres to refit and test
    /// on the way down (docs/performance-journal.md, "A wider character tree").
    /// The room's tree is built from `paper` for every method.
    pub fn character_build(self, paper: BuildParams) -> BuildParams {
        match self {
            Method::PrunedTriTri | Method::UndividedPrunedTriTri => BuildParams::WIDE,
            _ => paper,
        }
    }

    /// The name used on the command line, in files and in reports.
    pub fn name(self) -> &'static str {
        <Self as Choice>::name(self)
    }
}

impl Choice for Method {
    const WHAT: &'static str = "method";
    const ALL: &'static [Self] = &Method::ALL;

    fn name(self) -> &'static str {
        match self {
            Method::Original => "original",
            Method::SphereDivision => "sphere-division",
            Method::PlaneSphere => "plane-sphere",
            Method::QuaternaryPlaneSphere => "quaternary-plane-sphere",
            Method::PlaneSpherePruned => "plane-sphere-pruned",
            Method::QuaternaryPlaneSpherePruned => "quaternary-plane-sphere-pruned",
            Method::PrunedTriTri => "pruned-tri-tri",
            Method::UndividedPrunedTriTri => "undivided-pruned-tri-tri",
        }
    }

    fn summary(self) -> &'static str {
        match self {
            Method::Original => {
                "every room triangle one leaf, the triangle-triangle test at leaf pairs (§3)"
            }
            Method::SphereDivision => {
                "big triangles split four ways, triangle-triangle leaves (§5, sphere division)"
            }
            Method::PlaneSphere => {
                "corner-trees in big triangles, the plane-sphere test where a character leaf meets a corner-tree leaf (§5 as written)"
            }
            Method::QuaternaryPlaneSphere => {
                "full quaternary trees instead of corner-trees, plane-sphere leaves (§5's alternative)"
            }
            Method::PlaneSpherePruned => {
                "ours: plane-sphere with every character sphere tested against the plane on the way down"
            }
            Method::QuaternaryPlaneSpherePruned => {
                "ours: quaternary-plane-sphere pruned at the plane"
            }
            Method::PrunedTriTri => {
                "ours: corner-trees pruned at the plane and edge planes, the room's other nodes at their boxes, triangle-triangle leaves, each pair once (original's pairs)"
            }
            Method::UndividedPrunedTriTri => {
                "ours: pruned-tri-tri with big triangles left whole (original's pairs, fewest tests)"
            }
        }
    }
}

impl FromStr for Method {
    type Err = UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_choice(s)
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        show(*self, f)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_through_from_str() {
        for m in Method::ALL {
            assert_eq!(m.name().parse::<Method>(), Ok(m));
            assert_eq!(m.to_string(), m.name());
        }
        assert!("plane".parse::<Method>().is_err());
    }

    #[cfg(feature = "serde")]
    #[test]
    fn names_round_trip_through_serde() {
        for m in Method::ALL {
            let s = serde_json::to_string(&m).unwrap();
            assert_eq!(s, format!("\"{}\"", m.name()));
            assert_eq!(serde_json::from_str::<Method>(&s).unwrap(), m);
        }
    }
}
