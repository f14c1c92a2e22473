//! Environments: rooms of big and small triangles for the character to move in
//! (paper §4 "Big triangles, a problem", §6: a virtual museum of 9,482 vertices
//! and a living room of 133,139 vertices, both with triangles bigger than the
//! avatar).
//!
//! | file | what |
//! |---|---|
//! | [`museum`](mod@museum) | [`museum()`]: a 20 m × 12 m × 5 m gallery, 9,482 vertices |
//! | [`living_room`](mod@living_room) | [`living_room()`]: an 8 m × 6 m × 2.7 m living/dining room, 133,139 vertices |
//! | [`plaza`](mod@plaza) | [`plaza()`]: an open floor of big triangles for crowds, sized to them |
//! | [`scene`] | [`load_scene`]: a static glTF scene as an environment, degenerate triangles removed |
//! | `build` | shapes, the tessellation plan that meets a vertex target, the mesh builder (private) |
//! | `subdivide` | [`Environment::subdivide_object`]: one object's triangles split at edge midpoints (an experiment knob) |
//!
//! **Conventions.** Y up, metres, the floor at `y = 0`, the room spanning
//! `x ∈ [0, W]`, `z ∈ [0, D]`, `y ∈ [0, H]`. Every object is a contiguous run
//! of vertices and triangles of the one [`TriMesh`]; vertices are shared
//! within an object, never between objects. No triangle has zero area.
//!
//! **Big and small.** Floors, ceilings, walls (two triangles per plain wall,
//! a few more around a door or window opening), window glass, glass cases,
//! table tops, rugs and doors are a handful of triangles each, metres long:
//! bigger than the 1.75 m avatar, the triangles the paper's §4–5 hierarchies
//! are built for ([`big_triangles`] lists those whose longest edge exceeds a
//! threshold). Statues, furniture, cushions, plants, lamps and fringes are
//! finely tessellated sweeps and tori whose resolution follows one edge
//! length, chosen so that the vertex count is met exactly (see `build`).
//!
//! **Museum** (`W = 20`, `D = 12`, `H = 5`): floor, ceiling and three walls as
//! two triangles each; the west wall (`x = 0`) has a door opening
//! `z ∈ [9, 10]`, 2.1 m high, closed by a door that swings into the room about
//! a vertical hinge at `(0.06, ·, 9)` (the only moving object). Fifteen slots
//! on a 5 × 3 grid (`x ∈ {3, 6.5, 10, 13.5, 17}`, `z ∈ {4.5, 7, 9.5}`), shuffled
//! and jittered by the seed, hold four glass cases (2.2 m × 0.8 m cabinet,
//! 0.7 m hood of five thin glass panes, an artefact inside), eight 1 m
//! pedestals carrying statues (busts, spheres, upright tori, amphorae,
//! stacks) and three benches. Paintings hang on the north wall.
//! **Free walking area:** the corridor `z ∈ [0, 2.5]` along the whole south
//! wall (`z = 0`, a 20 m × 5 m wall of two triangles), and the door's swing
//! `x ∈ [0, 1.2]`, `z ∈ [8.8, 10.2]`; nothing else stands at `z < 3.3`.
//!
//! **Living room** (`W = 8`, `D = 6`, `H = 2.7`): floor, ceiling, south and
//! east walls as two triangles each; the north wall (`z = 6`) has a window
//! opening `x ∈ [2, 5]`, `y ∈ [0.8, 2.2]` with one big glass pane and a sill;
//! the west wall (`x = 0`) has a door opening `z ∈ [4.2, 5.1]`, 2.05 m high,
//! with a door swinging in about a hinge at `(0.06, ·, 4.2)`. Around a
//! 3 m × 2 m rug with fringes (centre `(3, 3.4)`): a coffee table, a sofa with
//! seat, back and arm parts, cushions and pillows (backing onto the window
//! wall), two armchairs, a floor lamp and a side table. To the east a
//! 1.8 m × 0.9 m dining table with four chairs, a fruit bowl and a vase; a
//! bookshelf with books against the east wall; plants, vases on the sill and
//! a ceiling lamp.
//! **Free walking area:** the corridor `z ∈ [0, 1.3]` along the whole south
//! wall (`z = 0`, an 8 m × 2.7 m wall of two triangles), and the door's swing
//! `x ∈ [0, 1.1]`, `z ∈ [4.0, 5.3]`.
//!
//! Both rooms are deterministic in the seed: the same seed gives bit-identical
//! positions and indices, another seed moves and varies the furniture.
//! [`museum_scaled`] and [`living_room_scaled`] keep the layout and meet any
//! other vertex count (within the supported range) exactly, for scaling studies.

