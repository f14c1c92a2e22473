//! A procedural humanoid: skeleton, closed skinned surface and three clips,
//! standing in for the paper's avatar (§6: 44,345 vertices) in tests and
//! benchmarks.
//!
//! **Skeleton.** 22 joints, parents before children, about 1.77 m tall, Y up,
//! facing +Z (the character's left is +X), arms hanging slightly spread. Every
//! rest rotation is the identity, so a joint's local axes are the world axes at
//! rest; inverse bind matrices are the inverse rest world matrices, the base is
//! the identity.
//!
//! **Surface.** A union of 17 closed parts (torso, neck, head; per side upper
//! arm, forearm, hand, thigh, shin, foot, toe) that overlap at the joints, as
//! game characters do. Each part is a generalised cylinder along a straight
//! axis: elliptical sections whose semi-axes are interpolated from a few keys,
//! closed by elliptical domes ending in a pole vertex. Rings are spaced evenly
//! along the meridian's arc length (`0.866·h`), each ring gets
//! `round(perimeter / h)` vertices spread evenly in arc length (alternate rings
//! shifted half a step), and neighbouring rings are zipped together by walking
//! both in order of their arc-length fraction, so rings of different counts
//! join with well-shaped triangles and every edge of a part is used by exactly
//! two triangles. The edge length `h` is found by bisection so that the vertex
//! count comes close to the target; the remainder is then added to or taken
//! from the largest rings one vertex at a time, which hits the target exactly
//! for any reasonable count.
//!
//! **Weights.** Each part lists the joints along its axis with the axial
//! coordinate where each takes over. Away from those boundaries a vertex is
//! bound rigidly; within a blend zone around a boundary it blends the parent and
//! child with a smoothstep of the axial coordinate (two influences, summing to
//! one), so the paper's one-joint model converts exactly.
//!
//! **Clips** (LINEAR rotations at 30 keys/s, the seed varies amplitudes, phases
//! and durations by a few per cent): `walk` (one stride cycle of 1.0–1.2 s
//! moving forward on +Z: hips swing, knees bend in swing, arms counter-swing,
//! pelvis bobs and twists), `reach` (turn the chest and reach the right arm
//! forward to a wall in front, hold, and back), `turn` (turn in place by about
//! 90° to the left, stepping), and three where the body touches itself:
//! `hand-to-hip` (the right arm drawn in until hand and forearm press the
//! hip), `arms-crossed` (both forearms folded across the chest, crossing
//! each other), `squat` (down until calves press thighs, arms forward, and
//! up again). Each of those rises, holds and returns to rest.

use std::f32::consts::{FRAC_PI_2, PI, TAU};

use nalgebra::{Matrix4, Quaternion, UnitQuaternion, Vector3};

use cornertree::geometry::Point;
use cornertree::mesh::{MeshError, TriMesh};

use cornertree::character::clip::ChannelError;
use cornertree::character::skinning::SkinError;
use cornertree::character::{
    Channel, ChannelValues, Character, Clip, Interpolation, Joint, JointId, Skeleton,
    SkeletonError, Trs,
};

/// The paper's avatar size (§6).
pub const PAPER_VERTICES: usize = 44_345;
/// Fewest vertices accepted: below this the parts cannot keep their shape.
pub const MIN_VERTICES: usize = 500;
/// Most vertices accepted.
pub const MAX_VERTICES: usize = 2_000_000;
/// Keyframes per second of the generated clips.
pub const KEYS_PER_SECOND: f32 = 30.0;

/// What to generate.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct HumanoidParams {
    /// Target vertex count (met within 1%, usually exactly).
    pub vertices: usize,
    /// Varies the clips slightly; the mesh does not depend on it.
    pub seed: u64,
}

impl Default for HumanoidParams {
    fn default() -> Self {
        Self {
            vertices: PAPER_VERTICES,
            seed: 0,
        }
    }
}

