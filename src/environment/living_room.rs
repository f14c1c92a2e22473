//! The virtual living room (paper §6: 133,139 vertices). Layout in the module
//! docs of [`crate::environment`].

use std::f32::consts::{FRAC_PI_2, PI, TAU};

use super::build::{
    Layout, Section, Shape, SplitMix, add_shell, along, capsule_keys, cuboid, cylinder_keys,
    ellipsoid_keys, fit, lathe_keys, lying, p, quad, sweep, upright, v,
};
use super::museum::{door, door_motion, wall_with_door};
use super::{Environment, EnvironmentError, ObjectKind};
use cornertree::geometry::Point;

/// The paper's living-room size (§6).
pub const LIVING_ROOM_VERTICES: usize = 133_139;
/// Extent along X, Z and height (metres).
pub const WIDTH: f32 = 8.0;
pub const DEPTH: f32 = 6.0;
pub const HEIGHT: f32 = 2.7;
/// The free corridor along the south wall: `z ∈ [0, CORRIDOR]`.
pub const CORRIDOR: f32 = 1.3;

/// The living room with the paper's vertex count.
pub fn living_room(seed: u64) -> Environment {
    living_room_scaled(seed, LIVING_ROOM_VERTICES)
        .expect("the living-room layout supports its own vertex count")
}

/// The living room's layout for `seed`, tessellated to exactly `vertices` vertices.
pub fn living_room_scaled(seed: u64, vertices: usize) -> Result<Environment, EnvironmentError> {
    fit(&layout(seed), vertices)
}

