//! `cornertree run`: per-frame counters of each method and the summary table
//! in the shape of the paper's Tables 2–3 (maximum and mean per frame).

use std::fmt;

use serde::Serialize;

use crate::truth::WorldPairs;
use crate::truth::{
    Accuracy, AccuracyTotals, Classified, Disagreement, FalseNegative, FalsePositive,
    FrameAccuracy, MethodTruth, MissCause,
};
use cornertree::pipeline::FrameCounters;
use cornertree::pipeline::Method;
use cornertree::world::{ByKind, PairKind, StepContacts};

/// How many differences of each kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct KindCounts {
    pub touching: u64,
    pub near_degenerate: u64,
    pub true_error: u64,
}

impl KindCounts {
    pub fn of(c: &Classified) -> Self {
        Self {
            touching: c.touching as u64,
            near_degenerate: c.near_degenerate as u64,
            true_error: c.true_error as u64,
        }
    }

    pub fn add(&mut self, o: &KindCounts) {
        self.touching += o.touching;
        self.near_degenerate += o.near_degenerate;
        self.true_error += o.true_error;
    }

    pub fn total(&self) -> u64 {
        self.touching + self.near_degenerate + self.true_error
    }
}

/// Differences between two answers, counted by kind in both directions.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct DisagreementCounts {
    /// In the first answer only.
    pub extra: KindCounts,
    /// In the second answer only.
    pub missed: KindCounts,
}

impl DisagreementCounts {
    pub fn of(d: &Disagreement) -> Self {
        Self {
            extra: KindCounts::of(&d.extra),
            missed: KindCounts::of(&d.missed),
        }
    }

    pub fn add(&mut self, o: &DisagreementCounts) {
        self.extra.add(&o.extra);
        self.missed.add(&o.missed);
    }
}

/// One frame of one method against the ground truth.
#[derive(Clone, Debug, Serialize)]
pub struct TruthRecord {
    /// Exactly colliding pairs (the truth) this frame.
    pub reference_pairs: usize,
    pub accuracy: FrameAccuracy,
    /// Reported pairs that do not collide, with their distance (metres).
    pub false_positives: Vec<FalsePositive>,
    /// Colliding pairs not reported, with their cause.
    pub false_negatives: Vec<FalseNegative>,
    /// This method's pairs against parry's, classified.
    pub vs_parry: DisagreementCounts,
    /// parry's pairs against the exact ones, classified.
    pub parry_vs_exact: DisagreementCounts,
    /// Largest distance of a pair parry reports and the exact oracle does not.
    pub parry_extra_max_distance: f64,
}

impl TruthRecord {
    pub fn new(
        t: &MethodTruth,
        reference_pairs: usize,
        parry_vs_exact: &Disagreement,
        parry_extra_max_distance: f64,
    ) -> Self {
        Self {
            reference_pairs,
            accuracy: t.accuracy,
            false_positives: t.false_positives.clone(),
            false_negatives: t.false_negatives.clone(),
            vs_parry: DisagreementCounts::of(&t.vs_parry),
            parry_vs_exact: DisagreementCounts::of(parry_vs_exact),
            parry_extra_max_distance,
        }
    }
}

/// One frame of one method, as written to the JSON report.
#[derive(Clone, Debug, Serialize)]
pub struct FrameRecord {
    pub frame: usize,
    pub sphere_sphere: u64,
    pub tri_tri: u64,
    pub plane_sphere: u64,
    pub sphere_box: u64,
    pub box_box: u64,
    pub operations: u64,
    pub refits: u64,
    pub skinned_vertices: u64,
    /// Total of the five stages below.
    pub time_ms: f64,
    pub pose_ms: f64,
    pub skinning_ms: f64,
    pub refit_ms: f64,
    pub traversal_ms: f64,
    pub narrow_ms: f64,
    /// Colliding `[avatar triangle, environment triangle]` pairs.
    pub pairs: Vec<[u32; 2]>,
    /// Against the ground truth (absent with `--no-truth`).
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub truth: Option<TruthRecord>,
    /// In a world (several characters, or moving objects): counters, pairs
    /// and accuracy per pair kind; `pairs` is then empty.
    #[serde(flatten, skip_serializing_if = "Option::is_none")]
    pub world: Option<WorldFrameRecord>,
    /// With `run --ccd` (or `ccd = true`), from frame 1 on: the step from
    /// the previous frame, continuously (docs/ccd.md).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub continuous: Option<super::continuous::ContinuousFrameRecord>,
}

