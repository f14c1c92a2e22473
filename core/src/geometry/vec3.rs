//! Three-component vectors `[T; 3]` over a [`Scalar`], for the generic
//! kernels (nalgebra's generic bounds would ask more of a counting scalar).
//! Products are evaluated in nalgebra's order, so `f64` results are the same
//! bit for bit.

use super::scalar::Scalar;
use super::{Point, Triangle};

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

#[inline(always)]
pub fn sub<T: Scalar>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

#[inline(always)]
pub fn dot<T: Scalar>(a: &V3<T>, b: &V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

#[inline(always)]
pub fn cross<T: Scalar>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

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
