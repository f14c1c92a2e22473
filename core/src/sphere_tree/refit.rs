//! Sphere update (paper §3): refitting the character's spheres to a pose from
//! per-joint weight ranges precomputed over each sphere's vertices.
//!
//! Every node of a joint tree stores *corners*: blends `Σ w_j·M_j` of skin
//! matrices. Refit maps the rest centre `c` through each corner, takes the
//! paper's enclosing sphere of the results (centre the mean, radius the
//! largest distance) and adds `r·σ`, where `r` is the rest radius and `σ` the
//! largest stretch (spectral norm) of the linear parts involved (1 for rigid
//! joints), and a margin for `f32` rounding (below).
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
//! **Rounding.** Skinned vertices are `f32` results and a character far from
//! the origin carries large translations (an `f32` ulp is about 1 mm at
//! 10 km), so the rule above, which holds in exact arithmetic, is not enough.
//! For a node with rest sphere `(c, r)` and joints ("slots") `j`, write
//! `M_j = [A_j t_j]` (skin matrices, fourth row exactly `[0, 0, 0, 1]`, see
//! `Skeleton::new`), `α_j = ‖A_j‖_F ≥ ‖|A_j|‖₂`, `τ_j = ‖t_j‖`,
//! `ρ = α·(‖c‖ + r) + τ` with `α`, `τ` the largest `α_j`, `τ_j`, `σ` the largest
//! spectral norm of the `A_j`, and `k` the number of slots. For a vertex `v`
//! (so `‖v − c‖ ≤ r`) with `f32` weights `w_j ≥ 0` summing to `s`, let `v*` be
//! `Σ_j w_j·M_j·(v, 1)` computed exactly from those `f32` numbers and `v̂` the
//! skinning code's `f32` result.
//!
//! 1. *Skinning rounds.* The code has at most `n` roundings on any path
//!    ([`LINEAR_ROUNDINGS`](crate::character::skinning::LINEAR_ROUNDINGS),
//!    [`PAPER_ROUNDINGS`](crate::character::skinning::PAPER_ROUNDINGS)), so each coordinate of
//!    `v̂ − v*` is at most `γ_n·Σ_j w_j·(|M_j|·|(v, 1)|)`, `γ_n = n·u/(1 − n·u)`,
//!    `u = 2⁻²⁴`. The norm of `|A_j|·|v| + |t_j|` is at most `α_j‖v‖ + τ_j`
//!    and `‖v‖ ≤ ‖c‖ + r`, hence `‖v̂ − v*‖ ≤ γ_n·s·ρ`.
//! 2. *Weights do not sum to 1.* `|s − 1| ≤ δ`, the largest over the
//!    character's vertices, measured when the rules are built (a joint listed
//!    twice in one vertex's influences is summed with outward rounding). `w`
//!    lies in the polytope `{min ≤ w ≤ max, Σ w = s}`, so it is a convex
//!    combination of that polytope's vertices; each has every weight but one
//!    at a bound, and the corner with the same bounds and the free weight
//!    `1 − Σ others` was stored (the acceptance slack exceeds `δ`; the paper's
//!    model: `w` between `min` and `max`, corners at both). Each such vertex
//!    and its corner (weights summing to `S_i`, `|S_i − 1| ≤ ε`) differ in one
//!    weight, by `|s − S_i| ≤ δ + ε`; the simplex corners of a large node
//!    give `Σ_j w_j·M_j c = s·(a convex combination)`. So `Σ_j w_j·M_j c` lies
//!    within `(δ + ε)·max_j ‖M_j c‖ ≤ (δ + ε)·ρ` of the hull `H` of the exact
//!    corner points, and `v* = Σ_j w_j·M_j c + Σ_j w_j·A_j (v − c)` within a
//!    further `s·σ·r ≤ (1 + δ)·σ·r`.
//! 3. *Corners in `f64`.* Corner points are computed in `f64` from the `f32`
//!    matrices, rest centre and `f64` weights (products of `f32` numbers are
//!    exact in `f64`); each is within `(k + 8)·2⁻⁵²·ρ` of its exact value.
//! 4. *Radius.* With `spread` the largest `f64` distance from the stored `f32`
//!    centre to a computed corner, the hull `H` lies within
//!    `spread + (k + 8)·2⁻⁵²·ρ` of the centre (distance to a point is convex),
//!    so by 1–3 every `v̂` lies within
//!    `spread + (1 + δ)·σ·r + κ·ρ`, `κ = γ_n·(1 + δ) + δ + ε + (k_max + 8)·2⁻⁵²`.
//!    That sum is evaluated in `f64`, grown by the factor `1 + 10⁻¹²` (far above
//!    its relative rounding) and rounded up to `f32`.
//!
//! Near the origin `ρ` is about the model size and the margin `κ·ρ` a few
//! micrometres; at 10 km it is some millimetres, a few times the
//! largest excess measured without it. Per node only `ρ` is new (the joints' `α_j`,
//! `τ_j` are taken once a frame, `‖c‖ + r` is stored with the rule), and refit
//! got cheaper on the whole: corner points are computed once instead of twice,
//! and the final rounding up has no branch.
//!
//! **Joint balls** ([`RefitRule::JointBalls`], ours; `pruned-tri-tri` and
//! `undivided-pruned-tri-tri`). For every node (root and extremity spheres
//! included) and every joint `j` that moves one of its vertices (non-zero
//! weight; the paper's model: the vertex's joint if `w > 0`, its parent or
//! the base frame if `w < 1`), the bind vertices `j` moves lie in a rest
//! ball `(c_j, r_j)` (their minimal sphere, radius checked in `f64` and
//! rounded up). A skinned vertex `Σ_j w_j·M_j·v` is a convex combination of
//! points `M_j·v`, each within `σ_j·r_j` of `M_j·c_j`, so it lies in the
//! hull of those moved balls, and so in any sphere holding them all: the
//! centre is the middle of the balls' bounding box, the radius the largest
//! `‖M_j·c_j − centre‖ + σ_j·r_j`. Rounding is bounded as above with the
//! node's `ρ` (weights summing to `s ≠ 1` move a vertex by at most
//! `|s − 1|·ρ`; the slot count `k` covers the balls, one `f64` point each).
//! The corner rule moves the node's rest *centre* through every joint,
//! which swings it by the joint's lever arm, and keeps the whole rest
//! radius; a ball per joint stays by its bone. On the 10k-vertex humanoids
//! of the crowd the corner rule's spheres are 1.3–1.8 times the radius
//! that holds the posed vertices about the same centre over the upper ten
//! levels (docs/performance-journal.md, "Joint balls").
//!
//! **Blended balls** ([`RefitRule::BlendedBalls`], ours; `pruned-tri-tri`
//! and `undivided-pruned-tri-tri`). The joint balls' sphere holds every
//! moved ball, so a vertex with a small weight of a joint that turns away
//! (glTF characters weight up to four joints a vertex) drags the sphere out
//! to that joint's ball. Blended balls use the weights too: write
//! `Σ_j w_j·M_j·v = Σ_j w_j·x_j` with `x_j = M_j·v` in the moved ball
//! `(q_j, σ_j·r_j)` (a term of weight zero takes any point), so the vertex
//! lies in the ball `(Σ_j w_j·q_j, Σ_j |w_j|·σ_j·r_j)`. Both are linear in
//! `w`, so over the node's weight polytope the vertex lies in the hull of
//! those balls at the polytope's corners — the corners of the rules above
//! (`polytope_corners`, `paper_corners`, with their `δ + ε` margin for
//! weights that do not sum to 1). The sphere's centre is the middle of the
//! corner balls' box, its radius the largest `‖centre_i − centre‖ + R_i`,
//! plus the rounding margin `κ·ρ` (the centres are computed as the corner
//! rule computes its points: each `q_j` once, then blended; `|c_j| ≤ ‖c‖ + r`
//! as a ball's centre lies in the hull of its vertices). A node with one
//! ball keeps its one moved ball (`Rule::OneBall`); a node with more than
//! [`MAX_BLENDED_CORNERS`] corners, a corner weighting a joint that moves
//! none of its vertices, or only the simplex's corners (a weight 1 each)
//! keeps the balls alone, which are the simplex corners' blend. On
//! CesiumMan (four influences a vertex) the spheres at depths 4 to 8 went
//! from 1.6–2.2 to 1.0–1.6 times the minimal sphere of their posed
//! vertices (docs/performance-journal.md, "Blended balls").
//!
//! **Boxes** (the ball rules; ours). Two characters' spheres meet far more
//! often than their surfaces come close: on the crowd's brushing walkers
//! the refit spheres are within 1–3% of the smallest radius about their
//! centres that holds the posed vertices (every depth), yet the exact posed
//! boxes of the same nodes would drop two thirds of the node pairs whose
//! spheres meet (docs/performance-journal.md, "Posed node boxes"). Every
//! node also keeps, per slot joint, the box of the bind vertices that joint
//! moves (`f32` corners, exact). A skinned vertex `Σ_j w_j·M_j·v` is a
//! convex combination of points `M_j·v`, each in the box `M_j·c ± |A_j|·h`
//! (centre `c`, half-extent `h` of joint `j`'s rest box), so it lies in the
//! union's box; weights summing to `s ≠ 1` and rounding move it by at most
//! `κ·ρ` as above, by which every face is widened (plus `F64_SLACK` of the
//! magnitudes, for the `f64` evaluation). That box, clipped to the cube of
//! the node's sphere (which holds the vertices), is kept in six bytes as
//! levels of that cube ([`LeveledBox`], built and tested with the same
//! `f32` arithmetic). It is built when a traversal between two characters
//! first asks for it after the node's refit, for inner nodes only (leaves
//! go to their triangle's own test; building their boxes cost more than it
//! saved), and a node pair whose spheres meet is dropped when their boxes
//! do not. Leaves keep only an empty entry in the model's rest boxes (so
//! inner nodes are found by node index), none of their joints' boxes.
//!
//! On demand: a node is refit the first time a traversal asks for it in a frame
//! (a frame stamp per node). [`Refitter::refit_all`] refits everything.
//! Ahead (opt-in, [`RefitState::set_refit_ahead`]): the nodes asked for last
//! frame are refit first, in one loop ([`Refitter::refit_ahead`]; see the
//! `refit_ahead` module).

