//! Continuous collision detection never misses a contact that dense
//! sub-stepping sees, and its time of impact is never later than the first
//! sub-step in contact.
//!
//! Moving triangle pairs (and their vertex–face and edge–edge parts) on a
//! lattice of step `2⁻²⁰` whose motion per sub-step is a whole number of
//! lattice steps: the positions at each of the [`STEPS`] sub-steps are then
//! exact in `f32`, so the exact discrete oracle (`geometry::exact`, adaptive
//! predicates) decides contact at each sub-step on exactly the
//! configuration the continuous kernels see at that time. The pairs include
//! random motions, a corner aimed at a point of the other triangle (a
//! corner, an edge midpoint, a face point) at a chosen sub-step, exactly or
//! a few lattice steps off (touching and near-touching), zero-area triangles
//! (segments and points), coplanar sliding and still pairs.
//!
//! Separately, the stated false-positive bound: a positive answer certifies
//! (its witness) that the primitives come within the tolerance δ in every
//! coordinate, so pairs kept `2δ` apart are never reported.

use cornertree::geometry::ccd_edge_edge::edge_edge;
use cornertree::geometry::ccd_root_finder::{CcdParams, DEFAULT_TOLERANCE, Impact};
use cornertree::geometry::ccd_triangles::{MovingTriangle, triangles};
use cornertree::geometry::ccd_vertex_face::vertex_face;
use cornertree::geometry::exact::triangles_intersect_exact;
use cornertree::geometry::{Point, Triangle};
use proptest::prelude::*;

/// Sub-steps of the discrete reference over the step.
const STEPS: i64 = 256;
/// Lattice step.
const H: f64 = 1.0 / (1 << 20) as f64;
/// Lattice extent of the corners at `t = 0` (±0.5).
const EXTENT: i64 = 1 << 19;
/// Largest motion per sub-step, lattice steps (about 1.5 over the step).
const SPEED: i64 = 6144;

type L3 = [i64; 3];

/// A triangle on the lattice: corners at `t = 0` and their motion per
/// sub-step.
#[derive(Clone, Copy, Debug)]
struct LatticeTriangle {
    corners: [L3; 3],
    motion: [L3; 3],
}

impl LatticeTriangle {
    fn at(&self, k: i64) -> [L3; 3] {
        std::array::from_fn(|i| std::array::from_fn(|a| self.corners[i][a] + k * self.motion[i][a]))
    }

    fn moving(&self) -> MovingTriangle<f64> {
        MovingTriangle {
            start: self.at(0).map(real),
            end: self.at(STEPS).map(real),
        }
    }
}

fn real(p: L3) -> [f64; 3] {
    p.map(|x| x as f64 * H)
}

fn point(p: L3) -> Point {
    let [x, y, z] = real(p);
    Point::new(x as f32, y as f32, z as f32)
}

fn triangle(c: [L3; 3]) -> Triangle {
    Triangle::new(point(c[0]), point(c[1]), point(c[2]))
}

/// The first sub-step at which the exact oracle sees `a` and `b` (closed,
/// possibly degenerate triangles) meet.
fn first_contact(a: impl Fn(i64) -> [L3; 3], b: impl Fn(i64) -> [L3; 3]) -> Option<i64> {
    (0..=STEPS).find(|&k| triangles_intersect_exact(&triangle(a(k)), &triangle(b(k))))
}

fn lattice_point(r: i64) -> impl Strategy<Value = L3> {
    [-r..=r, -r..=r, -r..=r]
}

/// How a triangle is shaped.
#[derive(Clone, Copy, Debug)]
enum Shape {
    General,
    /// The third corner halfway along the first edge.
    Segment,
    /// All three corners at one point.
    Point,
}

fn shape() -> impl Strategy<Value = Shape> {
    prop_oneof![6 => Just(Shape::General), 1 => Just(Shape::Segment), 1 => Just(Shape::Point)]
}

/// How a triangle moves.
#[derive(Clone, Copy, Debug)]
enum Motion {
    Still,
    Rigid,
    Deforming,
}

fn motion() -> impl Strategy<Value = Motion> {
    prop_oneof![1 => Just(Motion::Still), 3 => Just(Motion::Rigid), 2 => Just(Motion::Deforming)]
}

