//! Shapes, the tessellation plan that meets a vertex target, and the mesh builder
//! shared by the generated rooms.
//!
//! A room is a [`Layout`]: named objects, each a list of [`Shape`]s. Coarse
//! shapes (polygons, cuboids) have a fixed vertex count. Fine shapes are
//! *sweeps* (a stack of superellipse sections along a local Y axis, each
//! section a ring of vertices, closed by single pole vertices where a section
//! has zero size) and tori; their resolution follows one edge length `h`.
//! [`fit`] finds the `h` whose vertex count comes closest below the target,
//! then adds the remaining vertices one per ring to the largest rings, so the
//! target is met exactly. Neighbouring rings of different counts are joined
//! by walking both in order of arc-length fraction, so every triangle has two
//! corners on one ring and one on the other and none has zero area.

use std::f32::consts::{FRAC_PI_2, TAU};

use nalgebra::{Isometry3, Translation3, UnitQuaternion};

use super::{EnvObject, Environment, EnvironmentError, ObjectKind, RigidMotion};
use cornertree::geometry::{Point, Vector};
use cornertree::mesh::TriMesh;

/// Most vertices a generated room may have.
pub const MAX_VERTICES: usize = 20_000_000;

/// SplitMix64, as in the humanoid generator: small, seedable, deterministic.
pub(crate) struct SplitMix(u64);

impl SplitMix {
    pub(crate) fn new(seed: u64) -> Self {
        Self(seed)
    }

    pub(crate) fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// Uniform in `[lo, hi)`.
    pub(crate) fn range(&mut self, lo: f32, hi: f32) -> f32 {
        lo + (hi - lo) * ((self.next() >> 40) as f32 / (1u64 << 24) as f32)
    }

    /// `1 ± spread`.
    pub(crate) fn factor(&mut self, spread: f32) -> f32 {
        self.range(1.0 - spread, 1.0 + spread)
    }

    /// Uniform in `0..n` (`n > 0`).
    pub(crate) fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    /// Fisher–Yates.
    pub(crate) fn shuffle<T>(&mut self, items: &mut [T]) {
        for i in (1..items.len()).rev() {
            items.swap(i, self.below(i + 1));
        }
    }
}

/// One section of a sweep: at height `y` along the local axis, the
/// superellipse `|x/a|^p + |z/b|^p = 1` (`p = 2` is an ellipse, larger is
/// boxier). `a = b = 0` is a pole, allowed only first or last.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Section {
    pub y: f32,
    pub a: f32,
    pub b: f32,
    pub p: f32,
}

impl Section {
    pub(crate) fn new(y: f32, a: f32, b: f32, p: f32) -> Self {
        Self { y, a, b, p }
    }

    pub(crate) fn round(y: f32, r: f32) -> Self {
        Self::new(y, r, r, 2.0)
    }

    pub(crate) fn pole(y: f32) -> Self {
        Self::new(y, 0.0, 0.0, 2.0)
    }

    fn is_pole(&self) -> bool {
        self.a == 0.0 && self.b == 0.0
    }

    fn lerp(&self, o: &Self, t: f32) -> Self {
        let l = |x: f32, y: f32| x + (y - x) * t;
        Self::new(
            l(self.y, o.y),
            l(self.a, o.a),
            l(self.b, o.b),
            l(self.p, o.p),
        )
    }
}

/// A piece of geometry of an object.
#[derive(Clone, Debug)]
pub(crate) enum Shape {
    /// Fixed corners and triangles (local indices): walls, floors, panes.
    Polygon {
        points: Vec<Point>,
        triangles: Vec<[u32; 3]>,
    },
    /// A box of half extents `half` placed by `pose` (8 vertices, 12 triangles).
    Cuboid { pose: Isometry3<f32>, half: Vector },
    /// Sections along the local Y axis, placed by `pose`.
    Sweep {
        pose: Isometry3<f32>,
        keys: Vec<Section>,
    },
    /// A torus about the local Y axis.
    Torus {
        pose: Isometry3<f32>,
        major: f32,
        minor: f32,
    },
}

