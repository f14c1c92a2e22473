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
use std::sync::Arc;

use nalgebra::{Isometry3, Matrix4, Translation3, UnitQuaternion, Vector3};

use crate::environment::{
    Environment, LIVING_ROOM_VERTICES, MUSEUM_VERTICES, living_room, living_room_scaled,
    load_scene_with, museum, museum_scaled,
};
use crate::humanoid::generate_humanoid;
use crate::io::CharacterSource;
use cornertree::character::{Character, Clip, JointId, PoseBuffers, SkinningModel};
use cornertree::geometry::Real;
use cornertree::io::{LoadLimits, load_character_with};
use cornertree::pipeline::Method;
use cornertree::world::WorldSettings;

use super::budget::{self, RunBudget, RunLimits};
use super::motion::Motion;
use super::objects::ObjectShape;
use super::ranges::{self, MAX_FRAMES};
use super::shapes;
use super::{
    CharacterEntry, Doors, EnvironmentSection, Gap, Placement, Recording, Scenario, ScenarioError,
};
use cornertree::mesh::TriMesh;

/// A scenario made concrete: the world's bodies, the room and the run's
/// settings.
#[derive(Clone, Debug)]
pub struct Resolved {
    /// At least one.
    pub characters: Vec<Actor>,
    /// Rigid moving bodies: `[[objects]]`, then the room's doors when they
    /// swing.
    pub objects: Vec<Prop>,
    /// The static room (without its doors when they swing).
    pub environment: Environment,
    pub fps: Real,
    /// Frames to play.
    pub frames: usize,
    pub methods: Vec<Method>,
    pub dedup: bool,
    pub threshold: Real,
    pub recording: Recording,
    /// Continuous detection beside the frames, and its ground truth's
    /// sub-steps per frame step (`ccd`, `ccd_substeps`).
    pub ccd: bool,
    pub ccd_substeps: u32,
    /// Every character also against itself (`self_collision`).
    pub self_collision: bool,
    /// What its self pass culls (`self_culling`).
    pub self_culling: Vec<super::SelfCulling>,
    /// Bytes the bodies, hierarchies and ground truth are estimated to take
    /// (charged to the [`RunLimits`] they were resolved with).
    pub estimated_bytes: usize,
}

/// One character of a world, with its clip and placement over the frames.
#[derive(Clone, Debug)]
pub struct Actor {
    pub name: String,
    /// Shared with the collision worlds playing it.
    pub character: Arc<Character>,
    /// Index of the clip in `character.clips`; `None` for a character without clips (rest pose).
    pub clip_index: Option<usize>,
    pub skinning: SkinningModel,
    /// Seconds added to the world time before the clip is sampled.
    pub clip_offset: Real,
    /// Frame rate of the world's frames.
    pub fps: Real,
    pub placement: PlacementPlan,
    /// What the gap placement achieved, for `placement.gap`.
    pub gap: Option<GapReport>,
}

/// A rigid moving body: its mesh in its own frame and its motion.
#[derive(Clone, Debug)]
pub struct Prop {
    pub name: String,
    pub mesh: TriMesh,
    pub motion: Motion,
}