/// A lattice triangle, corners and motions multiples of 4 (so points
/// `Σ wᵢ qᵢ / 4` with whole `wᵢ` stay on the lattice at every sub-step).
fn lattice_triangle(flat: bool) -> impl Strategy<Value = LatticeTriangle> {
    (
        [
            lattice_point(EXTENT / 4),
            lattice_point(EXTENT / 4),
            lattice_point(EXTENT / 4),
        ],
        [
            lattice_point(SPEED / 4),
            lattice_point(SPEED / 4),
            lattice_point(SPEED / 4),
        ],
        shape(),
        motion(),
    )
        .prop_map(move |(corners, motion_of, shape, how)| {
            let mut corners = corners.map(|p| p.map(|x| 4 * x));
            let mut motion = motion_of.map(|p| p.map(|x| 4 * x));
            match how {
                Motion::Still => motion = [[0; 3]; 3],
                Motion::Rigid => motion = [motion[0]; 3],
                Motion::Deforming => {}
            }
            match shape {
                Shape::General => {}
                Shape::Segment => {
                    corners[2] = std::array::from_fn(|a| (corners[0][a] + corners[1][a]) / 2);
                    motion[2] = std::array::from_fn(|a| (motion[0][a] + motion[1][a]) / 2);
                }
                Shape::Point => {
                    corners = [corners[0]; 3];
                    motion = [motion[0]; 3];
                }
            }
            if flat {
                for p in corners.iter_mut().chain(motion.iter_mut()) {
                    p[2] = 0;
                }
            }
            LatticeTriangle { corners, motion }
        })
}

/// A pair whose corner `vertex` of `a` reaches, at sub-step `k`, the point
/// `Σ wᵢ bᵢ(k) / 4` of `b` moved by `offset` lattice steps.
fn aimed_pair() -> impl Strategy<Value = (LatticeTriangle, LatticeTriangle)> {
    (
        lattice_triangle(false),
        lattice_triangle(false),
        0usize..3,
        0..=STEPS,
        prop_oneof![
            Just([4, 0, 0]),
            Just([2, 2, 0]),
            Just([2, 1, 1]),
            Just([1, 1, 2]),
            Just([0, 3, 1])
        ],
        prop_oneof![2 => Just([0i64; 3]), 1 => lattice_point(2), 1 => lattice_point(64)],
    )
        .prop_map(|(mut a, b, vertex, k, w, offset)| {
            let bk = b.at(k);
            let target: L3 = std::array::from_fn(|x| {
                (w[0] * bk[0][x] + w[1] * bk[1][x] + w[2] * bk[2][x]) / 4 + offset[x]
            });
            let shift: L3 = std::array::from_fn(|x| {
                target[x] - (a.corners[vertex][x] + k * a.motion[vertex][x])
            });
            for c in a.corners.iter_mut() {
                for x in 0..3 {
                    c[x] += shift[x];
                }
            }
            (a, b)
        })
}

fn any_pair() -> impl Strategy<Value = (LatticeTriangle, LatticeTriangle)> {
    prop_oneof![
        2 => (lattice_triangle(false), lattice_triangle(false)),
        3 => aimed_pair(),
        // Coplanar: everything in z = 0, sliding in the plane.
        1 => (lattice_triangle(true), lattice_triangle(true)),
    ]
}

fn params() -> CcdParams {
    CcdParams::default()
}

/// `t` is at most sub-step `k`'s time.
fn not_after(toi: f64, k: i64) -> bool {
    toi <= k as f64 / STEPS as f64
}

/// `F` of a vertex–face (`edge = false`) or edge–edge query at `(t, u, v)`.
fn contact_function(
    start: &[[f64; 3]; 4],
    end: &[[f64; 3]; 4],
    edge: bool,
    t: f64,
    u: f64,
    v: f64,
) -> [f64; 3] {
    std::array::from_fn(|a| {
        let x: [f64; 4] = std::array::from_fn(|i| start[i][a] + t * (end[i][a] - start[i][a]));
        if edge {
            x[0] + u * (x[1] - x[0]) - x[2] - v * (x[3] - x[2])
        } else {
            x[0] - x[1] - u * (x[2] - x[1]) - v * (x[3] - x[1])
        }
    })
}