/// Why a humanoid cannot be generated.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum HumanoidError {
    #[error(
        "a humanoid of {requested} vertices was asked for; supported: {MIN_VERTICES} to {MAX_VERTICES}"
    )]
    VertexCount { requested: usize },
    #[error("generated skeleton is invalid: {0}")]
    Skeleton(#[from] SkeletonError),
    #[error("generated mesh is invalid: {0}")]
    Mesh(#[from] MeshError),
    #[error("generated weights are invalid: {0}")]
    Skin(#[from] SkinError),
    #[error("generated clip is invalid: {0}")]
    Clip(#[from] ChannelError),
}

/// One closed part of the surface: its vertices and triangles are contiguous.
#[derive(Clone, Debug, PartialEq)]
pub struct BodyPart {
    pub name: &'static str,
    pub vertices: std::ops::Range<usize>,
    pub triangles: std::ops::Range<usize>,
}

/// Generates the humanoid.
pub fn generate_humanoid(p: &HumanoidParams) -> Result<Character, HumanoidError> {
    generate_humanoid_parts(p).map(|(c, _)| c)
}

/// Generates the humanoid and reports where each body part lies in the mesh.
pub fn generate_humanoid_parts(
    p: &HumanoidParams,
) -> Result<(Character, Vec<BodyPart>), HumanoidError> {
    if !(MIN_VERTICES..=MAX_VERTICES).contains(&p.vertices) {
        return Err(HumanoidError::VertexCount {
            requested: p.vertices,
        });
    }
    let skeleton = skeleton()?;
    let specs = part_specs();
    let layouts = fit_layout(&specs, p.vertices);
    let built = build_surface(&specs, &layouts);
    let mesh = TriMesh::new(built.positions, built.triangles)?;
    let influences =
        cornertree::character::Influences::new(built.joints, built.weights, skeleton.len())?;
    let clips = clips(&skeleton, p.seed)?;
    let name = format!("humanoid-{}v-seed{}", p.vertices, p.seed);
    Ok((
        Character::new(name, skeleton, mesh, influences, clips),
        built.parts,
    ))
}

// ---------------------------------------------------------------------------
// Skeleton

/// Name, parent name and rest world position of every joint (metres).
const JOINTS: [(&str, Option<&str>, [f32; 3]); 22] = [
    ("pelvis", None, [0.0, 0.95, 0.0]),
    ("spine_01", Some("pelvis"), [0.0, 1.05, 0.0]),
    ("spine_02", Some("spine_01"), [0.0, 1.17, 0.0]),
    ("chest", Some("spine_02"), [0.0, 1.31, 0.0]),
    ("neck", Some("chest"), [0.0, 1.48, 0.0]),
    ("head", Some("neck"), [0.0, 1.56, 0.0]),
    ("clavicle_l", Some("chest"), [0.03, 1.43, 0.0]),
    ("upper_arm_l", Some("clavicle_l"), [0.18, 1.43, 0.0]),
    ("forearm_l", Some("upper_arm_l"), [0.235, 1.135, 0.0]),
    ("hand_l", Some("forearm_l"), [0.27, 0.875, 0.0]),
    ("clavicle_r", Some("chest"), [-0.03, 1.43, 0.0]),
    ("upper_arm_r", Some("clavicle_r"), [-0.18, 1.43, 0.0]),
    ("forearm_r", Some("upper_arm_r"), [-0.235, 1.135, 0.0]),
    ("hand_r", Some("forearm_r"), [-0.27, 0.875, 0.0]),
    ("thigh_l", Some("pelvis"), [0.10, 0.90, 0.0]),
    ("shin_l", Some("thigh_l"), [0.10, 0.47, 0.0]),
    ("foot_l", Some("shin_l"), [0.10, 0.08, 0.0]),
    ("toe_l", Some("foot_l"), [0.10, 0.03, 0.13]),
    ("thigh_r", Some("pelvis"), [-0.10, 0.90, 0.0]),
    ("shin_r", Some("thigh_r"), [-0.10, 0.47, 0.0]),
    ("foot_r", Some("shin_r"), [-0.10, 0.08, 0.0]),
    ("toe_r", Some("foot_r"), [-0.10, 0.03, 0.13]),
];

fn joint_index(name: &str) -> usize {
    JOINTS
        .iter()
        .position(|j| j.0 == name)
        .unwrap_or_else(|| panic!("no joint {name}"))
}

fn joint_pos(name: &str) -> Vector3<f32> {
    Vector3::from(JOINTS[joint_index(name)].2)
}

fn skeleton() -> Result<Skeleton, SkeletonError> {
    let joints = JOINTS
        .iter()
        .map(|&(name, parent, world)| {
            let world = Vector3::from(world);
            let parent_world = parent.map_or(Vector3::zeros(), joint_pos);
            Joint {
                name: name.to_string(),
                parent: parent.map(|p| JointId(joint_index(p) as u16)),
                rest: Trs::from_translation(world - parent_world),
                inverse_bind: Matrix4::new_translation(&-world),
            }
        })
        .collect();
    Skeleton::new(joints, Matrix4::identity())
}

// ---------------------------------------------------------------------------
// Part shapes

/// A generalised cylinder along `start + s·axis`, `s` in `[-cap0, len + cap1]`.
#[derive(Clone, Debug)]
struct PartSpec {
    name: &'static str,
    start: Vector3<f32>,
    /// Unit axis; `u` (semi-axis `a`) and `v = axis × u` (semi-axis `b`) span
    /// the sections.
    axis: Vector3<f32>,
    u: Vector3<f32>,
    /// `(s, a, b)` with `s` increasing from 0 to the part's length.
    keys: Vec<[f32; 3]>,
    /// Dome lengths before the first key and after the last.
    caps: [f32; 2],
    /// `(joint, s where it takes over, blend half-width)`, by increasing `s`;
    /// the first entry owns everything before the second.
    chain: Vec<(usize, f32, f32)>,
}

impl PartSpec {
    /// A part from `from` to `to` with section keys at fractions of its length.
    fn between(
        name: &'static str,
        from: Vector3<f32>,
        to: Vector3<f32>,
        keys: &[[f32; 3]],
        caps: [f32; 2],
    ) -> Self {
        let d = to - from;
        let len = d.norm();
        let axis = d / len;
        // Width direction: X (or Y for an axis along X) made perpendicular.
        let reference = if axis.x.abs() > 0.9 {
            Vector3::y()
        } else {
            Vector3::x()
        };
        let u = (reference - axis * reference.dot(&axis)).normalize();
        let keys = keys.iter().map(|k| [k[0] * len, k[1], k[2]]).collect();
        Self {
            name,
            start: from,
            axis,
            u,
            keys,
            caps,
            chain: Vec::new(),
        }
    }

    /// Adds the joints along the axis: `(joint name, s, blend half-width)`.
    fn chain(mut self, chain: &[(&str, f32, f32)]) -> Self {
        self.chain = chain
            .iter()
            .map(|&(j, s, z)| (joint_index(j), s, z))
            .collect();
        self
    }

    fn len(&self) -> f32 {
        self.keys.last().map_or(0.0, |k| k[0])
    }

    fn s_range(&self) -> (f32, f32) {
        (-self.caps[0], self.len() + self.caps[1])
    }

    fn v(&self) -> Vector3<f32> {
        self.axis.cross(&self.u)
    }

    /// Section semi-axes at `s`: keys interpolated linearly, domes elliptical.
    fn section(&self, s: f32) -> (f32, f32) {
        let first = self.keys[0];
        let last = *self.keys.last().unwrap();
        if s <= first[0] {
            let f = dome(s - first[0], self.caps[0]);
            return (first[1] * f, first[2] * f);
        }
        if s >= last[0] {
            let f = dome(s - last[0], self.caps[1]);
            return (last[1] * f, last[2] * f);
        }
        let k = self.keys.partition_point(|k| k[0] <= s) - 1;
        let (p, q) = (self.keys[k], self.keys[k + 1]);
        let t = (s - p[0]) / (q[0] - p[0]);
        (p[1] + t * (q[1] - p[1]), p[2] + t * (q[2] - p[2]))
    }

    /// `(joint, weight)` pairs of a vertex at axial coordinate `s`.
    fn weights(&self, s: f32) -> ([u16; 4], [f32; 4]) {
        let mut owner = 0;
        for (k, &(_, start, z)) in self.chain.iter().enumerate().skip(1) {
            if s >= start - z {
                owner = k;
            }
        }
        let (joint, start, z) = self.chain[owner];
        if owner == 0 || s >= start + z {
            return ([joint as u16, 0, 0, 0], [1.0, 0.0, 0.0, 0.0]);
        }
        let t = smoothstep((s - (start - z)) / (2.0 * z));
        let parent = self.chain[owner - 1].0;
        ([parent as u16, joint as u16, 0, 0], [1.0 - t, t, 0.0, 0.0])
    }
}

/// Dome profile: 1 at the key, 0 at distance `cap` beyond it.
fn dome(d: f32, cap: f32) -> f32 {
    let x = (d / cap).clamp(-1.0, 1.0);
    (1.0 - x * x).max(0.0).sqrt()
}

fn smoothstep(x: f32) -> f32 {
    let x = x.clamp(0.0, 1.0);
    x * x * (3.0 - 2.0 * x)
}

/// Mirrors a left-side position to the right.
fn mirror(p: Vector3<f32>) -> Vector3<f32> {
    Vector3::new(-p.x, p.y, p.z)
}

fn part_specs() -> Vec<PartSpec> {
    let mut parts = axial_parts();
    for side in ["l", "r"] {
        parts.extend(arm_parts(side));
        parts.extend(leg_parts(side));
    }
    parts
}

/// Torso, neck and head: vertical axes.
fn axial_parts() -> Vec<PartSpec> {
    let y = |v: f32| Vector3::new(0.0, v, 0.0);
    // (height, half-width, half-depth) from the hips to the shoulders.
    let torso_keys = [
        [0.85, 0.150, 0.100],
        [0.95, 0.165, 0.110],
        [1.08, 0.140, 0.095],
        [1.20, 0.145, 0.105],
        [1.33, 0.165, 0.115],
        [1.43, 0.175, 0.100],
        [1.47, 0.150, 0.085],
    ];
    // Domes close it at 0.78 m and 1.53 m.
    let (t0, t1) = (0.85, 1.47);
    let torso_keys: Vec<[f32; 3]> = torso_keys
        .iter()
        .map(|k| [(k[0] - t0) / (t1 - t0), k[1], k[2]])
        .collect();
    let torso = PartSpec::between("torso", y(t0), y(t1), &torso_keys, [0.07, 0.06]).chain(&[
        ("pelvis", f32::NEG_INFINITY, 0.0),
        ("spine_01", 1.05 - t0, 0.04),
        ("spine_02", 1.17 - t0, 0.04),
        ("chest", 1.31 - t0, 0.04),
    ]);
    let neck = PartSpec::between(
        "neck",
        y(1.43),
        y(1.58),
        &[[0.0, 0.056, 0.056], [1.0, 0.050, 0.050]],
        [0.04, 0.03],
    )
    .chain(&[
        ("chest", f32::NEG_INFINITY, 0.0),
        ("neck", 0.05, 0.035),
        ("head", 0.13, 0.03),
    ]);
    // Head: an ellipsoid centred at 1.66 m, a little forward (a 1 mm axis
    // between two domes).
    let centre = Vector3::new(0.0, 1.66, 0.012);
    let head = PartSpec::between(
        "head",
        centre,
        centre + Vector3::new(0.0, 1e-3, 0.0),
        &[[0.0, 0.078, 0.095], [1.0, 0.078, 0.095]],
        [0.115, 0.114],
    )
    .chain(&[("neck", f32::NEG_INFINITY, 0.0), ("head", -0.1, 0.03)]);
    vec![torso, neck, head]
}

fn side_name(base: &str, side: &str) -> &'static str {
    // Joint names are static; look the full name up in the table.
    let full = format!("{base}_{side}");
    JOINTS[joint_index(&full)].0
}

fn side_pos(base: &str, side: &str) -> Vector3<f32> {
    let p = joint_pos(&format!("{base}_l"));
    if side == "l" { p } else { mirror(p) }
}

fn arm_parts(side: &str) -> Vec<PartSpec> {
    let j = |b| side_name(b, side);
    let (shoulder, elbow, wrist) = (
        side_pos("upper_arm", side),
        side_pos("forearm", side),
        side_pos("hand", side),
    );
    let tip_l = Vector3::new(0.28, 0.70, 0.01);
    let tip = if side == "l" { tip_l } else { mirror(tip_l) };
    let upper_len = (elbow - shoulder).norm();
    let fore_len = (wrist - elbow).norm();
    let upper = PartSpec::between(
        side_name("upper_arm", side),
        shoulder,
        elbow,
        &[
            [0.0, 0.052, 0.050],
            [0.5, 0.046, 0.046],
            [1.0, 0.038, 0.038],
        ],
        [0.05, 0.035],
    )
    .chain(&[
        (j("clavicle"), f32::NEG_INFINITY, 0.0),
        (j("upper_arm"), 0.0, 0.035),
        (j("forearm"), upper_len, 0.03),
    ]);
    let fore = PartSpec::between(
        side_name("forearm", side),
        elbow,
        wrist,
        &[
            [0.0, 0.040, 0.040],
            [0.3, 0.042, 0.042],
            [1.0, 0.028, 0.023],
        ],
        [0.035, 0.022],
    )
    .chain(&[
        (j("upper_arm"), f32::NEG_INFINITY, 0.0),
        (j("forearm"), 0.0, 0.03),
        (j("hand"), fore_len, 0.03),
    ]);
    // Hand: flat, thin across X (palm faces the thigh).
    let hand = PartSpec::between(
        side_name("hand", side),
        wrist,
        tip,
        &[
            [0.0, 0.020, 0.030],
            [0.45, 0.016, 0.045],
            [1.0, 0.012, 0.034],
        ],
        [0.015, 0.03],
    )
    .chain(&[
        (j("forearm"), f32::NEG_INFINITY, 0.0),
        (j("hand"), 0.0, 0.03),
    ]);
    vec![upper, fore, hand]
}

fn leg_parts(side: &str) -> Vec<PartSpec> {
    let j = |b| side_name(b, side);
    let (hip, knee, ankle) = (
        side_pos("thigh", side),
        side_pos("shin", side),
        side_pos("foot", side),
    );
    let at = |p: [f32; 3]| {
        if side == "l" {
            Vector3::from(p)
        } else {
            mirror(Vector3::from(p))
        }
    };
    let thigh_len = (knee - hip).norm();
    let shin_len = (ankle - knee).norm();
    let thigh = PartSpec::between(
        side_name("thigh", side),
        hip,
        knee,
        &[
            [0.0, 0.090, 0.090],
            [0.3, 0.085, 0.085],
            [1.0, 0.055, 0.058],
        ],
        [0.08, 0.05],
    )
    .chain(&[
        ("pelvis", f32::NEG_INFINITY, 0.0),
        (j("thigh"), 0.0, 0.05),
        (j("shin"), thigh_len, 0.04),
    ]);
    let shin = PartSpec::between(
        side_name("shin", side),
        knee,
        ankle,
        &[
            [0.0, 0.052, 0.055],
            [0.3, 0.055, 0.060],
            [1.0, 0.035, 0.035],
        ],
        [0.045, 0.04],
    )
    .chain(&[
        (j("thigh"), f32::NEG_INFINITY, 0.0),
        (j("shin"), 0.0, 0.04),
        (j("foot"), shin_len, 0.03),
    ]);
    // Foot: heel to ball along +Z; the toe joint sits at the ball.
    let (heel, ball, toe_tip) = (
        at([0.10, 0.055, -0.05]),
        at([0.10, 0.045, 0.125]),
        at([0.10, 0.035, 0.20]),
    );
    let ball_s = (side_pos("toe", side) - heel).dot(&(ball - heel).normalize());
    let foot = PartSpec::between(
        side_name("foot", side),
        heel,
        ball,
        &[
            [0.0, 0.040, 0.045],
            [0.5, 0.045, 0.040],
            [1.0, 0.047, 0.028],
        ],
        [0.03, 0.02],
    )
    .chain(&[
        (j("foot"), f32::NEG_INFINITY, 0.0),
        (j("toe"), ball_s, 0.03),
    ]);
    let toe = PartSpec::between(
        side_name("toe", side),
        ball,
        toe_tip,
        &[[0.0, 0.046, 0.025], [1.0, 0.040, 0.018]],
        [0.015, 0.02],
    )
    .chain(&[(j("foot"), f32::NEG_INFINITY, 0.0), (j("toe"), 0.0, 0.03)]);
    vec![thigh, shin, foot, toe]
}

// ---------------------------------------------------------------------------
// Layout: rings per part for an edge length

/// One ring: axial coordinate, semi-axes and vertex count.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Ring {
    s: f32,
    a: f32,
    b: f32,
    n: usize,
}

/// A part's rings between its two poles.
#[derive(Clone, Debug, PartialEq)]
struct Layout {
    rings: Vec<Ring>,
}

impl Layout {
    fn vertex_count(&self) -> usize {
        2 + self.rings.iter().map(|r| r.n).sum::<usize>()
    }
}

/// Samples of the meridian for arc-length resampling.
const MERIDIAN_SAMPLES: usize = 1024;

/// `(s, cumulative meridian length)` using the mean of the semi-axes.
fn meridian(spec: &PartSpec) -> Vec<(f32, f32)> {
    let (s0, s1) = spec.s_range();
    let mut out = Vec::with_capacity(MERIDIAN_SAMPLES + 1);
    let mut prev = (s0, 0.0f32);
    let mut acc = 0.0;
    for i in 0..=MERIDIAN_SAMPLES {
        // Denser near the poles, where the dome is steep.
        let x = i as f32 / MERIDIAN_SAMPLES as f32;
        let s = s0 + (s1 - s0) * (0.5 - 0.5 * (PI * x).cos());
        let (a, b) = spec.section(s);
        let r = 0.5 * (a + b);
        if i > 0 {
            acc += ((s - prev.0).powi(2) + (r - prev.1).powi(2)).sqrt();
        }
        out.push((s, acc));
        prev = (s, r);
    }
    out
}

/// Axial coordinate at meridian length `l`.
fn s_at_length(m: &[(f32, f32)], l: f32) -> f32 {
    let k = m.partition_point(|e| e.1 <= l).clamp(1, m.len() - 1);
    let (p, q) = (m[k - 1], m[k]);
    if q.1 <= p.1 {
        p.0
    } else {
        p.0 + (q.0 - p.0) * (l - p.1) / (q.1 - p.1)
    }
}

/// Ramanujan's approximation of an ellipse's perimeter.
fn ellipse_perimeter(a: f32, b: f32) -> f32 {
    PI * (3.0 * (a + b) - ((3.0 * a + b) * (a + 3.0 * b)).sqrt())
}

/// Rings of a part for target edge length `h`.
fn layout(spec: &PartSpec, m: &[(f32, f32)], h: f32) -> Layout {
    let total = m.last().unwrap().1;
    let spacing = h * 3f32.sqrt() / 2.0;
    let segments = ((total / spacing).round() as usize).max(3);
    let rings = (1..segments)
        .map(|k| {
            let s = s_at_length(m, total * k as f32 / segments as f32);
            let (a, b) = spec.section(s);
            let n = ((ellipse_perimeter(a, b) / h).round() as usize).max(3);
            Ring { s, a, b, n }
        })
        .collect();
    Layout { rings }
}

/// Layouts of all parts with exactly (or, for tiny targets, nearly) `target`
/// vertices: bisection on the edge length, then one-vertex ring adjustments.
fn fit_layout(specs: &[PartSpec], target: usize) -> Vec<Layout> {
    let meridians: Vec<_> = specs.iter().map(meridian).collect();
    let at = |h: f32| -> Vec<Layout> {
        specs
            .iter()
            .zip(&meridians)
            .map(|(s, m)| layout(s, m, h))
            .collect()
    };
    let count = |ls: &[Layout]| ls.iter().map(Layout::vertex_count).sum::<usize>();
    let (mut lo, mut hi) = (1e-4f32, 0.5f32);
    for _ in 0..60 {
        let mid = (lo * hi).sqrt();
        if count(&at(mid)) > target {
            lo = mid
        } else {
            hi = mid
        }
    }
    let (a, b) = (at(lo), at(hi));
    let mut best = if count(&a).abs_diff(target) < count(&b).abs_diff(target) {
        a
    } else {
        b
    };
    adjust_counts(&mut best, target);
    best
}

/// Adds or removes single vertices on the largest rings until `target` is met
/// (at most an eighth of a ring's count changes).
fn adjust_counts(layouts: &mut [Layout], target: usize) {
    let mut order: Vec<(usize, usize)> = layouts
        .iter()
        .enumerate()
        .flat_map(|(p, l)| (0..l.rings.len()).map(move |r| (p, r)))
        .collect();
    order.sort_by_key(|&(p, r)| (std::cmp::Reverse(layouts[p].rings[r].n), p, r));
    let original: Vec<Vec<usize>> = layouts
        .iter()
        .map(|l| l.rings.iter().map(|r| r.n).collect())
        .collect();
    let mut current: isize = layouts.iter().map(Layout::vertex_count).sum::<usize>() as isize;
    let target = target as isize;
    let mut changed = true;
    while current != target && changed {
        changed = false;
        for &(p, r) in &order {
            if current == target {
                break;
            }
            let step = (target - current).signum();
            let n0 = original[p][r] as isize;
            let n = layouts[p].rings[r].n as isize + step;
            if n >= 3 && (n - n0).abs() <= n0 / 8 {
                layouts[p].rings[r].n = n as usize;
                current += step;
                changed = true;
            }
        }
    }
}

// ---------------------------------------------------------------------------
// Surface

/// Mesh data with per-vertex influences and part ranges.
struct Surface {
    positions: Vec<Point>,
    triangles: Vec<[u32; 3]>,
    joints: Vec<[u16; 4]>,
    weights: Vec<[f32; 4]>,
    parts: Vec<BodyPart>,
}

fn build_surface(specs: &[PartSpec], layouts: &[Layout]) -> Surface {
    let mut out = Surface {
        positions: Vec::new(),
        triangles: Vec::new(),
        joints: Vec::new(),
        weights: Vec::new(),
        parts: Vec::new(),
    };
    for (spec, layout) in specs.iter().zip(layouts) {
        let (v0, t0) = (out.positions.len(), out.triangles.len());
        add_part(&mut out, spec, layout);
        out.parts.push(BodyPart {
            name: spec.name,
            vertices: v0..out.positions.len(),
            triangles: t0..out.triangles.len(),
        });
    }
    out
}

/// Appends one part: start pole, rings, end pole, and the triangles joining them.
fn add_part(out: &mut Surface, spec: &PartSpec, layout: &Layout) {
    let (s0, s1) = spec.s_range();
    let start_pole = push_vertex(out, spec, s0, spec.start + spec.axis * s0);
    let mut ring_starts = Vec::with_capacity(layout.rings.len());
    let mut offsets = Vec::with_capacity(layout.rings.len());
    for (k, ring) in layout.rings.iter().enumerate() {
        // Alternate rings shifted by half a step.
        let offset = if k % 2 == 1 { 0.5 } else { 0.0 };
        ring_starts.push(out.positions.len() as u32);
        offsets.push(offset / ring.n as f32);
        for p in ring_points(spec, ring, offset) {
            push_vertex(out, spec, ring.s, p);
        }
    }
    let end_pole = push_vertex(out, spec, s1, spec.start + spec.axis * s1);
    let rings = &layout.rings;
    let last = rings.len() - 1;
    for i in 0..rings[0].n as u32 {
        let n = rings[0].n as u32;
        out.triangles
            .push([start_pole, ring_starts[0] + (i + 1) % n, ring_starts[0] + i]);
    }
    for k in 0..last {
        let a = (ring_starts[k], rings[k].n, offsets[k]);
        let b = (ring_starts[k + 1], rings[k + 1].n, offsets[k + 1]);
        zip_rings(&mut out.triangles, a, b);
    }
    for i in 0..rings[last].n as u32 {
        let n = rings[last].n as u32;
        out.triangles.push([
            end_pole,
            ring_starts[last] + i,
            ring_starts[last] + (i + 1) % n,
        ]);
    }
}

fn push_vertex(out: &mut Surface, spec: &PartSpec, s: f32, p: Vector3<f32>) -> u32 {
    let (j, w) = spec.weights(s);
    out.positions.push(Point::from(p));
    out.joints.push(j);
    out.weights.push(w);
    out.positions.len() as u32 - 1
}

/// Samples per ring for spacing vertices evenly in arc length.
const RING_SAMPLES: usize = 256;

/// `n` points on a ring, evenly spaced in arc length, starting `offset` steps
/// past angle 0.
fn ring_points(spec: &PartSpec, ring: &Ring, offset: f32) -> Vec<Vector3<f32>> {
    let centre = spec.start + spec.axis * ring.s;
    let (u, v) = (spec.u, spec.v());
    let at = |phi: f32| u * (ring.a * phi.cos()) + v * (ring.b * phi.sin());
    // Cumulative arc length at RING_SAMPLES even angles.
    let mut cum = Vec::with_capacity(RING_SAMPLES + 1);
    let mut acc = 0.0;
    cum.push(0.0);
    for i in 1..=RING_SAMPLES {
        let (p, q) = (
            at(TAU * (i - 1) as f32 / RING_SAMPLES as f32),
            at(TAU * i as f32 / RING_SAMPLES as f32),
        );
        acc += (q - p).norm();
        cum.push(acc);
    }
    (0..ring.n)
        .map(|i| {
            let l = acc * (i as f32 + offset) / ring.n as f32;
            let k = cum.partition_point(|&c| c <= l).clamp(1, RING_SAMPLES);
            let t = if cum[k] > cum[k - 1] {
                (l - cum[k - 1]) / (cum[k] - cum[k - 1])
            } else {
                0.0
            };
            let phi = TAU * ((k - 1) as f32 + t) / RING_SAMPLES as f32;
            centre + at(phi)
        })
        .collect()
}

/// Triangulates the band between two rings `(first index, count, fraction
/// offset)` by walking both in order of arc-length fraction: `na + nb`
/// triangles, every ring edge used once, outward facing when `b` follows `a`.
fn zip_rings(tris: &mut Vec<[u32; 3]>, a: (u32, usize, f32), b: (u32, usize, f32)) {
    let (sa, na, oa) = a;
    let (sb, nb, ob) = b;
    let frac = |i: usize, n: usize, o: f32| i as f32 / n as f32 + o;
    let (mut i, mut j) = (0usize, 0usize);
    while i < na || j < nb {
        let advance_a = j == nb || (i < na && frac(i + 1, na, oa) <= frac(j + 1, nb, ob));
        let (ai, bj) = (sa + (i % na) as u32, sb + (j % nb) as u32);
        if advance_a {
            tris.push([ai, sa + ((i + 1) % na) as u32, bj]);
            i += 1;
        } else {
            tris.push([ai, sb + ((j + 1) % nb) as u32, bj]);
            j += 1;
        }
    }
}

// ---------------------------------------------------------------------------
// Clips

/// SplitMix64: small, seedable, deterministic.
struct SplitMix(u64);

impl SplitMix {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next() >> 40) as f32 / (1u64 << 24) as f32)
    }

    /// `1 ± spread`.
    fn factor(&mut self, spread: f32) -> f32 {
        self.range(1.0 - spread, 1.0 + spread)
    }
}

