//! The recording of one method playing a world (several characters, moving
//! objects): every body, the characters' refit spheres per level, the
//! colliding triangles coloured by pair kind, counters per kind, and with the
//! ground truth the false positives and negatives of every kind (layout in
//! docs/recordings.md, "Worlds"; paths in [`super::layout`]).
//!
//! Bodies are grouped under `world/characters/` and `world/objects/`, one
//! entity per character or object (never one per sphere or triangle), so a
//! crowd of 16 stays one entity tree the blueprint shows through wildcards.
//! Objects' meshes and sphere levels are logged once in their own frame;
//! each frame only their pose (`Transform3D`) moves them.

use nalgebra::{Isometry3, Matrix4};
use rerun::RecordingStream;

use super::layout::{self, Rgba};
use super::run_recorder::{RecordOptions, SceneInfo, mesh3d, points, spheres_by_level};
use crate::scenario::Resolved;
use crate::truth::WorldPairs;
use crate::world::{MethodOutcome, MethodWorld, PairKind};
use cornertree::character::{JointId, PoseBuffers};
use cornertree::geometry::Point;
use cornertree::pipeline::driver::FrameCounters;
use cornertree::sphere_tree::NodeId;

/// A body's entity name: its index (so entities sort as the scenario lists
/// them) and its name with anything but letters, digits, `-` and `_` made `_`.
pub fn body_entity(index: usize, name: &str) -> String {
    let clean: String = name
        .chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c
            } else {
                '_'
            }
        })
        .collect();
    format!("{index:02}_{clean}")
}

fn p3(p: &Point) -> [f32; 3] {
    [p.x, p.y, p.z]
}

/// Colour of the colliding triangles of a pair kind (both sides).
pub fn kind_color(kind: PairKind) -> Rgba {
    match kind {
        PairKind::Environment => layout::HIT_ENV_COLOR,
        PairKind::Objects => layout::HIT_OBJECT_COLOR,
        PairKind::Characters => layout::HIT_CHARACTER_COLOR,
    }
}

/// Writes one method's frames of a world.
pub struct WorldRecorder {
    rec: RecordingStream,
    options: RecordOptions,
    method: &'static str,
    characters: Vec<String>,
    objects: Vec<String>,
    /// Per character: the level of each node, and the number of levels.
    levels: Vec<(Vec<u8>, usize)>,
    had_contact: [bool; 3],
    frames_logged: usize,
    // Scratch, reused every frame: per body, its triangles to show.
    hits: Vec<Vec<u32>>,
}

