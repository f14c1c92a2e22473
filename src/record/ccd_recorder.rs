//! What `run --ccd` adds to a method's recording at each frame step
//! (docs/recordings.md, "Continuous detection"; paths in [`super::layout`]):
//! the swept spheres of the character leaves that touch during the step
//! (wireframes), the characters and the touching objects posed at a time of
//! impact with the pairs touching there (the character's triangles filled,
//! the other side's outlined), and counters. Under `cd/`, so every 3D view of the blueprints shows them.
//!
//! The time of impact shown is the earliest among the pairs the method's
//! discrete frames missed at both ends (tunnelling), else the step's
//! earliest. Bodies there are interpolated between the two frames, as
//! continuous detection assumes (every vertex on a straight line).

use nalgebra::Isometry3;
use rerun::RecordingStream;

use super::draw::body_entity;
use super::layout;
use crate::scenario::Resolved;
use crate::truth::substep_score::StepPair;
use cornertree::geometry::Point;
use cornertree::pipeline::SweepState;
use cornertree::sphere_tree::character::CharacterTree;
use cornertree::sphere_tree::swept::SphereSweep;
use cornertree::world::CharacterHandle;
use cornertree::world::SweepContacts;

/// Pairs shown at the time of impact: those whose own time of impact is
/// within this fraction of the step after it.
pub const TOI_WINDOW: f64 = 0.02;

/// One step as the recorder reads it.
pub struct StepView<'a> {
    pub scene: &'a Resolved,
    pub outcome: &'a SweepContacts,
    /// Each character's skinned vertices at both ends.
    pub start: Vec<&'a [Point]>,
    pub end: Vec<&'a [Point]>,
    pub object_start: &'a [Isometry3<f32>],
    pub object_end: &'a [Isometry3<f32>],
    /// Each character's sweep (refit spheres at both ends).
    pub sweeps: Vec<&'a SweepState>,
    /// The pairs the discrete frames missed at both ends (sorted).
    pub missed_by_discrete: &'a [StepPair],
    /// Recall against the sub-stepped reference, if computed.
    pub recall: Option<f64>,
}

/// Writes the continuous part of one method's frames.
pub struct CcdRecorder {
    characters: Vec<String>,
    objects: Vec<String>,
    /// Per character: the leaf node of every triangle in its tree.
    leaf_of: Vec<Vec<u32>>,
}

fn lerp(a: &Point, b: &Point, t: f32) -> [f32; 3] {
    let l = |x: f32, y: f32| x + (y - x) * t;
    [l(a.x, b.x), l(a.y, b.y), l(a.z, b.z)]
}

impl CcdRecorder {
    pub fn new(scene: &Resolved, trees: &[&CharacterTree]) -> Self {
        let leaf_of = trees
            .iter()
            .zip(&scene.characters)
            .map(|(t, a)| {
                let mut v = vec![u32::MAX; a.character.mesh.triangle_count()];
                for (i, n) in t.tree.nodes().iter().enumerate() {
                    if let Some(p) = n.primitive() {
                        v[p as usize] = i as u32;
                    }
                }
                v
            })
            .collect();
        Self {
            characters: scene
                .characters
                .iter()
                .enumerate()
                .map(|(i, a)| format!("{}/characters/{}", layout::CCD_TOI, body_entity(i, &a.name)))
                .collect(),
            objects: scene
                .objects
                .iter()
                .enumerate()
                .map(|(i, o)| format!("{}/objects/{}", layout::CCD_TOI, body_entity(i, &o.name)))
                .collect(),
            leaf_of,
        }
    }