/// Evenly spaced key times over `duration` at about [`KEYS_PER_SECOND`].
fn key_times(duration: f32) -> Vec<f32> {
    let n = ((duration * KEYS_PER_SECOND).round() as usize).max(1);
    (0..=n).map(|i| duration * i as f32 / n as f32).collect()
}

/// Rotation about X (pitch), then Y (yaw) and Z (roll) on top: `Ry·Rx·Rz`.
fn rot(pitch: f32, yaw: f32, roll: f32) -> UnitQuaternion<f32> {
    UnitQuaternion::from_axis_angle(&Vector3::y_axis(), yaw)
        * UnitQuaternion::from_axis_angle(&Vector3::x_axis(), pitch)
        * UnitQuaternion::from_axis_angle(&Vector3::z_axis(), roll)
}

/// A LINEAR rotation channel sampled from `f` (kept in one hemisphere).
fn rotation_channel(
    s: &Skeleton,
    joint: &str,
    times: &[f32],
    f: impl Fn(f32) -> UnitQuaternion<f32>,
) -> Channel {
    let mut values: Vec<Quaternion<f32>> = Vec::with_capacity(times.len());
    for &t in times {
        let mut q = *f(t).quaternion();
        if values.last().is_some_and(|p| p.dot(&q) < 0.0) {
            q = -q;
        }
        values.push(q);
    }
    channel(s, joint, times, ChannelValues::Rotation(values))
}

