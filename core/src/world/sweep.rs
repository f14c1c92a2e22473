//! Continuous detection of a world over a step (the paper's future work,
//! §7; docs/ccd.md, "Swept hierarchies"): every vertex moves on a straight
//! line from its position at the last sweep to its position now
//! (characters: skinned; objects: posed, their path bounded by a
//! [`RigidPath`]). Per sweep:
//!
//! 1. every character, side by side: its swept tree against every room,
//!    against itself (worlds that test self-contact), the broad phase on
//!    swept root spheres against every object swept along its path, and
//!    the object passes;
//! 2. swept roots between characters, then each pair that meets;
//! 3. the contacts with their times of impact, sorted, and the counters.
//!
//! An inactive character, object or room is left out. One set active again
//! starts its steps where it is: the first sweep after that records its
//! pose and finds nothing for it (as a world's first sweep does).
//!
//! The end of one sweep is the start of the next, so a character's refit
//! states at the end are reused, not redone. Nothing is allocated per sweep
//! once the buffers are sized.

use std::time::Instant;

use nalgebra::{Isometry3, Vector3};

use crate::geometry::Sphere;
use crate::geometry::ccd_root_finder::CcdParams;
use crate::geometry::ccd_sphere_plane::StillPlane;
use crate::pipeline::FrameCounters;
use crate::pipeline::continuous_narrow::CcdCounters;
use crate::pipeline::pass::run;
use crate::pipeline::swept_passes::{SweptObjectPass, SweptPairPass, SweptRoomPass, SweptSelfPass};
use crate::pipeline::swept_side::{StepPose, SweptSide};
use crate::sphere_tree::NodeId;
use crate::sphere_tree::swept_rigid::RigidPath;

use super::bodies::{CharacterBody, RigidBody};
use super::broad_phase::SortAndSweep;
use super::collision_world::CollisionWorld;
use super::contacts::{CharacterPair, ObjectPair, RoomPair, SelfPair, SweepContacts, Timed};
use super::continuous_state::ContinuousState;
use super::error::WorldError;
use super::handles::{CharacterHandle, ObjectHandle, RoomHandle};
use super::step::{character_pairs, side_by_side};

impl CollisionWorld {
    /// Says how object `h` moves over the next [`Self::sweep`]: `path`
    /// (from its pose at the last sweep to its current pose) with its
    /// travel and turn, which bound where a rotating body's vertices go
    /// between the ends. Without it, the object's vertices move on straight
    /// lines between the two poses, as the continuous kernels assume.
    pub fn set_object_path(&mut self, h: ObjectHandle, path: RigidPath) -> Result<(), WorldError> {
        let cs = self.continuous.as_mut().ok_or(WorldError::ContinuousOff)?;
        let slot = cs
            .next_paths
            .get_mut(h.index())
            .ok_or(WorldError::UnknownObject(h))?;
        *slot = Some(path);
        Ok(())
    }

    /// Each object's path over the last sweep (empty when continuous
    /// detection is off).
    pub fn object_paths(&self) -> &[RigidPath] {
        self.continuous.as_ref().map_or(&[], |c| &c.paths)
    }

    /// Makes the next [`Self::sweep`] a first one: it records the poses as
    /// the start of the following step and finds nothing (after a jump in
    /// time, when the poses of the last sweep are not where the next step
    /// starts).
    pub fn restart_sweep(&mut self) {
        if let Some(cs) = self.continuous.as_mut() {
            cs.started = false;
        }
    }

    /// The contacts of the last sweep, when continuous detection is on.
    pub fn sweep_contacts(&self) -> Option<&SweepContacts> {
        self.continuous.as_ref().map(|c| &c.contacts)
    }

