//! Bounding sphere and the sphere-sphere overlap test.

use nalgebra::Isometry3;

use super::scalar::Scalar;
use super::vec3::{V3, norm_squared, sub, widen};
use super::{Point, Real};

/// A closed ball: every point within `radius` of `center`.
#[repr(C)]
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    /// Centre, in the units of the geometry it bounds (model or world space).
    pub center: Point,
    /// Radius, in the same units; a valid sphere's is finite and not
    /// negative ([`Sphere::is_valid`]). Zero is a single point.
    pub radius: Real,
}

impl Sphere {
    /// The closed ball of `radius` around `center` (nothing is checked: see
    /// [`Sphere::is_valid`]).
    pub const fn new(center: Point, radius: Real) -> Self {
        Self { center, radius }
    }

    /// Whether two closed balls share a point.
    ///
    /// Operation count (paper §2, §6): 10 — three subtractions, three
    /// multiplications and two additions for the squared distance, one addition
    /// and one multiplication for the squared sum of radii.
    /// In `f32`, the storage type; [`Sphere::overlaps_as`] is the same test
    /// in another [`Scalar`]. Closed sets: spheres that just touch overlap.
    ///
    /// ```
    /// use cornertree::geometry::{Point, Sphere};
    ///
    /// let a = Sphere::new(Point::new(0.0, 0.0, 0.0), 1.0);
    /// // Centres 2 apart, radii summing to 2: touching, which counts.
    /// let touching = Sphere::new(Point::new(2.0, 0.0, 0.0), 1.0);
    /// assert!(a.overlaps(&touching) && touching.overlaps(&a));
    /// // A gap of 0.01 between the surfaces: no contact.
    /// let apart = Sphere::new(Point::new(0.0, 2.01, 0.0), 1.0);
    /// assert!(!a.overlaps(&apart));
    /// // A small ball deep inside a big one overlaps it.
    /// let inner = Sphere::new(Point::new(0.5, 0.0, 0.0), 0.1);
    /// assert!(a.overlaps(&inner));
    /// ```
    #[inline]
    pub fn overlaps(&self, other: &Sphere) -> bool {
        self.overlaps_as::<Real>(other)
    }

    /// [`Sphere::overlaps`] computed in `T` (e.g. to count its operations).
    ///
    /// With [`Counted`](super::counted::Counted) it pays the paper's 10
    /// arithmetic operations (§6) and one comparison:
    ///
    /// ```
    /// use cornertree::geometry::counted::{Counted, Operations, count_operations_by_kind};
    /// use cornertree::geometry::{Point, Sphere};
    ///
    /// let a = Sphere::new(Point::new(0.0, 0.0, 0.0), 1.0);
    /// let b = Sphere::new(Point::new(1.0, 1.0, 1.0), 1.0);
    /// let (hit, ops) = count_operations_by_kind(|| a.overlaps_as::<Counted>(&b));
    /// assert!(hit); // centres √3 ≈ 1.73 apart, radii summing to 2
    /// assert_eq!(ops, Operations { arithmetic: 10, comparisons: 1 });
    /// // The same answer in f64 and in the storage type.
    /// assert_eq!(a.overlaps_as::<f64>(&b), hit);
    /// assert_eq!(a.overlaps(&b), hit);
    /// ```
    #[inline(always)]
    pub fn overlaps_as<T: Scalar>(&self, other: &Sphere) -> bool {
        balls_overlap(
            &widen::<T>(&self.center),
            T::from_f32(self.radius),
            &widen::<T>(&other.center),
            T::from_f32(other.radius),
        )
    }

    /// Whether `p` lies in the ball, allowing `tolerance` beyond the radius.
    /// Measured in `f64`, so `f32` rounding never moves a point across the surface.
    ///
    /// ```
    /// use cornertree::geometry::{Point, Sphere};
    ///
    /// let s = Sphere::new(Point::new(1.0, 0.0, 0.0), 2.0);
    /// assert!(s.contains_point(&Point::new(3.0, 0.0, 0.0), 0.0)); // on the surface
    /// assert!(!s.contains_point(&Point::new(3.5, 0.0, 0.0), 0.0));
    /// assert!(s.contains_point(&Point::new(3.5, 0.0, 0.0), 0.5));
    /// ```
    #[inline]
    pub fn contains_point(&self, p: &Point, tolerance: Real) -> bool {
        distance_f64(p, &self.center) <= self.radius as f64 + tolerance as f64
    }