/// A LINEAR translation channel for `joint` sampled from `f`.
fn translation_channel(
    s: &Skeleton,
    joint: &str,
    times: &[f32],
    f: impl Fn(f32) -> Vector3<f32>,
) -> Channel {
    channel(
        s,
        joint,
        times,
        ChannelValues::Translation(times.iter().map(|&t| f(t)).collect()),
    )
}

fn channel(s: &Skeleton, joint: &str, times: &[f32], values: ChannelValues) -> Channel {
    let joint = s.find(joint).unwrap_or_else(|| panic!("no joint {joint}"));
    Channel {
        joint,
        interpolation: Interpolation::Linear,
        times: times.to_vec(),
        values,
    }
}

fn clips(s: &Skeleton, seed: u64) -> Result<Vec<Clip>, ChannelError> {
    let mut rng = SplitMix(seed ^ 0x6875_6D61_6E6F_6964);
    Ok(vec![
        walk(s, &mut rng)?,
        reach(s, &mut rng)?,
        turn(s, &mut rng)?,
        hand_to_hip(s, &mut rng)?,
        arms_crossed(s, &mut rng)?,
        squat(s, &mut rng)?,
        swing_through(s, &mut rng)?,
    ])
}

/// Flexion signs: hips and shoulders flex forward with a negative X rotation,
/// knees bend back with a positive one, elbows forward with a negative one.
fn walk(s: &Skeleton, rng: &mut SplitMix) -> Result<Clip, ChannelError> {
    let period = rng.range(1.0, 1.2);
    let hip = 0.45 * rng.factor(0.1);
    let knee = 0.65 * rng.factor(0.1);
    let arm = 0.35 * rng.factor(0.15);
    let lag = rng.range(-0.15, 0.15);
    let stride = 1.35 * period * rng.factor(0.05);
    let times = key_times(period);
    let ph = move |t: f32| TAU * t / period;
    let pelvis_rest = s.joint(JointId(0)).rest.translation;
    let mut ch = vec![
        translation_channel(s, "pelvis", &times, |t| {
            pelvis_rest + Vector3::new(0.0, 0.02 * (2.0 * ph(t)).cos() - 0.02, stride * t / period)
        }),
        rotation_channel(s, "pelvis", &times, |t| {
            rot(0.0, 0.08 * ph(t).sin(), 0.03 * ph(t).sin())
        }),
        rotation_channel(s, "chest", &times, |t| rot(0.04, -0.12 * ph(t).sin(), 0.0)),
        rotation_channel(s, "head", &times, |t| rot(0.0, 0.04 * ph(t).sin(), 0.0)),
    ];
    for (side, shift) in [("l", 0.0), ("r", PI)] {
        let q = move |t: f32| ph(t) + shift;
        ch.push(rotation_channel(s, &format!("thigh_{side}"), &times, |t| {
            rot(-hip * q(t).sin(), 0.0, 0.0)
        }));
        // The knee bends most mid-swing, when the hip swings forward.
        ch.push(rotation_channel(s, &format!("shin_{side}"), &times, |t| {
            rot(0.08 + knee * (q(t) + lag).cos().max(0.0).powi(2), 0.0, 0.0)
        }));
        ch.push(rotation_channel(s, &format!("foot_{side}"), &times, |t| {
            rot(0.15 * q(t).sin(), 0.0, 0.0)
        }));
        // Arms swing against the leg of the same side.
        ch.push(rotation_channel(
            s,
            &format!("upper_arm_{side}"),
            &times,
            |t| rot(arm * q(t).sin(), 0.0, 0.0),
        ));
        ch.push(rotation_channel(
            s,
            &format!("forearm_{side}"),
            &times,
            |t| rot(-0.25 - 0.12 * (q(t) + PI).sin(), 0.0, 0.0),
        ));
    }
    Clip::new("walk".into(), ch, s.len())
}

