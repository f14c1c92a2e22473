//! Entity paths and colours shared by the recorders, the blueprint, the tests
//! and docs/recordings.md.

use cornertree::sphere_tree::SphereTree;

/// Timeline of frame numbers (sequence).
pub const FRAME: &str = "frame";
/// Timeline of clip time (seconds).
pub const CLIP_TIME: &str = "clip_time";

pub const WORLD: &str = "world";
pub const ENV_MESH: &str = "world/environment/mesh";
pub const ENV_SPHERES: &str = "world/environment/spheres";
pub const ENV_SUBDIVISION: &str = "world/environment/subdivision";
/// One entity per character and per object under these:
/// `<body>/{mesh,skeleton,spheres/level_kk}`.
pub const WORLD_CHARACTERS: &str = "world/characters";
pub const WORLD_OBJECTS: &str = "world/objects";
/// Colliding triangles, `cd/colliding/<kind>/{bodies,room}`.
pub const COLLIDING: &str = "cd/colliding";
/// Plane-sphere methods: the character leaf spheres that met a big
/// triangle's plane in a reported pair.
pub const COLLIDING_SPHERES: &str = "cd/colliding/plane_sphere";
pub const FALSE_POSITIVE: &str = "cd/false_positive";
pub const FALSE_NEGATIVE: &str = "cd/false_negative";
/// Precision and recall against the ground truth, per frame.
pub const ACCURACY_PATHS: [&str; 4] = [
    "stats/accuracy/pair_precision",
    "stats/accuracy/pair_recall",
    "stats/accuracy/triangle_precision",
    "stats/accuracy/triangle_recall",
];
/// Continuous detection (`run --ccd`): under `cd/` so every 3D view shows
/// it. The bodies at a time of impact (`…/toi/characters/<body>`,
/// `…/toi/objects/<body>`), the pairs touching there, the swept spheres of
/// the step's touching character leaves.
pub const CCD: &str = "cd/ccd";
pub const CCD_TOI: &str = "cd/ccd/toi";
pub const CCD_TOI_PAIRS: &str = "cd/ccd/toi/pairs";
/// The other side of those pairs (room, object or second character), outlined.
pub const CCD_TOI_OTHER: &str = "cd/ccd/toi/pairs_other";
pub const CCD_SWEPT: &str = "cd/ccd/swept_spheres";
/// Per step: pairs, pairs the discrete frames missed at both ends, recall
/// against the sub-stepped reference, earliest time of impact.
pub const CCD_STATS: [&str; 4] = [
    "stats/ccd/pairs",
    "stats/ccd/missed_by_discrete",
    "stats/ccd/recall",
    "stats/ccd/earliest_toi",
];
pub const REFERENCE_PAIRS: &str = "stats/reference_pairs";
pub const STATS: &str = "stats";
pub const EVENTS: &str = "events";
pub const FRAME_REPORT: &str = "frame_report";
pub const INFO: &str = "info";

/// `…/level_{k}` under a spheres root.
pub fn level_path(root: &str, level: usize) -> String {
    format!("{root}/level_{level:02}")
}

/// The counters of a frame (every kind together) logged as scalars, with
/// their entity paths under `stats/`.
pub const COUNTER_PATHS: [&str; 11] = [
    "stats/tests/sphere_sphere",
    "stats/tests/tri_tri",
    "stats/tests/plane_sphere",
    "stats/tests/sphere_box",
    "stats/tests/box_box",
    "stats/operations",
    "stats/refits",
    "stats/skinned_vertices",
    "stats/pairs",
    "stats/body_pairs",
    "stats/wall_ms",
];
/// The counters logged per pair kind, as `stats/by_kind/<counter>/<kind>`
/// (one time series view per counter shows the three kinds).
pub const KIND_COUNTERS: [&str; 7] = [
    "sphere_sphere",
    "tri_tri",
    "plane_sphere",
    "sphere_box",
    "box_box",
    "operations",
    "pairs",
];

/// `stats/by_kind/<counter>/<kind>`.
pub fn kind_counter_path(kind: cornertree::world::PairKind, counter: &str) -> String {
    format!("{STATS}/by_kind/{counter}/{}", kind.name())
}

