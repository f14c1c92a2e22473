//! Scenario variants of the scaling studies: a base scenario with another
//! character size, another room size, or a crowd of a given number of
//! generated humanoids.

use std::path::Path;

use crate::character::HumanoidParams;
use crate::geometry::bounds_of;
use crate::io::CharacterSource;
use crate::scenario::{
    CharacterEntry, CharacterSection, EnvironmentSection, Placement, Resolved, Scenario,
    ScenarioError, WalkPath, resolve,
};

fn base_dir(base: &Path) -> &Path {
    base.parent().unwrap_or(Path::new(""))
}

/// The base scenario `s` (read from `base`) with its first character replaced
/// by the generated humanoid of `character_vertices` (walking, if the base
/// names no clip) and, with `environment_vertices`, its generated room
/// re-tessellated to that many vertices.
pub fn sized(
    base: &Path,
    s: &Scenario,
    character_vertices: usize,
    environment_vertices: Option<usize>,
) -> Result<Resolved, ScenarioError> {
    let mut s = s.clone();
    let first = s.first_character_mut();
    let seed = match &first.character.source {
        CharacterSource::Humanoid(h) => h.seed,
        CharacterSource::File(_) => 0,
    };
    first.character.source = CharacterSource::Humanoid(HumanoidParams {
        vertices: character_vertices,
        seed,
    });
    if first.character.clip.is_none() {
        first.character.clip = Some("walk".into());
    }
    if let Some(n) = environment_vertices {
        match &mut s.environment {
            EnvironmentSection::Museum { vertices, .. }
            | EnvironmentSection::LivingRoom { vertices, .. } => *vertices = Some(n),
            EnvironmentSection::Gltf { .. } => {
                return Err(ScenarioError::new(
                    base,
                    None,
                    Some("environment.kind"),
                    "the environment study needs a generated room (kind = \"museum\" or \
                     \"living-room\"), not a glTF scene",
                ));
            }
        }
    }
    resolve(&s, base_dir(base))
}

/// Lanes of a crowd: side by side, this far apart (metres); neighbours walk
/// opposite ways and brush as they pass (as in `scenarios/crowd.toml`).
pub const LANE_SPACING: f32 = 0.47;
/// Kept clear of the room's walls (metres).
const WALL_MARGIN: f32 = 0.7;

/// The base scenario's room (and objects) with `count` generated humanoids of
/// `vertices` vertices walking at 1.2 m/s in lanes [`LANE_SPACING`] apart
/// along the room's depth, neighbours in opposite directions, out of step;
/// when the lanes across the room are used up, the room's depth is split
/// into rows. Each character has the same surroundings on average, so cost
/// per frame should grow linearly with `count`.
pub fn crowd(
    base: &Path,
    s: &Scenario,
    count: usize,
    vertices: usize,
) -> Result<Resolved, ScenarioError> {
    let fail = |msg: String| ScenarioError::new(base, None, Some("environment"), msg);
    // The room's floor extent, from the base scenario's room.
    let room = resolve(s, base_dir(base))?;
    let (lo, hi) = bounds_of(room.environment.mesh.positions().iter().copied())
        .ok_or_else(|| fail("the room has no vertices".into()))?;
    let (x0, x1) = (lo.x + WALL_MARGIN, hi.x - WALL_MARGIN);
    let (z0, z1) = (lo.z + WALL_MARGIN, hi.z - WALL_MARGIN);
    if x1 <= x0 || z1 <= z0 {
        return Err(fail(format!(
            "the room ({:.2} m x {:.2} m) is too small for a crowd",
            hi.x - lo.x,
            hi.z - lo.z
        )));
    }
    let floor = lo.y.max(0.0).min(hi.y);
    let lanes = (((x1 - x0) / LANE_SPACING).floor() as usize + 1).max(1);
    let rows = count.div_ceil(lanes).max(1);
    let depth = (z1 - z0) / rows as f32;
    let mut s = s.clone();
    let template = s.first_character().clone();
    s.characters = (0..count)
        .map(|i| {
            let (row, lane) = (i / lanes, i % lanes);
            let x = x0 + lane as f32 * LANE_SPACING;
            let (a, b) = (z0 + row as f32 * depth, z0 + (row + 1) as f32 * depth);
            let (from, to) = if lane % 2 == 0 { (a, b) } else { (b, a) };
            CharacterEntry {
                name: format!("crowd{i}"),
                character: CharacterSection {
                    source: CharacterSource::Humanoid(HumanoidParams {
                        vertices,
                        seed: 11 + i as u64,
                    }),
                    clip: Some("walk".into()),
                    skinning: template.character.skinning,
                },
                placement: Placement::Path(WalkPath {
                    waypoints: vec![[x, floor, from], [x, floor, to]],
                    speed: 1.2,
                }),
                clip_offset: (i as f32 * 0.37) % 1.0,
                surface_at: None,
                field: format!("characters[{i}]"),
            }
        })
        .collect();
    resolve(&s, base_dir(base))
}
