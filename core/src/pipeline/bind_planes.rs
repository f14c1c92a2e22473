//! A big triangle's plane and edge planes seen from the bind space of a
//! joint, so that a character triangle that joint alone moves is answered
//! from its rest corners, before (and instead of) skinning them.
//!
//! A corner `v` that joint `j` alone moves ([`Character::sole_joint`]) is
//! skinned to `x = fl(M·v)`, within `e` of `M·v = A·v + t`
//! ([`sole_joint_rounding`]). Its offset from a plane `n·x = d` is
//! `n·x − d = (Aᵀn)·v + (n·t − d) + n·(x − M·v)`: the first two terms are
//! the plane taken into the joint's bind space once (per big triangle and
//! joint in a pass), the last is at most `|n|·e`. Each answer below needs
//! every offset it reads to clear four times that bound, plus the margin
//! the narrow phase itself would apply to the skinned corner, plus a
//! relative `10⁻¹²` for the `f64` evaluation here; then the narrow phase,
//! run on the skinned corners, would give the same answer at the same step:
//!
//! - **apart**: the three corners on one side of the big triangle's plane
//!   (past its snapping, `16ε·|u|·|v|·|x − p₀|`, [`Prepared::plane`]): the
//!   triangle test's first plane-side exit
//!   ([`Prepared::plane_has_on_one_side`]);
//! - **contact**: corners on both sides of the plane, and all three inside
//!   the big triangle's three edge planes (past their margin,
//!   [`TrianglePrism::holds_inside`]): the triangle crosses the plane inside
//!   the triangle.
//!
//! Anything else (a corner near a plane) is left to the skinned test.
//!
//! [`Character::sole_joint`]: crate::character::Character::sole_joint
//! [`sole_joint_rounding`]: crate::character::skinning::sole_joint_rounding
//! [`Prepared::plane`]: crate::geometry::tropp::Prepared::plane
//! [`Prepared::plane_has_on_one_side`]: crate::geometry::tropp::Prepared::plane_has_on_one_side

use nalgebra::{Matrix4, Vector3};

use crate::character::skinning::{largest_row_sum, sole_joint_rounding};
use crate::geometry::coplanar_degenerate::SNAP;
use crate::geometry::triangle_prism::{MARGIN, TrianglePrism};
use crate::geometry::tropp::Prepared;
use crate::geometry::{Point, Triangle};

/// Entries of the table (a power of two): a pass meets few big triangles,
/// and a character few joints near each.
const SLOTS: usize = 64;

/// A plane in a joint's bind space: a bind corner's offset is
/// `normal·v + offset`, and an answer needs it past `±margin` (not finite:
/// never).
#[derive(Clone, Copy, Debug)]
struct BindPlane {
    normal: [f64; 3],
    offset: f64,
    margin: f64,
}

impl BindPlane {
    /// Never past its margin.
    const NONE: Self = Self {
        normal: [0.0; 3],
        offset: 0.0,
        margin: f64::INFINITY,
    };

    /// The plane `n·x = d` in the bind space of skin matrix `m`; `margin`:
    /// what the narrow phase asks of a skinned corner's offset, to which
    /// four times the skinning's rounding `e` (times `|n|`) and the `f64`
    /// slack (`reach`: a bound of `|x|` and of `d / |n|`) are added.
    fn new(n: &Vector3<f64>, d: f64, m: &Matrix4<f32>, e: f64, reach: f64, margin: f64) -> Self {
        let a = |i: usize, k: usize| f64::from(m[(i, k)]);
        let normal = [0, 1, 2].map(|k| (0..3).map(|i| a(i, k) * n[i]).sum::<f64>());
        let offset = (0..3).map(|i| n[i] * a(i, 3)).sum::<f64>() - d;
        let n_len = n.norm();
        let margin = margin + 4.0 * n_len * e + 1e-12 * n_len * reach;
        if margin.is_finite() && offset.is_finite() && normal.iter().all(|x| x.is_finite()) {
            Self {
                normal,
                offset,
                margin,
            }
        } else {
            Self::NONE
        }
    }

    #[inline(always)]
    fn offset_of(&self, v: &Point) -> f64 {
        self.normal[0] * f64::from(v.x)
            + self.normal[1] * f64::from(v.y)
            + self.normal[2] * f64::from(v.z)
            + self.offset
    }
}

