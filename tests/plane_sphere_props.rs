//! Algorithm 1 never misses: whenever the ball reaches the (non-degenerate)
//! triangle, it reaches the triangle's plane.

use cornertree::geometry::closest_point::point_triangle_distance;
use cornertree::geometry::plane_sphere::{sphere_meets_plane, sphere_triangle_distance};
use cornertree::geometry::{Point, Sphere, Triangle};
use proptest::prelude::*;

fn point(range: f32) -> impl Strategy<Value = Point> {
    (-range..=range, -range..=range, -range..=range).prop_map(|(x, y, z)| Point::new(x, y, z))
}

fn triangle() -> impl Strategy<Value = Triangle> {
    (point(2.0), point(2.0), point(2.0)).prop_map(|(a, b, c)| Triangle::new(a, b, c))
}

/// Non-zero area, decided as Algorithm 1 decides it (in `f64`).
fn has_plane(t: &Triangle) -> bool {
    let [a, b, c] = t.vertices().map(|p| p.coords.cast::<f64>());
    (b - a).cross(&(c - a)).norm() > 0.0
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(4000))]

    /// Random balls: the implication holds whenever its premise does.
    #[test]
    fn ball_meeting_triangle_meets_plane(t in triangle(), c in point(3.0), r in 0.0f32..=2.5) {
        let s = Sphere::new(c, r);
        if has_plane(&t) && sphere_triangle_distance(&s, &t) <= 0.0 {
            prop_assert!(sphere_meets_plane(&s, &t), "missed {s:?} / {t:?}");
        }
    }

    /// Balls grown to just reach the triangle (radius = distance, rounded up
    /// to `f32` plus a relative 2⁻²⁰), so the premise always holds and the
    /// contact is nearly tangent.
    #[test]
    fn ball_just_reaching_triangle_meets_plane(t in triangle(), c in point(3.0), k in 1u32..=64) {
        prop_assume!(has_plane(&t));
        let d = point_triangle_distance(&c.cast::<f64>(), &t);
        let r = (d * (1.0 + k as f64 / (1u64 << 20) as f64)) as f32;
        let s = Sphere::new(c, r);
        prop_assert!(sphere_triangle_distance(&s, &t) <= 0.0);
        prop_assert!(sphere_meets_plane(&s, &t), "missed {s:?} / {t:?}");
    }
}