/// Where the character is, frame by frame.
#[derive(Clone, Debug, PartialEq)]
pub enum PlacementPlan {
    /// The same transform at every frame (`start`, `gap`).
    Fixed(Isometry3<Real>),
    /// Waypoints walked at `speed` m/s from frame 0, facing the walking
    /// direction. The path alone moves the character: the clip's own
    /// horizontal travel at the frame's clip time (`root_travel`) is taken
    /// back out, so a walk clip that moves forward walks in place along the
    /// path.
    Walk {
        waypoints: Vec<Vector3<Real>>,
        speed: Real,
        fps: Real,
        root_travel: RootTravel,
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

impl Actor {
    pub fn clip(&self) -> Option<&Clip> {
        self.clip_index.map(|i| &self.character.clips[i])
    }

    /// Clip time (seconds) of `frame`: `start + frame / fps + clip_offset`,
    /// wrapped around the clip when outside it (the clip loops).
    pub fn time_at(&self, frame: usize) -> Real {
        let (start, duration) = self
            .clip()
            .map_or((0.0, 0.0), |c| (c.start(), c.duration()));
        clip_time(frame, self.fps, self.clip_offset, start, duration)
    }

    /// The character's world placement at `frame`: world = placement · model.
    pub fn placement_at(&self, frame: usize) -> Isometry3<Real> {
        self.placement.at(frame, self.time_at(frame))
    }

    /// Poses and places the character for `frame` into `buffers` (joint
    /// matrices and base; no vertex skinned); returns the milliseconds it took.
    pub fn pose_frame(&self, buffers: &mut PoseBuffers, frame: usize) -> f64 {
        let t0 = std::time::Instant::now();
        buffers.pose(&self.character, self.clip(), self.time_at(frame));
        buffers.place(&self.placement_at(frame).to_homogeneous());
        t0.elapsed().as_secs_f64() * 1e3
    }

    /// [`Actor::pose_frame`] and every vertex skinned; returns the
    /// milliseconds of each: `(pose, skinning)`.
    pub fn pose_and_skin_frame(&self, buffers: &mut PoseBuffers, frame: usize) -> (f64, f64) {
        let pose_ms = self.pose_frame(buffers, frame);
        let t0 = std::time::Instant::now();
        buffers.skin_all(&self.character, self.skinning);
        (pose_ms, t0.elapsed().as_secs_f64() * 1e3)
    }
}

impl Resolved {
    pub fn frames(&self) -> usize {
        self.frames
    }

    /// Whether the scenario is a world: several characters, moving
    /// objects, or characters against themselves (reports then count per
    /// pair kind).
    pub fn is_world(&self) -> bool {
        self.characters.len() > 1 || !self.objects.is_empty() || self.self_collision
    }

    /// The first character (a world has at least one).
    pub fn first(&self) -> &Actor {
        &self.characters[0]
    }

    /// The settings of every method's world: the scenario's big-triangle
    /// threshold, the paper's tree build, refit timed apart, self-collision
    /// and its culling as the scenario says.
    pub fn world_settings(&self) -> WorldSettings {
        WorldSettings {
            threshold: self.threshold,
            self_collision: self.self_collision,
            self_rigid_culling: self.self_culling.contains(&super::SelfCulling::Rigid),
            self_normal_cone_culling: self.self_culling.contains(&super::SelfCulling::NormalCones),
            ..WorldSettings::default()
        }
    }

    /// World time (seconds) of `frame`.
    pub fn world_time(&self, frame: usize) -> Real {
        frame as Real / self.fps
    }
}

impl PlacementPlan {
    /// The placement at `frame`, whose clip time is `clip_time`.
    pub fn at(&self, frame: usize, clip_time: Real) -> Isometry3<Real> {
        match self {
            PlacementPlan::Fixed(iso) => *iso,
            PlacementPlan::Walk {
                waypoints,
                speed,
                fps,
                root_travel,
            } => {
                let back = root_travel.at(clip_time);
                walk_at(waypoints, speed * frame as Real / fps) * Translation3::from(-back)
            }
        }
    }
}

/// Samples of [`RootTravel`] over one loop of a clip, at most.
const ROOT_TRAVEL_SAMPLES: usize = 4096;

/// A clip's horizontal travel over one loop: its first root joint's position
/// (through the skeleton's base) minus the position at the clip's start,
/// vertical part dropped, sampled evenly over the clip and interpolated
/// linearly between samples.
#[derive(Clone, Debug, PartialEq)]
pub struct RootTravel {
    start: Real,
    step: Real,
    samples: Vec<Vector3<Real>>,
}

impl RootTravel {
    /// No travel (no clip, no skeleton root).
    pub fn none() -> Self {
        Self {
            start: 0.0,
            step: 1.0,
            samples: vec![Vector3::zeros()],
        }
    }

    /// The travel of `clip` on `character`, sampled at `fps` (at most
    /// [`ROOT_TRAVEL_SAMPLES`] samples).
    fn of(character: &Character, clip: Option<&Clip>, fps: Real) -> Self {
        let Some(clip) = clip else {
            return Self::none();
        };
        let skeleton = &character.skeleton;
        let Some(root) =
            (0..skeleton.len()).find(|&j| skeleton.parent(JointId(j as u16)).is_none())
        else {
            return Self::none();
        };
        let duration = clip.duration().max(0.0);
        let n = ((duration * fps).ceil() as usize + 1).clamp(2, ROOT_TRAVEL_SAMPLES);
        let step = (duration / (n - 1) as Real).max(Real::MIN_POSITIVE);
        let mut local = skeleton.rest_pose();
        let mut world = vec![Matrix4::identity(); skeleton.len()];
        let mut at = |t: Real| {
            clip.sample(t, skeleton.rest_pose_ref(), &mut local);
            skeleton.world_matrices(&local, &mut world);
            let m = world[root];
            Vector3::new(m[(0, 3)], 0.0, m[(2, 3)])
        };
        let first = at(clip.start());
        let samples = (0..n)
            .map(|i| at(clip.start() + i as Real * step) - first)
            .collect();
        Self {
            start: clip.start(),
            step,
            samples,
        }
    }

    /// The travel at clip time `t`.
    pub fn at(&self, t: Real) -> Vector3<Real> {
        let x = ((t - self.start) / self.step).max(0.0);
        let i = (x.floor() as usize).min(self.samples.len() - 1);
        let j = (i + 1).min(self.samples.len() - 1);
        let f = (x - i as Real).clamp(0.0, 1.0);
        self.samples[i] * (1.0 - f) + self.samples[j] * f
    }
}

/// Clip time of `frame` at `fps`, shifted by `offset`, in a clip from
/// `start` lasting `duration` (looped).
fn clip_time(frame: usize, fps: Real, offset: Real, start: Real, duration: Real) -> Real {
    let mut local = frame as Real / fps + offset;
    if duration > 0.0 && (local > duration * (1.0 + 1e-6) || local < 0.0) {
        local = local.rem_euclid(duration);
    }
    start + local
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

/// Loads the characters, the objects and the room and works out frame times
/// and placements. Relative asset paths are looked for in `base_dir`, then as
/// given. Within the default [`RunLimits`].
pub fn resolve(s: &Scenario, base_dir: &Path) -> Result<Resolved, ScenarioError> {
    resolve_with(s, base_dir, &RunLimits::default())
}

/// [`resolve`] within `limits`: each body, and every method's hierarchies and
/// the ground truth over it, is charged to the budget before it is built
/// (module [`super::budget`]); past the budget the scenario is refused,
/// naming the value that drove the size.
pub fn resolve_with(
    s: &Scenario,
    base_dir: &Path,
    limits: &RunLimits,
) -> Result<Resolved, ScenarioError> {
    let file = s.file.as_path();
    let fail = |field: &str, msg: String| ScenarioError::new(file, None, Some(field), msg);
    let mut budget = RunBudget::new(limits);
    let methods = s.methods.len();
    // The ground truth holds the room once per character.
    let bodies = s.characters.len();
    let load_limits = |budget: &RunBudget| LoadLimits {
        max_bytes: budget.remaining().min(LoadLimits::default().max_bytes),
    };
    let with_methods = if methods == 1 {
        "1 method".to_owned()
    } else {
        format!("{methods} methods")
    };

    let generated_room =
        |budget: &mut RunBudget, name: &str, given: Option<usize>, default: usize| {
            let v = given.unwrap_or(default);
            let bytes = budget::cost::ROOM_PER_VERTEX
                .checked_mul(v)
                .zip(budget::static_mesh_bytes(
                    v.saturating_mul(budget::cost::ROOM_TRIANGLES_PER_VERTEX),
                    methods,
                    bodies,
                ))
                .and_then(|(a, b)| a.checked_add(b));
            let field = if given.is_some() {
                "environment.vertices"
            } else {
                "environment.kind"
            };
            budget
                .charge(bytes, || {
                    format!("a {name} of {v} vertices with {with_methods}' hierarchies")
                })
                .map_err(|m| fail(field, m))
        };
    let environment = match &s.environment {
        EnvironmentSection::Museum { seed, vertices } => {
            generated_room(&mut budget, "museum", *vertices, MUSEUM_VERTICES)?;
            match vertices {
                None => museum(*seed),
                Some(n) => museum_scaled(*seed, *n)
                    .map_err(|e| fail("environment.vertices", e.to_string()))?,
            }
        }
        EnvironmentSection::LivingRoom { seed, vertices } => {
            generated_room(&mut budget, "living room", *vertices, LIVING_ROOM_VERTICES)?;
            match vertices {
                None => living_room(*seed),
                Some(n) => living_room_scaled(*seed, *n)
                    .map_err(|e| fail("environment.vertices", e.to_string()))?,
            }
        }
        EnvironmentSection::Plaza { size } => {
            let Some([w, d]) = size.or_else(|| s.crowd.as_ref().map(|c| c.extent())) else {
                return Err(fail(
                    "environment.size",
                    "a plaza needs a size, or a [crowd] to be sized to".into(),
                ));
            };
            let max = crate::environment::plaza::MAX_SIDE;
            if !(w > 0.0 && d > 0.0 && w <= max && d <= max) {
                return Err(fail(
                    "crowd.count",
                    format!(
                        "the crowd needs a plaza of {w:.0} m × {d:.0} m, past the largest, {max:.0} m a side"
                    ),
                ));
            }
            let env = crate::environment::plaza(w, d);
            let t = env.mesh.triangle_count();
            // Sized to the crowd: the crowd's count drove it.
            let field = if size.is_some() {
                "environment.size"
            } else {
                "crowd.count"
            };
            budget
                .charge(budget::static_mesh_bytes(t, methods, bodies), || {
                    format!(
                        "a plaza of {t} triangles with {with_methods}' hierarchies and the \
                         reference's copy for each of {bodies} characters"
                    )
                })
                .map_err(|m| fail(field, m))?;
            env
        }
        EnvironmentSection::Gltf { path } => {
            let env = load_scene_with(&asset(base_dir, path), &load_limits(&budget))
                .map_err(|e| fail("environment.path", e.to_string()))?
                .0;
            let t = env.mesh.triangle_count();
            budget
                .charge(budget::static_mesh_bytes(t, methods, bodies), || {
                    format!("a scene of {t} triangles with {with_methods}' hierarchies")
                })
                .map_err(|m| fail("environment.path", m))?;
            env
        }
    };
    let mut environment = environment;
    for (i, sub) in s.subdivide.iter().enumerate() {
        if let Some(object) = environment.object(&sub.object) {
            let n = object.triangles.len();
            let added = 4usize
                .checked_pow(sub.times)
                .and_then(|f| (f - 1).checked_mul(n));
            let field = format!("environment.subdivide[{i}].times");
            budget
                .charge(
                    added.and_then(|a| budget::static_mesh_bytes(a, methods, bodies)),
                    || {
                        format!(
                            "splitting {:?} ({n} triangles) {} times with {with_methods}' hierarchies",
                            sub.object, sub.times
                        )
                    },
                )
                .map_err(|m| fail(&field, m))?;
        }
        environment = environment
            .subdivide_object(&sub.object, sub.times)
            .map_err(|e| fail("environment.subdivide", e.to_string()))?;
    }

    // Characters and their clips; the frame count is the longest clip's.
    // Entries of one source (the same file, the same generated humanoid)
    // share one character: loaded or generated once, charged in full once,
    // and each further instance charged only what it holds alone.
    let mut loaded: Vec<(Arc<Character>, Option<usize>)> = Vec::with_capacity(s.characters.len());
    let mut sources: Vec<(CharacterSource, Arc<Character>)> = Vec::new();
    for entry in &s.characters {
        let field = format!("{}.source", entry.field);
        let source = match &entry.character.source {
            CharacterSource::File(p) => CharacterSource::File(asset(base_dir, p)),
            generated => generated.clone(),
        };
        let known = sources
            .iter()
            .find(|(k, _)| *k == source)
            .map(|(_, c)| c.clone());
        let character = match known {
            Some(character) => {
                let (v, t) = (
                    character.mesh.vertex_count(),
                    character.mesh.triangle_count(),
                );
                budget
                    .charge(budget::instance_bytes(v, t, methods), || {
                        format!(
                            "another instance of a character of {v} vertices with {with_methods}' state"
                        )
                    })
                    .map_err(|m| fail(&field, m))?;
                character
            }
            None => {
                let character = Arc::new(match &source {
                    CharacterSource::File(p) => {
                        let character = load_character_with(p, &load_limits(&budget))
                            .map_err(|e| fail(&field, e.to_string()))?
                            .0;
                        let (v, t) = (
                            character.mesh.vertex_count(),
                            character.mesh.triangle_count(),
                        );
                        budget
                            .charge(budget::character_bytes(v, t, methods), || {
                                format!(
                                    "a character of {v} vertices with {with_methods}' hierarchies"
                                )
                            })
                            .map_err(|m| fail(&field, m))?;
                        character
                    }
                    CharacterSource::Humanoid(h) => {
                        let v = h.vertices;
                        budget
                            .charge(
                                budget::character_bytes(v, v.saturating_mul(2), methods),
                                || format!("a humanoid of {v} vertices with {with_methods}' hierarchies"),
                            )
                            .map_err(|m| fail(&field, m))?;
                        generate_humanoid(h).map_err(|e| fail(&field, e.to_string()))?
                    }
                });
                sources.push((source, character.clone()));
                character
            }
        };
        let clip_index = match (&entry.character.clip, character.clips.is_empty()) {
            (None, true) => None,
            (name, _) => {
                let clip = character
                    .clip(name.as_deref())
                    .map_err(|e| fail(&format!("{}.clip", entry.field), e.to_string()))?;
                character.clips.iter().position(|c| std::ptr::eq(c, clip))
            }
        };
        loaded.push((character, clip_index));
    }
    drop(sources);
    let frames = match s.frames {
        Some(n) => n,
        None => {
            // Every frame of the longest clip, within the frame range.
            let mut most = 1;
            for (entry, (c, i)) in s.characters.iter().zip(&loaded) {
                let duration = i.map_or(0.0, |i| c.clips[i].duration()) as f64;
                let n = (duration * s.fps as f64).floor() + 1.0;
                if !n.is_finite() || n > MAX_FRAMES as f64 {
                    return Err(fail(
                        &format!("{}.clip", entry.field),
                        format!(
                            "the clip lasts {} s: {} frames at {} fps, more than {MAX_FRAMES}; give frames",
                            ranges::show(duration),
                            ranges::show(n),
                            s.fps
                        ),
                    ));
                }
                most = most.max(n as usize);
            }
            most
        }
    };

    let mut characters = Vec::with_capacity(loaded.len());
    for (entry, (character, clip_index)) in s.characters.iter().zip(loaded) {
        let clip = clip_index.map(|i| &character.clips[i]);
        let (start, duration) = clip.map_or((0.0, 0.0), |c| (c.start(), c.duration()));
        let times = (0..frames).map(|k| clip_time(k, s.fps, entry.clip_offset, start, duration));
        let (placement, gap) = match &entry.placement {
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
                        root_travel: RootTravel::of(&character, clip, s.fps),
                    },
                    None,
                )
            }
            Placement::Gap(g) => {
                let (iso, report) =
                    place_at_gap(s, entry, &character, clip, times, &environment, g)?;
                (PlacementPlan::Fixed(iso), Some(report))
            }
        };
        characters.push(Actor {
            name: entry.name.clone(),
            character,
            clip_index,
            skinning: entry.character.skinning,
            clip_offset: entry.clip_offset,
            fps: s.fps,
            placement,
            gap,
        });
    }