/// One big triangle's planes in one joint's bind space.
#[derive(Clone, Copy, Debug)]
struct Slot {
    /// The pass it was made in (0: never).
    pass: u32,
    triangle: u32,
    joint: u16,
    plane: BindPlane,
    /// The inward edge planes (never past their margins without a prism).
    edges: [BindPlane; 3],
}

impl Slot {
    const EMPTY: Self = Self {
        pass: 0,
        triangle: 0,
        joint: 0,
        plane: BindPlane::NONE,
        edges: [BindPlane::NONE; 3],
    };

    fn new(
        (pass, triangle, joint): (u32, u32, u16),
        big: &Triangle,
        prism: Option<&TrianglePrism>,
        m: &Matrix4<f32>,
        c: f32,
    ) -> Self {
        let mut slot = Self {
            pass,
            triangle,
            joint,
            ..Self::EMPTY
        };
        let Some((p0, n, uv2)) = Prepared::<f64>::new(big).plane() else {
            return slot;
        };
        let e = sole_joint_rounding(m, c);
        let (p0, n) = (Vector3::from(p0), Vector3::from(n));
        // `|x|` for any corner this joint skins, and the planes' distances
        // from the origin, are at most this.
        let reach = 3f64.sqrt() * largest_row_sum(m) * f64::from(c) * (1.0 + 1e-6) + p0.norm();
        slot.plane = BindPlane::new(&n, n.dot(&p0), m, e, reach, SNAP * uv2.sqrt() * reach);
        if let Some(prism) = prism {
            let (normals, offsets) = prism.edge_planes();
            for k in 0..3 {
                // `holds_inside`'s margin with the corner's 1-norm at most
                // `√3·|x|`.
                let inside = MARGIN * (3f64.sqrt() * reach + offsets[k].abs());
                slot.edges[k] = BindPlane::new(&normals[k], offsets[k], m, e, reach, inside);
            }
        }
        slot
    }
}

/// Big triangles' planes in joints' bind spaces, kept during one pass in a
/// small direct-mapped table keyed by (big triangle, joint).
#[derive(Clone, Debug)]
pub(crate) struct BindPlanes {
    slots: Box<[Slot]>,
    /// The current pass, from 1.
    pass: u32,
}

impl Default for BindPlanes {
    fn default() -> Self {
        Self {
            slots: vec![Slot::EMPTY; SLOTS].into_boxed_slice(),
            pass: 1,
        }
    }
}

impl BindPlanes {
    /// Forgets every plane (a new pass: another character or pose).
    pub(crate) fn begin_pass(&mut self) {
        self.pass = self.pass.wrapping_add(1);
        if self.pass == 0 {
            self.slots.iter_mut().for_each(|s| s.pass = 0);
            self.pass = 1;
        }
    }