fn layout(seed: u64) -> Layout {
    let mut rng = SplitMix::new(seed ^ 0x6C69_7669_6E67);
    let mut l = Layout::new(format!("living-room-seed{seed}"));
    let (w, d, h) = (WIDTH, DEPTH, HEIGHT);
    add_shell(&mut l, w, d, h);
    l.add(
        "east wall",
        ObjectKind::Wall,
        vec![quad(p(w, 0., 0.), p(w, 0., d), p(w, h, d), p(w, h, 0.))],
    );
    let (wx0, wx1, wy0, wy1) = (2.0, 5.0, 0.8, 2.2);
    l.add(
        "north wall",
        ObjectKind::Wall,
        vec![wall_with_window(w, h, d, wx0, wx1, wy0, wy1)],
    );
    l.add(
        "window glass",
        ObjectKind::Window,
        vec![quad(
            p(wx0, wy0, d - 0.05),
            p(wx0, wy1, d - 0.05),
            p(wx1, wy1, d - 0.05),
            p(wx1, wy0, d - 0.05),
        )],
    );
    l.add(
        "window sill",
        ObjectKind::Shelf,
        vec![cuboid(
            p(0.5 * (wx0 + wx1), wy0 - 0.02, d - 0.12),
            v(1.6, 0.02, 0.12),
            0.0,
        )],
    );
    for (i, x) in [2.4f32, 4.5].into_iter().enumerate() {
        let s = rng.factor(0.2);
        l.add(
            format!("sill vase {}", i + 1),
            ObjectKind::Decoration,
            vec![sweep(upright(p(x, wy0, d - 0.12), 0.0), vase(0.25 * s))],
        );
    }
    let (z0, z1, dh) = (4.2, 5.1, 2.05);
    l.add(
        "west wall",
        ObjectKind::Wall,
        vec![wall_with_door(h, d, z0, z1, dh)],
    );
    l.add_moving("door", ObjectKind::Door, door_motion(z0), door(z0, z1, dh));

    // Living group around the rug.
    let (cx, cz) = (3.0 + rng.range(-0.1, 0.1), 3.4 + rng.range(-0.05, 0.05));
    l.add(
        "rug",
        ObjectKind::Rug,
        vec![cuboid(p(cx, 0.005, cz), v(1.5, 0.005, 1.0), 0.0)],
    );
    let mut fringe = Vec::new();
    for side in [-1.0f32, 1.0] {
        for k in 0..40 {
            let z = cz - 0.975 + 1.95 * k as f32 / 39.0;
            let dir = v(side, 0.0, rng.range(-0.15, 0.15));
            let at = p(cx + side * 1.5, 0.006, z);
            fringe.push(sweep(
                along(at, dir, 0.0),
                cylinder_keys(0.0, 0.07 * rng.factor(0.15), 0.005),
            ));
        }
    }
    l.add("rug fringe", ObjectKind::Rug, fringe);
    l.add(
        "coffee table",
        ObjectKind::Table,
        table(p(cx, 0.0, cz), 0.6, 0.3, 0.44, 0.02, 0.0),
    );
    l.add(
        "coffee table vase",
        ObjectKind::Decoration,
        vec![sweep(
            upright(p(cx + 0.3, 0.46, cz), 0.0),
            vase(0.3 * rng.factor(0.15)),
        )],
    );
    sofa(&mut l, &mut rng, p(cx, 0.0, 5.35), PI);
    armchair(
        &mut l,
        &mut rng,
        "armchair west",
        p(1.0, 0.0, cz - 0.3),
        FRAC_PI_2,
    );
    armchair(
        &mut l,
        &mut rng,
        "armchair east",
        p(5.0, 0.0, cz),
        -FRAC_PI_2,
    );
    floor_lamp(&mut l, p(1.45, 0.0, 5.6));
    let side = p(4.7, 0.0, 5.5);
    l.add(
        "side table",
        ObjectKind::Table,
        vec![sweep(
            upright(side, 0.0),
            lathe_keys(&[
                (0.0, 0.18),
                (0.03, 0.18),
                (0.05, 0.03),
                (0.5, 0.03),
                (0.52, 0.25),
                (0.55, 0.25),
            ]),
        )],
    );
    l.add(
        "side table bowl",
        ObjectKind::Decoration,
        vec![sweep(upright(side + v(0., 0.55, 0.), 0.0), bowl(0.12))],
    );

    // Dining group.
    let (dx, dz) = (6.6 + rng.range(-0.05, 0.05), 2.6 + rng.range(-0.05, 0.05));
    l.add(
        "dining table",
        ObjectKind::Table,
        table(p(dx, 0.0, dz), 0.9, 0.45, 0.75, 0.02, 0.0),
    );
    for (i, (ox, oz, yaw)) in [
        (-0.45, -0.85, 0.0),
        (0.45, -0.85, 0.0),
        (-0.45, 0.85, PI),
        (0.45, 0.85, PI),
    ]
    .into_iter()
    .enumerate()
    {
        let at = p(
            dx + ox + rng.range(-0.05, 0.05),
            0.0,
            dz + oz + rng.range(-0.03, 0.03),
        );
        l.add(
            format!("dining chair {}", i + 1),
            ObjectKind::Seating,
            chair(at, yaw + rng.range(-0.1, 0.1)),
        );
    }
    let top = 0.77;
    l.add(
        "fruit bowl",
        ObjectKind::Decoration,
        vec![sweep(upright(p(dx - 0.3, top, dz), 0.0), bowl(0.14))],
    );
    let mut fruit = Vec::new();
    for k in 0..6 {
        let a = TAU * k as f32 / 6.0 + rng.range(0.0, 0.4);
        let r = 0.035 * rng.factor(0.2);
        let at = p(
            dx - 0.3 + 0.07 * a.cos(),
            top + 0.04 + r,
            dz + 0.07 * a.sin(),
        );
        fruit.push(sweep(
            upright(at, a),
            ellipsoid_keys(r, r * rng.factor(0.15), r, 2.0),
        ));
    }
    l.add("fruit", ObjectKind::Decoration, fruit);
    l.add(
        "dining vase",
        ObjectKind::Decoration,
        vec![sweep(
            upright(p(dx + 0.4, top, dz), 0.0),
            vase(0.35 * rng.factor(0.1)),
        )],
    );

    bookshelf(&mut l, &mut rng, 7.82, 4.0, 5.6);
    plant(&mut l, &mut rng, "plant south-west", p(0.45, 0.0, 1.95));
    plant(&mut l, &mut rng, "plant north-east", p(7.6, 0.0, 3.75));
    l.add(
        "ceiling lamp",
        ObjectKind::Lamp,
        vec![
            sweep(
                upright(p(cx, h - 0.5, cz), 0.0),
                cylinder_keys(0.2, 0.5, 0.006),
            ),
            sweep(
                upright(p(cx, h - 0.5, cz), 0.0),
                lathe_keys(&[(0.0, 0.2), (0.05, 0.22), (0.18, 0.12), (0.22, 0.03)]),
            ),
        ],
    );
    l
}

