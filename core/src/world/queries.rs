//! Queries against a world at its current poses: a ray's first hit or all
//! its hits, and the triangles a ball or a capsule touches, by body handle.
//!
//! Each body is met first by its root sphere (one test; a ray that misses
//! every root costs one sphere test per body). A body whose root the shape
//! reaches runs one pass of the pass skeleton with the shape as its second
//! hierarchy (`pipeline::query_pass`): a character's spheres are refit on
//! demand in the current pose's frame — the frame a step at that pose uses
//! too, so no sphere is refit twice between two poses whoever asks first —
//! and only the triangles reached are skinned. A moving object is queried
//! in its own frame (the shape moved by its inverse pose). Queries read the
//! world through a shared borrow and write only the characters' refit and
//! skinning state (behind their locks) and the caller's [`QueryScratch`]:
//! several threads may query one world at once, each with its scratch.
//! After a scratch has served its first queries, a query allocates nothing.
//! Inactive characters, objects and rooms are not looked at (a query naming one
//! finds nothing).

use crate::geometry::query_shapes::{Capsule, Ray, ShapeError};
use crate::geometry::{Point, Real, Sphere};
use crate::pipeline::FrameCounters;
use crate::pipeline::pass::{PassScratch, run};
use crate::pipeline::query_pass::{
    QueryPass, QueryShape, RigidTarget, ShapeHit, set_shape_node, shape_node,
};
use crate::sphere_tree::{NodeId, SphereTree};

use super::bodies::{CharacterBody, RigidBody};
use super::collision_world::CollisionWorld;
use super::error::WorldError;
use super::groups::CollisionGroups;
use super::handles::{CharacterHandle, ObjectHandle, RoomHandle};
use super::step::side;

/// A body of a world, by kind and handle.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub enum BodyRef {
    /// A static room.
    Room(RoomHandle),
    /// A moving rigid object.
    Object(ObjectHandle),
    /// A skinned character.
    Character(CharacterHandle),
}

impl std::fmt::Display for BodyRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            BodyRef::Room(h) => h.fmt(f),
            BodyRef::Object(h) => h.fmt(f),
            BodyRef::Character(h) => h.fmt(f),
        }
    }
}

/// Which bodies a query looks at.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum QueryTargets {
    /// Every room, object and character.
    #[default]
    All,
    /// Every character.
    Characters,
    /// One character.
    Character(CharacterHandle),
    /// Every room and object (the static and rigid world).
    Rigid,
    /// One room.
    Room(RoomHandle),
    /// One object.
    Object(ObjectHandle),
    /// Every room, object and character whose groups meet these (a query
    /// that belongs to some groups: a hit-scan that ignores its shooter's
    /// group).
    Meeting(CollisionGroups),
}

impl QueryTargets {
    fn rooms(self) -> bool {
        matches!(
            self,
            QueryTargets::All | QueryTargets::Rigid | QueryTargets::Room(_)
        )
    }
    fn objects(self) -> bool {
        matches!(
            self,
            QueryTargets::All | QueryTargets::Rigid | QueryTargets::Object(_)
        )
    }
    fn characters(self) -> bool {
        matches!(
            self,
            QueryTargets::All | QueryTargets::Characters | QueryTargets::Character(_)
        )
    }
    /// Whether the query looks at `body`, of groups `groups`.
    fn wants(self, body: BodyRef, groups: CollisionGroups) -> bool {
        match (self, body) {
            (QueryTargets::Meeting(g), _) => g.meets(groups),
            (QueryTargets::Room(h), BodyRef::Room(b)) => h == b,
            (QueryTargets::Object(h), BodyRef::Object(b)) => h == b,
            (QueryTargets::Character(h), BodyRef::Character(b)) => h == b,
            (t, BodyRef::Room(_)) => t.rooms(),
            (t, BodyRef::Object(_)) => t.objects(),
            (t, BodyRef::Character(_)) => t.characters(),
        }
    }
}

/// Where a ray meets a body.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RayHit {
    /// The body met.
    pub body: BodyRef,
    /// Its triangle (an index of its mesh; for a character, of its
    /// character's mesh).
    pub triangle: u32,
    /// Distance from the ray's origin (world units).
    pub distance: Real,
    /// The point met, in the world.
    pub point: Point,
    /// The point's barycentric coordinates on the triangle's corners, as
    /// posed now.
    pub barycentric: [Real; 3],
}

/// A triangle a ball or a capsule touches.
#[derive(Clone, Copy, Debug, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct Touched {
    /// The body touched.
    pub body: BodyRef,
    /// Its triangle.
    pub triangle: u32,
}