mod build;
pub mod living_room;
pub mod museum;
pub mod plaza;
pub mod scene;
mod subdivide;

use std::fmt;
use std::ops::Range;

use nalgebra::{Isometry3, Translation3, Unit, UnitQuaternion};

use cornertree::geometry::{Point, Real, Vector};
use cornertree::mesh::{TriMesh, TriangleId};

pub use build::MAX_VERTICES;
pub use living_room::{LIVING_ROOM_VERTICES, living_room, living_room_scaled};
pub use museum::{MUSEUM_VERTICES, museum, museum_scaled};
pub use plaza::plaza;
pub use scene::{SceneError, SceneReport, load_scene, load_scene_with};
pub use subdivide::{MAX_SUBDIVIDED_TRIANGLES, SubdivideError};

/// What an object is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum ObjectKind {
    Floor,
    Ceiling,
    Wall,
    Window,
    Door,
    GlassCase,
    Pedestal,
    Statue,
    Painting,
    Bench,
    Table,
    Seating,
    Cushion,
    Shelf,
    Book,
    Lamp,
    Plant,
    Decoration,
    Rug,
    /// Loaded from a file: kind unknown.
    Scene,
}

/// A rigid motion over time of a moving object, from its rest pose (`t = 0`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RigidMotion {
    /// Rotation about the axis through `pivot` along `axis` by an angle that
    /// goes from 0 to `open` radians and back, `(1 - cos(2πt/period))/2·open`.
    Hinge {
        pivot: Point,
        axis: Unit<Vector>,
        open: Real,
        period: Real,
    },
    /// Translation by `travel` scaled the same way.
    Slide { travel: Vector, period: Real },
}

impl RigidMotion {
    /// Fraction of the full motion at time `t`: 0 at `t = 0`, 1 at half a period.
    fn phase(period: Real, t: Real) -> Real {
        0.5 * (1.0 - (std::f32::consts::TAU * t / period).cos())
    }

    /// Where the rest pose is moved to at time `t` (seconds).
    pub fn transform_at(&self, t: Real) -> Isometry3<Real> {
        match *self {
            Self::Hinge {
                pivot,
                axis,
                open,
                period,
            } => {
                let rotation =
                    UnitQuaternion::from_axis_angle(&axis, open * Self::phase(period, t));
                let shift = pivot.coords - rotation * pivot.coords;
                Isometry3::from_parts(Translation3::from(shift), rotation)
            }
            Self::Slide { travel, period } => Isometry3::from_parts(
                Translation3::from(travel * Self::phase(period, t)),
                UnitQuaternion::identity(),
            ),
        }
    }

    /// The motion's period in seconds.
    pub fn period(&self) -> Real {
        match *self {
            Self::Hinge { period, .. } | Self::Slide { period, .. } => period,
        }
    }
}

/// A named part of an environment: contiguous vertices and triangles of its mesh.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvObject {
    pub name: String,
    pub kind: ObjectKind,
    /// Vertices of the object, contiguous in the mesh.
    pub vertices: Range<u32>,
    /// Triangles of the object, contiguous in the mesh; they use only `vertices`.
    pub triangles: Range<u32>,
    /// `None` for static objects.
    pub motion: Option<RigidMotion>,
}

/// A room: one mesh (rest pose) and the objects it is made of.
#[derive(Clone, Debug, PartialEq)]
pub struct Environment {
    pub name: String,
    pub mesh: TriMesh,
    pub objects: Vec<EnvObject>,
}

impl Environment {
    /// Writes every vertex at time `t` into `out` (length = vertex count):
    /// moving objects transformed by their motion, the rest copied. Does not allocate.
    ///
    /// # Panics
    /// If `out.len()` differs from the mesh's vertex count.
    pub fn pose_at(&self, t: Real, out: &mut [Point]) {
        let rest = self.mesh.positions();
        assert_eq!(
            out.len(),
            rest.len(),
            "pose_at: output has {} slots for {} vertices",
            out.len(),
            rest.len()
        );
        out.copy_from_slice(rest);
        for object in &self.objects {
            if let Some(motion) = &object.motion {
                let m = motion.transform_at(t);
                let range = object.vertices.start as usize..object.vertices.end as usize;
                for (o, p) in out[range.clone()].iter_mut().zip(&rest[range]) {
                    *o = m * p;
                }
            }
        }
    }

