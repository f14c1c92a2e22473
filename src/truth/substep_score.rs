//! A continuous method's step against the sub-stepped reference
//! ([`super::substep`]): recall, the contacts it missed, and each pair only
//! it found, classified by refining around its time of impact.
//!
//! Classes of a pair continuous detection reports and the `N + 1`
//! sub-steps do not:
//! * `brief_contact`: the exact oracle finds a contact on a finer sampling
//!   of `[toi, toi + 2/N]` (`[toi, 1]` for a plane answer): a true contact
//!   the sub-steps skipped;
//! * `within_tolerance`: no contact found, the smallest distance there
//!   (sampled, then refined by golden section) is within the kernel's
//!   certified bound `√3 δ`: a false positive the tolerance allows;
//! * `plane_sphere`: answered by a plane test (plane-sphere methods), the
//!   distance is that method's approximation (as in discrete mode);
//! * `beyond_tolerance`: none of the above (never seen; a defect if it is).

use serde::Serialize;

use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::world::{CharacterPair, ObjectPair, RoomPair, SelfPair, SweepContacts, Timed};

use super::substep::{Found, MovingCorners, StepBodies, SubstepTruth, corners_at, touch_at};

/// A pair of any kind.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum StepPair {
    Environment(RoomPair),
    Objects(ObjectPair),
    Characters(CharacterPair),
    #[serde(rename = "self")]
    SelfContact(SelfPair),
}

impl StepPair {
    /// Both triangles at both ends of the step.
    pub fn corners(&self, bodies: &StepBodies<'_>) -> (MovingCorners, MovingCorners) {
        match *self {
            StepPair::Environment(p) => (
                bodies.character_triangle(p.character.index(), p.triangle),
                bodies.room_triangle(p.room_triangle),
            ),
            StepPair::Objects(p) => (
                bodies.character_triangle(p.character.index(), p.triangle),
                bodies.object_triangle(p.object.index(), p.object_triangle),
            ),
            StepPair::Characters(p) => (
                bodies.character_triangle(p.a.index(), p.triangle_a),
                bodies.character_triangle(p.b.index(), p.triangle_b),
            ),
            StepPair::SelfContact(p) => (
                bodies.character_triangle(p.character.index(), p.triangle_a),
                bodies.character_triangle(p.character.index(), p.triangle_b),
            ),
        }
    }
}

/// How a pair only continuous detection found is explained.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum OnlyClass {
    BriefContact,
    WithinTolerance,
    PlaneSphere,
    BeyondTolerance,
}

/// A pair only continuous detection found.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct OnlyContinuous {
    pub pair: StepPair,
    pub toi: f64,
    pub class: OnlyClass,
    /// A time of contact found by refining (`brief_contact`), else the time
    /// of the smallest distance.
    pub time: f64,
    /// 0 for a contact; else the smallest distance found near `time`.
    pub distance: f64,
}

/// A reference contact continuous detection missed.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Missed {
    pub pair: StepPair,
    pub first_substep: u32,
}

/// One method's step against the reference.
#[derive(Clone, Debug, Default, Serialize)]
pub struct StepScore {
    /// Contacts the sub-steps found.
    pub reference: usize,
    /// Of those, found by continuous detection.
    pub found: usize,
    pub recall: f64,
    pub missed: Vec<Missed>,
    pub only_continuous: Vec<OnlyContinuous>,
}

/// Samples of the refinement window.
const REFINE_SAMPLES: u32 = 1024;

