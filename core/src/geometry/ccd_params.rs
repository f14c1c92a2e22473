//! The settings of a CCD query ([`super::ccd_root_finder`]) and their
//! defaults, apart from the search so that the rounding bounds
//! ([`super::ccd_error_bounds`]) can read them without depending on it.

/// Default tolerance δ: a positive answer brings the primitives within δ of
/// each other in every coordinate (for inputs of unit scale).
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// Default budget of boxes per query.
pub const DEFAULT_MAX_BOXES: u32 = 1 << 16;

/// Default time tolerance τ (fraction of the step).
pub const DEFAULT_TIME_TOLERANCE: f64 = 1e-6;

/// Settings of a CCD query.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CcdParams {
    /// δ (length): a positive answer certifies that the primitives come
    /// within δ of each other in every coordinate (so within `√3 δ`), at
    /// the true inputs. Raised to `16 ε` where that is larger
    /// (`ε ≈ 1.4e-14` times the query's largest coordinate).
    pub tolerance: f64,
    /// How far each input coordinate may be from the true one, relative to
    /// its magnitude: 0 for positions taken as they are (`f32` or `f64`
    /// geometry), [`RATIONAL_ROUNDING`](super::ccd_error_bounds::RATIONAL_ROUNDING) for exact rationals rounded to
    /// `f64`.
    pub input_error: f64,
    /// Boxes examined at most; past it the answer is "contact", its
    /// witness certified only to [`Impact::within`](super::ccd_root_finder::Impact::within).
    pub max_boxes: u32,
    /// τ: once a contact is accepted, boxes starting less than τ before it
    /// are not examined, so the time of impact may be up to τ below the
    /// earliest accepted box (it stays a lower bound of the first contact).
    pub time_tolerance: f64,
}

impl Default for CcdParams {
    fn default() -> Self {
        Self {
            tolerance: DEFAULT_TOLERANCE,
            input_error: 0.0,
            max_boxes: DEFAULT_MAX_BOXES,
            time_tolerance: DEFAULT_TIME_TOLERANCE,
        }
    }
}
