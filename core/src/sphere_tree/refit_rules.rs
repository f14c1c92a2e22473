//! The refit rules of a character tree, built once from the skin weights
//! under every node (paper §3; the rules, their rounding margin and the
//! joint balls are argued in the [`super::refit`] module doc, which applies
//! them to a pose).

use crate::character::skinning::{LINEAR_ROUNDINGS, PAPER_ROUNDINGS};
use crate::character::{Character, JointId, Skeleton, SkinningModel};
use crate::choice::{Choice, UnknownName, parse_choice, show};
use crate::geometry::enclosing::{points_sphere, round_up};
use crate::geometry::{Point, bounds_of};

use super::containment::VertexSets;
use super::node::{NodeId, SphereTree};

/// Where a node of the merged tree comes from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum Origin {
    Root,
    Group(usize),
    /// Node `1` of joint tree `0`.
    Joint(usize, NodeId),
}

/// Unit roundoff of `f32` (round to nearest).
const F32_UNIT: f64 = 1.0 / (1u64 << 24) as f64;

/// `γ_n = n·u / (1 − n·u)` for `f32`: the relative error bound of `n`
/// roundings in a row.
fn gamma_f32(n: u32) -> f64 {
    let nu = n as f64 * F32_UNIT;
    nu / (1.0 - nu)
}

/// Relative slack covering the `f64` evaluation of a refit radius.
pub(super) const F64_SLACK: f64 = 1e-12;

/// Term index standing for the skeleton's base frame (the parent of a root joint).
pub(crate) const BASE: u16 = u16::MAX;

/// Above this many joints in one sphere, simplex corners replace the polytope's.
pub const MAX_POLYTOPE_JOINTS: usize = 8;

/// `(joint, min weight, max weight)` over a vertex set, sorted by joint. The
/// bounds are the vertices' `f32` weights (in `f64`), exactly.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WeightSummary {
    /// One `(joint index, min weight, max weight)` per joint weighting a
    /// vertex of the set.
    pub entries: Vec<(u16, f64, f64)>,
}

impl WeightSummary {
    /// Union of two vertex sets. With `absent_is_zero` (linear blend skinning) a
    /// joint missing from one side counts as weight 0 there; otherwise (paper
    /// model, one joint per vertex) it simply has no vertices there.
    fn merge(&self, other: &WeightSummary, absent_is_zero: bool) -> WeightSummary {
        let (mut i, mut j) = (0, 0);
        let (a, b) = (&self.entries, &other.entries);
        let mut out = Vec::with_capacity(a.len() + b.len());
        while i < a.len() || j < b.len() {
            let take_a = j >= b.len() || (i < a.len() && a[i].0 < b[j].0);
            let take_b = i >= a.len() || (j < b.len() && b[j].0 < a[i].0);
            if take_a {
                let (k, lo, hi) = a[i];
                out.push((k, if absent_is_zero { 0.0 } else { lo }, hi));
                i += 1;
            } else if take_b {
                let (k, lo, hi) = b[j];
                out.push((k, if absent_is_zero { 0.0 } else { lo }, hi));
                j += 1;
            } else {
                out.push((a[i].0, a[i].1.min(b[j].1), a[i].2.max(b[j].2)));
                i += 1;
                j += 1;
            }
        }
        WeightSummary { entries: out }
    }

    fn of_vertex(character: &Character, model: SkinningModel, v: usize) -> WeightSummary {
        let mut entries: Vec<(u16, f64, f64)> = match model {
            SkinningModel::Paper => {
                let w = character.paper.weight(v) as f64;
                vec![(character.paper.joint(v).0, w, w)]
            }
            SkinningModel::Linear => character
                .influences
                .of(v)
                .map(|(j, w)| (j.0, w as f64, w as f64))
                .collect(),
        };
        entries.sort_by_key(|e| e.0);
        // Repeated joints in one vertex's influences: add their weights (the
        // skinning adds their terms). A rounded sum widens to the neighbours.
        entries.dedup_by(|b, a| {
            if a.0 == b.0 {
                let (lo, exact) = two_sum(a.1, b.1);
                a.1 = if exact { lo } else { lo.next_down() };
                let (hi, exact) = two_sum(a.2, b.2);
                a.2 = if exact { hi } else { hi.next_up() };
                true
            } else {
                false
            }
        });
        WeightSummary { entries }
    }

