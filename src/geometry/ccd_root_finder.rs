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
//! `ε` per coordinate is `C · M` with `M` the largest magnitude of that
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

use super::counted::Counted;
use super::scalar::Scalar;
use super::vec3::{V3, cross, dot};

/// Scalars whose arithmetic is IEEE binary64 rounded to nearest, which the
/// error bound assumes: `f64`, and [`Counted`] (an `f64` that counts).
pub trait Binary64: Scalar {}
impl Binary64 for f64 {}
impl Binary64 for Counted {}

/// Unit roundoff of binary64, `2⁻⁵³`.
const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

/// Rounding of the evaluation of `F` at a corner, relative to the largest
/// input magnitude `M` of the coordinate: at least `18 γ₇`
/// (`γ₇ = 7u / (1 − 7u)`; 1.3989e-14), rounded up with room for the
/// roundings of `ε` itself (`docs/ccd.md`).
const EVALUATION_ERROR: f64 = 1.4e-14;

/// Rounding of a direction's component `d · F̃` at a corner, relative to
/// `Σₐ |dₐ| Mₐ`: at least `18 γ₃ (1 + γ₇)` (5.995e-15; `docs/ccd.md`).
const DIRECTION_ERROR: f64 = 6.1e-15;

/// Relative error of `fl(fl(n) / fl(d))`, an exact rational `n / d`
/// converted to `f64` (three roundings: `(1 + u)² / (1 − u) − 1 < 3.001 u`).
pub const RATIONAL_ROUNDING: f64 = 3.001 * UNIT_ROUNDOFF;

/// Default tolerance δ: a positive answer brings the primitives within δ of
/// each other in every coordinate (for inputs of unit scale).
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// Default budget of boxes per query.
pub const DEFAULT_MAX_BOXES: u32 = 1 << 16;

/// Default time tolerance τ (fraction of the step).
pub const DEFAULT_TIME_TOLERANCE: f64 = 1e-6;

/// Most halvings of one parameter (its intervals stay exact `f64` dyadics).
pub const MAX_LEVEL: u8 = 52;

/// The smallest acceptance bound, in units of `ε`: a tolerance below
/// `MIN_TOLERANCE_IN_EPS · ε` is raised to it (with `δ ≈ ε` rounding noise
/// alone would keep boxes from being accepted).
const MIN_TOLERANCE_IN_EPS: f64 = 16.0;

/// Settings of a CCD query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CcdParams {
    /// δ (length): a positive answer certifies that the primitives come
    /// within δ of each other in every coordinate (so within `√3 δ`), at
    /// the true inputs. Raised to `16 ε` where that is larger
    /// (`ε ≈ 1.4e-14` times the query's largest coordinate).
    pub tolerance: f64,
    /// How far each input coordinate may be from the true one, relative to
    /// its magnitude: 0 for positions taken as they are (`f32` or `f64`
    /// geometry), [`RATIONAL_ROUNDING`] for exact rationals rounded to
    /// `f64`.
    pub input_error: f64,
    /// Boxes examined at most; past it the answer is "contact", its
    /// witness certified only to [`Impact::within`].
    pub max_boxes: u32,
    /// τ: once a contact is accepted, boxes starting less than τ before it
    /// are not examined, so the time of impact may be up to τ below the
    /// earliest accepted box (it stays a lower bound of the first contact).
    pub time_tolerance: f64,
}

impl Default for CcdParams {
    fn default() -> Self {
        Self {
            tolerance: DEFAULT_TOLERANCE,
            input_error: 0.0,
            max_boxes: DEFAULT_MAX_BOXES,
            time_tolerance: DEFAULT_TIME_TOLERANCE,
        }
    }
}

/// An interval `[k / 2ˡ, (k + 1) / 2ˡ]` of a parameter.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dyadic {
    pub k: u64,
    pub level: u8,
}

impl Dyadic {
    const UNIT: Dyadic = Dyadic { k: 0, level: 0 };