    // Objects: the scenario's, then the room's doors when they swing.
    let mut objects = Vec::with_capacity(s.objects.len());
    for (i, o) in s.objects.iter().enumerate() {
        let mesh = object_mesh(&o.shape, base_dir, &load_limits(&budget))
            .map_err(|e| fail(&format!("objects[{i}].path"), e))?;
        let t = mesh.triangle_count();
        budget
            .charge(budget::static_mesh_bytes(t, methods, bodies), || {
                format!("an object of {t} triangles with {with_methods}' hierarchies")
            })
            .map_err(|m| fail(&format!("objects[{i}]"), m))?;
        objects.push(Prop {
            name: o.name.clone(),
            mesh,
            motion: o.motion.clone(),
        });
    }
    if s.doors == Doors::Swing {
        let (room, doors) = environment.split_moving();
        environment = room;
        for (name, mesh, motion) in doors {
            if objects.iter().any(|o: &Prop| o.name == name) {
                return Err(fail(
                    "objects",
                    format!("an object is named {name:?} like a door of the room; rename it"),
                ));
            }
            objects.push(Prop {
                name,
                mesh,
                motion: Motion::Periodic(motion),
            });
        }
    }

    // The big triangles' divisions, in the room and in every object.
    let nodes = std::iter::once(&environment.mesh)
        .chain(objects.iter().map(|o| &o.mesh))
        .map(|m| budget::division_node_count(m, &s.methods, s.threshold))
        .fold(0u64, u64::saturating_add);
    budget
        .charge(budget::division_bytes(nodes), || {
            format!(
                "threshold = {} m: dividing the big triangles ({nodes} nodes over {with_methods})",
                ranges::show_f32(s.threshold)
            )
        })
        .map_err(|m| fail("threshold", m))?;

