//! A query shape (a ray, a ball, a capsule) against one body: the one pass
//! skeleton ([`super::pass`]) with the shape as the second hierarchy, a
//! single leaf around it. Traversal meets the body's spheres with the
//! shape's bounding sphere and, as its guard, the shape's own sphere test;
//! a character's spheres are refit on demand (at most once a frame, whether
//! a contact pass or another query asked first) and only the triangles
//! reached are skinned; the leaf test is the shape's exact triangle test
//! in `f64` (`geometry::query_shapes`).

use std::cell::Cell;

use nalgebra::Vector3;

use crate::geometry::query_shapes::{
    Capsule, Ray, sphere_overlaps_triangle, sphere_reaches_sphere,
};
use crate::geometry::{Point, Sphere, Triangle};
use crate::mesh::{TriMesh, TriangleId};
use crate::sphere_tree::traverse::{LeafPair, TraversalStats};
use crate::sphere_tree::{
    Hierarchy, Node, NodeId, Order, SphereTree, Workspace, traverse_guarded, traverse_ordered,
};

use super::character_side::{CharacterSide, TimedRefit};
use super::counters::FrameCounters;
use super::pass::{Pass, Traversed};
use super::prepared_triangles::PreparedTriangles;

/// What a query asks about, in the frame of the body it is run against.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum QueryShape {
    /// The triangles a ray crosses, with where.
    Ray(Ray),
    /// The triangles a closed ball touches.
    Ball(Sphere),
    /// The triangles a capsule touches.
    Capsule(Capsule),
}

impl QueryShape {
    /// Whether the shape may reach node sphere `s` (conservative).
    #[inline]
    pub(crate) fn reaches(&self, s: &Sphere) -> bool {
        match self {
            QueryShape::Ray(r) => r.reaches_sphere(s),
            QueryShape::Ball(b) => sphere_reaches_sphere(b, s),
            QueryShape::Capsule(c) => c.reaches_sphere(s),
        }
    }

    /// The sphere a traversal meets the body with: for a ray, around its
    /// part inside `root` (`None`: it misses the root); the others' own.
    pub(crate) fn bounding_sphere(&self, root: &Sphere) -> Option<Sphere> {
        match self {
            QueryShape::Ray(r) => r
                .sphere_interval(root)
                .map(|(t0, t1)| r.bounding_sphere(t0, t1)),
            QueryShape::Ball(b) => sphere_reaches_sphere(b, root).then_some(*b),
            QueryShape::Capsule(c) => c.reaches_sphere(root).then(|| c.bounding_sphere()),
        }
    }

    /// The exact test against triangle `t`: `(distance, barycentric)` along
    /// a ray, `(0, 0)` for the others.
    #[inline]
    fn meets(&self, t: &Triangle) -> Option<(f64, [f64; 3])> {
        match self {
            QueryShape::Ray(r) => r.triangle_hit(t).map(|h| (h.distance, h.barycentric)),
            QueryShape::Ball(b) => sphere_overlaps_triangle(b, t).then_some((0.0, [0.0; 3])),
            QueryShape::Capsule(c) => c.overlaps_triangle(t).then_some((0.0, [0.0; 3])),
        }
    }
}

/// A triangle a query shape meets.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct ShapeHit {
    /// The body's triangle (its mesh index).
    pub(crate) triangle: u32,
    /// Along a ray: the distance from its origin; otherwise 0.
    pub(crate) distance: f64,
    /// Along a ray: the point's barycentric coordinates on the triangle.
    pub(crate) barycentric: [f64; 3],
}

/// A body as a query sees it: a hierarchy to traverse and its triangles.
pub(crate) trait QueryTarget {
    /// Spheres refit and vertices skinned so far this frame.
    fn work(&self) -> (u64, u64);

    /// Traverses the body's hierarchy against `node` (the shape's one-leaf
    /// tree) with `guard`, pushing leaf pairs (the body's leaf as `a`);
    /// returns the traversal's counters.
    fn traverse_against<G, F>(
        &mut self,
        node: &mut SphereTree,
        ws: &mut Workspace,
        guard: G,
        push: F,
    ) -> TraversalStats
    where
        G: FnMut(NodeId, &Sphere) -> bool,
        F: FnMut(LeafPair);