/// Rise to 1 over `[0, up]`, hold, fall back to 0 over `[down, end]`.
fn envelope(t: f32, up: f32, down: f32, end: f32) -> f32 {
    if t < down {
        smoothstep(t / up)
    } else {
        1.0 - smoothstep((t - down) / (end - down))
    }
}

fn reach(s: &Skeleton, rng: &mut SplitMix) -> Result<Clip, ChannelError> {
    let end = 2.0 * rng.factor(0.1);
    let (up, down) = (0.4 * end, 0.6 * end);
    let lift = 1.45 * rng.factor(0.05);
    let twist = 0.25 * rng.factor(0.2);
    let times = key_times(end);
    let e = move |t: f32| envelope(t, up, down, end);
    let ch = vec![
        // Turn the torso so the right shoulder comes forward, lean a little.
        rotation_channel(s, "spine_01", &times, |t| {
            rot(0.04 * e(t), 0.4 * twist * e(t), 0.0)
        }),
        rotation_channel(s, "spine_02", &times, |t| {
            rot(0.04 * e(t), 0.3 * twist * e(t), 0.0)
        }),
        rotation_channel(s, "chest", &times, |t| {
            rot(0.06 * e(t), 0.3 * twist * e(t), 0.0)
        }),
        rotation_channel(s, "head", &times, |t| {
            rot(0.1 * e(t), 0.5 * twist * e(t), 0.0)
        }),
        rotation_channel(s, "clavicle_r", &times, |t| rot(0.0, -0.15 * e(t), 0.0)),
        // Raise the right arm forward, bend the elbow on the way, palm to the wall.
        rotation_channel(s, "upper_arm_r", &times, |t| {
            rot(-lift * e(t), 0.0, -0.1 * e(t))
        }),
        rotation_channel(s, "forearm_r", &times, |t| {
            rot(-0.5 * (PI * e(t)).sin(), 0.0, 0.0)
        }),
        rotation_channel(s, "hand_r", &times, |t| rot(0.6 * e(t), 0.0, 0.0)),
    ];
    Clip::new("reach".into(), ch, s.len())
}

