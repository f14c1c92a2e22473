//! The ground truth of every frame ([`Truth`]: the exact pairs of every
//! kind, parry's answer beside them) and each method's score against it:
//! per pair kind, and per character against the room in detail (false
//! positives with their distances, false negatives with their causes).

use anyhow::Context;
use cornertree::pipeline::LeafTest;
use cornertree::world::ByKind;
use cornertree_workbench::session::Session;
use cornertree_workbench::truth::{Accuracy, MethodContext, MethodTruth, Truth};

/// One method's score this frame.
#[derive(Clone, Debug, Default)]
pub struct MethodScore {
    pub by_kind: ByKind<Accuracy>,
    /// Per kind, the exact pairs of triangles de-duplication removed.
    pub removed_by_dedup: ByKind<u64>,
    /// Per character, its pairs with the room in detail.
    pub details: Vec<MethodTruth>,
}

/// The truth of the frame and the methods' scores.
pub struct Reference {
    pub truth: Truth,
    /// Per method and character: whether each triangle is in the method's
    /// tree (kept by de-duplication).
    kept: Vec<Vec<Vec<bool>>>,
    /// Per method: its score this frame.
    pub scores: Vec<MethodScore>,
}

impl Reference {
    /// The reference of `session`'s scenario.
    pub fn new(session: &Session) -> anyhow::Result<Self> {
        let truth = Truth::new(&session.scene).context("setting up the ground truth")?;
        let kept = session
            .worlds()
            .iter()
            .map(|w| {
                (0..session.scene.characters.len())
                    .map(|c| {
                        let view = w
                            .character(session.character(c))
                            .expect("the session's character");
                        let tree = view.tree();
                        let mut kept = vec![false; tree.triangle_joint.len()];
                        for t in &tree.triangles {
                            kept[t.index()] = true;
                        }
                        kept
                    })
                    .collect()
            })
            .collect();
        Ok(Self {
            truth,
            kept,
            scores: vec![MethodScore::default(); session.worlds().len()],
        })
    }

    /// The truth of frame `k` (every vertex of `session` skinned).
    pub fn update(&mut self, session: &Session, k: usize) -> anyhow::Result<()> {
        self.truth
            .update(&session.scene, &session.buffers, &session.object_poses)
            .with_context(|| format!("ground truth of frame {k}"))
    }

    /// Scores method `m`'s step of frame `k`.
    pub fn score(&mut self, session: &Session, k: usize, m: usize) -> anyhow::Result<()> {
        let world = session.world(m);
        let contacts = world.contacts();
        let (room, _) = world.room(session.room()).expect("the session's room");
        let plane_sphere = world.method().big_leaf_test() == LeafTest::PlaneSphere;
        let score = &mut self.scores[m];
        score.by_kind = self.truth.score(contacts);
        let kept = &self.kept[m];
        score.removed_by_dedup = self
            .truth
            .removed_by_dedup(|c, t| kept[c].get(t as usize).copied().unwrap_or(true));
        score.details.clear();
        for c in 0..session.scene.characters.len() {
            let ctx = MethodContext {
                kept: &self.kept[m][c],
                big: &room.big,
                plane_sphere,
            };
            let detail = self
                .truth
                .room_detail(
                    c,
                    contacts,
                    &session.scene,
                    &session.buffers[c].positions,
                    &ctx,
                )
                .with_context(|| format!("scoring frame {k} of {}", world.method()))?;
            score.details.push(detail);
        }
        Ok(())
    }
}