    /// `2⁻ˡ`, exactly.
    fn scale(self) -> f64 {
        f64::from_bits((1023 - self.level as u64) << 52)
    }

    /// The lower end (exact).
    pub fn lo(self) -> f64 {
        self.k as f64 * self.scale()
    }

    /// The upper end (exact).
    pub fn hi(self) -> f64 {
        (self.k + 1) as f64 * self.scale()
    }

    fn halves(self) -> [Dyadic; 2] {
        let level = self.level + 1;
        [
            Dyadic {
                k: 2 * self.k,
                level,
            },
            Dyadic {
                k: 2 * self.k + 1,
                level,
            },
        ]
    }
}

/// A box of parameters: time `t` and the two feature parameters `u`, `v`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParamBox {
    pub t: Dyadic,
    pub u: Dyadic,
    pub v: Dyadic,
}

impl ParamBox {
    const UNIT: ParamBox = ParamBox {
        t: Dyadic::UNIT,
        u: Dyadic::UNIT,
        v: Dyadic::UNIT,
    };

    fn dims(&self) -> [Dyadic; 3] {
        [self.t, self.u, self.v]
    }

    fn with(&self, dim: usize, d: Dyadic) -> ParamBox {
        let mut b = *self;
        match dim {
            0 => b.t = d,
            1 => b.u = d,
            _ => b.v = d,
        }
        b
    }

    /// Whether `u_lo + v_lo ≤ 1` (the box reaches the triangle
    /// `{u, v ≥ 0, u + v ≤ 1}`), on the integer numerators.
    fn reaches_triangle(&self) -> bool {
        let l = self.u.level.max(self.v.level);
        let num = (self.u.k << (l - self.u.level)) + (self.v.k << (l - self.v.level));
        num <= 1u64 << l
    }
}

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

/// Per-coordinate rounding bound `ε` and acceptance bound of a query.
pub(super) struct Bounds<T> {
    /// `ε`: bounds `|F̃ − F|` at any corner of `[0, 1]³` (true inputs).
    pub(super) eps: V3<T>,
    /// Corner values within `±accept` (all coordinates) accept a box.
    accept: V3<T>,
    /// The largest input magnitude per coordinate.
    m: V3<T>,
}

impl<T: Binary64> Bounds<T> {
    /// The bounds for a query whose points have, per coordinate, magnitudes
    /// at most `m` ([`max_magnitudes`]); `weight` bounds the sum of the
    /// magnitudes of the points' weights in `F` (4 for vertex–face, 2 for
    /// edge–edge).
    pub(super) fn new(m: &V3<T>, params: &CcdParams, weight: f64) -> Self {
        let c = T::from_f64(EVALUATION_ERROR + weight * params.input_error);
        // Covers underflow: products of subnormals err by up to 2⁻¹⁰⁷⁵ each.
        let tiny = T::from_f64(f64::MIN_POSITIVE);
        let delta = T::from_f64(params.tolerance);
        let raise = T::from_f64(MIN_TOLERANCE_IN_EPS);
        let shrink = T::from_f64(1.0 - 4.0 * UNIT_ROUNDOFF);
        let two = T::from_f64(2.0);
        let mut eps = [T::zero(); 3];
        let mut accept = [T::zero(); 3];
        for a in 0..3 {
            eps[a] = c * m[a] + tiny;
            // accept ≤ δᵢ − 2ε, δᵢ = max(δ, 16 ε): an accepted box's
            // enclosure (corners ± ε) stays within ±δᵢ despite rounding.
            let d = delta.max_of(raise * eps[a]);
            accept[a] = d * shrink - two * eps[a];
        }
        Self { eps, accept, m: *m }
    }
}