use nalgebra::{Matrix3, Matrix4, Vector3};

use crate::character::Skeleton;
use crate::geometry::enclosing::round_up;
use crate::geometry::leveled_box::LeveledBox;
use crate::geometry::{Point, Sphere, Vector};
use crate::prefetch::prefetch_at;

use super::character::CharacterTree;
use super::node::{NodeId, SphereTree};
use super::refit_rules::{BASE, F64_SLACK, JointBox, Rule};
pub use super::refit_rules::{
    MAX_BLENDED_CORNERS, MAX_POLYTOPE_JOINTS, RefitData, RefitRule, WeightSummary,
};
use super::traverse::Hierarchy;

/// `f64` vectors: corner points and slot points of a refit.
type V64 = Vector3<f64>;

/// Norms of one joint's skin matrix `M = [A t]`, taken once a frame.
#[derive(Clone, Copy, Debug, PartialEq)]
struct JointNorms {
    /// `σ`: the spectral norm of `A`, rounded up.
    stretch: f64,
    /// `α`: the Frobenius norm of `A` (at least the spectral norm of `|A|`).
    frobenius: f64,
    /// `τ`: the length of `t`.
    translation: f64,
}

impl JointNorms {
    /// The identity's norms (before the first frame).
    const IDENTITY: JointNorms = JointNorms {
        stretch: 1.0,
        frobenius: 1.732_050_807_568_877_2,
        translation: 0.0,
    };

    /// Zero norms: the start of a largest-so-far.
    const ZERO: JointNorms = JointNorms {
        stretch: 0.0,
        frobenius: 0.0,
        translation: 0.0,
    };

    /// Each norm the larger of the two (`f64::max`, exact).
    #[inline]
    fn max(&self, o: &JointNorms) -> JointNorms {
        JointNorms {
            stretch: self.stretch.max(o.stretch),
            frobenius: self.frobenius.max(o.frobenius),
            translation: self.translation.max(o.translation),
        }
    }

    fn of(m: &Matrix4<f32>) -> Self {
        let a = m.fixed_view::<3, 3>(0, 0);
        let t = m.fixed_view::<3, 1>(0, 3);
        let sq = |x: &f32| (*x as f64) * (*x as f64);
        Self {
            stretch: stretch(m) as f64,
            frobenius: a.iter().map(sq).sum::<f64>().sqrt(),
            translation: t.iter().map(sq).sum::<f64>().sqrt(),
        }
    }
}

/// Per-frame refit results and bookkeeping; reused across frames.
#[derive(Clone, Debug)]
pub struct RefitState {
    /// This frame's spheres (valid where `stamp == frame`, or
    /// `frame | AHEAD`).
    pub spheres: Vec<Sphere>,
    /// Per node: `frame` once asked for this frame; `frame | AHEAD` if refit
    /// ahead and not asked for yet; anything else: stale.
    pub(super) stamp: Vec<u32>,
    /// Below [`AHEAD`].
    pub(super) frame: u32,
    /// What a refit writes in `stamp`: `frame`, or `frame | AHEAD` while
    /// refitting ahead.
    pub(super) writes: u32,
    /// Whether the nodes asked for are logged (refit ahead on).
    pub(super) ahead: bool,
    /// Whether asking for a node logs it now (off while a query runs:
    /// where a ray went is no forecast of the next frame's contacts).
    logging: bool,
    /// Nodes asked for this frame, each once (when `ahead`).
    pub(super) asked: Vec<u32>,
    /// Nodes asked for last frame (when `ahead`).
    pub(super) asked_before: Vec<u32>,
    /// Nodes refit ahead this frame (counted in `refits` too).
    pub refits_ahead: u64,
    /// Of those, the ones asked for since.
    ahead_used: u64,
    /// Norms of each joint's skin matrix; the last entry is the base frame's.
    norms: Vec<JointNorms>,
    /// Each joint's skin matrix `[A t]` in `f64`, row after row (the last:
    /// the base frame's), taken once a frame for [`Rule::JointBalls`].
    mats: Vec<[f64; 12]>,
    /// Nodes refit this frame.
    pub refits: u64,
    /// Slot points `M_j·c` of the node being refit.
    slot_points: Vec<V64>,
    /// Corner points of the node being refit.
    corner_points: Vec<V64>,
    /// Moved balls' radii `σ_j·r_j` of the node being refit (blended balls).
    slot_radii: Vec<f64>,
    /// Corner balls' radii of the node being refit (blended balls).
    corner_radii: Vec<f64>,
    /// This frame's box of each node refit by a ball rule, in levels
    /// around its sphere (valid with the sphere; empty for the corner rule).
    pub(super) boxes: Vec<LeveledBox>,
}