/// A wall in the plane `z = depth` with a window opening `x ∈ [x0, x1]`, `y ∈ [y0, y1]`.
fn wall_with_window(w: f32, h: f32, depth: f32, x0: f32, x1: f32, y0: f32, y1: f32) -> Shape {
    let points = vec![
        p(0., 0., depth),
        p(w, 0., depth),
        p(w, h, depth),
        p(0., h, depth),
        p(x0, y0, depth),
        p(x1, y0, depth),
        p(x1, y1, depth),
        p(x0, y1, depth),
    ];
    // Frame around the opening: bottom, right, top, left.
    let triangles = vec![
        [0, 1, 5],
        [0, 5, 4],
        [1, 2, 6],
        [1, 6, 5],
        [2, 3, 7],
        [2, 7, 6],
        [3, 0, 4],
        [3, 4, 7],
    ];
    Shape::Polygon { points, triangles }
}

fn vase(h: f32) -> Vec<Section> {
    lathe_keys(&[
        (0.0, 0.2 * h),
        (0.3 * h, 0.3 * h),
        (0.6 * h, 0.22 * h),
        (0.85 * h, 0.1 * h),
        (h, 0.14 * h),
    ])
}

fn bowl(r: f32) -> Vec<Section> {
    lathe_keys(&[
        (0.0, 0.4 * r),
        (0.2 * r, 0.75 * r),
        (0.45 * r, r),
        (0.5 * r, 0.95 * r),
    ])
}

/// A table: a box top of half extents `hx × hz` at height `height`, four turned legs.
fn table(at: Point, hx: f32, hz: f32, height: f32, thickness: f32, yaw: f32) -> Vec<Shape> {
    let mut shapes = vec![cuboid(
        at + v(0., height - thickness, 0.),
        v(hx, thickness, hz),
        yaw,
    )];
    let (s, c) = yaw.sin_cos();
    for (sx, sz) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let (lx, lz) = (sx * (hx - 0.06), sz * (hz - 0.06));
        let foot = p(at.x + c * lx + s * lz, 0.0, at.z - s * lx + c * lz);
        let top = height - 2.0 * thickness;
        shapes.push(sweep(
            upright(foot, 0.0),
            lathe_keys(&[
                (0.0, 0.018),
                (0.6 * top, 0.025),
                (0.9 * top, 0.03),
                (top, 0.03),
            ]),
        ));
    }
    shapes
}

/// Places a local point (`x` right, `z` forward = the way the seat faces) of a
/// piece of furniture at `at` turned by `yaw`.
fn local(at: Point, yaw: f32, x: f32, y: f32, z: f32) -> Point {
    let (s, c) = yaw.sin_cos();
    p(at.x + c * x + s * z, y, at.z - s * x + c * z)
}