/// The largest magnitude of each coordinate over the points of `sets`.
pub(super) fn max_magnitudes<T: Binary64>(sets: &[&[V3<T>]]) -> V3<T> {
    let mut m = [T::zero(); 3];
    for p in sets.iter().flat_map(|s| s.iter()) {
        for a in 0..3 {
            m[a] = m[a].max_of(p[a].abs());
        }
    }
    m
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
    let directions = Directions::new(f, bounds);
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

/// The directions besides the axes in which the search tests `F`
/// ([`ContactFunction::normals`]) with their rounding bounds: `d · F` is
/// also linear in each parameter, so its corner values enclose it too.
struct Directions<T> {
    d: [V3<T>; 2],
    /// Bounds `|fl(d · F̃) − d · F|` at any corner (true inputs).
    eta: [T; 2],
}

impl<T: Binary64> Directions<T> {
    fn new(f: &ContactFunction<T>, bounds: &Bounds<T>) -> Self {
        let d = f.normals();
        let c = T::from_f64(DIRECTION_ERROR);
        // Room for the few roundings of η itself.
        let up = T::from_f64(1.0 + 1e-12);
        let per_axis: V3<T> = std::array::from_fn(|a| bounds.eps[a] + c * bounds.m[a]);
        let eta = d.map(|d| dot(&d.map(T::abs), &per_axis) * up);
        Self { d, eta }
    }

    /// Whether `d · F` keeps one strict sign over the corners `c` (beyond
    /// its rounding bound) for one of the directions: no zero in the box.
    fn exclude_zero(&self, c: &[V3<T>; 8]) -> bool {
        self.d.iter().zip(&self.eta).any(|(d, &eta)| {
            let first = dot(d, &c[0]);
            let (mut lo, mut hi) = (first, first);
            for corner in &c[1..] {
                let g = dot(d, corner);
                lo = lo.min_of(g);
                hi = hi.max_of(g);
            }
            lo > eta || hi < -eta
        })
    }
}

/// Bound on every coordinate of `F` over a box not rejected (so enclosing
/// 0): `max(hi, −lo) + ε`, rounded up (`f64`, once per query).
fn within<T: Binary64>(lo: &V3<T>, hi: &V3<T>, eps: &V3<T>) -> f64 {
    (0..3)
        .map(|a| {
            let m = hi[a].to_f64().max(-lo[a].to_f64()) + eps[a].to_f64();
            m * (1.0 + 4.0 * UNIT_ROUNDOFF)
        })
        .fold(0.0, f64::max)
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dyadic_ends_are_exact() {
        let d = Dyadic { k: 3, level: 2 };
        assert_eq!((d.lo(), d.hi()), (0.75, 1.0));
        let [a, b] = d.halves();
        assert_eq!((a.lo(), a.hi(), b.lo(), b.hi()), (0.75, 0.875, 0.875, 1.0));
        let fine = Dyadic {
            k: (1 << 52) - 1,
            level: 52,
        };
        assert_eq!(fine.hi(), 1.0);
        assert_eq!(fine.lo(), 1.0 - f64::EPSILON);
    }

    #[test]
    fn triangle_domain_on_numerators() {
        let b = |ku, lu, kv, lv| ParamBox {
            t: Dyadic::UNIT,
            u: Dyadic { k: ku, level: lu },
            v: Dyadic { k: kv, level: lv },
        };
        assert!(b(0, 0, 0, 0).reaches_triangle());
        assert!(b(1, 1, 1, 1).reaches_triangle()); // 1/2 + 1/2 = 1
        assert!(!b(1, 1, 3, 2).reaches_triangle()); // 1/2 + 3/4
        assert!(b(1, 2, 3, 2).reaches_triangle()); // 1/4 + 3/4
    }

    #[test]
    fn evaluation_error_covers_eighteen_gamma_seven() {
        let u = UNIT_ROUNDOFF;
        let gamma7 = 7.0 * u / (1.0 - 7.0 * u);
        assert!(EVALUATION_ERROR > 18.0 * gamma7 * (1.0 + 1e-4));
        assert!((1.0 + u) * (1.0 + u) / (1.0 - u) - 1.0 < RATIONAL_ROUNDING);
    }
}
