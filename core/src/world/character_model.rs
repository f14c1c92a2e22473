//! What a character of a world is made from, checked once: its mesh,
//! skeleton and skin weights ([`Character`]), the skinning model that moves
//! it, and the triangles collision detection keeps (all, or those edge
//! de-duplication keeps, paper §4). Shared (`Arc`) by every world and every
//! instance made from it.

use std::sync::Arc;

use crate::character::skinning::SkinError;
use crate::character::{Character, SkinningModel};
use crate::io::limits::{MAX_COORDINATE, within_range};
use crate::mesh::{EdgeDedup, dedup_edges};

use super::error::WorldError;

/// A character source, checked: every vertex has influences of joints the
/// skeleton has, and every bind position lies inside the coordinate range.
#[derive(Clone, Debug)]
pub struct CharacterModel {
    character: Arc<Character>,
    skinning: SkinningModel,
    kept: EdgeDedup,
    /// The bind vertices' largest distance from the origin.
    bind_reach: f32,
}

impl CharacterModel {
    /// Every triangle of `character` takes part, skinned with `skinning`.
    pub fn new(
        character: impl Into<Arc<Character>>,
        skinning: SkinningModel,
    ) -> Result<Self, WorldError> {
        let character = character.into();
        let kept = EdgeDedup::keep_all(&character.mesh);
        Self::with_kept(character, skinning, kept)
    }

    /// Only the triangles edge de-duplication keeps take part (a triangle
    /// whose three edges kept neighbours carry is left out, paper §4).
    pub fn deduplicated(
        character: impl Into<Arc<Character>>,
        skinning: SkinningModel,
    ) -> Result<Self, WorldError> {
        let character = character.into();
        let kept = dedup_edges(&character.mesh);
        Self::with_kept(character, skinning, kept)
    }

    /// The triangles `kept` keeps take part (a de-duplication computed once
    /// for several models of one character).
    pub fn with_kept(
        character: impl Into<Arc<Character>>,
        skinning: SkinningModel,
        kept: EdgeDedup,
    ) -> Result<Self, WorldError> {
        let character = character.into();
        let mesh = &character.mesh;
        let vertices = mesh.vertex_count();
        let triangles = kept.kept_count() + kept.dropped_count();
        if triangles != mesh.triangle_count() {
            return Err(WorldError::KeptCount {
                expected: mesh.triangle_count(),
                got: triangles,
            });
        }
        for (what, got) in [
            ("influences", character.influences.len()),
            ("paper binding", character.paper.len()),
        ] {
            if got != vertices {
                return Err(SkinError::Length {
                    what,
                    got,
                    vertices,
                }
                .into());
            }
        }
        let joints = character.skeleton.len();
        for v in 0..vertices {
            let bad = character
                .influences
                .of(v)
                .map(|(j, _)| j.index())
                .chain([character.paper.joint(v).index()])
                .find(|&j| j >= joints);
            if let Some(joint) = bad {
                return Err(SkinError::JointOutOfRange {
                    vertex: v,
                    joint,
                    joints,
                }
                .into());
            }
        }
        let mut bind_reach = 0.0f32;
        for (vertex, p) in mesh.positions().iter().enumerate() {
            let d = p.coords.norm();
            if !within_range(d) {
                return Err(WorldError::MeshOutOfRange {
                    what: "character",
                    vertex,
                    distance: d,
                    limit: MAX_COORDINATE,
                });
            }
            bind_reach = bind_reach.max(d);
        }
        Ok(Self {
            character,
            skinning,
            kept,
            bind_reach,
        })
    }

    /// The character: mesh, skeleton, weights, clips.
    pub fn character(&self) -> &Character {
        &self.character
    }

    /// The character, shared.
    pub fn shared_character(&self) -> &Arc<Character> {
        &self.character
    }

    /// The skinning model that moves it.
    pub fn skinning(&self) -> SkinningModel {
        self.skinning
    }

    /// The triangles collision detection keeps.
    pub fn kept(&self) -> &EdgeDedup {
        &self.kept
    }

    /// The bind vertices' largest distance from the origin.
    pub fn bind_reach(&self) -> f32 {
        self.bind_reach
    }
}
