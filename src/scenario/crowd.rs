//! `[crowd]`: many instances of one character standing in a grid on a
//! plaza, each playing its clip in place, out of step with its neighbours.
//!
//! ```toml
//! [environment]
//! kind = "plaza"            # sized to the crowd unless `size` is given
//!
//! [crowd]
//! source = "generated:humanoid?vertices=10000&seed=11"
//! count = 1024
//! clip = "walk"             # default: the source's first clip
//! spacing = [0.59, 1.0]     # metres between neighbours across x and along z
//! ```
//!
//! Character `i` stands in column `i % columns`, row `i / columns` of a
//! grid about as wide as deep, [`MARGIN`] metres in from the plaza's
//! corner, facing +z (odd columns −z), and plays its clip in place (a walk
//! clip's own travel taken back out, as on a path walked at no speed), each
//! 0.37 s after the one before (modulo 1 s). Every instance shares its
//! source's mesh, skeleton, clips and trees (docs/architecture.md,
//! "Instances share their source"); the memory budget, not a fixed cap,
//! bounds the count.

use std::path::Path;

use serde::Deserialize;
use toml::Spanned;

use super::{
    CharacterEntry, CharacterSection, Placement, ScenarioError, WalkPath, character_section,
    linear, locate, ranges,
};
use cornertree::character::SkinningModel;

/// Spacing by default: neighbours across `x` 0.59 m apart, where the
/// generated humanoid's swinging hands brush its neighbours' about as often
/// as in `scenarios/crowd.toml` (13 colliding pairs per character a frame
/// against 11 there, de-duplication off; at 0.60 m, under one); rows 1 m
/// apart along `z`, out of reach.
pub const DEFAULT_SPACING: [f32; 2] = [0.59, 1.0];
/// Metres from the plaza's edge to the grid's outer characters.
pub const MARGIN: f32 = 2.0;
/// Least and most spacing accepted, metres.
pub const MIN_SPACING: f64 = 0.05;
pub const MAX_SPACING: f64 = 100.0;

/// A crowd as read.
#[derive(Clone, Debug, PartialEq)]
pub struct Crowd {
    pub character: CharacterSection,
    pub count: usize,
    /// Metres between neighbours across `x` and along `z`.
    pub spacing: [f32; 2],
}

impl Crowd {
    /// Columns of the grid: about as many metres wide as deep.
    pub fn columns(&self) -> usize {
        let [sx, sz] = self.spacing;
        let c = (self.count as f64 * f64::from(sz) / f64::from(sx))
            .sqrt()
            .ceil() as usize;
        c.clamp(1, self.count.max(1))
    }

    /// Width and depth of the plaza that holds the grid with [`MARGIN`]
    /// around it.
    pub fn extent(&self) -> [f32; 2] {
        let cols = self.columns();
        let rows = self.count.div_ceil(cols);
        let [sx, sz] = self.spacing;
        [
            2.0 * MARGIN + (cols - 1) as f32 * sx,
            2.0 * MARGIN + rows.saturating_sub(1) as f32 * sz,
        ]
    }

