//! The methods compared throughout (paper §5–6), one name for everything.

use std::fmt;

use serde::{Deserialize, Serialize};

use crate::big_triangle::DivisionKind;

/// How the environment's big triangles are handled.
#[derive(
    Clone,
    Copy,
    Debug,
    PartialEq,
    Eq,
    Hash,
    PartialOrd,
    Ord,
    Serialize,
    Deserialize,
    clap::ValueEnum,
)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Every environment triangle is one leaf; triangle-triangle tests (§3).
    Original,
    /// Big triangles get a full four-way hierarchy; leaves run the
    /// triangle-triangle test against the big triangle (§5, "Sphere Division").
    SphereDivision,
    /// Big triangles get a corner-tree; every character sphere paired with
    /// a corner-tree leaf is tested against the big triangle's plane
    /// (Algorithm 1) on the way down, and a limb whose sphere misses the
    /// plane is not descended; at character leaves that test is the answer
    /// (§5, the paper's method as we read it: docs/results.md).
    PlaneSphere,
    /// A full quaternary tree instead of the corner-tree, otherwise as
    /// [`Method::PlaneSphere`]: the alternative §5 argues against.
    QuaternaryPlaneSphere,
    /// Corner-trees with the plane-sphere test at leaf pairs only (§5 read
    /// literally): a character standing inside a corner-tree leaf's large
    /// sphere is descended to every leaf.
    PlaneSphereLeaf,
    /// Corner-trees pruned against the big triangle's plane on the way down
    /// as [`Method::PlaneSphere`], with triangle-triangle leaves: the exact
    /// answer (same pairs as `original`) at a fraction of the cost.
    PrunedTriTri,
}

/// The exact test run where a character leaf meets an environment leaf.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum LeafTest {
    /// Tropp triangle-triangle test (96 operations).
    TriTri,
    /// Character leaf sphere against the big triangle's plane (30 operations).
    PlaneSphere,
}

impl Method {
    pub const ALL: [Method; 6] = [
        Method::Original,
        Method::SphereDivision,
        Method::PlaneSphere,
        Method::QuaternaryPlaneSphere,
        Method::PlaneSphereLeaf,
        Method::PrunedTriTri,
    ];

    /// The hierarchy built inside big triangles, if any.
    pub fn division(self) -> Option<DivisionKind> {
        match self {
            Method::Original => None,
            Method::SphereDivision | Method::QuaternaryPlaneSphere => Some(DivisionKind::Full),
            Method::PlaneSphere | Method::PlaneSphereLeaf | Method::PrunedTriTri => {
                Some(DivisionKind::Corner)
            }
        }
    }

    /// The test at leaves inside a big triangle's hierarchy. Leaves of small
    /// triangles always run the triangle-triangle test.
    pub fn big_leaf_test(self) -> LeafTest {
        match self {
            Method::Original | Method::SphereDivision | Method::PrunedTriTri => LeafTest::TriTri,
            Method::PlaneSphere | Method::QuaternaryPlaneSphere | Method::PlaneSphereLeaf => {
                LeafTest::PlaneSphere
            }
        }
    }

    /// Whether character spheres meeting a big triangle's leaf are tested
    /// against its plane during traversal (not only at character leaves).
    pub fn prunes_at_plane(self) -> bool {
        matches!(
            self,
            Method::PlaneSphere | Method::QuaternaryPlaneSphere | Method::PrunedTriTri
        )
    }

    /// The name used on the command line, in files and in reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Original => "original",
            Method::SphereDivision => "sphere-division",
            Method::PlaneSphere => "plane-sphere",
            Method::QuaternaryPlaneSphere => "quaternary-plane-sphere",
            Method::PlaneSphereLeaf => "plane-sphere-leaf",
            Method::PrunedTriTri => "pruned-tri-tri",
        }
    }
}

impl fmt::Display for Method {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_through_serde() {
        for m in Method::ALL {
            let s = serde_json::to_string(&m).unwrap();
            assert_eq!(s, format!("\"{}\"", m.name()));
            assert_eq!(serde_json::from_str::<Method>(&s).unwrap(), m);
        }
    }
}
