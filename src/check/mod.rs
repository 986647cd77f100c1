//! `warpslice check`: read any 4/5-axis G-code for a machine — warpslice's own, or one written
//! by FullControl, Slicer4RTN, RotBot or by hand — and report what would go wrong on the
//! machine: axes outside their travel (reach), head parts into the printed material or the bed
//! (collisions), axes over their largest feed (speed), with the 1-based file line of each; and
//! the estimated print time, the filament, the tilt histogram.
//!
//! It is the emitter's own checks, not a copy: the G-code is read by the collision walker's
//! [`crate::collision::AxisReader`], each move goes through [`crate::collision::walk_line`]
//! (the on-by-default collision check), [`crate::machine::reach::Reach`] (the emitter's travel
//! check) and [`crate::machine::speed::AxisSpeeds`] (the emitter's time estimate).
//!
//! - [`stream`]: [`CheckStream`], push bytes then finish (the browser feeds 4 MB slices);
//! - [`report`]: [`CheckReport`], [`Finding`];
//! - [`options`]: [`CheckOptions`] and their [`options::PARAMS`] (the CLI's flags);
//! - [`error`]: [`CheckError`], a file that cannot be read as this machine's G-code.
//!
//! Frames and units: axes raw as written (mm, degrees), minus `G92` offsets; tip and tool axis
//! in the part (output) frame from [`crate::machine::Machine::forward`].

pub mod error;
pub mod options;
pub mod report;
pub mod stream;

pub use error::{CheckError, ERROR_CODES};
pub use options::CheckOptions;
pub use report::{CheckReport, Finding, FindingCounts, FindingKind};
pub use stream::{CheckStream, PathPoint};

use crate::machine::MachineSpec;

/// Check a whole G-code (see the module documentation).
pub fn check(
    gcode: &[u8],
    spec: &MachineSpec,
    options: &CheckOptions,
) -> Result<CheckReport, CheckError> {
    let mut s = CheckStream::new(spec, options)?;
    s.push(gcode)?;
    Ok(s.finish()?.0)
}