/// A named object of a layout.
#[derive(Clone, Debug)]
pub(crate) struct ObjectSpec {
    pub name: String,
    pub kind: ObjectKind,
    pub motion: Option<RigidMotion>,
    pub shapes: Vec<Shape>,
}

/// A room before tessellation.
#[derive(Clone, Debug, Default)]
pub(crate) struct Layout {
    pub name: String,
    pub objects: Vec<ObjectSpec>,
}

impl Layout {
    pub(crate) fn new(name: String) -> Self {
        Self {
            name,
            objects: Vec::new(),
        }
    }

    pub(crate) fn add(&mut self, name: impl Into<String>, kind: ObjectKind, shapes: Vec<Shape>) {
        self.objects.push(ObjectSpec {
            name: name.into(),
            kind,
            motion: None,
            shapes,
        });
    }

    pub(crate) fn add_moving(
        &mut self,
        name: impl Into<String>,
        kind: ObjectKind,
        motion: RigidMotion,
        shapes: Vec<Shape>,
    ) {
        self.objects.push(ObjectSpec {
            name: name.into(),
            kind,
            motion: Some(motion),
            shapes,
        });
    }
}

// ---------------------------------------------------------------------------
// Shape helpers

/// The quad `a b c d` (in order around it) as two triangles.
/// Shorthand for a point in room coordinates.
pub(crate) fn p(x: f32, y: f32, z: f32) -> Point {
    Point::new(x, y, z)
}

/// Shorthand for a vector in room coordinates.
pub(crate) fn v(x: f32, y: f32, z: f32) -> Vector {
    Vector::new(x, y, z)
}

/// The parts every room shares: the floor, the ceiling and the plain south
/// wall (`z = 0`) the free corridor runs along, for a `w × d × h` room.
pub(crate) fn add_shell(l: &mut Layout, w: f32, d: f32, h: f32) {
    l.add(
        "floor",
        ObjectKind::Floor,
        vec![quad(p(0., 0., 0.), p(0., 0., d), p(w, 0., d), p(w, 0., 0.))],
    );
    l.add(
        "ceiling",
        ObjectKind::Ceiling,
        vec![quad(p(0., h, 0.), p(w, h, 0.), p(w, h, d), p(0., h, d))],
    );
    l.add(
        "south wall",
        ObjectKind::Wall,
        vec![quad(p(0., 0., 0.), p(w, 0., 0.), p(w, h, 0.), p(0., h, 0.))],
    );
}

pub(crate) fn quad(a: Point, b: Point, c: Point, d: Point) -> Shape {
    Shape::Polygon {
        points: vec![a, b, c, d],
        triangles: vec![[0, 1, 2], [0, 2, 3]],
    }
}

/// An axis-aligned (up to `yaw` about Y) box centred at `center`.
pub(crate) fn cuboid(center: Point, half: Vector, yaw: f32) -> Shape {
    Shape::Cuboid {
        pose: upright(center, yaw),
        half,
    }
}

/// The local axis vertical, turned by `yaw` about it, origin at `at`.
pub(crate) fn upright(at: Point, yaw: f32) -> Isometry3<f32> {
    Isometry3::new(at.coords, Vector::y() * yaw)
}

/// The local axis horizontal: along world X when `yaw = 0`, then turned by
/// `yaw` about the vertical. The section's `a` is then vertical, `b` horizontal.
pub(crate) fn lying(at: Point, yaw: f32) -> Isometry3<f32> {
    let r = UnitQuaternion::from_axis_angle(&Vector::y_axis(), yaw)
        * UnitQuaternion::from_axis_angle(&Vector::z_axis(), -FRAC_PI_2);
    Isometry3::from_parts(Translation3::from(at.coords), r)
}

