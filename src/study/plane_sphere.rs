//! When does the plane-sphere method, read as §5 writes it, need as few tests
//! as Tables 2–3 report? An experiment, one factor at a time.
//!
//! §5 applies Algorithm 1 where a character *leaf* sphere meets a corner-tree
//! leaf ([`Method::PlaneSphere`]). A corner-tree stops splitting its central
//! sub-triangles, so a central leaf's sphere is large (the first one covers a
//! quarter of the big triangle); a character standing inside it is descended
//! to every leaf, each paying a plane-sphere test. How often that happens
//! depends on where the character stands relative to the big triangle, on how
//! the big surface is tessellated, on the threshold that decides what is big,
//! on edge de-duplication (§4) and on the gap. Each [`Factor`] moves one of
//! them away from the base scenario, and every chosen method is played on the
//! same frames. Besides the paper's counters, each row gives the radius of
//! the largest corner-tree (or quaternary) leaf any character leaf met: the
//! quantity the explanation above predicts the cost from.

use std::path::{Path, PathBuf};

use serde::Serialize;

use crate::scenario::{
    Placement, Scenario, ScenarioError, SubdivideObject, load_scenario, resolve, scenario_name,
};
use crate::session::{Session, SessionError};
use cornertree::geometry::Real;
use cornertree::pipeline::Method;

/// Which knob a condition turns, away from the base scenario.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum Factor {
    /// The base scenario as written.
    Base,
    /// Where along the big surface the character walks (`placement.gap.along`).
    Position,
    /// The gap surface (`[environment] subdivide`), and in a second series
    /// every big triangle of the room (floor, ceiling, walls, table tops, …),
    /// split four-way `times` times.
    Tessellation,
    /// The big-triangle threshold.
    Threshold,
    /// Edge de-duplication (§4) off.
    Dedup,
    /// The gap to the surface.
    Gap,
}

/// One setting of the experiment, applied to a base scenario.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Condition {
    pub factor: Factor,
    /// What was set, in words (`along +7.50 m`, `wall split 4x`, …).
    pub setting: String,
    #[serde(skip)]
    edit: Edit,
}

#[derive(Clone, Debug, PartialEq)]
enum Edit {
    None,
    /// A fraction of half the surface's length, from its middle.
    Along(Real),
    /// The gap surface split `times` times.
    SplitSurface(u32),
    /// Every big triangle of the room split to pieces of at most this many metres.
    SplitBig(Real),
    Threshold(Real),
    NoDedup,
    Gap(Real),
}

/// The conditions played for every base scenario: the base, then one factor
/// at a time.
pub fn conditions() -> Vec<Condition> {
    let c = |factor, setting: String, edit| Condition {
        factor,
        setting,
        edit,
    };
    let mut out = vec![c(Factor::Base, "as written".into(), Edit::None)];
    for f in [-0.75, -0.4, 0.4, 0.75] {
        out.push(c(
            Factor::Position,
            format!("{:+.0}% of the half-length", f * 100.0),
            Edit::Along(f),
        ));
    }
    for times in [2, 4, 6, 8] {
        out.push(c(
            Factor::Tessellation,
            format!("surface split {times}x"),
            Edit::SplitSurface(times),
        ));
    }
    for piece in [2.0, 1.0, 0.5, 0.3] {
        out.push(c(
            Factor::Tessellation,
            format!("every big triangle split to {piece} m"),
            Edit::SplitBig(piece),
        ));
    }
    for t in [0.5, 2.0, 8.0] {
        out.push(c(
            Factor::Threshold,
            format!("threshold {t} m"),
            Edit::Threshold(t),
        ));
    }
    out.push(c(Factor::Dedup, "de-duplication off".into(), Edit::NoDedup));
    for g in [0.05, 0.5] {
        out.push(c(Factor::Gap, format!("gap {g} m"), Edit::Gap(g)));
    }
    out
}

/// What one method did under one condition: maxima over the frames (as the
/// paper's tables report), and means.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct StudyRow {
    pub scenario: String,
    pub factor: Factor,
    pub setting: String,
    /// The gap surface's triangles after the condition's tessellation.
    pub surface_triangles: usize,
    /// Where the character's extent is centred, metres along the surface from its middle.
    pub along_metres: Real,
    pub threshold: Real,
    pub dedup: bool,
    pub method: Method,
    pub frames: usize,
    pub sphere_sphere_max: u64,
    pub tri_tri_max: u64,
    pub plane_sphere_max: u64,
    pub operations_max: u64,
    pub operations_mean: f64,
    pub refits_max: u64,
    /// Radius of the largest big-triangle division leaf met by a character
    /// leaf in any frame (0: none met).
    pub largest_division_leaf_met: Real,
    /// The object that leaf's big triangle belongs to (empty: none met).
    pub largest_leaf_object: String,
}

/// Why the experiment could not run.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    #[error("{file}: the experiment needs a gap placement (placement.gap) to move along a surface")]
    NotGap { file: PathBuf },
    #[error("{file}: {message}")]
    Split { file: PathBuf, message: String },
    #[error(transparent)]
    Session(#[from] SessionError),
}

