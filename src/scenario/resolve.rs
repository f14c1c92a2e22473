//! From a [`Scenario`] to what a run needs: the character, the room, the clip,
//! the clip time of every frame and the character's world placement per frame.
//!
//! **Gap placement** (§6, "extreme conditions"). The surface's plane is that of
//! its largest triangle, its normal `n` turned towards the room's centre (the
//! centre of the room's bounds). The character is turned by its yaw (default:
//! forward, +Z, along the surface), posed and skinned with the scenario's
//! model at every frame, and translated by `T = α n + β u + γ t`, with `t`
//! the horizontal direction along the surface and `u = n × t` (up on a wall):
//! `α` makes the minimum over every frame and vertex of the signed distance to
//! the plane equal the gap, `β` puts the lowest vertex over the clip on the
//! floor (`y = 0`), `γ` centres the character's extent over the clip on the
//! surface's extent along `t`, moved by `along` metres. The placement is the
//! same for every frame.

use std::path::{Path, PathBuf};

use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

use crate::character::{Character, Clip, PoseBuffers, SkinningModel, generate_humanoid};
use crate::environment::{
    Environment, living_room, living_room_scaled, load_scene, museum, museum_scaled,
};
use crate::geometry::Real;
use crate::io::{CharacterSource, load_character};
use crate::pipeline::Method;
use crate::pipeline::driver::{PipelineOptions, pose_frame};
use crate::sphere_tree::BuildParams;

use super::{EnvironmentSection, Gap, Placement, Recording, Scenario, ScenarioError};

/// A scenario made concrete.
#[derive(Clone, Debug)]
pub struct Resolved {
    pub character: Character,
    pub environment: Environment,
    /// Index of the clip in `character.clips`; `None` for a character without clips (rest pose).
    pub clip_index: Option<usize>,
    pub skinning: SkinningModel,
    pub fps: Real,
    /// Clip time (seconds) of every frame: `start + k / fps`, wrapped around
    /// the clip when more frames than the clip has are asked for.
    pub times: Vec<Real>,
    pub placement: PlacementPlan,
    /// What the gap placement achieved, for `placement.gap`.
    pub gap: Option<GapReport>,
    pub methods: Vec<Method>,
    pub dedup: bool,
    pub threshold: Real,
    pub recording: Recording,
}

/// Where the character is, frame by frame.
#[derive(Clone, Debug, PartialEq)]
pub enum PlacementPlan {
    /// The same transform at every frame (`start`, `gap`).
    Fixed(Isometry3<Real>),
    /// Waypoints walked at `speed` m/s from frame 0, facing the walking direction.
    Walk {
        waypoints: Vec<Vector3<Real>>,
        speed: Real,
        fps: Real,
    },
}

/// The plane and the distances of a gap placement.
#[derive(Clone, Debug, PartialEq)]
pub struct GapReport {
    pub surface: String,
    /// Unit normal of the surface's plane, towards the room's centre.
    pub normal: Vector3<Real>,
    /// The plane is `normal · x = offset`.
    pub offset: Real,
    /// The gap asked for.
    pub metres: Real,
    /// The minimum signed distance over every frame and vertex after placement.
    pub achieved: Real,
    /// The frame where the minimum is reached.
    pub closest_frame: usize,
    /// Frames where some vertex is behind the plane (distance < 0).
    pub penetrating_frames: usize,
}

impl Resolved {
    pub fn frames(&self) -> usize {
        self.times.len()
    }

    pub fn clip(&self) -> Option<&Clip> {
        self.clip_index.map(|i| &self.character.clips[i])
    }

    /// Clip time of `frame` (the last frame's time past the end).
    pub fn time_at(&self, frame: usize) -> Real {
        self.times
            .get(frame)
            .or(self.times.last())
            .copied()
            .unwrap_or(0.0)
    }

    /// The character's world placement at `frame`: world = placement · model.
    pub fn placement_at(&self, frame: usize) -> Isometry3<Real> {
        self.placement.at(frame)
    }

