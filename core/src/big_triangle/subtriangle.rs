//! Sub-triangles of a big triangle and the four-way midpoint split (§5, Fig. 2).

use crate::geometry::{Point, Real, Triangle};

/// A piece of an original triangle, with which of its edges lie on the
/// original triangle's boundary.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SubTriangle {
    /// The piece's corners, in the same space as the original triangle.
    pub triangle: Triangle,
    /// `boundary[k]` for edge k: ab, bc, ca.
    pub boundary: [bool; 3],
}

impl SubTriangle {
    /// The original triangle: all three edges on its boundary.
    pub fn whole(t: Triangle) -> Self {
        Self {
            triangle: t,
            boundary: [true; 3],
        }
    }

    /// Whether an edge lies on the original boundary (a vertex alone does not count).
    pub fn touches_boundary(&self) -> bool {
        self.boundary.iter().any(|b| *b)
    }

    /// Splits by joining the edge midpoints: three corner triangles, then the
    /// central one, which has no edge on the boundary. A midpoint is computed
    /// from the edge's two ends in a fixed order, so neighbours share it exactly.
    pub fn split(&self) -> [SubTriangle; 4] {
        let Triangle { a, b, c } = self.triangle;
        let (mab, mbc, mca) = (midpoint(&a, &b), midpoint(&b, &c), midpoint(&c, &a));
        let [ab, bc, ca] = self.boundary;
        [
            SubTriangle {
                triangle: Triangle::new(a, mab, mca),
                boundary: [ab, false, ca],
            },
            SubTriangle {
                triangle: Triangle::new(mab, b, mbc),
                boundary: [ab, bc, false],
            },
            SubTriangle {
                triangle: Triangle::new(mca, mbc, c),
                boundary: [false, bc, ca],
            },
            SubTriangle {
                triangle: Triangle::new(mab, mbc, mca),
                boundary: [false; 3],
            },
        ]
    }
}

/// Midpoint in `f64`, rounded once to `f32`; symmetric in its arguments.
fn midpoint(p: &Point, q: &Point) -> Point {
    let m = |x: Real, y: Real| ((x as f64 + y as f64) * 0.5) as Real;
    Point::new(m(p.x, q.x), m(p.y, q.y), m(p.z, q.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn split_tiles_and_tracks_boundary() {
        let t = Triangle::new(
            Point::new(0.0, 0.0, 0.0),
            Point::new(4.0, 0.0, 0.0),
            Point::new(1.0, 3.0, 0.0),
        );
        let parts = SubTriangle::whole(t).split();
        let sum: f32 = parts.iter().map(|p| p.triangle.area()).sum();
        assert!((sum - t.area()).abs() < 1e-5);
        assert!(
            parts[..3]
                .iter()
                .all(|p| p.boundary.iter().filter(|b| **b).count() == 2)
        );
        assert!(!parts[3].touches_boundary());
        // Grandchildren: of a corner's children, three keep a boundary edge.
        let g = parts[0].split();
        assert_eq!(g.iter().filter(|p| p.touches_boundary()).count(), 3);
    }
}
