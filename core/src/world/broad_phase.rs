//! The broad phase between bodies: which bodies' root spheres meet, so that
//! only those pairs' hierarchies are traversed.
//!
//! [`SortAndSweep`] sorts the spheres' extents along the axis on which
//! their centres spread most and tests a sphere only against those whose
//! extents on that axis and on the next widest overlap its own: `n log n`
//! to sort, then as many candidates as spheres share a slab of the sweep
//! axis (for a crowd spread over a square, about `n^1.5`, with a cheap
//! rejection on the second axis before any sphere test), where testing every
//! pair ([`all_pairs`], the reference) is `n²/2`. Below [`SWEEP_FROM`]
//! bodies it tests every pair, which is faster there. Both give the same pairs in the same order
//! (ascending `(i, j)`, `i < j`); they differ only in the sphere tests they
//! count. Measured against each other at 8 to 4,096 bodies in
//! `docs/performance.md`, "A broad phase for crowds".

use crate::geometry::Sphere;

/// Every two spheres that overlap, by testing every pair: `(i, j)` with
/// `i < j` in ascending order, into `out` (cleared first). Returns the
/// sphere tests made (every pair of present spheres). `None` is a body with
/// nothing to test (an empty tree).
pub fn all_pairs(spheres: &[Option<Sphere>], out: &mut Vec<(u32, u32)>) -> u64 {
    out.clear();
    let mut tests = 0;
    for (i, a) in spheres.iter().enumerate() {
        let Some(a) = a else { continue };
        for (j, b) in spheres.iter().enumerate().skip(i + 1) {
            let Some(b) = b else { continue };
            tests += 1;
            if a.overlaps(b) {
                out.push((i as u32, j as u32));
            }
        }
    }
    tests
}

/// Sort and sweep over spheres along one axis; keeps its buffers between
/// calls, so a call allocates only when there are more bodies or pairs than
/// ever before.
#[derive(Default, Debug)]
pub struct SortAndSweep {
    /// The present spheres' extents on the sweep axis, sorted by start.
    entries: Vec<Entry>,
}

#[derive(Clone, Copy, Debug)]
struct Entry {
    /// Extent on the sweep axis.
    start: f32,
    end: f32,
    /// Extent on the second widest axis.
    low: f32,
    high: f32,
    sphere: Sphere,
    index: u32,
}

/// Below this many bodies testing every pair is faster than sorting
/// (measured: `benches/broad_phase.rs`, docs/performance.md).
pub const SWEEP_FROM: usize = 96;

impl SortAndSweep {
    /// An empty broad phase.
    pub fn new() -> Self {
        Self::default()
    }

    /// Every two spheres that overlap, as [`all_pairs`] gives them (same
    /// pairs, same order), into `out` (cleared first). Returns the sphere
    /// tests made: every pair below [`SWEEP_FROM`] bodies; above, one for
    /// each two spheres whose extents overlap on the sweep axis and the
    /// next widest.
    pub fn pairs(&mut self, spheres: &[Option<Sphere>], out: &mut Vec<(u32, u32)>) -> u64 {
        if spheres.len() < SWEEP_FROM {
            return all_pairs(spheres, out);
        }
        self.sweep(spheres, out)
    }

    /// The sweep alone, whatever the count.
    pub fn sweep(&mut self, spheres: &[Option<Sphere>], out: &mut Vec<(u32, u32)>) -> u64 {
        out.clear();
        let (axis, second) = spread_axes(spheres);
        self.entries.clear();
        self.entries
            .extend(spheres.iter().enumerate().filter_map(|(i, s)| {
                s.map(|s| {
                    // A few ulps wider than the sphere, so that no pair the
                    // sphere test (in `f32`) would call touching is skipped.
                    let extent = |a: usize| {
                        let (c, r) = (s.center[a], s.radius);
                        let pad = (c.abs() + r) * (4.0 * f32::EPSILON);
                        (c - r - pad, c + r + pad)
                    };
                    let ((start, end), (low, high)) = (extent(axis), extent(second));
                    Entry {
                        start,
                        end,
                        low,
                        high,
                        sphere: s,
                        index: i as u32,
                    }
                })
            }));
        // Spheres are finite (a world refuses non-finite poses), so the
        // order is total; ties keep no particular order, the pairs are
        // sorted below.
        self.entries
            .sort_unstable_by(|a, b| a.start.total_cmp(&b.start));
        let mut tests = 0;
        for (k, a) in self.entries.iter().enumerate() {
            for b in &self.entries[k + 1..] {
                if b.start > a.end {
                    break;
                }
                if b.low > a.high || b.high < a.low {
                    continue;
                }
                tests += 1;
                if a.sphere.overlaps(&b.sphere) {
                    out.push((a.index.min(b.index), a.index.max(b.index)));
                }
            }
        }
        out.sort_unstable();
        tests
    }
}