/// The witness of a positive answer holds a point of the domain where every
/// coordinate of `F` is within the certified bound (up to this test's own
/// rounding), and a resolved answer certifies the tolerance.
fn check_witness(
    start: &[[f64; 3]; 4],
    end: &[[f64; 3]; 4],
    edge: bool,
    hit: &Impact,
    tolerance: f64,
) -> Result<(), TestCaseError> {
    let w = hit.witness;
    let (t, u, v) = (w.t.lo(), w.u.lo(), w.v.lo());
    prop_assert!(
        edge || u + v <= 1.0,
        "witness outside the triangle: {hit:?}"
    );
    prop_assert!(hit.toi <= t, "{hit:?}");
    if hit.resolved {
        prop_assert!(hit.within <= tolerance, "{hit:?}");
    }
    let f = contact_function(start, end, edge, t, u, v);
    for c in f {
        prop_assert!(
            c.abs() <= hit.within + 1e-12,
            "F = {f:?} at the witness of {hit:?}"
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]

    /// Triangle pairs: no contact seen by the sub-steps is missed, and the
    /// time of impact is not after the first sub-step in contact.
    #[test]
    fn triangles_never_miss_a_substep_contact((a, b) in any_pair()) {
        let first = first_contact(|k| a.at(k), |k| b.at(k));
        // Either argument order.
        for (x, y) in [(&a, &b), (&b, &a)] {
            let hit = triangles(&x.moving(), &y.moving(), &params());
            if let Some(k) = first {
                prop_assert!(
                    hit.is_some_and(|h| not_after(h.toi, k)),
                    "contact at sub-step {k}, answer {hit:?}: {x:?} {y:?}"
                );
            }
        }
    }

    /// Vertex–face: corner `i` of `a` against `b`.
    #[test]
    fn vertex_face_never_misses((a, b) in any_pair(), i in 0usize..3) {
        let p = |k: i64| [a.at(k)[i]; 3];
        let first = first_contact(p, |k| b.at(k));
        let pack = |k: i64| {
            let (q, t) = (a.at(k)[i], b.at(k));
            [real(q), real(t[0]), real(t[1]), real(t[2])]
        };
        let (start, end) = (pack(0), pack(STEPS));
        let hit = vertex_face(&start, &end, &params());
        if let Some(k) = first {
            prop_assert!(hit.is_some_and(|h| not_after(h.toi, k)), "sub-step {k}: {hit:?}, {a:?} {b:?}");
        }
        if let Some(h) = hit {
            check_witness(&start, &end, false, &h, params().tolerance)?;
        }
    }

    /// Edge–edge: edge `i` of `a` against edge `j` of `b`.
    #[test]
    fn edge_edge_never_misses((a, b) in any_pair(), i in 0usize..3, j in 0usize..3) {
        let edge = |t: &LatticeTriangle, i: usize, k: i64| {
            let c = t.at(k);
            [c[i], c[(i + 1) % 3], c[(i + 1) % 3]]
        };
        let first = first_contact(|k| edge(&a, i, k), |k| edge(&b, j, k));
        let pack = |k: i64| {
            let (x, y) = (edge(&a, i, k), edge(&b, j, k));
            [real(x[0]), real(x[1]), real(y[0]), real(y[1])]
        };
        let (start, end) = (pack(0), pack(STEPS));
        let hit = edge_edge(&start, &end, &params());
        if let Some(k) = first {
            prop_assert!(hit.is_some_and(|h| not_after(h.toi, k)), "sub-step {k}: {hit:?}, {a:?} {b:?}");
        }
        if let Some(h) = hit {
            check_witness(&start, &end, true, &h, params().tolerance)?;
        }
    }
}

fn unit(v: [f64; 3]) -> [f64; 3] {
    let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
    v.map(|x| x / n)
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn along(p: [f64; 3], d: [f64; 3], s: f64) -> [f64; 3] {
    std::array::from_fn(|a| p[a] + s * d[a])
}

fn direction() -> impl Strategy<Value = [f64; 3]> {
    [-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64]
        .prop_filter("not too short", |v| {
            v.iter().map(|x| x * x).sum::<f64>() > 0.05
        })
        .prop_map(unit)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(2000))]

    /// A point kept at distance `h ≥ 2δ` above a triangle's interior while
    /// both travel together (so apart by more than `√3 δ` all along) is
    /// never reported; at `h = 0` it always is.
    #[test]
    fn vertex_face_false_positives_stay_within_the_bound(
        a in direction(), b in direction(), c in direction(),
        travel in direction(), far in 0.0..2.0f64,
        w in (0.05..1.0f64, 0.05..1.0f64, 0.05..1.0f64),
        gap in 2.0..1000.0f64,
    ) {
        let n = cross(along(b, a, -1.0), along(c, a, -1.0));
        prop_assume!(n.iter().map(|x| x * x).sum::<f64>() > 0.01);
        let n = unit(n);
        let s = w.0 + w.1 + w.2;
        let inside: [f64; 3] = std::array::from_fn(|k| (w.0 * a[k] + w.1 * b[k] + w.2 * c[k]) / s);
        for (h, touching) in [(gap * DEFAULT_TOLERANCE, false), (0.0, true)] {
            let p = along(inside, n, h);
            let start = [p, a, b, c];
            let end = start.map(|q| along(q, travel, far));
            let hit = vertex_face(&start, &end, &params());
            prop_assert_eq!(hit.is_some(), touching, "h = {}: {:?}", h, hit);
        }
    }

    /// Two crossing edges kept `h ≥ 2δ` apart along their common normal
    /// while both travel together are never reported; at `h = 0` they are.
    #[test]
    fn edge_edge_false_positives_stay_within_the_bound(
        centre in direction(), e1 in direction(), e2 in direction(),
        travel in direction(), far in 0.0..2.0f64, gap in 2.0..1000.0f64,
    ) {
        let n = cross(e1, e2);
        prop_assume!(n.iter().map(|x| x * x).sum::<f64>() > 0.01);
        let n = unit(n);
        for (h, touching) in [(gap * DEFAULT_TOLERANCE, false), (0.0, true)] {
            let other = along(centre, n, h);
            let start = [along(centre, e1, -0.5), along(centre, e1, 0.5), along(other, e2, -0.5), along(other, e2, 0.5)];
            let end = start.map(|q| along(q, travel, far));
            let hit = edge_edge(&start, &end, &params());
            prop_assert_eq!(hit.is_some(), touching, "h = {}: {:?}", h, hit);
        }
    }
}

