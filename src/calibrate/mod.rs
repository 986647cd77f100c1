//! Calibration of 5-axis A/B rotary tables (seed 004, Open5x and descendants): from measured
//! axis lines to a calibrated `open5x-ab` machine, the raw probe formulas, the test prints that
//! check a calibration, and a simulation of what calibration errors do to a print.
//!
//! ## Model (seed 004 §4.1)
//! Each rotary axis is a line: a point and a unit direction, `(A_pos, A_dir)` (≈ +X) and
//! `(B_pos, B_dir)` (≈ +Z, given at A = 0), measured in the printer's current (uncalibrated)
//! frame in mm. The machine origin is the point of the B line closest to the A line (§4.1.1,
//! §5.4.2); the kinematics of [`crate::machine::abtable`] use the same model, so a calibrated
//! machine is a [`crate::machine::MachineSpec`] of kind `ab-table` with the measured lines.
//!
//! ## Files (one concept each)
//! - [`measurements`]: the `ab_values.out` file of listing 4.1 → [`Series`] (errors name the line).
//! - [`origin`]: Eq. 5.7 (biases, the A-axis z-rotation correction α_{A,z}, closest approach),
//!   statistics over repeated series (Table 6.2), the calibrated machine JSON.
//! - [`probes`]: Eqs. 5.2–5.6 and §5.1.6–5.1.8 (raw probe values → axis components).
//! - [`patterns`]: the test prints of §6.2 (G-code through the machine's inverse kinematics) and
//!   their base objects (STL).
//! - [`simulate`]: a true and a believed machine; where the tip really lands (Fig. 3.1, 6.12,
//!   6.16), as numbers and SVG ([`svg`]).
//!
//! ## Units
//! mm and degrees at every interface, radians inside. No filesystem access: callers read files
//! and pass text (so everything works in wasm).

// `!(x >= tol)` on purpose: a NaN must fail the check.
#![allow(clippy::neg_cmp_op_on_partial_ord)]

use core::fmt;

pub mod measurements;
pub mod origin;
pub mod patterns;
pub mod probes;
pub mod simulate;
pub mod svg;

pub use measurements::{parse_measurements, Series};
pub use origin::{calibrate_origin, machine_origin, OriginOptions, OriginReport};

use crate::machine::MachineError;

/// Below this |A_dir × B_dir| (sine of the angle between the axis lines) the lines are taken
/// to be parallel and the origin (closest approach) is refused.
pub const PARALLEL_SINE: f64 = 1e-6;

/// Errors of the calibration area. Messages say what to fix.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum CalibError {
    /// A line of the measurement file cannot be read (1-based line number).
    BadLine {
        /// 1-based line number in the measurement file.
        line: usize,
        /// The offending line as read (untrimmed).
        text: String,
        /// What is wrong with it (unknown component, missing or malformed value).
        message: String,
    },
    /// A measurement series lacks a component (the series starts at `line`).
    IncompleteSeries {
        /// 1-based line number of the incomplete series' first component line.
        line: usize,
        /// The component key the series lacks (`a_axis`, `a_axis_dir`, `b_axis` or `b_axis_dir`).
        missing: &'static str,
    },
    /// The file holds no measurement series.
    NoSeries,
    /// The A and B lines are (nearly) parallel: no closest approach.
    ParallelAxes {
        /// |A_dir × B_dir| / (|A_dir| |B_dir|): the sine of the angle between the axis directions.
        sine: f64,
    },
    /// A numeric input is unusable (`what` names it).
    BadInput {
        /// Which input is unusable (e.g. `a_axis_dir`, `print options`, `A scaling`).
        what: String,
        /// Why it is unusable and what is expected instead.
        message: String,
    },
    /// The machine cannot be used (wrong kind, bad JSON, unreachable test print…).
    Machine(MachineError),
}

impl fmt::Display for CalibError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            CalibError::BadLine { line, text, message } => write!(
                f,
                "measurement file line {line}: {message} (line is '{text}'); expected lines like 'a_axis {{x,y,z}}', 'a_z_in_y v', 'a_axis_dir {{x,y,z}}', 'b_axis {{x,y,z}}', 'b_axis_dir {{x,y,z}}'"
            ),
            CalibError::IncompleteSeries { line, missing } => write!(
                f,
                "measurement file: the series starting at line {line} has no '{missing}' line; re-run the measurement or delete the incomplete series"
            ),
            CalibError::NoSeries => write!(
                f,
                "the measurement file holds no measurement series (no 'a_axis', 'a_axis_dir', 'b_axis', 'b_axis_dir' lines); run the Calibration AB macro first"
            ),
            CalibError::ParallelAxes { sine } => write!(
                f,
                "the A and B axis directions are (nearly) parallel (sin of the angle between them = {sine:e}); the machine origin (their closest approach) is undefined: check a_axis_dir and b_axis_dir"
            ),
            CalibError::BadInput { what, message } => write!(f, "{what}: {message}"),
            CalibError::Machine(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for CalibError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            CalibError::Machine(e) => Some(e),
            _ => None,
        }
    }
}

crate::error_codes!(CalibError, ERROR_CODES, "calibrate" {
    BadLine => "calibrate.bad-line", "a measurement file line that cannot be read";
    IncompleteSeries => "calibrate.incomplete-series", "a measurement series lacks a component";
    NoSeries => "calibrate.no-series", "the measurement file holds no series";
    ParallelAxes => "calibrate.parallel-axes", "the A and B axes are parallel: no origin";
    BadInput => "calibrate.bad-input", "a numeric input is unusable";
} wraps { Machine });

impl From<MachineError> for CalibError {
    fn from(e: MachineError) -> Self {
        CalibError::Machine(e)
    }
}

/// `Err(BadInput)` unless every value is finite.
pub(crate) fn finite(what: &str, values: &[f64]) -> Result<(), CalibError> {
    if values.iter().all(|v| v.is_finite()) {
        Ok(())
    } else {
        Err(CalibError::BadInput {
            what: what.to_string(),
            message: format!("values {values:?} must all be finite numbers"),
        })
    }
}
