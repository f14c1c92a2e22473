//! Boxes of the CCD search's parameters (time `t` and the feature
//! parameters `u`, `v`; [`super::ccd_root_finder`]): each an interval
//! `[k / 2ˡ, (k + 1) / 2ˡ]` held by its integer numerator and level, so its
//! ends are exact `f64` and the bookkeeping costs no counted operation.

/// An interval `[k / 2ˡ, (k + 1) / 2ˡ]` of a parameter.
///
/// ```
/// use cornertree::geometry::ccd_param_box::Dyadic;
///
/// let d = Dyadic { k: 3, level: 2 };
/// assert_eq!((d.lo(), d.hi()), (0.75, 1.0));
/// // The finest level still has exact ends.
/// let fine = Dyadic { k: (1 << 52) - 1, level: 52 };
/// assert_eq!((fine.lo(), fine.hi()), (1.0 - f64::EPSILON, 1.0));
/// ```
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Dyadic {
    /// The numerator `k`, below `2ˡ` for an interval inside `[0, 1]`.
    pub k: u64,
    /// The level `l`: the interval's width is `2⁻ˡ` (at most
    /// [`MAX_LEVEL`](super::ccd_root_finder::MAX_LEVEL)).
    pub level: u8,
}

impl Dyadic {
    pub(super) const UNIT: Dyadic = Dyadic { k: 0, level: 0 };

    /// `2⁻ˡ`, exactly.
    fn scale(self) -> f64 {
        f64::from_bits((1023 - self.level as u64) << 52)
    }

    /// The lower end (exact).
    pub fn lo(self) -> f64 {
        self.k as f64 * self.scale()
    }

    /// The upper end (exact).
    pub fn hi(self) -> f64 {
        (self.k + 1) as f64 * self.scale()
    }

    pub(super) fn halves(self) -> [Dyadic; 2] {
        let level = self.level + 1;
        [
            Dyadic {
                k: 2 * self.k,
                level,
            },
            Dyadic {
                k: 2 * self.k + 1,
                level,
            },
        ]
    }
}

/// A box of parameters: time `t` and the two feature parameters `u`, `v`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct ParamBox {
    /// Time, as a fraction of the step.
    pub t: Dyadic,
    /// The first feature parameter: along the first edge (edge–edge), or the
    /// weight of the triangle's second corner (vertex–face).
    pub u: Dyadic,
    /// The second feature parameter: along the second edge (edge–edge), or
    /// the weight of the triangle's third corner (vertex–face).
    pub v: Dyadic,
}

impl ParamBox {
    pub(super) const UNIT: ParamBox = ParamBox {
        t: Dyadic::UNIT,
        u: Dyadic::UNIT,
        v: Dyadic::UNIT,
    };

    pub(super) fn dims(&self) -> [Dyadic; 3] {
        [self.t, self.u, self.v]
    }

    pub(super) fn with(&self, dim: usize, d: Dyadic) -> ParamBox {
        let mut b = *self;
        match dim {
            0 => b.t = d,
            1 => b.u = d,
            _ => b.v = d,
        }
        b
    }

    /// Whether `u_lo + v_lo ≤ 1` (the box reaches the triangle
    /// `{u, v ≥ 0, u + v ≤ 1}`), on the integer numerators.
    pub(super) fn reaches_triangle(&self) -> bool {
        let l = self.u.level.max(self.v.level);
        let num = (self.u.k << (l - self.u.level)) + (self.v.k << (l - self.v.level));
        num <= 1u64 << l
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dyadic_ends_are_exact() {
        let d = Dyadic { k: 3, level: 2 };
        assert_eq!((d.lo(), d.hi()), (0.75, 1.0));
        let [a, b] = d.halves();
        assert_eq!((a.lo(), a.hi(), b.lo(), b.hi()), (0.75, 0.875, 0.875, 1.0));
        let fine = Dyadic {
            k: (1 << 52) - 1,
            level: 52,
        };
        assert_eq!(fine.hi(), 1.0);
        assert_eq!(fine.lo(), 1.0 - f64::EPSILON);
    }

    #[test]
    fn triangle_domain_on_numerators() {
        let b = |ku, lu, kv, lv| ParamBox {
            t: Dyadic::UNIT,
            u: Dyadic { k: ku, level: lu },
            v: Dyadic { k: kv, level: lv },
        };
        assert!(b(0, 0, 0, 0).reaches_triangle());
        assert!(b(1, 1, 1, 1).reaches_triangle()); // 1/2 + 1/2 = 1
        assert!(!b(1, 1, 3, 2).reaches_triangle()); // 1/2 + 3/4
        assert!(b(1, 2, 3, 2).reaches_triangle()); // 1/4 + 3/4
    }
}