    /// Whether `other` lies in this ball, allowing `tolerance` beyond the radius
    /// (measured in `f64`).
    ///
    /// ```
    /// use cornertree::geometry::{Point, Sphere};
    ///
    /// let big = Sphere::new(Point::origin(), 2.0);
    /// // Inside, touching the surface from within.
    /// assert!(big.contains_sphere(&Sphere::new(Point::new(1.0, 0.0, 0.0), 1.0), 0.0));
    /// // Sticking out by 0.1.
    /// assert!(!big.contains_sphere(&Sphere::new(Point::new(1.1, 0.0, 0.0), 1.0), 0.0));
    /// ```
    #[inline]
    pub fn contains_sphere(&self, other: &Sphere, tolerance: Real) -> bool {
        distance_f64(&other.center, &self.center) + other.radius as f64
            <= self.radius as f64 + tolerance as f64
    }

    /// Whether centre and radius are finite and the radius is not negative.
    ///
    /// ```
    /// use cornertree::geometry::{Point, Sphere};
    ///
    /// assert!(Sphere::new(Point::origin(), 0.0).is_valid());
    /// assert!(!Sphere::new(Point::origin(), -1.0).is_valid());
    /// assert!(!Sphere::new(Point::new(f32::NAN, 0.0, 0.0), 1.0).is_valid());
    /// ```
    pub fn is_valid(&self) -> bool {
        self.center.iter().all(|c| c.is_finite()) && self.radius.is_finite() && self.radius >= 0.0
    }

    /// This ball in the frame `to` maps into, grown to cover the rounding of
    /// the transform in `f32`: every point of the ball, mapped by `to`,
    /// lies in the result.
    ///
    /// ```
    /// use cornertree::geometry::{Point, Sphere};
    /// use nalgebra::{Isometry3, Vector3};
    ///
    /// let s = Sphere::new(Point::new(1.0, 0.0, 0.0), 0.5);
    /// let to = Isometry3::new(Vector3::new(0.0, 2.0, 0.0), Vector3::new(0.0, 0.0, 1.0));
    /// let moved = s.in_frame(&to);
    /// let far_point = to * Point::new(1.5, 0.0, 0.0);
    /// assert!(moved.contains_point(&far_point, 0.0));
    /// assert!(moved.radius < 0.5 + 1e-5);
    /// ```
    #[inline]
    pub fn in_frame(&self, to: &Isometry3<Real>) -> Sphere {
        let c = to * self.center;
        let pad = FRAME_CHANGE_SLACK
            * (self.center.coords.norm() + to.translation.vector.norm() + self.radius);
        Sphere::new(c, self.radius + pad)
    }
}

/// Relative slack added to a sphere's radius when it changes frame
/// ([`Sphere::in_frame`]): a rigid transform in `f32` moves a point by a few
/// units in the last place of its coordinates and of the translation; eight
/// is generous.
const FRAME_CHANGE_SLACK: Real = 8.0 * Real::EPSILON;

/// Whether the closed balls `(c1, r1)` and `(c2, r2)` share a point:
/// `‖c1 - c2‖² <= (r1 + r2)²` (the test of [`Sphere::overlaps`], on
/// centres and radii already in `T`; radii are assumed not negative).
///
/// ```
/// use cornertree::geometry::sphere::balls_overlap;
///
/// let o = [0.0f64, 0.0, 0.0];
/// // 3-4-5: centres 5 apart.
/// assert!(balls_overlap(&o, 2.0, &[3.0, 4.0, 0.0], 3.0)); // touching
/// assert!(!balls_overlap(&o, 2.0, &[3.0, 4.0, 0.0], 2.999));
/// ```
#[inline(always)]
pub fn balls_overlap<T: Scalar>(c1: &V3<T>, r1: T, c2: &V3<T>, r2: T) -> bool {
    let d = sub(c1, c2);
    let r = r1 + r2;
    norm_squared(&d) <= r * r
}

/// Euclidean distance computed in `f64`.
#[inline]
pub(crate) fn distance_f64(p: &Point, q: &Point) -> f64 {
    let d = nalgebra::Vector3::new(
        p.x as f64 - q.x as f64,
        p.y as f64 - q.y as f64,
        p.z as f64 - q.z as f64,
    );
    d.norm()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn touching_spheres_overlap_and_separated_do_not() {
        let a = Sphere::new(Point::new(0.0, 0.0, 0.0), 1.0);
        let b = Sphere::new(Point::new(2.0, 0.0, 0.0), 1.0);
        let c = Sphere::new(Point::new(2.0 + 1e-3, 0.0, 0.0), 1.0);
        assert!(a.overlaps(&b));
        assert!(!a.overlaps(&c));
        assert!(c.overlaps(&b));
    }

    #[test]
    fn containment() {
        let a = Sphere::new(Point::origin(), 2.0);
        assert!(a.contains_sphere(&Sphere::new(Point::new(1.0, 0.0, 0.0), 1.0), 0.0));
        assert!(!a.contains_sphere(&Sphere::new(Point::new(1.1, 0.0, 0.0), 1.0), 0.0));
        assert!(a.contains_point(&Point::new(0.0, 2.0, 0.0), 0.0));
    }
}