/// Tests and pairs of one pair kind in one frame.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct KindRecord {
    pub sphere_sphere: u64,
    pub tri_tri: u64,
    pub plane_sphere: u64,
    pub sphere_box: u64,
    pub box_box: u64,
    pub operations: u64,
    pub pairs: u64,
}

impl KindRecord {
    pub fn of(c: &FrameCounters) -> Self {
        Self {
            sphere_sphere: c.sphere_sphere,
            tri_tri: c.tri_tri,
            plane_sphere: c.plane_sphere,
            sphere_box: c.sphere_box,
            box_box: c.box_box,
            operations: c.operations(),
            pairs: c.pairs,
        }
    }
}

/// One frame of a world, per pair kind.
#[derive(Clone, Debug, Serialize)]
pub struct WorldFrameRecord {
    pub by_kind: ByKind<KindRecord>,
    /// Milliseconds of each kind's passes (CPU time summed over them; a
    /// measurement, unlike the counters beside it).
    pub time_ms_by_kind: ByKind<f64>,
    /// Root-sphere tests of the world's broad phase.
    pub broad_phase_tests: u64,
    /// Body pairs traversed (character-object, character-character).
    pub body_pairs: u64,
    /// Wall-clock milliseconds of the method's frame on `threads` threads.
    pub wall_ms: f64,
    pub pairs_by_kind: WorldPairs,
    /// The method's pairs against the exact ones, per kind (absent with `--no-truth`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accuracy_by_kind: Option<ByKind<Accuracy>>,
    /// parry's pairs against the exact ones, per kind.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parry_accuracy_by_kind: Option<ByKind<Accuracy>>,
    /// Per kind, the exact pairs a character triangle of which edge
    /// de-duplication removed (each also a false negative of the method).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub removed_by_dedup_by_kind: Option<ByKind<u64>>,
}

impl WorldFrameRecord {
    pub fn new(o: &StepContacts) -> Self {
        Self {
            by_kind: ByKind {
                environment: KindRecord::of(&o.by_kind.environment),
                objects: KindRecord::of(&o.by_kind.objects),
                characters: KindRecord::of(&o.by_kind.characters),
                self_contact: KindRecord::of(&o.by_kind.self_contact),
            },
            time_ms_by_kind: ByKind {
                environment: o.by_kind.environment.time.total_ms(),
                objects: o.by_kind.objects.time.total_ms(),
                characters: o.by_kind.characters.time.total_ms(),
                self_contact: o.by_kind.self_contact.time.total_ms(),
            },
            broad_phase_tests: o.broad_phase_tests,
            body_pairs: o.body_pairs,
            wall_ms: o.wall_ms,
            pairs_by_kind: WorldPairs {
                environment: o.room_pairs.clone(),
                objects: o.object_pairs.clone(),
                characters: o.character_pairs.clone(),
                self_contact: o.self_pairs.clone(),
            },
            accuracy_by_kind: None,
            parry_accuracy_by_kind: None,
            removed_by_dedup_by_kind: None,
        }
    }
}

impl FrameRecord {
    pub fn new(frame: usize, c: &FrameCounters, pairs: &[(u32, u32)]) -> Self {
        Self {
            frame,
            sphere_sphere: c.sphere_sphere,
            tri_tri: c.tri_tri,
            plane_sphere: c.plane_sphere,
            sphere_box: c.sphere_box,
            box_box: c.box_box,
            operations: c.operations(),
            refits: c.refits,
            skinned_vertices: c.skinned_vertices,
            time_ms: c.time.total_ms(),
            pose_ms: c.time.pose_ms,
            skinning_ms: c.time.skinning_ms,
            refit_ms: c.time.refit_ms,
            traversal_ms: c.time.traversal_ms,
            narrow_ms: c.time.narrow_ms,
            pairs: pairs.iter().map(|&(a, b)| [a, b]).collect(),
            truth: None,
            world: None,
            continuous: None,
        }
    }
}

/// Everything one method did over a run.
#[derive(Clone, Debug, Serialize)]
pub struct MethodRun {
    pub scenario: String,
    pub method: Method,
    pub dedup: bool,
    /// Bytes of the avatar's and the environment's sphere hierarchies.
    pub hierarchy_bytes: usize,
    pub frames: Vec<FrameRecord>,
    /// With `run --ccd`: continuous detection over the run.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub continuous: Option<super::continuous::ContinuousTotals>,
    /// The summary table's column of this method (maximum and mean per
    /// frame, accuracy over the run, the reference pairs de-duplication
    /// removed and recall over the kept triangles).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub summary: Option<Summary>,
}

