//! One discrete step of a world ([`CollisionWorld::step`]).
//!
//! 1. Every character starts its step (spheres and skinned vertices stale)
//!    and refits its root sphere, characters side by side.
//! 2. The broad phase between characters' root spheres (every pair below
//!    [`SWEEP_FROM`] characters, sort and sweep above: [`SortAndSweep`])
//!    lists the character pairs to traverse.
//! 3. Every pass runs on the pool's threads ([`PassGraph`]): each
//!    character's passes against the rooms and, after the broad phase
//!    against every object's root sphere at its pose, against each object
//!    it meets; then its passes against the characters it meets, in any
//!    order, one at a time (each refits and skins both characters on
//!    demand). A pass starts as soon as its characters are free: no barrier
//!    between the rooms' passes and the character pairs.
//! 4. The contacts, in a fixed order.
//!
//! An inactive character, object or room takes part in none of this: no
//! root sphere, no pass, no contact, no counter.
//!
//! Which thread runs what never changes a counter or a pair: a pass's tests
//! do not depend on which spheres were refit before it, and each sphere and
//! vertex is refit or skinned at most once a step whichever pass asks
//! first. A character's own passes run before its pairs, so the refits and
//! skinned vertices counted for the rooms and objects are the same on any
//! thread, and those counted for the character pairs add up to the rest.
//!
//! [`PassGraph`]: super::pass_graph::PassGraph
//! [`SortAndSweep`]: super::broad_phase::SortAndSweep
//! [`SWEEP_FROM`]: super::broad_phase::SWEEP_FROM

use std::time::Instant;

use rayon::prelude::*;

use crate::geometry::Sphere;
use crate::pipeline::FrameCounters;
use crate::pipeline::Identity;
use crate::pipeline::character_side::CharacterSide;
use crate::pipeline::counters::{ms_since, refine_tick_rate, ticks};
use crate::pipeline::pair_pass::PairPass;
use crate::pipeline::pass::run;
use crate::pipeline::rigid_pass::RigidPass;
use crate::pipeline::self_pass::{SelfCulling, SelfPass};
use crate::pipeline::visit_log::NoLog;
use crate::sphere_tree::NodeId;

use super::bodies::{CharacterBody, RigidBody};
use super::collision_world::{CollisionWorld, PairState};
use super::contacts::{CharacterPair, ObjectPair, RoomPair, SelfPair, StepContacts};
use super::handles::{CharacterHandle, ObjectHandle, RoomHandle};

impl CollisionWorld {
    /// Detects every contact at the current poses: each character against
    /// the rooms, the objects its root sphere meets and the characters its
    /// root sphere meets, on the current rayon pool.
    pub fn step(&mut self) -> &StepContacts {
        let t0 = Instant::now();
        refine_tick_rate();
        // Objects' root spheres in the world.
        for (root, o) in self.object_roots.iter_mut().zip(&self.objects) {
            *root = (o.active && !o.tree.tree.is_empty()).then(|| {
                o.tree.tree.nodes()[NodeId::ROOT.index()]
                    .sphere
                    .in_frame(&o.pose)
            });
        }
        // 1. Each character's step starts and its root sphere is refit (a
        //    few dozen spheres; the room pass counts them, from the step's
        //    start, and would refit them first anyway).
        side_by_side(&mut self.characters, |c| {
            let t0 = ticks();
            let c = c.get_mut().expect("no pass panicked");
            if !c.active {
                c.sit_out_step();
                return;
            }
            c.begin_step_frame();
            c.own.root = side(c).root_sphere();
            c.own.start_seconds = (ms_since(t0) * 1e-3) as f32;
        });

        // 2. The broad phase between characters' root spheres.
        let t1 = Instant::now();
        let char_tests = self.character_broad_phase();
        while self.pairs.len() < self.candidates.len() {
            self.pairs.push(Default::default());
        }

        // 3. Every pass.
        // Sized for the characters once they are all added (not rebuilt at
        // every `add_character`: its size is quadratic in them).
        if self.graph.characters() != self.characters.len() {
            self.graph = super::pass_graph::PassGraph::new(self.characters.len());
        }
        self.graph.set_pairs(self.candidates.iter().copied());
        self.lent.prepare(rayon::current_num_threads());
        let serial_before = t1.elapsed().as_secs_f64();
        let n = self.characters.len();
        let CollisionWorld {
            method,
            settings,
            rooms,
            objects,
            object_roots,
            characters,
            pairs,
            graph,
            lent,
            ..
        } = self;
        let (method, timed) = (*method, settings.time_refit);
        let culling = SelfCulling {
            rigid: settings.self_rigid_culling,
            normal_cones: settings.self_normal_cone_culling,
        };
        graph.run(|t, pair| match pair {
            // A pass holds its characters alone: these locks are never
            // contended.
            None => {
                let mut c = characters[t].lock().expect("no pass panicked");
                lent.with(|l| {
                    own_passes(
                        &mut c,
                        l,
                        (method, timed, culling),
                        rooms,
                        objects,
                        object_roots,
                    )
                });
            }
            Some((i, j)) => {
                let mut s = pairs[t - n].lock().expect("no pass panicked");
                let mut a = characters[i as usize].lock().expect("no pass panicked");
                let mut b = characters[j as usize].lock().expect("no pass panicked");
                let PairState {
                    a: sa,
                    b: sb,
                    counters,
                    hits,
                } = &mut *s;
                (*sa, *sb) = (i, j);
                let mut pass = PairPass {
                    a: side(&mut a),
                    b: side(&mut b),
                    timed,
                };
                *counters = lent.with(|l| run(&mut pass, &mut l.scratch, hits));
            }
        });

        // 4. The contacts, in a fixed order.
        let t2 = Instant::now();
        self.lent.settle();
        self.gather(char_tests);
        let serial = serial_before + t2.elapsed().as_secs_f64();
        let (mut start_work, mut start_span) = (0.0f64, 0.0f64);
        for c in &mut self.characters {
            let s = f64::from(c.get_mut().expect("no pass panicked").own.start_seconds);
            start_work += s;
            start_span = start_span.max(s);
        }
        let (work, span) = self.graph.work_span();
        let out = &mut self.contacts;
        out.work_ms = (start_work + serial + work) * 1e3;
        out.span_ms = (start_span + serial + span) * 1e3;
        out.wall_ms = t0.elapsed().as_secs_f64() * 1e3;
        &self.contacts
    }