/// The local axis along `dir` (any non-zero direction), then turned by `roll` about it.
pub(crate) fn along(at: Point, dir: Vector, roll: f32) -> Isometry3<f32> {
    let d = dir.normalize();
    let r = UnitQuaternion::rotation_between(&Vector::y(), &d).unwrap_or_else(|| {
        UnitQuaternion::from_axis_angle(&Vector::x_axis(), std::f32::consts::PI)
    });
    let r = r * UnitQuaternion::from_axis_angle(&Vector::y_axis(), roll);
    Isometry3::from_parts(Translation3::from(at.coords), r)
}

pub(crate) fn sweep(pose: Isometry3<f32>, keys: Vec<Section>) -> Shape {
    Shape::Sweep { pose, keys }
}

/// Ellipsoid of semi-axes `rx`, `ry` (along the axis), `rz`, centred on the origin,
/// with section exponent `p`.
pub(crate) fn ellipsoid_keys(rx: f32, ry: f32, rz: f32, p: f32) -> Vec<Section> {
    const K: usize = 12;
    (0..=K)
        .map(|i| {
            let phi = -FRAC_PI_2 + std::f32::consts::PI * i as f32 / K as f32;
            if i == 0 || i == K {
                Section::new(ry * phi.sin(), 0.0, 0.0, p)
            } else {
                Section::new(ry * phi.sin(), rx * phi.cos(), rz * phi.cos(), p)
            }
        })
        .collect()
}

/// A rounded bar of length `len` along the axis (centred), sections `a × b` with
/// exponent `p`, ends domed to depth `end`.
pub(crate) fn capsule_keys(len: f32, a: f32, b: f32, p: f32, end: f32) -> Vec<Section> {
    let half = 0.5 * len;
    let end = end.min(half);
    let mut keys = Vec::with_capacity(10);
    let dome = [0.0f32, 30.0, 55.0, 75.0];
    for &deg in &dome {
        let phi = deg.to_radians();
        let s = phi.sin();
        let y = -half + end * (1.0 - phi.cos());
        keys.push(if deg == 0.0 {
            Section::new(y, 0.0, 0.0, p)
        } else {
            Section::new(y, a * s, b * s, p)
        });
    }
    keys.push(Section::new(-half + end, a, b, p));
    keys.push(Section::new(half - end, a, b, p));
    for &deg in dome.iter().rev() {
        let phi = deg.to_radians();
        let s = phi.sin();
        let y = half - end * (1.0 - phi.cos());
        keys.push(if deg == 0.0 {
            Section::new(y, 0.0, 0.0, p)
        } else {
            Section::new(y, a * s, b * s, p)
        });
    }
    keys
}

/// A round solid of revolution through `(y, r)` profile points, closed by poles
/// at the first and last heights.
pub(crate) fn lathe_keys(profile: &[(f32, f32)]) -> Vec<Section> {
    let mut keys = Vec::with_capacity(profile.len() + 2);
    keys.push(Section::pole(profile[0].0));
    keys.extend(profile.iter().map(|&(y, r)| Section::round(y, r)));
    keys.push(Section::pole(profile[profile.len() - 1].0));
    keys
}

/// A closed cylinder of radius `r` from `y0` to `y1`.
pub(crate) fn cylinder_keys(y0: f32, y1: f32, r: f32) -> Vec<Section> {
    lathe_keys(&[(y0, r), (y1, r)])
}

// ---------------------------------------------------------------------------
// The plan: how many vertices each ring gets for an edge length h.

#[derive(Clone, Debug)]
struct Ring {
    section: Section,
    count: usize,
}

#[derive(Clone, Debug)]
enum ShapePlan {
    Fixed,
    Sweep(Vec<Ring>),
    Torus(usize, usize),
}

/// Perimeter of the superellipse of a section (polyline of 32 chords).
fn perimeter(s: &Section) -> f32 {
    const M: usize = 32;
    let mut last = superellipse(s, 0.0);
    let mut total = 0.0;
    for k in 1..=M {
        let q = superellipse(s, TAU * k as f32 / M as f32);
        total += (q - last).norm();
        last = q;
    }
    total
}