fn turn(s: &Skeleton, rng: &mut SplitMix) -> Result<Clip, ChannelError> {
    let end = 1.5 * rng.factor(0.1);
    let angle = FRAC_PI_2 * rng.factor(0.05);
    let step = 0.35 * rng.factor(0.1);
    let times = key_times(end);
    let u = move |t: f32| t / end;
    // One step per leg: left in the first half, right in the second.
    let bump = move |x: f32| {
        if (0.0..=1.0).contains(&x) {
            (PI * x).sin().powi(2)
        } else {
            0.0
        }
    };
    let ch = vec![
        rotation_channel(s, "pelvis", &times, |t| {
            rot(0.0, angle * smoothstep(u(t)), 0.0)
        }),
        rotation_channel(s, "head", &times, |t| {
            rot(0.0, 0.2 * angle * bump(u(t)), 0.0)
        }),
        rotation_channel(s, "thigh_l", &times, |t| {
            rot(-step * bump(2.0 * u(t)), -0.3 * bump(2.0 * u(t)), 0.0)
        }),
        rotation_channel(s, "shin_l", &times, |t| {
            rot(2.0 * step * bump(2.0 * u(t)), 0.0, 0.0)
        }),
        rotation_channel(s, "thigh_r", &times, |t| {
            rot(
                -step * bump(2.0 * u(t) - 1.0),
                0.3 * bump(2.0 * u(t) - 1.0),
                0.0,
            )
        }),
        rotation_channel(s, "shin_r", &times, |t| {
            rot(2.0 * step * bump(2.0 * u(t) - 1.0), 0.0, 0.0)
        }),
        rotation_channel(s, "upper_arm_l", &times, |t| {
            rot(0.1 * bump(u(t)), 0.0, 0.0)
        }),
        rotation_channel(s, "upper_arm_r", &times, |t| {
            rot(-0.1 * bump(u(t)), 0.0, 0.0)
        }),
    ];
    Clip::new("turn".into(), ch, s.len())
}