/// The axes (0, 1, 2) along which the spheres' centres spread most and
/// next most (their variance): the sweep's, where it skips most pairs, and
/// the one its cheap second check uses.
fn spread_axes(spheres: &[Option<Sphere>]) -> (usize, usize) {
    let mut n = 0.0f64;
    let mut sum = [0.0f64; 3];
    let mut sq = [0.0f64; 3];
    for s in spheres.iter().flatten() {
        n += 1.0;
        for a in 0..3 {
            let c = f64::from(s.center[a]);
            sum[a] += c;
            sq[a] += c * c;
        }
    }
    if n == 0.0 {
        return (0, 1);
    }
    let var = |a: usize| sq[a] / n - (sum[a] / n).powi(2);
    let mut axes = [0, 1, 2];
    axes.sort_by(|&a, &b| var(b).total_cmp(&var(a)));
    (axes[0], axes[1])
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::Point;

    /// A little generator of spheres (no dependency for a test).
    fn spheres(n: usize, seed: u64, side: f32) -> Vec<Option<Sphere>> {
        let mut s = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let mut next = move || {
            s = s
                .wrapping_mul(6364136223846793005)
                .wrapping_add(1442695040888963407);
            ((s >> 40) as f32) / (1u64 << 24) as f32
        };
        (0..n)
            .map(|i| {
                let sphere = Sphere {
                    center: Point::new(next() * side, next() * 2.0, next() * side * 0.5),
                    radius: 0.2 + next(),
                };
                // Every seventh body has no tree.
                (i % 7 != 3).then_some(sphere)
            })
            .collect()
    }

    /// The sweep gives exactly the pairs every-pair testing gives, in the
    /// same order, on crowds sparse and dense, with absent bodies, ties and
    /// touching spheres; and tests fewer pairs where bodies spread out.
    #[test]
    fn same_pairs_as_testing_every_pair() {
        let mut sweep = SortAndSweep::new();
        let (mut a, mut b) = (Vec::new(), Vec::new());
        for (n, side) in [
            (0, 1.0),
            (1, 1.0),
            (2, 0.1),
            (8, 3.0),
            (64, 10.0),
            (300, 40.0),
            (300, 2.0),
        ] {
            for seed in 0..4 {
                let s = spheres(n, seed, side);
                let all = all_pairs(&s, &mut a);
                let swept = sweep.sweep(&s, &mut b);
                let mut c = Vec::new();
                sweep.pairs(&s, &mut c);
                assert_eq!(b, c);
                assert_eq!(a, b, "{n} bodies on {side} m, seed {seed}");
                assert!(swept <= all);
                if n == 300 && side == 40.0 {
                    assert!(swept * 4 < all, "{swept} tests of {all}");
                    assert!(!a.is_empty());
                }
            }
        }
        // Equal spheres (every extent ties) and spheres just touching.
        let one = Sphere {
            center: Point::new(1.0, 0.0, 0.0),
            radius: 0.5,
        };
        let touching = Sphere {
            center: Point::new(2.0, 0.0, 0.0),
            radius: 0.5,
        };
        let s = vec![Some(one), Some(touching), Some(one), None, Some(touching)];
        all_pairs(&s, &mut a);
        sweep.sweep(&s, &mut b);
        assert_eq!(a, b);
        assert_eq!(a.len(), 6, "{a:?}");
    }

    #[test]
    fn sweeps_along_the_widest_spread() {
        let s = spheres(50, 1, 30.0);
        assert_eq!(spread_axes(&s), (0, 2));
        let s: Vec<_> = s
            .into_iter()
            .map(|s| {
                s.map(|s| Sphere {
                    center: Point::new(s.center.z, s.center.y, s.center.x),
                    ..s
                })
            })
            .collect();
        assert_eq!(spread_axes(&s), (2, 0));
    }
}