    /// The broad phase between characters' root spheres (`root` of each):
    /// lists the pairs that meet in `candidates`, ascending; returns the
    /// sphere tests made.
    pub(crate) fn character_broad_phase(&mut self) -> u64 {
        character_pairs(
            &mut self.characters,
            &mut self.character_roots,
            &mut self.broad_phase,
            &mut self.candidates,
        )
    }

    fn gather(&mut self, char_tests: u64) {
        let out = &mut self.contacts;
        out.clear();
        out.broad_phase_tests = char_tests;
        out.body_pairs = self.candidates.len() as u64;
        out.by_kind.characters.sphere_sphere += char_tests;
        // Refits and skinned vertices: each character's own count for the
        // step (every pass adds to it once).
        let (mut refits, mut skinned) = (0, 0);
        for (i, c) in self.characters.iter_mut().enumerate() {
            let c = c.get_mut().expect("no pass panicked");
            let (r, s) = c.step_work();
            refits += r;
            skinned += s;
            c.own.add_to(out);
            out.object_pairs.extend_from_slice(&c.object_pairs);
            if let Some(s) = &c.itself {
                out.self_pairs
                    .extend(s.slot.hits.iter().map(|&(ta, tb)| SelfPair {
                        character: CharacterHandle(i as u32),
                        triangle_a: ta,
                        triangle_b: tb,
                    }));
            }
            for (r, slot) in c.rooms.iter().enumerate() {
                out.room_pairs
                    .extend(slot.hits.iter().map(|&(t, rt)| RoomPair {
                        character: CharacterHandle(i as u32),
                        triangle: t,
                        room: RoomHandle(r as u32),
                        room_triangle: rt,
                    }));
            }
        }
        for s in &mut self.pairs[..self.candidates.len()] {
            let s = s.get_mut().expect("no pass panicked");
            out.by_kind.characters.add(&s.counters);
            let (a, b) = (CharacterHandle(s.a), CharacterHandle(s.b));
            out.character_pairs
                .extend(s.hits.iter().map(|&(ta, tb)| CharacterPair {
                    a,
                    triangle_a: ta,
                    b,
                    triangle_b: tb,
                }));
        }
        out.room_pairs.sort_unstable();
        out.object_pairs.sort_unstable();
        out.character_pairs.sort_unstable();
        out.self_pairs.sort_unstable();
        out.sum_kinds(refits, skinned);
    }
}

/// The pairs of `characters` whose root spheres (`own.root`) meet, by
/// `broad_phase`, into `pairs` (ascending; `roots` is its scratch); returns
/// the sphere tests made. Discrete steps and sweeps both find their
/// character pairs here.
pub(crate) fn character_pairs(
    characters: &mut [std::sync::Mutex<CharacterBody>],
    roots: &mut Vec<Option<Sphere>>,
    broad_phase: &mut super::broad_phase::SortAndSweep,
    pairs: &mut Vec<(u32, u32)>,
) -> u64 {
    roots.clear();
    roots.extend(
        characters
            .iter_mut()
            .map(|c| c.get_mut().expect("no pass panicked").own.root),
    );
    let tests = broad_phase.pairs(roots, pairs);
    // Pairs whose groups do not meet are not traversed.
    let mut groups = |i: u32| {
        characters[i as usize]
            .get_mut()
            .expect("no pass panicked")
            .groups
    };
    pairs.retain(|&(i, j)| groups(i).meets(groups(j)));
    tests
}

/// Character `c` as a pass sees it.
pub(crate) fn side(c: &mut CharacterBody) -> CharacterSide<'_> {
    CharacterSide {
        character: c.model.character(),
        tree: &c.tree,
        model: c.model.skinning(),
        pose: c.pose.as_pose(),
        refit: &mut c.refit,
        skin: &mut c.skin,
    }
}