impl RefitState {
    /// State for `tree`, posed by a skeleton of `joints` joints, sized once.
    /// Its spheres are the rest (bind-space) ones until the first
    /// [`RefitState::begin_frame`].
    pub fn new(tree: &CharacterTree, joints: usize) -> Self {
        Self {
            spheres: tree.tree.nodes().iter().map(|n| n.sphere).collect(),
            stamp: vec![0; tree.tree.len()],
            boxes: if tree.refit.node_boxes.is_empty() {
                Vec::new()
            } else {
                vec![LeveledBox::UNKNOWN; tree.tree.len()]
            },
            frame: 0,
            writes: 0,
            ahead: false,
            logging: true,
            asked: Vec::new(),
            asked_before: Vec::new(),
            refits_ahead: 0,
            ahead_used: 0,
            norms: vec![JointNorms::IDENTITY; joints + 1],
            // Only joint-ball rules read the rows.
            mats: if tree.refit.moves_joint_balls() {
                vec![IDENTITY_ROWS; joints + 1]
            } else {
                Vec::new()
            },
            refits: 0,
            slot_points: vec![V64::zeros(); tree.refit.max_slots.max(1)],
            corner_points: vec![V64::zeros(); tree.refit.max_corners.max(1)],
            slot_radii: vec![0.0; tree.refit.max_slots.max(1)],
            corner_radii: vec![0.0; tree.refit.max_corners.max(1)],
        }
    }

    /// Starts a frame: every sphere becomes stale. No allocation.
    pub fn begin_frame(&mut self, skeleton: &Skeleton, skin: &[Matrix4<f32>]) {
        self.begin_frame_with_base(skin, skeleton.base());
    }

    /// [`RefitState::begin_frame`] with an explicit base frame (a placed
    /// character's base is `placement · base`).
    pub fn begin_frame_with_base(&mut self, skin: &[Matrix4<f32>], base: &Matrix4<f32>) {
        self.frame = (self.frame + 1) % AHEAD;
        if self.frame == 0 {
            // Wrapped (after 2³¹ frames): no stamp may look fresh.
            self.frame = 1;
            self.stamp.fill(0);
            self.asked.clear();
        }
        self.writes = self.frame;
        self.refits = 0;
        self.refits_ahead = 0;
        self.ahead_used = 0;
        if self.ahead {
            std::mem::swap(&mut self.asked, &mut self.asked_before);
            self.asked.clear();
        }
        for (n, m) in self.norms.iter_mut().zip(skin) {
            *n = JointNorms::of(m);
        }
        *self.norms.last_mut().unwrap() = JointNorms::of(base);
        if let Some((last, joints)) = self.mats.split_last_mut() {
            for (r, m) in joints.iter_mut().zip(skin) {
                *r = rows_f64(m);
            }
            *last = rows_f64(base);
        }
    }

    /// Whether the tree's rule keeps posed node boxes (the ball rules).
    pub fn has_boxes(&self) -> bool {
        !self.boxes.is_empty()
    }

    /// Whether node `id`'s sphere has been asked for (and so refit) this
    /// frame. A node refit ahead and not asked for is not fresh.
    pub fn is_fresh(&self, id: NodeId) -> bool {
        self.stamp[id.index()] == self.frame
    }

    /// Whether the next frames refit ahead the nodes asked for in the frame
    /// before ([`Refitter::refit_ahead`]). Sizes the logs once (no
    /// allocation per frame); off by default.
    pub fn set_refit_ahead(&mut self, on: bool) {
        self.ahead = on;
        self.asked.clear();
        self.asked_before.clear();
        if on {
            let room = ahead_log_room(self.stamp.len());
            self.asked.reserve_exact(room);
            self.asked_before.reserve_exact(room);
        }
    }

    /// Whether the nodes asked for from now on are logged for the next
    /// frame's refit ahead (on unless a query runs).
    pub(crate) fn set_logging(&mut self, on: bool) {
        self.logging = on;
    }

    /// Whether refit ahead is on.
    pub fn refits_ahead_on(&self) -> bool {
        self.ahead
    }

    /// Nodes refit ahead this frame and not asked for (so far): work lost,
    /// counted in `refits` but not [fresh](Self::is_fresh).
    pub fn refits_ahead_unused(&self) -> u64 {
        self.refits_ahead - self.ahead_used
    }

    /// Node `id`'s sphere if it is valid this frame, marked asked for (a
    /// node refit ahead becomes fresh and is logged), and whether it was
    /// refit ahead and is asked for now.
    #[inline]
    pub(super) fn take(&mut self, id: NodeId) -> Option<(Sphere, bool)> {
        let i = id.index();
        let s = self.stamp[i];
        if s == self.frame {
            return Some((self.spheres[i], false));
        }
        if s == self.frame | AHEAD {
            let now = self.writes == self.frame;
            if now {
                self.stamp[i] = self.frame;
                self.ahead_used += 1;
                self.log_asked(i);
            }
            return Some((self.spheres[i], now));
        }
        None
    }

    /// Logs node `i` as asked for this frame (once: the caller has just
    /// made its stamp `frame`).
    #[inline]
    fn log_asked(&mut self, i: usize) {
        // Never grows: each node is logged at most once a frame (when its
        // stamp becomes `frame`), up to the log's room
        // ([`ahead_log_room`]); a node asked for beyond it is refit on
        // demand next frame, as without refit ahead.
        if self.ahead && self.logging && self.asked.len() < self.asked.capacity() {
            self.asked.push(i as u32);
        }
    }
}

/// Room in each refit-ahead log for a tree of `nodes` nodes: an eighth of
/// them (at least 1,024). A frame asks for a small part of a tree (that is
/// the point of refitting on demand: the crowd's brushing walkers about 240
/// nodes of 30,000 each); room for every node cost 240 KB an instance of a
/// 10,000-vertex humanoid, the room its posed node boxes take instead.
pub(super) fn ahead_log_room(nodes: usize) -> usize {
    (nodes / 8).max(1024).min(nodes)
}