/// `stats/accuracy/<kind>/<precision|recall>`.
pub fn kind_accuracy_path(kind: cornertree::world::PairKind, what: &str) -> String {
    format!("{STATS}/accuracy/{}/{what}", kind.name())
}

/// Time per stage, milliseconds.
pub const TIME_PATHS: [&str; 6] = [
    "stats/time_ms/pose",
    "stats/time_ms/skinning",
    "stats/time_ms/refit",
    "stats/time_ms/traversal",
    "stats/time_ms/narrow",
    "stats/time_ms/total",
];

pub type Rgba = [u8; 4];

/// Translucent, so the character shows through walls from any side.
pub const ENV_COLOR: Rgba = [170, 170, 175, 90];
pub const AVATAR_COLOR: Rgba = [110, 160, 220, 255];
pub const SKELETON_COLOR: Rgba = [240, 240, 90, 255];
pub const HIT_AVATAR_COLOR: Rgba = [230, 40, 40, 255];
pub const HIT_ENV_COLOR: Rgba = [255, 150, 20, 255];
/// Moving objects, and the colliding triangles of the two pair kinds beside
/// the room's ([`HIT_ENV_COLOR`]).
pub const OBJECT_COLOR: Rgba = [200, 170, 120, 200];
pub const HIT_OBJECT_COLOR: Rgba = [120, 220, 40, 255];
pub const HIT_CHARACTER_COLOR: Rgba = [150, 90, 255, 255];
/// Both triangles of a character's contact with itself.
pub const HIT_SELF_COLOR: Rgba = [255, 225, 0, 255];
pub const SUBDIVISION_COLOR: Rgba = [40, 200, 120, 255];
pub const FALSE_POSITIVE_COLOR: Rgba = [255, 0, 255, 255];
pub const FALSE_NEGATIVE_COLOR: Rgba = [0, 230, 255, 255];
/// Continuous detection: a character at a time of impact, the pairs
/// touching there, swept spheres (translucent).
pub const CCD_TOI_COLOR: Rgba = [120, 200, 170, 120];
pub const CCD_PAIR_COLOR: Rgba = [255, 30, 30, 255];
pub const CCD_OTHER_COLOR: Rgba = [255, 230, 0, 255];
pub const CCD_SWEPT_COLOR: Rgba = [255, 170, 0, 200];

/// A colour per hierarchy level, from warm (root) to cool (leaves),
/// translucent so nested spheres stay readable.
pub fn level_color(level: usize, levels: usize) -> Rgba {
    const RAMP: [[u8; 3]; 6] = [
        [230, 80, 60],
        [240, 160, 40],
        [220, 220, 60],
        [90, 200, 90],
        [60, 170, 220],
        [140, 90, 220],
    ];
    let t = if levels <= 1 {
        0.0
    } else {
        level as f32 / (levels - 1) as f32
    };
    let x = t * (RAMP.len() - 1) as f32;
    let i = (x.floor() as usize).min(RAMP.len() - 2);
    let f = x - i as f32;
    let mix = |a: u8, b: u8| (a as f32 + (b as f32 - a as f32) * f).round() as u8;
    let (a, b) = (RAMP[i], RAMP[i + 1]);
    [mix(a[0], b[0]), mix(a[1], b[1]), mix(a[2], b[2]), 110]
}

/// The level (root = 0) of every node of `tree`.
pub fn node_levels(tree: &SphereTree) -> Vec<u8> {
    let mut level = vec![0u8; tree.len()];
    for (i, n) in tree.nodes().iter().enumerate() {
        if !n.is_leaf() {
            for c in n.children() {
                level[c as usize] = level[i].saturating_add(1);
            }
        }
    }
    level
}

/// The character level shown by default in a run's sphere view: the first
/// with at least 200 spheres (a body-shaped cloud), else the deepest.
pub fn display_level(tree: &SphereTree) -> usize {
    let per_level = tree.nodes_per_level();
    per_level
        .iter()
        .position(|&n| n >= 200)
        .unwrap_or(per_level.len().saturating_sub(1))
}