    /// The room without its moving objects, and each moving object apart:
    /// its name, its mesh (rest pose, room coordinates) and its motion.
    /// Triangles of the static part keep their order.
    pub fn split_moving(&self) -> (Environment, Vec<(String, TriMesh, RigidMotion)>) {
        let pos = self.mesh.positions();
        let idx = self.mesh.indices();
        let sub = |o: &EnvObject| {
            let v0 = o.vertices.start;
            let positions = pos[o.vertices.start as usize..o.vertices.end as usize].to_vec();
            let triangles = idx[o.triangles.start as usize..o.triangles.end as usize]
                .iter()
                .map(|t| t.map(|i| i - v0))
                .collect();
            TriMesh::new(positions, triangles).expect("an object's triangles use its own vertices")
        };
        let mut moving = Vec::new();
        let mut positions = Vec::with_capacity(pos.len());
        let mut triangles = Vec::with_capacity(idx.len());
        let mut objects = Vec::with_capacity(self.objects.len());
        for o in &self.objects {
            if let Some(m) = o.motion {
                moving.push((o.name.clone(), sub(o), m));
                continue;
            }
            let v0 = positions.len() as u32;
            let t0 = triangles.len() as u32;
            positions.extend_from_slice(&pos[o.vertices.start as usize..o.vertices.end as usize]);
            triangles.extend(
                idx[o.triangles.start as usize..o.triangles.end as usize]
                    .iter()
                    .map(|t| t.map(|i| i - o.vertices.start + v0)),
            );
            objects.push(EnvObject {
                vertices: v0..positions.len() as u32,
                triangles: t0..triangles.len() as u32,
                ..o.clone()
            });
        }
        let room = Environment {
            name: self.name.clone(),
            mesh: TriMesh::new(positions, triangles).expect("objects use their own vertices"),
            objects,
        };
        (room, moving)
    }

    /// Objects that move.
    pub fn moving_objects(&self) -> impl Iterator<Item = &EnvObject> + '_ {
        self.objects.iter().filter(|o| o.motion.is_some())
    }

    /// The first object named `name`.
    pub fn object(&self, name: &str) -> Option<&EnvObject> {
        self.objects.iter().find(|o| o.name == name)
    }

    /// The object that owns triangle `id`.
    pub fn object_of(&self, id: TriangleId) -> Option<&EnvObject> {
        self.objects.iter().find(|o| o.triangles.contains(&id.0))
    }

    /// Vertices, triangles, big triangles at `threshold`, bounds.
    pub fn summary(&self, threshold: Real) -> Summary {
        summary(
            &self.name,
            &self.mesh,
            threshold,
            self.objects.len(),
            self.moving_objects().count(),
        )
    }
}

/// Why a room cannot be generated.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum EnvironmentError {
    #[error("a room of {requested} vertices was asked for; this layout supports {min} to {max}")]
    VertexCount {
        requested: usize,
        min: usize,
        max: usize,
    },
}

/// Triangles whose longest edge exceeds `threshold` (the paper's "big" triangles, §4).
pub fn big_triangles(mesh: &TriMesh, threshold: Real) -> Vec<TriangleId> {
    mesh.iter_triangles()
        .filter(|(_, t)| t.longest_edge() > threshold)
        .map(|(id, _)| id)
        .collect()
}

/// Size figures of an environment.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Summary {
    pub name: String,
    pub vertices: usize,
    pub triangles: usize,
    pub objects: usize,
    pub moving_objects: usize,
    /// Longest-edge threshold of `big_triangles`.
    pub threshold: Real,
    pub big_triangles: usize,
    pub longest_edge: Real,
    pub bounds_min: [Real; 3],
    pub bounds_max: [Real; 3],
}

/// Size figures of `mesh` (named `name`, with the given object counts).
pub fn summary(
    name: &str,
    mesh: &TriMesh,
    threshold: Real,
    objects: usize,
    moving_objects: usize,
) -> Summary {
    let (min, max) = mesh.bounds();
    let mut big = 0;
    let mut longest: Real = 0.0;
    for (_, t) in mesh.iter_triangles() {
        let l = t.longest_edge();
        longest = longest.max(l);
        big += usize::from(l > threshold);
    }
    Summary {
        name: name.to_owned(),
        vertices: mesh.vertex_count(),
        triangles: mesh.triangle_count(),
        objects,
        moving_objects,
        threshold,
        big_triangles: big,
        longest_edge: longest,
        bounds_min: [min.x, min.y, min.z],
        bounds_max: [max.x, max.y, max.z],
    }
}

impl fmt::Display for Summary {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b, c] = self.bounds_min;
        let [x, y, z] = self.bounds_max;
        write!(
            f,
            "{}: {} vertices, {} triangles, {} objects ({} moving); {} big triangles (longest edge > {} m), longest edge {:.2} m; bounds ({a:.2}, {b:.2}, {c:.2})–({x:.2}, {y:.2}, {z:.2})",
            self.name,
            self.vertices,
            self.triangles,
            self.objects,
            self.moving_objects,
            self.big_triangles,
            self.threshold,
            self.longest_edge,
        )
    }
}
