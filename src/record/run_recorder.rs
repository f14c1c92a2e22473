//! The recording of one method's run: the scene once, then every frame
//! (layout in docs/recordings.md, paths in [`super::layout`]).

use nalgebra::Matrix4;
use rerun::RecordingStream;

use super::layout::{self, Rgba};
use cornertree::character::{Character, PoseBuffers};
use cornertree::geometry::{Point, Sphere};
use cornertree::mesh::TriMesh;
use cornertree::pipeline::LeafTest;
use cornertree::pipeline::driver::{FrameCounters, Pipeline};
use cornertree::sphere_tree::NodeId;
use cornertree::sphere_tree::refit::{RefitState, Refitter};

/// What to put in a run's recording.
#[derive(Clone, Copy, Debug)]
pub struct RecordOptions {
    /// Every sphere of every level each frame, not only those the traversal
    /// reached (the environment's once, as static data; the character's
    /// refit by the recorder in its own state, for display).
    pub all_spheres: bool,
    /// Log the character's mesh every this many frames.
    pub mesh_every: u32,
    /// Log spheres and sub-triangles every this many frames (the skeleton,
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

/// Writes one method's frames to a recording stream.
pub struct RunRecorder {
    rec: RecordingStream,
    options: RecordOptions,
    method: &'static str,
    avatar_levels: Vec<u8>,
    avatar_level_count: usize,
    env_levels: Vec<u8>,
    env_level_count: usize,
    /// Character leaf node of each character triangle (u32::MAX if left out).
    leaf_of_triangle: Vec<u32>,
    /// With `all_spheres`: the recorder's own refit of the whole character
    /// tree (the pipeline's refit state holds what the measured frame refit,
    /// and is never touched here).
    display_refit: Option<RefitState>,
    had_contact: bool,
    max_operations: u64,
    frames_logged: usize,
    // Scratch, reused every frame.
    hit_avatar: Vec<u32>,
    hit_env: Vec<u32>,
}

fn p3(p: &Point) -> [f32; 3] {
    [p.x, p.y, p.z]
}

impl RunRecorder {
    /// Logs the static scene (environment mesh, the character's triangles,
    /// series names, the scenario's description) and returns the recorder.
    /// Turns on `pipeline`'s visit log: the environment spheres recorded as
    /// tested are those its timed traversal marks.
    pub fn new(
        rec: RecordingStream,
        options: RecordOptions,
        info: &SceneInfo<'_>,
        pipeline: &mut Pipeline,
        character: &Character,
        env: &TriMesh,
    ) -> rerun::RecordingStreamResult<Self> {
        pipeline.set_visit_log(true);
        let avatar_tree = &pipeline.character_tree.tree;
        let env_tree = &pipeline.environment.tree;
        let avatar_levels = layout::node_levels(avatar_tree);
        let env_levels = layout::node_levels(env_tree);
        let avatar_level_count = avatar_levels
            .iter()
            .map(|&l| l as usize + 1)
            .max()
            .unwrap_or(0);
        let env_level_count = env_levels
            .iter()
            .map(|&l| l as usize + 1)
            .max()
            .unwrap_or(0);
        let mut leaf_of_triangle = vec![u32::MAX; character.mesh.triangle_count()];
        for (i, n) in avatar_tree.nodes().iter().enumerate() {
            if let Some(p) = n.primitive() {
                leaf_of_triangle[p as usize] = i as u32;
            }
        }

        // Y up, on the views' origin (`/`: its camera and grid follow it) and
        // on `world`.
        rec.log_static("/", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        rec.log_static(layout::WORLD, &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        rec.log_static(
            layout::ENV_MESH,
            &mesh3d(env.positions(), env.indices(), layout::ENV_COLOR),
        )?;
        rec.log_static(
            layout::AVATAR_MESH,
            &rerun::Mesh3D::update_fields()
                .with_triangle_indices(character.mesh.indices().iter().copied())
                .with_albedo_factor(layout::AVATAR_COLOR),
        )?;
        rec.log_static(
            layout::INFO,
            &rerun::TextDocument::new(info.markdown.clone())
                .with_media_type(rerun::MediaType::markdown()),
        )?;
        for path in layout::COUNTER_PATHS
            .iter()
            .chain(&layout::TIME_PATHS)
            .chain(&layout::ACCURACY_PATHS)
            .chain(&[layout::REFERENCE_PAIRS])
        {
            let name = path.rsplit('/').next().unwrap_or(path);
            rec.log_static(*path, &rerun::SeriesLines::new().with_names([name]))?;
        }
        if options.all_spheres {
            for (level, (c, r)) in spheres_by_level(
                env_tree.nodes().iter().map(|n| n.sphere),
                &env_levels,
                env_level_count,
                |_| true,
            )
            .into_iter()
            .enumerate()
            {
                rec.log_static(
                    layout::level_path(layout::ENV_SPHERES, level),
                    &points(c, r, layout::level_color(level, env_level_count)),
                )?;
            }
        }
        let recorder = Self {
            rec,
            options,
            method: pipeline.method.name(),
            avatar_levels,
            avatar_level_count,
            env_levels,
            env_level_count,
            leaf_of_triangle,
            display_refit: options
                .all_spheres
                .then(|| RefitState::new(&pipeline.character_tree, character.skeleton.len())),
            had_contact: false,
            max_operations: 0,
            frames_logged: 0,
            hit_avatar: Vec::new(),
            hit_env: Vec::new(),
        };
        recorder.event(
            "INFO",
            &format!("{}: method {} starts", info.scenario, recorder.method),
        )?;
        Ok(recorder)
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

    /// Logs frame `k` (clip time `t`) after [`Pipeline::detect`] ran on it.
    /// Reads what the measured frame produced; changes nothing in `pipeline`.
    #[allow(clippy::too_many_arguments)]
    pub fn log_frame(
        &mut self,
        k: usize,
        t: f32,
        pipeline: &Pipeline,
        buffers: &PoseBuffers,
        character: &Character,
        env: &TriMesh,
        c: &FrameCounters,
    ) -> rerun::RecordingStreamResult<()> {
        let rec = &self.rec;
        rec.set_time_sequence(layout::FRAME, k as i64);
        rec.set_duration_secs(layout::CLIP_TIME, t as f64);

        // Character mesh and skeleton.
        if k.is_multiple_of(self.options.mesh_every as usize) {
            rec.log(
                layout::AVATAR_MESH,
                &rerun::Mesh3D::update_fields()
                    .with_vertex_positions(buffers.positions.iter().map(p3)),
            )?;
        }
        let joint = |m: &Matrix4<f32>| [m[(0, 3)], m[(1, 3)], m[(2, 3)]];
        let bones: Vec<[[f32; 3]; 2]> = (0..character.skeleton.len())
            .filter_map(|j| {
                let id = cornertree::character::JointId(j as u16);
                character
                    .skeleton
                    .parent(id)
                    .map(|p| [joint(&buffers.world[p.index()]), joint(&buffers.world[j])])
            })
            .collect();
        rec.log(
            layout::AVATAR_SKELETON,
            &rerun::LineStrips3D::new(bones)
                .with_colors([layout::SKELETON_COLOR])
                .with_radii([rerun::Radius::new_ui_points(1.5)]),
        )?;

        if k.is_multiple_of(self.options.spheres_every as usize) {
            self.log_spheres(pipeline, buffers)?;
        }
        let rec = &self.rec;
        let state = pipeline.refit_state();

        // Colliding pairs: the triangles on both sides; for plane-sphere hits
        // also the character leaf sphere that met the big triangle's plane.
        self.hit_avatar.clear();
        self.hit_env.clear();
        self.hit_avatar.extend(pipeline.pairs.iter().map(|p| p.0));
        self.hit_env.extend(pipeline.pairs.iter().map(|p| p.1));
        for v in [&mut self.hit_avatar, &mut self.hit_env] {
            v.sort_unstable();
            v.dedup();
        }
        rec.log(
            layout::COLLIDING_AVATAR,
            &soup(
                &buffers.positions,
                character.mesh.indices(),
                &self.hit_avatar,
                layout::HIT_AVATAR_COLOR,
            ),
        )?;
        rec.log(
            layout::COLLIDING_ENVIRONMENT,
            &soup(
                env.positions(),
                env.indices(),
                &self.hit_env,
                layout::HIT_ENV_COLOR,
            ),
        )?;
        let plane_sphere = pipeline.method.big_leaf_test() == LeafTest::PlaneSphere;
        let mut ps_leaves: Vec<u32> = pipeline
            .pairs
            .iter()
            .filter(|p| plane_sphere && pipeline.environment.big[p.1 as usize])
            .map(|p| self.leaf_of_triangle[p.0 as usize])
            .filter(|&l| l != u32::MAX)
            .collect();
        ps_leaves.sort_unstable();
        ps_leaves.dedup();
        rec.log(
            layout::COLLIDING_SPHERES,
            &rerun::Ellipsoids3D::from_centers_and_radii(
                ps_leaves
                    .iter()
                    .map(|&l| p3(&state.spheres[l as usize].center)),
                ps_leaves.iter().map(|&l| state.spheres[l as usize].radius),
            )
            .with_colors([layout::HIT_AVATAR_COLOR])
            .with_fill_mode(rerun::FillMode::MajorWireframe),
        )?;

        // Counters.
        let ops = c.operations();
        let values = [
            c.sphere_sphere as f64,
            c.tri_tri as f64,
            c.plane_sphere as f64,
            ops as f64,
            c.refits as f64,
            c.skinned_vertices as f64,
            c.pairs as f64,
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

        // Notable events.
        let contact = c.pairs > 0;
        if contact != self.had_contact {
            let text = if contact {
                format!("frame {k}: contact begins ({} pairs)", c.pairs)
            } else {
                format!("frame {k}: contact ends")
            };
            self.event(if contact { "WARN" } else { "INFO" }, &text)?;
            self.had_contact = contact;
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
            &rerun::TextDocument::new(frame_report(self.method, k, t, c))
                .with_media_type(rerun::MediaType::markdown()),
        )?;
        self.frames_logged += 1;
        Ok(())
    }

    /// The spheres of both trees per level and the sub-triangles reached.
    fn log_spheres(
        &mut self,
        pipeline: &Pipeline,
        buffers: &PoseBuffers,
    ) -> rerun::RecordingStreamResult<()> {
        let rec = &self.rec;
        // Character spheres per level: those the measured frame refit, or
        // (with `all_spheres`) every sphere, refit here in our own state.
        let measured = pipeline.refit_state();
        let avatar_tree = &pipeline.character_tree.tree;
        let all = self.options.all_spheres;
        let by_level = match self.display_refit.as_mut() {
            Some(state) => {
                state.begin_frame_with_base(&buffers.skin, &buffers.base);
                Refitter {
                    tree: &pipeline.character_tree,
                    skin: &buffers.skin,
                    state,
                }
                .refit_all(&buffers.base);
                spheres_by_level(
                    state.spheres.iter().copied(),
                    &self.avatar_levels,
                    self.avatar_level_count,
                    |_| true,
                )
            }
            None => spheres_by_level(
                measured.spheres.iter().copied(),
                &self.avatar_levels,
                self.avatar_level_count,
                |i| measured.is_fresh(NodeId(i as u32)),
            ),
        };
        for (level, (c, r)) in by_level.into_iter().enumerate() {
            rec.log(
                layout::level_path(layout::AVATAR_SPHERES, level),
                &points(c, r, layout::level_color(level, self.avatar_level_count)),
            )?;
        }

        // Environment spheres the timed traversal tested (its visit log),
        // near the character.
        let env_tree = &pipeline.environment.tree;
        let tested = pipeline
            .visit_log()
            .expect("RunRecorder::new turns the visit log on");
        // Only spheres up to half the character's size that meet its root
        // sphere (refit every frame: the root pair is always tested): the
        // upper levels span the room and would hide the rest.
        let root = if avatar_tree.is_empty() {
            Sphere {
                center: Point::origin(),
                radius: 0.0,
            }
        } else {
            measured.spheres[0]
        };
        let near = |s: &Sphere, max: f32| s.radius <= max * root.radius && s.overlaps(&root);
        if !all {
            let by_level = spheres_by_level(
                env_tree.nodes().iter().map(|n| n.sphere),
                &self.env_levels,
                self.env_level_count,
                |i| tested.is_tested(NodeId(i as u32)) && near(&env_tree.nodes()[i].sphere, 0.5),
            );
            for (level, (c, r)) in by_level.into_iter().enumerate() {
                rec.log(
                    layout::level_path(layout::ENV_SPHERES, level),
                    &rerun::Ellipsoids3D::from_centers_and_radii(c, r)
                        .with_colors([layout::level_color(level, self.env_level_count)])
                        .with_fill_mode(rerun::FillMode::MajorWireframe)
                        .with_line_radii([rerun::Radius::new_ui_points(0.5)]),
                )?;
            }
        }

        // Sub-triangles of big triangles whose division nodes were tested
        // (those up to the character's size).
        let envt = &pipeline.environment;
        let strips: Vec<[[f32; 3]; 4]> = tested
            .tested_nodes()
            .filter(|i| near(&envt.tree.nodes()[i.index()].sphere, 1.0))
            .filter_map(|i| envt.division_node[i.index()])
            .map(|(d, n)| {
                let t = envt.divisions[d as usize].pieces[n as usize].triangle;
                [p3(&t.a), p3(&t.b), p3(&t.c), p3(&t.a)]
            })
            .collect();
        rec.log(
            layout::ENV_SUBDIVISION,
            &rerun::LineStrips3D::new(strips)
                .with_colors([layout::SUBDIVISION_COLOR])
                .with_radii([rerun::Radius::new_ui_points(1.0)]),
        )?;
        Ok(())
    }

    /// Logs frame `k`'s comparison with the ground truth (after
    /// [`Self::log_frame`], at the same time): false positives and false
    /// negatives as triangles (both sides) labelled with their distance or
    /// cause, and precision and recall.
    pub fn log_truth(
        &self,
        truth: &crate::truth::MethodTruth,
        reference_pairs: usize,
        positions: &[Point],
        character: &Character,
        env: &TriMesh,
    ) -> rerun::RecordingStreamResult<()> {
        let rec = &self.rec;
        let idx = character.mesh.indices();
        let centroid = |pts: [Point; 3]| {
            p3(&Point::from(
                (pts[0].coords + pts[1].coords + pts[2].coords) / 3.0,
            ))
        };
        let avatar_tri = |c: u32| idx[c as usize].map(|v| positions[v as usize]);
        let fps: Vec<(u32, u32, String)> = truth
            .false_positives
            .iter()
            .map(|f| {
                (
                    f.avatar,
                    f.environment,
                    format!("FP {:.2} mm", f.distance * 1e3),
                )
            })
            .collect();
        let fns: Vec<(u32, u32, String)> = truth
            .false_negatives
            .iter()
            .map(|f| (f.avatar, f.environment, format!("FN {:?}", f.cause)))
            .collect();
        for (path, items, color) in [
            (layout::FALSE_POSITIVE, &fps, layout::FALSE_POSITIVE_COLOR),
            (layout::FALSE_NEGATIVE, &fns, layout::FALSE_NEGATIVE_COLOR),
        ] {
            let avatar: Vec<u32> = items.iter().map(|i| i.0).collect();
            let environment: Vec<u32> = items.iter().map(|i| i.1).collect();
            rec.log(
                format!("{path}/avatar"),
                &soup(positions, idx, &avatar, color),
            )?;
            rec.log(
                format!("{path}/environment"),
                &soup(env.positions(), env.indices(), &environment, color),
            )?;
            // One label per pair, at the character triangle.
            rec.log(
                format!("{path}/labels"),
                &rerun::Points3D::new(items.iter().map(|i| centroid(avatar_tri(i.0))))
                    .with_labels(items.iter().map(|i| i.2.clone()))
                    .with_colors([color])
                    .with_radii([rerun::Radius::new_ui_points(3.0)]),
            )?;
        }
        let a = &truth.accuracy;
        let values = [
            a.pairs.precision(),
            a.pairs.recall(),
            a.triangles.precision(),
            a.triangles.recall(),
        ];
        for (path, v) in layout::ACCURACY_PATHS.iter().zip(values) {
            rec.log(*path, &rerun::Scalars::single(v))?;
        }
        rec.log(
            layout::REFERENCE_PAIRS,
            &rerun::Scalars::single(reference_pairs as f64),
        )?;
        let (nfp, nfn) = (fps.len(), fns.len());
        if nfp + nfn > 0 {
            self.event(
                "WARN",
                &format!("{nfp} false positives, {nfn} false negatives"),
            )?;
        }
        Ok(())
    }

    /// Logs how the run ended and flushes everything to the sink.
    pub fn finish(&self, note: &str) -> Result<(), rerun::sink::SinkFlushError> {
        let _ = self.event("INFO", note);
        self.rec.flush_blocking()
    }
}

fn frame_report(method: &str, k: usize, t: f32, c: &FrameCounters) -> String {
    format!(
        "### {method}, frame {k} (t = {t:.3} s)\n\n\
         | counter | value |\n|---|---|\n\
         | sphere-sphere tests | {} |\n| triangle-triangle tests | {} |\n\
         | plane-sphere tests | {} |\n| operations | {} |\n| refits | {} |\n\
         | skinned vertices | {} |\n| colliding pairs | {} |\n| time (ms) | {:.3} |\n",
        c.sphere_sphere,
        c.tri_tri,
        c.plane_sphere,
        c.operations(),
        c.refits,
        c.skinned_vertices,
        c.pairs,
        c.time.total_ms()
    )
}

/// Spheres grouped per level (`keep` filters by node index).
pub(crate) fn spheres_by_level(
    spheres: impl Iterator<Item = Sphere>,
    level_of: &[u8],
    levels: usize,
    keep: impl Fn(usize) -> bool,
) -> Vec<(Vec<[f32; 3]>, Vec<f32>)> {
    let mut out = vec![(Vec::new(), Vec::new()); levels];
    for (i, s) in spheres.enumerate() {
        if keep(i) {
            let l = level_of[i] as usize;
            out[l].0.push(p3(&s.center));
            out[l].1.push(s.radius);
        }
    }
    out
}

/// Spheres as points with scene-unit radii (fast for tens of thousands).
pub fn points(centers: Vec<[f32; 3]>, radii: Vec<f32>, color: Rgba) -> rerun::Points3D {
    rerun::Points3D::new(centers)
        .with_radii(radii)
        .with_colors([color])
}

/// An indexed mesh with one colour.
pub fn mesh3d(positions: &[Point], indices: &[[u32; 3]], color: Rgba) -> rerun::Mesh3D {
    rerun::Mesh3D::new(positions.iter().map(p3))
        .with_triangle_indices(indices.iter().copied())
        .with_albedo_factor(color)
}

/// The triangles `which` of a mesh, as a small unindexed mesh.
pub fn soup(
    positions: &[Point],
    indices: &[[u32; 3]],
    which: &[u32],
    color: Rgba,
) -> rerun::Mesh3D {
    let verts = which
        .iter()
        .flat_map(|&t| indices[t as usize].map(|v| p3(&positions[v as usize])));
    let tris = (0..which.len() as u32).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]);
    rerun::Mesh3D::new(verts)
        .with_triangle_indices(tris)
        .with_albedo_factor(color)
}
