//! Sphere update (paper §3): refitting the character's spheres to a pose from
//! per-joint weight ranges precomputed over each sphere's vertices.
//!
//! Every node of a joint tree stores *corners*: blends `Σ w_j·M_j` of skin
//! matrices. Refit maps the rest centre `c` through each corner, takes the
//! paper's enclosing sphere of the results (centre the mean, radius the
//! largest distance) and adds `r·σ`, where `r` is the rest radius and `σ` the
//! largest stretch (spectral norm) of the linear parts involved (1 for rigid
//! joints).
//!
//! - **Paper model.** Per joint `a` among the node's vertices, with weights in
//!   `[min, max]`: the corners are `(1 − min)·M_p + min·M_a` and the same at
//!   `max` — the paper's `c_min` and `c_max` (one corner when equal). The
//!   vertex transform is linear in `w`, so every vertex lies within `r·σ` of the
//!   segment between them.
//! - **glTF linear blend skinning** (the bound of our design notes): a vertex's
//!   weights lie in `{w : min_j ≤ w_j ≤ max_j, Σ w_j = 1}`; the corners are that
//!   polytope's vertices, so every `Σ w_j M_j c` lies in their convex hull. With
//!   more than [`MAX_POLYTOPE_JOINTS`] joints the simplex corners `M_j` are used
//!   (looser, still conservative).
//! - **Root and extremity spheres** enclose their children's refit spheres.
//!
//! On demand: a node is refit the first time a traversal asks for it in a frame
//! (a frame stamp per node). [`Refitter::refit_all`] refits everything.

use nalgebra::{Matrix3, Matrix4};

use crate::character::{Character, JointId, Skeleton, SkinningModel};
use crate::geometry::enclosing::round_up;
use crate::geometry::{Point, Sphere, Vector};

use super::character::{CharacterTree, Origin};
use super::node::{NodeId, SphereTree};
use super::traverse::Hierarchy;

/// Term index standing for the skeleton's base frame (the parent of a root joint).
pub(crate) const BASE: u16 = u16::MAX;

/// Above this many joints in one sphere, simplex corners replace the polytope's.
pub const MAX_POLYTOPE_JOINTS: usize = 8;

/// `(joint, min weight, max weight)` over a vertex set, sorted by joint.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct WeightSummary {
    pub entries: Vec<(u16, f32, f32)>,
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
        let mut entries: Vec<(u16, f32, f32)> = match model {
            SkinningModel::Paper => {
                let w = character.paper.weight(v);
                vec![(character.paper.joint(v).0, w, w)]
            }
            SkinningModel::Linear => character
                .influences
                .of(v)
                .map(|(j, w)| (j.0, w, w))
                .collect(),
        };
        entries.sort_by_key(|e| e.0);
        // Repeated joints in one vertex's influences: add their weights.
        entries.dedup_by(|b, a| {
            if a.0 == b.0 {
                a.1 += b.1;
                a.2 += b.2;
                true
            } else {
                false
            }
        });
        WeightSummary { entries }
    }
}

/// How one node is refit.
#[derive(Clone, Copy, Debug, PartialEq)]
enum Rule {
    /// Enclose the children's refit spheres (root and extremity spheres).
    FromChildren,
    /// The node's joints ("slots") are `joints[jstart..jend]`; its `count`
    /// corners are weight vectors over those slots, stored one after the other
    /// from `weights[wstart]`.
    Corners {
        jstart: u32,
        jend: u32,
        wstart: u32,
        count: u32,
    },
}

/// Refit rules for every node of a character tree.
#[derive(Clone, Debug, Default)]
pub struct RefitData {
    rules: Vec<Rule>,
    /// Slot joints of every node (`BASE` for the skeleton's base frame); their
    /// stretch also bounds the node's radius.
    joints: Vec<u16>,
    /// Corner weights, one per slot, corner after corner.
    weights: Vec<f32>,
    /// Most slots any node has (sizes the per-frame scratch).
    max_slots: usize,
}

