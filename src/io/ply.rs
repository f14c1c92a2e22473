//! Writing triangle meshes as PLY (ASCII), for `run --dump-frame`.
//!
//! ASCII with shortest round-trip float formatting, so a reader gets the very
//! `f32` positions we tested; faces keep our triangle order, so face `i` is
//! triangle `i` everywhere in reports. A dozen lines of format; the reading
//! side is checked with an independent PLY parser in the tests.

use std::io::{BufWriter, Write};
use std::path::Path;

use cornertree::geometry::Point;

/// Writes `positions` and `indices` to `path` as an ASCII PLY file.
pub fn write_ply(path: &Path, positions: &[Point], indices: &[[u32; 3]]) -> std::io::Result<()> {
    let mut w = BufWriter::new(std::fs::File::create(path)?);
    writeln!(w, "ply")?;
    writeln!(w, "format ascii 1.0")?;
    writeln!(w, "comment written by cornertree; face i is triangle i")?;
    writeln!(w, "element vertex {}", positions.len())?;
    writeln!(w, "property float x")?;
    writeln!(w, "property float y")?;
    writeln!(w, "property float z")?;
    writeln!(w, "element face {}", indices.len())?;
    writeln!(w, "property list uchar uint vertex_indices")?;
    writeln!(w, "end_header")?;
    for p in positions {
        writeln!(w, "{} {} {}", p.x, p.y, p.z)?;
    }
    for [a, b, c] in indices {
        writeln!(w, "3 {a} {b} {c}")?;
    }
    w.flush()
}