    /// `|Σ w − 1|` for vertex `v`'s weights as the skinning code uses them:
    /// its influences (linear blend), or `fl(1 − w)` and `w` (paper model).
    fn sum_error(character: &Character, model: SkinningModel, v: usize) -> f64 {
        let sum = match model {
            SkinningModel::Paper => {
                let w = character.paper.weight(v);
                (1.0 - w) as f64 + w as f64
            }
            SkinningModel::Linear => character.influences.of(v).map(|(_, w)| w as f64).sum(),
        };
        // Up to four f64 additions: a relative 2⁻⁵¹ covers their rounding.
        (sum - 1.0).abs() + sum * f64::EPSILON * 2.0
    }
}

/// `a + b` in `f64` and whether it is exact.
fn two_sum(a: f64, b: f64) -> (f64, bool) {
    let s = a + b;
    let bb = s - a;
    let err = (a - (s - bb)) + (b - bb);
    (s, err == 0.0)
}

/// How one node is refit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Rule {
    /// Enclose the children's refit spheres (root and extremity spheres).
    FromChildren,
    /// [`Rule::Corners`] with one corner of one non-zero weight (a node
    /// whose vertices all follow one joint: about two thirds of a
    /// humanoid's nodes under either skinning model): the same arithmetic,
    /// without the loops and the weight array's cache line. `norms_too` is
    /// the slot of weight zero (the paper's parent joint), or `joint` again;
    /// its norms still enter `σ`, `α` and `τ`, as in the general rule.
    Rigid {
        joint: u16,
        norms_too: u16,
        reach: f32,
        weight: f64,
    },
    /// The node's joints ("slots") are `joints[jstart..jend]`; its `count`
    /// corners are weight vectors over those slots, stored one after the other
    /// from `weights[wstart]`. `reach` is `‖c‖ + r` of the rest sphere, rounded
    /// up (it bounds the length of every vertex under the node).
    Corners {
        jstart: u32,
        jend: u32,
        wstart: u32,
        count: u32,
        reach: f32,
    },
    /// [`RefitRule::JointBalls`]: the node's balls are
    /// `balls[start..end]`; `reach` as for [`Rule::Corners`].
    JointBalls { start: u32, end: u32, reach: f32 },
    /// [`RefitRule::BlendedBalls`]: the node's balls are `balls[start..end]`
    /// (one per slot joint); its `count` corners are weight vectors over
    /// those slots, stored one after the other from `weights[wstart]`.
    BlendedBalls {
        start: u32,
        end: u32,
        wstart: u32,
        count: u32,
        reach: f32,
    },
    /// [`Rule::JointBalls`] with one ball, kept in the rule itself (one
    /// cache line fewer to fetch: about two thirds of a humanoid's nodes).
    OneBall {
        center: Point,
        radius: f32,
        joint: u16,
        reach: f32,
    },
}

// A rule stays 24 bytes, so a node's rule shares its cache line with the
// next nodes'.
const _: () = assert!(std::mem::size_of::<Rule>() == 24);

/// How a character tree's spheres are refit to a pose.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize, serde::Deserialize))]
#[cfg_attr(feature = "serde", serde(rename_all = "kebab-case"))]
pub enum RefitRule {
    /// The paper's (§3): the rest centre through every corner blend of the
    /// node's weight ranges plus the whole rest radius; root and extremity
    /// spheres enclose their children's (module doc).
    #[default]
    PaperCorners,
    /// Ours, for every node: one rest ball per joint over the node's
    /// vertices that joint moves (non-zero weight); the posed sphere holds
    /// every ball moved by its joint (module doc, "Joint balls").
    JointBalls,
    /// Ours: the joint balls blended by the corners of the node's weight
    /// ranges: at each corner the ball `Σ w_j·(moved ball j)`; the posed
    /// sphere holds those (module doc, "Blended balls"). Tighter than both
    /// where a node's vertices carry small weights of joints that turn away.
    BlendedBalls,
}

