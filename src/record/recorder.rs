//! The recording of one method playing a scenario, one character or a
//! world of many (layout in docs/recordings.md; paths in [`super::layout`]):
//! the room, every body (characters' meshes, skeletons and refit spheres per
//! level; objects' meshes and spheres in their own frame, moved by their
//! pose), the room's spheres and sub-triangles the timed traversal tested,
//! the colliding triangles coloured by pair kind, counters in total and per
//! kind, and with the ground truth the false positives and negatives of
//! every kind with precision and recall.
//!
//! Bodies are grouped under `world/characters/` and `world/objects/`, one
//! entity per body (never one per sphere or triangle), so a crowd stays one
//! entity tree the blueprint shows through wildcards.

use nalgebra::{Isometry3, Matrix4};
use rerun::RecordingStream;

use super::draw::{
    body_entity, kind_color, level_count, mesh3d, p3, points, spheres_by_level, wireframes,
};
use super::layout::{self, Rgba};
use crate::scenario::Resolved;
use crate::session::Session;
use crate::truth::{MethodTruth, Truth, WorldPairs};
use cornertree::character::{JointId, PoseBuffers};
use cornertree::geometry::Point;
use cornertree::pipeline::{FrameCounters, LeafTest};
use cornertree::sphere_tree::NodeId;
use cornertree::sphere_tree::refit::{RefitState, Refitter};
use cornertree::world::{CharacterPair, ObjectPair, PairKind, RoomPair, SelfPair, StepContacts};

/// What to put in a run's recording.
#[derive(Clone, Copy, Debug)]
pub struct RecordOptions {
    /// Every sphere of every level each frame, not only those the traversal
    /// reached (the room's once, as static data; the characters' refit by
    /// the recorder in its own state, for display).
    pub all_spheres: bool,
    /// Log the characters' meshes every this many frames.
    pub mesh_every: u32,
    /// Log spheres and sub-triangles every this many frames (the skeletons,
    /// the colliding pairs and the counters go in every frame).
    pub spheres_every: u32,
}

impl Default for RecordOptions {
    fn default() -> Self {
        Self {
            all_spheres: false,
            mesh_every: 1,
            spheres_every: 1,
        }
    }
}

/// Text shown beside the scene: what was run.
pub struct SceneInfo<'a> {
    pub scenario: &'a str,
    /// Markdown describing the scenario.
    pub markdown: String,
}

/// Each character's entity path under `world/characters`.
pub fn character_paths(scene: &Resolved) -> Vec<String> {
    scene
        .characters
        .iter()
        .enumerate()
        .map(|(i, a)| format!("{}/{}", layout::WORLD_CHARACTERS, body_entity(i, &a.name)))
        .collect()
}

/// Each object's entity path under `world/objects`.
pub fn object_paths(scene: &Resolved) -> Vec<String> {
    scene
        .objects
        .iter()
        .enumerate()
        .map(|(i, o)| format!("{}/{}", layout::WORLD_OBJECTS, body_entity(i, &o.name)))
        .collect()
}

/// One character's tree as the recorder draws it.
struct CharacterLevels {
    /// The level of each node, and the number of levels.
    levels: Vec<u8>,
    count: usize,
    /// The leaf node of each mesh triangle (`u32::MAX` if left out).
    leaf_of_triangle: Vec<u32>,
    /// With `all_spheres`: the recorder's own refit of the whole tree (the
    /// world's state holds what the measured frame refit, and is never
    /// touched here).
    display_refit: Option<RefitState>,
}

/// Writes one method's frames to a recording stream.
pub struct Recorder {
    rec: RecordingStream,
    options: RecordOptions,
    method: &'static str,
    /// Index of the method's world in the session.
    m: usize,
    characters: Vec<String>,
    objects: Vec<String>,
    trees: Vec<CharacterLevels>,
    room_levels: Vec<u8>,
    room_level_count: usize,
    had_contact: [bool; PairKind::ALL.len()],
    max_operations: u64,
    frames_logged: usize,
    // Scratch, reused every frame: per body, its triangles to show; per
    // room node, whether its sphere and its sub-triangle are shown.
    hits: Vec<Vec<u32>>,
    shown_spheres: Vec<bool>,
    shown_pieces: Vec<bool>,
}

