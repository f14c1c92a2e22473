//! Recordings read back: entity layout, the frame timeline, logged values
//! against the JSON report and the trees, the tested spheres against the
//! timed traversal's visit log, interruption, figures.

mod common;

use std::collections::{BTreeMap, BTreeSet};
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::Scratch;
use common::rrd::{LoggedSphere, Rrd, read_rrd};
use cornertree::big_triangle::hierarchy::MAX_LEVELS;
use cornertree::big_triangle::{Division, DivisionKind};
use cornertree::geometry::Sphere;
use cornertree::mesh::TriangleId;
use cornertree::pipeline::{FrameCounters, Method};
use cornertree::sphere_tree::refit::{OnDemand, RefitState, Refitter};
use cornertree::sphere_tree::{Hierarchy, NodeId, SphereTree, Workspace, traverse};
use cornertree_workbench::record::figures::{dedup_example, example_big_triangle};
use cornertree_workbench::record::layout;
use cornertree_workbench::scenario::{Resolved, open_scenario};
use cornertree_workbench::session::Session;

/// The mesh, skeleton and spheres of the one character of a
/// single-character scenario (its `[character]` section is named
/// `character`).
const AVATAR_MESH: &str = "world/characters/00_character/mesh";
const AVATAR_SKELETON: &str = "world/characters/00_character/skeleton";
const AVATAR_SPHERES: &str = "world/characters/00_character/spheres";
/// The character's and the room's triangles in a reported pair.
const COLLIDING_AVATAR: &str = "cd/colliding/environment/bodies";
const COLLIDING_ROOM: &str = "cd/colliding/environment/room";

fn bin() -> Command {
    Command::new(env!("CARGO_BIN_EXE_cornertree"))
}

fn root() -> &'static Path {
    Path::new(env!("CARGO_MANIFEST_DIR"))
}

fn cesium_scenario() -> PathBuf {
    root().join("scenarios/cesium_man.toml")
}

/// A copy of cesium_man.toml with an absolute asset path and `extra` appended.
fn cesium_variant(scratch: &Scratch, name: &str, extra: &str) -> PathBuf {
    let text = std::fs::read_to_string(cesium_scenario()).unwrap().replace(
        "../assets/CesiumMan.glb",
        root().join("assets/CesiumMan.glb").to_str().unwrap(),
    );
    scratch.write(name, format!("{text}\n{extra}\n"))
}

fn run_ok(args: &[&str], cwd: Option<&Path>) -> String {
    let mut cmd = bin();
    cmd.args(args);
    if let Some(d) = cwd {
        cmd.current_dir(d);
    }
    let o = cmd.output().unwrap();
    assert!(
        o.status.success(),
        "{args:?}: {}",
        String::from_utf8_lossy(&o.stderr)
    );
    String::from_utf8_lossy(&o.stdout).into_owned()
}

fn positions() -> rerun::ComponentIdentifier {
    rerun::Points3D::descriptor_positions().component
}

fn mesh_positions() -> rerun::ComponentIdentifier {
    rerun::Mesh3D::descriptor_vertex_positions().component
}

/// The session `run` builds for `r` with `method` alone.
fn session_of(r: &Resolved, method: Method) -> Session {
    let mut r = r.clone();
    r.methods = vec![method];
    Session::new(r, 1).unwrap()
}

/// The session `run` builds for cesium_man.toml, built here from the library.
fn cesium_session(method: Method) -> (Resolved, Session) {
    let r = open_scenario(&cesium_scenario()).unwrap();
    let s = session_of(&r, method);
    (r, s)
}

/// The character tree of `s`'s one character in its one world.
fn character_tree(s: &Session) -> SphereTree {
    s.world(0)
        .character(s.character(0))
        .unwrap()
        .tree()
        .tree
        .clone()
}

/// The room tree of `s`'s one world.
fn room_tree(s: &Session) -> SphereTree {
    s.world(0).room(s.room()).unwrap().0.tree.clone()
}

fn levels_logged(rrd: &Rrd, root: &str) -> usize {
    rrd.entity_paths()
        .iter()
        .filter(|p| p.starts_with(&format!("{root}/level_")))
        .count()
}