impl Choice for RefitRule {
    const WHAT: &'static str = "refit rule";
    const ALL: &'static [Self] = &[
        RefitRule::PaperCorners,
        RefitRule::JointBalls,
        RefitRule::BlendedBalls,
    ];

    fn name(self) -> &'static str {
        match self {
            RefitRule::PaperCorners => "paper-corners",
            RefitRule::JointBalls => "joint-balls",
            RefitRule::BlendedBalls => "blended-balls",
        }
    }

    fn summary(self) -> &'static str {
        match self {
            RefitRule::PaperCorners => {
                "the paper's: the rest centre through every corner blend of the weight ranges, the whole rest radius (§3)"
            }
            RefitRule::JointBalls => "ours: one rest ball per joint, moved by its joint",
            RefitRule::BlendedBalls => {
                "ours: the joint balls blended by the corners of the node's weight ranges"
            }
        }
    }
}

impl std::str::FromStr for RefitRule {
    type Err = UnknownName;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        parse_choice(s)
    }
}

impl std::fmt::Display for RefitRule {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        show(*self, f)
    }
}

/// A rest ball of [`RefitRule::JointBalls`]: the bind vertices of one node
/// that slot joint `joint` moves lie within `radius` of `center`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct JointBall {
    pub(super) center: Point,
    pub(super) radius: f32,
    pub(super) joint: u16,
}

/// A rest box of a ball rule's node: the bind vertices of the node that
/// slot joint `joint` moves lie in `lo..=hi` (their extent: `f32`
/// coordinates, exact).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct JointBox {
    pub(super) lo: Point,
    pub(super) hi: Point,
    pub(super) joint: u16,
}

/// A ball rule's node's rest boxes, one per slot joint: the first here
/// (one cache line holds two nodes', read by node index), the other
/// `more` at `RefitData::more_boxes[start..]`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct NodeBoxes {
    pub(super) lo: Point,
    pub(super) hi: Point,
    pub(super) joint: u16,
    pub(super) more: u16,
    pub(super) start: u32,
}

const _: () = assert!(std::mem::size_of::<NodeBoxes>() == 32);

/// Refit rules for every node of a character tree.
#[derive(Clone, Debug, Default)]
pub struct RefitData {
    pub(super) rules: Vec<Rule>,
    /// Slot joints of every node (`BASE` for the skeleton's base frame); their
    /// stretch also bounds the node's radius.
    pub(super) joints: Vec<u16>,
    /// Corner weights, one per slot, corner after corner.
    pub(super) weights: Vec<f64>,
    /// Rest balls of [`Rule::JointBalls`] nodes, node after node.
    pub(super) balls: Vec<JointBall>,
    /// Each node's rest boxes, one per slot joint (the ball rules; empty
    /// for the corner rule), moved into the node's posed box when a
    /// traversal first asks for it in a frame. A leaf's entry is empty and
    /// has no more boxes: it only keeps the inner nodes' places (a leaf is
    /// never boxed).
    pub(super) node_boxes: Vec<NodeBoxes>,
    /// The boxes after each node's first.
    pub(super) more_boxes: Vec<JointBox>,
    /// Most slots any node has (sizes the per-frame scratch).
    pub(super) max_slots: usize,
    /// Most corners any node has (sizes the per-frame scratch).
    pub(super) max_corners: usize,
    /// `δ`: the largest `|Σ w − 1|` over the vertices' weights.
    pub(super) weight_sum_error: f64,
    /// `κ`: the rounding margin of a node is `κ·ρ` (module doc).
    pub(super) rounding: f64,
}

