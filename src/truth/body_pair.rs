//! The ground truth of one pair of bodies in a frame (a character against a
//! room, an object or another character) and a method's score on it: the
//! piece [`super::Truth`] is made of.
//!
//! The truth of a frame is the exact answer on parry's broad phase
//! ([`ParryReference::exact_pairs`]); parry's own answer
//! ([`ParryReference::pairs`]) is kept beside it, and where the two differ the
//! pair is classified (touching, near-degenerate, true error) and counted.
//! A method's pairs are scored against the truth (precision and recall at
//! three levels); each false positive gets its distance, each false negative
//! its cause; and its differences with parry's answer are classified too.

use serde::Serialize;

use super::disagreement::{Disagreement, Tolerances, compare, differences, triangle_distance};
use super::{FrameAccuracy, ParryReference, TruthError};
use cornertree::geometry::{Point, Triangle};
use cornertree::mesh::{TriMesh, TriangleId};

/// Why a method missed a pair of the truth.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum MissCause {
    /// The character triangle was left out by edge de-duplication (§4): a
    /// kept neighbour carries its edges, not its interior.
    Dedup,
    /// The environment triangle is big and the method's leaves inside it run
    /// the plane-sphere test (which cannot miss a contact of the leaf's
    /// sphere: listed so that a bug would show).
    PlaneSphereLeaf,
    /// The environment triangle is big (above the threshold) and split into a
    /// sphere-division hierarchy with triangle-triangle leaves.
    Threshold,
    /// None of the above: the broad or narrow phase lost it.
    Other,
}

/// A reported pair that does not collide.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FalsePositive {
    pub avatar: u32,
    pub environment: u32,
    /// Distance between the two triangles, metres.
    pub distance: f64,
}

/// A colliding pair that was not reported.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FalseNegative {
    pub avatar: u32,
    pub environment: u32,
    pub cause: MissCause,
}

/// What a method is scored with besides its pairs.
pub struct MethodContext<'a> {
    /// Whether each character triangle is in the method's tree (kept by
    /// de-duplication).
    pub kept: &'a [bool],
    /// Whether each environment triangle is big.
    pub big: &'a [bool],
    /// Whether big triangles' leaves run the plane-sphere test.
    pub plane_sphere: bool,
}

/// One method's frame against the truth.
#[derive(Clone, Debug, Default, Serialize)]
pub struct MethodTruth {
    pub accuracy: FrameAccuracy,
    pub false_positives: Vec<FalsePositive>,
    pub false_negatives: Vec<FalseNegative>,
    /// The method's pairs against parry's, classified.
    pub vs_parry: Disagreement,
}

/// The reference of one body pair in the current frame (reused from frame
/// to frame): the first body's triangles are queried against the second's.
pub struct BodyPairTruth {
    reference: ParryReference,
    tolerances: Tolerances,
    /// Exact colliding pairs: the truth.
    pub exact: Vec<(u32, u32)>,
    /// parry's colliding pairs.
    pub parry: Vec<(u32, u32)>,
    /// Where parry's answer differs from the exact one.
    pub parry_vs_exact: Disagreement,
    /// Largest distance between the triangles of a pair parry reports and
    /// the exact oracle does not (metres; 0 when there is none).
    pub parry_extra_max_distance: f64,
    extra: Vec<(u32, u32)>,
    missed: Vec<(u32, u32)>,
}

impl BodyPairTruth {
    pub fn new(environment: &TriMesh, character_indices: &[[u32; 3]]) -> Result<Self, TruthError> {
        Ok(Self {
            reference: ParryReference::new(environment, character_indices)?,
            tolerances: Tolerances::for_scale(environment.size() as f64),
            exact: Vec::new(),
            parry: Vec::new(),
            parry_vs_exact: Disagreement::default(),
            parry_extra_max_distance: 0.0,
            extra: Vec::new(),
            missed: Vec::new(),
        })
    }

    pub fn tolerances(&self) -> &Tolerances {
        &self.tolerances
    }

    /// Computes the truth and parry's answer for the posed character.
    pub fn update(
        &mut self,
        positions: &[Point],
        character_indices: &[[u32; 3]],
        environment: &TriMesh,
    ) -> Result<(), TruthError> {
        self.reference.update(positions)?;
        self.reference.exact_pairs(&mut self.exact);
        self.reference.pairs(&mut self.parry);
        self.parry_vs_exact = compare(
            &self.parry,
            &self.exact,
            positions,
            character_indices,
            environment,
            &self.tolerances,
        )?;
        self.parry_extra_max_distance = 0.0;
        for &(c, e, _) in &self.parry_vs_exact.extra.items {
            let t = character_indices[c as usize].map(|v| positions[v as usize]);
            let d = triangle_distance(
                &Triangle::new(t[0], t[1], t[2]),
                &environment.triangle(TriangleId(e)),
            );
            self.parry_extra_max_distance = self.parry_extra_max_distance.max(d);
        }
        Ok(())
    }

    /// Scores a method's `reported` pairs of this frame.
    pub fn score(
        &mut self,
        reported: &[(u32, u32)],
        positions: &[Point],
        character_indices: &[[u32; 3]],
        environment: &TriMesh,
        method: &MethodContext<'_>,
    ) -> Result<MethodTruth, TruthError> {
        let accuracy = FrameAccuracy::compare(reported, &self.exact);
        differences(reported, &self.exact, &mut self.extra, &mut self.missed);
        let triangle = |c: u32| -> Result<Triangle, TruthError> {
            let out = TruthError::PairOutOfRange {
                character: c,
                environment: 0,
            };
            let t = character_indices.get(c as usize).ok_or(out.clone())?;
            let p = |k: usize| positions.get(t[k] as usize).copied().ok_or(out.clone());
            Ok(Triangle::new(p(0)?, p(1)?, p(2)?))
        };
        let false_positives = self
            .extra
            .iter()
            .map(|&(c, e)| {
                Ok(FalsePositive {
                    avatar: c,
                    environment: e,
                    distance: triangle_distance(
                        &triangle(c)?,
                        &environment.triangle(TriangleId(e)),
                    ),
                })
            })
            .collect::<Result<Vec<_>, TruthError>>()?;
        let false_negatives = self
            .missed
            .iter()
            .map(|&(c, e)| {
                let big = method.big.get(e as usize).copied().unwrap_or(false);
                let cause = if !method.kept.get(c as usize).copied().unwrap_or(true) {
                    MissCause::Dedup
                } else if big && method.plane_sphere {
                    MissCause::PlaneSphereLeaf
                } else if big {
                    MissCause::Threshold
                } else {
                    MissCause::Other
                };
                FalseNegative {
                    avatar: c,
                    environment: e,
                    cause,
                }
            })
            .collect();
        let vs_parry = compare(
            reported,
            &self.parry,
            positions,
            character_indices,
            environment,
            &self.tolerances,
        )?;
        Ok(MethodTruth {
            accuracy,
            false_positives,
            false_negatives,
            vs_parry,
        })
    }

    /// Broad-phase candidates parry tested this frame.
    pub fn candidates(&self) -> usize {
        self.reference.candidates()
    }
}