    /// The pipeline settings this scenario asks for.
    pub fn pipeline_options(&self) -> PipelineOptions {
        PipelineOptions {
            skinning: self.skinning,
            dedup: self.dedup,
            threshold: self.threshold,
            build: BuildParams::default(),
        }
    }

    /// Poses and places the character for `frame` into `buffers` (joint
    /// matrices and base; no vertex skinned); returns the milliseconds it took.
    pub fn pose_frame(&self, buffers: &mut PoseBuffers, frame: usize) -> f64 {
        pose_frame(
            buffers,
            &self.character,
            self.clip(),
            self.time_at(frame),
            &self.placement_at(frame).to_homogeneous(),
        )
    }

    /// [`Resolved::pose_frame`] and every vertex skinned; returns the
    /// milliseconds of each: `(pose, skinning)`.
    pub fn pose_and_skin_frame(&self, buffers: &mut PoseBuffers, frame: usize) -> (f64, f64) {
        let pose_ms = self.pose_frame(buffers, frame);
        let t0 = std::time::Instant::now();
        buffers.skin_all(&self.character, self.skinning);
        (pose_ms, t0.elapsed().as_secs_f64() * 1e3)
    }
}

impl PlacementPlan {
    /// The placement at `frame`.
    pub fn at(&self, frame: usize) -> Isometry3<Real> {
        match self {
            PlacementPlan::Fixed(iso) => *iso,
            PlacementPlan::Walk {
                waypoints,
                speed,
                fps,
            } => walk_at(waypoints, speed * frame as Real / fps),
        }
    }
}

/// Rotation about +Y taking the character's forward (+Z) to `(sin yaw, 0, cos yaw)`.
fn yaw_rotation(yaw: Real) -> UnitQuaternion<Real> {
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), yaw)
}

/// Position at arc length `s` along the polyline, facing along the current segment.
fn walk_at(points: &[Vector3<Real>], s: Real) -> Isometry3<Real> {
    let mut left = s.max(0.0);
    let mut yaw = 0.0;
    let mut at = points[0];
    for w in points.windows(2) {
        let d = w[1] - w[0];
        let len = d.norm();
        if len <= 0.0 {
            continue;
        }
        if d.x != 0.0 || d.z != 0.0 {
            yaw = d.x.atan2(d.z);
        }
        if left <= len {
            at = w[0] + d * (left / len);
            return Isometry3::from_parts(Translation3::from(at), yaw_rotation(yaw));
        }
        left -= len;
        at = w[1];
    }
    Isometry3::from_parts(Translation3::from(at), yaw_rotation(yaw))
}

fn asset(base: &Path, p: &Path) -> PathBuf {
    if p.is_relative() && base.join(p).is_file() {
        base.join(p)
    } else {
        p.to_owned()
    }
}