#[test]
fn run_recording_has_the_layout_and_the_reported_values() {
    let scratch = Scratch::new("rec-layout");
    let rrd_path = scratch.path("cm.rrd");
    let json_path = scratch.path("cm.json");
    let frames = 5;
    run_ok(
        &[
            "run",
            cesium_scenario().to_str().unwrap(),
            "--frames",
            &frames.to_string(),
            "--method",
            "plane-sphere",
            "--save",
            rrd_path.to_str().unwrap(),
            "--json",
            json_path.to_str().unwrap(),
        ],
        None,
    );
    let rrd = read_rrd(&rrd_path);
    assert_eq!(rrd.error, None, "the recording decodes to its end");
    assert!(
        rrd.has_blueprint,
        "a blueprint is stored with the recording"
    );
    // The contacts and spheres views open looking at the character's first
    // frame: each eye's look target is the centre of the recorded frame-0
    // mesh's box, the eye far enough out for the box to fit.
    let eyes = rrd.eyes();
    assert_eq!(eyes.len(), 2, "{eyes:?}");
    for &(_, position, target) in &eyes {
        let mesh = rrd.mesh_vertices(AVATAR_MESH, 0);
        assert!(!mesh.is_empty());
        let (mut lo, mut hi) = ([f32::INFINITY; 3], [f32::NEG_INFINITY; 3]);
        for v in &mesh {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
        let diagonal = (0..3).map(|k| (hi[k] - lo[k]).powi(2)).sum::<f32>().sqrt();
        for k in 0..3 {
            let centre = 0.5 * (lo[k] + hi[k]);
            assert!(
                (target[k] - centre).abs() < 1e-3,
                "look target {target:?}, box {lo:?} {hi:?}"
            );
        }
        let distance = (0..3)
            .map(|k| (position[k] - target[k]).powi(2))
            .sum::<f32>()
            .sqrt();
        assert!(
            distance >= diagonal,
            "eye {distance} m from the target, box diagonal {diagonal} m"
        );
    }
    let paths = rrd.entity_paths();
    for p in [
        layout::ENV_MESH,
        AVATAR_MESH,
        AVATAR_SKELETON,
        "world/characters/00_character/spheres/level_00",
        "world/environment/spheres/level_00",
        layout::ENV_SUBDIVISION,
        COLLIDING_AVATAR,
        COLLIDING_ROOM,
        layout::COLLIDING_SPHERES,
        layout::EVENTS,
        layout::FRAME_REPORT,
        layout::INFO,
    ]
    .iter()
    .chain(layout::COUNTER_PATHS.iter())
    .chain(layout::TIME_PATHS.iter())
    {
        assert!(paths.contains(*p), "{p} missing from {paths:?}");
    }

    // The frame timeline holds exactly the frames played.
    let expected: BTreeSet<i64> = (0..frames).collect();
    for p in layout::COUNTER_PATHS {
        assert_eq!(rrd.frames(p), expected, "{p}");
    }
    assert_eq!(rrd.frames(AVATAR_MESH), expected);

    // Logged counters equal the JSON report, frame by frame.
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json_path).unwrap()).unwrap();
    let report_frames = report["frames"].as_array().unwrap();
    let keys = [
        "sphere_sphere",
        "tri_tri",
        "plane_sphere",
        "sphere_box",
        "box_box",
        "operations",
        "refits",
        "skinned_vertices",
    ];
    for (path, key) in layout::COUNTER_PATHS.iter().zip(keys) {
        let logged = rrd.scalars(path);
        for (k, f) in report_frames.iter().enumerate() {
            assert_eq!(
                logged[&(k as i64)],
                f[key].as_u64().unwrap() as f64,
                "{path} frame {k}"
            );
        }
    }
    let pairs_logged = rrd.scalars("stats/pairs");

    // Static scene: the whole environment mesh, once.
    let (resolved, session) = cesium_session(Method::PlaneSphere);
    let env_rows = rrd.rows(layout::ENV_MESH, mesh_positions());
    assert_eq!(
        env_rows,
        vec![(None, resolved.environment.mesh.vertex_count())]
    );
    // The character's mesh every frame, every vertex.
    for (t, n) in rrd.counts_per_frame(AVATAR_MESH, mesh_positions()) {
        assert_eq!(
            n,
            resolved.first().character.mesh.vertex_count(),
            "frame {t}"
        );
    }

    // Character spheres shown = spheres refit this frame (visited on demand).
    let levels = levels_logged(&rrd, AVATAR_SPHERES);
    assert_eq!(levels, character_tree(&session).depth());
    for (k, f) in report_frames.iter().enumerate() {
        let shown: usize = (0..levels)
            .map(|l| {
                rrd.counts_per_frame(&layout::level_path(AVATAR_SPHERES, l), positions())
                    [&(k as i64)]
            })
            .sum();
        assert_eq!(shown as u64, f["refits"].as_u64().unwrap(), "frame {k}");

        // Colliding character triangles: three vertices each, one per distinct triangle.
        let pairs = f["pairs"].as_array().unwrap();
        assert_eq!(pairs.len() as f64, pairs_logged[&(k as i64)]);
        let avatar: BTreeSet<u64> = pairs.iter().map(|p| p[0].as_u64().unwrap()).collect();
        let hit = rrd.counts_per_frame(COLLIDING_AVATAR, mesh_positions());
        assert_eq!(hit[&(k as i64)], 3 * avatar.len(), "frame {k}");
    }
}

