//! `[[objects]]`: rigid bodies of a world, each a generated shape or a glTF
//! mesh, with a keyframed motion (docs/scenarios.md, "Worlds").
//!
//! Every mistake is one line naming the file, the entry and the key:
//! `objects[1].motion.times: keys out of time order: times[2] = 0.5 after times[1] = 1`.

use std::ops::Range;
use std::path::{Path, PathBuf};

use nalgebra::{Unit, Vector3};
use serde::Deserialize;
use toml::Spanned;

use super::motion::Motion;
use super::ranges::{self, MAX_DEGREES, MAX_METRES, MAX_SECONDS, show};
use super::{ScenarioError, find_asset, locate, missing};
use cornertree::geometry::Real;

/// What an object is made of.
#[derive(Clone, Debug, PartialEq)]
pub enum ObjectShape {
    /// Full extents in metres, centred on the object's origin.
    Box { size: [Real; 3] },
    /// Width (X, centred) × height (Y from 0), two triangles in z = 0.
    Panel { size: [Real; 2] },
    /// Radius in metres; an icosahedron split `subdivisions` times.
    Ball { radius: Real, subdivisions: u32 },
    /// Width × height × thickness; the hinge edge on the object's Y axis.
    Door { size: [Real; 3] },
    /// Every triangle of a static glTF scene, in the file's coordinates.
    Gltf { path: PathBuf },
}

/// One `[[objects]]` entry.
#[derive(Clone, Debug, PartialEq)]
pub struct ObjectEntry {
    /// Unique among the scenario's objects.
    pub name: String,
    pub shape: ObjectShape,
    pub motion: Motion,
}

/// The kinds an object may be, as written.
pub const OBJECT_KINDS: [&str; 5] = ["box", "panel", "ball", "door", "gltf"];

