//! `cornertree run`: per-frame counters of each method and the summary table
//! in the shape of the paper's Tables 2–3 (maximum and mean per frame).

use std::fmt;

use serde::Serialize;

use crate::pipeline::Method;
use crate::pipeline::driver::FrameCounters;

/// One frame of one method, as written to the JSON report.
#[derive(Clone, Debug, Serialize)]
pub struct FrameRecord {
    pub frame: usize,
    pub sphere_sphere: u64,
    pub tri_tri: u64,
    pub plane_sphere: u64,
    pub operations: u64,
    pub refits: u64,
    /// Total of the four stages below.
    pub time_ms: f64,
    pub skinning_ms: f64,
    pub refit_ms: f64,
    pub traversal_ms: f64,
    pub narrow_ms: f64,
    /// Colliding `[avatar triangle, environment triangle]` pairs.
    pub pairs: Vec<[u32; 2]>,
}

impl FrameRecord {
    pub fn new(frame: usize, c: &FrameCounters, pairs: &[(u32, u32)]) -> Self {
        Self {
            frame,
            sphere_sphere: c.sphere_sphere,
            tri_tri: c.tri_tri,
            plane_sphere: c.plane_sphere,
            operations: c.operations(),
            refits: c.refits,
            time_ms: c.time.total_ms(),
            skinning_ms: c.time.skinning_ms,
            refit_ms: c.time.refit_ms,
            traversal_ms: c.time.traversal_ms,
            narrow_ms: c.time.narrow_ms,
            pairs: pairs.iter().map(|&(a, b)| [a, b]).collect(),
        }
    }
}

/// Everything one method did over a run.
#[derive(Clone, Debug, Serialize)]
pub struct MethodRun {
    pub scenario: String,
    pub method: Method,
    pub dedup: bool,
    /// Bytes of the avatar's and the environment's sphere hierarchies.
    pub hierarchy_bytes: usize,
    pub frames: Vec<FrameRecord>,
}

/// Maximum and mean of one counter.
#[derive(Clone, Copy, Debug, Default, Serialize)]
pub struct Stat {
    pub max: f64,
    pub mean: f64,
}

fn stat(values: impl Iterator<Item = f64>) -> Stat {
    let (mut max, mut sum, mut n) = (0.0f64, 0.0, 0usize);
    for v in values {
        max = max.max(v);
        sum += v;
        n += 1;
    }
    Stat {
        max,
        mean: if n == 0 { 0.0 } else { sum / n as f64 },
    }
}

/// The summary row of one method.
#[derive(Clone, Debug, Serialize)]
pub struct Summary {
    pub method: Method,
    pub frames: usize,
    pub hierarchy_bytes: usize,
    pub sphere_sphere: Stat,
    pub tri_tri: Stat,
    pub plane_sphere: Stat,
    pub operations: Stat,
    pub refits: Stat,
    pub time_ms: Stat,
    /// Frames with at least one colliding pair.
    pub frames_with_contact: usize,
}

impl MethodRun {
    pub fn summary(&self) -> Summary {
        let f = &self.frames;
        Summary {
            method: self.method,
            frames: f.len(),
            hierarchy_bytes: self.hierarchy_bytes,
            sphere_sphere: stat(f.iter().map(|x| x.sphere_sphere as f64)),
            tri_tri: stat(f.iter().map(|x| x.tri_tri as f64)),
            plane_sphere: stat(f.iter().map(|x| x.plane_sphere as f64)),
            operations: stat(f.iter().map(|x| x.operations as f64)),
            refits: stat(f.iter().map(|x| x.refits as f64)),
            time_ms: stat(f.iter().map(|x| x.time_ms)),
            frames_with_contact: f.iter().filter(|x| !x.pairs.is_empty()).count(),
        }
    }
}

/// The summary table of a run: one column per method, rows as in Tables 2–3.
pub struct SummaryTable<'a>(pub &'a [Summary]);

impl fmt::Display for SummaryTable<'_> {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = self.0;
        write!(f, "{:<28}", "")?;
        for m in s {
            write!(f, "{:>26}", m.method.name())?;
        }
        writeln!(f)?;
        let row = |f: &mut fmt::Formatter<'_>,
                   label: &str,
                   get: &dyn Fn(&Summary) -> String|
         -> fmt::Result {
            write!(f, "{label:<28}")?;
            for m in s {
                write!(f, "{:>26}", get(m))?;
            }
            writeln!(f)
        };
        let mm = |x: Stat| format!("{:.0} / {:.0}", x.max, x.mean);
        row(f, "Data (hierarchies)", &|m| {
            format!("{:.2} MiB", m.hierarchy_bytes as f64 / 1048576.0)
        })?;
        row(f, "Sph-Sph tests (max / mean)", &|m| mm(m.sphere_sphere))?;
        row(f, "Tri-Tri tests (max / mean)", &|m| mm(m.tri_tri))?;
        row(f, "Pla-Sph tests (max / mean)", &|m| mm(m.plane_sphere))?;
        row(f, "Operations (max / mean)", &|m| mm(m.operations))?;
        row(f, "Refits (max / mean)", &|m| mm(m.refits))?;
        row(f, "Frame ms (max / mean)", &|m| {
            format!("{:.3} / {:.3}", m.time_ms.max, m.time_ms.mean)
        })?;
        row(f, "Frames with contact", &|m| {
            format!("{} of {}", m.frames_with_contact, m.frames)
        })?;
        Ok(())
    }
}