/// Maximum and mean of one counter.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Stat {
    pub max: f64,
    pub mean: f64,
}

/// A [`Stat`] being gathered.
#[derive(Clone, Copy, Debug, Default)]
struct StatSum {
    max: f64,
    sum: f64,
    n: usize,
}

impl StatSum {
    fn add(&mut self, v: f64) {
        self.max = self.max.max(v);
        self.sum += v;
        self.n += 1;
    }

    fn stat(&self) -> Stat {
        Stat {
            max: self.max,
            mean: if self.n == 0 {
                0.0
            } else {
                self.sum / self.n as f64
            },
        }
    }
}

/// The summary row of one method.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub method: Method,
    pub frames: usize,
    pub hierarchy_bytes: usize,
    pub sphere_sphere: Stat,
    pub tri_tri: Stat,
    pub plane_sphere: Stat,
    /// Sphere-box tests (ours; the room's node boxes).
    pub sphere_box: Stat,
    /// Box-box tests (ours; two characters' posed node boxes).
    pub box_box: Stat,
    pub operations: Stat,
    pub refits: Stat,
    pub time_ms: Stat,
    /// Frames with at least one colliding pair.
    pub frames_with_contact: usize,
    /// Against the ground truth, over all frames (absent with `--no-truth`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub accuracy: Option<AccuracyTotals>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub vs_parry: Option<DisagreementCounts>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub parry_vs_exact: Option<DisagreementCounts>,
    /// Largest distance of a false positive (metres).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_false_positive_distance: Option<f64>,
    /// Reference pairs whose character triangle edge de-duplication
    /// removed (paper §4): no method can report them (each is a false
    /// negative of cause `dedup`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference_pairs_removed_by_dedup: Option<u64>,
    /// Pair recall over the reference pairs whose character triangle the
    /// method keeps: `tp / (tp + fn − removed)`.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub recall_over_kept_triangles: Option<f64>,
}

impl Summary {
    /// Reference pairs in all (`tp + fn` of the pairs), with the truth.
    pub fn reference_pairs(&self) -> Option<u64> {
        self.accuracy.map(|a| a.pairs.tp + a.pairs.fn_)
    }
}

/// One pair kind over a world run: pairs, the largest frame's operations,
/// and accuracy against the exact pairs.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct KindTotals {
    pub pairs: u64,
    pub max_operations: u64,
    pub accuracy: Accuracy,
    /// Exact pairs of triangles edge de-duplication removed.
    pub removed_by_dedup: u64,
}

impl KindTotals {
    /// Recall over the exact pairs whose character triangles are kept.
    pub fn recall_over_kept_triangles(&self) -> f64 {
        let a = self.accuracy;
        let kept = (a.tp + a.fn_).saturating_sub(self.removed_by_dedup);
        if kept == 0 {
            1.0
        } else {
            a.tp as f64 / kept as f64
        }
    }
}

/// A [`Summary`] gathered frame by frame, so a long run need not keep its
/// frames (`run` keeps them only for `--json`).
#[derive(Clone, Debug)]
pub struct SummaryBuilder {
    method: Method,
    hierarchy_bytes: usize,
    frames: usize,
    sphere_sphere: StatSum,
    tri_tri: StatSum,
    plane_sphere: StatSum,
    sphere_box: StatSum,
    box_box: StatSum,
    operations: StatSum,
    refits: StatSum,
    time_ms: StatSum,
    frames_with_contact: usize,
    /// Whether every frame so far had a truth record.
    all_truth: bool,
    accuracy: AccuracyTotals,
    vs_parry: DisagreementCounts,
    parry_vs_exact: DisagreementCounts,
    max_false_positive_distance: f64,
    /// Reference pairs of character triangles de-duplication removed.
    removed_by_dedup: u64,
    /// Per pair kind (world frames).
    pub by_kind: ByKind<KindTotals>,
}

