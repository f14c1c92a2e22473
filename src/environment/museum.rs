//! The virtual museum (paper §6: 9,482 vertices). Layout in the module docs of
//! [`crate::environment`].

use std::f32::consts::{FRAC_PI_2, PI};

use nalgebra::Unit;

use super::build::{
    Layout, Section, Shape, SplitMix, add_shell, along, capsule_keys, cuboid, cylinder_keys,
    ellipsoid_keys, fit, lathe_keys, lying, p, quad, sweep, upright, v,
};
use super::{Environment, EnvironmentError, ObjectKind, RigidMotion};
use cornertree::geometry::{Point, Vector};

/// The paper's museum size (§6).
pub const MUSEUM_VERTICES: usize = 9_482;
/// Extent along X, Z and height (metres).
pub const WIDTH: f32 = 20.0;
pub const DEPTH: f32 = 12.0;
pub const HEIGHT: f32 = 5.0;
/// The free corridor along the south wall: `z ∈ [0, CORRIDOR]`.
pub const CORRIDOR: f32 = 2.5;

/// The museum with the paper's vertex count.
pub fn museum(seed: u64) -> Environment {
    museum_scaled(seed, MUSEUM_VERTICES).expect("the museum layout supports its own vertex count")
}

/// The museum's layout for `seed`, tessellated to exactly `vertices` vertices.
pub fn museum_scaled(seed: u64, vertices: usize) -> Result<Environment, EnvironmentError> {
    fit(&layout(seed), vertices)
}

fn layout(seed: u64) -> Layout {
    let mut rng = SplitMix::new(seed ^ 0x6D75_7365_756D);
    let mut l = Layout::new(format!("museum-seed{seed}"));
    let (w, d, h) = (WIDTH, DEPTH, HEIGHT);
    add_shell(&mut l, w, d, h);
    l.add(
        "north wall",
        ObjectKind::Wall,
        vec![quad(p(0., 0., d), p(0., h, d), p(w, h, d), p(w, 0., d))],
    );
    l.add(
        "east wall",
        ObjectKind::Wall,
        vec![quad(p(w, 0., 0.), p(w, 0., d), p(w, h, d), p(w, h, 0.))],
    );
    let (z0, z1, dh) = (9.0, 10.0, 2.1);
    l.add(
        "west wall",
        ObjectKind::Wall,
        vec![wall_with_door(h, d, z0, z1, dh)],
    );
    l.add_moving("door", ObjectKind::Door, door_motion(z0), door(z0, z1, dh));

    // Fifteen slots: 4 glass cases, 8 pedestals with statues, 3 benches.
    let mut kinds: Vec<u8> = [0u8; 4].into_iter().chain([1; 8]).chain([2; 3]).collect();
    rng.shuffle(&mut kinds);
    let xs = [3.0, 6.5, 10.0, 13.5, 17.0];
    let zs = [4.5, 7.0, 9.5];
    let (mut cases, mut pedestals, mut benches) = (0, 0, 0);
    for (slot, &kind) in kinds.iter().enumerate() {
        let x = xs[slot % 5] + rng.range(-0.3, 0.3);
        let z = zs[slot / 5] + rng.range(-0.25, 0.25);
        match kind {
            0 => {
                cases += 1;
                l.add(
                    format!("glass case {cases}"),
                    ObjectKind::GlassCase,
                    glass_case(x, z),
                );
                let artefact = artefact(&mut rng, p(x, 0.9, z));
                l.add(format!("artefact {cases}"), ObjectKind::Statue, artefact);
            }
            1 => {
                pedestals += 1;
                let yaw = rng.range(0.0, 2.0 * PI);
                l.add(
                    format!("pedestal {pedestals}"),
                    ObjectKind::Pedestal,
                    vec![cuboid(p(x, 0.5, z), v(0.25, 0.5, 0.25), yaw)],
                );
                let statue = statue(&mut rng, p(x, 1.0, z), yaw);
                l.add(format!("statue {pedestals}"), ObjectKind::Statue, statue);
            }
            _ => {
                benches += 1;
                let yaw = if rng.below(2) == 0 { 0.0 } else { FRAC_PI_2 };
                l.add(
                    format!("bench {benches}"),
                    ObjectKind::Bench,
                    bench(p(x, 0.0, z), yaw),
                );
            }
        }
    }
    for (i, x) in [3.5f32, 8.0, 12.5, 17.0].into_iter().enumerate() {
        let (hw, hh) = (rng.range(0.6, 1.0), rng.range(0.45, 0.7));
        let c = p(x + rng.range(-0.4, 0.4), 2.2, d - 0.02);
        l.add(
            format!("painting {}", i + 1),
            ObjectKind::Painting,
            vec![cuboid(c, v(hw, hh, 0.02), 0.0)],
        );
    }
    l
}