/// What the last query of a scratch cost.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[cfg_attr(feature = "serde", derive(serde::Serialize))]
pub struct QueryCounters {
    /// Bodies' root spheres tested against the shape (one per body looked
    /// at).
    pub root_tests: u64,
    /// Bodies whose root the shape reached, each then traversed.
    pub bodies_entered: u64,
    /// Sphere tests of the traversals below the roots (the shape's bounding
    /// sphere and its own test of each sphere).
    pub sphere_tests: u64,
    /// Exact shape-triangle tests.
    pub triangle_tests: u64,
    /// Character spheres refit by this query (not by earlier ones or a step
    /// in the same frame).
    pub refits: u64,
    /// Character vertices skinned by this query.
    pub skinned_vertices: u64,
}

impl QueryCounters {
    /// Adds `o`'s counts (a sum over queries).
    pub fn add(&mut self, o: &QueryCounters) {
        self.root_tests += o.root_tests;
        self.bodies_entered += o.bodies_entered;
        self.sphere_tests += o.sphere_tests;
        self.triangle_tests += o.triangle_tests;
        self.refits += o.refits;
        self.skinned_vertices += o.skinned_vertices;
    }

    fn add_pass(&mut self, c: &FrameCounters) {
        self.bodies_entered += 1;
        self.sphere_tests += c.sphere_sphere;
        self.triangle_tests += c.tri_tri;
        self.refits += c.refits;
        self.skinned_vertices += c.skinned_vertices;
    }
}

/// A query's working memory, kept by the caller between queries (one per
/// thread querying): after its first queries, a query allocates nothing.
#[derive(Clone, Debug)]
pub struct QueryScratch {
    pass: PassScratch,
    /// The shape's one-leaf tree.
    node: SphereTree,
    hits: Vec<ShapeHit>,
    counters: QueryCounters,
}

impl Default for QueryScratch {
    fn default() -> Self {
        Self {
            pass: PassScratch::default(),
            node: shape_node(),
            hits: Vec::new(),
            counters: QueryCounters::default(),
        }
    }
}

impl QueryScratch {
    /// An empty scratch.
    pub fn new() -> Self {
        Self::default()
    }

    /// What the last query cost.
    pub fn counters(&self) -> &QueryCounters {
        &self.counters
    }
}

/// What each body's hits become, for a query.
trait Gather {
    /// Takes body `body`'s hits (nearest first), `to_world` its pose.
    fn take(&mut self, body: BodyRef, hits: &[ShapeHit]);
    /// How far a ray still needs to look (first hit: the best so far).
    fn reach(&self) -> Real {
        Real::INFINITY
    }
    /// Whether only a ray's nearest hit is wanted.
    fn nearest_only(&self) -> bool {
        false
    }
}

impl CollisionWorld {
    /// The first triangle `ray` meets among `targets`, or `None`.
    ///
    /// ```
    /// # use std::sync::Arc;
    /// # use cornertree::geometry::{Point, Vector};
    /// # use cornertree::geometry::query_shapes::Ray;
    /// # use cornertree::mesh::TriMesh;
    /// # use cornertree::pipeline::Method;
    /// # use cornertree::world::{BodyRef, CollisionWorld, QueryScratch, QueryTargets};
    /// let floor = TriMesh::new(
    ///     vec![Point::new(-2.0, 0.0, -2.0), Point::new(2.0, 0.0, -2.0), Point::new(0.0, 0.0, 2.0)],
    ///     vec![[0, 2, 1]],
    /// )
    /// .unwrap();
    /// let mut world = CollisionWorld::new(Method::UndividedPrunedTriTri);
    /// let room = world.add_room(Arc::new(floor)).unwrap();
    /// let down = Ray::new(Point::new(0.0, 1.5, 0.0), Vector::new(0.0, -1.0, 0.0), f32::INFINITY).unwrap();
    /// let mut scratch = QueryScratch::new();
    /// let hit = world.cast_ray(&down, QueryTargets::All, &mut scratch).unwrap().unwrap();
    /// assert_eq!((hit.body, hit.triangle, hit.distance), (BodyRef::Room(room), 0, 1.5));
    /// assert_eq!(scratch.counters().root_tests, 1);
    /// // A handle this world did not give is refused.
    /// let nobody = QueryTargets::Character(cornertree::world::CharacterHandle(7));
    /// assert!(world.cast_ray(&down, nobody, &mut scratch).is_err());
    /// ```
    pub fn cast_ray(
        &self,
        ray: &Ray,
        targets: QueryTargets,
        scratch: &mut QueryScratch,
    ) -> Result<Option<RayHit>, WorldError> {
        self.check_targets(targets)?;
        struct First {
            ray: Ray,
            best: Option<RayHit>,
            /// The best hit's distance before rounding to `f32`.
            best_distance: f64,
        }
        impl Gather for First {
            fn take(&mut self, body: BodyRef, hits: &[ShapeHit]) {
                if let Some(h) = hits.first()
                    && h.distance < self.best_distance
                {
                    self.best = Some(ray_hit(&self.ray, body, h));
                    self.best_distance = h.distance;
                }
            }
            fn reach(&self) -> Real {
                self.best.map_or(self.ray.max_distance, |b| b.distance)
            }
            fn nearest_only(&self) -> bool {
                true
            }
        }
        let mut first = First {
            ray: *ray,
            best: None,
            best_distance: f64::INFINITY,
        };
        self.query(QueryShape::Ray(*ray), targets, scratch, &mut first);
        Ok(first.best)
    }