impl RefitData {
    pub(crate) fn new(
        character: &Character,
        model: SkinningModel,
        tree: &SphereTree,
        origin: &[Origin],
        joint_trees: &[(JointId, SphereTree)],
        rule: RefitRule,
    ) -> Self {
        let absent_is_zero = model == SkinningModel::Linear;
        let delta = (0..character.mesh.vertex_count())
            .map(|v| WeightSummary::sum_error(character, model, v))
            .fold(0.0, f64::max);
        // Summaries per joint-tree node, children before parents (corner
        // rules only).
        let corner_trees = match rule {
            RefitRule::PaperCorners => joint_trees,
            RefitRule::JointBalls | RefitRule::BlendedBalls => &[],
        };
        let sub: Vec<Vec<WeightSummary>> = corner_trees
            .iter()
            .map(|(_, t)| {
                let mut s = vec![WeightSummary::default(); t.len()];
                for i in (0..t.len()).rev() {
                    let n = t.node(NodeId(i as u32));
                    s[i] = match n.primitive() {
                        Some(p) => WeightSummary::of_vertices(
                            character,
                            model,
                            &character.mesh.indices()[p as usize],
                        ),
                        None => {
                            let mut ch = n.children();
                            let first = ch.next().unwrap() as usize;
                            ch.fold(s[first].clone(), |acc, c| {
                                acc.merge(&s[c as usize], absent_is_zero)
                            })
                        }
                    };
                }
                s
            })
            .collect();

        // Vertices under every node (joint balls only).
        let vertex_sets = match rule {
            RefitRule::PaperCorners => None,
            RefitRule::JointBalls | RefitRule::BlendedBalls => {
                Some(VertexSets::new(tree, &character.mesh))
            }
        };
        let mut data = RefitData {
            weight_sum_error: delta,
            ..RefitData::default()
        };
        // `ε`: how far a corner's weights sum from 1.
        let mut corner_sum_error = 0.0f64;
        let corners_of = |summary: &WeightSummary, sum_error: &mut f64| {
            let corners = match model {
                SkinningModel::Paper => paper_corners(&character.skeleton, summary),
                SkinningModel::Linear => polytope_corners(summary, delta),
            };
            for c in &corners {
                let sum: f64 = c.iter().map(|e| e.1).sum();
                let rounding =
                    c.len() as f64 * f64::EPSILON * c.iter().map(|e| e.1.abs()).sum::<f64>();
                *sum_error = sum_error.max((sum - 1.0).abs() + rounding);
            }
            corners
        };
        for (i, o) in origin.iter().enumerate() {
            debug_assert!(i < tree.len());
            let rest = tree.node(NodeId(i as u32)).sphere;
            let reach = round_up(rest.center.coords.map(|x| x as f64).norm() + rest.radius as f64);
            if let Some(sets) = &vertex_sets {
                let vertices = sets.of(i);
                let (balls, boxes) = rest_balls_and_boxes(character, model, vertices);
                // A node without a vertex (none is built) would get an
                // empty box, whose posed box is the whole cube. A leaf's
                // entry only keeps the inner nodes' places (a leaf is never
                // boxed: its triangle's test follows): empty, its joints'
                // boxes not kept.
                let empty = JointBox {
                    lo: Point::new(f32::INFINITY, f32::INFINITY, f32::INFINITY),
                    hi: Point::new(f32::NEG_INFINITY, f32::NEG_INFINITY, f32::NEG_INFINITY),
                    joint: BASE,
                };
                let leaf = tree.node(NodeId(i as u32)).is_leaf();
                let kept = if leaf { &[][..] } else { &boxes[..] };
                let first = kept.first().copied().unwrap_or(empty);
                data.node_boxes.push(NodeBoxes {
                    lo: first.lo,
                    hi: first.hi,
                    joint: first.joint,
                    more: kept.len().saturating_sub(1) as u16,
                    start: data.more_boxes.len() as u32,
                });
                data.more_boxes.extend(kept.iter().skip(1));
                if rule == RefitRule::BlendedBalls {
                    let summary = WeightSummary::of_vertices(character, model, vertices);
                    let corners = corners_of(&summary, &mut corner_sum_error);
                    data.push_blended_balls(balls, &corners, reach);
                } else {
                    data.push_joint_balls(balls, reach);
                }
                continue;
            }
            match *o {
                Origin::Root | Origin::Group(_) => {
                    data.rules.push(Rule::FromChildren);
                }
                Origin::Joint(t, n) => {
                    let corners = corners_of(&sub[t][n.index()], &mut corner_sum_error);
                    data.push_corners(&corners, reach);
                }
            }
        }
        let roundings = match model {
            SkinningModel::Linear => LINEAR_ROUNDINGS,
            SkinningModel::Paper => PAPER_ROUNDINGS,
        };
        data.rounding = gamma_f32(roundings) * (1.0 + delta)
            + delta
            + corner_sum_error
            + (data.max_slots + 8) as f64 * f64::EPSILON;
        data
    }

