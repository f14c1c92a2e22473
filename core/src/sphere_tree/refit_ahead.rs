//! Refit ahead: at a frame's start, the character nodes asked for in the
//! frame before are refit in one loop, before any traversal asks for them.
//!
//! On demand (§3, "Sphere update"), a node is refit where traversal first
//! asks for it: between two sphere tests, each refit a chain of dependent
//! `f64` operations whose result the next branch waits for, its rule and
//! rest sphere fetched from memory at that moment. Between two frames of an
//! animation the nodes traversal asks for are nearly the same, so the ones
//! asked for last frame are refit here first: independent refits one after
//! the other (the processor overlaps their chains), with the data of the
//! refit a few places ahead already being loaded. Traversal then finds them
//! refit; a node it asks for that was not refit ahead is refit on demand as
//! before, and a node refit ahead that it never asks for is work lost.
//!
//! Each sphere is the one on-demand refit computes (the same function), so
//! no pair and no test changes; only the refit count does. A node refit
//! ahead carries the stamp `frame | AHEAD` until traversal first asks for
//! it, which logs it for the next frame: the log holds the nodes traversal
//! asked for, never the ones only refit ahead, so work lost one frame is
//! not repeated in the next.

use nalgebra::Matrix4;

use super::node::NodeId;
use super::refit::{AHEAD, Refitter};

/// How many nodes ahead of the one being refit its data is prefetched.
const PREFETCH_DISTANCE: usize = 8;

impl Refitter<'_> {
    /// Refits ahead every node asked for in the frame before that is not
    /// refit yet (nothing unless [`super::refit::RefitState::set_refit_ahead`]
    /// is on). Call after `begin_frame`, before traversal; counts go to
    /// `refits` and `refits_ahead`. No allocation.
    pub fn refit_ahead(&mut self, base: &Matrix4<f32>) {
        if !self.state.ahead {
            return;
        }
        let frame = self.state.frame;
        let refits_before = self.state.refits;
        self.state.writes = frame | AHEAD;
        let n = self.state.asked_before.len();
        for k in 0..n {
            if let Some(&next) = self.state.asked_before.get(k + PREFETCH_DISTANCE) {
                self.prefetch(NodeId(next));
            }
            // Half-way: its rule has arrived, so its balls can be asked for.
            if let Some(&next) = self.state.asked_before.get(k + PREFETCH_DISTANCE / 2) {
                self.prefetch_balls(NodeId(next));
            }
            let id = NodeId(self.state.asked_before[k]);
            let stamp = self.state.stamp[id.index()];
            if stamp != frame && stamp != frame | AHEAD {
                self.refit_node(id, base);
            }
        }
        self.state.writes = frame;
        self.state.refits_ahead += self.state.refits - refits_before;
    }
}

#[cfg(test)]
mod tests {
    use std::collections::BTreeSet;

    use crate::character::PoseBuffers;
    use crate::humanoid::{HumanoidParams, generate_humanoid};
    use crate::mesh::EdgeDedup;
    use crate::sphere_tree::character::CharacterTree;
    use crate::sphere_tree::refit::{RefitState, Refitter, ahead_log_room};
    use crate::sphere_tree::{BuildParams, NodeId};

    /// The nodes "traversal" asks for in frame `k`: a window of the tree
    /// that slides a little from frame to frame, as contact moves (the
    /// root's children always, so that a group node is asked too).
    fn asked(k: usize, n: usize) -> Vec<u32> {
        let start = (37 * k) % (n / 2);
        // A tenth of the tree: within the log's room (an eighth).
        let mut v: Vec<u32> = (1..4)
            .chain(start as u32..(start + n / 10) as u32)
            .collect();
        // Not in index order, as a traversal asks.
        v.sort_by_key(|&i| (i.wrapping_mul(2_654_435_761)) >> 7);
        v
    }