    /// Every triangle `ray` meets among `targets`, nearest first, into `out`
    /// (cleared first).
    pub fn cast_ray_all(
        &self,
        ray: &Ray,
        targets: QueryTargets,
        scratch: &mut QueryScratch,
        out: &mut Vec<RayHit>,
    ) -> Result<(), WorldError> {
        self.check_targets(targets)?;
        struct All<'a> {
            ray: Ray,
            out: &'a mut Vec<RayHit>,
        }
        impl Gather for All<'_> {
            fn take(&mut self, body: BodyRef, hits: &[ShapeHit]) {
                let ray = self.ray;
                self.out.extend(hits.iter().map(|h| ray_hit(&ray, body, h)));
            }
        }
        out.clear();
        self.query(
            QueryShape::Ray(*ray),
            targets,
            scratch,
            &mut All { ray: *ray, out },
        );
        out.sort_unstable_by(|x, y| {
            x.distance
                .total_cmp(&y.distance)
                .then(x.body.cmp(&y.body))
                .then(x.triangle.cmp(&y.triangle))
        });
        Ok(())
    }

    /// Every triangle the closed ball `ball` touches among `targets`, into
    /// `out` (cleared first), by body then triangle.
    pub fn overlap_sphere(
        &self,
        ball: &Sphere,
        targets: QueryTargets,
        scratch: &mut QueryScratch,
        out: &mut Vec<Touched>,
    ) -> Result<(), WorldError> {
        if !ball.center.iter().all(|x| x.is_finite()) || !ball.radius.is_finite() {
            return Err(ShapeError::NonFinite("the ball").into());
        }
        if ball.radius < 0.0 {
            return Err(ShapeError::Negative("the ball's radius").into());
        }
        self.check_targets(targets)?;
        self.overlap(QueryShape::Ball(*ball), targets, scratch, out);
        Ok(())
    }

    /// Every triangle `capsule` touches among `targets`, into `out`
    /// (cleared first), by body then triangle.
    pub fn overlap_capsule(
        &self,
        capsule: &Capsule,
        targets: QueryTargets,
        scratch: &mut QueryScratch,
        out: &mut Vec<Touched>,
    ) -> Result<(), WorldError> {
        self.check_targets(targets)?;
        self.overlap(QueryShape::Capsule(*capsule), targets, scratch, out);
        Ok(())
    }

    /// Refuses a handle this world did not give.
    fn check_targets(&self, targets: QueryTargets) -> Result<(), WorldError> {
        match targets {
            QueryTargets::Character(h) if h.index() >= self.characters.len() => {
                Err(WorldError::UnknownCharacter(h))
            }
            QueryTargets::Object(h) if h.index() >= self.objects.len() => {
                Err(WorldError::UnknownObject(h))
            }
            QueryTargets::Room(h) if h.index() >= self.rooms.len() => {
                Err(WorldError::UnknownRoom(h))
            }
            _ => Ok(()),
        }
    }

    fn overlap(
        &self,
        shape: QueryShape,
        targets: QueryTargets,
        scratch: &mut QueryScratch,
        out: &mut Vec<Touched>,
    ) {
        struct Overlaps<'a>(&'a mut Vec<Touched>);
        impl Gather for Overlaps<'_> {
            fn take(&mut self, body: BodyRef, hits: &[ShapeHit]) {
                self.0.extend(hits.iter().map(|h| Touched {
                    body,
                    triangle: h.triangle,
                }));
            }
        }
        out.clear();
        self.query(shape, targets, scratch, &mut Overlaps(out));
        out.sort_unstable();
    }

    /// Runs `shape` against every body of `targets` whose root it reaches.
    fn query(
        &self,
        shape: QueryShape,
        targets: QueryTargets,
        scratch: &mut QueryScratch,
        gather: &mut impl Gather,
    ) {
        scratch.counters = QueryCounters::default();
        // A ray looking for its first hit stops where the best hit so far
        // is (rounded up: a nearer hit within its `f32` rounding is kept).
        let clipped = |shape: QueryShape, reach: Real| match shape {
            QueryShape::Ray(mut r) => {
                r.max_distance = r.max_distance.min(reach.next_up());
                QueryShape::Ray(r)
            }
            other => other,
        };
        for (k, room) in self.rooms.iter().enumerate() {
            let body = BodyRef::Room(RoomHandle(k as u32));
            if room.active && targets.wants(body, room.groups) {
                let s = clipped(shape, gather.reach());
                rigid(room, s, false, gather.nearest_only(), scratch);
                gather.take(body, &scratch.hits);
            }
        }
        for (k, object) in self.objects.iter().enumerate() {
            let body = BodyRef::Object(ObjectHandle(k as u32));
            if object.active && targets.wants(body, object.groups) {
                let s = clipped(shape, gather.reach());
                rigid(object, s, true, gather.nearest_only(), scratch);
                gather.take(body, &scratch.hits);
            }
        }
        for (k, c) in self.characters.iter().enumerate() {
            let body = BodyRef::Character(CharacterHandle(k as u32));
            // Only groups need the character's lock to be decided.
            let by_groups = matches!(targets, QueryTargets::Meeting(_));
            if !by_groups && !targets.wants(body, CollisionGroups::ALL) {
                continue;
            }
            let mut c = c.lock().expect("no pass panicked");
            if !c.active || (by_groups && !targets.wants(body, c.groups)) {
                continue;
            }
            let s = clipped(shape, gather.reach());
            c.begin_query_frame();
            c.refit.set_logging(false);
            character(&mut c, s, gather.nearest_only(), scratch);
            c.refit.set_logging(true);
            gather.take(body, &scratch.hits);
        }
    }
}

