//! The inclusion-based root finder behind the elementary CCD kernels
//! ([`super::ccd_vertex_face`], [`super::ccd_edge_edge`]).
//!
//! After B. Wang, Z. Ferguson, T. Schneider, X. Jiang, M. Attene,
//! D. Panozzo, "A Large-scale Benchmark and an Inclusion-based Algorithm for
//! Continuous Collision Detection", *ACM Transactions on Graphics* 40(5),
//! 2021 (their "Tight Inclusion" method), implemented from the paper's
//! description; why this method and the error bound in full: `docs/ccd.md`.
//!
//! Both elementary queries ask whether the contact function
//! `F(t, u, v) = g(t) + u·e₁(t) + v·e₂(t)` (three coordinates; `g`, `e₁`,
//! `e₂` each the difference of two of the query's four points, every point
//! moving on a straight line over the step `t ∈ [0, 1]`) vanishes on a
//! domain: the unit cube for edge–edge, `{u, v ≥ 0, u + v ≤ 1}` in `(u, v)`
//! for vertex–face. `F` is linear in each parameter, so over a box of
//! parameters each coordinate takes its extremes at the box's 8 corners: the
//! corner values, widened by a bound `ε` on their rounding error, enclose `F`
//! over the box (the inclusion function). The search subdivides boxes,
//! depth first, earliest times first:
//! * a box whose enclosure misses 0 in some coordinate holds no contact
//!   (certain, whatever the rounding: `ε` bounds it). Our addition: the
//!   same test along the normal `e₁ × e₂` at either end of the step (the
//!   triangle's, or the two edges' common one): `d · F` is linear in each
//!   parameter too, so its corner values enclose it, and a near miss along
//!   a slanted normal is rejected at once instead of by boxes of the size
//!   of the gap;
//! * a box whose enclosure lies within `±δ` in every coordinate (δ, the
//!   caller's tolerance) is accepted: every point of it brings the
//!   primitives within `δ` of each other in every coordinate. Its lowest
//!   time becomes the best answer, and from then on boxes starting after
//!   `best − τ` (τ, the time tolerance) are skipped, and a box reaching
//!   past that is split in time first;
//! * any other box is split in two along the parameter that changes `F` the
//!   most across it.
//!
//! Conservative: a box holding a contact is never rejected, so "no contact"
//! is certain, and the returned time (the least start of the accepted and
//! skipped boxes) is a lower bound of the first contact. The search
//! examines at most [`CcdParams::max_boxes`] boxes and splits a parameter
//! at most [`MAX_LEVEL`] times; past either limit it answers "contact"
//! conservatively, its witness then certified only to the looser
//! [`Impact::within`] it reached.
//!
//! The bounds ([`super::ccd_error_bounds`]): `ε` per coordinate is `C · M` with `M` the largest magnitude of that
//! coordinate over the query's eight input points: the rounding of the
//! evaluation (7 roundings deep, `|F|`'s magnitudes summing to at most
//! `18 M`: `C ≥ 18 γ₇`) plus the inputs' own rounding error
//! ([`CcdParams::input_error`], relative to each coordinate, times the sum
//! of the weights' magnitudes in `F`); along a normal `d`,
//! `Σₐ |dₐ| (εₐ + 18 γ₃ Mₐ)`. Parameters are dyadic (`k / 2ˡ`,
//! `l ≤ 52`), so every corner is exact.
//!
//! Generic over [`Binary64`] (`f64`, and `Counted` to count operations):
//! the bound assumes binary64 round-to-nearest arithmetic. Box bookkeeping
//! (dyadic numerators and levels, the stack) is on integers and not
//! counted; the search allocates nothing (a fixed stack of boxes).

pub use super::ccd_error_bounds::{Binary64, RATIONAL_ROUNDING};
use super::ccd_error_bounds::{Bounds, Directions, within};
pub use super::ccd_param_box::{Dyadic, ParamBox};
pub use super::ccd_params::{
    CcdParams, DEFAULT_MAX_BOXES, DEFAULT_TIME_TOLERANCE, DEFAULT_TOLERANCE,
};
use super::vec3::{V3, cross};

/// Most halvings of one parameter (its intervals stay exact `f64` dyadics).
pub const MAX_LEVEL: u8 = 52;

