//! Hand-made triangle pairs with known answers, checked on the exact oracle
//! (`exact::classify`), on both floating-point kernels (the Tropp test and
//! the edge-crossing test) and on their counting instantiations, under every
//! corner order and both argument orders.

use cornertree::geometry::counted::Counted;
use cornertree::geometry::exact::{Contact, classify, triangles_intersect_exact};
use cornertree::geometry::{Point, Triangle, edge_crossing, tri_tri, tropp};

use Contact::{Disjoint, Overlapping, Touching};

type C = [f32; 3];

/// A triangle-triangle test.
type TriTest = fn(&Triangle, &Triangle) -> bool;

fn tri(a: C, b: C, c: C) -> Triangle {
    Triangle::new(Point::from(a), Point::from(b), Point::from(c))
}

/// The six corner orders of a triangle.
fn orders(t: &Triangle) -> [Triangle; 6] {
    let [a, b, c] = t.vertices();
    [
        Triangle::new(a, b, c),
        Triangle::new(b, c, a),
        Triangle::new(c, a, b),
        Triangle::new(a, c, b),
        Triangle::new(c, b, a),
        Triangle::new(b, a, c),
    ]
}

fn check(name: &str, t1: Triangle, t2: Triangle, want: Contact) {
    for x in orders(&t1) {
        for y in orders(&t2) {
            for (p, q) in [(x, y), (y, x)] {
                assert_eq!(classify(&p, &q), want, "{name}: oracle on {p:?} / {q:?}");
                assert_eq!(
                    triangles_intersect_exact(&p, &q),
                    want != Disjoint,
                    "{name}: exact bool"
                );
                let kernels: [(&str, TriTest); 5] = [
                    ("Tropp", tropp::triangles_intersect),
                    ("Tropp, counted", tropp::triangles_intersect_as::<Counted>),
                    ("edge-crossing", edge_crossing::triangles_intersect),
                    (
                        "edge-crossing, counted",
                        edge_crossing::triangles_intersect_as::<Counted>,
                    ),
                    ("narrow phase", tri_tri::triangles_intersect),
                ];
                for (kernel, test) in kernels {
                    assert_eq!(
                        test(&p, &q),
                        want != Disjoint,
                        "{name}: {kernel} test on {p:?} / {q:?}"
                    );
                }
            }
        }
    }
}

/// The unit right triangle in z = 0.
fn base() -> Triangle {
    tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0])
}

#[test]
fn shared_vertex() {
    check(
        "apart",
        base(),
        tri([0.0, 0.0, 0.0], [-1.0, 0.0, 1.0], [0.0, -1.0, 1.0]),
        Touching,
    );
    check(
        "coplanar, opposite",
        base(),
        tri([0.0, 0.0, 0.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]),
        Touching,
    );
    check(
        "piercing from the vertex",
        base(),
        tri([0.0, 0.0, 0.0], [1.0, 1.0, 1.0], [1.0, 1.0, -1.0]),
        Overlapping,
    );
    check(
        "coplanar, inside the angle",
        base(),
        tri([0.0, 0.0, 0.0], [0.5, 0.25, 0.0], [0.25, 0.5, 0.0]),
        Overlapping,
    );
}

#[test]
fn shared_edge() {
    check(
        "hinge",
        base(),
        tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 1.0]),
        Touching,
    );
    check(
        "coplanar, opposite sides",
        base(),
        tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, -1.0, 0.0]),
        Touching,
    );
    check(
        "coplanar, same side",
        base(),
        tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]),
        Overlapping,
    );
    check(
        "partial collinear edge, coplanar",
        base(),
        tri([0.5, 0.0, 0.0], [2.0, 0.0, 0.0], [1.0, -1.0, 0.0]),
        Touching,
    );
}