    /// A ray's nearest hit, found while traversing: each leaf reached is
    /// tested at once and the ray shortened to the best hit so far, so
    /// spheres beyond it are not descended ([`nearest`]).
    fn nearest(&mut self, node: &mut SphereTree, ws: &mut Workspace, ray: &Ray) -> Nearest;

    /// Gets triangle `t` ready to be read (skins a character's corners).
    #[inline]
    fn prepare(&mut self, _t: u32) {}

    /// Triangle `t` in the body's frame.
    fn triangle(&self, t: u32) -> Triangle;
}

impl QueryTarget for CharacterSide<'_> {
    fn work(&self) -> (u64, u64) {
        CharacterSide::work(self)
    }

    fn traverse_against<G, F>(
        &mut self,
        node: &mut SphereTree,
        ws: &mut Workspace,
        guard: G,
        push: F,
    ) -> TraversalStats
    where
        G: FnMut(NodeId, &Sphere) -> bool,
        F: FnMut(LeafPair),
    {
        let mut h = LeavesUnrefit {
            inner: self.hierarchy::<false>(),
            leaves: 0,
        };
        let mut stats = traverse_guarded(&mut h, node, ws, guard, push);
        // A leaf let through was no test.
        stats.sphere_tests -= h.leaves;
        stats
    }

    fn nearest(&mut self, node: &mut SphereTree, ws: &mut Workspace, ray: &Ray) -> Nearest {
        let CharacterSide {
            character,
            tree,
            model,
            pose,
            refit,
            skin,
        } = self;
        let mut h = LeavesUnrefit {
            inner: TimedRefit::<false>::new(tree, *pose, refit),
            leaves: 0,
        };
        let indices = character.mesh.indices();
        let mut found = nearest(&mut h, node, ws, ray, |t| {
            let corners = indices[t as usize];
            for v in corners {
                skin.ensure(*pose, character, *model, v);
            }
            skin.triangle(corners)
        });
        found.stats.sphere_tests -= h.leaves;
        found
    }

    #[inline]
    fn prepare(&mut self, t: u32) {
        self.ensure_triangle(t);
    }

    #[inline]
    fn triangle(&self, t: u32) -> Triangle {
        CharacterSide::triangle(self, t)
    }
}

/// A character's tree for a query: inner spheres refit on demand, leaves
/// never refit — a leaf whose parent the shape reaches goes straight to
/// the exact triangle test. Skinning a leaf triangle's three corners (each
/// shared with about six triangles) and testing it costs less than
/// refitting the leaf's sphere from its joints, and answers exactly.
struct LeavesUnrefit<H> {
    inner: H,
    /// Leaves let through (their "sphere" holds everything).
    leaves: u64,
}

/// A sphere every shape reaches.
const EVERYWHERE: Sphere = Sphere::new(Point::new(0.0, 0.0, 0.0), f32::INFINITY);

impl<H: Hierarchy> Hierarchy for LeavesUnrefit<H> {
    #[inline]
    fn tree(&self) -> &SphereTree {
        self.inner.tree()
    }
    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        if self.inner.tree().node(id).is_leaf() {
            self.leaves += 1;
            return EVERYWHERE;
        }
        self.inner.sphere(id)
    }
    #[inline]
    fn prefetch(&self, id: NodeId) {
        self.inner.prefetch(id);
    }
}

/// A rigid body (a room, an object in its own frame): its static tree and
/// triangles. Every leaf of an environment tree names a mesh triangle (a
/// big triangle's division leaves, their big triangle).
pub(crate) struct RigidTarget<'a> {
    pub(crate) tree: &'a SphereTree,
    pub(crate) mesh: &'a TriMesh,
}

/// A static tree through a shared borrow.
struct Static<'a>(&'a SphereTree);

impl Hierarchy for Static<'_> {
    #[inline]
    fn tree(&self) -> &SphereTree {
        self.0
    }
    #[inline]
    fn sphere(&mut self, id: NodeId) -> Sphere {
        self.0.nodes()[id.index()].sphere
    }
}

impl QueryTarget for RigidTarget<'_> {
    fn work(&self) -> (u64, u64) {
        (0, 0)
    }

    fn traverse_against<G, F>(
        &mut self,
        node: &mut SphereTree,
        ws: &mut Workspace,
        guard: G,
        push: F,
    ) -> TraversalStats
    where
        G: FnMut(NodeId, &Sphere) -> bool,
        F: FnMut(LeafPair),
    {
        traverse_guarded(&mut Static(self.tree), node, ws, guard, push)
    }

    fn nearest(&mut self, node: &mut SphereTree, ws: &mut Workspace, ray: &Ray) -> Nearest {
        let mesh = self.mesh;
        nearest(&mut Static(self.tree), node, ws, ray, |t| {
            mesh.triangle(TriangleId(t))
        })
    }

    #[inline]
    fn triangle(&self, t: u32) -> Triangle {
        self.mesh.triangle(TriangleId(t))
    }
}

