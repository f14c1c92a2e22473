//! `cornertree inspect --animate`: play a clip, refit the character's spheres
//! every frame, and measure containment, tightness and cost.
//!
//! The character can be placed at a translation (`offset`): posing then goes
//! through [`PoseBuffers::place`], as in the run loop, so refit and skinning
//! see the large translations of a character far from the origin.
//!
//! - **Containment**: every deformed vertex of every node's triangles must lie
//!   in that node's refit sphere (tolerance `tolerance_rel × model size`, 0 by
//!   default: refit accounts for `f32` rounding itself).
//! - **Tightness**: refit radius over the radius of the minimal sphere (Welzl)
//!   of the same deformed vertices, per node; mean and maximum.
//! - **Cost per frame**: skinning; full refit of every node; on-demand refit,
//!   i.e. the nodes a traversal against a finely tessellated floor under the
//!   character reaches; and a rebuild of the tree from scratch.
//!
//! Finite keyframes can still pose a character out of range (a chain of
//! large scales): every frame's skinning matrices must be finite and its
//! skinned vertices within the loaders' [`MAX_COORDINATE`] before they are
//! used, and a clip that would need more than [`AnimateOptions::max_frames`]
//! frames is refused before the first one.

use std::time::Instant;

use serde::Serialize;

use nalgebra::{Matrix4, Vector3};

use cornertree::character::{Character, Clip, PoseBuffers, SkinningModel, UnknownClip};
use cornertree::geometry::Point;
use cornertree::geometry::enclosing::points_sphere;
use cornertree::io::limits::MAX_COORDINATE;
use cornertree::mesh::{EdgeDedup, TriMesh, TriangleId, dedup_edges};
use cornertree::sphere_tree::character::CharacterTree;
use cornertree::sphere_tree::containment::VertexSets;
use cornertree::sphere_tree::refit::{OnDemand, RefitRule, RefitState, Refitter};
use cornertree::sphere_tree::{BuildParams, SphereTree, Workspace, build_tree, traverse};

/// Settings of an animated inspection.
#[derive(Clone, Debug)]
pub struct AnimateOptions {
    pub model: SkinningModel,
    /// How the tree's spheres are refit.
    pub refit_rule: RefitRule,
    /// Clip name; the first clip when `None`.
    pub clip: Option<String>,
    pub fps: f32,
    pub dedup: bool,
    pub build: BuildParams,
    /// Measure the expensive figures (tightness: a Welzl sphere per node;
    /// rebuild from scratch) on every n-th frame; 0 picks about ten frames
    /// spread over the clip; `usize::MAX` measures the first frame only.
    pub sample_every: usize,
    /// Containment tolerance as a fraction of the model size.
    pub tolerance_rel: f64,
    /// Translation the character is placed at (metres), every frame.
    pub offset: [f32; 3],
    /// Most frames a clip may need at `fps`; longer clips are refused.
    pub max_frames: usize,
}

/// Why a clip cannot be played.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum AnimateError {
    #[error(transparent)]
    UnknownClip(#[from] UnknownClip),
    #[error(
        "clip {clip:?} lasts {duration} s: at {fps} fps that is more than the {max} frames allowed (AnimateOptions::max_frames)"
    )]
    TooManyFrames {
        clip: String,
        duration: f32,
        fps: f32,
        max: usize,
    },
    #[error(
        "clip {clip:?} at t = {time} s: {what}; the joint transforms take the character out of range"
    )]
    PoseOutOfRange {
        clip: String,
        time: f32,
        what: String,
    },
}

impl Default for AnimateOptions {
    fn default() -> Self {
        Self {
            model: SkinningModel::Linear,
            refit_rule: RefitRule::PaperCorners,
            clip: None,
            fps: 30.0,
            dedup: true,
            build: BuildParams::default(),
            sample_every: 0,
            tolerance_rel: 0.0,
            offset: [0.0; 3],
            max_frames: 1_000_000,
        }
    }
}