/// The right arm drawn in and back until the hand and forearm press the
/// hip and thigh; hold; back.
fn hand_to_hip(s: &Skeleton, rng: &mut SplitMix) -> Result<Clip, ChannelError> {
    let end = 2.0 * rng.factor(0.1);
    let (up, down) = (0.35 * end, 0.65 * end);
    let inward = 0.32 * rng.factor(0.05);
    let times = key_times(end);
    let e = move |t: f32| envelope(t, up, down, end);
    let ch = vec![
        // Positive roll swings a hanging right arm towards +X, the body.
        rotation_channel(s, "upper_arm_r", &times, |t| {
            rot(0.12 * e(t), 0.0, inward * e(t))
        }),
        rotation_channel(s, "forearm_r", &times, |t| {
            rot(-0.35 * e(t), 0.0, 0.15 * e(t))
        }),
        rotation_channel(s, "hand_r", &times, |t| rot(0.0, 0.0, 0.3 * e(t))),
    ];
    Clip::new("hand-to-hip".into(), ch, s.len())
}

/// Both forearms folded across the chest, the left a little higher, so
/// they cross each other in front of the body; hold; back.
fn arms_crossed(s: &Skeleton, rng: &mut SplitMix) -> Result<Clip, ChannelError> {
    let end = 2.2 * rng.factor(0.1);
    let (up, down) = (0.35 * end, 0.65 * end);
    let fold = 1.5 * rng.factor(0.03);
    let across = 1.05 * rng.factor(0.05);
    let times = key_times(end);
    let e = move |t: f32| envelope(t, up, down, end);
    let mut ch = Vec::new();
    for (side, sign, lift) in [("l", -1.0f32, 0.4f32), ("r", 1.0, 0.28)] {
        ch.push(rotation_channel(
            s,
            &format!("upper_arm_{side}"),
            &times,
            |t| rot(-lift * e(t), 0.0, sign * 0.08 * e(t)),
        ));
        // Flexed forward, then turned about the vertical to point across.
        ch.push(rotation_channel(
            s,
            &format!("forearm_{side}"),
            &times,
            |t| rot(-fold * e(t), sign * across * e(t), 0.0),
        ));
    }
    Clip::new("arms-crossed".into(), ch, s.len())
}