/// What [`QueryTarget::nearest`] found and cost.
pub(crate) struct Nearest {
    pub(crate) stats: TraversalStats,
    /// The shape's own sphere tests.
    pub(crate) guard_tests: u64,
    /// Triangles tested on the way.
    pub(crate) triangle_tests: u64,
    /// The leaf of the nearest hit, if any.
    pub(crate) leaf: Option<LeafPair>,
}

/// The traversal of [`traverse_guarded`] with a ray as the second tree's
/// leaf: every leaf reached is tested at once (`triangle` fetches, and
/// skins, its triangle), and spheres are met with the ray cut at the best
/// hit so far (rounded up to `f32`: a tie is kept, never cut). The order's
/// key is the ray's sphere test ([`NearestFirst`]), so the guard has none
/// of its own. The same traversal as every pass; only its closures differ.
fn nearest<H: Hierarchy>(
    h: &mut H,
    node: &mut SphereTree,
    ws: &mut Workspace,
    ray: &Ray,
    mut triangle: impl FnMut(u32) -> Triangle,
) -> Nearest {
    let reach = Cell::new(ray.max_distance);
    let best = Cell::new((f64::INFINITY, None::<LeafPair>));
    let tests = Cell::new(0u64);
    let order = NearestFirst::new(ray, &reach);
    let stats = traverse_ordered(
        h,
        node,
        ws,
        &order,
        |_, _| true,
        |p| {
            tests.set(tests.get() + 1);
            let mut r = *ray;
            r.max_distance = reach.get();
            if let Some(hit) = r.triangle_hit(&triangle(p.primitive_a))
                && hit.distance < best.get().0
            {
                best.set((hit.distance, Some(p)));
                reach.set((hit.distance as f32).next_up());
            }
        },
    );
    Nearest {
        stats,
        guard_tests: order.tests.get(),
        triangle_tests: tests.get(),
        leaf: best.get().1,
    }
}

/// The key of a sphere a ray cannot meet: not a number, so that
/// `key <= reach` is false for every reach, an infinite one included.
const MISSED: f32 = f32::NAN;

/// A ray's spheres opened nearest first, and one the ray can enter only
/// beyond the best hit so far dropped unopened ([`Order`]). The key is the
/// ray's one test of a sphere: a sphere the ray's line passes by, or one
/// wholly behind its origin, gets [`MISSED`], which no reach keeps.
struct NearestFirst<'r> {
    /// The ray's origin, and its direction made a unit vector, in `f64`.
    origin: Vector3<f64>,
    direction: Vector3<f64>,
    /// The best hit's distance so far (rounded up), or the ray's length.
    reach: &'r Cell<f32>,
    /// Spheres tested (keys of finite spheres computed).
    tests: Cell<u64>,
}

impl<'r> NearestFirst<'r> {
    fn new(ray: &Ray, reach: &'r Cell<f32>) -> Self {
        let d = ray.direction.cast::<f64>();
        Self {
            origin: ray.origin.coords.cast::<f64>(),
            direction: d / d.norm(),
            reach,
            tests: Cell::new(0),
        }
    }
}