    /// Logs step `k − 1 → k` at frame `k` (the stream's time is set here).
    pub fn log_step(
        &self,
        rec: &RecordingStream,
        k: usize,
        v: &StepView<'_>,
    ) -> rerun::RecordingStreamResult<()> {
        rec.set_time_sequence(layout::FRAME, k as i64);
        let o = v.outcome;
        let pairs = crate::report::continuous::continuous_step_pairs(o);
        rec.log(
            layout::CCD_STATS[0],
            &rerun::Scalars::single(pairs.len() as f64),
        )?;
        rec.log(
            layout::CCD_STATS[1],
            &rerun::Scalars::single(v.missed_by_discrete.len() as f64),
        )?;
        if let Some(r) = v.recall {
            rec.log(layout::CCD_STATS[2], &rerun::Scalars::single(r))?;
        }
        if let Some(t) = o.earliest() {
            rec.log(layout::CCD_STATS[3], &rerun::Scalars::single(t))?;
        }
        let focus = pairs
            .iter()
            .filter(|p| v.missed_by_discrete.binary_search(&p.pair).is_ok())
            .map(|p| p.toi)
            .min_by(f64::total_cmp)
            .or_else(|| o.earliest());
        let Some(toi) = focus else {
            rec.log(layout::CCD, &rerun::Clear::recursive())?;
            return Ok(());
        };
        let t = toi as f32;

        // Every body at the time of impact.
        for (c, path) in self.characters.iter().enumerate() {
            let a = &v.scene.characters[c].character;
            let verts = v.start[c].iter().zip(v.end[c]).map(|(x, y)| lerp(x, y, t));
            rec.log(
                path.as_str(),
                &rerun::Mesh3D::new(verts)
                    .with_triangle_indices(a.mesh.indices().iter().copied())
                    .with_albedo_factor(layout::CCD_TOI_COLOR),
            )?;
        }
        // The pairs touching there, both triangles at the time of impact,
        // and the swept spheres of the character leaves of every pair.
        let mut verts: Vec<[f32; 3]> = Vec::new();
        let mut others: Vec<[[f32; 3]; 4]> = Vec::new();
        let (mut centers, mut radii) = (Vec::new(), Vec::new());
        let mut involved = vec![false; self.objects.len()];
        let mut shown = 0usize;
        for p in &pairs {
            let (c, tri) = match p.pair {
                StepPair::Environment(q) => (q.character, q.triangle),
                StepPair::Objects(q) => (q.character, q.triangle),
                StepPair::Characters(q) => (q.a, q.triangle_a),
                StepPair::SelfContact(q) => (q.character, q.triangle_a),
            };
            if let StepPair::Objects(q) = p.pair {
                involved[q.object.index()] = true;
            }
            let leaf = self.leaf_of[c.index()][tri as usize];
            if leaf != u32::MAX {
                let (s0, s1) = v.sweeps[c.index()].refit_states();
                let sw = SphereSweep {
                    start: s0.spheres[leaf as usize],
                    end: s1.spheres[leaf as usize],
                }
                .swept();
                centers.push([sw.center.x, sw.center.y, sw.center.z]);
                radii.push(sw.radius);
            }
            if p.toi > toi + TOI_WINDOW {
                continue;
            }
            shown += 1;
            let char_tri = |c: CharacterHandle, t: u32| {
                let idx = v.scene.characters[c.index()].character.mesh.indices()[t as usize];
                idx.map(|i| {
                    lerp(
                        &v.start[c.index()][i as usize],
                        &v.end[c.index()][i as usize],
                        toi as f32,
                    )
                })
            };
            verts.extend(char_tri(c, tri));
            let other = match p.pair {
                StepPair::Environment(q) => {
                    let m = &v.scene.environment.mesh;
                    let idx = m.indices()[q.room_triangle as usize];
                    idx.map(|i| {
                        let x = m.positions()[i as usize];
                        [x.x, x.y, x.z]
                    })
                }
                StepPair::Objects(q) => {
                    let m = &v.scene.objects[q.object.index()].mesh;
                    let (from, to) = (
                        &v.object_start[q.object.index()],
                        &v.object_end[q.object.index()],
                    );
                    let idx = m.indices()[q.object_triangle as usize];
                    idx.map(|i| {
                        let x = m.positions()[i as usize];
                        lerp(&(from * x), &(to * x), toi as f32)
                    })
                }
                StepPair::Characters(q) => char_tri(q.b, q.triangle_b),
                StepPair::SelfContact(q) => char_tri(q.character, q.triangle_b),
            };
            others.push([other[0], other[1], other[2], other[0]]);
        }
        // The objects touching during the step, at the time of impact.
        for (o_i, path) in self.objects.iter().enumerate() {
            if !involved[o_i] {
                continue;
            }
            let mesh = &v.scene.objects[o_i].mesh;
            let (from, to) = (&v.object_start[o_i], &v.object_end[o_i]);
            let verts = mesh
                .positions()
                .iter()
                .map(|p| lerp(&(from * p), &(to * p), t));
            rec.log(
                path.as_str(),
                &rerun::Mesh3D::new(verts)
                    .with_triangle_indices(mesh.indices().iter().copied())
                    .with_albedo_factor(layout::OBJECT_COLOR),
            )?;
        }

        let tris = (0..verts.len() as u32 / 3).map(|i| [3 * i, 3 * i + 1, 3 * i + 2]);
        rec.log(
            layout::CCD_TOI_PAIRS,
            &rerun::Mesh3D::new(verts)
                .with_triangle_indices(tris)
                .with_albedo_factor(layout::CCD_PAIR_COLOR),
        )?;
        // The other side as outlines: an object's or the room's triangles
        // can be far bigger than the character's.
        rec.log(
            layout::CCD_TOI_OTHER,
            &rerun::LineStrips3D::new(others)
                .with_colors([layout::CCD_OTHER_COLOR])
                .with_radii([rerun::Radius::new_ui_points(1.5)]),
        )?;
        rec.log(
            layout::CCD_SWEPT,
            &rerun::Ellipsoids3D::from_centers_and_radii(centers, radii)
                .with_colors([layout::CCD_SWEPT_COLOR])
                .with_fill_mode(rerun::FillMode::MajorWireframe),
        )?;
        rec.log(
            layout::EVENTS,
            &rerun::TextLog::new(format!(
                "step {} → {k}: {} pairs touch during the step, earliest time of impact {:.4}; \
                 {} missed by the discrete frames at both ends; shown at t = {toi:.4} of the \
                 step with the {shown} pairs touching within {TOI_WINDOW} after it",
                k - 1,
                pairs.len(),
                o.earliest().unwrap_or(toi),
                v.missed_by_discrete.len(),
            ))
            .with_level("INFO"),
        )?;
        Ok(())
    }
}