    /// `κ`, the rounding margin per unit of `ρ` (see the module doc).
    pub fn rounding_coefficient(&self) -> f64 {
        self.rounding
    }

    /// Whether any node is refit by joint balls (which read each joint's
    /// matrix rows in `f64`, [`RefitState`](super::refit::RefitState)'s `mats`).
    pub(super) fn moves_joint_balls(&self) -> bool {
        self.rules.iter().any(|r| {
            matches!(
                r,
                Rule::JointBalls { .. } | Rule::BlendedBalls { .. } | Rule::OneBall { .. }
            )
        })
    }

    /// Nodes refit by [`Rule::Rigid`].
    #[cfg(test)]
    pub(super) fn rigid_count(&self) -> usize {
        self.rules
            .iter()
            .filter(|r| matches!(r, Rule::Rigid { .. }))
            .count()
    }

    /// The same rules with every [`Rule::Rigid`] written as the general
    /// [`Rule::Corners`] it stands for.
    #[cfg(test)]
    pub(super) fn without_rigid(&self) -> Self {
        let mut out = self.clone();
        for rule in &mut out.rules {
            if let Rule::Rigid {
                joint,
                norms_too,
                reach,
                weight,
            } = *rule
            {
                let two = norms_too != joint;
                *rule = Rule::Corners {
                    jstart: out.joints.len() as u32,
                    jend: out.joints.len() as u32 + 1 + two as u32,
                    wstart: out.weights.len() as u32,
                    count: 1,
                    reach,
                };
                if two {
                    // The zero slot first, as the paper's corners list it.
                    out.joints.push(norms_too);
                    out.weights.push(0.0);
                }
                out.joints.push(joint);
                out.weights.push(weight);
            }
        }
        out
    }

    /// Adds a node whose corners are the given blends `[(joint, weight)]`.
    fn push_corners(&mut self, corners: &[Vec<(u16, f64)>], reach: f32) {
        let jstart = self.joints.len();
        for c in corners {
            for &(j, _) in c {
                if !self.joints[jstart..].contains(&j) {
                    self.joints.push(j);
                }
            }
        }
        let slots = self.joints.len() - jstart;
        let wstart = self.weights.len();
        for c in corners {
            let mut w = vec![0.0f64; slots];
            for &(j, x) in c {
                let at = self.joints[jstart..].iter().position(|&s| s == j).unwrap();
                w[at] += x;
            }
            self.weights.extend(w);
        }
        self.max_slots = self.max_slots.max(slots);
        self.max_corners = self.max_corners.max(corners.len());
        // One corner over one joint, or over two where one weight is zero
        // (the paper's corner of a joint at weight 1 keeps its parent at 0).
        let weights = &self.weights[wstart..];
        let nonzero: Vec<usize> = (0..slots).filter(|&i| weights[i] != 0.0).collect();
        if corners.len() == 1 && slots <= 2 && nonzero.len() == 1 {
            let at = nonzero[0];
            self.rules.push(Rule::Rigid {
                joint: self.joints[jstart + at],
                norms_too: self.joints[jstart + slots - 1 - at],
                reach,
                weight: weights[at],
            });
            self.joints.truncate(jstart);
            self.weights.truncate(wstart);
            return;
        }
        self.rules.push(Rule::Corners {
            jstart: jstart as u32,
            jend: self.joints.len() as u32,
            wstart: wstart as u32,
            count: corners.len() as u32,
            reach,
        });
    }
}