/// Results of playing one clip. Field names are the `--json` keys under `refit`.
#[derive(Clone, Debug, Serialize)]
pub struct RefitReport {
    pub clip: String,
    pub model: SkinningModel,
    pub refit_rule: RefitRule,
    pub frames: usize,
    pub fps: f32,
    pub nodes: usize,
    /// Translation the character was placed at (metres).
    pub offset: [f32; 3],
    /// `κ`: the refit's rounding margin per unit of `ρ` (the node's joints'
    /// `‖A‖·(‖c‖ + r) + ‖t‖`); see `sphere_tree::refit`.
    pub rounding_coefficient: f64,
    /// Vertex-in-sphere checks made.
    pub checks: u64,
    /// Deformed vertices found outside a refit sphere that should hold them.
    pub violations: u64,
    /// Tolerance used, in model units.
    pub tolerance: f64,
    /// Largest distance of a vertex beyond a refit radius (0 if none).
    pub worst_excess: f64,
    pub tightness_mean: f64,
    pub tightness_max: f64,
    /// Frames on which tightness and rebuild cost were measured.
    pub sampled_frames: usize,
    pub skinning_ms_per_frame: f64,
    pub full_refit_ms_per_frame: f64,
    pub on_demand_ms_per_frame: f64,
    /// Mean nodes refit on demand per frame (traversal against the floor);
    /// `on_demand_ms_per_frame` includes that traversal.
    pub on_demand_refits_mean: f64,
    pub rebuild_ms_per_frame: f64,
}

/// Plays the clip and measures (see the module doc).
pub fn animate(
    character: &Character,
    options: &AnimateOptions,
) -> Result<RefitReport, AnimateError> {
    let clip = character.clip(options.clip.as_deref())?;
    let frames = (f64::from(clip.duration()) * f64::from(options.fps)).floor() + 1.0;
    // Not `>`: a NaN count (from a NaN fps) is refused too.
    let fits = frames <= options.max_frames as f64;
    if !fits {
        return Err(AnimateError::TooManyFrames {
            clip: clip.name.clone(),
            duration: clip.duration(),
            fps: options.fps,
            max: options.max_frames,
        });
    }
    let frames = frames as usize;
    let dedup = if options.dedup {
        dedup_edges(&character.mesh)
    } else {
        EdgeDedup::keep_all(&character.mesh)
    };
    let ct = CharacterTree::build_with_rule(
        character,
        &dedup,
        options.model,
        options.build,
        options.refit_rule,
    );
    let sets = VertexSets::new(&ct.tree, &character.mesh);
    let size = character.mesh.size() as f64;
    let tolerance = options.tolerance_rel * size;
    let offset = Vector3::from(options.offset);
    let placement = Matrix4::new_translation(&offset);

    let mut buffers = PoseBuffers::new(character);
    let mut state = RefitState::new(&ct, character.skeleton.len());
    let mut lazy = RefitState::new(&ct, character.skeleton.len());
    let mut ws = Workspace::new();

    // Floor under the first frame's pose.
    buffers.pose(character, Some(clip), clip.start());
    buffers.place(&placement);
    buffers.skin_all(character, options.model);
    check_pose(clip, clip.start(), &buffers)?;
    let mut floor = floor_under(&buffers.positions, size as f32);

    let every = match options.sample_every {
        0 => frames.div_ceil(10).max(1),
        n => n,
    };
    let mut r = RefitReport {
        clip: clip.name.clone(),
        model: options.model,
        refit_rule: options.refit_rule,
        frames,
        fps: options.fps,
        nodes: ct.tree.len(),
        offset: options.offset,
        rounding_coefficient: ct.refit.rounding_coefficient(),
        checks: 0,
        violations: 0,
        tolerance,
        worst_excess: 0.0,
        tightness_mean: 0.0,
        tightness_max: 0.0,
        sampled_frames: 0,
        skinning_ms_per_frame: 0.0,
        full_refit_ms_per_frame: 0.0,
        on_demand_ms_per_frame: 0.0,
        on_demand_refits_mean: 0.0,
        rebuild_ms_per_frame: 0.0,
    };
    let (mut tight_sum, mut tight_n) = (0.0f64, 0u64);
    let mut scratch: Vec<Point> = Vec::new();
    let mut posed = character.mesh.clone();
    for k in 0..frames {
        let t = clip.start() + k as f32 / options.fps;
        let t0 = Instant::now();
        buffers.pose(character, Some(clip), t);
        buffers.place(&placement);
        buffers.skin_all(character, options.model);
        r.skinning_ms_per_frame += ms(t0);
        check_pose(clip, t, &buffers)?;

        let base = buffers.base;
        let t0 = Instant::now();
        state.begin_frame_with_base(&buffers.skin, &base);
        Refitter {
            tree: &ct,
            skin: &buffers.skin,
            state: &mut state,
        }
        .refit_all(&base);
        r.full_refit_ms_per_frame += ms(t0);

        let t0 = Instant::now();
        lazy.begin_frame_with_base(&buffers.skin, &base);
        let mut od = OnDemand {
            refitter: Refitter {
                tree: &ct,
                skin: &buffers.skin,
                state: &mut lazy,
            },
            base,
        };
        traverse(&mut od, &mut floor, &mut ws, |_| {});
        r.on_demand_ms_per_frame += ms(t0);
        r.on_demand_refits_mean += lazy.refits as f64;

        let c = sets.check(&state.spheres, &buffers.positions, tolerance);
        r.checks += c.checks;
        r.violations += c.violations;
        r.worst_excess = r.worst_excess.max(c.worst_excess);

        if k % every == 0 {
            posed.positions_mut().copy_from_slice(&buffers.positions);
            let t0 = Instant::now();
            let rebuilt = build_tree(&posed, &ct.triangles, options.build);
            r.rebuild_ms_per_frame += ms(t0);
            drop(rebuilt);
            r.sampled_frames += 1;
            for (i, s) in state.spheres.iter().enumerate() {
                // Minimal spheres near the origin: subtracting the offset is
                // exact where it dominates, and Welzl's f32 centre then rounds
                // by the model's ulps, not the offset's.
                scratch.clear();
                scratch.extend(
                    sets.of(i)
                        .iter()
                        .map(|&v| buffers.positions[v as usize] - offset),
                );
                let tight = points_sphere(&scratch).radius as f64;
                if tight > 1e-9 * size {
                    let ratio = s.radius as f64 / tight;
                    tight_sum += ratio;
                    tight_n += 1;
                    r.tightness_max = r.tightness_max.max(ratio);
                }
            }
        }
    }
    let f = frames as f64;
    r.skinning_ms_per_frame /= f;
    r.full_refit_ms_per_frame /= f;
    r.on_demand_ms_per_frame /= f;
    r.on_demand_refits_mean /= f;
    r.rebuild_ms_per_frame /= r.sampled_frames.max(1) as f64;
    r.tightness_mean = if tight_n > 0 {
        tight_sum / tight_n as f64
    } else {
        0.0
    };
    Ok(r)
}