/// Point of the section's superellipse at parameter angle `theta` (local x, z).
fn superellipse(s: &Section, theta: f32) -> nalgebra::Vector2<f32> {
    let e = 2.0 / s.p;
    let (sin, cos) = theta.sin_cos();
    nalgebra::Vector2::new(
        s.a * cos.signum() * cos.abs().powf(e),
        s.b * sin.signum() * sin.abs().powf(e),
    )
}

fn ring_count(s: &Section, h: f32) -> usize {
    if s.is_pole() {
        1
    } else {
        ((perimeter(s) / h).round() as usize).max(3)
    }
}

/// Rings of a sweep: every key, plus enough in between that neighbouring rings
/// are about `0.866·h` apart along the meridian.
fn plan_sweep(keys: &[Section], h: f32) -> Vec<Ring> {
    let mut rings = Vec::new();
    let push = |rings: &mut Vec<Ring>, s: Section| {
        rings.push(Ring {
            count: ring_count(&s, h),
            section: s,
        })
    };
    push(&mut rings, keys[0]);
    for w in keys.windows(2) {
        let (p, q) = (w[0], w[1]);
        let radial = (q.a - p.a).abs().max((q.b - p.b).abs());
        let len = (q.y - p.y).hypot(radial);
        if len == 0.0 {
            continue;
        }
        let steps = ((len / (0.866 * h)).ceil() as usize).clamp(1, 1 << 20);
        for j in 1..=steps {
            push(&mut rings, p.lerp(&q, j as f32 / steps as f32));
        }
    }
    rings
}

fn torus_counts(major: f32, minor: f32, h: f32) -> (usize, usize) {
    let nu = ((TAU * major / h).round() as usize).max(3);
    let nv = ((TAU * minor / h).round() as usize).max(3);
    (nu, nv)
}

type Plan = Vec<Vec<ShapePlan>>;

fn plan(layout: &Layout, h: f32) -> (Plan, usize) {
    let mut total = 0;
    let plan = layout
        .objects
        .iter()
        .map(|o| {
            o.shapes
                .iter()
                .map(|s| match s {
                    Shape::Polygon { points, .. } => {
                        total += points.len();
                        ShapePlan::Fixed
                    }
                    Shape::Cuboid { .. } => {
                        total += 8;
                        ShapePlan::Fixed
                    }
                    Shape::Sweep { keys, .. } => {
                        let rings = plan_sweep(keys, h);
                        total += rings.iter().map(|r| r.count).sum::<usize>();
                        ShapePlan::Sweep(rings)
                    }
                    Shape::Torus { major, minor, .. } => {
                        let (nu, nv) = torus_counts(*major, *minor, h);
                        total += nu * nv;
                        ShapePlan::Torus(nu, nv)
                    }
                })
                .collect()
        })
        .collect();
    (plan, total)
}

