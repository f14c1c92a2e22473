//! Scenario files: one TOML file says which character plays which clip in which
//! room, where it stands or walks, and which methods to compare (paper §6). The
//! format is described in `docs/scenarios.md`; `scenarios/` ships examples.
//!
//! | file | what |
//! |---|---|
//! | `mod.rs` | [`Scenario`], its sections, [`load_scenario`], [`ScenarioError`] |
//! | [`objects`] | `[[objects]]`: shapes and motions of moving bodies |
//! | [`motion`] | [`motion::Motion`]: an object's pose over time (waypoints, hinge, a room door's swing); its path over a step for continuous detection |
//! | [`shapes`] | meshes of the generated objects (box, panel, ball, door) |
//! | [`ranges`] | the valid range of every number, checked here at load |
//! | [`budget`] | [`RunLimits`]: bytes a run may allocate; sizes charged before they are allocated |
//! | [`resolve`](mod@resolve) | [`resolve()`]: character, room, clip, frame times, and per-frame placement ([`Resolved`]); the "gap" placement of §6's extreme conditions |
//!
//! Every error is one line: `file:line:column: field: problem`, the line and
//! column when the TOML parser reports a span (its own errors quote the
//! offending line instead of a field). Nothing here panics on bad input.

pub mod budget;
pub mod crowd;
pub mod motion;
pub mod objects;
pub mod ranges;
pub mod resolve;
pub mod shapes;

use std::fmt;
use std::ops::Range;
use std::path::{Path, PathBuf};

use serde::Deserialize;
use toml::Spanned;

use crate::io::CharacterSource;
use cornertree::character::SkinningModel;
use cornertree::geometry::Real;
use cornertree::pipeline::{DEFAULT_THRESHOLD, Method};

pub use budget::RunLimits;

/// Sub-steps per frame step of continuous detection's reference
/// (`ccd_substeps`) by default.
pub const DEFAULT_CCD_SUBSTEPS: u32 = 256;
pub use objects::{ObjectEntry, ObjectShape};
pub use resolve::{Actor, GapReport, PlacementPlan, Prop, Resolved, resolve, resolve_with};

/// A scenario as read from a file; asset paths are as found on disk (see
/// [`load_scenario`]).
#[derive(Clone, Debug, PartialEq)]
pub struct Scenario {
    /// The file it was read from (for messages); empty for [`Scenario::parse`] of a string without a name.
    pub file: PathBuf,
    /// `[[characters]]`, or the one `[character]` with its `[placement]`
    /// (named `"character"`); never empty.
    pub characters: Vec<CharacterEntry>,
    /// `[crowd]`, when the characters are one (then `characters` lists its
    /// instances; change the crowd and call [`Scenario::set_crowd`]).
    pub crowd: Option<crowd::Crowd>,
    /// `[[objects]]`: rigid bodies moving through the room.
    pub objects: Vec<ObjectEntry>,
    pub environment: EnvironmentSection,
    /// `[environment] doors`: whether the room's doors stay shut or swing.
    pub doors: Doors,
    /// Frames to play; `None`: every frame of the clip at `fps`.
    pub frames: Option<usize>,
    pub fps: Real,
    pub methods: Vec<Method>,
    /// De-duplicate shared edges of the character mesh (§4).
    pub dedup: bool,
    /// Big-triangle threshold in metres (longest edge).
    pub threshold: Real,
    pub recording: Recording,
    /// `ccd`: continuous detection of every frame step beside the discrete
    /// frames (`run`; docs/ccd.md).
    pub ccd: bool,
    /// `ccd_substeps`: sub-steps per frame step of continuous detection's
    /// ground truth.
    pub ccd_substeps: u32,
    /// `self_collision`: every character also against itself (pair kind
    /// `self`; docs/self-collision.md).
    pub self_collision: bool,
    /// `self_culling`: what the self pass culls (default: parts one joint
    /// moves).
    pub self_culling: Vec<SelfCulling>,
    /// `[environment] subdivide`, applied in order to the room once built.
    pub subdivide: Vec<SubdivideObject>,
}

