//! Scenario variants of the scaling studies: a base scenario with another
//! character size, another room size, a crowd of a given number of
//! generated humanoids, or its character at another gap to a surface.

use std::path::Path;

use crate::humanoid::HumanoidParams;
use crate::io::CharacterSource;
use crate::scenario::{
    CharacterEntry, CharacterSection, EnvironmentSection, Gap, Placement, Resolved, RunLimits,
    Scenario, ScenarioError, WalkPath, resolve_with,
};
use cornertree::geometry::bounds_of;

/// The seed of the crowd's one humanoid.
const CROWD_SEED: u64 = 11;

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
    limits: &RunLimits,
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
            EnvironmentSection::Gltf { .. } | EnvironmentSection::Plaza { .. } => {
                return Err(ScenarioError::new(
                    base,
                    None,
                    Some("environment.kind"),
                    "the environment study needs a generated room (kind = \"museum\" or \
                     \"living-room\"), not a glTF scene or a plaza",
                ));
            }
        }
    }
    resolve_with(&s, base_dir(base), limits)
}

/// Surface of the contact sweep when the base scenario keeps no gap.
pub const SWEEP_SURFACE: &str = "south wall";

/// The base scenario `s` (read from `base`) with its first character kept
/// `metres` from its gap surface over the clip (negative: that deep into
/// it at the deepest), everything else as in the base: the contact sweep.
/// A base placed otherwise gets a gap to [`SWEEP_SURFACE`].
pub fn at_gap(
    base: &Path,
    s: &Scenario,
    metres: f32,
    limits: &RunLimits,
) -> Result<Resolved, ScenarioError> {
    let mut s = s.clone();
    let first = s.first_character_mut();
    match &mut first.placement {
        Placement::Gap(g) => g.metres = metres,
        other => {
            *other = Placement::Gap(Gap {
                surface: SWEEP_SURFACE.into(),
                metres,
                yaw_degrees: None,
                along: 0.0,
            })
        }
    }
    resolve_with(&s, base_dir(base), limits)
}

/// Lanes of a crowd: side by side, this far apart (metres), neighbours
/// walking opposite ways; far enough that they pass without touching (a
/// crowd brushing past is `scenarios/crowd.toml`), so that every character
/// costs the same and the study shows how the frame grows with their number.
pub const LANE_SPACING: f32 = 0.62;
/// Length of floor a crowd member's slot keeps free along its lane (metres):
/// 16 frames at 1.2 m/s walk 0.64 m.
const SLOT_LENGTH: f32 = 1.0;
/// Clearance kept around a slot from furniture and walls (metres).
const CLEARANCE: f32 = 0.35;

/// Free slots of the room's floor for crowd members: lanes along +z every
/// [`LANE_SPACING`] across the room, cut into [`SLOT_LENGTH`] pieces, kept
/// where no furniture's box (anything but floor, ceiling, walls, windows,
/// rugs and what hangs above 2 m) comes within [`CLEARANCE`]. Each slot is
/// `(x, z_start, lane)`.
fn free_slots(env: &crate::environment::Environment) -> Vec<(f32, f32, usize)> {
    use crate::environment::ObjectKind;
    let Some((lo, hi)) = bounds_of(env.mesh.positions().iter().copied()) else {
        return Vec::new();
    };
    let obstacles: Vec<(cornertree::geometry::Point, cornertree::geometry::Point)> = env
        .objects
        .iter()
        .filter(|o| {
            !matches!(
                o.kind,
                ObjectKind::Floor
                    | ObjectKind::Ceiling
                    | ObjectKind::Wall
                    | ObjectKind::Window
                    | ObjectKind::Rug
            )
        })
        .filter_map(|o| {
            let (a, b) = (o.vertices.start as usize, o.vertices.end as usize);
            bounds_of(env.mesh.positions()[a..b].iter().copied())
        })
        .filter(|(blo, _)| blo.y < 2.0)
        .collect();
    let mut slots = Vec::new();
    let (x0, x1) = (lo.x + CLEARANCE + 0.3, hi.x - CLEARANCE - 0.3);
    let (z0, z1) = (lo.z + CLEARANCE + 0.3, hi.z - CLEARANCE - 0.3);
    let mut lane = 0;
    let mut x = x0;
    while x <= x1 {
        let mut z = z0;
        while z + SLOT_LENGTH <= z1 {
            let free = obstacles.iter().all(|(blo, bhi)| {
                bhi.x < x - CLEARANCE
                    || blo.x > x + CLEARANCE
                    || bhi.z < z - CLEARANCE
                    || blo.z > z + SLOT_LENGTH + CLEARANCE
            });
            if free {
                slots.push((x, z, lane));
            }
            z += SLOT_LENGTH + CLEARANCE;
        }
        x += LANE_SPACING;
        lane += 1;
    }
    slots
}