/// Scores `outcome` against `truth` (both of the step between the poses of
/// `bodies`); `params` gives the tolerance of the false-positive bound.
pub fn score_step(
    truth: &SubstepTruth,
    outcome: &SweepContacts,
    bodies: &StepBodies<'_>,
    params: &CcdParams,
) -> StepScore {
    let mut s = StepScore::default();
    let n = truth.substeps;
    let mut compare = |reference: Vec<(StepPair, u32)>, reported: Vec<(StepPair, f64, bool)>| {
        let (mut i, mut j) = (0, 0);
        while i < reference.len() || j < reported.len() {
            let take_ref =
                j >= reported.len() || (i < reference.len() && reference[i].0 < reported[j].0);
            let take_rep =
                i >= reference.len() || (j < reported.len() && reported[j].0 < reference[i].0);
            if take_ref {
                s.reference += 1;
                s.missed.push(Missed {
                    pair: reference[i].0,
                    first_substep: reference[i].1,
                });
                i += 1;
            } else if take_rep {
                let (pair, toi, by_plane) = reported[j];
                s.only_continuous
                    .push(classify(pair, toi, by_plane, bodies, n, params));
                j += 1;
            } else {
                s.reference += 1;
                s.found += 1;
                i += 1;
                j += 1;
            }
        }
    };
    fn refs<P: Copy>(v: &[Found<P>], f: impl Fn(P) -> StepPair) -> Vec<(StepPair, u32)> {
        v.iter().map(|x| (f(x.pair), x.first_substep)).collect()
    }
    fn reps<P: Copy>(v: &[Timed<P>], f: impl Fn(P) -> StepPair) -> Vec<(StepPair, f64, bool)> {
        v.iter().map(|x| (f(x.pair), x.toi, x.by_plane)).collect()
    }
    compare(
        refs(&truth.room_pairs, StepPair::Environment),
        reps(&outcome.room_pairs, StepPair::Environment),
    );
    compare(
        refs(&truth.object_pairs, StepPair::Objects),
        reps(&outcome.object_pairs, StepPair::Objects),
    );
    compare(
        refs(&truth.character_pairs, StepPair::Characters),
        reps(&outcome.character_pairs, StepPair::Characters),
    );
    compare(
        refs(&truth.self_pairs, StepPair::SelfContact),
        reps(&outcome.self_pairs, StepPair::SelfContact),
    );
    s.recall = if s.reference == 0 {
        1.0
    } else {
        s.found as f64 / s.reference as f64
    };
    s
}

/// Refines around `toi` (module doc).
fn classify(
    pair: StepPair,
    toi: f64,
    by_plane: bool,
    bodies: &StepBodies<'_>,
    n: u32,
    params: &CcdParams,
) -> OnlyContinuous {
    let (a, b) = pair.corners(bodies);
    let lo = toi.clamp(0.0, 1.0);
    let hi = if by_plane {
        1.0
    } else {
        (lo + 2.0 / n as f64).min(1.0)
    };
    let at = |i: u32| lo + (hi - lo) * i as f64 / REFINE_SAMPLES as f64;
    if let Some(i) = (0..=REFINE_SAMPLES).find(|&i| touch_at(&a, &b, at(i))) {
        return OnlyContinuous {
            pair,
            toi,
            class: OnlyClass::BriefContact,
            time: at(i),
            distance: 0.0,
        };
    }
    let dist = |t: f64| triangle_distance(&corners_at(&a, t), &corners_at(&b, t));
    let (mut best_t, mut best) = (lo, f64::INFINITY);
    for i in 0..=REFINE_SAMPLES {
        let d = dist(at(i));
        if d < best {
            (best_t, best) = (at(i), d);
        }
    }
    // Golden section on the samples' neighbourhood.
    let h = (hi - lo) / REFINE_SAMPLES as f64;
    let (mut x0, mut x1) = ((best_t - h).max(lo), (best_t + h).min(hi));
    let g = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..60 {
        let (p, q) = (x1 - g * (x1 - x0), x0 + g * (x1 - x0));
        if dist(p) < dist(q) {
            x1 = q;
        } else {
            x0 = p;
        }
    }
    let mid = 0.5 * (x0 + x1);
    let dm = dist(mid);
    if dm < best {
        (best_t, best) = (mid, dm);
    }
    let bound = 3f64.sqrt() * params.tolerance * (1.0 + 1e-9);
    let class = if best <= bound {
        OnlyClass::WithinTolerance
    } else if by_plane {
        OnlyClass::PlaneSphere
    } else {
        OnlyClass::BeyondTolerance
    };
    OnlyContinuous {
        pair,
        toi,
        class,
        time: best_t,
        distance: best,
    }
}

type P = [f64; 3];