/// Every skinning matrix finite and every skinned vertex within
/// [`MAX_COORDINATE`], the range the loaders accept for positions.
fn check_pose(clip: &Clip, time: f32, buffers: &PoseBuffers) -> Result<(), AnimateError> {
    let fail = |what: String| AnimateError::PoseOutOfRange {
        clip: clip.name.clone(),
        time,
        what,
    };
    if let Some(j) = buffers
        .skin
        .iter()
        .position(|m| !m.iter().all(|c| c.is_finite()))
    {
        return Err(fail(format!(
            "the skinning matrix of joint {j} is not finite"
        )));
    }
    if let Some((v, p)) = buffers
        .positions
        .iter()
        .enumerate()
        .find(|(_, p)| !p.iter().all(|c| c.abs() <= MAX_COORDINATE))
    {
        return Err(fail(format!(
            "skinned vertex {v} is at ({}, {}, {}), beyond {MAX_COORDINATE:e} in magnitude",
            p.x, p.y, p.z
        )));
    }
    Ok(())
}

fn ms(t0: Instant) -> f64 {
    t0.elapsed().as_secs_f64() * 1e3
}

/// A square grid floor (Y up) just under the lowest vertex, twice the
/// character's footprint, in cells of about 2% of the model size.
fn floor_under(positions: &[Point], size: f32) -> SphereTree {
    let (lo, hi) = cornertree::geometry::bounds_of(positions.iter().copied())
        .expect("a posed character has vertices");
    let cx = 0.5 * (lo.x + hi.x);
    let cz = 0.5 * (lo.z + hi.z);
    let half = (hi.x - lo.x).max(hi.z - lo.z).max(1e-3 * size);
    let cell = (0.02 * size).max(1e-6);
    let n = ((2.0 * half / cell).ceil() as u32).clamp(1, 120);
    let y = lo.y - 1e-3 * size;
    let step = 2.0 * half / n as f32;
    let mut p = Vec::with_capacity(((n + 1) * (n + 1)) as usize);
    for j in 0..=n {
        for i in 0..=n {
            p.push(Point::new(
                cx - half + i as f32 * step,
                y,
                cz - half + j as f32 * step,
            ));
        }
    }
    let at = |i: u32, j: u32| j * (n + 1) + i;
    let mut t = Vec::with_capacity((2 * n * n) as usize);
    for j in 0..n {
        for i in 0..n {
            t.push([at(i, j), at(i + 1, j + 1), at(i + 1, j)]);
            t.push([at(i, j), at(i, j + 1), at(i + 1, j + 1)]);
        }
    }
    let mesh = TriMesh::new(p, t).expect("floor grid is well formed");
    let all: Vec<TriangleId> = (0..mesh.triangle_count() as u32).map(TriangleId).collect();
    build_tree(&mesh, &all, BuildParams::default())
}