/// One character of a scenario: what it is, which clip, where.
#[derive(Clone, Debug, PartialEq)]
pub struct CharacterEntry {
    /// Unique among the scenario's characters.
    pub name: String,
    pub character: CharacterSection,
    pub placement: Placement,
    /// Seconds added to the world time before the clip is sampled (so two
    /// copies of one clip are out of step).
    pub clip_offset: Real,
    /// Where this entry's `placement.gap` was written, for messages of [`resolve()`].
    pub(crate) surface_at: Option<Location>,
    /// The entry's field prefix in messages (`character` or `characters[2]`).
    pub(crate) field: String,
}

impl Scenario {
    /// Makes `crowd` the scenario's characters (its instances replace the
    /// characters; a plaza without a size is sized to it).
    pub fn set_crowd(&mut self, crowd: crowd::Crowd) {
        self.characters = crowd.entries();
        self.crowd = Some(crowd);
    }

    /// The first character (a scenario has at least one).
    pub fn first_character(&self) -> &CharacterEntry {
        &self.characters[0]
    }

    /// The first character, to change it.
    pub fn first_character_mut(&mut self) -> &mut CharacterEntry {
        &mut self.characters[0]
    }
}

/// `[environment] doors`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Doors {
    /// The room's doors are part of the static room, shut (as the paper's
    /// tables are measured).
    #[default]
    Closed,
    /// Each of the room's doors is a moving object swinging on its hinge.
    Swing,
}

/// `[character]`.
#[derive(Clone, Debug, PartialEq)]
pub struct CharacterSection {
    pub source: CharacterSource,
    /// Clip name; `None`: the character's first clip.
    pub clip: Option<String>,
    pub skinning: SkinningModel,
}

/// `[environment]`.
#[derive(Clone, Debug, PartialEq)]
pub enum EnvironmentSection {
    /// `vertices`: the layout tessellated to this many vertices instead of
    /// the paper's count (scaling studies).
    Museum {
        seed: u64,
        vertices: Option<usize>,
    },
    LivingRoom {
        seed: u64,
        vertices: Option<usize>,
    },
    Gltf {
        path: PathBuf,
    },
    /// An open floor ([`crate::environment::plaza()`]), `size` metres wide
    /// (`x`) and deep (`z`); `None`: sized to the scenario's crowd.
    Plaza {
        size: Option<[Real; 2]>,
    },
}

/// `[placement]`: exactly one of `start`, `path`, `gap`.
#[derive(Clone, Debug, PartialEq)]
pub enum Placement {
    /// A fixed transform for every frame.
    Start(Transform),
    /// Walk piecewise-linearly through waypoints at a constant speed, facing the walking direction.
    Path(WalkPath),
    /// Keep a gap to a surface over the whole clip.
    Gap(Gap),
}

/// A rigid transform: yaw about +Y, then translation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Transform {
    pub translation: [Real; 3],
    pub yaw_degrees: Real,
}

/// Waypoints (positions of the character's origin) walked at `speed` m/s.
#[derive(Clone, Debug, PartialEq)]
pub struct WalkPath {
    pub waypoints: Vec<[Real; 3]>,
    pub speed: Real,
}

/// "Keep a gap of `metres` from `surface` over the whole clip". A negative gap
/// is allowed on purpose: the character then penetrates the surface by that
/// much at its deepest (the `touching` scenario).
#[derive(Clone, Debug, PartialEq)]
pub struct Gap {
    /// Object name in the environment (e.g. `"south wall"`).
    pub surface: String,
    pub metres: Real,
    /// World yaw of the character; default: its +Z (forward) along the surface.
    pub yaw_degrees: Option<Real>,
    /// Metres from the surface's middle along it (horizontally on a wall),
    /// where the character's extent over the clip is centred; default 0.
    pub along: Real,
}

/// One entry of `[environment] subdivide`: an object's triangles split
/// four-way at their edge midpoints `times` times (an experiment on how big
/// surfaces are tessellated; docs/results.md).
#[derive(Clone, Debug, PartialEq)]
pub struct SubdivideObject {
    /// Object name in the environment (e.g. `"south wall"`).
    pub object: String,
    pub times: u32,
}

/// `[recording]`: what `run` puts in its recordings (docs/recordings.md).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Recording {
    /// Every sphere of every level, not only those the traversal reached.
    pub all_spheres: bool,
    /// The character's mesh every this many frames.
    pub mesh_every: u32,
    /// Spheres and sub-triangles every this many frames (counters, pairs and
    /// the skeleton are logged every frame).
    pub spheres_every: u32,
}

