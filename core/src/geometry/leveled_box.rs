//! An axis-aligned box held in six bytes as levels across the cube around a
//! sphere, built every frame for a moving node and tested against another
//! such box (ours; a character's posed node boxes, see
//! `sphere_tree::refit`, "Boxes").
//!
//! The same idea as [`super::sphere_box::QuantizedBox`] (a static node's
//! box, built once), with arithmetic cheap enough to run at every refit: a
//! face at level `q` lies at `c + r·L[q]` computed in `f32`, `L` a table of
//! 256 `f32` values from just below `−1` to just above `1`. Building checks
//! each face with that very arithmetic (each low face at or below the
//! geometry's least coordinate, each high face at or above its greatest,
//! compared in `f64`),
//! so the box the test sees holds the geometry; the test compares two boxes'
//! `f32` faces, exactly. A `NaN` anywhere gives the whole cube, and the
//! cube, or a `NaN` face, never separates.

use super::Sphere;

/// Operations charged per box-box test ([`leveled_boxes_meet`]): twelve
/// faces, each a product and a sum, and six comparisons.
pub const BOX_BOX: u64 = 12 * 2 + 6;

/// The top level of a face.
const TOP: u8 = u8::MAX;

/// How far the outermost levels lie beyond the sphere's cube, relative to
/// its radius: so that the `f32` faces at levels 0 and 255 hold the sphere's
/// extent despite rounding (where `r·2⁻¹⁰` exceeds half an ulp of the
/// centre: a 1 cm node up to 80 m from the origin).
const OUTSIDE: f64 = 1.0 + 1.0 / 1024.0;

/// `L[q] = (q·2/255 − 1)·OUTSIDE` rounded to `f32`: where level `q` lies
/// across the cube.
static LEVELS: [f32; 256] = {
    let mut l = [0.0f32; 256];
    let mut q = 0;
    while q < 256 {
        l[q] = ((q as f64 * (2.0 / 255.0) - 1.0) * OUTSIDE) as f32;
        q += 1;
    }
    l
};

/// The face at level `q` of the cube around `(c, r)`, on one axis.
#[inline(always)]
fn face(c: f32, r: f32, q: u8) -> f32 {
    c + r * LEVELS[q as usize]
}

/// A box as levels across the cube around a sphere (module doc).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct LeveledBox {
    /// Low faces' levels.
    pub lo: [u8; 3],
    /// High faces' levels.
    pub hi: [u8; 3],
}

impl LeveledBox {
    /// The whole cube around the sphere (no tighter box known).
    pub const CUBE: LeveledBox = LeveledBox {
        lo: [0; 3],
        hi: [TOP; 3],
    };

    /// No box yet: a marker no box built here has (a high face below its
    /// low face), for a box to be built when first asked for.
    pub const UNKNOWN: LeveledBox = LeveledBox {
        lo: [TOP; 3],
        hi: [0; 3],
    };

