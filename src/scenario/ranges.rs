//! The valid range of every number a scenario holds, checked when the file
//! is read (docs/robustness.md lists them). Bounds keep every quantity far
//! inside `f32` (squared distances of world coordinates stay below 1e13)
//! and every count small enough that what it sizes can be charged to the
//! run's memory budget ([`super::budget`]) before it is allocated.

/// Largest magnitude of a length or coordinate: gaps, translations,
/// waypoints, object sizes and positions, hinge pivots (1,000 km).
pub const MAX_METRES: f64 = 1.0e6;
/// Largest magnitude of an angle in degrees (yaws, hinge angles).
pub const MAX_DEGREES: f64 = 1.0e6;
/// Largest magnitude of a time in seconds (clip offsets, motion keys).
pub const MAX_SECONDS: f64 = 1.0e6;
/// Largest walking speed, metres per second.
pub const MAX_SPEED: f64 = 1.0e6;
/// Most frames a run plays (`frames`, `--frames`, or the clip's length at
/// `fps`): 9 h 15 min at 30 fps.
pub const MAX_FRAMES: u64 = 1_000_000;
/// Frame rates accepted, frames per second.
pub const MIN_FPS: f64 = 1.0e-3;
pub const MAX_FPS: f64 = 1.0e4;
/// Big-triangle thresholds accepted, metres (below a micrometre every
/// triangle is big and divisions stop at their level cap anyway).
pub const MIN_THRESHOLD: f64 = 1.0e-6;
pub const MAX_THRESHOLD: f64 = 1.0e6;
/// Most sub-steps per frame step of continuous detection's ground truth
/// (`ccd_substeps`; each costs an exact test per candidate pair).
pub const MAX_CCD_SUBSTEPS: i64 = 65_536;
/// Most characters in one scenario's `[[characters]]` list, a cap on what
/// is read before anything is charged; the memory budget, which charges
/// every instance (`super::budget`), bounds real scenarios long before it.
/// (Character pairs are found by a broad phase, not tested pairwise.)
pub const MAX_CHARACTERS: usize = 1 << 20;
/// Most moving objects in one scenario.
pub const MAX_OBJECTS: usize = 1024;
/// Most times one `[environment] subdivide` entry splits an object
/// (`4^16` triangles per triangle is already past every budget).
pub const MAX_SUBDIVIDE_TIMES: i64 = 16;
/// Largest scenario file read, in bytes.
pub const MAX_FILE_BYTES: u64 = 4 << 20;

/// A number as messages show it: the shortest form, in exponent notation
/// when very large or small (`-1e30`, not thirty-one digits).
pub fn show(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e6).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// An `f32` as [`show`] shows it, from its shortest decimal form (`1e-6`,
/// not `9.999999974752427e-7`).
pub fn show_f32(v: f32) -> String {
    show(v.to_string().parse().unwrap_or(f64::from(v)))
}

/// `Err` unless `v` is finite and `|v| <= max`: "must be finite UNIT within ±MAX, not V".
pub fn within(v: f64, max: f64, unit: &str) -> Result<f64, String> {
    if v.is_finite() && v.abs() <= max {
        Ok(v)
    } else {
        Err(format!(
            "must be finite {unit} within ±{}, not {}",
            show(max),
            show(v)
        ))
    }
}

/// `Err` unless `lo <= v <= hi`: "must be UNIT from LO to HI, not V".
pub fn between(v: f64, lo: f64, hi: f64, unit: &str) -> Result<f64, String> {
    if v.is_finite() && v >= lo && v <= hi {
        Ok(v)
    } else {
        Err(format!(
            "must be {unit} from {} to {}, not {}",
            show(lo),
            show(hi),
            show(v)
        ))
    }
}

/// `Err` unless `0 < v <= max`: "must be positive UNIT up to MAX, not V".
pub fn above_zero(v: f64, max: f64, unit: &str) -> Result<f64, String> {
    if v.is_finite() && v > 0.0 && v <= max {
        Ok(v)
    } else {
        Err(format!(
            "must be positive {unit} up to {}, not {}",
            show(max),
            show(v)
        ))
    }
}

/// `Err` unless `lo <= v <= hi`: "must be a whole number from LO to HI, not V".
pub fn whole(v: i64, lo: i64, hi: i64) -> Result<i64, String> {
    if (lo..=hi).contains(&v) {
        Ok(v)
    } else {
        Err(format!("must be a whole number from {lo} to {hi}, not {v}"))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_show_short() {
        assert_eq!(show(-1e30), "-1e30");
        assert_eq!(show(1e300), "1e300");
        assert_eq!(show(0.005), "0.005");
        assert_eq!(show(1e6), "1e6");
        assert_eq!(show(999_999.0), "999999");
        assert_eq!(show(1e-6), "1e-6");
        assert_eq!(show(f64::NAN), "NaN");
        assert_eq!(show(f64::NEG_INFINITY), "-inf");
        assert_eq!(show_f32(1e-6), "1e-6");
        assert_eq!(show_f32(3.2e30), "3.2e30");
    }

    #[test]
    fn ranges_accept_their_ends_and_refuse_past_them() {
        assert_eq!(within(-1e6, MAX_METRES, "metres"), Ok(-1e6));
        assert_eq!(
            within(-1e30, MAX_METRES, "metres").unwrap_err(),
            "must be finite metres within ±1e6, not -1e30"
        );
        assert!(within(f64::NAN, 1.0, "metres").is_err());
        assert_eq!(
            between(1e-3, MIN_FPS, MAX_FPS, "frames per second"),
            Ok(1e-3)
        );
        assert!(between(0.0, MIN_FPS, MAX_FPS, "fps").is_err());
        assert!(between(f64::INFINITY, MIN_FPS, MAX_FPS, "fps").is_err());
        assert_eq!(whole(1, 1, 3), Ok(1));
        assert_eq!(
            whole(0, 1, 3).unwrap_err(),
            "must be a whole number from 1 to 3, not 0"
        );
    }
}
