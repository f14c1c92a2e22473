//! `cornertree kernels`: the operations each kernel of the operation model
//! (§6) is *charged* beside those it *pays*, and its time per test.
//!
//! Every kernel runs on the same seeded mixed inputs
//! ([`super::kernel_inputs`]) twice: instantiated with
//! [`cornertree::geometry::counted::Counted`], which counts each
//! arithmetic operation (`+ − × ÷`, negation, `abs`, `sqrt`) and each
//! comparison it executes, and with the scalar the pipeline runs (`f64`;
//! `f32` for sphere-sphere), which is timed. The two must give the same
//! answers on every input, or the measurement is an error.
//!
//! The continuous kernels (`geometry::ccd_*`: vertex–face, edge–edge,
//! triangle–triangle) follow, on [`CCD_INPUTS`] moving pairs at most
//! ([`KernelInputs::moving_pairs`]); the paper charges them nothing (it has
//! no continuous test), and each is timed in its own interleaved rounds.

use std::fmt;
use std::hint::black_box;
use std::time::Instant;

use serde::Serialize;

use cornertree::geometry::ccd_edge_edge::edge_edge_as;
use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::geometry::ccd_triangles::{MovingTriangle, triangles_as};
use cornertree::geometry::ccd_vertex_face::vertex_face_as;
use cornertree::geometry::counted::{Counted, count_operations_by_kind};
use cornertree::geometry::plane_sphere::{
    TrianglePlane, sphere_meets_plane, sphere_meets_plane_as,
};
use cornertree::geometry::vec3::V3;
use cornertree::geometry::{edge_crossing, ops, tri_tri, tropp};

use super::kernel_inputs::KernelInputs;

/// Seed of the input set.
pub const SEED: u64 = 0x006B_6572_6E65_6C73;

/// Inputs of each continuous kernel, at most (they cost microseconds).
pub const CCD_INPUTS: usize = 5_000;

/// One kernel's figures.
#[derive(Clone, Debug, Serialize)]
pub struct KernelCost {
    pub name: &'static str,
    /// The paper's figure for this kind of test (§6); none for the
    /// continuous kernels.
    pub charged_operations: Option<u64>,
    /// Inputs it ran on.
    pub inputs: usize,
    /// Arithmetic operations and comparisons executed, per test.
    pub paid_operations_mean: f64,
    pub paid_operations_min: u64,
    pub paid_operations_max: u64,
    /// The mean split: arithmetic (`+ − × ÷`, negation, `abs`, `sqrt`; the
    /// paper counts additions and multiplications) and comparisons.
    pub paid_arithmetic_mean: f64,
    pub paid_comparisons_mean: f64,
    /// Nanoseconds per test of the pipeline's instantiation: best of 15
    /// rounds over all the inputs, the kernels interleaved. The inputs are
    /// all distinct, so branch predictors cannot learn their sequence (as
    /// they do when a bench repeats a few thousand inputs).
    pub ns_per_test: f64,
    /// Inputs the kernel answered `true` on.
    pub positives: usize,
}

/// Every kernel on `pairs` inputs each.
#[derive(Clone, Debug, Serialize)]
pub struct KernelsReport {
    pub pairs: usize,
    pub seed: u64,
    /// The kernel behind `geometry::tri_tri::triangles_intersect`.
    pub narrow_phase: &'static str,
    pub kernels: Vec<KernelCost>,
}

/// Measures every kernel on `pairs` inputs each (`pairs > 0`).
pub fn measure_kernels(pairs: usize) -> Result<KernelsReport, String> {
    assert!(pairs > 0, "no inputs");
    let inputs = KernelInputs::new(pairs, SEED);
    let planes: Vec<_> = inputs
        .sphere_triangles
        .iter()
        .map(|(s, t)| (*s, TrianglePlane::<f64>::new(t)))
        .collect();
    let counted_planes: Vec<_> = inputs
        .sphere_triangles
        .iter()
        .map(|(_, t)| TrianglePlane::<Counted>::new(t))
        .collect();
    let measured = [
        count(
            "sphere-sphere",
            ops::SPHERE_SPHERE,
            &inputs.sphere_pairs,
            |(a, b)| a.overlaps(b),
            |(a, b)| a.overlaps_as::<Counted>(b),
        )?,
        count(
            "plane-sphere",
            ops::PLANE_SPHERE,
            &inputs.sphere_triangles,
            |(s, t)| sphere_meets_plane(s, t),
            |(s, t)| sphere_meets_plane_as::<Counted>(s, t),
        )?,
        count_with(
            "plane-sphere-prepared",
            Some(ops::PLANE_SPHERE),
            &planes,
            |(s, p)| p.meets(s),
            |i, (s, _)| counted_planes[i].meets(s),
        )?,
        count(
            "tri-tri-tropp",
            ops::TRI_TRI,
            &inputs.triangle_pairs,
            |(a, b)| tropp::triangles_intersect(a, b),
            |(a, b)| tropp::triangles_intersect_as::<Counted>(a, b),
        )?,
        count(
            "tri-tri-edge-crossing",
            ops::TRI_TRI,
            &inputs.triangle_pairs,
            |(a, b)| edge_crossing::triangles_intersect(a, b),
            |(a, b)| edge_crossing::triangles_intersect_as::<Counted>(a, b),
        )?,
    ];
    let passes: Vec<&Pass> = measured.iter().map(|(_, p)| p).collect();
    let ns = time_interleaved(&passes, pairs, 200_000);
    let mut kernels: Vec<KernelCost> = measured
        .into_iter()
        .zip(ns)
        .map(|((k, _), ns)| KernelCost {
            ns_per_test: ns,
            ..k
        })
        .collect();
    kernels.extend(measure_ccd_kernels(&inputs, pairs.min(CCD_INPUTS))?);
    Ok(KernelsReport {
        pairs,
        seed: SEED,
        narrow_phase: tri_tri::NARROW_PHASE_KERNEL,
        kernels,
    })
}