/// The bit of a stamp saying "refit ahead, not asked for yet".
pub(super) const AHEAD: u32 = 1 << 31;

/// Largest singular value of the linear part `A`, rounded up a little: the
/// square root of the largest eigenvalue of `B = AᵀA`.
///
/// Taken for every joint every frame, so the eigen decomposition (about a
/// quarter microsecond a joint) is skipped where Gershgorin's bound, the
/// largest row sum of `|B|`, is already tight: when the off-diagonal entries
/// are tiny beside the diagonal, as for a rotation (`B ≈ I`) or a rotation
/// times an axis-aligned scale (`B` diagonal). Both are upper bounds of the
/// largest eigenvalue; entries of `B` are sums of three exact `f64` products
/// (relative error below 2⁻⁵⁰), far inside the final `1 + 10⁻⁶` slack.
fn stretch(m: &Matrix4<f32>) -> f32 {
    let l: Matrix3<f64> = m.fixed_view::<3, 3>(0, 0).map(|x| x as f64);
    let b = l.transpose() * l;
    let diagonal = b[(0, 0)].max(b[(1, 1)]).max(b[(2, 2)]);
    let off = b[(0, 1)].abs().max(b[(0, 2)].abs()).max(b[(1, 2)].abs());
    let largest = if off <= 1e-7 * diagonal {
        (0..3)
            .map(|r| (0..3).map(|k| b[(r, k)].abs()).sum::<f64>())
            .fold(0.0f64, f64::max)
    } else {
        b.symmetric_eigenvalues().max()
    };
    round_up(largest.max(0.0).sqrt() * (1.0 + 1e-6))
}

/// Smallest `f32` not below a radius `x ≥ 0` ([`round_up`] without a branch:
/// whether `x` rounds down is data-dependent and mispredicts half the time).
#[inline]
fn radius_up(x: f64) -> f32 {
    let r = x as f32;
    f32::from_bits(r.to_bits() + ((r as f64) < x) as u32)
}

/// `A·c + t` for `M = [A t]` (its fourth row is `[0, 0, 0, 1]`), in `f64`.
#[inline]
fn apply_f64(m: &Matrix4<f32>, c: &V64) -> V64 {
    let e = |r: usize, k: usize| m[(r, k)] as f64;
    V64::new(
        e(0, 0) * c.x + e(0, 1) * c.y + e(0, 2) * c.z + e(0, 3),
        e(1, 0) * c.x + e(1, 1) * c.y + e(1, 2) * c.z + e(1, 3),
        e(2, 0) * c.x + e(2, 1) * c.y + e(2, 2) * c.z + e(2, 3),
    )
}

/// The identity's rows `[A t]`.
const IDENTITY_ROWS: [f64; 12] = [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0];

/// The first three rows of `m` in `f64` (exact).
fn rows_f64(m: &Matrix4<f32>) -> [f64; 12] {
    std::array::from_fn(|i| m[(i / 4, i % 4)] as f64)
}

/// [`apply_f64`] on rows taken by [`rows_f64`]: the same operations, the
/// same result.
#[inline]
fn apply_rows(e: &[f64; 12], c: &V64) -> V64 {
    V64::new(
        e[0] * c.x + e[1] * c.y + e[2] * c.z + e[3],
        e[4] * c.x + e[5] * c.y + e[6] * c.z + e[7],
        e[8] * c.x + e[9] * c.y + e[10] * c.z + e[11],
    )
}

/// `p` in `f64` (exact).
#[inline]
fn widen(p: &Point) -> V64 {
    V64::new(p.x as f64, p.y as f64, p.z as f64)
}

/// A corner rule's sphere (module doc, item 4) around the `f64` point `p`
/// (the corners' mean): the centre is `p` rounded to `f32`, `spread` comes
/// from `spread_from(centre)`, `r` is the rest radius and `largest` holds
/// the slots' largest `σ`, `α` and `τ`.
#[inline]
fn corner_sphere(
    data: &RefitData,
    p: V64,
    spread_from: impl FnOnce(&V64) -> f64,
    r: f64,
    largest: JointNorms,
    reach: f32,
) -> (Point, f32) {
    let center = Point::new(p.x as f32, p.y as f32, p.z as f32);
    let spread = spread_from(&widen(&center));
    let rho = largest.frobenius * reach as f64 + largest.translation;
    let radius = spread + r * largest.stretch * (1.0 + data.weight_sum_error) + data.rounding * rho;
    (center, radius_up(radius * (1.0 + F64_SLACK)))
}

/// The sphere around the `f64` balls `(centres[i], radii[i])`: its centre
/// the middle of their box, rounded to `f32`, and the largest `f64`
/// distance from that centre to a ball's far side.
#[inline]
fn around_balls(centres: &[V64], radii: &[f64]) -> (Point, f64) {
    let (mut lo, mut hi) = (V64::repeat(f64::MAX), V64::repeat(f64::MIN));
    for (q, &r) in centres.iter().zip(radii) {
        lo = lo.inf(&q.add_scalar(-r));
        hi = hi.sup(&q.add_scalar(r));
    }
    let mid = (lo + hi) * 0.5;
    let center = Point::new(mid.x as f32, mid.y as f32, mid.z as f32);
    let cw = widen(&center);
    let hold = centres
        .iter()
        .zip(radii)
        .map(|(q, r)| (q - cw).norm_squared().sqrt() + r)
        .fold(0.0f64, f64::max);
    (center, hold)
}

/// A joint-ball rule's sphere (module doc, "Joint balls") about `center`:
/// `hold` is the largest `f64` distance from it to a moved ball's far side,
/// `largest` holds the balls' joints' largest `α` and `τ`, and the radius
/// adds the rounding margin `κ·ρ`.
#[inline]
fn ball_sphere(
    data: &RefitData,
    center: Point,
    hold: f64,
    largest: &JointNorms,
    reach: f32,
) -> (Point, f32) {
    let rho = largest.frobenius * reach as f64 + largest.translation;
    let radius = hold * (1.0 + data.weight_sum_error) + data.rounding * rho;
    (center, radius_up(radius * (1.0 + F64_SLACK)))
}

/// A character tree posed for one frame: answers traversal's sphere requests,
/// refitting on first request.
pub struct Refitter<'a> {
    /// The tree, with its rest spheres and refit rules.
    pub tree: &'a CharacterTree,
    /// This frame's skin matrices, one per joint: bind space to world.
    pub skin: &'a [Matrix4<f32>],
    /// Where the refit spheres (world) and their frame stamps are kept.
    pub state: &'a mut RefitState,
}