#[test]
fn coplanar() {
    check(
        "overlap",
        base(),
        tri([0.2, 0.2, 0.0], [2.0, 0.2, 0.0], [0.2, 2.0, 0.0]),
        Overlapping,
    );
    check(
        "contained",
        base(),
        tri([0.1, 0.1, 0.0], [0.3, 0.1, 0.0], [0.1, 0.3, 0.0]),
        Overlapping,
    );
    check(
        "star of David",
        tri([0.0, 0.0, 0.0], [4.0, 0.0, 0.0], [2.0, 4.0, 0.0]),
        tri([0.0, 3.0, 0.0], [4.0, 3.0, 0.0], [2.0, -1.0, 0.0]),
        Overlapping,
    );
    check(
        "disjoint",
        base(),
        tri([1.0, 1.0, 0.0], [2.0, 1.0, 0.0], [1.0, 2.0, 0.0]),
        Disjoint,
    );
    check(
        "vertex on edge",
        base(),
        tri([0.5, 0.5, 0.0], [1.0, 1.0, 0.0], [0.5, 2.0, 0.0]),
        Touching,
    );
    check(
        "vertex to vertex",
        base(),
        tri([1.0, 0.0, 0.0], [2.0, 0.0, 0.0], [2.0, 1.0, 0.0]),
        Touching,
    );
    check(
        "tilted plane",
        tri([0.0, 0.0, 0.0], [2.0, 0.0, 2.0], [0.0, 2.0, 2.0]),
        tri([1.0, 0.0, 1.0], [0.0, 1.0, 1.0], [2.0, 2.0, 4.0]),
        Overlapping,
    );
    check(
        "tilted plane, apart",
        tri([0.0, 0.0, 0.0], [2.0, 0.0, 2.0], [0.0, 2.0, 2.0]),
        tri([2.0, 1.0, 3.0], [1.0, 2.0, 3.0], [2.0, 2.0, 4.0]),
        Disjoint,
    );
}

#[test]
fn vertex_on_face_and_edges() {
    check(
        "vertex on face",
        base(),
        tri([0.25, 0.25, 0.0], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]),
        Touching,
    );
    check(
        "vertex on edge",
        base(),
        tri([0.5, 0.0, 0.0], [0.5, -1.0, 1.0], [0.5, 1.0, 1.0]),
        Touching,
    );
    check(
        "edge crosses edge",
        base(),
        tri([0.5, 1.0, 1.0], [0.5, -1.0, -1.0], [0.5, -1.0, 1.0]),
        Touching,
    );
    check(
        "edge lies on face",
        base(),
        tri([0.1, 0.1, 0.0], [0.6, 0.1, 0.0], [0.3, 0.3, 1.0]),
        Touching,
    );
    check(
        "vertex just above face",
        base(),
        tri([0.25, 0.25, 1e-6], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]),
        Disjoint,
    );
    check(
        "vertex just below face",
        base(),
        tri([0.25, 0.25, -1e-6], [0.0, 0.0, 1.0], [1.0, 1.0, 1.0]),
        Overlapping,
    );
}

#[test]
fn piercing() {
    check(
        "edge through face",
        base(),
        tri([0.25, 0.25, -1.0], [0.25, 0.25, 1.0], [3.0, 3.0, 0.0]),
        Overlapping,
    );
    check(
        "interlocked",
        base(),
        tri([0.5, 0.2, -1.0], [0.5, 0.2, 1.0], [0.5, -2.0, 0.0]),
        Overlapping,
    );
    check(
        "plane crossed beside the triangle",
        base(),
        tri([2.0, 2.0, -1.0], [2.0, 2.0, 1.0], [3.0, 1.0, 0.0]),
        Disjoint,
    );
    // The base plane cuts these in the segment (0.8, -0.5)-(1.5, 0.3), which
    // passes beside the corner (1, 0): only the segment's line separates.
    check(
        "plane crossed beside a corner",
        base(),
        tri([0.8, -0.5, -1.0], [0.8, -0.5, 1.0], [1.5, 0.3, 0.0]),
        Disjoint,
    );
    // Cut in (0.8, -0.5)-(0.9, 0.3): in through one edge, out through another.
    check(
        "plane crossed across a corner",
        base(),
        tri([0.8, -0.5, -1.0], [0.8, -0.5, 1.0], [0.9, 0.3, 0.0]),
        Overlapping,
    );
}

#[test]
fn parallel_planes() {
    check(
        "above",
        base(),
        tri([0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]),
        Disjoint,
    );
    check(
        "tiny gap",
        base(),
        tri([0.1, 0.1, 1e-6], [1.0, 0.1, 1e-6], [0.1, 1.0, 1e-6]),
        Disjoint,
    );
}