/// Starts and ends of the four points of an elementary CCD query.
type Query<T> = ([V3<T>; 4], [V3<T>; 4]);

fn counted<const N: usize>(p: &[V3<f64>; N]) -> [V3<Counted>; N] {
    p.map(|q| q.map(Counted))
}

fn counted_triangle(t: &MovingTriangle<f64>) -> MovingTriangle<Counted> {
    MovingTriangle {
        start: counted(&t.start),
        end: counted(&t.end),
    }
}

/// The continuous kernels on `n` moving pairs each: the second triangle's
/// first corner against the first triangle, the first edges of both, and
/// the two triangles.
fn measure_ccd_kernels(inputs: &KernelInputs, n: usize) -> Result<Vec<KernelCost>, String> {
    let pairs = inputs.moving_pairs(n, SEED ^ 0xCCD);
    let params = CcdParams::default();
    let vf: Vec<Query<f64>> = pairs
        .iter()
        .map(|(a, b)| {
            let s = [b.start[0], a.start[0], a.start[1], a.start[2]];
            let e = [b.end[0], a.end[0], a.end[1], a.end[2]];
            (s, e)
        })
        .collect();
    let ee: Vec<Query<f64>> = pairs
        .iter()
        .map(|(a, b)| {
            let s = [a.start[0], a.start[1], b.start[0], b.start[1]];
            let e = [a.end[0], a.end[1], b.end[0], b.end[1]];
            (s, e)
        })
        .collect();
    let measured = [
        count_with(
            "ccd-vertex-face",
            None,
            &vf,
            |(s, e)| vertex_face_as(s, e, &params, 1.0).is_some(),
            |_, (s, e)| vertex_face_as(&counted(s), &counted(e), &params, 1.0).is_some(),
        )?,
        count_with(
            "ccd-edge-edge",
            None,
            &ee,
            |(s, e)| edge_edge_as(s, e, &params, 1.0).is_some(),
            |_, (s, e)| edge_edge_as(&counted(s), &counted(e), &params, 1.0).is_some(),
        )?,
        count_with(
            "ccd-tri-tri",
            None,
            &pairs,
            |(a, b)| triangles_as(a, b, &params).is_some(),
            |_, (a, b)| triangles_as(&counted_triangle(a), &counted_triangle(b), &params).is_some(),
        )?,
    ];
    let passes: Vec<&Pass> = measured.iter().map(|(_, p)| p).collect();
    let ns = time_interleaved(&passes, n, n);
    Ok(measured
        .into_iter()
        .zip(ns)
        .map(|((k, _), ns)| KernelCost {
            ns_per_test: ns,
            ..k
        })
        .collect())
}

/// One timed pass of a kernel over all its inputs: how many it accepts.
type Pass<'a> = Box<dyn Fn() -> usize + 'a>;

/// Counts one kernel's operations (`ns_per_test` left at 0) and returns its
/// timed pass; `fast` is the pipeline's instantiation, `counted` the
/// counting one.
fn count<'a, I>(
    name: &'static str,
    charged: u64,
    inputs: &'a [I],
    fast: impl Fn(&I) -> bool + 'a,
    counted: impl Fn(&I) -> bool,
) -> Result<(KernelCost, Pass<'a>), String> {
    count_with(name, Some(charged), inputs, fast, |_, x| counted(x))
}

