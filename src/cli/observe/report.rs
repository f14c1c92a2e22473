//! The run's report: per frame and method a record (counters, pairs and,
//! with the ground truth, accuracy), summed as it comes into the summary
//! table, and kept for the JSON report only when one is asked for, so a long
//! run's memory stays flat.

use cornertree_workbench::report::run::{
    FrameRecord, MethodRun, SummaryBuilder, TruthRecord, WorldFrameRecord,
};
use cornertree_workbench::session::Session;

use super::{Observer, Seen};

/// Every method's records and sums.
pub struct Report {
    pub runs: Vec<MethodRun>,
    pub summing: Vec<SummaryBuilder>,
    keep_frames: bool,
    /// Several characters or moving objects: records per pair kind.
    world: bool,
}

impl Report {
    /// For every method of `session` (scenario `name`); frames kept for
    /// the JSON report when `keep_frames`.
    pub fn new(session: &Session, name: &str, keep_frames: bool) -> Self {
        let runs: Vec<MethodRun> = session
            .worlds()
            .iter()
            .map(|w| MethodRun {
                scenario: name.to_string(),
                method: w.method(),
                dedup: session.scene.dedup,
                hierarchy_bytes: w.hierarchy_bytes(),
                frames: Vec::new(),
                continuous: None,
                summary: None,
            })
            .collect();
        let summing = runs
            .iter()
            .map(|r| SummaryBuilder::new(r.method, r.hierarchy_bytes))
            .collect();
        Self {
            runs,
            summing,
            keep_frames,
            world: session.scene.is_world(),
        }
    }

    /// Method `m`'s record of the frame.
    fn record(&self, seen: &Seen<'_>, m: usize) -> FrameRecord {
        let session = seen.session;
        let o = session.contacts(m);
        let score = seen.reference.map(|r| (r, &r.scores[m]));
        let mut record = if self.world {
            let mut r = FrameRecord::new(seen.k, &o.total, &[]);
            let mut w = WorldFrameRecord::new(o);
            if let Some((reference, s)) = score {
                w.accuracy_by_kind = Some(s.by_kind);
                w.removed_by_dedup_by_kind = Some(s.removed_by_dedup);
                w.parry_accuracy_by_kind = Some(reference.truth.parry_score());
            }
            r.world = Some(w);
            r
        } else {
            let pairs: Vec<(u32, u32)> = o
                .room_pairs
                .iter()
                .map(|p| (p.triangle, p.room_triangle))
                .collect();
            FrameRecord::new(seen.k, &o.total, &pairs)
        };
        if !self.world
            && let Some((reference, s)) = score
        {
            let room = reference.truth.room(0);
            record.truth = Some(TruthRecord::new(
                &s.details[0],
                room.exact.len(),
                &room.parry_vs_exact,
                room.parry_extra_max_distance,
            ));
        }
        record.continuous = seen.continuous[m].clone();
        record
    }
}

impl Observer for Report {
    fn method(&mut self, seen: &Seen<'_>, m: usize) -> anyhow::Result<()> {
        let record = self.record(seen, m);
        self.summing[m].add(&record);
        if self.keep_frames {
            self.runs[m].frames.push(record);
        }
        Ok(())
    }
}