    /// The crowd's characters, `crowd0`, `crowd1`, … in grid order.
    pub fn entries(&self) -> Vec<CharacterEntry> {
        let cols = self.columns();
        let [sx, sz] = self.spacing;
        (0..self.count)
            .map(|i| {
                let (c, r) = (i % cols, i / cols);
                CharacterEntry {
                    name: format!("crowd{i}"),
                    character: self.character.clone(),
                    // Walking in place: a path at no speed keeps the spot
                    // and faces along it, and takes the clip's own travel
                    // back out.
                    placement: Placement::Path(WalkPath {
                        waypoints: {
                            let (x, z) = (MARGIN + c as f32 * sx, MARGIN + r as f32 * sz);
                            let ahead = if c % 2 == 0 { 1.0 } else { -1.0 };
                            vec![[x, 0.0, z], [x, 0.0, z + ahead]]
                        },
                        speed: 0.0,
                    }),
                    clip_offset: (i as f32 * 0.37) % 1.0,
                    surface_at: None,
                    field: "crowd".into(),
                }
            })
            .collect()
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct RawCrowd {
    source: Spanned<String>,
    count: Spanned<i64>,
    clip: Option<String>,
    #[serde(default = "linear")]
    skinning: SkinningModel,
    spacing: Option<Spanned<[f64; 2]>>,
}

/// Reads `[crowd]`.
pub(super) fn parse_crowd(
    text: &str,
    file: &Path,
    base: &Path,
    raw: RawCrowd,
) -> Result<Crowd, ScenarioError> {
    let err_at = |span: std::ops::Range<usize>, field: &str, msg: String| {
        ScenarioError::new(file, Some(locate(text, span.start)), Some(field), msg)
    };
    // The cap on any scenario's characters: entries are listed before the
    // budget is charged, and the budget refuses far fewer of any real size.
    let count = ranges::whole(*raw.count.get_ref(), 1, ranges::MAX_CHARACTERS as i64)
        .map_err(|m| err_at(raw.count.span(), "crowd.count", m))? as usize;
    let spacing = match &raw.spacing {
        None => DEFAULT_SPACING,
        Some(s) => {
            let mut out = [0.0f32; 2];
            for (o, &v) in out.iter_mut().zip(s.get_ref()) {
                *o = ranges::between(v, MIN_SPACING, MAX_SPACING, "metres")
                    .map_err(|m| err_at(s.span(), "crowd.spacing", m))? as f32;
            }
            out
        }
    };
    let character = character_section(
        text,
        file,
        base,
        "crowd",
        &raw.source,
        raw.clip,
        raw.skinning,
    )?;
    Ok(Crowd {
        character,
        count,
        spacing,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::humanoid::HumanoidParams;
    use crate::io::CharacterSource;

    fn crowd(count: usize, spacing: [f32; 2]) -> Crowd {
        Crowd {
            character: CharacterSection {
                source: CharacterSource::Humanoid(HumanoidParams {
                    vertices: 3000,
                    seed: 1,
                }),
                clip: None,
                skinning: SkinningModel::Linear,
            },
            count,
            spacing,
        }
    }

    /// Every character stands on the plaza its extent asks for, at least
    /// the margin in from its edge, neighbours exactly the spacing apart,
    /// no two on one spot.
    #[test]
    fn a_grid_inside_its_plaza() {
        for (count, spacing) in [
            (1, [0.62, 1.0]),
            (7, [0.62, 1.0]),
            (1024, [0.62, 1.0]),
            (300, [0.4, 0.5]),
        ] {
            let c = crowd(count, spacing);
            let [w, d] = c.extent();
            let e = c.entries();
            assert_eq!(e.len(), count);
            let mut spots = Vec::new();
            for x in &e {
                let Placement::Path(p) = &x.placement else {
                    panic!("{x:?}")
                };
                assert_eq!(p.speed, 0.0);
                let [px, _, pz] = p.waypoints[0];
                assert!(
                    px >= MARGIN - 1e-4 && px <= w - MARGIN + 1e-4,
                    "{px} of {w}"
                );
                assert!(
                    pz >= MARGIN - 1e-4 && pz <= d - MARGIN + 1e-4,
                    "{pz} of {d}"
                );
                spots.push(((px * 100.0).round() as i64, (pz * 100.0).round() as i64));
            }
            spots.sort();
            spots.dedup();
            assert_eq!(spots.len(), count);
            // About square: neither side more than twice the other, beyond
            // the margins (a crowd of one is a point).
            if count > 4 {
                let (gw, gd) = (w - 2.0 * MARGIN, d - 2.0 * MARGIN);
                assert!(
                    gw < 2.0 * gd + spacing[0] && gd < 2.0 * gw + spacing[1],
                    "{gw} × {gd}"
                );
            }
        }
    }
}