#[test]
fn all_spheres_option_logs_every_level_of_both_trees() {
    let scratch = Scratch::new("rec-all");
    let scenario = cesium_variant(&scratch, "all.toml", "[recording]\nall_spheres = true");
    let rrd_path = scratch.path("all.rrd");
    run_ok(
        &[
            "run",
            scenario.to_str().unwrap(),
            "--frames",
            "2",
            "--method",
            "plane-sphere",
            "--save",
            rrd_path.to_str().unwrap(),
        ],
        None,
    );
    let rrd = read_rrd(&rrd_path);
    let (_, session) = cesium_session(Method::PlaneSphere);
    let avatar_levels = character_tree(&session).nodes_per_level();
    assert_eq!(levels_logged(&rrd, AVATAR_SPHERES), avatar_levels.len());
    for (l, &n) in avatar_levels.iter().enumerate() {
        let counts = rrd.counts_per_frame(&layout::level_path(AVATAR_SPHERES, l), positions());
        assert_eq!(counts.len(), 2, "level {l}: every frame");
        assert!(
            counts.values().all(|&c| c == n),
            "level {l}: {counts:?} vs {n}"
        );
    }
    // The recorder refits the whole tree in its own state, for display: on
    // the nodes the measured frame refit, the very same spheres.
    let r = open_scenario(&scenario).unwrap();
    let (_, measured) = measure(&r, Method::PlaneSphere, 2);
    for (k, m) in measured.iter().enumerate() {
        let shown: BTreeSet<LoggedSphere> = (0..avatar_levels.len())
            .flat_map(|l| {
                rrd.points(&layout::level_path(AVATAR_SPHERES, l))
                    .remove(&(k as i64))
                    .unwrap_or_default()
            })
            .collect();
        for s in &m.refit {
            assert!(shown.contains(s), "frame {k}: {s:?}");
        }
    }
    let env_levels = room_tree(&session).nodes_per_level();
    assert_eq!(levels_logged(&rrd, layout::ENV_SPHERES), env_levels.len());
    for (l, &n) in env_levels.iter().enumerate() {
        let rows = rrd.rows(&layout::level_path(layout::ENV_SPHERES, l), positions());
        assert_eq!(rows, vec![(None, n)], "environment level {l} (static)");
    }
}

/// cesium_man.toml with the character 5 cm into the south wall (deepest over the clip): contacts for
/// every method, big triangles at hand.
fn cesium_into_wall(scratch: &Scratch) -> PathBuf {
    let text = std::fs::read_to_string(cesium_scenario()).unwrap();
    assert!(text.contains("metres = 0.01 }"), "{text}");
    let text = text
        .replace(
            "../assets/CesiumMan.glb",
            root().join("assets/CesiumMan.glb").to_str().unwrap(),
        )
        .replace("metres = 0.01 }", "metres = -0.05 }");
    scratch.write("into_wall.toml", text)
}

/// Records `methods` on `scenario` for `frames` frames (no ground truth) and
/// reads each recording back.
fn record(scratch: &Scratch, scenario: &Path, methods: &[Method], frames: usize) -> Vec<Rrd> {
    let save = scratch.path("rec.rrd");
    let frames = frames.to_string();
    let mut args = vec![
        "run",
        scenario.to_str().unwrap(),
        "--frames",
        &frames,
        "--no-truth",
        "--save",
        save.to_str().unwrap(),
    ];
    for m in methods {
        args.extend(["--method", m.name()]);
    }
    run_ok(&args, None);
    methods
        .iter()
        .map(|m| {
            let file = if methods.len() == 1 {
                save.clone()
            } else {
                scratch.path(&format!("rec-{}.rrd", m.name()))
            };
            let rrd = read_rrd(&file);
            assert_eq!(rrd.error, None, "{m}");
            rrd
        })
        .collect()
}