/// Per slot joint of the bind vertices `vertices`, the minimal ball of the
/// ones it moves (non-zero weight; the paper's model: the vertex's joint if
/// `w > 0`, its parent or the base frame if `w < 1`), by joint.
fn rest_balls_and_boxes(
    character: &Character,
    model: SkinningModel,
    vertices: &[u32],
) -> (Vec<JointBall>, Vec<JointBox>) {
    let bind = character.mesh.positions();
    let mut moved: Vec<(u16, u32)> = Vec::new();
    for &v in vertices {
        let vi = v as usize;
        match model {
            SkinningModel::Linear => {
                moved.extend(character.influences.of(vi).map(|(j, _)| (j.0, v)));
            }
            SkinningModel::Paper => {
                // `(1 − w)·M_p + w·M_a`: a term of weight zero adds
                // an exact zero.
                let (a, w) = (character.paper.joint(vi), character.paper.weight(vi));
                if w > 0.0 {
                    moved.push((a.0, v));
                }
                if w < 1.0 {
                    let p = character.skeleton.parent(a).map_or(BASE, |p| p.0);
                    moved.push((p, v));
                }
            }
        }
    }
    moved.sort_unstable();
    moved.dedup();
    let mut points = Vec::new();
    moved
        .chunk_by(|x, y| x.0 == y.0)
        .map(|group| {
            points.clear();
            points.extend(group.iter().map(|&(_, v)| bind[v as usize]));
            let s = points_sphere(&points);
            // Every vertex within the stored radius, measured in `f64`.
            let r = points
                .iter()
                .map(|p| crate::geometry::sphere::distance_f64(p, &s.center))
                .fold(s.radius as f64, f64::max);
            let joint = group[0].0;
            let (lo, hi) = bounds_of(points.iter().copied()).expect("a group has a vertex");
            (
                JointBall {
                    center: s.center,
                    radius: round_up(r),
                    joint,
                },
                JointBox { lo, hi, joint },
            )
        })
        .unzip()
}

impl WeightSummary {
    /// The summary of the vertex set `vertices` (not empty).
    fn of_vertices(character: &Character, model: SkinningModel, vertices: &[u32]) -> Self {
        let absent_is_zero = model == SkinningModel::Linear;
        let mut out = WeightSummary::of_vertex(character, model, vertices[0] as usize);
        for &v in &vertices[1..] {
            out = out.merge(
                &WeightSummary::of_vertex(character, model, v as usize),
                absent_is_zero,
            );
        }
        out
    }
}

impl RefitData {
    /// Adds a [`Rule::JointBalls`] node with rest balls `balls` (a
    /// [`Rule::OneBall`] if there is one).
    fn push_joint_balls(&mut self, balls: Vec<JointBall>, reach: f32) {
        if let [b] = balls[..] {
            self.rules.push(Rule::OneBall {
                center: b.center,
                radius: b.radius,
                joint: b.joint,
                reach,
            });
            return;
        }
        let start = self.balls.len();
        self.max_slots = self.max_slots.max(balls.len());
        self.balls.extend(balls);
        self.rules.push(Rule::JointBalls {
            start: start as u32,
            end: self.balls.len() as u32,
            reach,
        });
    }

