//! Exact triangle-triangle oracle on adaptive exact predicates.
//! STUB: to be implemented.

use super::Triangle;

/// How two closed triangles meet, decided exactly.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Contact {
    /// No common point.
    Disjoint,
    /// They meet, but only on the boundary of at least one of them.
    Touching,
    /// Their relative interiors share a point.
    Overlapping,
}

/// Exact classification of a triangle pair.
pub fn classify(_t1: &Triangle, _t2: &Triangle) -> Contact {
    unimplemented!("exact")
}
