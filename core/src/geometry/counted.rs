//! [`Counted`]: an `f64` that counts the operations done on it.
//!
//! Each `+ − × ÷`, negation, `abs`, `sqrt` and each comparison (`<`, `<=`,
//! `>`, `>=`, `==`, `!=`) adds one to a per-thread counter; conversions are
//! free. Running a kernel instantiated with `Counted` therefore measures the
//! operations that kernel *pays* on that input, branch by branch, where the
//! paper's model (§6) *charges* a fixed figure per test. The values are the
//! `f64` ones, so the answers are those of the `f64` instantiation.
//!
//! Use [`count_operations`] to measure one call; only tests and
//! `cornertree kernels` use this type.

use std::cell::Cell;
use std::cmp::Ordering;
use std::ops::{Add, Div, Mul, Neg, Sub};

use super::scalar::Scalar;

thread_local! {
    static ARITHMETIC: Cell<u64> = const { Cell::new(0) };
    static COMPARISONS: Cell<u64> = const { Cell::new(0) };
}

/// One arithmetic operation.
#[inline]
fn tick() {
    ARITHMETIC.with(|c| c.set(c.get() + 1));
}

/// One comparison.
#[inline]
fn tick_comparison() {
    COMPARISONS.with(|c| c.set(c.get() + 1));
}

/// Operations counted, by kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Operations {
    /// `+ − × ÷`, negation, `abs`, `sqrt`.
    pub arithmetic: u64,
    /// `<`, `<=`, `>`, `>=`, `==`, `!=` (and `partial_cmp`).
    pub comparisons: u64,
}

impl Operations {
    /// Arithmetic operations and comparisons together.
    pub fn total(&self) -> u64 {
        self.arithmetic + self.comparisons
    }

    fn now() -> Self {
        Self {
            arithmetic: ARITHMETIC.with(Cell::get),
            comparisons: COMPARISONS.with(Cell::get),
        }
    }
}

/// Runs `f` and returns its result with the number of [`Counted`] operations
/// it executed on this thread, by kind.
///
/// The sphere-sphere test pays the 10 arithmetic operations the paper
/// charges it (§6), plus its one comparison:
///
/// ```
/// use cornertree::geometry::counted::{Counted, Operations, count_operations_by_kind};
/// use cornertree::geometry::{Point, Sphere};
///
/// let a = Sphere::new(Point::new(0.0, 0.0, 0.0), 1.0);
/// let b = Sphere::new(Point::new(3.0, 0.0, 0.0), 1.0);
/// let (hit, ops) = count_operations_by_kind(|| a.overlaps_as::<Counted>(&b));
/// assert!(!hit);
/// assert_eq!(ops, Operations { arithmetic: 10, comparisons: 1 });
/// assert_eq!(ops.total(), 11);
/// ```
pub fn count_operations_by_kind<R>(f: impl FnOnce() -> R) -> (R, Operations) {
    let before = Operations::now();
    let r = f();
    let after = Operations::now();
    let ops = Operations {
        arithmetic: after.arithmetic - before.arithmetic,
        comparisons: after.comparisons - before.comparisons,
    };
    (r, ops)
}

/// Runs `f` and returns its result with the number of [`Counted`] operations
/// (arithmetic and comparisons) it executed on this thread.
///
/// Short-circuits are not paid, so an early exit costs less:
///
/// ```
/// use cornertree::geometry::counted::{Counted, count_operations};
/// use cornertree::geometry::scalar::Scalar;
///
/// let (a, b) = (Counted(3.0), Counted(4.0));
/// let (r, n) = count_operations(|| (a * a + b * b).sqrt());
/// assert_eq!((r.0, n), (5.0, 4));
/// // Only the first comparison runs.
/// let (r, n) = count_operations(|| a > b && a * b > Counted(0.0));
/// assert_eq!((r, n), (false, 1));
/// // Conversions are free.
/// let (_, n) = count_operations(|| Counted::from_f32(1.5).to_f64());
/// assert_eq!(n, 0);
/// ```
pub fn count_operations<R>(f: impl FnOnce() -> R) -> (R, u64) {
    let (r, ops) = count_operations_by_kind(f);
    (r, ops.total())
}

/// An `f64` whose every operation is counted (see the module docs).
#[derive(Clone, Copy, Debug)]
pub struct Counted(pub f64);

impl Add for Counted {
    type Output = Self;
    #[inline]
    fn add(self, b: Self) -> Self {
        tick();
        Counted(self.0 + b.0)
    }
}

impl Sub for Counted {
    type Output = Self;
    #[inline]
    fn sub(self, b: Self) -> Self {
        tick();
        Counted(self.0 - b.0)
    }
}

impl Mul for Counted {
    type Output = Self;
    #[inline]
    fn mul(self, b: Self) -> Self {
        tick();
        Counted(self.0 * b.0)
    }
}

impl Div for Counted {
    type Output = Self;
    #[inline]
    fn div(self, b: Self) -> Self {
        tick();
        Counted(self.0 / b.0)
    }
}

impl Neg for Counted {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        tick();
        Counted(-self.0)
    }
}

impl PartialEq for Counted {
    #[inline]
    fn eq(&self, b: &Self) -> bool {
        tick_comparison();
        self.0 == b.0
    }
}

impl PartialOrd for Counted {
    #[inline]
    fn partial_cmp(&self, b: &Self) -> Option<Ordering> {
        tick_comparison();
        self.0.partial_cmp(&b.0)
    }
    #[inline]
    fn lt(&self, b: &Self) -> bool {
        tick_comparison();
        self.0 < b.0
    }
    #[inline]
    fn le(&self, b: &Self) -> bool {
        tick_comparison();
        self.0 <= b.0
    }
    #[inline]
    fn gt(&self, b: &Self) -> bool {
        tick_comparison();
        self.0 > b.0
    }
    #[inline]
    fn ge(&self, b: &Self) -> bool {
        tick_comparison();
        self.0 >= b.0
    }
}

impl Scalar for Counted {
    #[inline]
    fn zero() -> Self {
        Counted(0.0)
    }
    #[inline]
    fn from_f32(x: f32) -> Self {
        Counted(x as f64)
    }
    #[inline]
    fn from_f64(x: f64) -> Self {
        Counted(x)
    }
    #[inline]
    fn to_f64(self) -> f64 {
        self.0
    }
    #[inline]
    fn abs(self) -> Self {
        tick();
        Counted(self.0.abs())
    }
    #[inline]
    fn sqrt(self) -> Self {
        tick();
        Counted(self.0.sqrt())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_each_operation_once() {
        let (a, b) = (Counted(3.0), Counted(4.0));
        let (r, n) = count_operations(|| (a * a + b * b).sqrt());
        assert_eq!((r.0, n), (5.0, 4));
        let (lt, n) = count_operations_by_kind(|| a < b && a != b && (-a).abs() >= a);
        assert!(lt);
        assert_eq!(
            n,
            Operations {
                arithmetic: 2,
                comparisons: 3
            }
        );
        let (_, n) = count_operations(|| (Counted::from_f32(1.5), Counted::zero().to_f64()));
        assert_eq!(n, 0);
    }

    #[test]
    fn short_circuit_is_not_paid() {
        let (a, b) = (Counted(1.0), Counted(2.0));
        let (r, n) = count_operations(|| a > b && a / b > Counted(0.0));
        assert!(!r);
        assert_eq!(n, 1);
    }
}
