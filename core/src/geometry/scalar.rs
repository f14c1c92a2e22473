//! The number type the kernels are generic over.
//!
//! Every kernel of the operation model (§6) is written once against
//! [`Scalar`] and instantiated twice: with `f64` (`f32` for the
//! sphere-sphere test, whose spheres are stored in `f32`) on the hot path,
//! where the generic code compiles to the same machine code as a hand-written
//! version, and with [`super::counted::Counted`], which counts every
//! operation it executes (`cornertree kernels`, tests).
//!
//! A kernel must do all its arithmetic and comparisons through this trait:
//! conversions (`from_f32`, `from_f64`, `to_f64`) are free, everything else
//! is an operation.

use std::ops::{Add, Div, Mul, Neg, Sub};

/// A real number type: the four operations, negation, `abs`, `sqrt` and
/// comparisons.
///
/// A kernel written once over `Scalar` runs in `f64` and, with
/// [`Counted`](super::counted::Counted), counts what it pays:
///
/// ```
/// use cornertree::geometry::counted::{Counted, count_operations};
/// use cornertree::geometry::scalar::Scalar;
///
/// fn hypot<T: Scalar>(a: T, b: T) -> T {
///     (a * a + b * b).sqrt()
/// }
///
/// assert_eq!(hypot(3.0f64, 4.0), 5.0);
/// let (r, n) = count_operations(|| hypot(Counted::from_f64(3.0), Counted::from_f64(4.0)));
/// assert_eq!((r.to_f64(), n), (5.0, 4)); // two products, a sum, a root
/// ```
pub trait Scalar:
    Copy
    + PartialOrd
    + Add<Output = Self>
    + Sub<Output = Self>
    + Mul<Output = Self>
    + Div<Output = Self>
    + Neg<Output = Self>
{
    /// Zero (free).
    fn zero() -> Self;
    /// An `f32` value, widened exactly (free).
    fn from_f32(x: f32) -> Self;
    /// An `f64` value (free; rounded to the nearest value for a narrower type).
    fn from_f64(x: f64) -> Self;
    /// The value as `f64` (free; for reports and tests).
    fn to_f64(self) -> f64;
    /// Magnitude (one operation).
    fn abs(self) -> Self;
    /// Square root (one operation).
    fn sqrt(self) -> Self;

    /// The smaller of two values (one comparison); `b` when they compare equal.
    #[inline(always)]
    fn min_of(self, b: Self) -> Self {
        if self < b { self } else { b }
    }

    /// The larger of two values (one comparison); `b` when they compare equal.
    #[inline(always)]
    fn max_of(self, b: Self) -> Self {
        if self > b { self } else { b }
    }
}

impl Scalar for f64 {
    #[inline(always)]
    fn zero() -> Self {
        0.0
    }
    #[inline(always)]
    fn from_f32(x: f32) -> Self {
        x as f64
    }
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        x
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f64::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f64::sqrt(self)
    }
}

impl Scalar for f32 {
    #[inline(always)]
    fn zero() -> Self {
        0.0
    }
    #[inline(always)]
    fn from_f32(x: f32) -> Self {
        x
    }
    #[inline(always)]
    fn from_f64(x: f64) -> Self {
        x as f32
    }
    #[inline(always)]
    fn to_f64(self) -> f64 {
        self as f64
    }
    #[inline(always)]
    fn abs(self) -> Self {
        f32::abs(self)
    }
    #[inline(always)]
    fn sqrt(self) -> Self {
        f32::sqrt(self)
    }
}
