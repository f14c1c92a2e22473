//! Picking a walking character: each frame, the caller poses the character
//! (joint transforms from a clip) and casts a grid of rays at it from a
//! camera, then one ray at the room. The world answers from its sphere
//! trees, refit on demand along the rays and skinning only the triangles
//! they reach; nothing is skinned or refit for a ray that misses.
//!
//! Each frame's hits are checked against brute force: every vertex skinned
//! and every triangle tested.
//!
//! `cargo run --release -p cornertree --example ray_pick [VERTICES] [FRAMES]`
//! (default 10,000 vertices, 30 frames; a third argument `unchecked` skips
//! the brute force).

use std::sync::Arc;
use std::time::Instant;

use cornertree::character::{PoseBuffers, SkinningModel};
use cornertree::geometry::query_shapes::Ray;
use cornertree::geometry::{Point, Triangle, Vector};
use cornertree::mesh::TriMesh;
use cornertree::pipeline::Method;
use cornertree::world::{BodyRef, CharacterModel, CollisionWorld, QueryScratch, QueryTargets};
use nalgebra::Isometry3;

/// The workbench's generated humanoid (a mesh, a 22-joint skeleton, skin
/// weights and clips), standing in for an engine's own character.
#[path = "../../src/humanoid.rs"]
#[allow(dead_code)]
mod humanoid;

/// Rays per side of the picking grid.
const GRID: usize = 10;

/// What the frames saw.
struct Seen {
    rays: usize,
    hits: usize,
    microseconds_per_frame: f64,
    refits: u64,
    skinned: u64,
}

fn run(vertices: usize, frames: usize, check_hits: bool) -> Seen {
    let character = Arc::new(
        humanoid::generate_humanoid(&humanoid::HumanoidParams { vertices, seed: 0 })
            .expect("valid parameters"),
    );
    let floor = TriMesh::new(
        vec![
            Point::new(-5.0, 0.0, -5.0),
            Point::new(5.0, 0.0, -5.0),
            Point::new(5.0, 0.0, 5.0),
            Point::new(-5.0, 0.0, 5.0),
        ],
        vec![[0, 2, 1], [0, 3, 2]],
    )
    .expect("a valid mesh");

    let mut world = CollisionWorld::new(Method::UndividedPrunedTriTri);
    world.add_room(Arc::new(floor)).expect("in range");
    let model = CharacterModel::new(character.clone(), SkinningModel::Linear).expect("valid");
    let walker = world.add_character(Arc::new(model)).expect("valid");

    let clip = character.clip(Some("walk")).expect("the humanoid walks");
    let mut local = character.skeleton.rest_pose();
    let mut scratch = QueryScratch::new();
    let mut check = PoseBuffers::new(&character);
    let mut seen = Seen {
        rays: 0,
        hits: 0,
        microseconds_per_frame: 0.0,
        refits: 0,
        skinned: 0,
    };
    for k in 0..frames {
        // The caller's animation: a clip sampled, the walker turned a little.
        let t = clip.start() + clip.duration() * k as f32 / frames as f32;
        clip.sample(t, character.skeleton.rest_pose_ref(), &mut local);
        let placement = Isometry3::rotation(Vector::y() * (0.02 * k as f32));
        let t0 = Instant::now();
        world
            .set_joint_transforms(walker, &local, &placement)
            .expect("a valid pose");
        // A grid of rays from a camera 3 m in front, over the body.
        let mut hits = Vec::new();
        for i in 0..GRID * GRID {
            let (x, y) = (
                (i % GRID) as f32 / GRID as f32 - 0.5,
                (i / GRID) as f32 / GRID as f32 * 1.9,
            );
            let ray = Ray::new(
                Point::new(x * 0.9, y, 3.0),
                Vector::new(0.0, 0.0, -1.0),
                10.0,
            )
            .expect("a valid ray");
            let hit = world
                .cast_ray(&ray, QueryTargets::Character(walker), &mut scratch)
                .expect("the walker is in this world");
            seen.refits += scratch.counters().refits;
            seen.skinned += scratch.counters().skinned_vertices;
            hits.push((ray, hit));
        }
        // Straight down from above the head: the room's floor, or the walker.
        let down = Ray::new(Point::new(0.0, 3.0, 0.3), Vector::new(0.0, -1.0, 0.0), 10.0).unwrap();
        let below = world
            .cast_ray(&down, QueryTargets::All, &mut scratch)
            .expect("valid targets")
            .expect("the floor is there");
        seen.microseconds_per_frame += t0.elapsed().as_secs_f64() * 1e6 / frames as f64;
        assert!(below.distance <= 3.0 + 1e-4);

        if !check_hits {
            seen.rays += hits.len();
            seen.hits += hits.iter().filter(|(_, h)| h.is_some()).count();
            continue;
        }
        // Brute force: every vertex skinned, every triangle tested.
        check.pose(&character, Some(clip), t);
        check.place(&placement.to_homogeneous());
        check.skin_all(&character, SkinningModel::Linear);
        for (ray, hit) in &hits {
            let nearest = character
                .mesh
                .indices()
                .iter()
                .enumerate()
                .filter_map(|(n, &[a, b, c])| {
                    let p = |v: u32| check.positions[v as usize];
                    ray.triangle_hit(&Triangle::new(p(a), p(b), p(c)))
                        .map(|h| (h.distance, n as u32))
                })
                .min_by(|x, y| x.0.total_cmp(&y.0));
            match (hit, nearest) {
                (None, None) => {}
                (Some(h), Some((d, _))) => {
                    assert_eq!(h.body, BodyRef::Character(walker));
                    assert!(
                        (f64::from(h.distance) - d).abs() <= 1e-6 * d,
                        "{} vs {d}",
                        h.distance
                    );
                    seen.hits += 1;
                }
                (h, n) => panic!("frame {k}: the world says {h:?}, brute force {n:?}"),
            }
            seen.rays += 1;
        }
    }
    seen
}

fn main() {
    let mut args = std::env::args().skip(1);
    let vertices = args.next().and_then(|a| a.parse().ok()).unwrap_or(10_000);
    let frames = args.next().and_then(|a| a.parse().ok()).unwrap_or(30);
    // `unchecked`: only the queries run (for a profiler).
    let check = args.next().as_deref() != Some("unchecked");
    let s = run(vertices, frames, check);
    println!(
        "{} rays at a walker of {vertices} vertices over {frames} frames: {} hits{}; \
         {:.0} µs a frame ({} rays and one at the floor), {:.1} spheres refit and {:.1} vertices skinned per ray",
        s.rays,
        s.hits,
        if check {
            ", each the brute force's"
        } else {
            ""
        },
        s.microseconds_per_frame,
        GRID * GRID,
        s.refits as f64 / s.rays as f64,
        s.skinned as f64 / s.rays as f64,
    );
}

#[test]
fn picking_a_walker_finds_the_brute_force_hits() {
    let s = run(3_000, 6, true);
    assert_eq!(s.rays, 6 * GRID * GRID);
    assert!(s.hits > s.rays / 5, "{} hits of {} rays", s.hits, s.rays);
}
