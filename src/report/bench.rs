//! What `bench` and `scaling` print: a measurement's table, and the markdown
//! tables of the scaling studies (docs/performance.md).

use std::fmt;

use crate::bench::Bench;
use cornertree::pipeline::Method;

/// One measurement as a text table: the baseline, then every method.
pub struct BenchTable<'a>(pub &'a Bench);

impl fmt::Display for BenchTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let b = self.0;
        let bodies = if b.characters == 1 && b.objects == 0 {
            String::new()
        } else {
            format!(
                "{} characters, {} moving objects, ",
                b.characters, b.objects
            )
        };
        writeln!(
            f,
            "{}: {bodies}{} frames, de-duplication {}, median ms per frame on {} threads and on one, \
             parry3d likewise; every row includes posing ({:.3} ms; on one thread {:.3} ms); \
             parry skins all {} vertices ({:.3} ms on one thread), each method only those it tests",
            b.scenario,
            b.frames,
            if b.dedup { "on" } else { "off" },
            b.threads,
            b.pose_ms_per_frame,
            b.pose_ms_per_frame_one_thread,
            b.vertices,
            b.skinning_all_ms_per_frame,
        )?;
        let t = b.threads;
        writeln!(
            f,
            "{:<32}{:>11}{:>12}{:>12}{:>12}{:>10}{:>10}{:>10}{:>10}{:>15}{:>11}{:>10}{:>10}",
            "",
            format!("{t} thr ms"),
            format!("vs parry {t}"),
            "1 thr ms",
            "vs parry 1",
            "parallel",
            "work ms",
            "span ms",
            "work/span",
            "operations",
            "skinned",
            "pairs",
            "≠ parry"
        )?;
        writeln!(
            f,
            "{:<32}{:>11.3}{:>12}{:>12.3}{:>12}{:>9.2}×{:>10}{:>10}{:>10}{:>15}{:>11}{:>10}{:>10}",
            "parry3d baseline",
            b.parry_ms_per_frame_same_threads,
            "1.00×",
            b.parry_ms_per_frame,
            "1.00×",
            ratio(b.parry_ms_per_frame, b.parry_ms_per_frame_same_threads),
            "-",
            "-",
            "-",
            "-",
            b.vertices,
            "-",
            "-"
        )?;
        for m in &b.methods {
            writeln!(
                f,
                "{:<32}{:>11.3}{:>11.2}×{:>12.3}{:>11.2}×{:>9.2}×{:>10.3}{:>10.3}{:>10.1}{:>15.0}{:>11.0}{:>10.0}{:>10}",
                m.method.name(),
                m.ms_per_frame,
                m.speedup_vs_parry_same_threads,
                m.ms_per_frame_one_thread,
                m.speedup_vs_parry_one_thread,
                m.parallel_speedup,
                m.work_ms,
                m.span_ms,
                m.available_parallelism,
                m.operations_per_frame,
                m.skinned_vertices_per_frame,
                m.pairs_per_frame,
                m.frames_with_other_pairs_than_parry
            )?;
        }
        writeln!(
            f,
            "(vs parry {t}: parry3d on the same {t} threads over the method on {t}; vs parry 1: both on one \
             thread; work/span: the one-thread frame's work over its longest chain of passes that must \
             run one after another, the threads it could keep busy; ≠ parry: frames whose pairs differ \
             from parry3d's f32 test, which reports some pairs millimetres apart; see docs/performance.md)"
        )
    }
}

/// `a / b`, 0 when `b` is not positive.
fn ratio(a: f64, b: f64) -> f64 {
    if b > 0.0 { a / b } else { 0.0 }
}

/// A column of a scaling table: its heading and its value for a row.
pub type Column = (&'static str, fn(&Bench) -> String);

/// Markdown rows of a scaling study: the first `key` columns, the baseline
/// on the methods' threads, then each method's median ms per frame with its
/// speed-up over parry3d on the same threads.
pub fn scaling_table(rows: &[Bench], methods: &[Method], key: &[Column]) -> String {
    let mut out = String::from("|");
    for (name, _) in key {
        out += &format!(" {name} |");
    }
    out += " parry3d |";
    for m in methods {
        out += &format!(" {} |", m.name());
    }
    out += "\n|";
    out += &"---:|".repeat(key.len() + 1 + methods.len());
    out += "\n";
    for b in rows {
        out += "|";
        for (_, value) in key {
            out += &format!(" {} |", value(b));
        }
        out += &format!(" {:.3} |", b.parry_ms_per_frame_same_threads);
        for m in &b.methods {
            // Two significant digits below 1×, one decimal above.
            let x = m.speedup_vs_parry_same_threads;
            let digits = if x < 1.0 { 2 } else { 1 };
            out += &format!(" {:.3} ({:.*}×) |", m.ms_per_frame, digits, x);
        }
        out += "\n";
    }
    out
}