    /// Against on-demand refit alone, frame after frame of a walk: the same
    /// spheres bit for bit, the same nodes fresh; the refit count grows by
    /// exactly the nodes refit ahead and never asked for; a frame asking
    /// for last frame's nodes again refits nothing on demand; and nodes
    /// refit ahead but not asked for are not refit ahead again.
    #[test]
    fn refit_ahead_gives_the_on_demand_spheres_and_learns_from_asks() {
        let c = generate_humanoid(&HumanoidParams {
            vertices: 3000,
            seed: 3,
        })
        .unwrap();
        let model = crate::character::SkinningModel::Linear;
        let ct = CharacterTree::build(
            &c,
            &EdgeDedup::keep_all(&c.mesh),
            model,
            BuildParams::default(),
        );
        let n = ct.tree.len();
        let joints = c.skeleton.len();
        let mut plain = RefitState::new(&ct, joints);
        let mut ahead = RefitState::new(&ct, joints);
        ahead.set_refit_ahead(true);
        assert!(ahead.refits_ahead_on() && !plain.refits_ahead_on());
        let clip = &c.clips[0];
        let mut b = PoseBuffers::new(&c);
        let mut before: BTreeSet<u32> = BTreeSet::new();
        for k in 0..12 {
            let t = clip.start() + clip.duration() * k as f32 / 12.0;
            clip.sample(t, c.skeleton.rest_pose_ref(), &mut b.local);
            b.pose_local(&c);
            plain.begin_frame_with_base(&b.skin, &b.base);
            ahead.begin_frame_with_base(&b.skin, &b.base);
            // Frames 6 and 7 ask for the same nodes.
            let ask = asked(if k == 7 { 6 } else { k }, n);
            let mut ra = Refitter {
                tree: &ct,
                skin: &b.skin,
                state: &mut ahead,
            };
            ra.refit_ahead(&b.base);
            let refit_ahead = ra.state.refits_ahead;
            // Refit ahead: last frame's asks that still need it, as many
            // as the log holds, and at most what group nodes pull in
            // beneath them.
            if k == 0 {
                assert_eq!(refit_ahead, 0);
            } else {
                let logged = before.len().min(ahead_log_room(n)) as u64;
                assert!(refit_ahead >= logged - 1, "frame {k}");
            }
            for &i in &ask {
                let s = ra.fresh(NodeId(i), &b.base);
                let p = Refitter {
                    tree: &ct,
                    skin: &b.skin,
                    state: &mut plain,
                }
                .fresh(NodeId(i), &b.base);
                assert_eq!(s, p, "frame {k} node {i}");
            }
            let fresh = |st: &RefitState| -> BTreeSet<u32> {
                (0..n as u32).filter(|&i| st.is_fresh(NodeId(i))).collect()
            };
            let now = fresh(&ahead);
            assert_eq!(now, fresh(&plain), "frame {k}");
            for &i in &now {
                assert_eq!(ahead.spheres[i as usize], plain.spheres[i as usize]);
            }
            assert_eq!(
                ahead.refits - ahead.refits_ahead_unused(),
                plain.refits,
                "frame {k}"
            );
            if k == 7 {
                // Everything asked was refit ahead: nothing on demand.
                assert_eq!(ahead.refits, ahead.refits_ahead, "frame {k}");
                assert_eq!(ahead.refits_ahead_unused(), 0);
            }
            if k > 0 && k != 7 {
                // The window moved: some nodes refit ahead went unasked.
                assert!(ahead.refits_ahead_unused() > 0, "frame {k}");
            }
            before = now;
        }
    }

    /// Off (the default), nothing is refit ahead and nothing is logged.
    #[test]
    fn refit_ahead_off_does_nothing() {
        let c = generate_humanoid(&HumanoidParams {
            vertices: 1000,
            seed: 4,
        })
        .unwrap();
        let ct = CharacterTree::build(
            &c,
            &EdgeDedup::keep_all(&c.mesh),
            crate::character::SkinningModel::Paper,
            BuildParams::default(),
        );
        let mut st = RefitState::new(&ct, c.skeleton.len());
        let b = PoseBuffers::new(&c);
        for _ in 0..3 {
            st.begin_frame_with_base(&b.skin, &b.base);
            let mut r = Refitter {
                tree: &ct,
                skin: &b.skin,
                state: &mut st,
            };
            r.refit_ahead(&b.base);
            assert_eq!(r.state.refits, 0);
            r.fresh(NodeId(0), &b.base);
        }
    }
}
