//! What `bench --ccd` prints: each method's continuous step beside its
//! discrete frame, and the naive alternative of discrete sub-steps
//! (docs/ccd.md, "Cost").

use std::fmt;

use crate::bench::continuous::CcdBench;

/// A `bench --ccd` run as a text table.
pub struct CcdBenchTable<'a>(pub &'a CcdBench);

impl fmt::Display for CcdBenchTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let b = self.0;
        writeln!(
            f,
            "{}: {} frames ({} steps), de-duplication {}, median ms per frame on {} threads, \
             posing ({:.3} ms) included; continuous: the step ending at the frame",
            b.scenario,
            b.frames,
            b.frames.saturating_sub(1),
            if b.dedup { "on" } else { "off" },
            b.threads,
            b.pose_ms_per_frame,
        )?;
        writeln!(
            f,
            "{:<32}{:>12}{:>14}{:>8}{:>14}{:>14}{:>10}{:>9}{:>6}{:>14}{:>10}{:>10}",
            "",
            "discrete ms",
            "continuous ms",
            "ratio",
            "disc. ops",
            "cont. ops",
            "kernel",
            "pairs",
            "k",
            "k sub-st. ms",
            "vs cont.",
            "k bodies"
        )?;
        for m in &b.methods {
            let (k, ms, vs) = match (
                m.substeps,
                m.substeps_ms_per_frame,
                m.substeps_vs_continuous,
            ) {
                (Some(k), Some(ms), Some(vs)) => {
                    (k.to_string(), format!("{ms:.3}"), format!("{vs:.2}×"))
                }
                _ if b.steps_with_contacts == 0 => ("-".into(), "-".into(), "-".into()),
                _ => (format!(">{}", b.max_substeps), "-".into(), "-".into()),
            };
            let kb = match m.substeps_for_every_body_pair {
                Some(k) => k.to_string(),
                None if b.steps_with_contacts == 0 => "-".into(),
                None => format!(">{}", b.max_substeps),
            };
            writeln!(
                f,
                "{:<32}{:>12.3}{:>14.3}{:>7.2}×{:>14.0}{:>14.0}{:>10.1}{:>9.1}{:>6}{:>14}{:>10}{:>10}",
                m.method.name(),
                m.discrete_ms_per_frame,
                m.continuous_ms_per_frame,
                m.continuous_vs_discrete,
                m.discrete_operations_per_frame,
                m.continuous_operations_per_frame,
                m.kernel_tests_per_step,
                m.continuous_pairs_per_step,
                k,
                ms,
                vs,
                kb
            )?;
        }
        for m in b.methods.iter().filter(|m| !m.coverage.is_empty()) {
            let cells: Vec<String> = m
                .coverage
                .iter()
                .map(|c| format!("{}: {}", c.substeps, c.contacts))
                .collect();
            writeln!(
                f,
                "{:<32}contacts found at k sub-steps (of {}): {}",
                m.method.name(),
                b.reference_contacts,
                cells.join(", ")
            )?;
        }
        writeln!(
            f,
            "(kernel: triangle pairs the CCD kernel tested per step; pairs: continuous pairs per \
             step; k: fewest discrete sub-steps per step finding every contact of the \
             {}-sub-step reference on the {} steps with contacts ({} contacts), its ms per \
             such step; k bodies: fewest finding a contact of each of the {} touching body \
             pairs)",
            b.reference_substeps,
            b.steps_with_contacts,
            b.reference_contacts,
            b.reference_body_pairs
        )
    }
}