// ---- The swept hierarchies' parts (issue 14, item 4) on the same pairs. ----

use cornertree::geometry::ccd_sphere_plane::sweep_meets_plane;
use cornertree::geometry::enclosing::triangle_sphere;
use cornertree::pipeline::continuous_narrow::{CcdCounters, leaf_toi};
use cornertree::sphere_tree::swept::SphereSweep;

/// `a` held still at its start.
fn still(a: &LatticeTriangle) -> LatticeTriangle {
    LatticeTriangle {
        corners: a.corners,
        motion: [[0; 3]; 3],
    }
}

/// `a`'s minimal spheres at both ends of the step, grown by `grow`.
fn end_spheres(a: &LatticeTriangle, grow: f32) -> SphereSweep {
    let at = |k| {
        let mut s = triangle_sphere(&triangle(a.at(k)));
        s.radius += grow;
        s
    };
    SphereSweep {
        start: at(0),
        end: at(STEPS),
    }
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(600))]

    /// The pipeline's leaf test of a triangle pair (the plane-side skip
    /// against a still triangle, the exact test at the start, the kernel:
    /// `continuous_narrow::leaf_toi`) misses no sub-step contact, against a
    /// moving or a still second triangle.
    #[test]
    fn leaf_test_never_misses_a_substep_contact(
        (a, b) in any_pair(),
        b_still in any::<bool>(),
    ) {
        let b = if b_still { still(&b) } else { b };
        let first = first_contact(|k| a.at(k), |k| b.at(k));
        let mut c = CcdCounters::default();
        let toi = leaf_toi(&a.moving(), &b.moving(), b_still, &params(), &mut c);
        if let Some(k) = first {
            prop_assert!(
                toi.is_some_and(|t| not_after(t, k)),
                "contact at sub-step {k}, answer {toi:?} ({c:?}): {a:?} {b:?}"
            );
        }
    }

    /// A triangle moving linearly stays, at every sub-step, inside the
    /// sphere interpolated between spheres holding it at both ends and
    /// inside the swept sphere around both (`sphere_tree::swept`).
    #[test]
    fn interpolated_and_swept_spheres_hold_the_moving_triangle(
        (a, _) in any_pair(),
        grow in 0.0f32..0.05,
    ) {
        let sweep = end_spheres(&a, grow);
        let swept = sweep.swept();
        for k in 0..=STEPS {
            let t = k as f64 / STEPS as f64;
            let s = sweep.at(t);
            for p in a.at(k).map(real) {
                let q = Point::new(p[0] as f32, p[1] as f32, p[2] as f32);
                // `p` is exact; its `f32` copy is within an ulp of 0.5.
                prop_assert!(s.contains_point(&q, 1e-7), "sub-step {k}: {p:?} outside {s:?}");
                prop_assert!(swept.contains_point(&q, 1e-7), "sub-step {k}: {p:?} outside {swept:?}");
            }
        }
    }

    /// The moving sphere against a still triangle's plane: whenever the
    /// triangle it holds touches the still triangle at a sub-step, the
    /// plane test answers with a time of impact no later.
    #[test]
    fn sphere_against_plane_never_misses_a_substep_contact(
        (a, b) in any_pair(),
        grow in 0.0f32..0.01,
    ) {
        let b = still(&b);
        let Some(k) = first_contact(|k| a.at(k), |k| b.at(k)) else {
            return Ok(());
        };
        let sweep = end_spheres(&a, grow);
        let plane = triangle(b.at(0));
        let [p, q, r] = b.at(0).map(real);
        let (e, f) = ([q[0] - p[0], q[1] - p[1], q[2] - p[2]], [r[0] - p[0], r[1] - p[1], r[2] - p[2]]);
        if e[1] * f[2] == e[2] * f[1] && e[2] * f[0] == e[0] * f[2] && e[0] * f[1] == e[1] * f[0] {
            return Ok(()); // no plane: the test answers `None` by design
        }
        let toi = sweep_meets_plane(&sweep.start, &sweep.end, &plane);
        prop_assert!(
            toi.is_some_and(|t| t <= k as f64 / STEPS as f64 + 1e-9),
            "contact at sub-step {k}, answer {toi:?}"
        );
    }
}