    /// A box of levels around `sphere` holding `min..=max` (the tightest,
    /// or a level looser where a face's `f32` rounding makes it so),
    /// clipped to the cube around `sphere` (the geometry lies in the
    /// sphere, which the caller guarantees). A non-finite or empty extent,
    /// or an invalid sphere, gives [`LeveledBox::CUBE`].
    #[inline]
    pub fn enclosing(min: [f64; 3], max: [f64; 3], sphere: &Sphere) -> Self {
        let r = sphere.radius;
        let finite = min.iter().chain(&max).all(|x| x.is_finite());
        if !finite || !sphere.is_valid() || r <= 0.0 {
            return Self::CUBE;
        }
        let scale = 127.5 / (f64::from(r) * OUTSIDE);
        let mut b = Self::CUBE;
        for k in 0..3 {
            let c = sphere.center[k];
            if min[k] > max[k] {
                return Self::CUBE;
            }
            // The geometry lies in the sphere, so within its cube (exact
            // in `f64` from `f32` centre and radius).
            let (lo_k, hi_k) = (f64::from(c) - f64::from(r), f64::from(c) + f64::from(r));
            let (min_k, max_k) = (min[k].max(lo_k), max[k].min(hi_k));
            // A first guess (truncated, after clamping), then the highest
            // level whose face is at or below `min` and the lowest at or
            // above `max`, by the test's own arithmetic.
            let guess = |x: f64| ((x - f64::from(c)) * scale + 127.5).clamp(0.0, 255.0);
            let mut ql = guess(min_k) as u8;
            while ql > 0 && f64::from(face(c, r, ql)) > min_k {
                ql -= 1;
            }
            let g = guess(max_k);
            let mut qh = (g as u8).saturating_add((g > f64::from(g as u8)) as u8);
            while qh < TOP && f64::from(face(c, r, qh)) < max_k {
                qh += 1;
            }
            // Far from the origin the outermost `f32` faces may round
            // inside the sphere's extent: then no box (the cube never
            // separates).
            if f64::from(face(c, r, ql)) > min_k || f64::from(face(c, r, qh)) < max_k {
                return Self::CUBE;
            }
            b.lo[k] = ql;
            b.hi[k] = qh.max(ql);
        }
        b
    }

    /// The box's faces around `sphere` (the one it was built around):
    /// `(low, high)` per axis, in `f32`.
    #[inline(always)]
    pub fn faces(&self, sphere: &Sphere) -> ([f32; 3], [f32; 3]) {
        let (c, r) = (sphere.center, sphere.radius);
        (
            [0, 1, 2].map(|k| face(c[k], r, self.lo[k])),
            [0, 1, 2].map(|k| face(c[k], r, self.hi[k])),
        )
    }
}

