//! `cornertree rays`'s table: accuracy against the exact reference, cost
//! per frame beside both baselines, and what the queries did.

use std::fmt;

use crate::bench::rays::RaysReport;

/// The text report of a `rays` run.
pub struct RaysTable<'a>(pub &'a RaysReport);

impl fmt::Display for RaysTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let r = self.0;
        let verts: Vec<String> = r.character_vertices.iter().map(|v| v.to_string()).collect();
        writeln!(
            f,
            "{}: {} rays a frame ({:?}) against {} character(s) of {} vertices, {} frames, method {}",
            r.scenario,
            r.rays / r.frames.max(1) as u64,
            r.pattern,
            r.characters,
            verts.join(", "),
            r.frames,
            r.method
        )?;
        writeln!(
            f,
            "first hits equal to the exact reference: {} of {} rays ({} hit a character); parry3d's: {} of {}",
            r.hits_equal_reference, r.rays, r.hits, r.parry_hits_equal_reference, r.rays
        )?;
        if r.mismatches > 0 {
            let shared = r
                .mismatch_examples
                .iter()
                .filter(|m| m.at_shared_edge_or_vertex)
                .count();
            writeln!(
                f,
                "  {} rays differ ({} of the first {} at an edge or corner two triangles share)",
                r.mismatches,
                shared,
                r.mismatch_examples.len()
            )?;
        }
        writeln!(
            f,
            "ms per frame, one thread each (mean, min-max over frames):"
        )?;
        let row = |f: &mut fmt::Formatter<'_>,
                   name: &str,
                   s: &crate::bench::rays::Spread,
                   ratio: Option<f64>| {
            let ratio = ratio.map_or(String::new(), |x| format!("  ours {x:.1}x faster"));
            writeln!(
                f,
                "  {name:<44} {:>9.3}  ({:.3}-{:.3}){ratio}",
                s.mean, s.min, s.max
            )
        };
        row(
            f,
            "ours (poses handed over, refit on demand)",
            &r.ms_per_frame_spread,
            None,
        )?;
        row(
            f,
            "parry3d (skin all, update_vertices, cast)",
            &r.parry_ms_per_frame_spread,
            Some(r.speedup_vs_parry),
        )?;
        writeln!(
            f,
            "  {:<44} {:>9.3}  ours {:.1}x faster",
            "skin all, test every triangle of a box hit",
            r.skin_all_test_every_triangle_ms_per_frame,
            r.speedup_vs_skin_all_test_every_triangle
        )?;
        let c = &r.counters;
        let per = |x: u64| x as f64 / r.rays.max(1) as f64;
        writeln!(
            f,
            "per ray (ours): {:.2} root tests, {:.1} sphere tests, {:.1} triangle tests, {:.1} spheres refit, {:.1} vertices skinned",
            per(c.root_tests),
            per(c.sphere_tests),
            per(c.triangle_tests),
            per(c.refits),
            per(c.skinned_vertices)
        )?;
        writeln!(
            f,
            "rays missing every character's root sphere: {}, {} root tests ({:.2} per character), {} sphere tests below a root",
            r.rays_missing_every_root,
            r.root_tests_of_those,
            r.root_tests_of_those as f64
                / (r.rays_missing_every_root.max(1) * r.characters.max(1) as u64) as f64,
            r.sphere_tests_of_those
        )
    }
}
