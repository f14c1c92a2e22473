//! A character against itself: the world's self pairs equal the exact
//! oracle's on every frame of every clip at 30 fps (the workbench's truth:
//! parry's BVH of the posed mesh against itself for candidates, neighbours
//! dropped, the exact triangle-triangle predicate), for the trees of
//! several methods and both skinning models; the rigid-part culling changes
//! no pair, only the work. The oracle itself is checked against a brute
//! force over every pair of triangles on some frames.

use std::path::Path;
use std::sync::Arc;

use cornertree::character::{Character, PoseBuffers, SkinningModel};
use cornertree::geometry::exact::triangles_intersect_exact;
use cornertree::geometry::{Point, Triangle};
use cornertree::io::load_character;
use cornertree::mesh::dedup::weld_positions;
use cornertree::pipeline::Method;
use cornertree::world::{CharacterHandle, CharacterModel, CollisionWorld, WorldSettings};
use cornertree_workbench::humanoid::{HumanoidParams, generate_humanoid};
use cornertree_workbench::truth::self_truth::SelfTruth;

fn asset(name: &str) -> Character {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("assets")
        .join(name);
    load_character(&path).unwrap_or_else(|e| panic!("{e}")).0
}

/// Every pair of triangles sharing no welded corner that the exact
/// predicate says touch, lower index first, sorted: boxes swept along `x`,
/// then the predicate.
fn brute_force(c: &Character, posed: &[Point]) -> Vec<(u32, u32)> {
    let weld = weld_positions(&c.mesh);
    let tris: Vec<([u32; 3], Triangle, [f32; 6])> = c
        .mesh
        .indices()
        .iter()
        .map(|t| {
            let [a, b, d] = t.map(|v| posed[v as usize]);
            let lo = [
                a.x.min(b.x).min(d.x),
                a.y.min(b.y).min(d.y),
                a.z.min(b.z).min(d.z),
            ];
            let hi = [
                a.x.max(b.x).max(d.x),
                a.y.max(b.y).max(d.y),
                a.z.max(b.z).max(d.z),
            ];
            (
                t.map(|v| weld[v as usize]),
                Triangle::new(a, b, d),
                [lo[0], lo[1], lo[2], hi[0], hi[1], hi[2]],
            )
        })
        .collect();
    let mut order: Vec<usize> = (0..tris.len()).collect();
    order.sort_by(|&i, &j| tris[i].2[0].total_cmp(&tris[j].2[0]));
    let mut out = Vec::new();
    for (k, &i) in order.iter().enumerate() {
        let bi = tris[i].2;
        for &j in &order[k + 1..] {
            let bj = tris[j].2;
            if bj[0] > bi[3] {
                break;
            }
            if bj[1] > bi[4] || bi[1] > bj[4] || bj[2] > bi[5] || bi[2] > bj[5] {
                continue;
            }
            if tris[i].0.iter().any(|v| tris[j].0.contains(v)) {
                continue;
            }
            if triangles_intersect_exact(&tris[i].1, &tris[j].1) {
                out.push((i.min(j) as u32, i.max(j) as u32));
            }
        }
    }
    out.sort_unstable();
    out
}

/// Steps `character` through every frame of each clip at 30 fps (every
/// `stride`-th) in worlds of every method given (culling on; for the first
/// also with normal cones, and with no culling), and checks each world's
/// self pairs against the oracle, and
/// the oracle against the brute force on `brute` frames spread over each
/// clip. Returns the frames that had self-contact and the pairs found.
fn check(
    character: Character,
    model: SkinningModel,
    methods: &[Method],
    stride: usize,
    brute: usize,
) -> (usize, usize) {
    let character = Arc::new(character);
    let cm = Arc::new(CharacterModel::new(character.clone(), model).unwrap());
    let settings = |cull, cones| WorldSettings {
        self_collision: true,
        self_rigid_culling: cull,
        self_normal_cone_culling: cones,
        time_refit: false,
        ..WorldSettings::default()
    };
    let mut worlds: Vec<(String, CollisionWorld)> = methods
        .iter()
        .map(|&m| {
            (
                m.to_string(),
                CollisionWorld::with_settings(m, settings(true, false)),
            )
        })
        .collect();
    worlds.push((
        format!("{} with normal cones", methods[0]),
        CollisionWorld::with_settings(methods[0], settings(true, true)),
    ));
    worlds.push((
        format!("{} without culling", methods[0]),
        CollisionWorld::with_settings(methods[0], settings(false, false)),
    ));
    for (_, w) in &mut worlds {
        w.add_character(cm.clone()).unwrap();
    }
    let mut pose = PoseBuffers::new(&character);
    let mut posed = vec![Point::origin(); character.mesh.vertex_count()];
    let mut oracle = SelfTruth::new(&character.mesh).unwrap();
    let (mut touching, mut pairs) = (0, 0);
    // Sphere tests of the first method's world, with and without normal
    // cones, over the whole run.
    let (mut rigid_only, mut with_cones) = (0u64, 0u64);
    for clip in &character.clips {
        let frames = (clip.duration() * 30.0).floor() as usize + 1;
        let checked: Vec<usize> = (0..frames).step_by(stride).collect();
        let brute_at: Vec<usize> = (0..brute)
            .map(|b| checked[b * (checked.len() - 1) / (brute - 1).max(1)])
            .collect();
        for f in checked {
            let t = clip.start() + f as f32 / 30.0;
            pose.pose(&character, Some(clip), t);
            pose.skin_all_into(&character, model, &mut posed);
            oracle.update(&posed).unwrap();
            let expect = oracle.exact.clone();
            if brute_at.contains(&f) {
                assert_eq!(
                    expect,
                    brute_force(&character, &posed),
                    "{} clip {} frame {f}: the oracle against brute force",
                    character.name,
                    clip.name
                );
            }
            touching += usize::from(!expect.is_empty());
            pairs += expect.len();
            let mut tests = Vec::new();
            for (name, w) in &mut worlds {
                w.set_pose(CharacterHandle(0), &pose).unwrap();
                let got: Vec<(u32, u32)> = w
                    .step()
                    .self_pairs
                    .iter()
                    .map(|p| (p.triangle_a, p.triangle_b))
                    .collect();
                assert_eq!(
                    got, expect,
                    "{}, {model}, {name}, clip {} frame {f}",
                    character.name, clip.name
                );
                tests.push(w.contacts().by_kind.self_contact.sphere_sphere);
            }
            // Culling only ever saves work.
            let n = tests.len();
            assert!(tests[0] <= tests[n - 1] && tests[n - 2] <= tests[0]);
            rigid_only += tests[0];
            with_cones += tests[n - 2];
        }
    }
    // The normal cones proved something (so the comparison above tested
    // their culling, not a pass that never skips).
    assert!(
        with_cones < rigid_only,
        "{}: normal cones saved no sphere test ({with_cones} against {rigid_only})",
        character.name
    );
    (touching, pairs)
}