/// Down into a deep squat (hips flexed past the horizontal, knees folded
/// until calves press thighs, torso leaning and arms reaching forward for
/// balance), hold, and up.
fn squat(s: &Skeleton, rng: &mut SplitMix) -> Result<Clip, ChannelError> {
    let end = 2.4 * rng.factor(0.1);
    let (up, down) = (0.4 * end, 0.6 * end);
    let hip = 1.85 * rng.factor(0.03);
    let knee = 2.35 * rng.factor(0.02);
    let times = key_times(end);
    let e = move |t: f32| envelope(t, up, down, end);
    // The pelvis drops by what the folded legs lose in height (thigh and
    // shin lengths from the rest skeleton), with the shin's absolute angle
    // `knee − hip` back from vertical.
    let thigh = (joint_pos("thigh_l") - joint_pos("shin_l")).norm();
    let shin = (joint_pos("shin_l") - joint_pos("foot_l")).norm();
    let pelvis_rest = s.joint(JointId(0)).rest.translation;
    let drop = move |x: f32| {
        let (h, k) = (hip * x, knee * x);
        thigh + shin - (thigh * h.cos() + shin * (k - h).cos())
    };
    let mut ch = vec![
        translation_channel(s, "pelvis", &times, |t| {
            pelvis_rest + Vector3::new(0.0, -drop(e(t)), -0.1 * e(t))
        }),
        rotation_channel(s, "spine_01", &times, |t| rot(0.35 * e(t), 0.0, 0.0)),
        rotation_channel(s, "chest", &times, |t| rot(0.2 * e(t), 0.0, 0.0)),
    ];
    for side in ["l", "r"] {
        ch.push(rotation_channel(s, &format!("thigh_{side}"), &times, |t| {
            rot(-hip * e(t), 0.0, 0.0)
        }));
        ch.push(rotation_channel(s, &format!("shin_{side}"), &times, |t| {
            rot(knee * e(t), 0.0, 0.0)
        }));
        // Keeps the sole flat: the shin leans `knee − hip` back.
        ch.push(rotation_channel(s, &format!("foot_{side}"), &times, |t| {
            rot((hip - knee) * e(t), 0.0, 0.0)
        }));
        ch.push(rotation_channel(
            s,
            &format!("upper_arm_{side}"),
            &times,
            |t| rot(-1.3 * e(t), 0.0, 0.0),
        ));
    }
    Clip::new("squat".into(), ch, s.len())
}

/// The right arm raised forward to the horizontal, then swept sideways
/// through the chest and out at the back within half a second (no body
/// would, a bad blend of clips can), then held there.
fn swing_through(s: &Skeleton, rng: &mut SplitMix) -> Result<Clip, ChannelError> {
    let end = 1.0 * rng.factor(0.05);
    let times = key_times(end);
    let raise = move |t: f32| smoothstep((t / (0.3 * end)).min(1.0));
    // Positive yaw turns a right arm pointing forward (+Z) towards +X,
    // across the body.
    let sweep = move |t: f32| smoothstep(((t - 0.35 * end) / (0.5 * end)).clamp(0.0, 1.0));
    let ch = vec![rotation_channel(s, "upper_arm_r", &times, |t| {
        rot(-1.5 * raise(t), -0.6 + 3.0 * sweep(t), 0.0)
    })];
    Clip::new("swing-through".into(), ch, s.len())
}