/// A wall in the plane `x = 0` from `z = 0` to `depth`, with a door opening
/// `z ∈ [z0, z1]` up to `door_h`.
pub(super) fn wall_with_door(h: f32, depth: f32, z0: f32, z1: f32, door_h: f32) -> Shape {
    let points = vec![
        p(0., 0., 0.),
        p(0., h, 0.),
        p(0., 0., z0),
        p(0., h, z0),
        p(0., door_h, z0),
        p(0., door_h, z1),
        p(0., 0., z1),
        p(0., h, z1),
        p(0., 0., depth),
        p(0., h, depth),
    ];
    // Left of the door, above it, right of it.
    let triangles = vec![
        [0, 2, 3],
        [0, 3, 1],
        [4, 5, 7],
        [4, 7, 3],
        [6, 8, 9],
        [6, 9, 7],
    ];
    Shape::Polygon { points, triangles }
}

/// A door in the opening `z ∈ [z0, z1]` of the wall `x = 0`, just inside the
/// room, with a round handle on the room side.
pub(super) fn door(z0: f32, z1: f32, door_h: f32) -> Vec<Shape> {
    let half = v(0.02, 0.5 * door_h - 0.005, 0.5 * (z1 - z0) - 0.005);
    let slab = cuboid(p(0.04, 0.5 * door_h, 0.5 * (z0 + z1)), half, 0.0);
    let handle_at = p(0.06, 1.0, z1 - 0.09);
    let stem = sweep(lying(handle_at, 0.0), cylinder_keys(0.0, 0.06, 0.008));
    let knob = sweep(
        along(p(0.135, 1.0, z1 - 0.09), Vector::x(), 0.0),
        ellipsoid_keys(0.03, 0.02, 0.03, 2.0),
    );
    vec![slab, stem, knob]
}

/// Swinging into the room (+X) about a vertical hinge at the door's `z0` edge,
/// 80° open at half the 4 s period.
pub(super) fn door_motion(z0: f32) -> RigidMotion {
    RigidMotion::Hinge {
        pivot: p(0.06, 0.0, z0),
        axis: Unit::new_normalize(Vector::y()),
        open: 80f32.to_radians(),
        period: 4.0,
    }
}

/// A cabinet 2.2 m × 0.9 m × 0.8 m and a hood of five 1 cm glass panes up to 1.6 m.
fn glass_case(x: f32, z: f32) -> Vec<Shape> {
    let (hx, hz) = (1.1, 0.4);
    vec![
        cuboid(p(x, 0.45, z), v(hx, 0.45, hz), 0.0),
        cuboid(p(x, 1.25, z - hz + 0.005), v(hx, 0.35, 0.005), 0.0),
        cuboid(p(x, 1.25, z + hz - 0.005), v(hx, 0.35, 0.005), 0.0),
        cuboid(p(x - hx + 0.005, 1.25, z), v(0.005, 0.35, hz - 0.01), 0.0),
        cuboid(p(x + hx - 0.005, 1.25, z), v(0.005, 0.35, hz - 0.01), 0.0),
        cuboid(p(x, 1.605, z), v(hx, 0.005, hz), 0.0),
    ]
}

/// A bench: seat 1.6 m × 0.4 m at 0.45 m on two legs.
fn bench(at: Point, yaw: f32) -> Vec<Shape> {
    let (s, c) = yaw.sin_cos();
    let off = |dx: f32| p(at.x + c * dx, 0.21, at.z - s * dx);
    vec![
        cuboid(p(at.x, 0.45, at.z), v(0.8, 0.03, 0.2), yaw),
        cuboid(off(-0.65), v(0.03, 0.21, 0.18), yaw),
        cuboid(off(0.65), v(0.03, 0.21, 0.18), yaw),
    ]
}