impl SummaryBuilder {
    pub fn new(method: Method, hierarchy_bytes: usize) -> Self {
        Self {
            method,
            hierarchy_bytes,
            frames: 0,
            sphere_sphere: StatSum::default(),
            tri_tri: StatSum::default(),
            plane_sphere: StatSum::default(),
            sphere_box: StatSum::default(),
            box_box: StatSum::default(),
            operations: StatSum::default(),
            refits: StatSum::default(),
            time_ms: StatSum::default(),
            frames_with_contact: 0,
            all_truth: true,
            accuracy: AccuracyTotals::default(),
            vs_parry: DisagreementCounts::default(),
            parry_vs_exact: DisagreementCounts::default(),
            max_false_positive_distance: 0.0,
            removed_by_dedup: 0,
            by_kind: ByKind::default(),
        }
    }

    /// Adds one frame.
    pub fn add(&mut self, x: &FrameRecord) {
        self.frames += 1;
        self.sphere_sphere.add(x.sphere_sphere as f64);
        self.tri_tri.add(x.tri_tri as f64);
        self.plane_sphere.add(x.plane_sphere as f64);
        self.sphere_box.add(x.sphere_box as f64);
        self.box_box.add(x.box_box as f64);
        self.operations.add(x.operations as f64);
        self.refits.add(x.refits as f64);
        self.time_ms.add(x.time_ms);
        let contact = !x.pairs.is_empty()
            || x.world.as_ref().is_some_and(|w| {
                w.by_kind.environment.pairs + w.by_kind.objects.pairs + w.by_kind.characters.pairs
                    > 0
            });
        self.frames_with_contact += usize::from(contact);
        match &x.truth {
            Some(t) => {
                self.accuracy.add(&t.accuracy);
                self.vs_parry.add(&t.vs_parry);
                self.parry_vs_exact.add(&t.parry_vs_exact);
                for fp in &t.false_positives {
                    self.max_false_positive_distance =
                        self.max_false_positive_distance.max(fp.distance);
                }
                self.removed_by_dedup += t
                    .false_negatives
                    .iter()
                    .filter(|f| f.cause == MissCause::Dedup)
                    .count() as u64;
            }
            None => self.all_truth = false,
        }
        if let Some(w) = &x.world {
            for kind in PairKind::ALL {
                let k = self.by_kind.get_mut(kind);
                let r = w.by_kind.get(kind);
                k.pairs += r.pairs;
                k.max_operations = k.max_operations.max(r.operations);
                if let Some(a) = &w.accuracy_by_kind {
                    let a = a.get(kind);
                    k.accuracy.tp += a.tp;
                    k.accuracy.fp += a.fp;
                    k.accuracy.fn_ += a.fn_;
                }
                if let Some(d) = &w.removed_by_dedup_by_kind {
                    k.removed_by_dedup += d.get(kind);
                }
            }
        }
    }

    pub fn method(&self) -> Method {
        self.method
    }

    pub fn summary(&self) -> Summary {
        let truth = self.all_truth && self.frames > 0;
        Summary {
            method: self.method,
            frames: self.frames,
            hierarchy_bytes: self.hierarchy_bytes,
            sphere_sphere: self.sphere_sphere.stat(),
            tri_tri: self.tri_tri.stat(),
            plane_sphere: self.plane_sphere.stat(),
            sphere_box: self.sphere_box.stat(),
            box_box: self.box_box.stat(),
            operations: self.operations.stat(),
            refits: self.refits.stat(),
            time_ms: self.time_ms.stat(),
            frames_with_contact: self.frames_with_contact,
            accuracy: truth.then_some(self.accuracy),
            vs_parry: truth.then_some(self.vs_parry),
            parry_vs_exact: truth.then_some(self.parry_vs_exact),
            max_false_positive_distance: truth.then_some(self.max_false_positive_distance),
            reference_pairs_removed_by_dedup: truth.then_some(self.removed_by_dedup),
            recall_over_kept_triangles: truth.then(|| {
                let p = self.accuracy.pairs;
                let kept = (p.tp + p.fn_).saturating_sub(self.removed_by_dedup);
                if kept == 0 {
                    1.0
                } else {
                    p.tp as f64 / kept as f64
                }
            }),
        }
    }
}

impl MethodRun {
    pub fn summary(&self) -> Summary {
        let mut b = SummaryBuilder::new(self.method, self.hierarchy_bytes);
        for f in &self.frames {
            b.add(f);
        }
        b.summary()
    }
}

/// The summary table of a run: one column per method, rows as in Tables 2–3.
pub struct SummaryTable<'a>(pub &'a [Summary]);