/// Character `i`'s own passes: against every room (its frame start's refits
/// and refit ahead counted with them), against itself when the world asks,
/// then against every object whose root sphere its root sphere meets.
/// `how`: the method, whether refits are timed, what the self pass culls.
fn own_passes(
    c: &mut CharacterBody,
    lent: &mut super::pass_pool::Lent,
    (method, timed, culling): (crate::pipeline::Method, bool, SelfCulling),
    rooms: &[RigidBody],
    objects: &[RigidBody],
    object_roots: &[Option<Sphere>],
) {
    // An inactive character sat the step out at its start.
    if !c.active {
        return;
    }
    // Last step's nodes first, when the method refits ahead (timed only
    // then: two clock reads the other methods need not pay).
    let ahead_ms = if c.refit.refits_ahead_on() {
        let t0 = ticks();
        side(c).refit_ahead();
        ms_since(t0)
    } else {
        0.0
    };
    let (refits, skinned_vertices) = c.step_work();
    let mut counters = FrameCounters {
        refits,
        skinned_vertices,
        ..FrameCounters::default()
    };
    if timed {
        counters.time.refit_ms = ahead_ms;
    } else {
        counters.time.traversal_ms = ahead_ms;
    }
    let CharacterBody {
        handle,
        model,
        tree,
        pose,
        refit,
        skin,
        rooms: slots,
        visits,
        object_hits,
        object_pairs,
        own,
        itself,
        groups,
        ..
    } = c;
    let super::pass_pool::Lent { marks, scratch } = lent;
    let mut character = CharacterSide {
        character: model.character(),
        tree,
        model: model.skinning(),
        pose: pose.as_pose(),
        refit,
        skin,
    };
    for (r, (room, slot)) in rooms.iter().zip(slots.iter_mut()).enumerate() {
        if !room.meets(*groups) {
            slot.hits.clear();
            continue;
        }
        let c = match visits.as_mut() {
            Some(logs) => {
                let log = &mut logs[r];
                log.begin_frame();
                room_pass(character.reborrow(), marks, room, method, timed, log, slot)
            }
            None => room_pass(
                character.reborrow(),
                marks,
                room,
                method,
                timed,
                &mut NoLog,
                slot,
            ),
        };
        counters.add(&c);
    }
    own.rooms = counters;
    own.itself = FrameCounters::default();
    if let Some(s) = itself.as_deref_mut() {
        let mut pass = SelfPass {
            side: character.reborrow(),
            data: &s.data,
            gaps: &mut s.gaps,
            cones: &mut s.cones,
            culling,
            timed,
        };
        own.itself = run(&mut pass, &mut s.slot.scratch, &mut s.slot.hits);
    }
    own.objects = FrameCounters::default();
    own.broad_phase_tests = 0;
    own.body_pairs = 0;
    object_pairs.clear();
    let Some(root) = own.root else { return };
    for (o, (body, oroot)) in objects.iter().zip(object_roots).enumerate() {
        let Some(oroot) = oroot else { continue };
        if !body.meets(*groups) {
            continue;
        }
        own.broad_phase_tests += 1;
        if !root.overlaps(oroot) {
            continue;
        }
        own.body_pairs += 1;
        let mut pass = RigidPass {
            character: character.reborrow(),
            marks: &mut *marks,
            body: &body.tree,
            mesh: &body.mesh,
            to_body: body.pose.inverse(),
            method,
            log: &mut NoLog,
            timed,
            skin_all_when_cheaper: false,
        };
        let c = run(&mut pass, scratch, object_hits);
        own.objects.add(&c);
        object_pairs.extend(object_hits.iter().map(|&(t, ot)| ObjectPair {
            character: *handle,
            triangle: t,
            object: ObjectHandle(o as u32),
            object_triangle: ot,
        }));
    }
}

/// One room pass of a character.
fn room_pass<L: crate::pipeline::visit_log::VisitLog>(
    character: CharacterSide<'_>,
    marks: &mut crate::pipeline::pass::PassMarksOf,
    room: &RigidBody,
    method: crate::pipeline::Method,
    timed: bool,
    log: &mut L,
    slot: &mut super::bodies::PassSlot<(u32, u32)>,
) -> FrameCounters {
    let mut pass = RigidPass {
        character,
        marks,
        body: &room.tree,
        mesh: &room.mesh,
        to_body: Identity,
        method,
        log,
        timed,
        skin_all_when_cheaper: true,
    };
    run(&mut pass, &mut slot.scratch, &mut slot.hits)
}

/// Calls `f` on every item; on the current pool in pieces of at least
/// `len / threads` items when it has several threads (rayon's indexed
/// iterators split by `join`: nothing is boxed, so nothing allocates).
pub(crate) fn side_by_side<A: Send>(items: &mut [A], f: impl Fn(&mut A) + Sync + Send) {
    let threads = rayon::current_num_threads();
    if threads > 1 && items.len() > 1 {
        let chunk = items.len().div_ceil(threads);
        items.par_iter_mut().with_min_len(chunk).for_each(f);
    } else {
        items.iter_mut().for_each(f);
    }
}