/// One frame as measured in this process, through the pipeline's visit log.
struct Measured {
    counters: FrameCounters,
    /// Environment nodes the timed traversal tested (its log).
    tested: BTreeSet<u32>,
    /// Environment nodes an unguarded traversal of the same pose tests, and
    /// its number of sphere-sphere tests.
    unguarded: BTreeSet<u32>,
    unguarded_tests: u64,
    /// The character's root sphere and every sphere refit this frame.
    root: Sphere,
    refit: Vec<LoggedSphere>,
}

fn logged(s: &Sphere) -> LoggedSphere {
    (
        [s.center.x, s.center.y, s.center.z].map(f32::to_bits),
        s.radius.to_bits(),
    )
}

/// The environment tree, marking every node whose sphere is tested.
struct Marking<'a> {
    tree: &'a SphereTree,
    marked: BTreeSet<u32>,
}

impl Hierarchy for Marking<'_> {
    fn tree(&self) -> &SphereTree {
        self.tree
    }
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.tree.node(id).sphere
    }
    fn tested(&mut self, id: NodeId) {
        self.marked.insert(id.0);
    }
}

/// Plays `frames` frames of `method` with the visit log on, checking each
/// frame's log against the counters; beside it, the unguarded traversal of
/// the same pose with a refit state of its own. Returns the session (with
/// its one world) and the frames.
fn measure(r: &Resolved, method: Method, frames: usize) -> (Session, Vec<Measured>) {
    let mut session = session_of(r, method);
    session.world_mut(0).set_visit_log(true);
    let (h, room) = (session.character(0), session.room());
    let ctree = session.world(0).character(h).unwrap().tree().clone();
    let env_tree = room_tree(&session);
    let mut own = RefitState::new(&ctree, r.first().character.skeleton.len());
    let mut ws = Workspace::new();
    let parents = env_tree.parents();
    let mut out = Vec::new();
    for k in 0..frames {
        session.pose(k);
        session.detect(0);
        let counters = session.contacts(0).total;
        let view = session.world(0).character(h).unwrap();
        let log = view.visit_log(room).expect("the log is on");
        let tested: BTreeSet<u32> = log.tested_nodes().map(|n| n.0).collect();
        for n in &tested {
            assert!(log.is_tested(NodeId(*n)));
        }
        // The log saw every sphere-sphere test the counters count, each
        // involving one environment node; the root pair's test among them.
        assert_eq!(
            log.sphere_tests(),
            counters.sphere_sphere,
            "{method} frame {k}"
        );
        assert!(tested.contains(&0), "{method} frame {k}: the root pair");
        assert!(tested.len() as u64 <= counters.sphere_sphere);
        // A node is tested only below a tested parent, and every leaf pair
        // handed to the narrow phase passed a test of its environment leaf.
        for &n in &tested {
            if n != 0 {
                assert!(tested.contains(&parents[n as usize]), "{method}: {n}");
            }
        }
        for lp in view.room_leaf_pairs(room) {
            assert!(
                tested.contains(&lp.leaf_b.0),
                "{method}: leaf {:?}",
                lp.leaf_b
            );
        }

        let pose = view.pose();
        own.begin_frame_with_base(pose.skin, pose.base);
        let mut character = OnDemand {
            refitter: Refitter {
                tree: &ctree,
                skin: pose.skin,
                state: &mut own,
            },
            base: *pose.base,
        };
        let mut marking = Marking {
            tree: &env_tree,
            marked: BTreeSet::new(),
        };
        let unguarded = traverse(&mut character, &mut marking, &mut ws, |_| {});

        let state = view.refit_state();
        let refit: Vec<LoggedSphere> = (0..state.spheres.len())
            .filter(|&i| state.is_fresh(NodeId(i as u32)))
            .map(|i| logged(&state.spheres[i]))
            .collect();
        // Refit ahead and never asked for: refit, not fresh.
        let unused = state.refits_ahead_unused();
        assert_eq!(refit.len() as u64, counters.refits - unused);
        out.push(Measured {
            counters,
            tested,
            unguarded: marking.marked,
            unguarded_tests: unguarded.sphere_tests,
            root: state.spheres[0],
            refit,
        });
    }
    (session, out)
}