impl Default for Recording {
    fn default() -> Self {
        Self {
            all_spheres: false,
            mesh_every: 1,
            spheres_every: 1,
        }
    }
}

/// Walking speed when a path gives none, m/s.
const DEFAULT_SPEED: f64 = 1.2;

/// A line and column (both from 1) in a scenario file.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Location {
    pub line: usize,
    pub column: usize,
}

/// A scenario problem, displayed on one line: `file[:line:column]: [field: ]problem`.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub struct ScenarioError {
    pub file: PathBuf,
    pub at: Option<Location>,
    /// Dotted field name, when known (`placement.gap.surface`).
    pub field: Option<String>,
    pub message: String,
}

impl fmt::Display for ScenarioError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}", self.file.display())?;
        if let Some(at) = self.at {
            write!(f, ":{}:{}", at.line, at.column)?;
        }
        f.write_str(": ")?;
        if let Some(field) = &self.field {
            write!(f, "{field}: ")?;
        }
        f.write_str(&self.message)
    }
}

impl ScenarioError {
    pub(crate) fn new(
        file: &Path,
        at: Option<Location>,
        field: Option<&str>,
        message: impl Into<String>,
    ) -> Self {
        Self {
            file: file.to_owned(),
            at,
            field: field.map(str::to_owned),
            message: one_line(&message.into()),
        }
    }
}

/// Collapses a message onto one line.
fn one_line(s: &str) -> String {
    s.lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect::<Vec<_>>()
        .join("; ")
}

/// Line and column (from 1, column in characters) of byte `offset` in `text`.
fn locate(text: &str, offset: usize) -> Location {
    let mut offset = offset.min(text.len());
    while !text.is_char_boundary(offset) {
        offset -= 1;
    }
    let before = &text[..offset];
    let line = before.matches('\n').count() + 1;
    let line_start = before.rfind('\n').map_or(0, |i| i + 1);
    Location {
        line,
        column: text[line_start..offset].chars().count() + 1,
    }
}

/// The trimmed text of the line holding byte `offset`, shortened.
fn line_text(text: &str, offset: usize) -> String {
    let loc = locate(text, offset);
    let line = text.lines().nth(loc.line - 1).unwrap_or("").trim();
    let mut s: String = line.chars().take(60).collect();
    if line.chars().count() > 60 {
        s.push('…');
    }
    s
}

// ---- The file as written: spans kept where later checks need a line. ----