    Ok(Resolved {
        estimated_bytes: budget.used(),
        characters,
        objects,
        environment,
        fps: s.fps,
        frames,
        methods: s.methods.clone(),
        dedup: s.dedup,
        threshold: s.threshold,
        recording: s.recording,
        ccd: s.ccd,
        ccd_substeps: s.ccd_substeps,
        self_collision: s.self_collision,
        self_culling: s.self_culling.clone(),
    })
}

/// The mesh of a generated or loaded object, in its own frame.
fn object_mesh(
    shape: &ObjectShape,
    base_dir: &Path,
    limits: &LoadLimits,
) -> Result<TriMesh, String> {
    Ok(match shape {
        ObjectShape::Box { size } => shapes::box_mesh(*size),
        ObjectShape::Door { size } => shapes::door_mesh(*size),
        ObjectShape::Panel { size } => shapes::panel_mesh(*size),
        ObjectShape::Ball {
            radius,
            subdivisions,
        } => shapes::ball_mesh(*radius, *subdivisions),
        ObjectShape::Gltf { path } => {
            load_scene_with(&asset(base_dir, path), limits)
                .map_err(|e| e.to_string())?
                .0
                .mesh
        }
    })
}

fn place_at_gap(
    s: &Scenario,
    entry: &CharacterEntry,
    character: &Character,
    clip: Option<&Clip>,
    times: impl Iterator<Item = Real> + Clone,
    env: &Environment,
    gap: &Gap,
) -> Result<(Isometry3<Real>, GapReport), ScenarioError> {
    let (surface, metres, yaw_degrees) = (gap.surface.as_str(), gap.metres, gap.yaw_degrees);
    let field = format!("{}.surface", gap_field(entry));
    let err = |msg: String| ScenarioError::new(&s.file, entry.surface_at, Some(&field), msg);
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
    let f = |p: &cornertree::geometry::Point| Vector3::new(p.x as f64, p.y as f64, p.z as f64);
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
    for time in times.clone() {
        buffers.pose(character, clip, time);
        buffers.skin_all(character, entry.character.skinning);
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
    for (k, time) in times.enumerate() {
        buffers.pose(character, clip, time);
        buffers.skin_all(character, entry.character.skinning);
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

/// The field of an entry's gap placement in messages.
fn gap_field(entry: &CharacterEntry) -> String {
    if entry.field == "character" {
        "placement.gap".into()
    } else {
        format!("{}.placement.gap", entry.field)
    }
}