fn sub(a: P, b: P) -> P {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
fn dot(a: P, b: P) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
fn add_scaled(a: P, d: P, s: f64) -> P {
    [a[0] + d[0] * s, a[1] + d[1] * s, a[2] + d[2] * s]
}
fn dist(a: P, b: P) -> f64 {
    dot(sub(a, b), sub(a, b)).sqrt()
}

/// Closest point of segment `ab` to `p`.
fn on_segment(p: P, a: P, b: P) -> P {
    let d = sub(b, a);
    let dd = dot(d, d);
    if dd == 0.0 {
        return a;
    }
    add_scaled(a, d, (dot(sub(p, a), d) / dd).clamp(0.0, 1.0))
}

/// Distance from `p` to the closed triangle `t` (face if the projection is
/// inside, else the nearest edge).
fn point_triangle(p: P, t: &[P; 3]) -> f64 {
    let (e1, e2) = (sub(t[1], t[0]), sub(t[2], t[0]));
    let n = [
        e1[1] * e2[2] - e1[2] * e2[1],
        e1[2] * e2[0] - e1[0] * e2[2],
        e1[0] * e2[1] - e1[1] * e2[0],
    ];
    let nn = dot(n, n);
    let edges = [(0, 1), (1, 2), (2, 0)];
    let edge_best = edges
        .iter()
        .map(|&(i, j)| dist(p, on_segment(p, t[i], t[j])))
        .fold(f64::INFINITY, f64::min);
    if nn == 0.0 {
        return edge_best;
    }
    let q = add_scaled(p, n, -dot(sub(p, t[0]), n) / nn);
    let inside = edges.iter().all(|&(i, j)| {
        let e = sub(t[j], t[i]);
        let w = sub(q, t[i]);
        let c = [
            e[1] * w[2] - e[2] * w[1],
            e[2] * w[0] - e[0] * w[2],
            e[0] * w[1] - e[1] * w[0],
        ];
        dot(c, n) >= 0.0
    });
    if inside { dist(p, q) } else { edge_best }
}

/// Distance between closed segments `pq` and `rs`.
fn segment_segment(p: P, q: P, r: P, s: P) -> f64 {
    let ends = dist(p, on_segment(p, r, s))
        .min(dist(q, on_segment(q, r, s)))
        .min(dist(r, on_segment(r, p, q)))
        .min(dist(s, on_segment(s, p, q)));
    let (d1, d2, w) = (sub(q, p), sub(s, r), sub(p, r));
    let (a, b, c) = (dot(d1, d1), dot(d1, d2), dot(d2, d2));
    let (d, e) = (dot(d1, w), dot(d2, w));
    let det = a * c - b * b;
    if det > 0.0 {
        let u = (b * e - c * d) / det;
        let v = (a * e - b * d) / det;
        if (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v) {
            return ends.min(dist(add_scaled(p, d1, u), add_scaled(r, d2, v)));
        }
    }
    ends
}

/// Distance between two closed triangles (`f64`; 0 where the exact oracle
/// says they meet): the least of the six corner–triangle and nine
/// edge–edge distances.
pub fn triangle_distance(a: &[P; 3], b: &[P; 3]) -> f64 {
    if cornertree::geometry::exact::corners_intersect_exact(a, b) {
        return 0.0;
    }
    let mut best = f64::INFINITY;
    for i in 0..3 {
        best = best
            .min(point_triangle(a[i], b))
            .min(point_triangle(b[i], a));
        for j in 0..3 {
            best = best.min(segment_segment(a[i], a[(i + 1) % 3], b[j], b[(j + 1) % 3]));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances_of_simple_pairs() {
        let floor = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        let above = [[0.2, 0.2, 0.5], [0.3, 0.2, 0.9], [0.2, 0.3, 0.9]];
        assert!((triangle_distance(&floor, &above) - 0.5).abs() < 1e-12);
        // Crossing edges above each other, 0.25 apart.
        let bar = [[0.5, -1.0, 0.25], [0.5, 2.0, 0.25], [0.5, 2.0, 3.0]];
        let d = triangle_distance(&floor, &bar);
        assert!((d - 0.25).abs() < 1e-12, "{d}");
        let through = [[0.2, 0.2, -0.5], [0.3, 0.2, 0.9], [0.2, 0.3, 0.9]];
        assert_eq!(triangle_distance(&floor, &through), 0.0);
    }
}
