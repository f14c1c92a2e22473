//! `cornertree rays`: ray casts against a scenario's posed characters, per
//! frame, checked against the exact reference and timed against two
//! baselines, all on one thread:
//!
//! - **ours**: the poses handed to the world, then each ray's first hit
//!   ([`CollisionWorld::cast_ray`]): spheres refit and triangles skinned
//!   on demand, only where rays go;
//! - **parry3d**: every vertex skinned, each character's `TriMesh` moved
//!   with `update_vertices` (its BVH refit), then each ray cast on every
//!   character's mesh (`cast_local_ray_and_get_normal`), the nearest kept;
//! - **skin all, test every triangle**: every vertex skinned, each
//!   character's box recomputed, then a ray that enters the box tested
//!   against every triangle (what an engine without a tree over the posed
//!   mesh does).
//!
//! The reference ([`crate::truth::ray_reference`]) is untimed. Posing (clip
//! sampling, joint matrices) is common to all three and not timed.

use std::time::Instant;

use cornertree::geometry::query_shapes::Ray;
use cornertree::geometry::{Point, Vector, bounds_of};
use cornertree::pipeline::Method;
use cornertree::world::{BodyRef, QueryCounters, QueryScratch, QueryTargets, RayHit};
use parry3d::query::{Ray as ParryRay, RayCast};
use parry3d::shape::TriMesh as ParryMesh;
use serde::Serialize;

use crate::scenario::Resolved;
use crate::session::Session;
use crate::truth::parry_world::{to_parry, update_character};
use crate::truth::ray_reference::{self, FirstHits, Mesh};

/// Which rays a frame casts.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, clap::ValueEnum)]
#[serde(rename_all = "kebab-case")]
pub enum RayPattern {
    /// A fan from a point beside the characters across all of them, its
    /// height sweeping from the feet to over the heads over the frames (a
    /// hit-scan weapon swept across a crowd).
    HitScan,
    /// A grid of parallel rays over the first character's box, from in
    /// front of it (picking).
    Picking,
    /// Half the rays of each.
    Both,
}

/// What `rays` measures.
#[derive(Clone, Debug)]
pub struct RaysConfig {
    pub method: Method,
    pub frames: usize,
    pub rays_per_frame: usize,
    pub pattern: RayPattern,
}

/// A ray whose first hit differs from the reference's.
#[derive(Clone, Debug, Serialize)]
pub struct Mismatch {
    pub frame: usize,
    pub ray: usize,
    /// `(character, triangle, distance)` of ours and of the reference.
    pub ours: Option<(usize, u32, f32)>,
    pub reference: Option<(usize, u32, f64)>,
    /// Both name triangles sharing a corner at distances within 1e-5
    /// relative: a ray through or beside an edge or a vertex.
    pub at_shared_edge_or_vertex: bool,
}

/// One frame's rays: what was cast, found and recorded.
pub struct FrameRays {
    pub frame: usize,
    pub rays: Vec<Ray>,
    pub hits: Vec<Option<RayHit>>,
}

/// Per-frame milliseconds: mean, least and most over the frames.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Spread {
    pub mean: f64,
    pub min: f64,
    pub max: f64,
}

impl Spread {
    fn of(xs: &[f64]) -> Self {
        if xs.is_empty() {
            return Self::default();
        }
        Self {
            mean: xs.iter().sum::<f64>() / xs.len() as f64,
            min: xs.iter().copied().fold(f64::INFINITY, f64::min),
            max: xs.iter().copied().fold(0.0, f64::max),
        }
    }
}

/// The report (`--json`).
#[derive(Clone, Debug, Serialize)]
pub struct RaysReport {
    pub scenario: String,
    pub method: Method,
    pub pattern: RayPattern,
    pub characters: usize,
    /// Vertices of each character.
    pub character_vertices: Vec<usize>,
    pub frames: usize,
    /// Rays cast in all, and how many met a character (ours).
    pub rays: u64,
    pub hits: u64,
    /// Rays whose first hit is the reference's: same character and
    /// triangle (or one tied with it), distance within 1e-5 relative; or no
    /// hit in both.
    pub hits_equal_reference: u64,
    /// The others, the first 20 in detail.
    pub mismatches: u64,
    pub mismatch_examples: Vec<Mismatch>,
    /// parry3d's first hits that equal the reference's (same rule).
    pub parry_hits_equal_reference: u64,
    /// Triangles the reference decided by exact predicates.
    pub reference_exact_decisions: u64,
    /// Ours: poses handed over and every ray cast.
    pub ms_per_frame: f64,
    pub ms_per_frame_spread: Spread,
    /// parry3d: skin every vertex, `update_vertices`, cast.
    pub parry_ms_per_frame: f64,
    pub parry_ms_per_frame_spread: Spread,
    pub speedup_vs_parry: f64,
    /// Skin every vertex, then every triangle of each box a ray enters.
    pub skin_all_test_every_triangle_ms_per_frame: f64,
    pub speedup_vs_skin_all_test_every_triangle: f64,
    /// Threads of every side (the same: one).
    pub threads: usize,
    /// Ours, summed over the run.
    pub counters: QueryCounters,
    /// Rays that missed every character's root sphere, and the root tests
    /// they cost in all (one per character each).
    pub rays_missing_every_root: u64,
    pub root_tests_of_those: u64,
    /// Sphere tests below a root made by those rays (none).
    pub sphere_tests_of_those: u64,
}