impl SummaryTable<'_> {
    /// The rows: label and one cell per method.
    pub fn rows(&self) -> Vec<(&'static str, Vec<String>)> {
        let s = self.0;
        let col = |get: &dyn Fn(&Summary) -> String| s.iter().map(get).collect::<Vec<_>>();
        let mm = |x: Stat| format!("{:.0} / {:.0}", x.max, x.mean);
        let mut rows = vec![
            (
                "Data (hierarchies)",
                col(&|m| format!("{:.2} MiB", m.hierarchy_bytes as f64 / 1048576.0)),
            ),
            ("Sph-Sph tests (max / mean)", col(&|m| mm(m.sphere_sphere))),
            ("Tri-Tri tests (max / mean)", col(&|m| mm(m.tri_tri))),
            ("Pla-Sph tests (max / mean)", col(&|m| mm(m.plane_sphere))),
            ("Sph-Box tests (max / mean)", col(&|m| mm(m.sphere_box))),
            ("Box-Box tests (max / mean)", col(&|m| mm(m.box_box))),
            ("Operations (max / mean)", col(&|m| mm(m.operations))),
            ("Refits (max / mean)", col(&|m| mm(m.refits))),
            (
                "Frame ms (max / mean)",
                col(&|m| format!("{:.3} / {:.3}", m.time_ms.max, m.time_ms.mean)),
            ),
            (
                "Frames with contact",
                col(&|m| format!("{} of {}", m.frames_with_contact, m.frames)),
            ),
        ];
        if s.iter().all(|m| m.accuracy.is_some()) {
            let pr =
                |a: crate::truth::Accuracy| format!("{:.3} / {:.3}", a.precision(), a.recall());
            rows.push((
                "Pairs precision / recall",
                col(&|m| pr(m.accuracy.unwrap_or_default().pairs)),
            ));
            if s.iter()
                .any(|m| m.reference_pairs_removed_by_dedup.unwrap_or(0) > 0)
            {
                rows.push((
                    "Pairs lost to de-dup (§4)",
                    col(&|m| {
                        format!(
                            "{} of {}",
                            m.reference_pairs_removed_by_dedup.unwrap_or(0),
                            m.reference_pairs().unwrap_or(0)
                        )
                    }),
                ));
                rows.push((
                    "Pairs recall, kept tris",
                    col(&|m| format!("{:.3}", m.recall_over_kept_triangles.unwrap_or(1.0))),
                ));
            }
            rows.push((
                "Avatar tris prec. / recall",
                col(&|m| pr(m.accuracy.unwrap_or_default().triangles)),
            ));
            rows.push((
                "Frames precision / recall",
                col(&|m| pr(m.accuracy.unwrap_or_default().frames_with_contact)),
            ));
            rows.push((
                "Max false-positive dist.",
                col(&|m| match m.max_false_positive_distance {
                    Some(d) if d > 0.0 => format!("{:.2} mm", d * 1e3),
                    _ => "-".into(),
                }),
            ));
            rows.push((
                "vs parry: touch/degen/err",
                col(&|m| {
                    let d = m.vs_parry.unwrap_or_default();
                    format!(
                        "{}/{}/{}",
                        d.extra.touching + d.missed.touching,
                        d.extra.near_degenerate + d.missed.near_degenerate,
                        d.extra.true_error + d.missed.true_error
                    )
                }),
            ));
        }
        rows
    }

    /// A sentence under the table when de-duplication removed reference
    /// pairs: the misses it explains are not the methods'.
    pub fn dedup_note(&self) -> Option<String> {
        let m = self
            .0
            .iter()
            .find(|m| m.reference_pairs_removed_by_dedup.unwrap_or(0) > 0)?;
        let removed = m.reference_pairs_removed_by_dedup.unwrap_or(0);
        Some(format!(
            "{removed} of {} reference pairs involve character triangles removed by edge \
             de-duplication (paper §4; `--no-dedup` keeps them): no method reports them, and \
             \"Pairs recall, kept tris\" leaves them out.",
            m.reference_pairs().unwrap_or(0)
        ))
    }

    /// The same table in Markdown.
    pub fn markdown(&self) -> String {
        let mut out = String::from("| |");
        for m in self.0 {
            out += &format!(" {} |", m.method.name());
        }
        out += "\n|---|";
        for _ in self.0 {
            out += "---|";
        }
        out += "\n";
        for (label, cells) in self.rows() {
            out += &format!("| {label} | {} |\n", cells.join(" | "));
        }
        out
    }
}