/// A possible contact found by a CCD kernel.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Impact {
    /// A lower bound of the time of first contact, in `[0, 1)`.
    pub toi: f64,
    /// A box of parameters, reaching the query's domain, at every point of
    /// which the primitives are within [`Impact::within`] of each other in
    /// every coordinate (true inputs). Usually the accepted box that set
    /// [`Impact::toi`]; when the search stopped at a limit, the last box it
    /// could not reject.
    pub witness: ParamBox,
    /// The bound on every coordinate of `F` over the witness: at most the
    /// (raised) tolerance when the search accepted a box.
    pub within: f64,
    /// Whether the search ended within its limits: then [`Impact::toi`]
    /// is at most [`CcdParams::time_tolerance`] below the earliest
    /// accepted box and [`Impact::within`] at most the (raised) tolerance. Otherwise it stopped at
    /// [`CcdParams::max_boxes`] or [`MAX_LEVEL`] and answered
    /// conservatively.
    pub resolved: bool,
    /// Boxes examined.
    pub boxes: u32,
}

/// Which `(u, v)` the query ranges over.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Domain {
    /// `[0, 1]²` (edge–edge).
    Square,
    /// `{u, v ≥ 0, u + v ≤ 1}` (vertex–face).
    Triangle,
}

/// `F(t, u, v) = g(t) + u·e₁(t) + v·e₂(t)`, each of `g`, `e₁`, `e₂` held as
/// its value at `t = 0` and its change over the step.
pub(super) struct ContactFunction<T> {
    g: [V3<T>; 2],
    e1: [V3<T>; 2],
    e2: [V3<T>; 2],
}

impl<T: Binary64> ContactFunction<T> {
    /// The function whose `g`, `e₁`, `e₂` are the differences
    /// `xᵢ − xⱼ` of the points at the index pairs given.
    pub(super) fn new(
        start: &[V3<T>; 4],
        end: &[V3<T>; 4],
        g: (usize, usize),
        e1: (usize, usize),
        e2: (usize, usize),
    ) -> Self {
        let term = |(i, j): (usize, usize)| {
            let d0: V3<T> = std::array::from_fn(|a| start[i][a] - start[j][a]);
            let d1: V3<T> = std::array::from_fn(|a| end[i][a] - end[j][a]);
            [d0, std::array::from_fn(|a| d1[a] - d0[a])]
        };
        Self {
            g: term(g),
            e1: term(e1),
            e2: term(e2),
        }
    }

    /// `e₁ × e₂` at `t = 0` and `t = 1`: the triangle's normal
    /// (vertex–face) or the edges' common normal (edge–edge) at either end
    /// of the step, the directions in which `F` is tested besides the axes.
    fn normals(&self) -> [V3<T>; 2] {
        let at_end = |x: &[V3<T>; 2]| -> V3<T> { std::array::from_fn(|a| x[0][a] + x[1][a]) };
        [
            cross(&self.e1[0], &self.e2[0]),
            cross(&at_end(&self.e1), &at_end(&self.e2)),
        ]
    }

    /// `F` at the 8 corners of a box, corner `4·it + 2·iu + iv`.
    #[inline]
    #[allow(clippy::needless_range_loop)]
    fn corners(&self, t: [T; 2], u: [T; 2], v: [T; 2]) -> [V3<T>; 8] {
        let mut out = [[T::zero(); 3]; 8];
        for (it, &tt) in t.iter().enumerate() {
            for a in 0..3 {
                let g = self.g[0][a] + tt * self.g[1][a];
                let e1 = self.e1[0][a] + tt * self.e1[1][a];
                let e2 = self.e2[0][a] + tt * self.e2[1][a];
                let ve = [v[0] * e2, v[1] * e2];
                for (iu, &uu) in u.iter().enumerate() {
                    let h = g + uu * e1;
                    for (iv, &vv) in ve.iter().enumerate() {
                        out[4 * it + 2 * iu + iv][a] = h + vv;
                    }
                }
            }
        }
        out
    }
}

/// Stack capacity: depth first, each split adds one box, at most
/// `3 · MAX_LEVEL` splits deep.
const STACK: usize = 3 * MAX_LEVEL as usize + 2;

/// When to stop.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Seek {
    /// The earliest contact starting before this time (`≤ 1`).
    EarliestBefore(f64),
    /// Any contact: stop at the first accepted box.
    Any,
}