impl Order for NearestFirst<'_> {
    const ORDERED: bool = true;

    /// A lower bound of the distance at which the ray enters `s` (`-∞`
    /// for a leaf let through): `along − √(r² − across²)`, the radius
    /// widened by a billionth, the square widened by 10⁻¹² of `|m|² + r²`,
    /// and the result lowered by a millionth of `|m|₁ + r` (`f64` rounding
    /// here is below 10⁻¹⁵ of those sizes; the ray's `f32` direction, with
    /// which hits are measured, is a unit vector within 10⁻⁷). [`MISSED`]
    /// where the line misses the widened sphere (`r² − across²` below zero)
    /// or leaves it before the origin (`along + √(…)` plus the margin below
    /// zero): the ray cannot meet it.
    #[inline]
    fn key(&self, s: &Sphere) -> f32 {
        if s.radius == f32::INFINITY {
            return f32::NEG_INFINITY;
        }
        self.tests.set(self.tests.get() + 1);
        let m = s.center.coords.cast::<f64>() - self.origin;
        let along = m.dot(&self.direction);
        let across2 = (m - self.direction * along).norm_squared();
        let r = f64::from(s.radius) * (1.0 + 1e-9);
        let m2 = m.norm_squared();
        let h2 = r * r - across2 + 1e-12 * (m2 + r * r);
        if h2 < 0.0 {
            return MISSED;
        }
        let h = h2.sqrt();
        let far = m.x.abs() + m.y.abs() + m.z.abs();
        let margin = 1e-6 * (far + r);
        if along + h + margin < 0.0 {
            return MISSED;
        }
        let enter = along - h - margin;
        // Rounded down to `f32`.
        let k = enter as f32;
        if f64::from(k) > enter {
            k.next_down()
        } else {
            k
        }
    }

    #[inline]
    fn keep(&self, key: f32) -> bool {
        key <= self.reach.get()
    }
}

/// The one-leaf tree a query shape is traversed as (kept in the caller's
/// scratch: set per query, never reallocated).
pub(crate) fn shape_node() -> SphereTree {
    SphereTree::from_nodes(vec![Node::leaf(Sphere::new(Point::origin(), 0.0), 0)])
}

/// Sets the one-leaf tree's sphere.
pub(crate) fn set_shape_node(node: &mut SphereTree, s: Sphere) {
    if let Some(x) = node.spheres_mut().next() {
        *x = s;
    }
}

/// A query shape against one body whose root it may reach.
pub(crate) struct QueryPass<'a, T: QueryTarget> {
    pub(crate) target: T,
    pub(crate) shape: QueryShape,
    /// The shape's one-leaf tree, its sphere set to the bounding sphere.
    pub(crate) node: &'a mut SphereTree,
    /// A ray's nearest hit only ([`QueryTarget::nearest`]); otherwise
    /// every hit.
    pub(crate) nearest_only: bool,
}

impl<T: QueryTarget> Pass for QueryPass<'_, T> {
    type Hit = ShapeHit;

    fn work(&self) -> (u64, u64) {
        self.target.work()
    }

    fn times_stages(&self) -> bool {
        false
    }

    fn traverse<const TIMED: bool>(
        &mut self,
        ws: &mut Workspace,
        leaf_pairs: &mut Vec<LeafPair>,
    ) -> Traversed {
        let shape = self.shape;
        if let (true, QueryShape::Ray(ray)) = (self.nearest_only, shape) {
            let found = self.target.nearest(self.node, ws, &ray);
            // The narrow phase confirms the nearest hit alone.
            leaf_pairs.extend(found.leaf);
            return Traversed {
                stats: found.stats,
                guard_sphere_tests: found.guard_tests,
                leaf_tests: found.triangle_tests,
                ..Traversed::default()
            };
        }
        let guards = Cell::new(0u64);
        let stats = self.target.traverse_against(
            self.node,
            ws,
            |_, s| {
                if s.radius == f32::INFINITY {
                    return true;
                }
                guards.set(guards.get() + 1);
                shape.reaches(s)
            },
            |p| leaf_pairs.push(p),
        );
        Traversed {
            stats,
            guard_sphere_tests: guards.get(),
            ..Traversed::default()
        }
    }

    fn prepare(&mut self, leaf_pairs: &[LeafPair]) {
        for p in leaf_pairs {
            self.target.prepare(p.primitive_a);
        }
    }

    #[inline]
    fn test(
        &mut self,
        leaf_pairs: &[LeafPair],
        k: usize,
        _prepared: &mut [PreparedTriangles; 2],
        c: &mut FrameCounters,
    ) -> Option<ShapeHit> {
        let t = leaf_pairs[k].primitive_a;
        c.tri_tri += 1;
        self.shape
            .meets(&self.target.triangle(t))
            .map(|(distance, barycentric)| ShapeHit {
                triangle: t,
                distance,
                barycentric,
            })
    }

    /// Nearest first; a triangle met through several leaves (a big
    /// triangle's division) once.
    fn finish(hits: &mut Vec<ShapeHit>) {
        hits.sort_unstable_by(|x, y| {
            x.distance
                .total_cmp(&y.distance)
                .then(x.triangle.cmp(&y.triangle))
        });
        hits.dedup_by_key(|h| h.triangle);
    }
}