/// Plays every condition of [`conditions`] on `base` with each of `methods`,
/// `frames` frames each (`None`: the scenario's). Calls `progress` after each
/// condition with (done, total).
pub fn run_study(
    base: &Path,
    methods: &[Method],
    frames: Option<usize>,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<StudyRow>, StudyError> {
    let scenario = load_scenario(base)?;
    let Placement::Gap(gap) = &scenario.first_character().placement else {
        return Err(StudyError::NotGap {
            file: base.to_owned(),
        });
    };
    let surface = gap.surface.clone();
    let base_dir = base.parent().map(PathBuf::from).unwrap_or_default();
    let name = scenario_name(base);
    let conditions = conditions();
    let base_room = inspect_base(&scenario, &base_dir)?;
    let mut rows = Vec::new();
    for (i, condition) in conditions.iter().enumerate() {
        let mut s = scenario.clone();
        s.frames = frames.or(s.frames);
        apply(&mut s, &condition.edit, &surface, &base_room);
        let mut resolved = resolve(&s, &base_dir)?;
        if let Edit::SplitBig(piece) = condition.edit {
            resolved.environment = resolved
                .environment
                .subdivide_big(resolved.threshold, piece)
                .map_err(|e| StudyError::Split {
                    file: base.to_owned(),
                    message: e.to_string(),
                })?;
        }
        let surface_triangles = resolved
            .environment
            .object(&surface)
            .map_or(0, |o| o.triangles.len());
        let along_metres = match &s.first_character().placement {
            Placement::Gap(g) => g.along,
            _ => 0.0,
        };
        let frames = resolved.frames();
        let threshold = resolved.threshold;
        let dedup = resolved.dedup;
        resolved.methods = methods.to_vec();
        // The room, for naming its triangles after the run.
        let environment = resolved.environment.clone();
        let mut session = Session::new(resolved, 1)?;
        let (room, character) = (session.room(), session.character(0));
        let mut rows_now: Vec<(StudyRow, Option<u32>)> = methods
            .iter()
            .map(|&method| {
                let row = StudyRow {
                    scenario: name.clone(),
                    factor: condition.factor,
                    setting: condition.setting.clone(),
                    surface_triangles,
                    along_metres,
                    threshold,
                    dedup,
                    method,
                    frames,
                    sphere_sphere_max: 0,
                    tri_tri_max: 0,
                    plane_sphere_max: 0,
                    operations_max: 0,
                    operations_mean: 0.0,
                    refits_max: 0,
                    largest_division_leaf_met: 0.0,
                    largest_leaf_object: String::new(),
                };
                (row, None)
            })
            .collect();
        while session.step().is_some() {
            for (m, (row, largest_leaf_triangle)) in rows_now.iter_mut().enumerate() {
                let c = session.contacts(m).total;
                row.sphere_sphere_max = row.sphere_sphere_max.max(c.sphere_sphere);
                row.tri_tri_max = row.tri_tri_max.max(c.tri_tri);
                row.plane_sphere_max = row.plane_sphere_max.max(c.plane_sphere);
                row.operations_max = row.operations_max.max(c.operations());
                row.operations_mean += c.operations() as f64;
                row.refits_max = row.refits_max.max(c.refits);
                let w = session.world(m);
                let (tree, _) = w.room(room).expect("the session's room");
                let view = w.character(character).expect("the session's character");
                let nodes = tree.tree.nodes();
                for lp in view.room_leaf_pairs(room) {
                    if tree.is_division_leaf(lp.leaf_b) {
                        let r = nodes[lp.leaf_b.index()].sphere.radius;
                        if r > row.largest_division_leaf_met {
                            row.largest_division_leaf_met = r;
                            *largest_leaf_triangle = Some(lp.primitive_b);
                        }
                    }
                }
            }
        }
        for (mut row, largest_leaf_triangle) in rows_now {
            row.operations_mean /= frames.max(1) as f64;
            if let Some(t) = largest_leaf_triangle {
                row.largest_leaf_object = environment
                    .object_of(cornertree::mesh::TriangleId(t))
                    .map_or_else(String::new, |o| o.name.clone());
            }
            rows.push(row);
        }
        progress(i + 1, conditions.len());
    }
    Ok(rows)
}

/// What the conditions need to know of the base scenario's room.
struct BaseRoom {
    /// Half the gap surface's length along the horizontal direction the gap
    /// placement moves along (`up × normal`).
    half_length: Real,
}

fn inspect_base(s: &Scenario, base_dir: &Path) -> Result<BaseRoom, StudyError> {
    let mut probe = s.clone();
    probe.frames = Some(1);
    let r = resolve(&probe, base_dir)?;
    let (Some(report), Placement::Gap(g)) = (&r.first().gap, &s.first_character().placement) else {
        return Err(StudyError::NotGap {
            file: s.file.clone(),
        });
    };
    let t = nalgebra::Vector3::y().cross(&report.normal);
    let t = if t.norm() > 1e-3 {
        t.normalize()
    } else {
        nalgebra::Vector3::x()
    };
    let env = &r.environment;
    let object = env
        .object(&g.surface)
        .expect("resolve checked the surface exists");
    let pos = env.mesh.positions();
    let (lo, hi) = object
        .vertices
        .clone()
        .map(|v| t.dot(&pos[v as usize].coords))
        .fold((Real::INFINITY, Real::NEG_INFINITY), |(lo, hi), a| {
            (lo.min(a), hi.max(a))
        });
    Ok(BaseRoom {
        half_length: 0.5 * (hi - lo),
    })
}

fn apply(s: &mut Scenario, edit: &Edit, surface: &str, base: &BaseRoom) {
    match *edit {
        Edit::None => {}
        Edit::Along(f) => {
            if let Placement::Gap(g) = &mut s.first_character_mut().placement {
                g.along = f * base.half_length;
            }
        }
        Edit::SplitSurface(times) => {
            s.subdivide = vec![SubdivideObject {
                object: surface.to_owned(),
                times,
            }];
        }
        // Applied to the resolved room (`Environment::subdivide_big`).
        Edit::SplitBig(_) => {}
        Edit::Threshold(t) => s.threshold = t,
        Edit::NoDedup => s.dedup = false,
        Edit::Gap(m) => {
            if let Placement::Gap(g) = &mut s.first_character_mut().placement {
                g.metres = m;
            }
        }
    }
}
