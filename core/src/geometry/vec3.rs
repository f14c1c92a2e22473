//! Three-component vectors `[T; 3]` over a [`Scalar`], for the generic
//! kernels (nalgebra's generic bounds would ask more of a counting scalar).
//! Products are evaluated in nalgebra's order, so `f64` results are the same
//! bit for bit.

use super::scalar::Scalar;
use super::{Point, Triangle};

/// A vector or point `[x, y, z]` in the scalar `T`.
pub type V3<T> = [T; 3];

/// A stored `f32` point in `T` (free).
#[inline(always)]
pub fn widen<T: Scalar>(p: &Point) -> V3<T> {
    [T::from_f32(p.x), T::from_f32(p.y), T::from_f32(p.z)]
}

/// The three corners of a triangle in `T` (free).
#[inline(always)]
pub fn widen_triangle<T: Scalar>(t: &Triangle) -> [V3<T>; 3] {
    t.vertices().map(|p| widen(&p))
}

/// `a - b`, component by component (three operations).
#[inline(always)]
pub fn sub<T: Scalar>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// The dot product `a · b` (three multiplications, two additions).
#[inline(always)]
pub fn dot<T: Scalar>(a: &V3<T>, b: &V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// The cross product `a × b` (six multiplications, three subtractions).
///
/// ```
/// use cornertree::geometry::vec3::cross;
///
/// let (x, y) = ([1.0f64, 0.0, 0.0], [0.0, 1.0, 0.0]);
/// assert_eq!(cross(&x, &y), [0.0, 0.0, 1.0]);
/// assert_eq!(cross(&y, &x), [0.0, 0.0, -1.0]);
/// assert_eq!(cross(&[1.0, 2.0, 3.0], &[4.0, 5.0, 6.0]), [-3.0, 6.0, -3.0]);
/// ```
#[inline(always)]
pub fn cross<T: Scalar>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// The squared length `a · a` (five operations).
#[inline(always)]
pub fn norm_squared<T: Scalar>(a: &V3<T>) -> T {
    dot(a, a)
}

/// Whether every component is zero (three comparisons at most).
#[inline(always)]
pub fn is_zero<T: Scalar>(a: &V3<T>) -> bool {
    let z = T::zero();
    a[0] == z && a[1] == z && a[2] == z
}

/// Whether two vectors are equal component by component.
#[inline(always)]
pub fn equal<T: Scalar>(a: &V3<T>, b: &V3<T>) -> bool {
    a[0] == b[0] && a[1] == b[1] && a[2] == b[2]
}

/// Index of the component of largest magnitude (the first on ties).
///
/// ```
/// use cornertree::geometry::vec3::major_axis;
///
/// assert_eq!(major_axis(&[1.0f64, -3.0, 2.0]), 1);
/// assert_eq!(major_axis(&[2.0f64, -2.0, 2.0]), 0);
/// ```
#[inline(always)]
pub fn major_axis<T: Scalar>(a: &V3<T>) -> usize {
    let m = a.map(T::abs);
    let mut k = 0;
    if m[1] > m[0] {
        k = 1;
    }
    if m[2] > m[k] {
        k = 2;
    }
    k
}