/// A small tessellated piece inside a glass case, standing at `at`.
fn artefact(rng: &mut SplitMix, at: Point) -> Vec<Shape> {
    let s = rng.factor(0.15);
    match rng.below(3) {
        0 => vec![sweep(upright(at, 0.0), amphora(0.35 * s))],
        1 => {
            // A bowl with a lid knob.
            let prof = [
                (0.0, 0.05 * s),
                (0.02 * s, 0.1 * s),
                (0.08 * s, 0.14 * s),
                (0.12 * s, 0.13 * s),
            ];
            vec![
                sweep(upright(at, 0.0), lathe_keys(&prof)),
                sweep(
                    upright(at + v(0., 0.15 * s, 0.), 0.0),
                    ellipsoid_keys(0.03 * s, 0.03 * s, 0.03 * s, 2.0),
                ),
            ]
        }
        _ => {
            // A skull-like ellipsoid on a ring stand.
            vec![
                Shape::Torus {
                    pose: upright(at + v(0., 0.02, 0.), 0.0),
                    major: 0.08 * s,
                    minor: 0.02 * s,
                },
                sweep(
                    upright(at + v(0., 0.14 * s, 0.), 0.0),
                    ellipsoid_keys(0.09 * s, 0.11 * s, 0.12 * s, 2.0),
                ),
            ]
        }
    }
}

/// An amphora of height `h` standing on the origin of its local frame.
fn amphora(h: f32) -> Vec<Section> {
    let prof = [
        (0.0, 0.06 * h),
        (0.05 * h, 0.1 * h),
        (0.25 * h, 0.25 * h),
        (0.5 * h, 0.3 * h),
        (0.72 * h, 0.22 * h),
        (0.85 * h, 0.1 * h),
        (0.95 * h, 0.09 * h),
        (h, 0.12 * h),
    ];
    lathe_keys(&prof)
}

/// A statue on a pedestal top at `at`.
fn statue(rng: &mut SplitMix, at: Point, yaw: f32) -> Vec<Shape> {
    let s = rng.factor(0.15);
    let up = |dy: f32| at + v(0., dy, 0.);
    match rng.below(5) {
        0 => {
            // Bust: shoulders, neck, head, nose.
            let (sn, cs) = yaw.sin_cos();
            let facing = v(sn, 0.0, cs);
            vec![
                sweep(
                    lying(up(0.1 * s), yaw),
                    capsule_keys(0.44 * s, 0.1 * s, 0.12 * s, 3.0, 0.1 * s),
                ),
                sweep(
                    upright(up(0.15 * s), yaw),
                    cylinder_keys(0.0, 0.14 * s, 0.05 * s),
                ),
                sweep(
                    upright(up(0.38 * s), yaw),
                    ellipsoid_keys(0.085 * s, 0.12 * s, 0.1 * s, 2.0),
                ),
                sweep(
                    along(up(0.37 * s) + facing * 0.1 * s, facing, 0.0),
                    ellipsoid_keys(0.015 * s, 0.03 * s, 0.02 * s, 2.0),
                ),
            ]
        }
        1 => {
            // A sphere on a short stem.
            let r = 0.25 * s;
            vec![
                sweep(upright(at, yaw), cylinder_keys(0.0, 0.12, 0.05 * s)),
                sweep(upright(up(0.1 + r), yaw), ellipsoid_keys(r, r, r, 2.0)),
            ]
        }
        2 => {
            // An upright torus on a plinth.
            let (major, minor) = (0.25 * s, 0.06 * s);
            vec![
                cuboid(up(0.03), v(0.15, 0.03, 0.1), yaw),
                Shape::Torus {
                    pose: along(up(0.06 + major + minor), v(yaw.cos(), 0.0, -yaw.sin()), 0.0),
                    major,
                    minor,
                },
            ]
        }
        3 => vec![sweep(upright(at, yaw), amphora(0.6 * s))],
        _ => {
            // A stack of three squarish stones.
            let mut y = 0.0;
            let mut shapes = Vec::new();
            for k in 0..3 {
                let r = (0.2 - 0.05 * k as f32) * rng.factor(0.1);
                let hy = 0.6 * r;
                shapes.push(sweep(
                    upright(up(y + hy), yaw + rng.range(0.0, 1.0)),
                    ellipsoid_keys(r, hy, 0.8 * r, 3.0),
                ));
                y += 1.9 * hy;
            }
            shapes
        }
    }
}