#[test]
fn generated_humanoid_self_pairs_equal_the_oracle() {
    for model in [SkinningModel::Linear, SkinningModel::Paper] {
        let h = generate_humanoid(&HumanoidParams {
            vertices: 3000,
            seed: 5,
        })
        .unwrap();
        let (touching, pairs) = check(
            h,
            model,
            &[Method::Original, Method::UndividedPrunedTriTri],
            1,
            2,
        );
        eprintln!("humanoid, {model}: {touching} frames touching, {pairs} pairs");
    }
}

#[test]
fn cesium_man_self_pairs_equal_the_oracle() {
    let (touching, pairs) = check(
        asset("CesiumMan.glb"),
        SkinningModel::Linear,
        &[Method::Original, Method::UndividedPrunedTriTri],
        1,
        3,
    );
    eprintln!("CesiumMan: {touching} frames touching, {pairs} pairs");
}

/// A stride from the environment, or `default`: BrainStem's 34k vertices
/// make every frame of its clip a few minutes unoptimised
/// (`CORNERTREE_BRAINSTEM_STRIDE=1` for all of them).
fn stride_of(var: &str, default: usize) -> usize {
    std::env::var(var)
        .ok()
        .and_then(|s| s.parse().ok())
        .filter(|&s| s > 0)
        .unwrap_or(default)
}

#[test]
fn brain_stem_self_pairs_equal_the_oracle() {
    let (touching, pairs) = check(
        asset("BrainStem.glb"),
        SkinningModel::Linear,
        &[Method::UndividedPrunedTriTri],
        stride_of("CORNERTREE_BRAINSTEM_STRIDE", 32),
        2,
    );
    eprintln!("BrainStem: {touching} frames touching, {pairs} pairs");
}

/// Continuous detection of a character against itself skips parts one
/// joint moves over each step (bounded through the blend of the step's two
/// matrices) and loses nothing: the same self pairs with the same times of
/// impact as without the culling, on every step of the arm swinging
/// through the chest, with fewer sphere tests.
#[test]
fn self_sweeps_skip_parts_one_joint_moves_and_keep_every_pair() {
    let character = Arc::new(
        generate_humanoid(&HumanoidParams {
            vertices: 3000,
            seed: 5,
        })
        .unwrap(),
    );
    let clip = character
        .clips
        .iter()
        .find(|c| c.name == "swing-through")
        .expect("the humanoid has a swing-through clip");
    let model = SkinningModel::Linear;
    let cm = Arc::new(CharacterModel::new(character.clone(), model).unwrap());
    let mut runs = Vec::new();
    for cull in [true, false] {
        let mut w = CollisionWorld::with_settings(
            Method::UndividedPrunedTriTri,
            WorldSettings {
                self_collision: true,
                self_rigid_culling: cull,
                time_refit: false,
                ..WorldSettings::default()
            },
        );
        w.add_character(cm.clone()).unwrap();
        w.enable_continuous(cornertree::geometry::ccd_params::CcdParams::default());
        let mut pose = PoseBuffers::new(&character);
        let (mut pairs, mut tests) = (Vec::new(), 0u64);
        let steps = (clip.duration() * 10.0).ceil() as usize;
        for k in 0..=steps {
            pose.pose(&character, Some(clip), clip.start() + k as f32 / 10.0);
            w.set_pose(CharacterHandle(0), &pose).unwrap();
            let s = w.sweep().unwrap();
            tests += s.by_kind.self_contact.sphere_sphere;
            pairs.push(
                s.self_pairs
                    .iter()
                    .map(|p| (p.pair.triangle_a, p.pair.triangle_b, p.toi.to_bits()))
                    .collect::<Vec<_>>(),
            );
        }
        runs.push((pairs, tests));
    }
    let ((culled, culled_tests), (all, all_tests)) = (&runs[0], &runs[1]);
    assert!(all.iter().any(|s| !s.is_empty()), "no self-contact swept");
    for (k, (c, a)) in culled.iter().zip(all).enumerate() {
        assert_eq!(c, a, "step {k}");
    }
    assert!(
        culled_tests < all_tests,
        "the culling saved nothing: {culled_tests} against {all_tests} sphere tests"
    );
    eprintln!("swept self: {culled_tests} sphere tests culled, {all_tests} without");
}
