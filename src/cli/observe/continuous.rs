//! `run --ccd`'s observer of the frame loop ([`crate::cli::play`]):
//! continuous detection of every method over each frame step, its score
//! against the sub-stepped reference, its part of the JSON report and of
//! the recordings (docs/ccd.md, "In the driver").

use cornertree::geometry::Point;
use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree_workbench::record::ccd_recorder::{CcdRecorder, StepView};
use cornertree_workbench::report::continuous::{
    ContinuousFrameRecord, ContinuousTotals, discrete_step_pairs,
};
use cornertree_workbench::session::Session;
use cornertree_workbench::truth::substep::{StepBodies, SubstepTruth};
use cornertree_workbench::truth::substep_score::{StepPair, score_step};
use nalgebra::Isometry3;

/// Continuous detection beside a run.
pub struct ContinuousObserver {
    params: CcdParams,
    truth: Option<SubstepTruth>,
    substeps: u32,
    /// Every character's skinned vertices and every object's pose at the
    /// previous frame (for the reference and the recordings).
    prev_positions: Vec<Vec<Point>>,
    prev_poses: Vec<Isometry3<f32>>,
    /// Each method's discrete pairs at the previous frame and this one.
    prev_discrete: Vec<Vec<StepPair>>,
    discrete: Vec<Vec<StepPair>>,
    recorders: Vec<Option<CcdRecorder>>,
    pub totals: Vec<ContinuousTotals>,
}

impl ContinuousObserver {
    /// For every method of `session` (continuous detection turned on in
    /// its worlds); the reference if `truth`; a recorder for the methods
    /// `recorded` says.
    pub fn new(session: &mut Session, substeps: u32, truth: bool, recorded: &[bool]) -> Self {
        let params = CcdParams::default();
        session.enable_continuous(params);
        let n = session.worlds().len();
        let recorders = session
            .worlds()
            .iter()
            .zip(recorded)
            .map(|(w, &on)| {
                on.then(|| {
                    let views: Vec<_> = (0..session.scene.characters.len())
                        .map(|c| w.character(session.character(c)).expect("character"))
                        .collect();
                    let trees: Vec<_> = views.iter().map(|v| v.tree()).collect();
                    CcdRecorder::new(&session.scene, &trees)
                })
            })
            .collect();
        Self {
            params,
            truth: truth.then(|| SubstepTruth::new(&session.scene, substeps)),
            substeps,
            prev_positions: Vec::new(),
            prev_poses: Vec::new(),
            prev_discrete: vec![Vec::new(); n],
            discrete: vec![Vec::new(); n],
            recorders,
            totals: vec![ContinuousTotals::default(); n],
        }
    }

    /// Whether every vertex must be skinned each frame (the reference).
    pub fn wants_skin(&self) -> bool {
        self.truth.is_some()
    }

    /// The reference of the step ending at frame `k` (every vertex of
    /// `world` skinned for `k`).
    pub fn begin_frame(&mut self, world: &Session, k: usize) {
        if k == 0 || self.prev_positions.is_empty() {
            return;
        }
        if let Some(mut t) = self.truth.take() {
            t.update(&StepBodies::between(
                &self.prev_positions,
                &self.prev_poses,
                world,
            ));
            self.truth = Some(t);
        }
    }

    /// Method `m`'s step ending at frame `k`, after its discrete frame
    /// (whose pairs are read from `session`); logs to `rec` if given.
    pub fn method(
        &mut self,
        session: &mut Session,
        k: usize,
        m: usize,
        rec: Option<&rerun::RecordingStream>,
    ) -> anyhow::Result<Option<ContinuousFrameRecord>> {
        session.sweep(m, k)?;
        discrete_step_pairs(session.contacts(m), &mut self.discrete[m]);
        if k == 0 || self.prev_positions.is_empty() {
            return Ok(None);
        }
        let session = &*session;
        let world = session.world(m);
        let outcome = world.sweep_contacts().expect("continuous detection is on");
        let bodies = StepBodies::between(&self.prev_positions, &self.prev_poses, session);
        let score = self
            .truth
            .as_ref()
            .map(|t| score_step(t, outcome, &bodies, &self.params));
        let record = ContinuousFrameRecord::new(
            k,
            outcome,
            &self.prev_discrete[m],
            &self.discrete[m],
            score,
        );
        self.totals[m].add(&record, self.substeps);
        if let (Some(rec), Some(r)) = (rec, &self.recorders[m]) {
            let views: Vec<_> = (0..session.scene.characters.len())
                .map(|c| world.character(session.character(c)).expect("character"))
                .collect();
            let view = StepView {
                scene: &session.scene,
                outcome,
                start: bodies.start.clone(),
                end: bodies.end.clone(),
                object_start: &self.prev_poses,
                object_end: &session.object_poses,
                sweeps: views
                    .iter()
                    .map(|v| v.sweep_state().expect("continuous detection is on"))
                    .collect(),
                missed_by_discrete: &record.missed_by_discrete,
                recall: record.reference.as_ref().map(|s| s.recall),
            };
            r.log_step(rec, k, &view)?;
        }
        Ok(Some(record))
    }

    /// Ends frame `k`: its pose becomes the next step's start.
    pub fn end_frame(&mut self, world: &Session) {
        self.prev_positions
            .resize_with(world.buffers.len(), Vec::new);
        for (p, b) in self.prev_positions.iter_mut().zip(&world.buffers) {
            p.clone_from(&b.positions);
        }
        self.prev_poses.clone_from(&world.object_poses);
        std::mem::swap(&mut self.prev_discrete, &mut self.discrete);
    }

    /// One line per method for the run's summary.
    pub fn summary(&self, world: &Session) -> String {
        let mut out = format!(
            "continuous detection (per frame step; reference: exact oracle on {} sub-steps):\n",
            self.substeps
        );
        for (method, t) in world.methods().zip(&self.totals) {
            out += &format!(
                "  {:32} {} steps, {} pairs, {} missed by discrete at both ends ({} steps), earliest toi {}, {:.3} ms mean / {:.3} max",
                method.name(),
                t.steps,
                t.pairs,
                t.missed_by_discrete,
                t.steps_missed_by_discrete,
                t.earliest_toi
                    .map_or("-".to_string(), |x| format!("{x:.4}")),
                t.mean_wall_ms,
                t.max_wall_ms,
            );
            if let Some(r) = &t.reference {
                out += &format!(
                    "; recall {:.3} ({} of {} contacts, lowest step {:.3}); only continuous: {:?}",
                    r.recall, r.found, r.contacts, r.min_step_recall, r.only_continuous
                );
            }
            out += "\n";
        }
        out
    }
}