/// [`count`], the counting instantiation also given the input's index.
fn count_with<'a, I>(
    name: &'static str,
    charged: Option<u64>,
    inputs: &'a [I],
    fast: impl Fn(&I) -> bool + 'a,
    counted: impl Fn(usize, &I) -> bool,
) -> Result<(KernelCost, Pass<'a>), String> {
    let (mut sum, mut min, mut max, mut positives) = (0u64, u64::MAX, 0u64, 0usize);
    let mut arithmetic = 0u64;
    for (i, x) in inputs.iter().enumerate() {
        let (answer, ops) = count_operations_by_kind(|| counted(i, x));
        let n = ops.total();
        arithmetic += ops.arithmetic;
        if answer != fast(x) {
            return Err(format!(
                "{name}: input {i}: the counting and the timed instantiations disagree"
            ));
        }
        positives += answer as usize;
        sum += n;
        min = min.min(n);
        max = max.max(n);
    }
    let per_test = |n: u64| n as f64 / inputs.len() as f64;
    let cost = KernelCost {
        name,
        charged_operations: charged,
        inputs: inputs.len(),
        paid_operations_mean: per_test(sum),
        paid_arithmetic_mean: per_test(arithmetic),
        paid_comparisons_mean: per_test(sum - arithmetic),
        paid_operations_min: min,
        paid_operations_max: max,
        ns_per_test: 0.0,
        positives,
    };
    Ok((cost, Box::new(move || accepted(inputs, &fast))))
}

/// Timing rounds: the best is kept (the machine's load only ever adds time).
const ROUNDS: usize = 15;

/// Nanoseconds per test of each pass (each over `n` inputs): the best of
/// [`ROUNDS`] rounds, a round timing every kernel in turn (so load drifts hit
/// all alike), each for at least `min_tests` tests.
fn time_interleaved(passes: &[&Pass], n: usize, min_tests: usize) -> Vec<f64> {
    let repeats = min_tests.div_ceil(n);
    let mut best = vec![f64::INFINITY; passes.len()];
    for _ in 0..ROUNDS {
        for (pass, best) in passes.iter().zip(&mut best) {
            let t0 = Instant::now();
            for _ in 0..repeats {
                black_box(pass());
            }
            let ns = t0.elapsed().as_nanos() as f64 / (repeats * n) as f64;
            *best = best.min(ns);
        }
    }
    best
}

/// How many inputs the test accepts (the timed loop).
#[inline(never)]
fn accepted<I>(inputs: &[I], test: &impl Fn(&I) -> bool) -> usize {
    inputs.iter().filter(|x| test(black_box(x))).count()
}

impl fmt::Display for KernelsReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        writeln!(
            f,
            "{} inputs per kernel (a third each disjoint, near touching, intersecting; seed {:#x}); \
             narrow phase: {}",
            self.pairs, self.seed, self.narrow_phase
        )?;
        writeln!(
            f,
            "{:<22} {:>7} | {:>9} {:>5} {:>5} | {:>10} {:>11} | {:>8} {:>8}",
            "kernel",
            "charged",
            "paid mean",
            "min",
            "max",
            "arithmetic",
            "comparisons",
            "ns/test",
            "positive"
        )?;
        for k in &self.kernels {
            let charged = k.charged_operations.map_or("-".into(), |c| c.to_string());
            writeln!(
                f,
                "{:<22} {:>7} | {:>9.1} {:>5} {:>5} | {:>10.1} {:>11.1} | {:>8.2} {:>7.1}%",
                k.name,
                charged,
                k.paid_operations_mean,
                k.paid_operations_min,
                k.paid_operations_max,
                k.paid_arithmetic_mean,
                k.paid_comparisons_mean,
                k.ns_per_test,
                100.0 * k.positives as f64 / k.inputs as f64
            )?;
        }
        writeln!(
            f,
            "charged: the paper's figure per test (§6, additions and multiplications; the \
             edge-crossing test is charged like any triangle-triangle test). paid: operations \
             executed, counted per test: arithmetic (+ - * /, negation, abs, sqrt) and \
             comparisons. ns/test: the pipeline's f64 instantiation (f32 for sphere-sphere), \
             meaningful in a release build only. ccd-*: continuous tests (docs/ccd.md) on {} \
             moving pairs (the triangle pairs as the end of a step, the second triangle \
             arriving from elsewhere), charged nothing by the paper",
            self.kernels
                .iter()
                .find(|k| k.name.starts_with("ccd-"))
                .map_or(0, |k| k.inputs)
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_kernel_measured() {
        let r = measure_kernels(60).unwrap();
        assert_eq!(r.kernels.len(), 8);
        for k in &r.kernels {
            assert!(k.paid_operations_min > 0 && k.paid_operations_min <= k.paid_operations_max);
            assert!(k.ns_per_test > 0.0, "{k:?}");
            // The mix has both answers.
            assert!(k.positives > 0 && k.positives < k.inputs, "{k:?}");
        }
        assert!(r.to_string().contains("tri-tri-tropp"));
    }
}