impl Recorder {
    /// Logs the static scene (the room, every character's triangles, every
    /// object's mesh and spheres per level in its own frame, series names,
    /// the scenario's description) for the method `m` of `session`, and
    /// turns on its world's visit logs: the room spheres recorded as tested
    /// are those its timed traversal marks.
    pub fn new(
        rec: RecordingStream,
        options: RecordOptions,
        info: &SceneInfo<'_>,
        session: &mut Session,
        m: usize,
    ) -> rerun::RecordingStreamResult<Self> {
        session.world_mut(m).set_visit_log(true);
        let scene = &session.scene;
        let world = session.world(m);
        let characters = character_paths(scene);
        let objects = object_paths(scene);
        // Y up, on the views' origin (`/`: its camera and grid follow it)
        // and on `world`.
        rec.log_static("/", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        rec.log_static(layout::WORLD, &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        let room = &scene.environment.mesh;
        rec.log_static(
            layout::ENV_MESH,
            &mesh3d(room.positions(), room.indices(), layout::ENV_COLOR),
        )?;
        let mut trees = Vec::new();
        for (i, (path, a)) in characters.iter().zip(&scene.characters).enumerate() {
            rec.log_static(
                format!("{path}/mesh"),
                &rerun::Mesh3D::update_fields()
                    .with_triangle_indices(a.character.mesh.indices().iter().copied())
                    .with_albedo_factor(layout::AVATAR_COLOR),
            )?;
            let view = world
                .character(session.character(i))
                .expect("the session's character");
            let tree = &view.tree().tree;
            let levels = layout::node_levels(tree);
            let mut leaf_of_triangle = vec![u32::MAX; a.character.mesh.triangle_count()];
            for (n, node) in tree.nodes().iter().enumerate() {
                if let Some(p) = node.primitive() {
                    leaf_of_triangle[p as usize] = n as u32;
                }
            }
            trees.push(CharacterLevels {
                count: level_count(&levels),
                levels,
                leaf_of_triangle,
                display_refit: options
                    .all_spheres
                    .then(|| RefitState::new(view.tree(), a.character.skeleton.len())),
            });
        }
        for (o, (path, prop)) in objects.iter().zip(&scene.objects).enumerate() {
            rec.log_static(
                format!("{path}/mesh"),
                &mesh3d(
                    prop.mesh.positions(),
                    prop.mesh.indices(),
                    layout::OBJECT_COLOR,
                ),
            )?;
            let (tree, _, _) = world
                .object(session.object(o))
                .expect("the session's object");
            let lv = layout::node_levels(&tree.tree);
            let n = level_count(&lv);
            for (level, (c, r)) in
                spheres_by_level(tree.tree.nodes().iter().map(|n| n.sphere), &lv, n, |_| true)
                    .into_iter()
                    .enumerate()
            {
                rec.log_static(
                    layout::level_path(&format!("{path}/spheres"), level),
                    &wireframes(c, r, layout::level_color(level, n)),
                )?;
            }
        }
        let (room_tree, _) = world.room(session.room()).expect("the session's room");
        let room_levels = layout::node_levels(&room_tree.tree);
        let room_level_count = level_count(&room_levels);
        if options.all_spheres {
            for (level, (c, r)) in spheres_by_level(
                room_tree.tree.nodes().iter().map(|n| n.sphere),
                &room_levels,
                room_level_count,
                |_| true,
            )
            .into_iter()
            .enumerate()
            {
                rec.log_static(
                    layout::level_path(layout::ENV_SPHERES, level),
                    &points(c, r, layout::level_color(level, room_level_count)),
                )?;
            }
        }
        rec.log_static(
            layout::INFO,
            &rerun::TextDocument::new(info.markdown.clone())
                .with_media_type(rerun::MediaType::markdown()),
        )?;
        log_series_names(&rec)?;
        let r = Self {
            rec,
            options,
            method: world.method().name(),
            m,
            hits: vec![Vec::new(); characters.len() + objects.len() + 1],
            shown_spheres: vec![false; room_tree.tree.len()],
            shown_pieces: vec![false; room_tree.tree.len()],
            characters,
            objects,
            trees,
            room_levels,
            room_level_count,
            had_contact: [false; PairKind::ALL.len()],
            max_operations: 0,
            frames_logged: 0,
        };
        r.event(
            "INFO",
            &format!("{}: method {} starts", info.scenario, r.method),
        )?;
        Ok(r)
    }

    /// Frames written so far.
    pub fn frames_logged(&self) -> usize {
        self.frames_logged
    }

    /// The stream (for flushing or extra events).
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    /// Logs a line to the `events` text log at the current time.
    pub fn event(&self, level: &str, text: &str) -> rerun::RecordingStreamResult<()> {
        self.rec
            .log(layout::EVENTS, &rerun::TextLog::new(text).with_level(level))
    }

    /// Logs frame `k` (clip or world time `t`) after the method stepped on
    /// it: `session.buffers` skinned (every vertex). Reads the world's
    /// contacts and state; changes nothing in them.
    pub fn log_frame(
        &mut self,
        k: usize,
        t: f32,
        session: &Session,
    ) -> rerun::RecordingStreamResult<()> {
        let rec = &self.rec;
        rec.set_time_sequence(layout::FRAME, k as i64);
        rec.set_duration_secs(layout::CLIP_TIME, t as f64);
        let scene = &session.scene;
        let mesh_now = k.is_multiple_of(self.options.mesh_every.max(1) as usize);
        for ((path, a), b) in self
            .characters
            .iter()
            .zip(&scene.characters)
            .zip(&session.buffers)
        {
            if mesh_now {
                rec.log(
                    format!("{path}/mesh"),
                    &rerun::Mesh3D::update_fields()
                        .with_vertex_positions(b.positions.iter().map(p3)),
                )?;
            }
            rec.log(format!("{path}/skeleton"), &bones(&a.character.skeleton, b))?;
        }
        for (path, pose) in self.objects.iter().zip(&session.object_poses) {
            rec.log(path.as_str(), &transform(pose))?;
        }
        if k.is_multiple_of(self.options.spheres_every.max(1) as usize) {
            self.log_spheres(session)?;
        }
        let o = session.contacts(self.m);
        self.log_pairs(layout::COLLIDING, &PairsOf::from_contacts(o), session, None)?;
        self.log_plane_sphere_hits(session)?;
        self.log_counters(k, t, o)?;
        self.frames_logged += 1;
        Ok(())
    }

    /// Each character's spheres per level (those the measured frame refit,
    /// or every one with `all_spheres`), the room spheres its timed
    /// traversal tested near it, and the sub-triangles of big triangles
    /// reached.
    fn log_spheres(&mut self, session: &Session) -> rerun::RecordingStreamResult<()> {
        let world = session.world(self.m);
        let room = session.room();
        let (room_tree, _) = world.room(room).expect("the session's room");
        let nodes = room_tree.tree.nodes();
        self.shown_spheres.iter_mut().for_each(|s| *s = false);
        self.shown_pieces.iter_mut().for_each(|s| *s = false);
        for (c, (path, tree)) in self.characters.iter().zip(&mut self.trees).enumerate() {
            let view = world
                .character(session.character(c))
                .expect("the session's character");
            let measured = view.refit_state();
            let by_level = match tree.display_refit.as_mut() {
                Some(state) => {
                    let pose = view.pose();
                    state.begin_frame_with_base(pose.skin, pose.base);
                    Refitter {
                        tree: view.tree(),
                        skin: pose.skin,
                        state,
                    }
                    .refit_all(pose.base);
                    spheres_by_level(
                        state.spheres.iter().copied(),
                        &tree.levels,
                        tree.count,
                        |_| true,
                    )
                }
                None => spheres_by_level(
                    measured.spheres.iter().copied(),
                    &tree.levels,
                    tree.count,
                    |i| measured.is_fresh(NodeId(i as u32)),
                ),
            };
            for (level, (cs, rs)) in by_level.into_iter().enumerate() {
                self.rec.log(
                    layout::level_path(&format!("{path}/spheres"), level),
                    &points(cs, rs, layout::level_color(level, tree.count)),
                )?;
            }
            if view.tree().tree.is_empty() {
                continue;
            }
            // Near this character: room spheres up to half its size and
            // sub-triangles up to its size that meet its root sphere
            // (refit every frame: the root pair is always tested); the
            // upper levels span the room and would hide the rest.
            let root = measured.spheres[0];
            let tested = view
                .visit_log(room)
                .expect("Recorder::new turns the visit logs on");
            for i in tested.tested_nodes() {
                let s = &nodes[i.index()].sphere;
                if s.overlaps(&root) {
                    self.shown_spheres[i.index()] |= s.radius <= 0.5 * root.radius;
                    self.shown_pieces[i.index()] |= s.radius <= root.radius;
                }
            }
        }
        if !self.options.all_spheres {
            let shown = &self.shown_spheres;
            let by_level = spheres_by_level(
                nodes.iter().map(|n| n.sphere),
                &self.room_levels,
                self.room_level_count,
                |i| shown[i],
            );
            for (level, (c, r)) in by_level.into_iter().enumerate() {
                self.rec.log(
                    layout::level_path(layout::ENV_SPHERES, level),
                    &wireframes(c, r, layout::level_color(level, self.room_level_count)),
                )?;
            }
        }
        let strips: Vec<[[f32; 3]; 4]> = (0..nodes.len())
            .filter(|&i| self.shown_pieces[i])
            .filter_map(|i| room_tree.division_node[i])
            .map(|(d, n)| {
                let t = room_tree.divisions[d as usize].pieces[n as usize].triangle;
                [p3(&t.a), p3(&t.b), p3(&t.c), p3(&t.a)]
            })
            .collect();
        self.rec.log(
            layout::ENV_SUBDIVISION,
            &rerun::LineStrips3D::new(strips)
                .with_colors([layout::SUBDIVISION_COLOR])
                .with_radii([rerun::Radius::new_ui_points(1.0)]),
        )?;
        Ok(())
    }

    /// Plane-sphere methods: the character leaf spheres that met a big
    /// triangle's plane in a reported pair.
    fn log_plane_sphere_hits(&self, session: &Session) -> rerun::RecordingStreamResult<()> {
        let world = session.world(self.m);
        let (room_tree, _) = world.room(session.room()).expect("the session's room");
        let plane = world.method().big_leaf_test() == LeafTest::PlaneSphere;
        let (mut centers, mut radii) = (Vec::new(), Vec::new());
        if plane {
            for (c, tree) in self.trees.iter().enumerate() {
                let h = session.character(c);
                let view = world.character(h).expect("the session's character");
                let mut leaves: Vec<u32> = session
                    .contacts(self.m)
                    .room_contacts_of(h)
                    .iter()
                    .filter(|p| room_tree.big[p.room_triangle as usize])
                    .map(|p| tree.leaf_of_triangle[p.triangle as usize])
                    .filter(|&l| l != u32::MAX)
                    .collect();
                leaves.sort_unstable();
                leaves.dedup();
                let spheres = &view.refit_state().spheres;
                centers.extend(leaves.iter().map(|&l| p3(&spheres[l as usize].center)));
                radii.extend(leaves.iter().map(|&l| spheres[l as usize].radius));
            }
        }
        self.rec.log(
            layout::COLLIDING_SPHERES,
            &rerun::Ellipsoids3D::from_centers_and_radii(centers, radii)
                .with_colors([layout::HIT_AVATAR_COLOR])
                .with_fill_mode(rerun::FillMode::MajorWireframe),
        )
    }

    /// Logs frame `k`'s comparison with the ground truth (after
    /// [`Self::log_frame`], at the same time): false positives and
    /// negatives of every kind (both sides), labelled at the character's
    /// triangle with their distance (a false positive) or cause (a room
    /// pair missed; `details`, one per character, from
    /// [`Truth::room_detail`]), and precision and recall per kind and in
    /// total.
    pub fn log_truth(
        &mut self,
        truth: &Truth,
        details: &[MethodTruth],
        session: &Session,
    ) -> rerun::RecordingStreamResult<()> {
        let reported = PairsOf::from_contacts(session.contacts(self.m));
        let exact = PairsOf::from_world(&truth.exact);
        let fp = reported.minus(&exact);
        let fn_ = exact.minus(&reported);
        let (fp, fn_) = (fp.as_ref(), fn_.as_ref());
        self.log_pairs(
            layout::FALSE_POSITIVE,
            &fp,
            session,
            Some(layout::FALSE_POSITIVE_COLOR),
        )?;
        self.log_pairs(
            layout::FALSE_NEGATIVE,
            &fn_,
            session,
            Some(layout::FALSE_NEGATIVE_COLOR),
        )?;
        self.log_labels(details, session)?;
        let mut total = crate::truth::Accuracy::default();
        for kind in PairKind::ALL {
            let (r, t, f) = (reported.len(kind), exact.len(kind), fp.len(kind));
            let tp = r - f;
            let a = crate::truth::Accuracy {
                tp: tp as u64,
                fp: f as u64,
                fn_: (t - tp) as u64,
            };
            total.tp += a.tp;
            total.fp += a.fp;
            total.fn_ += a.fn_;
            self.rec.log(
                layout::kind_accuracy_path(kind, "precision"),
                &rerun::Scalars::single(a.precision()),
            )?;
            self.rec.log(
                layout::kind_accuracy_path(kind, "recall"),
                &rerun::Scalars::single(a.recall()),
            )?;
        }
        let mut triangles = crate::truth::Accuracy::default();
        for d in details {
            let a = &d.accuracy.triangles;
            triangles.tp += a.tp;
            triangles.fp += a.fp;
            triangles.fn_ += a.fn_;
        }
        let values = [
            total.precision(),
            total.recall(),
            triangles.precision(),
            triangles.recall(),
        ];
        for (path, v) in layout::ACCURACY_PATHS.iter().zip(values) {
            self.rec.log(*path, &rerun::Scalars::single(v))?;
        }
        self.rec.log(
            layout::REFERENCE_PAIRS,
            &rerun::Scalars::single(exact.total() as f64),
        )?;
        let (nfp, nfn) = (fp.total(), fn_.total());
        if nfp + nfn > 0 {
            self.event(
                "WARN",
                &format!("{nfp} false positives, {nfn} false negatives"),
            )?;
        }
        Ok(())
    }

    /// One label per false positive and negative of the room, at its
    /// character triangle: the distance between the two triangles, or the
    /// cause of the miss.
    fn log_labels(
        &self,
        details: &[MethodTruth],
        session: &Session,
    ) -> rerun::RecordingStreamResult<()> {
        let scene = &session.scene;
        let centroid = |c: usize, t: u32| {
            let positions = &session.buffers[c].positions;
            let pts = scene.characters[c].character.mesh.indices()[t as usize]
                .map(|v| positions[v as usize]);
            p3(&Point::from(
                (pts[0].coords + pts[1].coords + pts[2].coords) / 3.0,
            ))
        };
        let mut fps: Vec<([f32; 3], String)> = Vec::new();
        let mut fns: Vec<([f32; 3], String)> = Vec::new();
        for (c, d) in details.iter().enumerate() {
            fps.extend(d.false_positives.iter().map(|f| {
                (
                    centroid(c, f.avatar),
                    format!("FP {:.2} mm", f.distance * 1e3),
                )
            }));
            fns.extend(
                d.false_negatives
                    .iter()
                    .map(|f| (centroid(c, f.avatar), format!("FN {:?}", f.cause))),
            );
        }
        for (path, items, color) in [
            (layout::FALSE_POSITIVE, &fps, layout::FALSE_POSITIVE_COLOR),
            (layout::FALSE_NEGATIVE, &fns, layout::FALSE_NEGATIVE_COLOR),
        ] {
            self.rec.log(
                format!("{path}/labels"),
                &rerun::Points3D::new(items.iter().map(|i| i.0))
                    .with_labels(items.iter().map(|i| i.1.clone()))
                    .with_colors([color])
                    .with_radii([rerun::Radius::new_ui_points(3.0)]),
            )?;
        }
        Ok(())
    }

    /// The triangles of `pairs` on both sides, one entity per kind under
    /// `root`, coloured by kind (or `color`); the room's side as outlines.
    fn log_pairs(
        &mut self,
        root: &str,
        pairs: &PairsOf<'_>,
        session: &Session,
        color: Option<Rgba>,
    ) -> rerun::RecordingStreamResult<()> {
        let scene = &session.scene;
        let nc = scene.characters.len();
        // Characters' triangles are collected per character, the other
        // side's per room (slot `nc + objects`) or object (`nc + o`).
        let room_slot = nc + scene.objects.len();
        for kind in PairKind::ALL {
            self.hits.iter_mut().for_each(Vec::clear);
            match kind {
                PairKind::Environment => {
                    for p in pairs.environment {
                        self.hits[p.character.index()].push(p.triangle);
                        self.hits[room_slot].push(p.room_triangle);
                    }
                }
                PairKind::Objects => {
                    for p in pairs.objects {
                        self.hits[p.character.index()].push(p.triangle);
                        self.hits[nc + p.object.index()].push(p.object_triangle);
                    }
                }
                PairKind::Characters => {
                    for p in pairs.characters {
                        self.hits[p.a.index()].push(p.triangle_a);
                        self.hits[p.b.index()].push(p.triangle_b);
                    }
                }
                PairKind::SelfContact => {
                    for p in pairs.self_contact {
                        self.hits[p.character.index()].push(p.triangle_a);
                        self.hits[p.character.index()].push(p.triangle_b);
                    }
                }
            }
            for h in &mut self.hits {
                h.sort_unstable();
                h.dedup();
            }
            let color = color.unwrap_or_else(|| kind_color(kind));
            // One soup of every body's triangles, in world coordinates.
            let mut verts: Vec<[f32; 3]> = Vec::new();
            for (c, (a, b)) in scene.characters.iter().zip(&session.buffers).enumerate() {
                let idx = a.character.mesh.indices();
                for &t in &self.hits[c] {
                    verts.extend(idx[t as usize].map(|v| p3(&b.positions[v as usize])));
                }
            }
            for (o, (prop, pose)) in scene.objects.iter().zip(&session.object_poses).enumerate() {
                let (pos, idx) = (prop.mesh.positions(), prop.mesh.indices());
                for &t in &self.hits[nc + o] {
                    verts.extend(idx[t as usize].map(|v| p3(&(pose * pos[v as usize]))));
                }
            }
            let tris = (0..verts.len() as u32 / 3).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]);
            self.rec.log(
                format!("{root}/{}/bodies", kind.name()),
                &rerun::Mesh3D::new(verts)
                    .with_triangle_indices(tris)
                    .with_albedo_factor(color),
            )?;
            if kind == PairKind::Environment {
                // The room's side as outlines: a big floor or wall triangle
                // filled would hide the bodies.
                let room = &scene.environment.mesh;
                let (pos, idx) = (room.positions(), room.indices());
                let outlines: Vec<[[f32; 3]; 4]> = self.hits[room_slot]
                    .iter()
                    .map(|&t| {
                        let [a, b, c] = idx[t as usize].map(|v| p3(&pos[v as usize]));
                        [a, b, c, a]
                    })
                    .collect();
                self.rec.log(
                    format!("{root}/{}/room", kind.name()),
                    &rerun::LineStrips3D::new(outlines)
                        .with_colors([color])
                        .with_radii([rerun::Radius::new_ui_points(1.5)]),
                )?;
            }
        }
        Ok(())
    }