/// A character's triangles: its index and its posed mesh.
fn meshes(session: &Session) -> Vec<Mesh<'_>> {
    session
        .scene
        .characters
        .iter()
        .zip(&session.buffers)
        .map(|(a, b)| Mesh {
            positions: &b.positions,
            indices: a.character.mesh.indices(),
        })
        .collect()
}

/// The frame's rays, aimed with the characters' posed boxes.
pub fn frame_rays(
    boxes: &[(Point, Point)],
    pattern: RayPattern,
    count: usize,
    frame: usize,
    out: &mut Vec<Ray>,
) {
    out.clear();
    let (fan, grid) = match pattern {
        RayPattern::HitScan => (count, 0),
        RayPattern::Picking => (0, count),
        RayPattern::Both => (count - count / 2, count / 2),
    };
    let Some((lo, hi)) = bounds_of(boxes.iter().flat_map(|(l, h)| [*l, *h])) else {
        return;
    };
    if fan > 0 {
        // From 3 m beyond the crowd's +x side, across its z extent, at a
        // height that sweeps from the feet to well over the heads (where
        // the fan misses every character).
        let size = hi - lo;
        let height = 0.05 + 1.35 * ((frame as f32 * 0.37 + 0.5) % 1.0);
        let eye = Point::new(hi.x + 3.0, lo.y + height * size.y, 0.5 * (lo.z + hi.z));
        for i in 0..fan {
            let s = (i as f32 + 0.5) / fan as f32;
            let z = lo.z - 0.1 + (hi.z - lo.z + 0.2) * s;
            let target = Point::new(lo.x, eye.y - 0.05, z);
            out.push(Ray::new(eye, target - eye, f32::INFINITY).expect("finite direction"));
        }
    }
    if grid > 0 {
        // Over the first character's box, from 1 m in front of it (+z).
        let (lo, hi) = boxes[0];
        let cols = (grid as f64).sqrt().ceil() as usize;
        let rows = grid.div_ceil(cols);
        let pad = 0.05 * (hi - lo);
        for i in 0..grid {
            let (c, r) = (i % cols, i / cols);
            let x = lo.x - pad.x + (hi.x - lo.x + 2.0 * pad.x) * (c as f32 + 0.5) / cols as f32;
            let y = lo.y - pad.y + (hi.y - lo.y + 2.0 * pad.y) * (r as f32 + 0.5) / rows as f32;
            let o = Point::new(x, y, hi.z + 1.0);
            out.push(Ray::new(o, Vector::new(0.01, 0.0, -1.0), f32::INFINITY).expect("finite"));
        }
    }
}

/// Whether `ours` is one of the reference's first hits.
fn equal(ours: Option<&RayHit>, reference: &FirstHits) -> bool {
    match (ours, reference.first()) {
        (None, None) => true,
        (Some(h), Some(r)) => {
            let BodyRef::Character(c) = h.body else {
                return false;
            };
            reference.accepts(c.index(), h.triangle)
                && (f64::from(h.distance) - r.distance).abs() <= 1e-5 * r.distance.max(1e-3)
        }
        _ => false,
    }
}