/// Loads the character and the room and works out frame times and placement.
/// Relative asset paths are looked for in `base_dir`, then as given.
pub fn resolve(s: &Scenario, base_dir: &Path) -> Result<Resolved, ScenarioError> {
    let file = s.file.as_path();
    let fail = |field: &str, msg: String| ScenarioError::new(file, None, Some(field), msg);

    let character = match &s.character.source {
        CharacterSource::File(p) => {
            load_character(&asset(base_dir, p))
                .map_err(|e| fail("character.source", e.to_string()))?
                .0
        }
        CharacterSource::Humanoid(h) => {
            generate_humanoid(h).map_err(|e| fail("character.source", e.to_string()))?
        }
    };
    let environment = match &s.environment {
        EnvironmentSection::Museum { seed, vertices } => match vertices {
            None => museum(*seed),
            Some(n) => {
                museum_scaled(*seed, *n).map_err(|e| fail("environment.vertices", e.to_string()))?
            }
        },
        EnvironmentSection::LivingRoom { seed, vertices } => match vertices {
            None => living_room(*seed),
            Some(n) => living_room_scaled(*seed, *n)
                .map_err(|e| fail("environment.vertices", e.to_string()))?,
        },
        EnvironmentSection::Gltf { path } => {
            load_scene(&asset(base_dir, path))
                .map_err(|e| fail("environment.path", e.to_string()))?
                .0
        }
    };
    let mut environment = environment;
    for sub in &s.subdivide {
        environment = environment
            .subdivide_object(&sub.object, sub.times)
            .map_err(|e| fail("environment.subdivide", e.to_string()))?;
    }
    let clip_index = match (&s.character.clip, character.clips.is_empty()) {
        (None, true) => None,
        (name, _) => {
            let clip = character
                .clip(name.as_deref())
                .map_err(|e| fail("character.clip", e.to_string()))?;
            character.clips.iter().position(|c| std::ptr::eq(c, clip))
        }
    };
    let clip = clip_index.map(|i| &character.clips[i]);
    let (start, duration) = clip.map_or((0.0, 0.0), |c| (c.start(), c.duration()));
    let frames = s
        .frames
        .unwrap_or_else(|| (duration * s.fps).floor() as usize + 1);
    let times: Vec<Real> = (0..frames)
        .map(|k| {
            let mut local = k as Real / s.fps;
            if duration > 0.0 && local > duration * (1.0 + 1e-6) {
                local %= duration;
            }
            start + local
        })
        .collect();

    let (placement, gap) = match &s.placement {
        Placement::Start(t) => {
            let [x, y, z] = t.translation;
            let iso = Isometry3::from_parts(
                Translation3::new(x, y, z),
                yaw_rotation(t.yaw_degrees.to_radians()),
            );
            (PlacementPlan::Fixed(iso), None)
        }
        Placement::Path(w) => {
            let waypoints = w
                .waypoints
                .iter()
                .map(|&[x, y, z]| Vector3::new(x, y, z))
                .collect();
            (
                PlacementPlan::Walk {
                    waypoints,
                    speed: w.speed,
                    fps: s.fps,
                },
                None,
            )
        }
        Placement::Gap(g) => {
            let (iso, report) = place_at_gap(s, &character, clip, &times, &environment, g)?;
            (PlacementPlan::Fixed(iso), Some(report))
        }
    };

    Ok(Resolved {
        clip_index,
        skinning: s.character.skinning,
        fps: s.fps,
        times,
        placement,
        gap,
        methods: s.methods.clone(),
        dedup: s.dedup,
        threshold: s.threshold,
        recording: s.recording,
        character,
        environment,
    })
}