/// Runs the search; `None` when `F` certainly has no zero on the domain
/// (before the time sought).
pub(super) fn find_root<T: Binary64>(
    f: &ContactFunction<T>,
    bounds: &Bounds<T>,
    domain: Domain,
    seek: Seek,
    max_boxes: u32,
    time_tolerance: f64,
) -> Option<Impact> {
    let before = match seek {
        Seek::EarliestBefore(b) => b,
        Seek::Any => 1.0,
    };
    let max_boxes = max_boxes.max(1);
    let tau = T::from_f64(time_tolerance);
    let directions = Directions::new(f.normals(), bounds);
    let mut stack = [ParamBox::UNIT; STACK];
    let mut len = 1;
    let mut best = T::from_f64(before);
    // Boxes start no earlier than this, or are skipped (`best − τ` once a
    // box is accepted), and the least start of those skipped below `best`.
    let mut cutoff = best;
    let mut skipped = best;
    // The latest (so earliest in time) accepted box, and the last box
    // neither rejected nor accepted, each with its corner extremes.
    let mut accepted: Option<(ParamBox, V3<T>, V3<T>)> = None;
    let mut open: Option<(ParamBox, V3<T>, V3<T>)> = None;
    let mut limited = false;
    let mut boxes = 0u32;
    while len > 0 {
        len -= 1;
        let b = stack[len];
        let t_lo = T::from_f64(b.t.lo());
        if t_lo >= cutoff {
            if t_lo < skipped {
                skipped = t_lo;
            }
            continue;
        }
        if domain == Domain::Triangle && !b.reaches_triangle() {
            continue;
        }
        if boxes == max_boxes {
            // Out of budget: every box left starts at or after the least
            // lower end among them (all below `best`, or skipped anyway).
            best = stack[..len]
                .iter()
                .map(|s| T::from_f64(s.t.lo()))
                .fold(t_lo, |m, x| m.min_of(x));
            limited = true;
            break;
        }
        boxes += 1;
        let dims = b.dims();
        let ends = |d: Dyadic| [T::from_f64(d.lo()), T::from_f64(d.hi())];
        let c = f.corners(ends(dims[0]), ends(dims[1]), ends(dims[2]));
        let mut lo = c[0];
        let mut hi = c[0];
        for corner in &c[1..] {
            for a in 0..3 {
                lo[a] = lo[a].min_of(corner[a]);
                hi[a] = hi[a].max_of(corner[a]);
            }
        }
        let eps = &bounds.eps;
        if (0..3).any(|a| lo[a] > eps[a] || hi[a] < -eps[a]) || directions.exclude_zero(&c) {
            continue;
        }
        let acc = &bounds.accept;
        if (0..3).all(|a| hi[a] <= acc[a] && lo[a] >= -acc[a]) {
            best = t_lo;
            cutoff = best - tau;
            accepted = Some((b, lo, hi));
            if seek == Seek::Any {
                break;
            }
            continue;
        }
        open = Some((b, lo, hi));
        // Once a contact is accepted only earlier starts matter: a box
        // reaching past the best time is split in time, so that its part
        // after `best − τ` is skipped (a box wholly earlier is split as any).
        let refine_time =
            accepted.is_some() && dims[0].level < MAX_LEVEL && T::from_f64(dims[0].hi()) > cutoff;
        let split = if refine_time {
            Some(0)
        } else {
            split_dimension(&c, &dims)
        };
        match split {
            Some(d) => {
                let [first, second] = dims[d].halves();
                // Later times pushed first: the earlier half is examined first.
                stack[len] = b.with(d, second);
                stack[len + 1] = b.with(d, first);
                len += 2;
            }
            None => {
                // Every parameter at its finest: contact, unresolved.
                best = t_lo;
                cutoff = best;
                limited = true;
            }
        }
    }
    if best >= T::from_f64(before) {
        return None;
    }
    let best = best.min_of(skipped);
    // A positive answer has examined a box not rejected.
    let (witness, lo, hi) = accepted.or(open)?;
    Some(Impact {
        toi: best.to_f64(),
        witness,
        within: within(&lo, &hi, &bounds.eps),
        resolved: !limited,
        boxes,
    })
}

/// The parameter to split: the one along which `F` changes most across the
/// box (largest difference between corners on a parallel edge, any
/// coordinate), among those not at [`MAX_LEVEL`].
fn split_dimension<T: Binary64>(c: &[V3<T>; 8], dims: &[Dyadic; 3]) -> Option<usize> {
    let mut best: Option<(usize, T)> = None;
    for (d, bit) in [(0usize, 4usize), (1, 2), (2, 1)] {
        if dims[d].level >= MAX_LEVEL {
            continue;
        }
        let mut w = T::zero();
        for i in (0..8).filter(|i| i & bit == 0) {
            for (&x, &y) in c[i | bit].iter().zip(&c[i]) {
                w = w.max_of((x - y).abs());
            }
        }
        if best.is_none_or(|(_, bw)| w > bw) {
            best = Some((d, w));
        }
    }
    best.map(|(d, _)| d)
}