impl fmt::Display for SummaryTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let rows = self.rows();
        // Each column as wide as its widest cell or name, two spaces apart.
        let widths: Vec<usize> = self
            .0
            .iter()
            .enumerate()
            .map(|(i, m)| {
                rows.iter()
                    .map(|(_, cells)| cells[i].chars().count())
                    .chain([m.method.name().len()])
                    .max()
                    .unwrap_or(0)
                    + 2
            })
            .collect();
        write!(f, "{:<28}", "")?;
        for (m, w) in self.0.iter().zip(&widths) {
            write!(f, "{:>w$}", m.method.name())?;
        }
        writeln!(f)?;
        for (label, cells) in rows {
            write!(f, "{label:<28}")?;
            for (c, w) in cells.iter().zip(&widths) {
                write!(f, "{c:>w$}")?;
            }
            writeln!(f)?;
        }
        if let Some(note) = self.dedup_note() {
            writeln!(f, "{note}")?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::truth::FalseNegative;

    /// A frame of six reference pairs: three found, three of triangles
    /// de-duplication removed, and one more missed for another cause.
    fn frame(k: usize, other_miss: bool) -> FrameRecord {
        let found = [(1, 9), (2, 9), (3, 9)];
        let mut reference: Vec<(u32, u32)> = found.to_vec();
        reference.extend([(10, 9), (11, 9), (12, 9)]);
        let mut false_negatives: Vec<FalseNegative> = [10, 11, 12]
            .map(|avatar| FalseNegative {
                avatar,
                environment: 9,
                cause: MissCause::Dedup,
            })
            .to_vec();
        if other_miss {
            reference.push((13, 9));
            false_negatives.push(FalseNegative {
                avatar: 13,
                environment: 9,
                cause: MissCause::Other,
            });
        }
        let mut r = FrameRecord::new(k, &FrameCounters::default(), &found);
        r.truth = Some(TruthRecord {
            reference_pairs: reference.len(),
            accuracy: FrameAccuracy::compare(&found, &reference),
            false_positives: Vec::new(),
            false_negatives,
            vs_parry: DisagreementCounts::default(),
            parry_vs_exact: DisagreementCounts::default(),
            parry_extra_max_distance: 0.0,
        });
        r
    }

    /// The pairs de-duplication removed are counted apart, recall over the
    /// kept triangles leaves them out (and only them), and the table says so.
    #[test]
    fn dedup_losses_are_separated_from_misses() {
        let mut b = SummaryBuilder::new(Method::UndividedPrunedTriTri, 0);
        b.add(&frame(0, false));
        let s = b.summary();
        assert_eq!(s.reference_pairs(), Some(6));
        assert_eq!(s.reference_pairs_removed_by_dedup, Some(3));
        assert_eq!(s.accuracy.unwrap().pairs.recall(), 0.5);
        assert_eq!(s.recall_over_kept_triangles, Some(1.0));
        let table = SummaryTable(std::slice::from_ref(&s)).to_string();
        assert!(table.contains("3 of 6"), "{table}");
        assert!(
            table.contains("3 of 6 reference pairs involve character triangles removed"),
            "{table}"
        );

        // A miss of another cause stays a miss over the kept triangles.
        b.add(&frame(1, true));
        let s = b.summary();
        assert_eq!(s.reference_pairs_removed_by_dedup, Some(6));
        assert_eq!(s.recall_over_kept_triangles, Some(6.0 / 7.0));
        let json = serde_json::to_value(&s).unwrap();
        assert_eq!(json["reference_pairs_removed_by_dedup"], 6);

        // No de-duplication loss: no row, no note.
        let mut clean = SummaryBuilder::new(Method::UndividedPrunedTriTri, 0);
        let mut f = FrameRecord::new(0, &FrameCounters::default(), &[(1, 2)]);
        f.truth = Some(TruthRecord {
            reference_pairs: 1,
            accuracy: FrameAccuracy::compare(&[(1, 2)], &[(1, 2)]),
            false_positives: Vec::new(),
            false_negatives: Vec::new(),
            vs_parry: DisagreementCounts::default(),
            parry_vs_exact: DisagreementCounts::default(),
            parry_extra_max_distance: 0.0,
        });
        clean.add(&f);
        let table = SummaryTable(&[clean.summary()]).to_string();
        assert!(!table.contains("de-dup"), "{table}");
    }
}