impl RefitData {
    pub(crate) fn new(
        character: &Character,
        model: SkinningModel,
        tree: &SphereTree,
        origin: &[Origin],
        joint_trees: &[(JointId, SphereTree)],
    ) -> Self {
        let absent_is_zero = model == SkinningModel::Linear;
        // Summaries per joint-tree node, children before parents.
        let sub: Vec<Vec<WeightSummary>> = joint_trees
            .iter()
            .map(|(_, t)| {
                let mut s = vec![WeightSummary::default(); t.len()];
                for i in (0..t.len()).rev() {
                    let n = t.node(NodeId(i as u32));
                    s[i] = match n.primitive() {
                        Some(p) => {
                            let tri = character.mesh.indices()[p as usize];
                            let mut acc =
                                WeightSummary::of_vertex(character, model, tri[0] as usize);
                            for &v in &tri[1..] {
                                acc = acc.merge(
                                    &WeightSummary::of_vertex(character, model, v as usize),
                                    absent_is_zero,
                                );
                            }
                            acc
                        }
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

        let mut data = RefitData::default();
        for (i, o) in origin.iter().enumerate() {
            debug_assert!(i < tree.len());
            match *o {
                Origin::Root | Origin::Group(_) => {
                    data.rules.push(Rule::FromChildren);
                }
                Origin::Joint(t, n) => {
                    let summary = &sub[t][n.index()];
                    let corners = match model {
                        SkinningModel::Paper => paper_corners(&character.skeleton, summary),
                        SkinningModel::Linear => polytope_corners(summary),
                    };
                    data.push_corners(&corners);
                }
            }
        }
        data
    }

    /// Adds a node whose corners are the given blends `[(joint, weight)]`.
    fn push_corners(&mut self, corners: &[Vec<(u16, f32)>]) {
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
            let mut w = vec![0.0f32; slots];
            for &(j, x) in c {
                let at = self.joints[jstart..].iter().position(|&s| s == j).unwrap();
                w[at] += x;
            }
            self.weights.extend(w);
        }
        self.max_slots = self.max_slots.max(slots);
        self.rules.push(Rule::Corners {
            jstart: jstart as u32,
            jend: self.joints.len() as u32,
            wstart: wstart as u32,
            count: corners.len() as u32,
        });
    }
}

/// The paper's corners: per joint `a` with weights in `[lo, hi]`, the blends
/// `(1 − lo)·M_p + lo·M_a` and `(1 − hi)·M_p + hi·M_a` (one when equal).
fn paper_corners(skeleton: &Skeleton, s: &WeightSummary) -> Vec<Vec<(u16, f32)>> {
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
fn polytope_corners(s: &WeightSummary) -> Vec<Vec<(u16, f32)>> {
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
    let mut seen: Vec<Vec<(u16, f32)>> = Vec::new();
    for free in 0..k {
        for mask in 0u32..(1 << (k - 1)) {
            let mut w = vec![0.0f32; k];
            let mut bit = 0;
            let mut sum = 0.0f64;
            for (i, wi) in w.iter_mut().enumerate() {
                if i == free {
                    continue;
                }
                *wi = if mask >> bit & 1 == 1 { e[i].2 } else { e[i].1 };
                sum += *wi as f64;
                bit += 1;
            }
            let f = 1.0 - sum;
            let slack = 1e-5;
            if f < e[free].1 as f64 - slack || f > e[free].2 as f64 + slack {
                continue;
            }
            w[free] = f.clamp(0.0, 1.0) as f32;
            let corner: Vec<(u16, f32)> = e.iter().zip(&w).map(|(x, &wi)| (x.0, wi)).collect();
            if !seen.contains(&corner) {
                seen.push(corner);
            }
        }
    }
    // Rounding can leave the polytope empty: fall back to the simplex.
    if seen.is_empty() { simplex() } else { seen }
}

/// Per-frame refit results and bookkeeping; reused across frames.
#[derive(Clone, Debug)]
pub struct RefitState {
    /// This frame's spheres (valid where `stamp == frame`).
    pub spheres: Vec<Sphere>,
    stamp: Vec<u32>,
    frame: u32,
    /// Stretch of each joint's skin matrix; the last entry is the base frame's.
    sigma: Vec<f32>,
    /// Nodes refit this frame.
    pub refits: u64,
    /// Slot centres of the node being refit.
    scratch: Vec<Vector>,
}

impl RefitState {
    pub fn new(tree: &CharacterTree, joints: usize) -> Self {
        Self {
            spheres: tree.tree.nodes().iter().map(|n| n.sphere).collect(),
            stamp: vec![0; tree.tree.len()],
            frame: 0,
            sigma: vec![1.0; joints + 1],
            refits: 0,
            scratch: vec![Vector::zeros(); tree.refit.max_slots.max(1)],
        }
    }

    /// Starts a frame: every sphere becomes stale. No allocation.
    pub fn begin_frame(&mut self, skeleton: &Skeleton, skin: &[Matrix4<f32>]) {
        self.begin_frame_with_base(skin, skeleton.base());
    }

    /// [`RefitState::begin_frame`] with an explicit base frame (a placed
    /// character's base is `placement · base`).
    pub fn begin_frame_with_base(&mut self, skin: &[Matrix4<f32>], base: &Matrix4<f32>) {
        self.frame = self.frame.wrapping_add(1).max(1);
        if self.frame == 1 {
            self.stamp.fill(0);
        }
        self.refits = 0;
        for (s, m) in self.sigma.iter_mut().zip(skin) {
            *s = stretch(m);
        }
        *self.sigma.last_mut().unwrap() = stretch(base);
    }

    /// Whether node `id` has been refit this frame.
    pub fn is_fresh(&self, id: NodeId) -> bool {
        self.stamp[id.index()] == self.frame
    }
}

/// Largest singular value of the linear part, rounded up a little.
fn stretch(m: &Matrix4<f32>) -> f32 {
    let l: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).map(|x| x as f64);
    let e = (l.transpose() * l).symmetric_eigenvalues();
    let s = e.max().max(0.0).sqrt();
    round_up(s * (1.0 + 1e-6))
}

/// A character tree posed for one frame: answers traversal's sphere requests,
/// refitting on first request.
pub struct Refitter<'a> {
    pub tree: &'a CharacterTree,
    pub skin: &'a [Matrix4<f32>],
    pub state: &'a mut RefitState,
}

impl Refitter<'_> {
    /// Refits node `id` now (its children first where the rule needs them).
    pub fn refit_node(&mut self, id: NodeId, base: &Matrix4<f32>) -> Sphere {
        let rest = self.tree.tree.node(id);
        let s = match self.tree.refit.rules[id.index()] {
            Rule::FromChildren => {
                let kids = rest.children();
                let n = kids.len() as f32;
                let mut sum = Vector::zeros();
                for c in kids.clone() {
                    sum += self.fresh(NodeId(c), base).center.coords;
                }
                let center = Point::from(sum / n);
                let r = kids
                    .map(|c| {
                        let s = self.state.spheres[c as usize];
                        crate::geometry::sphere::distance_f64(&s.center, &center) + s.radius as f64
                    })
                    .fold(0.0, f64::max);
                Sphere::new(center, round_up(r))
            }
            Rule::Corners {
                jstart,
                jend,
                wstart,
                count,
            } => {
                let data = &self.tree.refit;
                let c = rest.sphere.center;
                let slots = &data.joints[jstart as usize..jend as usize];
                let k = slots.len();
                // Each slot's matrix applied to the rest centre, once.
                let mut sigma = 0.0f32;
                for (q, &j) in self.state.scratch.iter_mut().zip(slots) {
                    let (m, st) = if j == BASE {
                        (base, *self.state.sigma.last().unwrap())
                    } else {
                        (&self.skin[j as usize], self.state.sigma[j as usize])
                    };
                    *q = m.transform_point(&c).coords;
                    sigma = sigma.max(st);
                }
                let q = &self.state.scratch[..k];
                let weights = &data.weights[wstart as usize..wstart as usize + count as usize * k];
                let corner = |w: &[f32]| -> Point {
                    Point::from(
                        q.iter()
                            .zip(w)
                            .fold(Vector::zeros(), |acc, (v, x)| acc + v * *x),
                    )
                };
                let mut sum = Vector::zeros();
                for w in weights.chunks_exact(k) {
                    sum += corner(w).coords;
                }
                let center = Point::from(sum / count as f32);
                let mut spread = 0.0f64;
                for w in weights.chunks_exact(k) {
                    spread = spread.max(crate::geometry::sphere::distance_f64(&corner(w), &center));
                }
                // Relative slack for f32 rounding in the corner points.
                let r = (spread + rest.sphere.radius as f64 * sigma as f64) * (1.0 + 1e-6);
                Sphere::new(center, round_up(r))
            }
        };
        self.state.spheres[id.index()] = s;
        self.state.stamp[id.index()] = self.state.frame;
        self.state.refits += 1;
        s
    }

    #[inline]
    fn fresh(&mut self, id: NodeId, base: &Matrix4<f32>) -> Sphere {
        if self.state.is_fresh(id) {
            self.state.spheres[id.index()]
        } else {
            self.refit_node(id, base)
        }
    }

    /// Refits every node (children before parents).
    pub fn refit_all(&mut self, base: &Matrix4<f32>) {
        for i in (0..self.tree.tree.len()).rev() {
            self.refit_node(NodeId(i as u32), base);
        }
    }
}

/// [`Refitter`] with the skeleton base bound, for traversal.
pub struct OnDemand<'a> {
    pub refitter: Refitter<'a>,
    pub base: Matrix4<f32>,
}

impl Hierarchy for OnDemand<'_> {
    fn tree(&self) -> &SphereTree {
        &self.refitter.tree.tree
    }

    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        let base = self.base;
        self.refitter.fresh(id, &base)
    }
}