/// Level of every node (the root is 0), from the parent links.
fn levels(tree: &SphereTree) -> Vec<usize> {
    let parents = tree.parents();
    let mut level = vec![0; tree.len()];
    for i in 1..tree.len() {
        level[i] = level[parents[i] as usize] + 1;
    }
    level
}

/// What the recording should show of a set of environment nodes: per level,
/// those up to half the character's root radius that meet its root sphere
/// (docs/recordings.md, `world/environment/spheres/level_{kk}`).
fn shown(
    tree: &SphereTree,
    nodes: &BTreeSet<u32>,
    root: &Sphere,
) -> BTreeMap<usize, Vec<LoggedSphere>> {
    let level = levels(tree);
    let mut out: BTreeMap<usize, Vec<LoggedSphere>> = BTreeMap::new();
    for &n in nodes {
        let s = tree.node(NodeId(n)).sphere;
        if s.radius <= 0.5 * root.radius && s.overlaps(root) {
            out.entry(level[n as usize]).or_default().push(logged(&s));
        }
    }
    for v in out.values_mut() {
        v.sort_unstable();
    }
    out
}

/// The environment spheres a recording shows at frame `k`, per level.
fn recorded_env(rrd: &Rrd, levels: usize, k: usize) -> BTreeMap<usize, Vec<LoggedSphere>> {
    (0..levels)
        .filter_map(|l| {
            let v = rrd
                .ellipsoids(&layout::level_path(layout::ENV_SPHERES, l))
                .remove(&(k as i64))
                .unwrap_or_default();
            (!v.is_empty()).then_some((l, v))
        })
        .collect()
}

#[test]
fn recorded_tested_spheres_are_the_timed_traversals_for_every_method() {
    let scratch = Scratch::new("rec-tested");
    let scenario = cesium_into_wall(&scratch);
    let frames = 4;
    let recordings = record(&scratch, &scenario, &Method::ALL, frames);
    let r = open_scenario(&scenario).unwrap();
    for (&method, rrd) in Method::ALL.iter().zip(&recordings) {
        let (session, measured) = measure(&r, method, frames);
        let env_tree = &room_tree(&session);
        let env_levels = env_tree.depth();
        let avatar_levels = character_tree(&session).depth();
        let ss = rrd.scalars("stats/tests/sphere_sphere");
        let mut seen = 0;
        let mut pruned_tests = false;
        for (k, m) in measured.iter().enumerate() {
            // The recorded run played the same frames as this process.
            assert_eq!(
                ss[&(k as i64)],
                m.counters.sphere_sphere as f64,
                "{method} frame {k}"
            );
            // The plane guard drops a pair only at a big triangle's division
            // leaf, whose sphere has just been tested, and the pairs below it
            // hold that same leaf: it prunes tests (and character spheres),
            // never an environment node the unguarded traversal tests. The
            // node boxes of the methods that test each pair once also drop
            // pairs at inner nodes: their nodes are some of the unguarded
            // traversal's.
            if method.tests_each_pair_once() {
                assert!(m.tested.is_subset(&m.unguarded), "{method} frame {k}");
            } else {
                assert_eq!(m.tested, m.unguarded, "{method} frame {k}");
            }
            if method.prunes_at_plane() {
                assert!(m.counters.sphere_sphere <= m.unguarded_tests);
                pruned_tests |= m.counters.sphere_sphere < m.unguarded_tests;
            } else {
                assert_eq!(m.counters.sphere_sphere, m.unguarded_tests);
            }
            let expected = shown(env_tree, &m.tested, &m.root);
            assert_eq!(
                recorded_env(rrd, env_levels, k),
                expected,
                "{method} frame {k}: recorded environment spheres"
            );
            seen += expected.values().map(Vec::len).sum::<usize>();

            // Character spheres: exactly those the measured frame refit.
            let mut avatar: Vec<LoggedSphere> = (0..avatar_levels)
                .flat_map(|l| {
                    rrd.points(&layout::level_path(AVATAR_SPHERES, l))
                        .remove(&(k as i64))
                        .unwrap_or_default()
                })
                .collect();
            avatar.sort_unstable();
            let mut refit = m.refit.clone();
            refit.sort_unstable();
            assert_eq!(avatar, refit, "{method} frame {k}: character spheres");
        }
        assert!(
            measured.iter().any(|m| m.counters.pairs > 0),
            "{method}: contacts"
        );
        assert_eq!(
            pruned_tests,
            method.prunes_at_plane(),
            "{method}: the guard saves tests on some frame"
        );
        // Without a split (no division, or a whole one) the wall is one
        // sphere far bigger than the character, hidden by the display rule.
        let splits = method.division().is_some_and(|k| k != DivisionKind::Whole);
        assert_eq!(
            seen > 0,
            splits,
            "{method}: tested spheres shown near the character"
        );
    }
}

