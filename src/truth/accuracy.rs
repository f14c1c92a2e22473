//! Precision and recall of a method against ground truth, at three levels:
//!
//! * **pairs**: (character triangle, environment triangle) pairs;
//! * **triangles**: character triangles in contact (the distinct first
//!   elements of the pairs);
//! * **frames**: whether a frame has any contact at all (a frame where
//!   neither answer has contact is a true negative and counts nowhere).
//!
//! [`FrameAccuracy::compare`] scores one frame; [`AccuracyTotals`] sums frames.
//! Counts are summed, so a run's precision weighs every pair (triangle, frame)
//! equally rather than averaging per-frame ratios.
//!
//! Convention: precision is 1 when nothing was reported (`tp + fp = 0`) and
//! recall is 1 when there was nothing to find (`tp + fn = 0`): an empty answer
//! to an empty truth is perfect, and no division by zero reaches a report.

use std::borrow::Cow;

use serde::Serialize;

/// True positives, false positives and false negatives.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct Accuracy {
    pub tp: u64,
    pub fp: u64,
    #[serde(rename = "fn")]
    pub fn_: u64,
}

impl Accuracy {
    /// `tp / (tp + fp)`, or 1 when nothing was reported.
    pub fn precision(&self) -> f64 {
        ratio(self.tp, self.tp + self.fp)
    }

    /// `tp / (tp + fn)`, or 1 when there was nothing to find.
    pub fn recall(&self) -> f64 {
        ratio(self.tp, self.tp + self.fn_)
    }

    /// Counts of `reported` against `truth`, both sorted and distinct.
    pub fn of_sorted<T: Ord>(
        reported: impl Iterator<Item = T>,
        truth: impl Iterator<Item = T>,
    ) -> Self {
        let (mut r, mut t) = (reported.peekable(), truth.peekable());
        let mut acc = Self::default();
        loop {
            match (r.peek(), t.peek()) {
                (Some(x), Some(y)) => match x.cmp(y) {
                    std::cmp::Ordering::Equal => {
                        acc.tp += 1;
                        r.next();
                        t.next();
                    }
                    std::cmp::Ordering::Less => {
                        acc.fp += 1;
                        r.next();
                    }
                    std::cmp::Ordering::Greater => {
                        acc.fn_ += 1;
                        t.next();
                    }
                },
                (Some(_), None) => {
                    acc.fp += 1;
                    r.next();
                }
                (None, Some(_)) => {
                    acc.fn_ += 1;
                    t.next();
                }
                (None, None) => return acc,
            }
        }
    }
}

impl std::ops::AddAssign for Accuracy {
    fn add_assign(&mut self, o: Self) {
        self.tp += o.tp;
        self.fp += o.fp;
        self.fn_ += o.fn_;
    }
}

fn ratio(num: u64, den: u64) -> f64 {
    if den == 0 {
        1.0
    } else {
        num as f64 / den as f64
    }
}

/// The pairs sorted and distinct: borrowed when they already are (as
/// a world's contacts and `ParryReference::pairs` give them).
fn sorted(pairs: &[(u32, u32)]) -> Cow<'_, [(u32, u32)]> {
    if pairs.windows(2).all(|w| w[0] < w[1]) {
        Cow::Borrowed(pairs)
    } else {
        let mut v = pairs.to_vec();
        v.sort_unstable();
        v.dedup();
        Cow::Owned(v)
    }
}

/// Distinct first elements of sorted pairs.
fn firsts(pairs: &[(u32, u32)]) -> impl Iterator<Item = u32> + '_ {
    pairs
        .iter()
        .enumerate()
        .filter(|&(i, p)| i == 0 || pairs[i - 1].0 != p.0)
        .map(|(_, p)| p.0)
}

/// One frame's accuracy at the three levels.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct FrameAccuracy {
    pub pairs: Accuracy,
    pub triangles: Accuracy,
    /// At most one of `tp`, `fp`, `fn` is 1.
    pub frame: Accuracy,
}

impl FrameAccuracy {
    /// Scores `reported` against `truth`. Either list may be unsorted or
    /// repeat pairs (they are then sorted into a copy).
    pub fn compare(reported: &[(u32, u32)], truth: &[(u32, u32)]) -> Self {
        let (r, t) = (sorted(reported), sorted(truth));
        let frame = match (r.is_empty(), t.is_empty()) {
            (false, false) => Accuracy {
                tp: 1,
                ..Default::default()
            },
            (false, true) => Accuracy {
                fp: 1,
                ..Default::default()
            },
            (true, false) => Accuracy {
                fn_: 1,
                ..Default::default()
            },
            (true, true) => Accuracy::default(),
        };
        Self {
            pairs: Accuracy::of_sorted(r.iter(), t.iter()),
            triangles: Accuracy::of_sorted(firsts(&r), firsts(&t)),
            frame,
        }
    }
}

/// Sums of [`FrameAccuracy`] over the frames of a run.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
pub struct AccuracyTotals {
    /// Frames added.
    pub frames: u64,
    pub pairs: Accuracy,
    pub triangles: Accuracy,
    /// Frames with contact: `tp + fp + fn ≤ frames`.
    pub frames_with_contact: Accuracy,
}

impl AccuracyTotals {
    pub fn add(&mut self, f: &FrameAccuracy) {
        self.frames += 1;
        self.pairs += f.pairs;
        self.triangles += f.triangles;
        self.frames_with_contact += f.frame;
    }
}