/// Tessellates `layout` to exactly `target` vertices.
pub(crate) fn fit(layout: &Layout, target: usize) -> Result<Environment, EnvironmentError> {
    const COARSEST: f32 = 1.0e3;
    let (_, min) = plan(layout, COARSEST);
    if target < min || target > MAX_VERTICES {
        return Err(EnvironmentError::VertexCount {
            requested: target,
            min,
            max: MAX_VERTICES,
        });
    }
    // lo: too many vertices; hi: at most target.
    let mut hi = COARSEST;
    let mut lo = 0.1;
    while plan(layout, lo).1 <= target {
        hi = lo;
        lo *= 0.5;
        if lo < 1.0e-5 {
            return Err(EnvironmentError::VertexCount {
                requested: target,
                min,
                max: MAX_VERTICES,
            });
        }
    }
    for _ in 0..48 {
        let mid = (lo * hi).sqrt();
        if plan(layout, mid).1 > target {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    let (mut plan, count) = plan(layout, hi);
    let mut deficit = target - count;
    // The largest rings (first come first on ties) take one more vertex each.
    let mut rings: Vec<(usize, usize, usize, usize)> = Vec::new();
    for (o, shapes) in plan.iter().enumerate() {
        for (s, sp) in shapes.iter().enumerate() {
            if let ShapePlan::Sweep(rs) = sp {
                for (r, ring) in rs.iter().enumerate() {
                    if ring.count >= 3 {
                        rings.push((ring.count, o, s, r));
                    }
                }
            }
        }
    }
    rings.sort_by(|x, y| y.0.cmp(&x.0).then((x.1, x.2, x.3).cmp(&(y.1, y.2, y.3))));
    if deficit > 0 && rings.is_empty() {
        return Err(EnvironmentError::VertexCount {
            requested: target,
            min,
            max: MAX_VERTICES,
        });
    }
    while deficit > 0 {
        for &(_, o, s, r) in &rings {
            if deficit == 0 {
                break;
            }
            if let ShapePlan::Sweep(rs) = &mut plan[o][s] {
                rs[r].count += 1;
                deficit -= 1;
            }
        }
    }
    Ok(build(layout, &plan))
}

// ---------------------------------------------------------------------------
// Building

fn build(layout: &Layout, plan: &Plan) -> Environment {
    let mut positions: Vec<Point> = Vec::new();
    let mut triangles: Vec<[u32; 3]> = Vec::new();
    let mut objects = Vec::with_capacity(layout.objects.len());
    for (spec, shape_plans) in layout.objects.iter().zip(plan) {
        let (v0, t0) = (positions.len() as u32, triangles.len() as u32);
        for (shape, sp) in spec.shapes.iter().zip(shape_plans) {
            let base = positions.len() as u32;
            match (shape, sp) {
                (
                    Shape::Polygon {
                        points,
                        triangles: tris,
                    },
                    _,
                ) => {
                    positions.extend_from_slice(points);
                    triangles.extend(tris.iter().map(|t| t.map(|i| base + i)));
                }
                (Shape::Cuboid { pose, half }, _) => {
                    for k in 0..8u32 {
                        let sx = if k & 1 == 0 { -1.0 } else { 1.0 };
                        let sy = if k & 2 == 0 { -1.0 } else { 1.0 };
                        let sz = if k & 4 == 0 { -1.0 } else { 1.0 };
                        positions.push(pose * Point::new(sx * half.x, sy * half.y, sz * half.z));
                    }
                    // Faces -x, +x, -y, +y, -z, +z as quads of corner bits.
                    const FACES: [[u32; 4]; 6] = [
                        [0, 4, 6, 2],
                        [1, 3, 7, 5],
                        [0, 1, 5, 4],
                        [2, 6, 7, 3],
                        [0, 2, 3, 1],
                        [4, 5, 7, 6],
                    ];
                    for f in FACES {
                        triangles.push([base + f[0], base + f[1], base + f[2]]);
                        triangles.push([base + f[0], base + f[2], base + f[3]]);
                    }
                }
                (Shape::Sweep { pose, .. }, ShapePlan::Sweep(rings)) => {
                    build_sweep(pose, rings, &mut positions, &mut triangles);
                }
                (Shape::Torus { pose, major, minor }, ShapePlan::Torus(nu, nv)) => {
                    build_torus(
                        pose,
                        *major,
                        *minor,
                        *nu,
                        *nv,
                        &mut positions,
                        &mut triangles,
                    );
                }
                _ => unreachable!("plan and layout disagree"),
            }
        }
        objects.push(EnvObject {
            name: spec.name.clone(),
            kind: spec.kind,
            vertices: v0..positions.len() as u32,
            triangles: t0..triangles.len() as u32,
            motion: spec.motion,
        });
    }
    let mesh = TriMesh::new(positions, triangles).expect("generated rooms are valid meshes");
    Environment {
        name: layout.name.clone(),
        mesh,
        objects,
    }
}

/// `count` points spread evenly in arc length around the section, starting at
/// fraction `offset / count`.
fn ring_points(s: &Section, count: usize, offset: f32, out: &mut Vec<nalgebra::Vector2<f32>>) {
    out.clear();
    if count == 1 {
        out.push(nalgebra::Vector2::zeros());
        return;
    }
    let m = (4 * count).max(128);
    let samples: Vec<_> = (0..=m)
        .map(|k| superellipse(s, TAU * k as f32 / m as f32))
        .collect();
    let mut cumulative = Vec::with_capacity(m + 1);
    let mut total = 0.0;
    cumulative.push(0.0);
    for w in samples.windows(2) {
        total += (w[1] - w[0]).norm();
        cumulative.push(total);
    }
    let mut k = 0;
    for j in 0..count {
        let target = total * (j as f32 + offset) / count as f32;
        while k + 1 < m && cumulative[k + 1] < target {
            k += 1;
        }
        let span = cumulative[k + 1] - cumulative[k];
        let t = if span > 0.0 {
            ((target - cumulative[k]) / span).clamp(0.0, 1.0)
        } else {
            0.0
        };
        out.push(samples[k] + (samples[k + 1] - samples[k]) * t);
    }
}

fn build_sweep(
    pose: &Isometry3<f32>,
    rings: &[Ring],
    positions: &mut Vec<Point>,
    triangles: &mut Vec<[u32; 3]>,
) {
    let mut points = Vec::new();
    let mut previous: Option<(u32, usize, f32)> = None;
    for (i, ring) in rings.iter().enumerate() {
        let offset = if i % 2 == 1 { 0.5 } else { 0.0 };
        ring_points(&ring.section, ring.count, offset, &mut points);
        let start = positions.len() as u32;
        positions.extend(
            points
                .iter()
                .map(|q| pose * Point::new(q.x, ring.section.y, q.y)),
        );
        if let Some((a, na, oa)) = previous {
            zip(triangles, (a, na, oa), (start, ring.count, offset));
        }
        previous = Some((start, ring.count, offset));
    }
}

/// Joins ring `a` to ring `b` (start index, count, offset in steps), walking
/// both in order of arc-length fraction.
fn zip(
    triangles: &mut Vec<[u32; 3]>,
    (a, na, oa): (u32, usize, f32),
    (b, nb, ob): (u32, usize, f32),
) {
    let ai = |i: usize| a + (i % na) as u32;
    let bi = |j: usize| b + (j % nb) as u32;
    if nb == 1 {
        triangles.extend((0..na).map(|i| [ai(i), ai(i + 1), b]));
        return;
    }
    if na == 1 {
        triangles.extend((0..nb).map(|j| [a, bi(j + 1), bi(j)]));
        return;
    }
    let (mut i, mut j) = (0, 0);
    while i < na || j < nb {
        let fa = (i as f32 + 1.0 + oa) / na as f32;
        let fb = (j as f32 + 1.0 + ob) / nb as f32;
        if j >= nb || (i < na && fa <= fb) {
            triangles.push([ai(i), ai(i + 1), bi(j)]);
            i += 1;
        } else {
            triangles.push([ai(i), bi(j + 1), bi(j)]);
            j += 1;
        }
    }
}

fn build_torus(
    pose: &Isometry3<f32>,
    major: f32,
    minor: f32,
    nu: usize,
    nv: usize,
    positions: &mut Vec<Point>,
    triangles: &mut Vec<[u32; 3]>,
) {
    let base = positions.len() as u32;
    for u in 0..nu {
        let (su, cu) = (TAU * u as f32 / nu as f32).sin_cos();
        for v in 0..nv {
            let (sv, cv) = (TAU * v as f32 / nv as f32).sin_cos();
            let r = major + minor * cv;
            positions.push(pose * Point::new(r * cu, minor * sv, r * su));
        }
    }
    let id = |u: usize, v: usize| base + ((u % nu) * nv + v % nv) as u32;
    for u in 0..nu {
        for v in 0..nv {
            triangles.push([id(u, v), id(u, v + 1), id(u + 1, v + 1)]);
            triangles.push([id(u, v), id(u + 1, v + 1), id(u + 1, v)]);
        }
    }
}
