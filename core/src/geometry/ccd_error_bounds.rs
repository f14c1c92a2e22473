//! The rounding bounds of the CCD search ([`super::ccd_root_finder`]):
//! `ε`, which bounds the error of the contact function `F` at a corner of
//! a parameter box against its value at the exact inputs; the acceptance
//! bound derived from the tolerance; `η`, the same for `F` along a normal
//! direction; and the certified bound of a witness box. Derivations:
//! `docs/ccd.md`, "The error bound".

use super::ccd_params::CcdParams;
use super::counted::Counted;
use super::scalar::Scalar;
use super::vec3::{V3, dot};

/// Scalars whose arithmetic is IEEE binary64 rounded to nearest, which the
/// error bound assumes: `f64`, and [`Counted`] (an `f64` that counts).
pub trait Binary64: Scalar {}
impl Binary64 for f64 {}
impl Binary64 for Counted {}

/// Unit roundoff of binary64, `2⁻⁵³`.
pub(super) const UNIT_ROUNDOFF: f64 = f64::EPSILON / 2.0;

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

/// The smallest acceptance bound, in units of `ε`: a tolerance below
/// `MIN_TOLERANCE_IN_EPS · ε` is raised to it (with `δ ≈ ε` rounding noise
/// alone would keep boxes from being accepted).
const MIN_TOLERANCE_IN_EPS: f64 = 16.0;

/// Per-coordinate rounding bound `ε` and acceptance bound of a query.
pub(super) struct Bounds<T> {
    /// `ε`: bounds `|F̃ − F|` at any corner of `[0, 1]³` (true inputs).
    pub(super) eps: V3<T>,
    /// Corner values within `±accept` (all coordinates) accept a box.
    pub(super) accept: V3<T>,
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

/// The directions besides the axes in which the search tests `F`
/// (the normals of `ccd_root_finder::ContactFunction`) with their rounding bounds: `d · F` is
/// also linear in each parameter, so its corner values enclose it too.
pub(super) struct Directions<T> {
    d: [V3<T>; 2],
    /// Bounds `|fl(d · F̃) − d · F|` at any corner (true inputs).
    eta: [T; 2],
}

impl<T: Binary64> Directions<T> {
    /// The bounds for the directions `d` (`ContactFunction::normals`).
    pub(super) fn new(d: [V3<T>; 2], bounds: &Bounds<T>) -> Self {
        let c = T::from_f64(DIRECTION_ERROR);
        // Room for the few roundings of η itself.
        let up = T::from_f64(1.0 + 1e-12);
        let per_axis: V3<T> = std::array::from_fn(|a| bounds.eps[a] + c * bounds.m[a]);
        let eta = d.map(|d| dot(&d.map(T::abs), &per_axis) * up);
        Self { d, eta }
    }

    /// Whether `d · F` keeps one strict sign over the corners `c` (beyond
    /// its rounding bound) for one of the directions: no zero in the box.
    pub(super) fn exclude_zero(&self, c: &[V3<T>; 8]) -> bool {
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
pub(super) fn within<T: Binary64>(lo: &V3<T>, hi: &V3<T>, eps: &V3<T>) -> f64 {
    (0..3)
        .map(|a| {
            let m = hi[a].to_f64().max(-lo[a].to_f64()) + eps[a].to_f64();
            m * (1.0 + 4.0 * UNIT_ROUNDOFF)
        })
        .fold(0.0, f64::max)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evaluation_error_covers_eighteen_gamma_seven() {
        let u = UNIT_ROUNDOFF;
        let gamma7 = 7.0 * u / (1.0 - 7.0 * u);
        assert!(EVALUATION_ERROR > 18.0 * gamma7 * (1.0 + 1e-4));
        assert!((1.0 + u) * (1.0 + u) / (1.0 - u) - 1.0 < RATIONAL_ROUNDING);
    }
}