#[test]
fn zero_area() {
    let seg = |a: C, b: C| {
        tri(
            a,
            b,
            [
                (a[0] + b[0]) / 2.0,
                (a[1] + b[1]) / 2.0,
                (a[2] + b[2]) / 2.0,
            ],
        )
    };
    let point = |p: C| tri(p, p, p);
    check(
        "segment pierces face",
        base(),
        seg([0.2, 0.2, -1.0], [0.2, 0.2, 1.0]),
        Touching,
    );
    check(
        "segment ends on face",
        base(),
        seg([0.2, 0.2, 0.0], [0.2, 0.2, 1.0]),
        Touching,
    );
    check(
        "segment above face",
        base(),
        seg([0.2, 0.2, 0.5], [0.2, 0.2, 1.0]),
        Disjoint,
    );
    check(
        "segment in plane, crossing",
        base(),
        seg([-1.0, 0.5, 0.0], [2.0, 0.5, 0.0]),
        Touching,
    );
    check(
        "segment in plane, outside",
        base(),
        seg([-1.0, 2.0, 0.0], [2.0, 2.0, 0.0]),
        Disjoint,
    );
    check("point on face", base(), point([0.25, 0.25, 0.0]), Touching);
    check("point on corner", base(), point([1.0, 0.0, 0.0]), Touching);
    check(
        "point off face",
        base(),
        point([0.25, 0.25, 0.25]),
        Disjoint,
    );
    check(
        "point in plane, outside",
        base(),
        point([1.0, 1.0, 0.0]),
        Disjoint,
    );
    check(
        "crossing segments",
        seg([0.0, 0.0, 0.0], [2.0, 2.0, 0.0]),
        seg([2.0, 0.0, 0.0], [0.0, 2.0, 0.0]),
        Touching,
    );
    check(
        "skew segments",
        seg([0.0, 0.0, 0.0], [2.0, 2.0, 0.0]),
        seg([2.0, 0.0, 1.0], [0.0, 2.0, 1.0]),
        Disjoint,
    );
    check(
        "collinear overlapping",
        seg([0.0, 0.0, 0.0], [2.0, 2.0, 2.0]),
        seg([1.0, 1.0, 1.0], [3.0, 3.0, 3.0]),
        Touching,
    );
    check(
        "collinear apart",
        seg([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
        seg([2.0, 2.0, 2.0], [3.0, 3.0, 3.0]),
        Disjoint,
    );
    check(
        "parallel segments",
        seg([0.0, 0.0, 0.0], [1.0, 1.0, 1.0]),
        seg([0.0, 0.0, 1.0], [1.0, 1.0, 2.0]),
        Disjoint,
    );
    check(
        "point on segment",
        seg([0.0, 0.0, 0.0], [2.0, 2.0, 2.0]),
        point([0.5, 0.5, 0.5]),
        Touching,
    );
    check(
        "same point",
        point([1.0, 2.0, 3.0]),
        point([1.0, 2.0, 3.0]),
        Touching,
    );
    check(
        "different points",
        point([1.0, 2.0, 3.0]),
        point([1.0, 2.0, 3.5]),
        Disjoint,
    );
    // Two equal corners: a segment with a doubled end.
    check(
        "doubled corner",
        base(),
        tri([0.3, 0.3, -1.0], [0.3, 0.3, -1.0], [0.3, 0.3, 1.0]),
        Touching,
    );
}

#[test]
fn identical() {
    check("same triangle", base(), base(), Overlapping);
    let t = tri([0.1, -2.5, 3.0], [7.25, 1.0, -0.5], [-3.0, 4.0, 1.5]);
    check("same general triangle", t, t, Overlapping);
}

/// A corner of the first triangle on the second's face, at coordinates that
/// are not round (a pair from `tests/tri_tri_agreement.rs`): seen from the
/// first triangle's plane the contact is on its corner, where rounding
/// decides; Tropp's test finds it with the roles swapped.
#[test]
fn corner_on_face_not_round() {
    let corner_first = tri(
        [-0.114985466, 0.58111477, -0.15904331],
        [-0.012040138, 0.31498623, 0.29553318],
        [0.28640366, 0.46795082, -0.045988083],
    );
    let face = tri(
        [0.8990326, 0.36977386, -0.8082504],
        [0.017082214, 0.66830444, 0.13300323],
        [0.407753, -0.33746338, 0.58358],
    );
    assert_eq!(classify(&corner_first, &face), Touching);
    for (p, q) in [(corner_first, face), (face, corner_first)] {
        assert!(tropp::triangles_intersect(&p, &q));
        assert!(edge_crossing::triangles_intersect(&p, &q));
    }
}