impl Refitter<'_> {
    /// Refits node `id` now (its children first where the rule needs them).
    pub fn refit_node(&mut self, id: NodeId, base: &Matrix4<f32>) -> Sphere {
        let rest = self.tree.tree.node(id);
        let (center, radius) = match self.tree.refit.rules[id.index()] {
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
                (center, radius_up(r * (1.0 + F64_SLACK)))
            }
            Rule::Rigid {
                joint,
                norms_too,
                reach,
                weight,
            } => {
                // `Rule::Corners` with one corner, operation for operation:
                // the same `f64` results, since a zero weight times a finite
                // slot point adds an exact zero, as does the sum's start.
                let rest = rest.sphere;
                let (m, n) = self.slot(joint, base);
                let (_, o) = self.slot(norms_too, base);
                let p = apply_f64(m, &widen(&rest.center)) * weight;
                corner_sphere(
                    &self.tree.refit,
                    p,
                    |cw| (p - cw).norm_squared().sqrt(),
                    rest.radius as f64,
                    n.max(o),
                    reach,
                )
            }
            Rule::Corners {
                jstart,
                jend,
                wstart,
                count,
                reach,
            } => {
                let data = &self.tree.refit;
                let rest = rest.sphere;
                let c = widen(&rest.center);
                let slots = &data.joints[jstart as usize..jend as usize];
                let k = slots.len();
                // Each slot's matrix applied to the rest centre, once; the
                // largest stretch and the norms bounding rounding (`ρ`).
                let mut largest = JointNorms::ZERO;
                for (i, &j) in slots.iter().enumerate() {
                    let (m, n) = self.slot(j, base);
                    let (q, n) = (apply_f64(m, &c), *n);
                    self.state.slot_points[i] = q;
                    largest = largest.max(&n);
                }
                let q = &self.state.slot_points[..k];
                let weights = &data.weights[wstart as usize..wstart as usize + count as usize * k];
                let corners = &mut self.state.corner_points[..count as usize];
                let mut sum = V64::zeros();
                for (p, w) in corners.iter_mut().zip(weights.chunks_exact(k)) {
                    *p = q
                        .iter()
                        .zip(w)
                        .fold(V64::zeros(), |acc, (v, x)| acc + v * *x);
                    sum += *p;
                }
                corner_sphere(
                    data,
                    sum * (1.0 / count as f64),
                    |cw| {
                        corners
                            .iter()
                            .map(|p| (p - cw).norm_squared())
                            .fold(0.0f64, f64::max)
                            .sqrt()
                    },
                    rest.radius as f64,
                    largest,
                    reach,
                )
            }
            Rule::JointBalls { start, end, reach } => {
                let data = &self.tree.refit;
                let balls = &data.balls[start as usize..end as usize];
                // Each ball moved by its joint: centre `M_j·c_j`, radius
                // `σ_j·r_j`; the sphere's centre is the middle of their box.
                let mut largest = JointNorms::ZERO;
                for (i, b) in balls.iter().enumerate() {
                    let (m, n) = self.slot_rows(b.joint);
                    let (q, n) = (apply_rows(m, &widen(&b.center)), *n);
                    self.state.slot_points[i] = q;
                    self.state.slot_radii[i] = b.radius as f64 * n.stretch;
                    largest = largest.max(&n);
                }
                let k = balls.len();
                let (center, hold) =
                    around_balls(&self.state.slot_points[..k], &self.state.slot_radii[..k]);
                ball_sphere(data, center, hold, &largest, reach)
            }
            Rule::BlendedBalls {
                start,
                end,
                wstart,
                count,
                reach,
            } => {
                let data = &self.tree.refit;
                let balls = &data.balls[start as usize..end as usize];
                let k = balls.len();
                // Each ball moved by its joint, once.
                let mut largest = JointNorms::ZERO;
                for (i, b) in balls.iter().enumerate() {
                    let (m, n) = self.slot_rows(b.joint);
                    let (q, n) = (apply_rows(m, &widen(&b.center)), *n);
                    self.state.slot_points[i] = q;
                    self.state.slot_radii[i] = b.radius as f64 * n.stretch;
                    largest = largest.max(&n);
                }
                // Each corner's ball `Σ w_j·(moved ball j)`; the sphere's
                // centre is the middle of their box.
                let (q, qr) = (&self.state.slot_points[..k], &self.state.slot_radii[..k]);
                let weights = &data.weights[wstart as usize..wstart as usize + count as usize * k];
                let n = count as usize;
                let (corners, radii) = (
                    &mut self.state.corner_points[..n],
                    &mut self.state.corner_radii[..n],
                );
                for ((p, pr), w) in corners
                    .iter_mut()
                    .zip(radii.iter_mut())
                    .zip(weights.chunks_exact(k))
                {
                    let (mut c, mut r) = (V64::zeros(), 0.0f64);
                    for i in 0..k {
                        c += q[i] * w[i];
                        r += w[i].abs() * qr[i];
                    }
                    (*p, *pr) = (c, r);
                }
                let (center, hold) = around_balls(corners, radii);
                ball_sphere(data, center, hold, &largest, reach)
            }
            Rule::OneBall {
                center: rest_center,
                radius: rest_radius,
                joint,
                reach,
            } => {
                // One joint moves every vertex: its ball, moved.
                let data = &self.tree.refit;
                let (m, n) = self.slot_rows(joint);
                let q = apply_rows(m, &widen(&rest_center));
                let center = Point::new(q.x as f32, q.y as f32, q.z as f32);
                // How far rounding moved the centre, bounded by the sum of
                // the components (never below the length, and no square
                // root on the traversal's path: the gap is an `f32` ulp).
                let d = q - widen(&center);
                let hold = d.x.abs() + d.y.abs() + d.z.abs() + rest_radius as f64 * n.stretch;
                ball_sphere(data, center, hold, n, reach)
            }
        };
        // An inner node's box, when first asked for ([`Refitter::node_box`]).
        if !rest.is_leaf()
            && let Some(b) = self.state.boxes.get_mut(id.index())
        {
            *b = LeveledBox::UNKNOWN;
        }
        // Field by field: a whole-sphere copy from a temporary stalled on
        // store forwarding.
        let slot = &mut self.state.spheres[id.index()];
        slot.center = center;
        slot.radius = radius;
        let was = std::mem::replace(&mut self.state.stamp[id.index()], self.state.writes);
        self.state.refits += 1;
        if self.state.writes == self.state.frame && was != self.state.frame {
            self.state.log_asked(id.index());
        }
        Sphere::new(center, radius)
    }

    /// Node `id`'s box this frame, in levels around its sphere, built on
    /// the first request after its refit (ask after its sphere). The whole
    /// cube for a leaf (its triangle's own test follows; boxes on leaves
    /// cost more than they saved, module doc "Boxes") and where the rule
    /// keeps no boxes.
    #[inline]
    pub fn node_box(&mut self, id: NodeId) -> LeveledBox {
        let i = id.index();
        if self.tree.tree.node(id).is_leaf() {
            return LeveledBox::CUBE;
        }
        match self.state.boxes.get(i) {
            None => LeveledBox::CUBE,
            Some(&b) if b != LeveledBox::UNKNOWN => b,
            Some(_) => {
                let b = self.posed_box(id, &self.state.spheres[i]);
                self.state.boxes[i] = b;
                b
            }
        }
    }

    /// Node `id`'s box this frame (a ball rule's node), in levels around
    /// `sphere`, its sphere this frame (module doc, "Boxes"): each rest box
    /// `lo..=hi` of a slot joint moved by the joint's `f64` rows, `M·c ±
    /// |A|·h` about its centre `c` and half-extent `h` (exact from the `f32`
    /// corners), their union widened on every side by `κ·ρ` and a relative
    /// `F64_SLACK`, then clipped to the cube around `sphere` and rounded
    /// outward to its levels.
    fn posed_box(&self, id: NodeId, sphere: &Sphere) -> LeveledBox {
        let data = &self.tree.refit;
        let i = id.index();
        let reach = match data.rules[i] {
            Rule::JointBalls { reach, .. }
            | Rule::BlendedBalls { reach, .. }
            | Rule::OneBall { reach, .. } => reach,
            _ => return LeveledBox::CUBE,
        };
        let first = &data.node_boxes[i];
        let more = &data.more_boxes[first.start as usize..][..first.more as usize];
        let first = JointBox {
            lo: first.lo,
            hi: first.hi,
            joint: first.joint,
        };
        let (mut lo, mut hi) = (V64::repeat(f64::MAX), V64::repeat(f64::MIN));
        let mut largest = JointNorms::ZERO;
        for b in std::iter::once(&first).chain(more) {
            let (m, n) = self.slot_rows(b.joint);
            let (l, h) = (widen(&b.lo), widen(&b.hi));
            let (c, half) = ((l + h) * 0.5, (h - l) * 0.5);
            let q = apply_rows(m, &c);
            let e = V64::new(
                m[0].abs() * half.x + m[1].abs() * half.y + m[2].abs() * half.z,
                m[4].abs() * half.x + m[5].abs() * half.y + m[6].abs() * half.z,
                m[8].abs() * half.x + m[9].abs() * half.y + m[10].abs() * half.z,
            );
            lo = lo.inf(&(q - e));
            hi = hi.sup(&(q + e));
            largest = largest.max(n);
        }
        let rho = largest.frobenius * reach as f64 + largest.translation;
        let far = lo.abs().max().max(hi.abs().max());
        let pad = data.rounding * rho * (1.0 + F64_SLACK) + F64_SLACK * (far + rho);
        let lo = lo.add_scalar(-pad);
        let hi = hi.add_scalar(pad);
        LeveledBox::enclosing([lo.x, lo.y, lo.z], [hi.x, hi.y, hi.z], sphere)
    }

    /// Starts loading what asking for node `id`'s sphere reads: its stamp
    /// and sphere, its rest node and its rule (a hint; see
    /// `crate::prefetch`).
    #[inline(always)]
    pub fn prefetch(&self, id: NodeId) {
        let i = id.index();
        prefetch_at(&self.state.stamp, i);
        prefetch_at(&self.state.spheres, i);
        prefetch_at(self.tree.tree.nodes(), i);
        prefetch_at(&self.tree.refit.rules, i);
    }

    /// Starts loading what building node `id`'s box reads first: its rest
    /// boxes (a hint; see [`Refitter::node_box`]).
    #[inline(always)]
    pub fn prefetch_box(&self, id: NodeId) {
        prefetch_at(&self.tree.refit.node_boxes, id.index());
    }

    /// Starts loading node `id`'s rest balls, if its rule keeps them apart
    /// ([`RefitRule::JointBalls`] with several balls). Reads the rule: call it once
    /// [`Self::prefetch`] has had time to load it.
    #[inline(always)]
    pub fn prefetch_balls(&self, id: NodeId) {
        if let Rule::JointBalls { start, end, .. } | Rule::BlendedBalls { start, end, .. } =
            self.tree.refit.rules[id.index()]
        {
            let balls = &self.tree.refit.balls;
            prefetch_at(balls, start as usize);
            // A ball is 20 bytes: the last one may start a line of its own.
            prefetch_at(balls, (end as usize).saturating_sub(1));
        }
    }

    /// Slot joint `j`'s skin matrix and norms (`BASE`: the base frame's).
    #[inline]
    fn slot<'s>(&'s self, j: u16, base: &'s Matrix4<f32>) -> (&'s Matrix4<f32>, &'s JointNorms) {
        if j == BASE {
            (base, self.state.norms.last().unwrap())
        } else {
            (&self.skin[j as usize], &self.state.norms[j as usize])
        }
    }

    /// Slot joint `j`'s matrix rows in `f64` and norms (`BASE`: the base
    /// frame's).
    #[inline]
    fn slot_rows(&self, j: u16) -> (&[f64; 12], &JointNorms) {
        let i = if j == BASE {
            self.state.norms.len() - 1
        } else {
            j as usize
        };
        (&self.state.mats[i], &self.state.norms[i])
    }

    /// Node `id`'s sphere this frame: as refit already, or refit now.
    #[inline]
    pub fn fresh(&mut self, id: NodeId, base: &Matrix4<f32>) -> Sphere {
        match self.state.take(id) {
            Some((s, false)) => s,
            Some((s, true)) => {
                // Refit ahead and asked for now: the children its rule
                // read are asked for too, as refitting it on demand would
                // have refit them (the same nodes fresh either way).
                if matches!(self.tree.refit.rules[id.index()], Rule::FromChildren) {
                    for c in self.tree.tree.node(id).children() {
                        self.fresh(NodeId(c), base);
                    }
                }
                s
            }
            None => self.refit_node(id, base),
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
    /// The posed tree that refits on request.
    pub refitter: Refitter<'a>,
    /// The skeleton's base frame this frame (a placed character's:
    /// `placement · base`), the matrix of a root joint's parent.
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
    #[inline]
    fn prefetch(&self, id: NodeId) {
        self.refitter.prefetch(id);
    }
}

#[cfg(test)]
mod tests {
    use nalgebra::{Matrix3, Matrix4, Rotation3, Vector3};

    use super::{NodeId, RefitRule, RefitState, Refitter, stretch};
    use crate::character::{Character, Influences, JointId, PoseBuffers, SkinningModel};
    use crate::geometry::Sphere;
    use crate::geometry::leveled_box::LeveledBox;
    use crate::humanoid::{HumanoidParams, generate_humanoid};
    use crate::mesh::EdgeDedup;
    use crate::sphere_tree::BuildParams;
    use crate::sphere_tree::character::CharacterTree;
    use crate::sphere_tree::containment::VertexSets;

    /// Poses `c`'s first clip at `at` (a fraction of its duration) with
    /// joints stretched apart from their parents, so that a parent's norms
    /// left out of `σ`, `α` or `τ` show, placed 1.2 km from the origin.
    fn pose_stretched_far_away(c: &Character, b: &mut PoseBuffers, at: f32) {
        let clip = &c.clips[0];
        clip.sample(
            clip.start() + clip.duration() * at,
            c.skeleton.rest_pose_ref(),
            &mut b.local,
        );
        for (j, l) in b.local.iter_mut().enumerate() {
            let f = 1.0 + 0.05 * (j % 5) as f32;
            l.scale = Vector3::new(f, 1.0 / f, 1.0 + 0.1 * (j % 3) as f32);
        }
        b.pose_local(c);
        b.place(&Matrix4::new_translation(&Vector3::new(
            1234.5, -20.25, 3.0,
        )));
    }

    /// Every sphere of `tree` refit to `b`'s pose.
    fn every_sphere(tree: &CharacterTree, c: &Character, b: &PoseBuffers) -> Vec<Sphere> {
        let mut state = RefitState::new(tree, c.skeleton.len());
        state.begin_frame_with_base(&b.skin, &b.base);
        Refitter {
            tree,
            skin: &b.skin,
            state: &mut state,
        }
        .refit_all(&b.base);
        state.spheres
    }

    /// Poses `c` at eight points of its first clip, stretched and placed far
    /// away ([`pose_stretched_far_away`]), skins it under `model`, refits
    /// `tight` and `loose`, asserts that `tight`'s spheres hold every
    /// skinned vertex (tolerance 0), and hands each step's two sets of
    /// spheres to `compare`.
    fn each_stretched_pose(
        c: &Character,
        model: SkinningModel,
        (tight, loose): (&CharacterTree, &CharacterTree),
        label: &str,
        mut compare: impl FnMut(usize, &[Sphere], &[Sphere]),
    ) {
        let sets = VertexSets::new(&tight.tree, &c.mesh);
        let mut b = PoseBuffers::new(c);
        for step in 0..8 {
            pose_stretched_far_away(c, &mut b, step as f32 / 8.0);
            b.skin_all(c, model);
            let (st, sl) = (every_sphere(tight, c, &b), every_sphere(loose, c, &b));
            let held = sets.check(&st, &b.positions, 0.0);
            assert!(held.checks > 0);
            assert_eq!(
                held.violations, 0,
                "{label} step {step}: worst excess {}",
                held.worst_excess
            );
            compare(step, &st, &sl);
        }
    }

    /// `Rule::Rigid` gives the very spheres of the general rule it stands
    /// for, bit for bit, on a walking humanoid placed far from the origin
    /// (both skinning models), and stands for over half the nodes.
    #[test]
    fn rigid_rule_equals_the_general_corner_rule() {
        let c = generate_humanoid(&HumanoidParams {
            vertices: 3000,
            seed: 1,
        })
        .unwrap();
        for model in [SkinningModel::Paper, SkinningModel::Linear] {
            let ct = CharacterTree::build(
                &c,
                &EdgeDedup::keep_all(&c.mesh),
                model,
                BuildParams::default(),
            );
            let rigid = ct.refit.rigid_count();
            assert!(
                2 * rigid > ct.tree.len(),
                "{model:?}: {rigid} of {}",
                ct.tree.len()
            );
            let mut general = ct.clone();
            general.refit = ct.refit.without_rigid();
            let mut b = PoseBuffers::new(&c);
            for step in 0..6 {
                pose_stretched_far_away(&c, &mut b, step as f32 / 6.0);
                assert_eq!(
                    every_sphere(&ct, &c, &b),
                    every_sphere(&general, &c, &b),
                    "{model:?} step {step}"
                );
            }
        }
    }

    /// Joint balls hold every skinned vertex exactly (tolerance 0) on a
    /// walking humanoid with joints stretched apart from their parents,
    /// placed 1.2 km from the origin, under both skinning models; and they
    /// are tighter than the paper's corners where several joints meet: the
    /// root's sphere and the sum of all radii are smaller on every pose.
    #[test]
    fn joint_balls_hold_every_vertex_and_are_tighter_than_corners() {
        let c = generate_humanoid(&HumanoidParams {
            vertices: 3000,
            seed: 2,
        })
        .unwrap();
        for model in [SkinningModel::Paper, SkinningModel::Linear] {
            let build = |rule| {
                CharacterTree::build_with_rule(
                    &c,
                    &EdgeDedup::keep_all(&c.mesh),
                    model,
                    BuildParams::default(),
                    rule,
                )
            };
            let balls = build(RefitRule::JointBalls);
            let corners = build(RefitRule::PaperCorners);
            let label = format!("{model:?}");
            each_stretched_pose(&c, model, (&balls, &corners), &label, |step, sb, sc| {
                assert!(sb[0].radius < sc[0].radius, "{label} step {step}: root");
                let sum = |s: &[Sphere]| s.iter().map(|x| x.radius as f64).sum::<f64>();
                assert!(sum(sb) < sum(sc), "{label} step {step}: radii");
            });
        }
    }

    /// The wider character tree ([`BuildParams::WIDE`], our methods'
    /// build) is a different tree (fewer nodes than the paper's build) and
    /// its joint balls still hold every skinned vertex exactly, under both
    /// skinning models, on the stretched, far-placed walk above.
    #[test]
    fn the_wide_character_tree_holds_every_vertex() {
        let c = generate_humanoid(&HumanoidParams {
            vertices: 3000,
            seed: 4,
        })
        .unwrap();
        let paper = BuildParams::default();
        for model in [SkinningModel::Paper, SkinningModel::Linear] {
            let build = |params| {
                let keep = EdgeDedup::keep_all(&c.mesh);
                CharacterTree::build_with_rule(&c, &keep, model, params, RefitRule::JointBalls)
            };
            let wide = build(BuildParams::WIDE);
            let deep = build(paper);
            assert!(
                wide.tree.len() < deep.tree.len(),
                "{model:?}: {} nodes, paper's build {}",
                wide.tree.len(),
                deep.tree.len()
            );
            let sets = VertexSets::new(&wide.tree, &c.mesh);
            let mut b = PoseBuffers::new(&c);
            for step in 0..8 {
                pose_stretched_far_away(&c, &mut b, step as f32 / 8.0);
                b.skin_all(&c, model);
                let held = sets.check(&every_sphere(&wide, &c, &b), &b.positions, 0.0);
                assert!(held.checks > 0);
                assert_eq!(
                    held.violations, 0,
                    "{model:?} step {step}: worst excess {}",
                    held.worst_excess
                );
            }
        }
    }

    /// The humanoid with four influences a vertex, as glTF characters are
    /// weighted: its joint, its parent and grandparent, and one joint
    /// anywhere in the skeleton with a small weight (the case where a ball
    /// per joint swings far from the vertices).
    fn four_influences(seed: u64) -> Character {
        let mut c = generate_humanoid(&HumanoidParams {
            vertices: 3000,
            seed,
        })
        .unwrap();
        let mut next = crate::test_rng::unit_floats(seed * 7919 + 1);
        let n = c.skeleton.len();
        let up = |j: JointId| c.skeleton.parent(j).unwrap_or(j);
        let (mut joints, mut weights) = (Vec::new(), Vec::new());
        for v in 0..c.mesh.vertex_count() {
            let j = c.paper.joint(v);
            let far = ((next() * n as f32) as usize).min(n - 1) as u16;
            joints.push([j.0, up(j).0, up(up(j)).0, far]);
            let w = [0.4 + next(), 0.3 * next(), 0.1 * next(), 0.05 * next()];
            let sum: f32 = w.iter().sum();
            weights.push(w.map(|x| x / sum));
        }
        c.influences = Influences::new(joints, weights, n).unwrap();
        c
    }

    /// Blended balls hold every skinned vertex exactly (tolerance 0) where
    /// vertices blend four joints, one of them anywhere in the skeleton,
    /// on the stretched walk placed 1.2 km from the origin, in the wide
    /// tree our methods build; and they are tighter than the balls alone:
    /// the sum of all radii is at least a tenth smaller on every pose.
    #[test]
    fn blended_balls_hold_every_vertex_and_are_tighter_than_the_balls_alone() {
        for seed in [3, 8] {
            let c = four_influences(seed);
            let model = SkinningModel::Linear;
            let build = |rule| {
                let keep = EdgeDedup::keep_all(&c.mesh);
                CharacterTree::build_with_rule(&c, &keep, model, BuildParams::WIDE, rule)
            };
            let (blended, balls) = (build(RefitRule::BlendedBalls), build(RefitRule::JointBalls));
            let label = format!("seed {seed}");
            each_stretched_pose(&c, model, (&blended, &balls), &label, |step, sb, sj| {
                let sum = |s: &[Sphere]| s.iter().map(|x| x.radius as f64).sum::<f64>();
                assert!(
                    sum(sb) < 0.9 * sum(sj),
                    "{label} step {step}: {} against {}",
                    sum(sb),
                    sum(sj)
                );
            });
        }
    }

    /// Every inner node's posed box holds its skinned vertices exactly (the
    /// faces the box test reads, tolerance 0), under both skinning models
    /// and both ball rules, on the stretched walk placed 1.2 km from the
    /// origin and at the origin, for characters blending four joints a
    /// vertex and the humanoid; and the boxes cut: at the origin nine inner
    /// nodes in ten get a box, on average under half their sphere's cube.
    #[test]
    fn posed_boxes_hold_every_vertex_and_cut_the_cube() {
        let humanoid = generate_humanoid(&HumanoidParams {
            vertices: 3000,
            seed: 2,
        })
        .unwrap();
        let characters = [four_influences(3), four_influences(8), humanoid];
        for (ci, c) in characters.iter().enumerate() {
            let sets_of = |t: &CharacterTree| VertexSets::new(&t.tree, &c.mesh);
            for model in [SkinningModel::Linear, SkinningModel::Paper] {
                for rule in [RefitRule::BlendedBalls, RefitRule::JointBalls] {
                    let keep = EdgeDedup::keep_all(&c.mesh);
                    let t =
                        CharacterTree::build_with_rule(c, &keep, model, BuildParams::WIDE, rule);
                    let sets = sets_of(&t);
                    let mut b = PoseBuffers::new(c);
                    let (mut boxed, mut inner, mut fill) = (0usize, 0usize, 0.0f64);
                    for step in 0..6 {
                        pose_stretched_far_away(c, &mut b, step as f32 / 6.0);
                        if step % 2 == 1 {
                            // Back near the origin.
                            b.place(&Matrix4::new_translation(&Vector3::new(
                                -1234.5, 20.25, -3.0,
                            )));
                        }
                        b.skin_all(c, model);
                        let mut state = RefitState::new(&t, c.skeleton.len());
                        state.begin_frame_with_base(&b.skin, &b.base);
                        let mut r = Refitter {
                            tree: &t,
                            skin: &b.skin,
                            state: &mut state,
                        };
                        r.refit_all(&b.base);
                        for i in 0..t.tree.len() {
                            let id = NodeId(i as u32);
                            if t.tree.node(id).is_leaf() {
                                continue;
                            }
                            // Counted at the origin (1.2 km away an `f32`
                            // face is about a node's size: no box).
                            let near = step % 2 == 1;
                            inner += near as usize;
                            let s = r.state.spheres[i];
                            let q = r.node_box(id);
                            if q == LeveledBox::CUBE {
                                continue;
                            }
                            let (lo, hi) = q.faces(&s);
                            if near {
                                boxed += 1;
                                let side = 2.0 * f64::from(s.radius);
                                fill += (0..3)
                                    .map(|k| f64::from(hi[k] - lo[k]) / side)
                                    .product::<f64>();
                            }
                            for &v in sets.of(i) {
                                let p = b.positions[v as usize];
                                for k in 0..3 {
                                    assert!(
                                        lo[k] <= p[k] && p[k] <= hi[k],
                                        "character {ci} {model:?} {rule:?} step {step} node {i}: \
                                         vertex {v} at {} outside {}..{} on axis {k}",
                                        p[k],
                                        lo[k],
                                        hi[k]
                                    );
                                }
                            }
                        }
                    }
                    let mean = fill / boxed as f64;
                    eprintln!(
                        "character {ci} {model:?} {rule:?}: {boxed} boxes of {inner} nodes, filling {mean:.2} of the cube"
                    );
                    assert!(
                        10 * boxed > 9 * inner,
                        "character {ci}: {boxed} boxes of {inner} nodes"
                    );
                    assert!(
                        mean < 0.7,
                        "character {ci} {model:?} {rule:?}: boxes fill {mean:.2} of the cube"
                    );
                }
            }
        }
    }

    /// The stretch bounds the largest singular value (from nalgebra's SVD)
    /// from above and is within 10⁻⁵ of it, on both of its paths: rotations
    /// times axis-aligned scales (the Gershgorin path) and sheared or
    /// rotated-then-scaled matrices (the eigen path).
    #[test]
    fn stretch_is_a_tight_upper_bound_of_the_spectral_norm() {
        let mut next = crate::test_rng::unit_floats(0x2545_f491_4f6c_dd1d);
        for case in 0..2000 {
            let axis = Vector3::new(next() - 0.5, next() - 0.5, next() - 0.5);
            let r = Rotation3::from_scaled_axis(axis * 6.0).into_inner();
            let s = Matrix3::from_diagonal(&Vector3::new(
                0.2 + 3.0 * next(),
                0.2 + 3.0 * next(),
                0.2 + 3.0 * next(),
            ));
            let a: Matrix3<f32> = match case % 3 {
                0 => r,
                1 => r * s,
                _ => s * r,
            };
            let mut m = Matrix4::identity();
            m.fixed_view_mut::<3, 3>(0, 0).copy_from(&a);
            let exact = a.map(|v| v as f64).singular_values().max();
            let bound = stretch(&m) as f64;
            assert!(bound >= exact, "case {case}: {bound} < {exact}");
            assert!(
                bound <= exact * (1.0 + 1e-5),
                "case {case}: {bound} ≫ {exact}"
            );
        }
    }
}