    fn log_counters(
        &mut self,
        k: usize,
        t: f32,
        o: &StepContacts,
    ) -> rerun::RecordingStreamResult<()> {
        let rec = &self.rec;
        for kind in PairKind::ALL {
            let c = o.by_kind.get(kind);
            let values = [
                c.sphere_sphere as f64,
                c.tri_tri as f64,
                c.plane_sphere as f64,
                c.sphere_box as f64,
                c.box_box as f64,
                c.operations() as f64,
                c.pairs as f64,
            ];
            for (counter, v) in layout::KIND_COUNTERS.iter().zip(values) {
                rec.log(
                    layout::kind_counter_path(kind, counter),
                    &rerun::Scalars::single(v),
                )?;
            }
        }
        let c = &o.total;
        let ops = c.operations();
        let values = [
            c.sphere_sphere as f64,
            c.tri_tri as f64,
            c.plane_sphere as f64,
            c.sphere_box as f64,
            c.box_box as f64,
            ops as f64,
            c.refits as f64,
            c.skinned_vertices as f64,
            c.pairs as f64,
            o.body_pairs as f64,
            o.wall_ms,
        ];
        for (path, v) in layout::COUNTER_PATHS.iter().zip(values) {
            rec.log(*path, &rerun::Scalars::single(v))?;
        }
        let tm = &c.time;
        let times = [
            tm.pose_ms,
            tm.skinning_ms,
            tm.refit_ms,
            tm.traversal_ms,
            tm.narrow_ms,
            tm.total_ms(),
        ];
        for (path, v) in layout::TIME_PATHS.iter().zip(times) {
            rec.log(*path, &rerun::Scalars::single(v))?;
        }
        for (i, kind) in PairKind::ALL.into_iter().enumerate() {
            let n = o.by_kind.get(kind).pairs;
            let contact = n > 0;
            if contact != self.had_contact[i] {
                let text = if contact {
                    format!("frame {k}: {} contact begins ({n} pairs)", kind.name())
                } else {
                    format!("frame {k}: {} contact ends", kind.name())
                };
                self.event(if contact { "WARN" } else { "INFO" }, &text)?;
                self.had_contact[i] = contact;
            }
        }
        if ops > self.max_operations && k > 0 {
            self.event(
                "DEBUG",
                &format!("frame {k}: most operations so far ({ops})"),
            )?;
        }
        self.max_operations = self.max_operations.max(ops);
        self.rec.log(
            layout::FRAME_REPORT,
            &rerun::TextDocument::new(frame_report(self.method, k, t, o))
                .with_media_type(rerun::MediaType::markdown()),
        )?;
        Ok(())
    }

