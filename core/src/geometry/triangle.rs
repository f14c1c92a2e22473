//! A triangle given by its three corners.

use super::{Point, Real, Vector};

/// Three corners; the orientation (counter-clockwise seen from the normal) is
/// kept as stored but no test depends on it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Triangle {
    pub a: Point,
    pub b: Point,
    pub c: Point,
}

impl Triangle {
    pub const fn new(a: Point, b: Point, c: Point) -> Self {
        Self { a, b, c }
    }

    /// The corners as an array.
    #[inline]
    pub fn vertices(&self) -> [Point; 3] {
        [self.a, self.b, self.c]
    }

    /// Unnormalised normal `(b - a) × (c - a)`; zero for a degenerate triangle.
    #[inline]
    pub fn scaled_normal(&self) -> Vector {
        (self.b - self.a).cross(&(self.c - self.a))
    }

    pub fn area(&self) -> Real {
        0.5 * self.scaled_normal().norm()
    }

    pub fn centroid(&self) -> Point {
        Point::from((self.a.coords + self.b.coords + self.c.coords) / 3.0)
    }

    /// The three edges as (start, end) pairs: ab, bc, ca.
    #[inline]
    pub fn edges(&self) -> [(Point, Point); 3] {
        [(self.a, self.b), (self.b, self.c), (self.c, self.a)]
    }

    /// Length of the longest edge.
    pub fn longest_edge(&self) -> Real {
        self.edges()
            .iter()
            .map(|(p, q)| (q - p).norm())
            .fold(0.0, Real::max)
    }

    /// Whether every coordinate is finite.
    pub fn is_finite(&self) -> bool {
        self.vertices()
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite()))
    }
}