fn sofa(l: &mut Layout, rng: &mut SplitMix, at: Point, yaw: f32) {
    let q = |x: f32, y: f32, z: f32| local(at, yaw, x, y, z);
    let len = 2.2;
    let body = vec![
        sweep(
            lying(q(0.0, 0.25, 0.0), yaw),
            capsule_keys(len, 0.17, 0.43, 6.0, 0.05),
        ),
        sweep(
            lying(q(0.0, 0.62, -0.34), yaw),
            capsule_keys(len, 0.3, 0.1, 5.0, 0.06),
        ),
        sweep(
            lying(q(-1.02, 0.45, 0.0), yaw + FRAC_PI_2),
            capsule_keys(0.9, 0.22, 0.09, 4.0, 0.06),
        ),
        sweep(
            lying(q(1.02, 0.45, 0.0), yaw + FRAC_PI_2),
            capsule_keys(0.9, 0.22, 0.09, 4.0, 0.06),
        ),
    ];
    let mut feet = Vec::new();
    for (x, z) in [
        (-1.0, -0.35),
        (0.0, -0.35),
        (1.0, -0.35),
        (-1.0, 0.35),
        (0.0, 0.35),
        (1.0, 0.35),
    ] {
        feet.push(sweep(
            upright(q(x, 0.0, z), 0.0),
            lathe_keys(&[(0.0, 0.02), (0.08, 0.03)]),
        ));
    }
    l.add("sofa", ObjectKind::Seating, body);
    l.add("sofa feet", ObjectKind::Seating, feet);
    let mut seat = Vec::new();
    let mut back = Vec::new();
    for k in 0..3 {
        let x = -0.64 + 0.64 * k as f32;
        seat.push(sweep(
            lying(q(x, 0.5, 0.06), yaw),
            capsule_keys(0.62, 0.08 * rng.factor(0.1), 0.36, 4.0, 0.06),
        ));
        back.push(sweep(
            along(q(x, 0.78, -0.2), v(0.0, 1.0, 0.0), yaw),
            capsule_keys(0.4, 0.3, 0.08 * rng.factor(0.1), 4.0, 0.08),
        ));
    }
    l.add("sofa seat cushions", ObjectKind::Cushion, seat);
    l.add("sofa back cushions", ObjectKind::Cushion, back);
    let mut pillows = Vec::new();
    for x in [-0.8f32, 0.8] {
        pillows.push(sweep(
            along(
                q(x, 0.78, -0.08),
                v(0.0, 1.0, 0.3),
                yaw + rng.range(-0.3, 0.3),
            ),
            ellipsoid_keys(0.2, 0.2, 0.07, 3.0),
        ));
    }
    l.add("sofa pillows", ObjectKind::Cushion, pillows);
}

fn armchair(l: &mut Layout, rng: &mut SplitMix, name: &str, at: Point, yaw: f32) {
    let q = |x: f32, y: f32, z: f32| local(at, yaw, x, y, z);
    let mut body = vec![
        sweep(
            lying(q(0.0, 0.25, 0.0), yaw),
            capsule_keys(0.85, 0.17, 0.4, 6.0, 0.05),
        ),
        sweep(
            lying(q(0.0, 0.6, -0.32), yaw),
            capsule_keys(0.85, 0.3, 0.09, 5.0, 0.06),
        ),
        sweep(
            lying(q(-0.36, 0.45, 0.0), yaw + FRAC_PI_2),
            capsule_keys(0.85, 0.2, 0.07, 4.0, 0.05),
        ),
        sweep(
            lying(q(0.36, 0.45, 0.0), yaw + FRAC_PI_2),
            capsule_keys(0.85, 0.2, 0.07, 4.0, 0.05),
        ),
    ];
    for (x, z) in [(-0.35, -0.33), (0.35, -0.33), (-0.35, 0.33), (0.35, 0.33)] {
        body.push(sweep(
            upright(q(x, 0.0, z), 0.0),
            lathe_keys(&[(0.0, 0.02), (0.08, 0.03)]),
        ));
    }
    l.add(name, ObjectKind::Seating, body);
    l.add(
        format!("{name} cushion"),
        ObjectKind::Cushion,
        vec![sweep(
            lying(q(0.0, 0.49, 0.05), yaw),
            capsule_keys(0.62, 0.07 * rng.factor(0.1), 0.33, 4.0, 0.06),
        )],
    );
}

/// A dining chair facing `yaw` (local +Z forward).
fn chair(at: Point, yaw: f32) -> Vec<Shape> {
    let q = |x: f32, y: f32, z: f32| local(at, yaw, x, y, z);
    let mut shapes = vec![
        sweep(
            lying(q(0.0, 0.45, 0.0), yaw),
            capsule_keys(0.44, 0.025, 0.21, 6.0, 0.02),
        ),
        sweep(
            lying(q(0.0, 0.8, -0.2), yaw),
            capsule_keys(0.42, 0.12, 0.02, 4.0, 0.02),
        ),
    ];
    for (x, z) in [(-0.19, -0.18), (0.19, -0.18), (-0.19, 0.18), (0.19, 0.18)] {
        shapes.push(sweep(
            upright(q(x, 0.0, z), 0.0),
            cylinder_keys(0.0, 0.43, 0.017),
        ));
    }
    for x in [-0.19f32, 0.19] {
        shapes.push(sweep(
            upright(q(x, 0.45, -0.2), 0.0),
            cylinder_keys(0.0, 0.45, 0.014),
        ));
    }
    shapes
}