    /// Logs how the run ended and flushes everything to the sink.
    pub fn finish(&self, note: &str) -> Result<(), rerun::sink::SinkFlushError> {
        let _ = self.event("INFO", note);
        self.rec.flush_blocking()
    }

    /// Closes the stream: its sink (a file's writer thread) is flushed and
    /// dropped before this returns.
    pub fn close(self) {
        self.rec.disconnect();
    }
}

/// Names of the time series, logged once.
fn log_series_names(rec: &RecordingStream) -> rerun::RecordingStreamResult<()> {
    for kind in PairKind::ALL {
        for counter in layout::KIND_COUNTERS {
            rec.log_static(
                layout::kind_counter_path(kind, counter),
                &rerun::SeriesLines::new()
                    .with_names([kind.name()])
                    .with_colors([kind_color(kind)]),
            )?;
        }
        for (i, what) in ["precision", "recall"].into_iter().enumerate() {
            rec.log_static(
                layout::kind_accuracy_path(kind, what),
                &rerun::SeriesLines::new()
                    .with_names([format!("{} {what}", kind.name())])
                    .with_colors([kind_color(kind)])
                    .with_widths([if i == 0 { 2.0 } else { 1.0 }]),
            )?;
        }
    }
    for path in layout::COUNTER_PATHS
        .iter()
        .chain(&layout::TIME_PATHS)
        .chain(&layout::ACCURACY_PATHS)
        .chain(&[layout::REFERENCE_PAIRS])
    {
        let name = path.rsplit('/').next().unwrap_or(path);
        rec.log_static(*path, &rerun::SeriesLines::new().with_names([name]))?;
    }
    Ok(())
}