/// The largest ball subdivision (20·4⁶ = 81,920 triangles).
pub const MAX_BALL_SUBDIVISIONS: u32 = 6;

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawObject {
    name: Spanned<String>,
    kind: Spanned<String>,
    size: Option<Spanned<Vec<f64>>>,
    radius: Option<Spanned<f64>>,
    subdivisions: Option<Spanned<i64>>,
    path: Option<Spanned<String>>,
    motion: Option<Spanned<RawMotion>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct RawMotion {
    #[serde(default)]
    times: Vec<f64>,
    positions: Option<Vec<[f64; 3]>>,
    yaw_degrees: Option<YawKeys>,
    degrees: Option<Vec<f64>>,
    pivot: Option<[f64; 3]>,
    axis: Option<[f64; 3]>,
}

/// `yaw_degrees`: one number for every key, or one per key.
#[derive(Deserialize)]
#[serde(untagged)]
enum YawKeys {
    One(f64),
    PerKey(Vec<f64>),
}

pub(super) fn parse_objects(
    text: &str,
    file: &Path,
    base: &Path,
    raw: Vec<Spanned<RawObject>>,
) -> Result<Vec<ObjectEntry>, ScenarioError> {
    if let Some(past) = raw.get(ranges::MAX_OBJECTS) {
        return Err(ScenarioError::new(
            file,
            Some(locate(text, past.span().start)),
            Some("objects"),
            format!("at most {} objects, not {}", ranges::MAX_OBJECTS, raw.len()),
        ));
    }
    let mut out: Vec<ObjectEntry> = Vec::with_capacity(raw.len());
    for (i, entry) in raw.into_iter().enumerate() {
        let span = entry.span();
        let o = entry.into_inner();
        let at = |s: Range<usize>, key: &str, msg: String| {
            ScenarioError::new(
                file,
                Some(locate(text, s.start)),
                Some(&format!("objects[{i}]{key}")),
                msg,
            )
        };
        let name = o.name.get_ref().trim().to_owned();
        if name.is_empty() {
            return Err(at(o.name.span(), ".name", "must not be empty".into()));
        }
        if let Some(j) = out.iter().position(|e| e.name == name) {
            return Err(at(
                o.name.span(),
                ".name",
                format!("two objects named {name:?} (objects[{j}] and objects[{i}])"),
            ));
        }
        let kind = o.kind.get_ref().as_str();
        let size = |n: usize, default: &[f64]| -> Result<Vec<Real>, ScenarioError> {
            let Some(s) = &o.size else {
                return Ok(default.iter().map(|&v| v as Real).collect());
            };
            let v = s.get_ref();
            if v.len() != n {
                return Err(at(
                    s.span(),
                    ".size",
                    format!("a {kind} takes {n} numbers, not {}", v.len()),
                ));
            }
            for &x in v {
                ranges::above_zero(x, MAX_METRES, "metres")
                    .map_err(|m| at(s.span(), ".size", m))?;
            }
            Ok(v.iter().map(|&x| x as Real).collect())
        };
        let not_for = |present: bool, s: Range<usize>, key: &str| {
            if present {
                Err(at(s, key, format!("not a key of a {kind}")))
            } else {
                Ok(())
            }
        };
        let has_radius = o.radius.is_some();
        let radius_span = o.radius.as_ref().map_or(span.clone(), |r| r.span());
        let sub_span = o.subdivisions.as_ref().map_or(span.clone(), |r| r.span());
        let path_span = o.path.as_ref().map_or(span.clone(), |r| r.span());
        let size_span = o.size.as_ref().map_or(span.clone(), |r| r.span());
        let shape = match kind {
            "box" | "door" => {
                not_for(has_radius, radius_span, ".radius")?;
                not_for(o.subdivisions.is_some(), sub_span, ".subdivisions")?;
                not_for(o.path.is_some(), path_span, ".path")?;
                if kind == "box" {
                    let s = size(3, &[0.5, 0.5, 0.5])?;
                    ObjectShape::Box {
                        size: [s[0], s[1], s[2]],
                    }
                } else {
                    let s = size(3, &[0.9, 2.0, 0.04])?;
                    ObjectShape::Door {
                        size: [s[0], s[1], s[2]],
                    }
                }
            }
            "panel" => {
                not_for(has_radius, radius_span, ".radius")?;
                not_for(o.subdivisions.is_some(), sub_span, ".subdivisions")?;
                not_for(o.path.is_some(), path_span, ".path")?;
                let s = size(2, &[1.0, 1.0])?;
                ObjectShape::Panel { size: [s[0], s[1]] }
            }
            "ball" => {
                not_for(o.size.is_some(), size_span, ".size")?;
                not_for(o.path.is_some(), path_span, ".path")?;
                let radius = match &o.radius {
                    None => 0.15,
                    Some(r) => ranges::above_zero(*r.get_ref(), MAX_METRES, "metres")
                        .map_err(|m| at(r.span(), ".radius", m))?
                        as Real,
                };
                let subdivisions = match &o.subdivisions {
                    None => 3,
                    Some(n) if (0..=MAX_BALL_SUBDIVISIONS as i64).contains(n.get_ref()) => {
                        *n.get_ref() as u32
                    }
                    Some(n) => {
                        return Err(at(
                            n.span(),
                            ".subdivisions",
                            format!(
                                "must be a whole number from 0 to {MAX_BALL_SUBDIVISIONS}, not {}",
                                n.get_ref()
                            ),
                        ));
                    }
                };
                ObjectShape::Ball {
                    radius,
                    subdivisions,
                }
            }
            "gltf" => {
                not_for(o.size.is_some(), size_span, ".size")?;
                not_for(has_radius, radius_span, ".radius")?;
                not_for(o.subdivisions.is_some(), sub_span, ".subdivisions")?;
                let Some(p) = &o.path else {
                    return Err(at(
                        span.clone(),
                        ".path",
                        "kind = \"gltf\" needs a path".into(),
                    ));
                };
                let path = PathBuf::from(p.get_ref());
                let found = find_asset(base, &path)
                    .ok_or_else(|| at(p.span(), ".path", missing(base, &path)))?;
                ObjectShape::Gltf { path: found }
            }
            other => {
                return Err(at(
                    o.kind.span(),
                    ".kind",
                    format!(
                        "unknown object kind {other:?}; kinds: {}",
                        OBJECT_KINDS.join(", ")
                    ),
                ));
            }
        };
        let Some(m) = o.motion else {
            return Err(at(
                span,
                ".motion",
                "no motion keys: give `motion = { times = [...], positions = [[x, y, z], ...] }` \
                 (waypoints) or `motion = { times = [...], degrees = [...], pivot = [x, y, z], axis = [x, y, z] }` (hinge)"
                    .into(),
            ));
        };
        let motion = motion(m, &|s, key, msg| at(s, &format!(".motion{key}"), msg))?;
        out.push(ObjectEntry {
            name,
            shape,
            motion,
        });
    }
    Ok(out)
}

fn motion(
    m: Spanned<RawMotion>,
    at: &dyn Fn(Range<usize>, &str, String) -> ScenarioError,
) -> Result<Motion, ScenarioError> {
    let span = m.span();
    let m = m.into_inner();
    let err = |key: &str, msg: String| at(span.clone(), key, msg);
    let finite = |key: &str, values: &mut dyn Iterator<Item = f64>| {
        let (max, unit) = match key {
            ".times" => (MAX_SECONDS, "seconds"),
            ".degrees" | ".yaw_degrees" => (MAX_DEGREES, "degrees"),
            ".axis" => (MAX_METRES, "numbers"),
            _ => (MAX_METRES, "metres"),
        };
        for v in values {
            ranges::within(v, max, unit).map_err(|m| err(key, m))?;
        }
        Ok(())
    };
    if m.times.is_empty() {
        return Err(err(
            ".times",
            "no motion keys: give at least one time, with positions (waypoints) or degrees (hinge)"
                .into(),
        ));
    }
    finite(".times", &mut m.times.iter().copied())?;
    for (k, w) in m.times.windows(2).enumerate() {
        if w[1] <= w[0] {
            return Err(err(
                ".times",
                format!(
                    "keys out of time order: times[{}] = {} after times[{k}] = {}",
                    k + 1,
                    show(w[1]),
                    show(w[0])
                ),
            ));
        }
    }
    let n = m.times.len();
    let times: Vec<Real> = m.times.iter().map(|&t| t as Real).collect();
    let count = |key: &str, len: usize| {
        if len == n {
            Ok(())
        } else {
            Err(err(key, format!("{len} keys for {n} times")))
        }
    };
    match (&m.positions, &m.degrees) {
        (Some(positions), None) => {
            if m.pivot.is_some() || m.axis.is_some() {
                return Err(err(
                    ".pivot",
                    "pivot and axis are for a hinge (degrees), not waypoints (positions)".into(),
                ));
            }
            count(".positions", positions.len())?;
            finite(".positions", &mut positions.iter().flatten().copied())?;
            let yaw_degrees: Vec<f64> = match m.yaw_degrees {
                None => vec![0.0; n],
                Some(YawKeys::One(y)) => vec![y; n],
                Some(YawKeys::PerKey(v)) => {
                    count(".yaw_degrees", v.len())?;
                    v
                }
            };
            finite(".yaw_degrees", &mut yaw_degrees.iter().copied())?;
            let yaw_degrees = yaw_degrees.iter().map(|&y| y as Real).collect();
            Ok(Motion::Waypoints {
                times,
                positions: positions
                    .iter()
                    .map(|p| Vector3::new(p[0] as Real, p[1] as Real, p[2] as Real))
                    .collect(),
                yaw_degrees,
            })
        }
        (None, Some(degrees)) => {
            count(".degrees", degrees.len())?;
            finite(".degrees", &mut degrees.iter().copied())?;
            let pivot = m.pivot.unwrap_or([0.0; 3]);
            finite(".pivot", &mut pivot.iter().copied())?;
            let axis = m.axis.unwrap_or([0.0, 1.0, 0.0]);
            finite(".axis", &mut axis.iter().copied())?;
            let a = Vector3::new(axis[0] as Real, axis[1] as Real, axis[2] as Real);
            let Some(axis) = Unit::try_new(a, 1e-6) else {
                return Err(err(
                    ".axis",
                    format!("a hinge axis of zero length ({axis:?})"),
                ));
            };
            let yaw = match m.yaw_degrees {
                None => 0.0,
                Some(YawKeys::One(y)) => y,
                Some(YawKeys::PerKey(_)) => {
                    return Err(err(
                        ".yaw_degrees",
                        "a hinge takes one yaw (its rest turn about +Y), not one per key".into(),
                    ));
                }
            };
            finite(".yaw_degrees", &mut std::iter::once(yaw))?;
            Ok(Motion::Hinge {
                pivot: Vector3::new(pivot[0] as Real, pivot[1] as Real, pivot[2] as Real),
                axis,
                yaw_degrees: yaw as Real,
                times,
                degrees: degrees.iter().map(|&d| d as Real).collect(),
            })
        }
        (Some(_), Some(_)) => Err(err(
            ".positions",
            "give positions (waypoints) or degrees (hinge), not both".into(),
        )),
        (None, None) => Err(err(
            ".positions",
            "no motion keys: give positions (waypoints) or degrees (hinge) for the times".into(),
        )),
    }
}
