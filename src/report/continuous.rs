//! `run --ccd`'s part of the JSON report (docs/ccd.md, "In the driver"):
//! per frame step of each method, the pairs touching during the step with
//! their times of impact, the earliest, the pairs the method's discrete
//! frames missed at both ends, and the score against the sub-stepped
//! reference; over the run, totals.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::truth::substep_score::{OnlyClass, StepPair, StepScore};
use cornertree::pipeline::continuous_narrow::CcdCounters;
use cornertree::world::{StepContacts, SweepContacts};

/// A pair with its time of impact.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct TimedStepPair {
    #[serde(flatten)]
    pub pair: StepPair,
    pub toi: f64,
    pub by_plane: bool,
}

/// One method's step from frame `step[0]` to `step[1]`.
#[derive(Clone, Debug, Serialize)]
pub struct ContinuousFrameRecord {
    pub step: [usize; 2],
    pub sphere_sphere: u64,
    pub tri_tri: u64,
    pub plane_sphere: u64,
    /// A swept sphere against a room node's box.
    pub sphere_box: u64,
    pub operations: u64,
    /// Both ends.
    pub refits: u64,
    pub skinned_vertices: u64,
    pub wall_ms: f64,
    pub ccd: CcdCounters,
    /// Every pair touching during the step, sorted by kind and pair.
    pub pairs: Vec<TimedStepPair>,
    pub earliest_toi: Option<f64>,
    /// Pairs touching during the step that the method's discrete frames
    /// report at neither end.
    pub missed_by_discrete: Vec<StepPair>,
    /// Against the exact oracle on sub-steps (absent with `--no-truth`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<StepScore>,
}

/// Every pair of a discrete outcome, sorted.
pub fn discrete_step_pairs(o: &StepContacts, out: &mut Vec<StepPair>) {
    out.clear();
    out.extend(o.room_pairs.iter().map(|&p| StepPair::Environment(p)));
    out.extend(o.object_pairs.iter().map(|&p| StepPair::Objects(p)));
    out.extend(o.character_pairs.iter().map(|&p| StepPair::Characters(p)));
    out.extend(o.self_pairs.iter().map(|&p| StepPair::SelfContact(p)));
    out.sort_unstable();
}

/// Every pair of a continuous outcome, sorted.
pub fn continuous_step_pairs(o: &SweepContacts) -> Vec<TimedStepPair> {
    let mut v: Vec<TimedStepPair> = o
        .room_pairs
        .iter()
        .map(|p| TimedStepPair {
            pair: StepPair::Environment(p.pair),
            toi: p.toi,
            by_plane: p.by_plane,
        })
        .chain(o.object_pairs.iter().map(|p| TimedStepPair {
            pair: StepPair::Objects(p.pair),
            toi: p.toi,
            by_plane: p.by_plane,
        }))
        .chain(o.character_pairs.iter().map(|p| TimedStepPair {
            pair: StepPair::Characters(p.pair),
            toi: p.toi,
            by_plane: p.by_plane,
        }))
        .chain(o.self_pairs.iter().map(|p| TimedStepPair {
            pair: StepPair::SelfContact(p.pair),
            toi: p.toi,
            by_plane: p.by_plane,
        }))
        .collect();
    v.sort_by_key(|p| p.pair);
    v
}

impl ContinuousFrameRecord {
    /// The record of `o` (a step), given the method's discrete pairs at the
    /// step's two frames (sorted).
    pub fn new(
        k: usize,
        o: &SweepContacts,
        discrete_start: &[StepPair],
        discrete_end: &[StepPair],
        reference: Option<StepScore>,
    ) -> Self {
        let pairs = continuous_step_pairs(o);
        let missed_by_discrete = pairs
            .iter()
            .map(|p| p.pair)
            .filter(|p| {
                discrete_start.binary_search(p).is_err() && discrete_end.binary_search(p).is_err()
            })
            .collect();
        Self {
            step: [k.saturating_sub(1), k],
            sphere_sphere: o.total.sphere_sphere,
            tri_tri: o.total.tri_tri,
            plane_sphere: o.total.plane_sphere,
            sphere_box: o.total.sphere_box,
            operations: o.total.operations(),
            refits: o.total.refits,
            skinned_vertices: o.total.skinned_vertices,
            wall_ms: o.wall_ms,
            ccd: o.extra,
            earliest_toi: o.earliest(),
            pairs,
            missed_by_discrete,
            reference,
        }
    }
}

/// One method's continuous detection over a run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ContinuousTotals {
    pub steps: usize,
    pub pairs: usize,
    pub missed_by_discrete: usize,
    /// Steps with a pair discrete detection missed at both ends.
    pub steps_missed_by_discrete: usize,
    pub earliest_toi: Option<f64>,
    pub mean_wall_ms: f64,
    pub max_wall_ms: f64,
    /// Against the sub-stepped reference (absent with `--no-truth`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<ReferenceTotals>,
}

/// Recall and the pairs only continuous detection found, over a run.
#[derive(Clone, Debug, Default, Serialize)]
pub struct ReferenceTotals {
    pub substeps: u32,
    pub contacts: usize,
    pub found: usize,
    /// `found / contacts` over the run (1 when there are none).
    pub recall: f64,
    /// The lowest recall of any step.
    pub min_step_recall: f64,
    pub steps_below_full_recall: usize,
    /// Pairs only continuous detection found, per class.
    pub only_continuous: BTreeMap<String, usize>,
    /// Largest distance of a `within_tolerance` pair.
    pub max_within_tolerance_distance: f64,
}

impl ContinuousTotals {
    /// Adds a step.
    pub fn add(&mut self, r: &ContinuousFrameRecord, substeps: u32) {
        let n = self.steps as f64;
        self.steps += 1;
        self.pairs += r.pairs.len();
        self.missed_by_discrete += r.missed_by_discrete.len();
        self.steps_missed_by_discrete += usize::from(!r.missed_by_discrete.is_empty());
        self.earliest_toi = match (self.earliest_toi, r.earliest_toi) {
            (Some(a), Some(b)) => Some(a.min(b)),
            (a, b) => a.or(b),
        };
        self.mean_wall_ms = (self.mean_wall_ms * n + r.wall_ms) / (n + 1.0);
        self.max_wall_ms = self.max_wall_ms.max(r.wall_ms);
        if let Some(s) = &r.reference {
            let t = self.reference.get_or_insert_with(|| ReferenceTotals {
                substeps,
                min_step_recall: 1.0,
                ..ReferenceTotals::default()
            });
            t.contacts += s.reference;
            t.found += s.found;
            t.recall = if t.contacts == 0 {
                1.0
            } else {
                t.found as f64 / t.contacts as f64
            };
            t.min_step_recall = t.min_step_recall.min(s.recall);
            t.steps_below_full_recall += usize::from(s.found < s.reference);
            for o in &s.only_continuous {
                let name = serde_json::to_value(o.class)
                    .ok()
                    .and_then(|v| v.as_str().map(str::to_string))
                    .unwrap_or_default();
                *t.only_continuous.entry(name).or_default() += 1;
                if o.class == OnlyClass::WithinTolerance {
                    t.max_within_tolerance_distance =
                        t.max_within_tolerance_distance.max(o.distance);
                }
            }
        }
    }
}