    /// Detects every contact during the step from the poses at the last
    /// sweep to the current ones, with times of impact (continuous
    /// detection; [`Self::enable_continuous`] first). The first sweep has no
    /// step: it records the poses and finds nothing.
    pub fn sweep(&mut self) -> Result<&SweepContacts, WorldError> {
        let t0 = Instant::now();
        crate::pipeline::counters::refine_tick_rate();
        let cull_rigid = self.settings.self_rigid_culling;
        let CollisionWorld {
            method,
            rooms,
            objects,
            characters,
            continuous,
            character_roots,
            broad_phase,
            candidates,
            ..
        } = self;
        let cs = continuous.as_mut().ok_or(WorldError::ContinuousOff)?;
        let method = *method;
        cs.contacts.clear();
        // Whether this sweep detects (then its end states are the next
        // one's start states).
        let detects = cs.started;
        for c in characters.iter_mut() {
            let c = c.get_mut().expect("no pass panicked");
            c.sweep.as_mut().expect("continuous detection is on").swept = false;
        }
        if detects {
            // An object swept now was active at the last sweep and is now.
            for ((swept, primed), o) in cs
                .object_swept
                .iter_mut()
                .zip(&cs.object_primed)
                .zip(objects.iter())
            {
                *swept = *primed && o.active;
            }
            for ((path, next), (start, o)) in cs
                .paths
                .iter_mut()
                .zip(&mut cs.next_paths)
                .zip(cs.object_starts.iter().zip(objects.iter()))
            {
                *path = next.take().unwrap_or_else(|| straight(start, &o.pose));
            }
            // 1. Each character against the rooms and the objects.
            let (params, planes) = (&cs.params, &cs.room_planes);
            let (paths, swept) = (&cs.paths, &cs.object_swept);
            side_by_side(characters, |c| {
                let c = c.get_mut().expect("no pass panicked");
                // Swept now: active at the last sweep and now (a character
                // set active again starts its steps where it is).
                let s = c.sweep.as_mut().expect("continuous detection is on");
                if !(c.active && s.primed) {
                    sit_out_sweep(c);
                    return;
                }
                s.swept = true;
                own_sweeps(
                    c,
                    (method, cull_rigid),
                    params,
                    rooms,
                    planes,
                    (objects, paths, swept),
                );
            });
            // 2. Characters against each other.
            let (tests, pairs) =
                sweep_pairs(characters, character_roots, broad_phase, candidates, cs);
            // 3. The contacts.
            gather(characters, cs, tests, pairs);
        }
        // The end of this sweep starts the next.
        cs.started = true;
        for ((start, primed), o) in cs
            .object_starts
            .iter_mut()
            .zip(cs.object_primed.iter_mut())
            .zip(objects.iter())
        {
            *start = o.pose;
            *primed = o.active;
        }
        for c in characters.iter_mut() {
            let c = c.get_mut().expect("no pass panicked");
            let pose = &c.pose;
            let s = c.sweep.as_mut().expect("continuous detection is on");
            s.start.skin.copy_from_slice(&pose.skin);
            s.start.base = pose.base;
            s.continues = s.swept;
            s.primed = c.active;
        }
        cs.contacts.wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        Ok(&cs.contacts)
    }
}

/// Vertices on straight lines from `from` to `to`.
fn straight(from: &Isometry3<f32>, to: &Isometry3<f32>) -> RigidPath {
    RigidPath {
        from: *from,
        to: *to,
        travel: 0.0,
        turn: 0.0,
        axis_point: Vector3::zeros(),
    }
}

/// Character `c`'s step as a pass sees it.
fn swept_side(c: &mut CharacterBody) -> SweptSide<'_> {
    let s = c.sweep.as_mut().expect("continuous detection is on");
    SweptSide {
        character: c.model.character(),
        tree: &c.tree,
        model: c.model.skinning(),
        pose: StepPose {
            start: s.start.as_pose(),
            end: c.pose.as_pose(),
        },
        state: &mut s.state,
    }
}

/// Character `c`'s sweeps against every room, against itself when the world
/// asks, and against every object its swept root sphere meets. `how`: the
/// method, and whether the self sweep skips parts one joint moves.
fn own_sweeps(
    c: &mut CharacterBody,
    (method, cull_rigid): (crate::pipeline::Method, bool),
    params: &CcdParams,
    rooms: &[RigidBody],
    planes: &[Vec<StillPlane>],
    (objects, paths, swept): (&[RigidBody], &[RigidPath], &[bool]),
) {
    let s = c.sweep.as_mut().expect("continuous detection is on");
    let continues = s.continues;
    let CharacterBody {
        handle,
        model,
        tree,
        pose,
        sweep,
        own,
        itself,
        groups,
        ..
    } = c;
    let s = sweep.as_mut().expect("continuous detection is on");
    let mut side = SweptSide {
        character: model.character(),
        tree,
        model: model.skinning(),
        pose: StepPose {
            start: s.start.as_pose(),
            end: pose.as_pose(),
        },
        state: &mut s.state,
    };
    side.state.begin_step(side.pose, continues);
    own.ccd = CcdCounters::default();
    own.rooms = FrameCounters::default();
    for ((room, planes), slot) in rooms.iter().zip(planes).zip(s.rooms.iter_mut()) {
        if !room.meets(*groups) {
            slot.hits.clear();
            continue;
        }
        let mut pass = SweptRoomPass {
            character: side.reborrow(),
            room: &room.tree,
            planes,
            mesh: &room.mesh,
            method,
            params,
            ccd: &mut own.ccd,
        };
        let c = run(&mut pass, &mut slot.scratch, &mut slot.hits);
        own.rooms.add(&c);
    }
    own.itself = FrameCounters::default();
    if let (Some(data), Some(slot)) = (itself.as_deref_mut(), s.itself.as_mut()) {
        let mut pass = SweptSelfPass {
            character: side.reborrow(),
            data: &data.data,
            gaps: &mut data.gaps,
            cull_rigid,
            params,
            ccd: &mut own.ccd,
        };
        own.itself = run(&mut pass, &mut slot.scratch, &mut slot.hits);
    }
    own.root = side.root_sphere();
    own.objects = FrameCounters::default();
    own.broad_phase_tests = 0;
    own.body_pairs = 0;
    s.object_pairs.clear();
    let Some(root) = own.root else { return };
    for (o, ((body, path), &swept)) in objects.iter().zip(paths).zip(swept).enumerate() {
        if !swept || body.tree.tree.is_empty() || !body.meets(*groups) {
            continue;
        }
        own.broad_phase_tests += 1;
        let oroot = path.sweep(&body.tree.tree.nodes()[NodeId::ROOT.index()].sphere);
        if !root.overlaps(&oroot) {
            continue;
        }
        own.body_pairs += 1;
        let mut pass = SweptObjectPass {
            character: side.reborrow(),
            object: &body.tree,
            mesh: &body.mesh,
            path,
            params,
            ccd: &mut own.ccd,
        };
        let slot = &mut s.objects;
        let c = run(&mut pass, &mut slot.scratch, &mut slot.hits);
        own.objects.add(&c);
        s.object_pairs.extend(slot.hits.iter().map(|p| Timed {
            pair: ObjectPair {
                character: *handle,
                triangle: p.a,
                object: ObjectHandle(o as u32),
                object_triangle: p.b,
            },
            toi: p.toi,
            by_plane: p.by_plane,
        }));
    }
}