/// One segment per bone, parent joint to child joint.
fn bones(skeleton: &cornertree::character::Skeleton, b: &PoseBuffers) -> rerun::LineStrips3D {
    let joint = |m: &Matrix4<f32>| [m[(0, 3)], m[(1, 3)], m[(2, 3)]];
    let segments: Vec<[[f32; 3]; 2]> = (0..skeleton.len())
        .filter_map(|j| {
            skeleton
                .parent(JointId(j as u16))
                .map(|p| [joint(&b.world[p.index()]), joint(&b.world[j])])
        })
        .collect();
    rerun::LineStrips3D::new(segments)
        .with_colors([layout::SKELETON_COLOR])
        .with_radii([rerun::Radius::new_ui_points(1.5)])
}

/// An object's pose as a transform of its entity.
fn transform(pose: &Isometry3<f32>) -> rerun::Transform3D {
    let q = pose.rotation;
    rerun::Transform3D::from_translation_rotation(
        p3(&Point::from(pose.translation.vector)),
        rerun::Quaternion::from_xyzw([q.i, q.j, q.k, q.w]),
    )
}

/// The pairs of every kind, borrowed.
struct PairsOf<'a> {
    environment: &'a [RoomPair],
    objects: &'a [ObjectPair],
    characters: &'a [CharacterPair],
    self_contact: &'a [SelfPair],
}