/// The order slots are filled in: each next slot the farthest from those
/// taken, so any number of characters spreads over the room.
fn spread(slots: &[(f32, f32, usize)]) -> Vec<usize> {
    let mut order = Vec::with_capacity(slots.len());
    let mut dist = vec![f32::INFINITY; slots.len()];
    let mut next = 0;
    while order.len() < slots.len() {
        order.push(next);
        let (xn, zn, _) = slots[next];
        for (d, &(x, z, _)) in dist.iter_mut().zip(slots) {
            *d = d.min((x - xn).hypot(z - zn));
        }
        for &o in &order {
            dist[o] = -1.0;
        }
        next = (0..slots.len())
            .max_by(|&a, &b| dist[a].total_cmp(&dist[b]))
            .unwrap_or(0);
    }
    order
}

/// The base scenario's room (and objects) with `count` instances of one
/// generated humanoid of `vertices` vertices (one source, built once:
/// instances share its mesh, skeleton, clips and trees) walking at 1.2 m/s in free slots of the floor (lanes
/// [`LANE_SPACING`] apart, clear of furniture, neighbouring lanes in opposite
/// directions, out of step), filled farthest-first so that any number
/// spreads over the room. Each character then has the same surroundings
/// (the floor under its feet), so cost per frame should grow linearly with
/// `count`.
pub fn crowd(
    base: &Path,
    s: &Scenario,
    count: usize,
    vertices: usize,
    limits: &RunLimits,
) -> Result<Resolved, ScenarioError> {
    if let Some(c) = &s.crowd {
        return crowd_of_crowd(base, s, c, count, vertices, limits);
    }
    let room = resolve_with(s, base_dir(base), limits)?;
    let slots = free_slots(&room.environment);
    if count > slots.len() {
        return Err(ScenarioError::new(
            base,
            None,
            Some("environment"),
            format!(
                "the room has free floor for {} crowd members in lanes {LANE_SPACING} m apart, \
                 not {count} (a scenario with a [crowd] on a plaza holds any number: \
                 scenarios/plaza_brushing.toml)",
                slots.len()
            ),
        ));
    }
    let floor = bounds_of(room.environment.mesh.positions().iter().copied())
        .map_or(0.0, |(lo, hi)| lo.y.max(0.0).min(hi.y));
    let order = spread(&slots);
    let mut s = s.clone();
    let template = s.first_character().clone();
    s.characters = order[..count]
        .iter()
        .enumerate()
        .map(|(i, &slot)| {
            let (x, z, lane) = slots[slot];
            let (from, to) = if lane % 2 == 0 {
                (z, z + SLOT_LENGTH)
            } else {
                (z + SLOT_LENGTH, z)
            };
            CharacterEntry {
                name: format!("crowd{i}"),
                character: CharacterSection {
                    source: CharacterSource::Humanoid(HumanoidParams {
                        vertices,
                        seed: CROWD_SEED,
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
    resolve_with(&s, base_dir(base), limits)
}

/// The base scenario's `[crowd]` grown or shrunk to `count` instances of the
/// generated humanoid of `vertices` vertices (its seed, or the crowd
/// study's), same spacing, same clip: the same layout at every count, on a
/// plaza sized to it unless the base gives the plaza's size.
fn crowd_of_crowd(
    base: &Path,
    s: &Scenario,
    c: &crate::scenario::crowd::Crowd,
    count: usize,
    vertices: usize,
    limits: &RunLimits,
) -> Result<Resolved, ScenarioError> {
    let mut s = s.clone();
    let mut c = c.clone();
    let seed = match &c.character.source {
        CharacterSource::Humanoid(h) => h.seed,
        CharacterSource::File(_) => CROWD_SEED,
    };
    c.character.source = CharacterSource::Humanoid(HumanoidParams { vertices, seed });
    c.count = count;
    s.set_crowd(c);
    resolve_with(&s, base_dir(base), limits)
}