impl WorldRecorder {
    /// Logs the static scene (the room, every character's triangles, every
    /// object's mesh and spheres per level in its own frame, series names,
    /// the scenario's description).
    pub fn new(
        rec: RecordingStream,
        options: RecordOptions,
        info: &SceneInfo<'_>,
        mw: &mut MethodWorld,
        scene: &Resolved,
    ) -> rerun::RecordingStreamResult<Self> {
        let characters: Vec<String> = scene
            .characters
            .iter()
            .enumerate()
            .map(|(i, a)| format!("{}/{}", layout::WORLD_CHARACTERS, body_entity(i, &a.name)))
            .collect();
        let objects: Vec<String> = scene
            .objects
            .iter()
            .enumerate()
            .map(|(i, o)| format!("{}/{}", layout::WORLD_OBJECTS, body_entity(i, &o.name)))
            .collect();
        // Y up, on the views' origin (`/`) and on `world` (as in the
        // recordings of one character).
        rec.log_static("/", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        rec.log_static(layout::WORLD, &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        let room = &scene.environment.mesh;
        rec.log_static(
            layout::ENV_MESH,
            &mesh3d(room.positions(), room.indices(), layout::ENV_COLOR),
        )?;
        for (path, a) in characters.iter().zip(&scene.characters) {
            rec.log_static(
                format!("{path}/mesh"),
                &rerun::Mesh3D::update_fields()
                    .with_triangle_indices(a.character.mesh.indices().iter().copied())
                    .with_albedo_factor(layout::AVATAR_COLOR),
            )?;
        }
        for ((path, o), tree) in objects.iter().zip(&scene.objects).zip(&mw.objects) {
            rec.log_static(
                format!("{path}/mesh"),
                &mesh3d(o.mesh.positions(), o.mesh.indices(), layout::OBJECT_COLOR),
            )?;
            let lv = layout::node_levels(&tree.tree);
            let n = lv.iter().map(|&l| l as usize + 1).max().unwrap_or(0);
            for (level, (c, r)) in
                spheres_by_level(tree.tree.nodes().iter().map(|n| n.sphere), &lv, n, |_| true)
                    .into_iter()
                    .enumerate()
            {
                rec.log_static(
                    layout::level_path(&format!("{path}/spheres"), level),
                    &rerun::Ellipsoids3D::from_centers_and_radii(c, r)
                        .with_colors([layout::level_color(level, n)])
                        .with_fill_mode(rerun::FillMode::MajorWireframe)
                        .with_line_radii([rerun::Radius::new_ui_points(0.5)]),
                )?;
            }
        }
        rec.log_static(
            layout::INFO,
            &rerun::TextDocument::new(info.markdown.clone())
                .with_media_type(rerun::MediaType::markdown()),
        )?;
        for kind in PairKind::ALL {
            for counter in layout::KIND_COUNTERS {
                let path = layout::kind_counter_path(kind, counter);
                rec.log_static(
                    path,
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
        for path in layout::WORLD_TOTAL_PATHS {
            let name = path.rsplit('/').next().unwrap_or(path);
            rec.log_static(path, &rerun::SeriesLines::new().with_names([name]))?;
        }
        let levels = mw
            .pipelines()
            .map(|p| {
                let lv = layout::node_levels(&p.character_tree.tree);
                let n = lv.iter().map(|&l| l as usize + 1).max().unwrap_or(0);
                (lv, n)
            })
            .collect();
        let hits = vec![Vec::new(); scene.characters.len() + scene.objects.len() + 1];
        let r = Self {
            rec,
            options,
            method: mw.method.name(),
            characters,
            objects,
            levels,
            had_contact: [false; 3],
            frames_logged: 0,
            hits,
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

    /// The stream (for flushing).
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    /// Logs a line to the `events` text log at the current time.
    pub fn event(&self, level: &str, text: &str) -> rerun::RecordingStreamResult<()> {
        self.rec
            .log(layout::EVENTS, &rerun::TextLog::new(text).with_level(level))
    }

    /// Logs frame `k` (world time `t`) after the method ran on it: `buffers`
    /// skinned (every vertex), objects at `poses`. Reads the pipelines' refit
    /// state; changes nothing in them.
    pub fn log_frame(
        &mut self,
        k: usize,
        t: f32,
        mw: &mut MethodWorld,
        scene: &Resolved,
        buffers: &[PoseBuffers],
        poses: &[Isometry3<f32>],
    ) -> rerun::RecordingStreamResult<()> {
        let rec = &self.rec;
        rec.set_time_sequence(layout::FRAME, k as i64);
        rec.set_duration_secs(layout::CLIP_TIME, t as f64);
        let mesh_now = k.is_multiple_of(self.options.mesh_every.max(1) as usize);
        let spheres_now = k.is_multiple_of(self.options.spheres_every.max(1) as usize);
        for ((path, a), b) in self.characters.iter().zip(&scene.characters).zip(buffers) {
            if mesh_now {
                rec.log(
                    format!("{path}/mesh"),
                    &rerun::Mesh3D::update_fields()
                        .with_vertex_positions(b.positions.iter().map(p3)),
                )?;
            }
            let joint = |m: &Matrix4<f32>| [m[(0, 3)], m[(1, 3)], m[(2, 3)]];
            let skeleton = &a.character.skeleton;
            let bones: Vec<[[f32; 3]; 2]> = (0..skeleton.len())
                .filter_map(|j| {
                    skeleton
                        .parent(JointId(j as u16))
                        .map(|p| [joint(&b.world[p.index()]), joint(&b.world[j])])
                })
                .collect();
            rec.log(
                format!("{path}/skeleton"),
                &rerun::LineStrips3D::new(bones)
                    .with_colors([layout::SKELETON_COLOR])
                    .with_radii([rerun::Radius::new_ui_points(1.0)]),
            )?;
        }
        if spheres_now {
            // Each character's spheres the measured frame refit, per level.
            for (c, p) in mw.pipelines().enumerate() {
                let (levels, n) = &self.levels[c];
                let state = p.refit_state();
                for (level, (cs, rs)) in
                    spheres_by_level(state.spheres.iter().copied(), levels, *n, |i| {
                        state.is_fresh(NodeId(i as u32))
                    })
                    .into_iter()
                    .enumerate()
                {
                    rec.log(
                        layout::level_path(&format!("{}/spheres", self.characters[c]), level),
                        &points(cs, rs, layout::level_color(level, *n)),
                    )?;
                }
            }
        }
        for (path, pose) in self.objects.iter().zip(poses) {
            let q = pose.rotation;
            rec.log(
                path.as_str(),
                &rerun::Transform3D::from_translation_rotation(
                    p3(&Point::from(pose.translation.vector)),
                    rerun::Quaternion::from_xyzw([q.i, q.j, q.k, q.w]),
                ),
            )?;
        }
        let o = &mw.outcome;
        self.log_pairs(
            layout::COLLIDING,
            &PairsOf::from_outcome(o),
            scene,
            buffers,
            poses,
            None,
        )?;
        self.log_counters(k, t, o)?;
        self.frames_logged += 1;
        Ok(())
    }

    /// Logs frame `k`'s false positives and negatives of every kind against
    /// the exact pairs, and precision and recall per kind (after
    /// [`Self::log_frame`], at the same time).
    pub fn log_truth(
        &mut self,
        exact: &WorldPairs,
        outcome: &MethodOutcome,
        scene: &Resolved,
        buffers: &[PoseBuffers],
        poses: &[Isometry3<f32>],
    ) -> rerun::RecordingStreamResult<()> {
        let reported = PairsOf::from_outcome(outcome);
        let truth = PairsOf {
            environment: &exact.environment,
            objects: &exact.objects,
            characters: &exact.characters,
        };
        let fp = reported.minus(&truth);
        let fn_ = truth.minus(&reported);
        let fp_ref = fp.as_ref();
        let fn_ref = fn_.as_ref();
        self.log_pairs(
            layout::FALSE_POSITIVE,
            &fp_ref,
            scene,
            buffers,
            poses,
            Some(layout::FALSE_POSITIVE_COLOR),
        )?;
        self.log_pairs(
            layout::FALSE_NEGATIVE,
            &fn_ref,
            scene,
            buffers,
            poses,
            Some(layout::FALSE_NEGATIVE_COLOR),
        )?;
        for kind in PairKind::ALL {
            let (r, t, f) = (reported.len(kind), truth.len(kind), fp_ref.len(kind));
            let tp = r - f;
            let precision = if r == 0 { 1.0 } else { tp as f64 / r as f64 };
            let recall = if t == 0 { 1.0 } else { tp as f64 / t as f64 };
            self.rec.log(
                layout::kind_accuracy_path(kind, "precision"),
                &rerun::Scalars::single(precision),
            )?;
            self.rec.log(
                layout::kind_accuracy_path(kind, "recall"),
                &rerun::Scalars::single(recall),
            )?;
        }
        let (nfp, nfn) = (fp_ref.total(), fn_ref.total());
        if nfp + nfn > 0 {
            self.event(
                "WARN",
                &format!("{nfp} false positives, {nfn} false negatives"),
            )?;
        }
        Ok(())
    }

    /// The triangles of `pairs` on both sides, one entity per kind under
    /// `root`, coloured by kind (or `color`).
    fn log_pairs(
        &mut self,
        root: &str,
        pairs: &PairsOf<'_>,
        scene: &Resolved,
        buffers: &[PoseBuffers],
        poses: &[Isometry3<f32>],
        color: Option<Rgba>,
    ) -> rerun::RecordingStreamResult<()> {
        let nc = scene.characters.len();
        let clear = |h: &mut Vec<Vec<u32>>| h.iter_mut().for_each(Vec::clear);
        // Characters' triangles are collected per character, the other
        // side's per room (slot `nc + objects`) or object (`nc + o`).
        let room_slot = nc + scene.objects.len();
        for kind in PairKind::ALL {
            clear(&mut self.hits);
            match kind {
                PairKind::Environment => {
                    for p in pairs.environment {
                        self.hits[p.character as usize].push(p.triangle);
                        self.hits[room_slot].push(p.room_triangle);
                    }
                }
                PairKind::Objects => {
                    for p in pairs.objects {
                        self.hits[p.character as usize].push(p.triangle);
                        self.hits[nc + p.object as usize].push(p.object_triangle);
                    }
                }
                PairKind::Characters => {
                    for p in pairs.characters {
                        self.hits[p.a as usize].push(p.triangle_a);
                        self.hits[p.b as usize].push(p.triangle_b);
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
            for (c, (a, b)) in scene.characters.iter().zip(buffers).enumerate() {
                let idx = a.character.mesh.indices();
                for &t in &self.hits[c] {
                    verts.extend(idx[t as usize].map(|v| p3(&b.positions[v as usize])));
                }
            }
            for (o, (prop, pose)) in scene.objects.iter().zip(poses).enumerate() {
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
        o: &MethodOutcome,
    ) -> rerun::RecordingStreamResult<()> {
        let rec = &self.rec;
        for kind in PairKind::ALL {
            let c = o.by_kind.get(kind);
            let values = [
                c.sphere_sphere as f64,
                c.tri_tri as f64,
                c.plane_sphere as f64,
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
        let totals = [
            c.operations() as f64,
            c.refits as f64,
            c.skinned_vertices as f64,
            o.body_pairs as f64,
            o.wall_ms,
        ];
        for (path, v) in layout::WORLD_TOTAL_PATHS.iter().zip(totals) {
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
        self.rec.log(
            layout::FRAME_REPORT,
            &rerun::TextDocument::new(world_report(self.method, k, t, o))
                .with_media_type(rerun::MediaType::markdown()),
        )?;
        Ok(())
    }

    /// Logs how the run ended and flushes everything to the sink.
    pub fn finish(&self, note: &str) -> Result<(), rerun::sink::SinkFlushError> {
        let _ = self.event("INFO", note);
        self.rec.flush_blocking()
    }
}

/// The pairs of every kind, borrowed.
struct PairsOf<'a> {
    environment: &'a [cornertree::world::RoomPair],
    objects: &'a [cornertree::world::ObjectPair],
    characters: &'a [cornertree::world::CharacterPair],
}

/// The pairs of every kind, owned.
struct OwnedPairs {
    environment: Vec<cornertree::world::RoomPair>,
    objects: Vec<cornertree::world::ObjectPair>,
    characters: Vec<cornertree::world::CharacterPair>,
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
    fn from_outcome(o: &'a MethodOutcome) -> Self {
        Self {
            environment: &o.room_pairs,
            objects: &o.object_pairs,
            characters: &o.character_pairs,
        }
    }

    fn minus(&self, other: &PairsOf<'_>) -> OwnedPairs {
        OwnedPairs {
            environment: minus(self.environment, other.environment),
            objects: minus(self.objects, other.objects),
            characters: minus(self.characters, other.characters),
        }
    }

    fn len(&self, kind: PairKind) -> usize {
        match kind {
            PairKind::Environment => self.environment.len(),
            PairKind::Objects => self.objects.len(),
            PairKind::Characters => self.characters.len(),
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
        }
    }
}

fn world_report(method: &str, k: usize, t: f32, o: &MethodOutcome) -> String {
    let mut s = format!(
        "### {method}, frame {k} (t = {t:.3} s)\n\n\
         | kind | sphere-sphere | triangle-triangle | plane-sphere | operations | pairs |\n\
         |---|---:|---:|---:|---:|---:|\n"
    );
    let row = |name: &str, c: &FrameCounters| {
        format!(
            "| {name} | {} | {} | {} | {} | {} |\n",
            c.sphere_sphere,
            c.tri_tri,
            c.plane_sphere,
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