    /// Adds a [`Rule::BlendedBalls`] node: rest balls `balls` blended by the
    /// weight vectors `corners`. One ball: a [`Rule::OneBall`]. A corner
    /// with weight on a joint that moves none of the node's vertices, more
    /// corners than [`MAX_BLENDED_CORNERS`], or only the simplex's corners
    /// (a weight 1 each): the balls alone ([`Rule::JointBalls`]).
    fn push_blended_balls(
        &mut self,
        balls: Vec<JointBall>,
        corners: &[Vec<(u16, f64)>],
        reach: f32,
    ) {
        let k = balls.len();
        let mut weights = vec![0.0f64; k * corners.len()];
        let fits = k > 1
            && corners.len() <= MAX_BLENDED_CORNERS
            && corners
                .iter()
                .zip(weights.chunks_exact_mut(k))
                .all(|(c, w)| {
                    c.iter()
                        .all(|&(j, x)| match balls.iter().position(|b| b.joint == j) {
                            Some(at) => {
                                w[at] += x;
                                true
                            }
                            None => x == 0.0,
                        })
                });
        // Corners that are the simplex's (each a single weight 1) blend
        // nothing: the balls alone give the same hull for less work.
        let simplex = weights
            .chunks_exact(k)
            .all(|w| w.iter().all(|&x| x == 0.0 || x == 1.0) && w.iter().sum::<f64>() == 1.0);
        if !fits || simplex {
            self.push_joint_balls(balls, reach);
            return;
        }
        let (start, wstart) = (self.balls.len(), self.weights.len());
        self.max_slots = self.max_slots.max(k);
        self.max_corners = self.max_corners.max(corners.len());
        self.balls.extend(balls);
        self.weights.extend(weights);
        self.rules.push(Rule::BlendedBalls {
            start: start as u32,
            end: self.balls.len() as u32,
            wstart: wstart as u32,
            count: corners.len() as u32,
            reach,
        });
    }
}

/// Most corners a node refit by [`RefitRule::BlendedBalls`] blends (more:
/// the balls alone, as [`RefitRule::JointBalls`]).
pub const MAX_BLENDED_CORNERS: usize = 256;

/// The paper's corners: per joint `a` with weights in `[lo, hi]`, the blends
/// `(1 − lo)·M_p + lo·M_a` and `(1 − hi)·M_p + hi·M_a` (one when equal;
/// `1 − lo` is exact in `f64`).
fn paper_corners(skeleton: &Skeleton, s: &WeightSummary) -> Vec<Vec<(u16, f64)>> {
    let mut out = Vec::new();
    for &(a, lo, hi) in &s.entries {
        let p = skeleton.parent(JointId(a)).map_or(BASE, |p| p.0);
        out.push(vec![(p, 1.0 - lo), (a, lo)]);
        if hi != lo {
            out.push(vec![(p, 1.0 - hi), (a, hi)]);
        }
    }
    out
}

/// Vertices of the weight polytope `{lo ≤ w ≤ hi, Σ w = 1}` (every coordinate
/// but one at a bound); the simplex corners beyond [`MAX_POLYTOPE_JOINTS`].
///
/// The free coordinate is kept unclamped in `f64`, so every corner's weights
/// sum to 1 up to `f64` rounding; it may leave its range by a slack that
/// exceeds `delta` (the vertices' `|Σ w − 1|`), so that every vertex of
/// `{lo ≤ w ≤ hi, Σ w = s}` with `|s − 1| ≤ delta` has a corner differing from
/// it in the free coordinate only.
fn polytope_corners(s: &WeightSummary, delta: f64) -> Vec<Vec<(u16, f64)>> {
    let e = &s.entries;
    let k = e.len();
    let simplex = || {
        e.iter()
            .map(|&(j, _, _)| vec![(j, 1.0)])
            .collect::<Vec<_>>()
    };
    if k > MAX_POLYTOPE_JOINTS {
        return simplex();
    }
    let slack = 1e-5 + 2.0 * delta;
    let mut seen: Vec<Vec<(u16, f64)>> = Vec::new();
    for free in 0..k {
        for mask in 0u32..(1 << (k - 1)) {
            let mut w = vec![0.0f64; k];
            let mut bit = 0;
            let mut sum = 0.0f64;
            for (i, wi) in w.iter_mut().enumerate() {
                if i == free {
                    continue;
                }
                *wi = if mask >> bit & 1 == 1 { e[i].2 } else { e[i].1 };
                sum += *wi;
                bit += 1;
            }
            let f = 1.0 - sum;
            if f < e[free].1 - slack || f > e[free].2 + slack {
                continue;
            }
            w[free] = f;
            let corner: Vec<(u16, f64)> = e.iter().zip(&w).map(|(x, &wi)| (x.0, wi)).collect();
            if !seen.contains(&corner) {
                seen.push(corner);
            }
        }
    }
    // Rounding can leave the polytope empty: fall back to the simplex.
    if seen.is_empty() { simplex() } else { seen }
}
