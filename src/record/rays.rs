//! The recording of `cornertree rays`: per frame, each character's posed
//! mesh, the rays (to their first hit, or on past the characters), the hit
//! points, and the spheres the rays' queries refit on their way, per level.

use cornertree::geometry::Point;
use cornertree::world::CharacterHandle;
use rerun::RecordingStream;

use super::draw::{body_entity, mesh3d, p3, points, spheres_by_level};
use super::layout::{self, Rgba};
use crate::bench::rays::FrameRays;
use crate::session::Session;

const RAY_HIT: Rgba = [60, 200, 90, 255];
const RAY_MISS: Rgba = [150, 150, 150, 120];
const HIT_POINT: Rgba = [250, 220, 40, 255];
const MESH: Rgba = layout::AVATAR_COLOR;

/// How far a ray that hits nothing is drawn.
const MISS_LENGTH: f32 = 6.0;

/// Levels the blueprint lists (deeper than any character tree).
pub const LEVELS: usize = 40;

/// The entity of character `i` named `name`.
pub fn character_entity(i: usize, name: &str) -> String {
    format!("world/characters/{}", body_entity(i, name))
}

/// The recording of a `rays` run: the stream, and each character tree's
/// node levels (computed at the first frame; trees do not change).
pub struct RaysRecording {
    rec: RecordingStream,
    levels: Vec<(Vec<u8>, usize)>,
}

impl RaysRecording {
    /// Logs the world's axes (Y up), once.
    pub fn begin(rec: RecordingStream) -> anyhow::Result<Self> {
        rec.log_static("/", &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        rec.log_static(layout::WORLD, &rerun::ViewCoordinates::RIGHT_HAND_Y_UP())?;
        Ok(Self {
            rec,
            levels: Vec::new(),
        })
    }

    /// The stream (to flush it).
    pub fn stream(&self) -> &RecordingStream {
        &self.rec
    }

    /// Logs frame `rays.frame`.
    pub fn log_frame(&mut self, session: &Session, rays: &FrameRays) -> anyhow::Result<()> {
        let rec = &self.rec;
        rec.set_time_sequence(layout::FRAME, rays.frame as i64);
        for (i, (a, b)) in session
            .scene
            .characters
            .iter()
            .zip(&session.buffers)
            .enumerate()
        {
            let root = character_entity(i, &a.name);
            rec.log(
                format!("{root}/mesh"),
                &mesh3d(&b.positions, a.character.mesh.indices(), MESH),
            )?;
            let view = session.world(0).character(CharacterHandle(i as u32))?;
            if self.levels.len() <= i {
                let levels = layout::node_levels(&view.tree().tree);
                let count = super::draw::level_count(&levels);
                self.levels.push((levels, count));
            }
            let (levels, count) = (&self.levels[i].0, self.levels[i].1);
            let refit = view.refit_state();
            let by_level = spheres_by_level(refit.spheres.iter().copied(), levels, count, |n| {
                refit.is_fresh(cornertree::sphere_tree::NodeId(n as u32))
            });
            for (l, (c, r)) in by_level.into_iter().enumerate() {
                rec.log(
                    format!("{root}/refit_by_rays/level_{l}"),
                    &points(c, r, {
                        let [r, g, b, _] = layout::level_color(l, count);
                        [r, g, b, 70]
                    }),
                )?;
            }
        }
        log_rays(rec, rays)
    }
}

/// The rays, their hit points and how many hit.
fn log_rays(rec: &RecordingStream, rays: &FrameRays) -> anyhow::Result<()> {
    let (mut hit_lines, mut miss_lines, mut hit_points) = (Vec::new(), Vec::new(), Vec::new());
    for (r, h) in rays.rays.iter().zip(&rays.hits) {
        let o = p3(&r.origin);
        match h {
            Some(h) => {
                hit_lines.push(vec![o, p3(&h.point)]);
                hit_points.push(p3(&h.point));
            }
            None => {
                let end: Point = r.origin + r.direction * MISS_LENGTH;
                miss_lines.push(vec![o, p3(&end)]);
            }
        }
    }
    rec.log(
        "world/rays/hit",
        &rerun::LineStrips3D::new(hit_lines)
            .with_colors([RAY_HIT])
            .with_radii([rerun::Radius::new_ui_points(1.0)]),
    )?;
    rec.log(
        "world/rays/missed",
        &rerun::LineStrips3D::new(miss_lines)
            .with_colors([RAY_MISS])
            .with_radii([rerun::Radius::new_ui_points(0.5)]),
    )?;
    rec.log(
        "world/rays/hit_points",
        &rerun::Points3D::new(hit_points)
            .with_colors([HIT_POINT])
            .with_radii([rerun::Radius::new_ui_points(4.0)]),
    )?;
    rec.log(
        "stats/rays_hit",
        &rerun::Scalars::single(rays.hits.iter().filter(|h| h.is_some()).count() as f64),
    )?;
    Ok(())
}
