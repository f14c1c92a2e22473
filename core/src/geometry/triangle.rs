//! A triangle given by its three corners.

use super::{Point, Real, Vector};

/// Three corners; the orientation (counter-clockwise seen from the normal) is
/// kept as stored but no test depends on it. The tests treat it as a closed
/// set (edges and corners included); collinear corners make a zero-area
/// triangle, which the tests handle as the segment or point it is.
///
/// ```
/// use cornertree::geometry::{Point, Triangle};
///
/// let t = Triangle::new(
///     Point::new(0.0, 0.0, 0.0),
///     Point::new(3.0, 0.0, 0.0),
///     Point::new(0.0, 3.0, 0.0),
/// );
/// assert_eq!(t.vertices(), [t.a, t.b, t.c]);
/// assert_eq!(t.edges()[1], (t.b, t.c));
/// ```
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    /// First corner.
    pub a: Point,
    /// Second corner.
    pub b: Point,
    /// Third corner.
    pub c: Point,
}

impl Triangle {
    /// The triangle with corners `a`, `b`, `c`, in that order.
    pub const fn new(a: Point, b: Point, c: Point) -> Self {
        Self { a, b, c }
    }

    /// The corners as an array.
    #[inline]
    pub fn vertices(&self) -> [Point; 3] {
        [self.a, self.b, self.c]
    }

    /// Unnormalised normal `(b - a) × (c - a)`; zero for a degenerate triangle.
    /// Its length is twice the area.
    ///
    /// ```
    /// use cornertree::geometry::{Point, Triangle, Vector};
    ///
    /// let t = Triangle::new(
    ///     Point::new(0.0, 0.0, 0.0),
    ///     Point::new(3.0, 0.0, 0.0),
    ///     Point::new(0.0, 3.0, 0.0),
    /// );
    /// // Counter-clockwise seen from +z.
    /// assert_eq!(t.scaled_normal(), Vector::new(0.0, 0.0, 9.0));
    /// let flipped = Triangle::new(t.a, t.c, t.b);
    /// assert_eq!(flipped.scaled_normal(), Vector::new(0.0, 0.0, -9.0));
    /// ```
    #[inline]
    pub fn scaled_normal(&self) -> Vector {
        (self.b - self.a).cross(&(self.c - self.a))
    }

    /// Area, half the length of [`Triangle::scaled_normal`]; zero for a
    /// degenerate triangle.
    ///
    /// ```
    /// use cornertree::geometry::{Point, Triangle};
    ///
    /// let t = Triangle::new(
    ///     Point::new(0.0, 0.0, 0.0),
    ///     Point::new(3.0, 0.0, 0.0),
    ///     Point::new(0.0, 3.0, 0.0),
    /// );
    /// assert_eq!(t.area(), 4.5);
    /// let collinear = Triangle::new(t.a, t.b, Point::new(6.0, 0.0, 0.0));
    /// assert_eq!(collinear.area(), 0.0);
    /// ```
    pub fn area(&self) -> Real {
        0.5 * self.scaled_normal().norm()
    }

    /// The mean of the three corners.
    ///
    /// ```
    /// use cornertree::geometry::{Point, Triangle};
    ///
    /// let t = Triangle::new(
    ///     Point::new(0.0, 0.0, 0.0),
    ///     Point::new(3.0, 0.0, 0.0),
    ///     Point::new(0.0, 3.0, 6.0),
    /// );
    /// assert_eq!(t.centroid(), Point::new(1.0, 1.0, 2.0));
    /// ```
    pub fn centroid(&self) -> Point {
        Point::from((self.a.coords + self.b.coords + self.c.coords) / 3.0)
    }

    /// The three edges as (start, end) pairs: ab, bc, ca.
    #[inline]
    pub fn edges(&self) -> [(Point, Point); 3] {
        [(self.a, self.b), (self.b, self.c), (self.c, self.a)]
    }

    /// Length of the longest edge.
    ///
    /// ```
    /// use cornertree::geometry::{Point, Triangle};
    ///
    /// let t = Triangle::new(
    ///     Point::new(0.0, 0.0, 0.0),
    ///     Point::new(3.0, 0.0, 0.0),
    ///     Point::new(0.0, 4.0, 0.0),
    /// );
    /// assert_eq!(t.longest_edge(), 5.0); // the hypotenuse of 3-4-5
    /// ```
    pub fn longest_edge(&self) -> Real {
        self.edges()
            .iter()
            .map(|(p, q)| (q - p).norm())
            .fold(0.0, Real::max)
    }

    /// Whether every coordinate is finite.
    ///
    /// ```
    /// use cornertree::geometry::{Point, Triangle};
    ///
    /// let p = Point::new(1.0, 2.0, 3.0);
    /// assert!(Triangle::new(p, p, p).is_finite());
    /// let q = Point::new(1.0, f32::INFINITY, 3.0);
    /// assert!(!Triangle::new(p, q, p).is_finite());
    /// ```
    pub fn is_finite(&self) -> bool {
        self.vertices()
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite()))
    }
}