#[test]
fn default_recording_goes_to_the_recordings_directory() {
    let scratch = Scratch::new("rec-default");
    let out = run_ok(
        &[
            "run",
            cesium_scenario().to_str().unwrap(),
            "--frames",
            "2",
            "--method",
            "original",
        ],
        Some(scratch.dir()),
    );
    let file = scratch.dir().join("recordings/cesium_man-original.rrd");
    assert!(file.is_file(), "{out}");
    assert!(
        out.contains("recording: recordings/cesium_man-original.rrd ("),
        "says where: {out}"
    );
    assert_eq!(read_rrd(&file).frames("stats/operations").len(), 2);
}

/// Starts a long run and waits until its recording holds a few frames.
fn start_long_run(scratch: &Scratch, name: &str) -> (std::process::Child, PathBuf, PathBuf) {
    let rrd = scratch.path(&format!("{name}.rrd"));
    let json = scratch.path(&format!("{name}.json"));
    let child = bin()
        .args([
            "run",
            cesium_scenario().to_str().unwrap(),
            "--frames",
            "100000",
            "--method",
            "plane-sphere",
            "--save",
            rrd.to_str().unwrap(),
            "--json",
            json.to_str().unwrap(),
        ])
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    loop {
        if rrd.is_file() && read_rrd(&rrd).frames("stats/operations").len() >= 3 {
            break;
        }
        assert!(
            t0.elapsed() < Duration::from_secs(120),
            "no frames recorded"
        );
        std::thread::sleep(Duration::from_millis(100));
    }
    (child, rrd, json)
}

fn signal(child: &std::process::Child, sig: &str) {
    let ok = Command::new("kill")
        .args([sig, &child.id().to_string()])
        .status()
        .unwrap();
    assert!(ok.success());
}

#[test]
fn ctrl_c_ends_with_the_summary_and_a_complete_recording() {
    let scratch = Scratch::new("rec-sigint");
    let (child, rrd, json) = start_long_run(&scratch, "int");
    signal(&child, "-INT");
    let o = child.wait_with_output().unwrap();
    let stdout = String::from_utf8_lossy(&o.stdout);
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    assert!(stdout.contains("interrupted (Ctrl-C) after"), "{stdout}");
    assert!(stdout.contains("Operations"), "summary table: {stdout}");
    let report: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let played = report["frames"].as_array().unwrap().len();
    let rec = read_rrd(&rrd);
    assert_eq!(rec.error, None, "complete recording");
    let frames = rec.frames("stats/operations");
    assert_eq!(
        frames,
        (0..played as i64).collect(),
        "every frame played is recorded"
    );
}

#[test]
fn a_killed_run_leaves_a_readable_recording() {
    let scratch = Scratch::new("rec-sigkill");
    let (mut child, rrd, _) = start_long_run(&scratch, "kill");
    signal(&child, "-KILL");
    child.wait().unwrap();
    let rec = read_rrd(&rrd);
    let frames = rec.frames("stats/operations");
    assert!(frames.len() >= 3, "frames before the kill: {frames:?}");
    assert_eq!(frames, (0..frames.len() as i64).collect(), "no gaps");
    assert!(rec.entity_paths().contains(layout::ENV_MESH));
}