/// `shape` (in the world) against character `c`, in a frame of its
/// current pose: its hits (in `scratch`).
fn character(
    c: &mut CharacterBody,
    shape: QueryShape,
    nearest_only: bool,
    scratch: &mut QueryScratch,
) {
    scratch.hits.clear();
    let mut side = side(c);
    let Some(root) = side.root_sphere() else {
        return;
    };
    scratch.counters.root_tests += 1;
    let Some(bound) = shape.bounding_sphere(&root) else {
        return;
    };
    set_shape_node(&mut scratch.node, bound);
    let mut pass = QueryPass {
        target: side,
        shape,
        node: &mut scratch.node,
        nearest_only,
    };
    let counters = run(&mut pass, &mut scratch.pass, &mut scratch.hits);
    scratch.counters.add_pass(&counters);
}

/// `shape` (in the world) against a rigid body: its hits (in `scratch`).
fn rigid(
    body: &RigidBody,
    shape: QueryShape,
    moves: bool,
    nearest_only: bool,
    scratch: &mut QueryScratch,
) {
    scratch.hits.clear();
    let tree = &body.tree.tree;
    if tree.is_empty() {
        return;
    }
    let local = if moves {
        let to_body = body.pose.inverse();
        match shape {
            QueryShape::Ray(r) => QueryShape::Ray(r.in_frame(&to_body)),
            QueryShape::Ball(b) => QueryShape::Ball(Sphere::new(to_body * b.center, b.radius)),
            QueryShape::Capsule(c) => QueryShape::Capsule(c.in_frame(&to_body)),
        }
    } else {
        shape
    };
    scratch.counters.root_tests += 1;
    let root = tree.nodes()[NodeId::ROOT.index()].sphere;
    let Some(bound) = local.bounding_sphere(&root) else {
        return;
    };
    set_shape_node(&mut scratch.node, bound);
    let mut pass = QueryPass {
        target: RigidTarget {
            tree,
            mesh: &body.mesh,
        },
        shape: local,
        node: &mut scratch.node,
        nearest_only,
    };
    let counters = run(&mut pass, &mut scratch.pass, &mut scratch.hits);
    scratch.counters.add_pass(&counters);
}

/// A hit of `ray` on `body` (distance along the world ray: an object's
/// frame keeps distances).
fn ray_hit(ray: &Ray, body: BodyRef, h: &ShapeHit) -> RayHit {
    RayHit {
        body,
        triangle: h.triangle,
        distance: h.distance as Real,
        point: ray.at(h.distance).cast::<Real>(),
        barycentric: h.barycentric.map(|x| x as Real),
    }
}