/// Whether box `a` (built around sphere `sa`) and box `b` (around `sb`) may
/// meet: `false` only when, on some axis, one lies wholly beyond the other.
/// The whole cube stands for "no box" and meets everything.
#[inline(always)]
pub fn leveled_boxes_meet(a: &LeveledBox, sa: &Sphere, b: &LeveledBox, sb: &Sphere) -> bool {
    if *a == LeveledBox::CUBE || *b == LeveledBox::CUBE {
        return true;
    }
    let (al, ah) = a.faces(sa);
    let (bl, bh) = b.faces(sb);
    // Without short-circuits: one branch on the answer. A NaN compares
    // false: kept.
    let apart = (al[0] > bh[0])
        | (bl[0] > ah[0])
        | (al[1] > bh[1])
        | (bl[1] > ah[1])
        | (al[2] > bh[2])
        | (bl[2] > ah[2]);
    !apart
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    /// Random extents inside random spheres, near and far from the origin:
    /// the box holds every corner of the extent (by the faces the test
    /// reads), within a level of the tightest levels that do, and two boxes
    /// are found apart only when their extents are.
    #[test]
    fn holds_its_extent_tightly_and_separates_only_what_is_apart() {
        let mut rnd = crate::test_rng::unit_floats(0x1e7e1);
        let (mut apart_found, mut cubes) = (0, 0);
        let mut boxes = Vec::new();
        for case in 0..4000 {
            let far = if case % 4 == 0 { 9000.0 } else { 3.0 };
            let c = Point::new(
                (rnd() - 0.5) * far,
                (rnd() - 0.5) * far,
                (rnd() - 0.5) * far,
            );
            let r = 0.001 + rnd() * 0.5;
            let s = Sphere::new(c, r);
            // An extent inside the sphere's cube (a box a third of it wide).
            let corner = |k: usize, u: f32| f64::from(c[k]) + f64::from(r) * f64::from(u);
            let (mut lo, mut hi) = ([0.0; 3], [0.0; 3]);
            for k in 0..3 {
                let (u, w) = (rnd() * 1.4 - 0.7, rnd() * 0.6);
                lo[k] = corner(k, u);
                hi[k] = corner(k, (u + w).min(1.0));
            }
            let b = LeveledBox::enclosing(lo, hi, &s);
            if b == LeveledBox::CUBE {
                // No box: where the extent reaches a face of the cube that
                // rounds inside it (or the faces are coarse far away).
                cubes += 1;
                continue;
            }
            let (fl, fh) = b.faces(&s);
            for k in 0..3 {
                assert!(
                    f64::from(fl[k]) <= lo[k] && f64::from(fh[k]) >= hi[k],
                    "case {case}"
                );
                // Near the origin, within a level of the tightest (the
                // guess is exact, its `f32` face may round past the extent
                // by a level); far away faces round together.
                if case % 4 == 0 {
                    continue;
                }
                let up = b.lo[k].saturating_add(2);
                assert!(
                    b.lo[k] >= TOP - 1 || f64::from(face(c[k], r, up)) > lo[k],
                    "case {case}: loose"
                );
                let down = b.hi[k].saturating_sub(2);
                assert!(
                    b.hi[k] <= b.lo[k] + 1 || f64::from(face(c[k], r, down)) < hi[k],
                    "case {case}: loose"
                );
            }
            boxes.push((b, s, lo, hi));
        }
        for w in boxes.windows(2) {
            let (a, sa, al, ah) = &w[0];
            let (b, sb, bl, bh) = &w[1];
            let extents_apart = (0..3).any(|k| al[k] > bh[k] || bl[k] > ah[k]);
            if !leveled_boxes_meet(a, sa, b, sb) {
                assert!(extents_apart);
                apart_found += 1;
            }
        }
        assert!(
            apart_found > 1000 && cubes < 500,
            "{apart_found} apart, {cubes} cubes"
        );
        // Degenerate input: the cube.
        let s = Sphere::new(Point::origin(), 1.0);
        assert_eq!(
            LeveledBox::enclosing([f64::NAN; 3], [0.0; 3], &s),
            LeveledBox::CUBE
        );
        assert_eq!(
            LeveledBox::enclosing([1.0; 3], [0.0; 3], &s),
            LeveledBox::CUBE
        );
        assert!(leveled_boxes_meet(
            &LeveledBox::CUBE,
            &s,
            &LeveledBox::CUBE,
            &s
        ));
    }

    /// Extents close to one another: two boxes are apart only if their
    /// extents are (a few thousand pairs a few ulps apart).
    #[test]
    fn never_separates_extents_that_touch() {
        let mut rnd = crate::test_rng::unit_floats(0xb0c5);
        for case in 0..4000 {
            let c = Point::new(rnd() * 10.0, rnd() * 10.0, rnd() * 10.0);
            let (ra, rb) = (0.01 + rnd(), 0.01 + rnd());
            // Both extents share the face x = c.x (touching on x).
            let x = f64::from(c.x);
            let a_lo = [
                x - 0.5 * f64::from(ra),
                f64::from(c.y) - 0.1,
                f64::from(c.z) - 0.1,
            ];
            let a_hi = [x, f64::from(c.y) + 0.1, f64::from(c.z) + 0.1];
            let b_lo = [x, f64::from(c.y) - 0.05, f64::from(c.z) - 0.05];
            let b_hi = [
                x + 0.5 * f64::from(rb),
                f64::from(c.y) + 0.05,
                f64::from(c.z) + 0.05,
            ];
            let sa = Sphere::new(Point::new(c.x - 0.25 * ra, c.y, c.z), ra);
            let sb = Sphere::new(Point::new(c.x + 0.25 * rb, c.y, c.z), rb);
            let (a, b) = (
                LeveledBox::enclosing(a_lo, a_hi, &sa),
                LeveledBox::enclosing(b_lo, b_hi, &sb),
            );
            assert!(leveled_boxes_meet(&a, &sa, &b, &sb), "case {case}");
        }
    }
}