/// Whether triangles `x` and `y` of meshes share a corner position.
fn share_a_corner(meshes: &[Mesh<'_>], x: (usize, u32), y: (usize, u32)) -> bool {
    let corners = |(m, t): (usize, u32)| {
        meshes[m].indices[t as usize].map(|v| meshes[m].positions[v as usize])
    };
    let (a, b) = (corners(x), corners(y));
    a.iter().any(|p| b.contains(p))
}

/// Measures `scene` (its characters; rooms and objects are not cast
/// against). `each` sees every frame's rays and hits after it is measured
/// (for a recording) with the session, whose world's refit spheres are the
/// frame's.
pub fn measure_rays(
    scene: Resolved,
    name: &str,
    config: &RaysConfig,
    mut each: impl FnMut(&Session, &FrameRays) -> anyhow::Result<()>,
) -> anyhow::Result<RaysReport> {
    let mut scene = scene;
    scene.methods = vec![config.method];
    // Queries see every triangle.
    scene.dedup = false;
    let frames = config.frames.min(scene.frames).max(1);
    let mut session = Session::new(scene, 1)?;
    let n = session.scene.characters.len();
    let character_vertices = session
        .scene
        .characters
        .iter()
        .map(|a| a.character.mesh.vertex_count())
        .collect();
    let mut parry: Vec<Option<ParryMesh>> = vec![None; n];
    let mut scratch = QueryScratch::new();
    let mut rays = Vec::new();
    let mut hits: Vec<Option<RayHit>> = Vec::new();
    let mut boxes = vec![(Point::origin(), Point::origin()); n];
    let (mut ours_ms, mut parry_ms, mut naive_ms) = (Vec::new(), Vec::new(), Vec::new());
    let mut report = RaysReport {
        scenario: name.to_string(),
        method: config.method,
        pattern: config.pattern,
        characters: n,
        character_vertices,
        frames,
        rays: 0,
        hits: 0,
        hits_equal_reference: 0,
        mismatches: 0,
        mismatch_examples: Vec::new(),
        parry_hits_equal_reference: 0,
        reference_exact_decisions: 0,
        ms_per_frame: 0.0,
        ms_per_frame_spread: Spread::default(),
        parry_ms_per_frame: 0.0,
        parry_ms_per_frame_spread: Spread::default(),
        speedup_vs_parry: 0.0,
        skin_all_test_every_triangle_ms_per_frame: 0.0,
        speedup_vs_skin_all_test_every_triangle: 0.0,
        threads: 1,
        counters: QueryCounters::default(),
        rays_missing_every_root: 0,
        root_tests_of_those: 0,
        sphere_tests_of_those: 0,
    };
    let mut counters = QueryCounters::default();
    // Untimed warm-up on the first frame: parry3d's meshes and BVHs built,
    // our scratch sized.
    session.pose_on_one_thread(0);
    if session.out_of_range().is_none() {
        session.skin_all();
        for (slot, (a, b)) in parry
            .iter_mut()
            .zip(session.scene.characters.iter().zip(&session.buffers))
        {
            update_character(slot, a.character.mesh.indices(), b)?;
        }
        for (b, buf) in boxes.iter_mut().zip(&session.buffers) {
            *b = bounds_of(buf.positions.iter().copied()).unwrap_or_default();
        }
        frame_rays(&boxes, config.pattern, config.rays_per_frame, 0, &mut rays);
        session.hand_poses(0);
        for r in &rays {
            session
                .world(0)
                .cast_ray(r, QueryTargets::Characters, &mut scratch)?;
        }
    }
    for k in 0..frames {
        session.pose_on_one_thread(k);
        if let Some((i, reach)) = session.out_of_range() {
            anyhow::bail!(
                "frame {k}: character {i} is posed {reach} from the origin, out of range"
            );
        }
        // Untimed: every vertex, to aim the rays and for the reference.
        session.skin_all();
        for (b, buf) in boxes.iter_mut().zip(&session.buffers) {
            *b = bounds_of(buf.positions.iter().copied()).unwrap_or_default();
        }
        frame_rays(&boxes, config.pattern, config.rays_per_frame, k, &mut rays);

        // Ours.
        hits.clear();
        let mut frame_counters = Vec::with_capacity(rays.len());
        let t0 = Instant::now();
        session.hand_poses(0);
        let world = session.world(0);
        for r in &rays {
            hits.push(world.cast_ray(r, QueryTargets::Characters, &mut scratch)?);
            frame_counters.push(*scratch.counters());
        }
        ours_ms.push(t0.elapsed().as_secs_f64() * 1e3);

        // parry3d: skin, update, cast.
        let t0 = Instant::now();
        session.skin_all();
        for (slot, (a, b)) in parry
            .iter_mut()
            .zip(session.scene.characters.iter().zip(&session.buffers))
        {
            update_character(slot, a.character.mesh.indices(), b)?;
        }
        let mut parry_hits = Vec::with_capacity(rays.len());
        for r in &rays {
            let pr = ParryRay::new(to_parry(&r.origin), to_parry(&Point::from(r.direction)));
            let best = parry
                .iter()
                .enumerate()
                .filter_map(|(c, m)| {
                    let m = m.as_ref()?;
                    m.cast_local_ray_and_get_normal(&pr, r.max_distance, true)
                        .map(|h| (c, h.subshape, h.time_of_impact))
                })
                .min_by(|x, y| x.2.total_cmp(&y.2));
            parry_hits.push(best);
        }
        parry_ms.push(t0.elapsed().as_secs_f64() * 1e3);

        // Skin all, then every triangle of each box entered.
        let t0 = Instant::now();
        session.skin_all();
        let mut naive_hits = 0u64;
        for (b, buf) in boxes.iter_mut().zip(&session.buffers) {
            *b = bounds_of(buf.positions.iter().copied()).unwrap_or_default();
        }
        let all = meshes(&session);
        for r in &rays {
            let mut best = f64::INFINITY;
            for (m, (lo, hi)) in all.iter().zip(&boxes) {
                if !ray_enters_box(r, lo, hi) {
                    continue;
                }
                for tri in m.indices {
                    let [a, b, c] = tri.map(|v| m.positions[v as usize]);
                    if let Some(h) = r.triangle_hit(&cornertree::geometry::Triangle::new(a, b, c)) {
                        best = best.min(h.distance);
                    }
                }
            }
            naive_hits += best.is_finite() as u64;
        }
        std::hint::black_box(naive_hits);
        naive_ms.push(t0.elapsed().as_secs_f64() * 1e3);

        // The reference, and the scores.
        for (i, r) in rays.iter().enumerate() {
            let reference = ray_reference::first_hits(r, &all);
            report.reference_exact_decisions += reference.exact_decisions;
            let ours = hits[i].as_ref();
            report.rays += 1;
            report.hits += ours.is_some() as u64;
            let c = &frame_counters[i];
            counters.add(c);
            if c.bodies_entered == 0 {
                report.rays_missing_every_root += 1;
                report.root_tests_of_those += c.root_tests;
                report.sphere_tests_of_those += c.sphere_tests;
            }
            if equal(ours, &reference) {
                report.hits_equal_reference += 1;
            } else {
                report.mismatches += 1;
                let ours_t = ours.map(|h| {
                    let BodyRef::Character(c) = h.body else {
                        unreachable!("characters only")
                    };
                    (c.index(), h.triangle, h.distance)
                });
                let ref_t = reference.first().map(|h| (h.mesh, h.triangle, h.distance));
                let shared = match (ours_t, ref_t) {
                    (Some(o), Some(r)) => {
                        share_a_corner(&all, (o.0, o.1), (r.0, r.1))
                            && (f64::from(o.2) - r.2).abs() <= 1e-5 * r.2.max(1e-3)
                    }
                    _ => false,
                };
                if report.mismatch_examples.len() < 20 {
                    report.mismatch_examples.push(Mismatch {
                        frame: k,
                        ray: i,
                        ours: ours_t,
                        reference: ref_t,
                        at_shared_edge_or_vertex: shared,
                    });
                }
            }
            let parry_equal = match (parry_hits[i], reference.first()) {
                (None, None) => true,
                (Some((c, t, d)), Some(r)) => {
                    reference.accepts(c, t)
                        && (f64::from(d) - r.distance).abs() <= 1e-5 * r.distance.max(1e-3)
                }
                _ => false,
            };
            report.parry_hits_equal_reference += parry_equal as u64;
        }
        // The world's state is ours again for the recording (the baselines
        // skinned the buffers only).
        each(
            &session,
            &FrameRays {
                frame: k,
                rays: rays.clone(),
                hits: hits.clone(),
            },
        )?;
    }
    let (o, p, s) = (
        Spread::of(&ours_ms),
        Spread::of(&parry_ms),
        Spread::of(&naive_ms),
    );
    report.ms_per_frame = o.mean;
    report.ms_per_frame_spread = o;
    report.parry_ms_per_frame = p.mean;
    report.parry_ms_per_frame_spread = p;
    report.speedup_vs_parry = p.mean / o.mean.max(1e-9);
    report.skin_all_test_every_triangle_ms_per_frame = s.mean;
    report.speedup_vs_skin_all_test_every_triangle = s.mean / o.mean.max(1e-9);
    report.counters = counters;
    Ok(report)
}

/// Whether `r` enters the box `[lo, hi]` (slabs, in `f64`, closed).
fn ray_enters_box(r: &Ray, lo: &Point, hi: &Point) -> bool {
    let (mut t0, mut t1) = (0.0f64, f64::from(r.max_distance));
    for k in 0..3 {
        let (o, d) = (f64::from(r.origin[k]), f64::from(r.direction[k]));
        let (l, h) = (f64::from(lo[k]), f64::from(hi[k]));
        if d == 0.0 {
            if o < l || o > h {
                return false;
            }
            continue;
        }
        let (a, b) = ((l - o) / d, (h - o) / d);
        let (a, b) = if a < b { (a, b) } else { (b, a) };
        t0 = t0.max(a);
        t1 = t1.min(b);
        if t0 > t1 * (1.0 + 1e-12) + 1e-12 {
            return false;
        }
    }
    true
}