/// The pairs of every kind, owned.
struct OwnedPairs {
    environment: Vec<RoomPair>,
    objects: Vec<ObjectPair>,
    characters: Vec<CharacterPair>,
    self_contact: Vec<SelfPair>,
}

/// Items of sorted `a` not in sorted `b`.
fn minus<T: Ord + Copy>(a: &[T], b: &[T]) -> Vec<T> {
    let mut out = Vec::new();
    let mut j = 0;
    for &x in a {
        while j < b.len() && b[j] < x {
            j += 1;
        }
        if j >= b.len() || b[j] != x {
            out.push(x);
        }
    }
    out
}

impl<'a> PairsOf<'a> {
    fn from_contacts(o: &'a StepContacts) -> Self {
        Self {
            environment: &o.room_pairs,
            objects: &o.object_pairs,
            characters: &o.character_pairs,
            self_contact: &o.self_pairs,
        }
    }

    fn from_world(p: &'a WorldPairs) -> Self {
        Self {
            environment: &p.environment,
            objects: &p.objects,
            characters: &p.characters,
            self_contact: &p.self_contact,
        }
    }

    fn minus(&self, other: &PairsOf<'_>) -> OwnedPairs {
        OwnedPairs {
            environment: minus(self.environment, other.environment),
            objects: minus(self.objects, other.objects),
            characters: minus(self.characters, other.characters),
            self_contact: minus(self.self_contact, other.self_contact),
        }
    }