fn floor_lamp(l: &mut Layout, at: Point) {
    l.add(
        "floor lamp",
        ObjectKind::Lamp,
        vec![
            sweep(
                upright(at, 0.0),
                lathe_keys(&[(0.0, 0.16), (0.02, 0.16), (0.04, 0.1), (0.05, 0.02)]),
            ),
            sweep(upright(at, 0.0), cylinder_keys(0.04, 1.45, 0.012)),
            sweep(
                upright(at + v(0., 1.35, 0.), 0.0),
                lathe_keys(&[(0.0, 0.22), (0.3, 0.14)]),
            ),
        ],
    );
}

fn bookshelf(l: &mut Layout, rng: &mut SplitMix, x_back: f32, z0: f32, z1: f32) {
    let (depth, height) = (0.34, 2.0);
    let xc = x_back - 0.5 * depth;
    let zc = 0.5 * (z0 + z1);
    let hz = 0.5 * (z1 - z0);
    let mut frame = vec![
        cuboid(
            p(xc, 0.5 * height, z0 + 0.01),
            v(0.5 * depth, 0.5 * height, 0.01),
            0.0,
        ),
        cuboid(
            p(xc, 0.5 * height, z1 - 0.01),
            v(0.5 * depth, 0.5 * height, 0.01),
            0.0,
        ),
        cuboid(
            p(x_back + 0.005, 0.5 * height, zc),
            v(0.005, 0.5 * height, hz),
            0.0,
        ),
    ];
    let shelves = [0.02, 0.42, 0.82, 1.22, 1.62, 1.98];
    for &y in &shelves {
        frame.push(cuboid(p(xc, y, zc), v(0.5 * depth, 0.015, hz - 0.02), 0.0));
    }
    l.add("bookshelf", ObjectKind::Shelf, frame);
    let mut books = Vec::new();
    for w in shelves.windows(2).take(4) {
        let mut z = z0 + 0.03;
        while z < z1 - 0.08 {
            let t = rng.range(0.02, 0.06);
            let bh = rng.range(0.2, 0.32);
            let bd = rng.range(0.15, 0.24);
            let lean = if rng.below(12) == 0 { 0.15 } else { 0.0 };
            books.push(Shape::Cuboid {
                pose: nalgebra::Isometry3::new(
                    v(
                        x_back - 0.02 - 0.5 * bd,
                        w[0] + 0.015 + 0.5 * bh,
                        z + 0.5 * t,
                    ),
                    v(lean, 0.0, 0.0),
                ),
                half: v(0.5 * bd, 0.5 * bh, 0.5 * t),
            });
            z += t + 0.002 + if lean > 0.0 { 0.05 } else { 0.0 };
        }
    }
    l.add("books", ObjectKind::Book, books);
}

fn plant(l: &mut Layout, rng: &mut SplitMix, name: &str, at: Point) {
    l.add(
        format!("{name} pot"),
        ObjectKind::Plant,
        vec![sweep(
            upright(at, 0.0),
            lathe_keys(&[(0.0, 0.12), (0.35, 0.17), (0.37, 0.19), (0.38, 0.15)]),
        )],
    );
    let mut leaves = Vec::new();
    let n = 14;
    for k in 0..n {
        let a = TAU * (k as f32 + rng.range(0.0, 0.5)) / n as f32;
        let tilt = rng.range(0.2, 0.7);
        let dir = v(a.cos() * tilt.sin(), tilt.cos(), a.sin() * tilt.sin());
        let len = rng.range(0.5, 0.8);
        let base = at + v(0.0, 0.36, 0.0);
        leaves.push(sweep(
            along(base, dir, 0.0),
            cylinder_keys(0.0, 0.6 * len, 0.006),
        ));
        leaves.push(sweep(
            along(base + dir * (0.6 * len), dir, a),
            ellipsoid_keys(0.06, 0.2 * len, 0.008, 2.0),
        ));
    }
    l.add(format!("{name} leaves"), ObjectKind::Plant, leaves);
}
