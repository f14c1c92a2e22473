//! Swept boxes: the axis-aligned box holding points over a step of linear
//! motion, the cheap conservative early-out of the CCD kernels.
//!
//! A point moving on a straight line stays in the box of its two ends; a
//! convex combination of moving points (a point of an edge or a triangle at
//! any time) stays in the box of all their ends. Two such boxes apart along
//! some axis by more than the inputs' rounding margin mean the primitives
//! never touch during the step.

use super::scalar::Scalar;
use super::vec3::V3;

/// The box `[lo, hi]` of some points at both ends of a step.
///
/// ```
/// use cornertree::geometry::ccd_swept_box::SweptBox;
///
/// // A point moving from the origin to (1, -1, 2), and a segment moving
/// // from x = 1.5..2 to x = 1.5.
/// let a = SweptBox::of(&[[0.0, 0.0, 0.0]], &[[1.0, -1.0, 2.0]]);
/// assert_eq!((a.lo, a.hi), ([0.0, -1.0, 0.0], [1.0, 0.0, 2.0]));
/// let b = SweptBox::of(&[[1.5, 0.0, 0.0], [2.0, 0.0, 0.0]], &[[1.5, 0.0, 0.0]]);
/// // 0.5 apart along x: apart with no margin, not with a margin of 0.5.
/// assert!(a.apart(&b, &[0.0; 3]) && b.apart(&a, &[0.0; 3]));
/// assert!(!a.apart(&b, &[0.5; 3]));
/// // Boxes that touch are not apart.
/// let c = SweptBox::of(&[[1.0, 0.0, 0.0]], &[[3.0, 0.0, 0.0]]);
/// assert!(!a.apart(&c, &[0.0; 3]));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SweptBox<T> {
    /// The least coordinates, per axis.
    pub lo: V3<T>,
    /// The greatest coordinates, per axis.
    pub hi: V3<T>,
}

impl<T: Scalar> SweptBox<T> {
    /// The box of `start` and `end` (not both empty).
    pub fn of(start: &[V3<T>], end: &[V3<T>]) -> Self {
        let first = start.first().or(end.first()).expect("points to bound");
        let (mut lo, mut hi) = (*first, *first);
        for p in start.iter().chain(end) {
            for a in 0..3 {
                lo[a] = lo[a].min_of(p[a]);
                hi[a] = hi[a].max_of(p[a]);
            }
        }
        Self { lo, hi }
    }

    /// Whether the boxes are apart by more than `margin[a]` along some axis
    /// `a` (then nothing inside one meets anything inside the other, even
    /// with every coordinate moved by up to `margin / 2`).
    pub fn apart(&self, other: &Self, margin: &V3<T>) -> bool {
        (0..3).any(|a| self.lo[a] - other.hi[a] > margin[a] || other.lo[a] - self.hi[a] > margin[a])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn boxes_of_moving_points() {
        let a = SweptBox::of(&[[0.0, 0.0, 0.0]], &[[1.0, -1.0, 2.0]]);
        assert_eq!((a.lo, a.hi), ([0.0, -1.0, 0.0], [1.0, 0.0, 2.0]));
        let b = SweptBox::of(&[[1.5, 0.0, 0.0], [2.0, 0.0, 0.0]], &[[1.5, 0.0, 0.0]]);
        assert!(a.apart(&b, &[0.0; 3]) && b.apart(&a, &[0.0; 3]));
        assert!(!a.apart(&b, &[0.5; 3]));
        assert!(!a.apart(&a, &[0.0; 3]));
    }
}