    fn len(&self, kind: PairKind) -> usize {
        match kind {
            PairKind::Environment => self.environment.len(),
            PairKind::Objects => self.objects.len(),
            PairKind::Characters => self.characters.len(),
            PairKind::SelfContact => self.self_contact.len(),
        }
    }

    fn total(&self) -> usize {
        PairKind::ALL.iter().map(|&k| self.len(k)).sum()
    }
}

impl OwnedPairs {
    fn as_ref(&self) -> PairsOf<'_> {
        PairsOf {
            environment: &self.environment,
            objects: &self.objects,
            characters: &self.characters,
            self_contact: &self.self_contact,
        }
    }
}

/// This frame's counters per kind and in total, as a Markdown table.
fn frame_report(method: &str, k: usize, t: f32, o: &StepContacts) -> String {
    let mut s = format!(
        "### {method}, frame {k} (t = {t:.3} s)\n\n\
         | kind | sphere-sphere | triangle-triangle | plane-sphere | sphere-box | box-box | operations | pairs |\n\
         |---|---:|---:|---:|---:|---:|---:|---:|\n"
    );
    let row = |name: &str, c: &FrameCounters| {
        format!(
            "| {name} | {} | {} | {} | {} | {} | {} | {} |\n",
            c.sphere_sphere,
            c.tri_tri,
            c.plane_sphere,
            c.sphere_box,
            c.box_box,
            c.operations(),
            c.pairs
        )
    };
    for kind in PairKind::ALL {
        s += &row(kind.name(), o.by_kind.get(kind));
    }
    s += &row("**total**", &o.total);
    s += &format!(
        "\nrefits {}, skinned vertices {}, body pairs traversed {} of {} tested, {:.3} ms\n",
        o.total.refits, o.total.skinned_vertices, o.body_pairs, o.broad_phase_tests, o.wall_ms
    );
    s
}