#[test]
fn figures_reproduce_the_papers_constructions() {
    let scratch = Scratch::new("rec-figures");
    let out = run_ok(&["figures", "--out", scratch.dir().to_str().unwrap()], None);
    for f in [
        "figure1_dedup.rrd",
        "figure2_sphere_division.rrd",
        "figure3_corner_tree.rrd",
    ] {
        assert!(out.contains(f), "{out}");
        let r = read_rrd(&scratch.dir().join(f));
        assert_eq!(r.error, None, "{f}");
        assert!(r.has_blueprint, "{f}");
    }

    // Figure 1: one red triangle, three neighbours.
    let f1 = read_rrd(&scratch.dir().join("figure1_dedup.rrd"));
    assert_eq!(f1.rows("world/left_out", mesh_positions()), vec![(None, 3)]);
    for k in 1..=3 {
        assert_eq!(
            f1.rows(&format!("world/kept_neighbour_{k}"), mesh_positions()),
            vec![(None, 3)]
        );
    }

    // Figure 2: the enclosing sphere and four sub-spheres.
    let f2 = read_rrd(&scratch.dir().join("figure2_sphere_division.rrd"));
    let centers = rerun::Ellipsoids3D::descriptor_centers().component;
    assert_eq!(f2.rows("world/spheres/enclosing", centers), vec![(None, 1)]);
    assert_eq!(f2.rows("world/spheres/sub", centers), vec![(None, 4)]);

    // Figure 3: one step per level; the spheres of each level are the
    // corner-tree's nodes of that level.
    let f3 = read_rrd(&scratch.dir().join("figure3_corner_tree.rrd"));
    let d = Division::build(
        &example_big_triangle(),
        TriangleId(0),
        DivisionKind::Corner,
        0.15,
        MAX_LEVELS,
    );
    let per_level = d.nodes_per_level();
    assert!(per_level.len() >= 4, "{per_level:?}");
    let rows = f3.rows_on("level", "world/spheres", centers);
    let logged: Vec<usize> = rows.iter().map(|&(_, n)| n).collect();
    assert_eq!(logged, per_level);
    let levels: Vec<Option<i64>> = rows.iter().map(|&(t, _)| t).collect();
    assert_eq!(
        levels,
        (0..per_level.len() as i64).map(Some).collect::<Vec<_>>()
    );
}

#[test]
fn figure1_triangle_is_covered_by_its_three_neighbours() {
    let c = cornertree_workbench::humanoid::generate_humanoid(
        &cornertree_workbench::humanoid::HumanoidParams {
            vertices: 3000,
            seed: 1,
        },
    )
    .unwrap();
    let mesh = &c.mesh;
    let (t, n) = dedup_example(mesh).expect("an example exists");
    let dedup = cornertree::mesh::dedup_edges(mesh);
    assert!(!dedup.is_kept(t));
    // Independently of the de-duplication code: each edge of `t`, as a pair of
    // positions, is an edge of a different kept neighbour.
    let key = |p: &cornertree::geometry::Point| [p.x.to_bits(), p.y.to_bits(), p.z.to_bits()];
    let edges = |id: TriangleId| {
        let tr = mesh.triangle(id);
        let v = [key(&tr.a), key(&tr.b), key(&tr.c)];
        [(v[0], v[1]), (v[1], v[2]), (v[2], v[0])].map(|(a, b)| (a.min(b), a.max(b)))
    };
    let mine = edges(t);
    for (k, e) in mine.iter().enumerate() {
        assert!(dedup.is_kept(n[k]));
        assert!(edges(n[k]).contains(e), "neighbour {k} lacks edge {k}");
    }
    let distinct: BTreeSet<u32> = n.iter().map(|x| x.0).collect();
    assert_eq!(distinct.len(), 3);
}

#[test]
fn stdout_streams_one_method_and_refuses_several() {
    let scratch = Scratch::new("rec-stdout");
    let o = bin()
        .args([
            "run",
            cesium_scenario().to_str().unwrap(),
            "--frames",
            "2",
            "--method",
            "original",
            "--stdout",
        ])
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
    let file = scratch.write("piped.rrd", &o.stdout);
    let rec = read_rrd(&file);
    assert_eq!(rec.error, None, "standard output holds the recording only");
    assert_eq!(rec.frames("stats/operations").len(), 2);
    assert!(
        String::from_utf8_lossy(&o.stderr).contains("Operations"),
        "summary on stderr"
    );

    let o = bin()
        .args([
            "run",
            cesium_scenario().to_str().unwrap(),
            "--frames",
            "2",
            "--stdout",
        ])
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1));
    assert!(String::from_utf8_lossy(&o.stderr).contains("--stdout carries one recording"));
}
