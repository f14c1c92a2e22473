//! The CCD kernels allocate nothing (their search runs on a fixed stack of
//! boxes), so the swept hierarchies can call them per frame: counted with a
//! global allocator that counts, over contacts, near misses, sliding and
//! piercing pairs, and a search stopped by its box budget. The kernels run
//! on the test's thread, so that thread's count is the one read: the
//! process-wide count also took in the test harness's allocations at the
//! test's start (4 once in a CI run).

use cornertree::geometry::ccd_edge_edge::edge_edge;
use cornertree::geometry::ccd_root_finder::CcdParams;
use cornertree::geometry::ccd_triangles::{MovingTriangle, triangles};
use cornertree::geometry::ccd_vertex_face::vertex_face;

#[path = "common/counting_alloc.rs"]
mod counting_alloc;
use counting_alloc::on_this_thread;

fn shifted(t: [[f64; 3]; 3], d: [f64; 3]) -> MovingTriangle<f64> {
    MovingTriangle {
        start: t,
        end: t.map(|p| [p[0] + d[0], p[1] + d[1], p[2] + d[2]]),
    }
}

#[test]
fn ccd_kernels_allocate_nothing() {
    let floor = shifted(
        [[-1.0, -1.0, 0.0], [2.0, -1.0, 0.0], [-1.0, 2.0, 0.0]],
        [0.0; 3],
    );
    let small = [[0.2, 0.2, 0.5], [0.6, 0.2, 1.0], [0.2, 0.6, 1.0]];
    let pairs = [
        (shifted(small, [0.0, 0.0, -1.0]), floor), // falls through
        (shifted(small, [0.0, 0.0, -0.5 + 1e-5]), floor), // stops just above
        (shifted(small, [3.0, 0.0, 0.0]), floor),  // passes by
        (
            shifted(
                [[0.0, 0.0, 0.0], [0.5, 0.0, 0.0], [0.0, 0.5, 0.0]],
                [0.3, 0.0, 0.0],
            ),
            floor,
        ), // slides on it
        (
            shifted(
                [[0.0, 0.0, -1.0], [0.0, 0.1, 1.0], [0.1, 0.0, 1.0]],
                [0.1, 0.1, 0.0],
            ),
            floor,
        ), // pierces it all along
    ];
    let tight = CcdParams {
        max_boxes: 3,
        ..CcdParams::default()
    };
    let params = [CcdParams::default(), tight];
    let edges = (
        [
            [-1.0, 0.0, 1.0],
            [1.0, 0.0, 1.0],
            [0.0, -1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        [
            [-1.0, 0.0, -1.0],
            [1.0, 0.0, -1.0],
            [0.0, -1.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
    );
    let point = (
        [
            [0.25, 0.25, 1.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
        [
            [0.25, 0.25, -1.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ],
    );
    let before = on_this_thread();
    let mut found = 0;
    for p in &params {
        for (a, b) in &pairs {
            found += triangles(a, b, p).is_some() as usize;
        }
        found += edge_edge(&edges.0, &edges.1, p).is_some() as usize;
        found += vertex_face(&point.0, &point.1, p).is_some() as usize;
    }
    let after = on_this_thread();
    assert_eq!(after - before, 0, "the CCD kernels allocated");
    // Falling, sliding, piercing, both elementary crossings; with either budget.
    assert_eq!(found, 2 * 5, "{found}");
}