/// A culling of the self pass (scenario key `self_culling`; each exact,
/// docs/self-collision.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum SelfCulling {
    /// Parts one joint moves that lie apart at rest are skipped.
    Rigid,
    /// Disks of the mesh whose normals face one direction with a simple
    /// outline are skipped (normal cones; measured not to pay on our
    /// characters).
    NormalCones,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawScenario {
    character: Option<Spanned<RawCharacter>>,
    characters: Option<Vec<Spanned<RawCharacterEntry>>>,
    crowd: Option<Spanned<crowd::RawCrowd>>,
    objects: Option<Vec<Spanned<objects::RawObject>>>,
    environment: Spanned<RawEnvironment>,
    placement: Option<Spanned<RawPlacement>>,
    frames: Option<Spanned<i64>>,
    fps: Option<Spanned<f64>>,
    methods: Option<Spanned<Vec<Method>>>,
    dedup: Option<bool>,
    threshold: Option<Spanned<f64>>,
    ccd: Option<bool>,
    ccd_substeps: Option<Spanned<i64>>,
    self_collision: Option<bool>,
    self_culling: Option<Spanned<Vec<SelfCulling>>>,
    #[serde(default)]
    recording: Option<RawRecording>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCharacter {
    source: Spanned<String>,
    clip: Option<String>,
    #[serde(default = "linear")]
    skinning: SkinningModel,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawCharacterEntry {
    name: Spanned<String>,
    source: Spanned<String>,
    clip: Option<String>,
    #[serde(default = "linear")]
    skinning: SkinningModel,
    placement: Spanned<RawPlacement>,
    clip_offset: Option<Spanned<f64>>,
}

fn linear() -> SkinningModel {
    SkinningModel::Linear
}

#[derive(Deserialize, Clone, Copy, PartialEq, Eq, Debug)]
#[serde(rename_all = "kebab-case")]
enum EnvKind {
    Museum,
    LivingRoom,
    Gltf,
    Plaza,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawEnvironment {
    kind: EnvKind,
    seed: Option<u64>,
    vertices: Option<Spanned<i64>>,
    path: Option<Spanned<String>>,
    size: Option<Spanned<[f64; 2]>>,
    #[serde(default)]
    subdivide: Vec<RawSubdivide>,
    #[serde(default)]
    doors: Doors,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawRecording {
    all_spheres: Option<bool>,
    mesh_every: Option<Spanned<i64>>,
    spheres_every: Option<Spanned<i64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawSubdivide {
    object: String,
    times: Spanned<i64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawPlacement {
    start: Option<Spanned<RawTransform>>,
    path: Option<Spanned<RawWalkPath>>,
    gap: Option<Spanned<RawGap>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawTransform {
    translation: Spanned<[f64; 3]>,
    yaw_degrees: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawWalkPath {
    waypoints: Spanned<Vec<[f64; 3]>>,
    speed: Option<Spanned<f64>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawGap {
    surface: String,
    metres: Spanned<f64>,
    yaw_degrees: Option<Spanned<f64>>,
    along: Option<Spanned<f64>>,
}

impl Scenario {
    /// Parses and checks scenario text; `file` names it in messages and its
    /// directory (then the current directory) is where relative asset paths
    /// are looked for. Asset paths are replaced by the paths found.
    pub fn parse(text: &str, file: &Path) -> Result<Scenario, ScenarioError> {
        let err_at = |span: Range<usize>, field: &str, msg: String| {
            ScenarioError::new(file, Some(locate(text, span.start)), Some(field), msg)
        };
        let raw: RawScenario = toml::from_str(text).map_err(|e| {
            let at = e.span().map(|s| locate(text, s.start));
            let near = e
                .span()
                .map(|s| line_text(text, s.start))
                .filter(|l| !l.is_empty());
            let msg = match near {
                Some(l) => format!("{} (at `{l}`)", one_line(e.message())),
                None => one_line(e.message()),
            };
            ScenarioError::new(file, at, None, msg)
        })?;
        let base = file.parent().unwrap_or(Path::new(""));

        // `[crowd]` alone, or the characters: `[character]` with
        // `[placement]`, or `[[characters]]`.
        let crowd = match raw.crowd {
            None => None,
            Some(c) => {
                if raw.character.is_some() || raw.characters.is_some() {
                    return Err(err_at(
                        c.span(),
                        "crowd",
                        "give [crowd] alone, without [character] or [[characters]]".into(),
                    ));
                }
                Some(crowd::parse_crowd(text, file, base, c.into_inner())?)
            }
        };
        let characters = match (raw.character, raw.characters) {
            (None, None) if crowd.is_some() => {
                crowd.as_ref().map(|c| c.entries()).unwrap_or_default()
            }
            (Some(c), None) => {
                let Some(pl) = raw.placement else {
                    return Err(err_at(
                        c.span(),
                        "placement",
                        "[character] needs a [placement] table".into(),
                    ));
                };
                let c = c.into_inner();
                let character = character_section(
                    text,
                    file,
                    base,
                    "character",
                    &c.source,
                    c.clip,
                    c.skinning,
                )?;
                let (placement, surface_at) = placement(text, file, "placement", pl)?;
                vec![CharacterEntry {
                    name: "character".into(),
                    character,
                    placement,
                    clip_offset: 0.0,
                    surface_at,
                    field: "character".into(),
                }]
            }
            (None, Some(list)) => {
                if let Some(pl) = &raw.placement {
                    return Err(err_at(
                        pl.span(),
                        "placement",
                        "with [[characters]], each character has its own placement".into(),
                    ));
                }
                if list.is_empty() || list.len() > ranges::MAX_CHARACTERS {
                    return Err(ScenarioError::new(
                        file,
                        list.get(ranges::MAX_CHARACTERS)
                            .map(|c| locate(text, c.span().start)),
                        Some("characters"),
                        format!(
                            "needs 1 to {} characters, not {}",
                            ranges::MAX_CHARACTERS,
                            list.len()
                        ),
                    ));
                }
                let mut out: Vec<CharacterEntry> = Vec::with_capacity(list.len());
                for (i, entry) in list.into_iter().enumerate() {
                    let span = entry.span();
                    let e = entry.into_inner();
                    let prefix = format!("characters[{i}]");
                    let name = e.name.get_ref().trim().to_owned();
                    if name.is_empty() {
                        return Err(err_at(
                            e.name.span(),
                            &format!("{prefix}.name"),
                            "must not be empty".into(),
                        ));
                    }
                    if let Some(j) = out.iter().position(|o| o.name == name) {
                        return Err(err_at(
                            e.name.span(),
                            &format!("{prefix}.name"),
                            format!(
                                "two characters named {name:?} (characters[{j}] and characters[{i}])"
                            ),
                        ));
                    }
                    let character = character_section(
                        text, file, base, &prefix, &e.source, e.clip, e.skinning,
                    )?;
                    let (placement, surface_at) =
                        placement(text, file, &format!("{prefix}.placement"), e.placement)?;
                    let clip_offset = match e.clip_offset {
                        None => 0.0,
                        Some(o) => ranges::within(*o.get_ref(), ranges::MAX_SECONDS, "seconds")
                            .map_err(|m| err_at(o.span(), &format!("{prefix}.clip_offset"), m))?
                            as Real,
                    };
                    let _ = span;
                    out.push(CharacterEntry {
                        name,
                        character,
                        placement,
                        clip_offset,
                        surface_at,
                        field: prefix,
                    });
                }
                out
            }
            (Some(c), Some(_)) => {
                return Err(err_at(
                    c.span(),
                    "character",
                    "give either [character] or [[characters]], not both".into(),
                ));
            }
            (None, None) => {
                return Err(ScenarioError::new(
                    file,
                    None,
                    Some("characters"),
                    "no character: give [character] with [placement], [[characters]] or [crowd]",
                ));
            }
        };
        let objects = objects::parse_objects(text, file, base, raw.objects.unwrap_or_default())?;

        // [environment]
        let env_span = raw.environment.span();
        let env = raw.environment.into_inner();
        let mut subdivide = Vec::with_capacity(env.subdivide.len());
        for (i, sub) in env.subdivide.iter().enumerate() {
            let times = ranges::whole(*sub.times.get_ref(), 0, ranges::MAX_SUBDIVIDE_TIMES)
                .map_err(|m| {
                    err_at(
                        sub.times.span(),
                        &format!("environment.subdivide[{i}].times"),
                        m,
                    )
                })?;
            subdivide.push(SubdivideObject {
                object: sub.object.clone(),
                times: times as u32,
            });
        }
        let doors = env.doors;
        if let (Some(sz), false) = (&env.size, env.kind == EnvKind::Plaza) {
            return Err(err_at(
                sz.span(),
                "environment.size",
                "only for kind = \"plaza\"".into(),
            ));
        }
        let environment = match env.kind {
            EnvKind::Plaza => {
                for (given, field) in [
                    (env.path.as_ref().map(|p| p.span()), "environment.path"),
                    (
                        env.vertices.as_ref().map(|v| v.span()),
                        "environment.vertices",
                    ),
                ] {
                    if let Some(span) = given {
                        return Err(err_at(span, field, "a plaza takes only a size".into()));
                    }
                }
                if env.seed.is_some() {
                    return Err(err_at(
                        env_span,
                        "environment.seed",
                        "a plaza takes only a size".into(),
                    ));
                }
                let size = match &env.size {
                    None if crowd.is_none() => {
                        return Err(err_at(
                            env_span,
                            "environment.size",
                            "a plaza needs a size = [width, depth] in metres, or a [crowd] to be sized to".into(),
                        ));
                    }
                    None => None,
                    Some(sz) => {
                        let mut out = [0.0; 2];
                        for (o, &v) in out.iter_mut().zip(sz.get_ref()) {
                            *o = ranges::above_zero(
                                v,
                                f64::from(crate::environment::plaza::MAX_SIDE),
                                "metres",
                            )
                            .map_err(|m| err_at(sz.span(), "environment.size", m))?
                                as Real;
                        }
                        Some(out)
                    }
                };
                EnvironmentSection::Plaza { size }
            }
            EnvKind::Museum | EnvKind::LivingRoom => {
                if let Some(p) = &env.path {
                    return Err(err_at(
                        p.span(),
                        "environment.path",
                        "only for kind = \"gltf\"".into(),
                    ));
                }
                let seed = env.seed.unwrap_or(0);
                let vertices = match &env.vertices {
                    None => None,
                    Some(v) => Some(
                        ranges::whole(*v.get_ref(), 1, crate::environment::MAX_VERTICES as i64)
                            .map_err(|m| err_at(v.span(), "environment.vertices", m))?
                            as usize,
                    ),
                };
                if env.kind == EnvKind::Museum {
                    EnvironmentSection::Museum { seed, vertices }
                } else {
                    EnvironmentSection::LivingRoom { seed, vertices }
                }
            }
            EnvKind::Gltf => {
                let Some(p) = env.path else {
                    return Err(err_at(
                        env_span,
                        "environment.path",
                        "kind = \"gltf\" needs a path".into(),
                    ));
                };
                if env.seed.is_some() {
                    return Err(err_at(
                        env_span,
                        "environment.seed",
                        "a glTF scene takes no seed".into(),
                    ));
                }
                if let Some(v) = &env.vertices {
                    return Err(err_at(
                        v.span(),
                        "environment.vertices",
                        "a glTF scene is used as it is; vertices is for generated rooms".into(),
                    ));
                }
                let path = PathBuf::from(p.get_ref());
                let found = find_asset(base, &path)
                    .ok_or_else(|| err_at(p.span(), "environment.path", missing(base, &path)))?;
                EnvironmentSection::Gltf { path: found }
            }
        };

        // Scalars.
        let frames = match raw.frames {
            Some(f) => Some(
                ranges::whole(*f.get_ref(), 1, ranges::MAX_FRAMES as i64)
                    .map_err(|m| err_at(f.span(), "frames", m))? as usize,
            ),
            None => None,
        };
        let fps = match raw.fps {
            Some(f) => ranges::between(
                *f.get_ref(),
                ranges::MIN_FPS,
                ranges::MAX_FPS,
                "frames per second",
            )
            .map_err(|m| err_at(f.span(), "fps", m))? as Real,
            None => 30.0,
        };
        let methods = match raw.methods {
            Some(m) if m.get_ref().is_empty() => {
                return Err(err_at(
                    m.span(),
                    "methods",
                    format!(
                        "empty; valid methods: {}",
                        Method::ALL.map(Method::name).join(", ")
                    ),
                ));
            }
            Some(m) => {
                let list = m.get_ref();
                if let Some((i, twice)) = list
                    .iter()
                    .enumerate()
                    .find(|(i, a)| list[..*i].contains(a))
                {
                    return Err(err_at(
                        m.span(),
                        "methods",
                        format!("{} is listed twice (methods[{i}])", twice.name()),
                    ));
                }
                m.into_inner()
            }
            None => Method::ALL.to_vec(),
        };
        let threshold = match raw.threshold {
            Some(t) => ranges::between(
                *t.get_ref(),
                ranges::MIN_THRESHOLD,
                ranges::MAX_THRESHOLD,
                "metres",
            )
            .map_err(|m| err_at(t.span(), "threshold", m))? as Real,
            None => DEFAULT_THRESHOLD,
        };
        let ccd_substeps = match raw.ccd_substeps {
            Some(n) => ranges::whole(*n.get_ref(), 1, ranges::MAX_CCD_SUBSTEPS)
                .map_err(|m| err_at(n.span(), "ccd_substeps", m))? as u32,
            None => DEFAULT_CCD_SUBSTEPS,
        };
        let self_collision = raw.self_collision.unwrap_or(false);
        let self_culling = match raw.self_culling {
            Some(c) if !self_collision => {
                return Err(err_at(
                    c.span(),
                    "self_culling",
                    "culls the self pass, which runs only with `self_collision = true`".into(),
                ));
            }
            Some(c) => c.into_inner(),
            None => vec![SelfCulling::Rigid],
        };
        let recording = match raw.recording {
            Some(r) => {
                let every = |v: &Option<Spanned<i64>>, field: &str| match v {
                    None => Ok(1),
                    Some(v) => ranges::whole(*v.get_ref(), 1, i64::from(u32::MAX))
                        .map(|n| n as u32)
                        .map_err(|m| err_at(v.span(), field, m)),
                };
                Recording {
                    all_spheres: r.all_spheres.unwrap_or(false),
                    mesh_every: every(&r.mesh_every, "recording.mesh_every")?,
                    spheres_every: every(&r.spheres_every, "recording.spheres_every")?,
                }
            }
            None => Recording::default(),
        };

        Ok(Scenario {
            file: file.to_owned(),
            characters,
            objects,
            environment,
            doors,
            frames,
            fps,
            methods,
            dedup: raw.dedup.unwrap_or(true),
            threshold,
            recording,
            ccd: raw.ccd.unwrap_or(false),
            ccd_substeps,
            self_collision,
            self_culling,
            subdivide,
            crowd,
        })
    }
}

/// Reads, parses and checks a scenario file (see [`Scenario::parse`]).
pub fn load_scenario(path: &Path) -> Result<Scenario, ScenarioError> {
    use std::io::Read;
    let fail = |e: String| ScenarioError::new(path, None, None, e);
    let file = std::fs::File::open(path).map_err(|e| fail(e.to_string()))?;
    let mut bytes = Vec::new();
    file.take(ranges::MAX_FILE_BYTES + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| fail(e.to_string()))?;
    if bytes.len() as u64 > ranges::MAX_FILE_BYTES {
        return Err(fail(format!(
            "larger than the {} bytes a scenario file may have",
            ranges::MAX_FILE_BYTES
        )));
    }
    let text = String::from_utf8(bytes).map_err(|e| {
        fail(format!(
            "not UTF-8 text (byte {})",
            e.utf8_error().valid_up_to()
        ))
    })?;
    Scenario::parse(&text, path)
}

/// Loads `path` and resolves it against its own directory (relative asset
/// paths are relative to the scenario file): what every command starts with.
pub fn open_scenario(path: &Path) -> Result<Resolved, ScenarioError> {
    open_scenario_with(path, |_| {})
}

/// [`open_scenario`] with the scenario changed by `edit` before it is
/// resolved (command-line overrides that the placement depends on, such as
/// the skinning model).
pub fn open_scenario_with(
    path: &Path,
    edit: impl FnOnce(&mut Scenario),
) -> Result<Resolved, ScenarioError> {
    open_scenario_within(path, &RunLimits::default(), edit)
}

/// [`open_scenario_with`] within `limits` (see [`resolve_with`]).
pub fn open_scenario_within(
    path: &Path,
    limits: &RunLimits,
    edit: impl FnOnce(&mut Scenario),
) -> Result<Resolved, ScenarioError> {
    let mut scenario = load_scenario(path)?;
    edit(&mut scenario);
    let base_dir = path.parent().map(PathBuf::from).unwrap_or_default();
    resolve_with(&scenario, &base_dir, limits)
}

/// A scenario's name in reports and recording file names: its file stem.
pub fn scenario_name(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_default()
}

/// `path` if absolute and present; else `base/path`, else `path` from the current directory.
fn find_asset(base: &Path, path: &Path) -> Option<PathBuf> {
    if path.is_absolute() {
        return path.is_file().then(|| path.to_owned());
    }
    let in_base = base.join(path);
    if in_base.is_file() {
        return Some(in_base);
    }
    path.is_file().then(|| path.to_owned())
}

fn missing(base: &Path, path: &Path) -> String {
    if path.is_absolute() {
        format!("file {} does not exist", path.display())
    } else {
        let dir = if base.as_os_str().is_empty() {
            Path::new(".")
        } else {
            base
        };
        format!(
            "file {} does not exist (looked in {} and the current directory)",
            path.display(),
            dir.display()
        )
    }
}

/// `[character]` or one `[[characters]]` entry's character keys.
fn character_section(
    text: &str,
    file: &Path,
    base: &Path,
    prefix: &str,
    src: &Spanned<String>,
    clip: Option<String>,
    skinning: SkinningModel,
) -> Result<CharacterSection, ScenarioError> {
    let field = format!("{prefix}.source");
    let err_at = |span: Range<usize>, msg: String| {
        ScenarioError::new(file, Some(locate(text, span.start)), Some(&field), msg)
    };
    let mut source: CharacterSource = src
        .get_ref()
        .parse()
        .map_err(|e: crate::io::SourceError| err_at(src.span(), e.to_string()))?;
    match &source {
        CharacterSource::File(p) => {
            let found = find_asset(base, p).ok_or_else(|| err_at(src.span(), missing(base, p)))?;
            source = CharacterSource::File(found);
        }
        CharacterSource::Humanoid(h) => {
            use crate::humanoid::{MAX_VERTICES, MIN_VERTICES};
            if !(MIN_VERTICES..=MAX_VERTICES).contains(&h.vertices) {
                return Err(err_at(
                    src.span(),
                    format!(
                        "vertices must be a whole number from {MIN_VERTICES} to {MAX_VERTICES}, not {}",
                        h.vertices
                    ),
                ));
            }
        }
    }
    Ok(CharacterSection {
        source,
        clip,
        skinning,
    })
}

/// A `placement` table (`prefix` names it in messages): the placement and,
/// for `gap`, where it was written.
fn placement(
    text: &str,
    file: &Path,
    prefix: &str,
    raw: Spanned<RawPlacement>,
) -> Result<(Placement, Option<Location>), ScenarioError> {
    let err_at = |span: Range<usize>, field: &str, msg: String| {
        ScenarioError::new(file, Some(locate(text, span.start)), Some(field), msg)
    };
    let f = |rest: &str| format!("{prefix}{rest}");
    let pl_span = raw.span();
    let pl = raw.into_inner();
    let count = usize::from(pl.start.is_some())
        + usize::from(pl.path.is_some())
        + usize::from(pl.gap.is_some());
    if count != 1 {
        return Err(err_at(
            pl_span,
            &f(""),
            format!("give exactly one of start, path, gap (found {count})"),
        ));
    }
    let mut surface_at = None;
    let metres = |v: &Spanned<f64>, field: &str| {
        ranges::within(*v.get_ref(), ranges::MAX_METRES, "metres")
            .map(|v| v as Real)
            .map_err(|m| err_at(v.span(), &f(field), m))
    };
    let degrees = |v: &Spanned<f64>, field: &str| {
        ranges::within(*v.get_ref(), ranges::MAX_DEGREES, "degrees")
            .map(|v| v as Real)
            .map_err(|m| err_at(v.span(), &f(field), m))
    };
    let placement = if let Some(t) = pl.start {
        let t = t.into_inner();
        let span = t.translation.span();
        let mut translation = [0.0; 3];
        for (out, &v) in translation.iter_mut().zip(t.translation.get_ref()) {
            *out = metres(&Spanned::new(span.clone(), v), ".start.translation")?;
        }
        let yaw_degrees = match &t.yaw_degrees {
            Some(y) => degrees(y, ".start.yaw_degrees")?,
            None => 0.0,
        };
        Placement::Start(Transform {
            translation,
            yaw_degrees,
        })
    } else if let Some(p) = pl.path {
        let span = p.span();
        let w = p.into_inner();
        if w.waypoints.get_ref().is_empty() {
            return Err(err_at(
                span,
                &f(".path.waypoints"),
                "needs at least one waypoint".into(),
            ));
        }
        let at = w.waypoints.span();
        let mut waypoints = Vec::with_capacity(w.waypoints.get_ref().len());
        for (i, point) in w.waypoints.get_ref().iter().enumerate() {
            let mut out = [0.0; 3];
            for (o, &v) in out.iter_mut().zip(point) {
                *o = metres(
                    &Spanned::new(at.clone(), v),
                    &format!(".path.waypoints[{i}]"),
                )?;
            }
            waypoints.push(out);
        }
        let speed = match &w.speed {
            Some(v) => ranges::above_zero(*v.get_ref(), ranges::MAX_SPEED, "m/s")
                .map_err(|m| err_at(v.span(), &f(".path.speed"), m))?,
            None => DEFAULT_SPEED,
        };
        Placement::Path(WalkPath {
            waypoints,
            speed: speed as Real,
        })
    } else {
        let g = pl.gap.expect("counted above");
        let span = g.span();
        let g = g.into_inner();
        let gap = Gap {
            metres: metres(&g.metres, ".gap.metres")?,
            along: match &g.along {
                Some(a) => metres(a, ".gap.along")?,
                None => 0.0,
            },
            yaw_degrees: match &g.yaw_degrees {
                Some(y) => Some(degrees(y, ".gap.yaw_degrees")?),
                None => None,
            },
            surface: g.surface,
        };
        surface_at = Some(locate(text, span.start));
        Placement::Gap(gap)
    };
    Ok((placement, surface_at))
}