/// A sweep that leaves character `c` out (inactive, or set active since
/// the last sweep): no root, no contacts, no counters.
fn sit_out_sweep(c: &mut CharacterBody) {
    c.own = Default::default();
    let s = c.sweep.as_mut().expect("continuous detection is on");
    for slot in &mut s.rooms {
        slot.hits.clear();
    }
    if let Some(slot) = s.itself.as_mut() {
        slot.hits.clear();
    }
    s.object_pairs.clear();
}

/// Swept roots between characters (the broad phase over them), then each
/// pair that meets, one after the other; returns the root tests and the
/// pairs traversed.
fn sweep_pairs(
    characters: &mut [std::sync::Mutex<CharacterBody>],
    roots: &mut Vec<Option<Sphere>>,
    broad_phase: &mut SortAndSweep,
    candidates: &mut Vec<(u32, u32)>,
    cs: &mut ContinuousState,
) -> (u64, u64) {
    let tests = character_pairs(characters, roots, broad_phase, candidates);
    let pairs = candidates.len() as u64;
    let out = &mut cs.contacts;
    for &(i, j) in candidates.iter() {
        let (i, j) = (i as usize, j as usize);
        let (lo, hi) = characters.split_at_mut(j);
        let a = lo[i].get_mut().expect("no pass panicked");
        let b = hi[0].get_mut().expect("no pass panicked");
        let mut pass = SweptPairPass {
            a: swept_side(a),
            b: swept_side(b),
            params: &cs.params,
            ccd: &mut cs.pair_ccd,
        };
        let slot = &mut cs.pairs;
        let c = run(&mut pass, &mut slot.scratch, &mut slot.hits);
        out.by_kind.characters.add(&c);
        let (ha, hb) = (CharacterHandle(i as u32), CharacterHandle(j as u32));
        out.character_pairs.extend(slot.hits.iter().map(|p| Timed {
            pair: CharacterPair {
                a: ha,
                triangle_a: p.a,
                b: hb,
                triangle_b: p.b,
            },
            toi: p.toi,
            by_plane: false,
        }));
    }
    out.by_kind.characters.sphere_sphere += tests;
    (tests, pairs)
}

/// The sweep's contacts, in a fixed order, and its counters.
fn gather(
    characters: &mut [std::sync::Mutex<CharacterBody>],
    cs: &mut ContinuousState,
    tests: u64,
    pairs: u64,
) {
    let out = &mut cs.contacts;
    out.broad_phase_tests = tests;
    out.body_pairs = pairs;
    out.extra.add(&cs.pair_ccd);
    cs.pair_ccd = CcdCounters::default();
    let (mut refits, mut skinned) = (0, 0);
    for (i, c) in characters.iter_mut().enumerate() {
        let c = c.get_mut().expect("no pass panicked");
        let s = c.sweep.as_ref().expect("continuous detection is on");
        if !s.swept {
            continue;
        }
        refits += s.state.refits();
        skinned += s.state.skinned();
        c.own.add_to(out);
        out.extra.add(&c.own.ccd);
        let h = CharacterHandle(i as u32);
        out.object_pairs.extend_from_slice(&s.object_pairs);
        if let Some(slot) = &s.itself {
            out.self_pairs.extend(slot.hits.iter().map(|p| Timed {
                pair: SelfPair {
                    character: h,
                    triangle_a: p.a,
                    triangle_b: p.b,
                },
                toi: p.toi,
                by_plane: false,
            }));
        }
        for (r, slot) in s.rooms.iter().enumerate() {
            out.room_pairs.extend(slot.hits.iter().map(|p| Timed {
                pair: RoomPair {
                    character: h,
                    triangle: p.a,
                    room: RoomHandle(r as u32),
                    room_triangle: p.b,
                },
                toi: p.toi,
                by_plane: p.by_plane,
            }));
        }
    }
    out.room_pairs.sort_unstable_by_key(|p| p.pair);
    out.object_pairs.sort_unstable_by_key(|p| p.pair);
    out.character_pairs.sort_unstable_by_key(|p| p.pair);
    out.self_pairs.sort_unstable_by_key(|p| p.pair);
    out.sum_kinds(refits, skinned);
}