    /// The answer for the character triangle with bind corners `corners`,
    /// all three moved by joint `joint` alone with skin matrix `m` (bind
    /// coordinates at most `c`), against big triangle `triangle`
    /// (`big()`: its corners and prism, asked for once a pass and joint):
    /// `Some(false)` apart, `Some(true)` a contact, `None` unknown (see the
    /// module doc).
    #[inline]
    pub(crate) fn answer<'p>(
        &mut self,
        triangle: u32,
        big: impl FnOnce() -> (Triangle, Option<&'p TrianglePrism>),
        joint: u16,
        m: &Matrix4<f32>,
        c: f32,
        corners: [&Point; 3],
    ) -> Option<bool> {
        let k = (joint as usize ^ (triangle as usize).wrapping_mul(0x9E37_79B9)) & (SLOTS - 1);
        let slot = &mut self.slots[k];
        if !(slot.pass == self.pass && slot.triangle == triangle && slot.joint == joint) {
            let (t, prism) = big();
            *slot = Slot::new((self.pass, triangle, joint), &t, prism, m, c);
        }
        let plane = &slot.plane;
        let d = corners.map(|v| plane.offset_of(v));
        let m = plane.margin;
        let above = d.iter().filter(|&&x| x > m).count();
        let below = d.iter().filter(|&&x| x < -m).count();
        if above == 3 || below == 3 {
            return Some(false);
        }
        if above > 0
            && below > 0
            && slot
                .edges
                .iter()
                .all(|e| corners.iter().all(|v| e.offset_of(v) > e.margin))
        {
            return Some(true);
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix4, Rotation3, Unit, Vector3};

    use super::BindPlanes;
    use crate::character::skinning::Influences;
    use crate::geometry::exact::triangles_intersect_exact;
    use crate::geometry::triangle_prism::TrianglePrism;
    use crate::geometry::tropp::Prepared;
    use crate::geometry::{Point, Triangle};

    /// Random skin matrices (a rotation, a scale from 0.5 to 1.5 per axis,
    /// a translation up to 300 m), big triangles about 2 m across near
    /// them, and character triangles a few centimetres across near the big
    /// triangle's plane, a fifth of their corners placed exactly on it (in
    /// exact arithmetic; their bind corners are the inverse map's, rounded,
    /// so that skinning puts them within rounding of the plane, on either
    /// side). Skinned by the linear blend with one influence of weight 1:
    /// every "apart" is an exit of the narrow phase's plane-side test, every
    /// "contact" a triangle across the plane and inside the prism that the
    /// exact predicate says meets; and both answers are given often.
    #[test]
    fn answers_only_what_the_skinned_corners_answer() {
        let mut r = crate::test_rng::unit_floats(0xb1d_5ace);
        let influences = Influences::new(vec![[0; 4]; 3], vec![[1.0, 0.0, 0.0, 0.0]; 3], 1)
            .expect("valid influences");
        let mut planes = BindPlanes::default();
        let (mut apart, mut contact, mut unknown) = (0, 0, 0);
        for case in 0..20_000u32 {
            planes.begin_pass();
            let mut v3 = |s: f32| Vector3::new(r() - 0.5, r() - 0.5, r() - 0.5) * s;
            let (spin, turn) = (v3(2.0), v3(14.0).x + 7.0);
            let axis = Unit::new_normalize(spin + Vector3::new(0.0, 0.0, 1e-3));
            let far = if case % 3 == 0 { 600.0 } else { 4.0 };
            let t = v3(far);
            let scale = Vector3::new(0.5, 0.5, 0.5) + v3(1.0).map(|x| x + 0.5);
            let m: Matrix4<f32> = Matrix4::new_translation(&t)
                * Rotation3::from_axis_angle(&axis, turn).to_homogeneous()
                * Matrix4::new_nonuniform_scaling(&scale);
            let inverse = m.cast::<f64>().try_inverse().expect("invertible");
            let at = t + v3(1.0);
            let big = Triangle::new(
                Point::from(at + v3(4.0)),
                Point::from(at + v3(4.0)),
                Point::from(at + v3(4.0)),
            );
            let prism = TrianglePrism::new(&big);
            let [a, b, c] = [big.a, big.b, big.c].map(|p| p.coords.cast::<f64>());
            let n = (b - a).cross(&(c - a)).normalize();
            // A point of the big triangle's plane near its middle.
            let middle = (a + b + c) / 3.0 + (b - a) * f64::from(0.6 * v3(1.0).x);
            let mut corner = || {
                let along = v3(0.12).cast::<f64>();
                let on_plane = middle + along - n * n.dot(&along);
                let [pick, depth, _] = v3(1.0).into();
                let off = if pick < -0.3 {
                    0.0
                } else {
                    0.03 * f64::from(depth)
                };
                let x = on_plane + n * off;
                let v = inverse.transform_point(&nalgebra::Point3::from(x));
                Point::new(v.x as f32, v.y as f32, v.z as f32)
            };
            let bind = [corner(), corner(), corner()];
            let bound = bind
                .iter()
                .flat_map(|p| [p.x, p.y, p.z])
                .fold(1.0f32, |m, x| m.max(x.abs()));
            let skinned = Triangle::new(
                influences.skin_vertex(0, &bind[0], &[m]),
                influences.skin_vertex(1, &bind[1], &[m]),
                influences.skin_vertex(2, &bind[2], &[m]),
            );
            let answer = planes.answer(
                case,
                || (big, Some(&prism)),
                0,
                &m,
                bound,
                [&bind[0], &bind[1], &bind[2]],
            );
            let one_side = Prepared::<f64>::new(&big).plane_has_on_one_side(&skinned);
            match answer {
                Some(false) => {
                    assert!(
                        one_side,
                        "case {case}: apart, but not by the plane-side exit"
                    );
                    apart += 1;
                }
                Some(true) => {
                    assert!(
                        !one_side && prism.holds_inside(&skinned),
                        "case {case}: a contact the narrow phase does not answer so"
                    );
                    assert!(triangles_intersect_exact(&skinned, &big), "case {case}");
                    contact += 1;
                }
                None => unknown += 1,
            }
        }
        assert!(
            apart > 1_500 && contact > 5_000 && unknown > 3_000,
            "apart {apart}, contact {contact}, unknown {unknown}"
        );
    }
}