fn place_at_gap(
    s: &Scenario,
    character: &Character,
    clip: Option<&Clip>,
    times: &[Real],
    env: &Environment,
    gap: &Gap,
) -> Result<(Isometry3<Real>, GapReport), ScenarioError> {
    let (surface, metres, yaw_degrees) = (gap.surface.as_str(), gap.metres, gap.yaw_degrees);
    let field = "placement.gap.surface";
    let err = |msg: String| ScenarioError::new(&s.file, s.surface_at, Some(field), msg);
    let Some(object) = env.object(surface) else {
        const SHOWN: usize = 8;
        let names: Vec<String> = env
            .objects
            .iter()
            .take(SHOWN)
            .map(|o| format!("{:?}", o.name))
            .collect();
        let more = env.objects.len().saturating_sub(SHOWN);
        let tail = if more > 0 {
            format!(" and {more} more")
        } else {
            String::new()
        };
        return Err(err(format!(
            "no object named {surface:?} in {}; objects: {}{tail}",
            env.name,
            names.join(", ")
        )));
    };

    // The plane of the largest triangle, normal towards the room's centre (f64 throughout).
    let mesh = &env.mesh;
    let pos = mesh.positions();
    let f = |p: &crate::geometry::Point| Vector3::new(p.x as f64, p.y as f64, p.z as f64);
    let mut best: Option<(f64, Vector3<f64>, Vector3<f64>)> = None;
    for ti in object.triangles.clone() {
        let [a, b, c] = mesh.indices()[ti as usize].map(|i| f(&pos[i as usize]));
        let cross = (b - a).cross(&(c - a));
        let area = cross.norm();
        if area > 0.0 && best.is_none_or(|(m, _, _)| area > m) {
            best = Some((area, cross / area, a));
        }
    }
    let Some((_, mut n, on_plane)) = best else {
        return Err(err(format!(
            "object {surface:?} has no triangle of positive area"
        )));
    };
    let (lo, hi) = mesh.bounds();
    let centre = (f(&lo) + f(&hi)) * 0.5;
    if n.dot(&(centre - on_plane)) < 0.0 {
        n = -n;
    }
    let offset = n.dot(&on_plane);

    // Basis: t along the surface (horizontal when it can be), u = n × t.
    let up = Vector3::new(0.0, 1.0, 0.0);
    let horizontal = up.cross(&n);
    let t = if horizontal.norm() > 1e-3 {
        horizontal.normalize()
    } else {
        let x = Vector3::new(1.0, 0.0, 0.0);
        (x - n * n.dot(&x)).normalize()
    };
    let u = n.cross(&t);
    let yaw = match yaw_degrees {
        Some(d) => d.to_radians(),
        None => (t.x as Real).atan2(t.z as Real),
    };
    let rotation = yaw_rotation(yaw);

    // Pass 1: extremes of the turned character over the clip.
    let mut buffers = PoseBuffers::new(character);
    let (mut dmin, mut ymin) = (f64::INFINITY, f64::INFINITY);
    let (mut tmin, mut tmax) = (f64::INFINITY, f64::NEG_INFINITY);
    for &time in times {
        buffers.pose(character, clip, time);
        buffers.skin_all(character, s.character.skinning);
        for p in &buffers.positions {
            let q = f(&(rotation * p));
            dmin = dmin.min(n.dot(&q));
            ymin = ymin.min(q.y);
            let along = t.dot(&q);
            tmin = tmin.min(along);
            tmax = tmax.max(along);
        }
    }
    if !dmin.is_finite() {
        return Err(err("the character has no vertices".into()));
    }
    let (mut smin, mut smax) = (f64::INFINITY, f64::NEG_INFINITY);
    for v in object.vertices.clone() {
        let along = t.dot(&f(&pos[v as usize]));
        smin = smin.min(along);
        smax = smax.max(along);
    }

    let alpha = metres as f64 + offset - dmin;
    // Feet on the floor, unless the surface is itself (nearly) horizontal.
    let beta = if u.y.abs() > 0.1 {
        (-ymin - alpha * n.y) / u.y
    } else {
        0.0
    };
    let gamma = (smin + smax) * 0.5 - (tmin + tmax) * 0.5 + gap.along as f64;
    let shift = n * alpha + u * beta + t * gamma;
    let iso = Isometry3::from_parts(
        Translation3::new(shift.x as Real, shift.y as Real, shift.z as Real),
        rotation,
    );

    // Pass 2: what the placement achieves (in f32 world coordinates, as a run sees them).
    let mut achieved = f64::INFINITY;
    let mut closest_frame = 0;
    let mut penetrating_frames = 0;
    for (k, &time) in times.iter().enumerate() {
        buffers.pose(character, clip, time);
        buffers.skin_all(character, s.character.skinning);
        let frame_min = buffers
            .positions
            .iter()
            .map(|p| n.dot(&f(&(iso * p))) - offset)
            .fold(f64::INFINITY, f64::min);
        if frame_min < achieved {
            achieved = frame_min;
            closest_frame = k;
        }
        penetrating_frames += usize::from(frame_min < 0.0);
    }
    let report = GapReport {
        surface: surface.to_owned(),
        normal: n.map(|c| c as Real),
        offset: offset as Real,
        metres,
        achieved: achieved as Real,
        closest_frame,
        penetrating_frames,
    };
    Ok((iso, report))
}
