//! Unwarp: map a planar slicer's G-code of the warped mesh back to the real part.
//!
//! Two streaming passes over the G-code bytes (memory is bounded by the longest line, the
//! height grid and the caller's output buffer, never by the file):
//! 1. [`crate::register`]: find where the slicer put the mesh and which lines are the warped
//!    region, the skirt, the anchor layer.
//! 2. This module: every object extrusion is split adaptively ([`segment`]) so that the mapped
//!    polyline stays within `tolerance` of the exact image of the straight move under T⁻¹ and
//!    no piece is longer than `max_segment`; every point is mapped with T⁻¹, gets the tool
//!    axis (layer normal), layer, feature and feed; E is made volume-correct ([`extrusion`]);
//!    travels are re-planned ([`travel`]); skirt and brim stay flat at their slicer height (or
//!    are dropped, `drop_skirt`); the anchor layer's extrusions are dropped; non-move lines
//!    inside the region pass through verbatim and in order; lines outside it (start and end
//!    G-code) pass through verbatim on 3-axis output, and on a machine output their moves are
//!    placed and converted at the machine's rest pose, or refused by name ([`outside`]).
//!
//! Coordinates: a G-code point g (slicer bed frame) → STL point g − (dx, dy, 0) → T-space
//! q = STL − (0, 0, stl_z_offset) → model p = T⁻¹(q) → output p + model_to_output, with
//! model_to_output = (dx, dy, z_offset), written as `; warpslice model_to_output = dx dy dz`.
//! With `place` = (px, py) the part goes there instead of where the slicer put it:
//! model_to_output = (px, py, z_offset), and the flat skirt and brim move with it by
//! (px − dx, py − dy) (for machines whose rotary axes pass through a fixed point, e.g. an A/B
//! table's origin). Lines outside the region (start and end G-code) are moved with the part only
//! on a machine output ([`outside`]); on 3-axis output they stay the slicer's.
//!
//! **Never below the bed.** A mapped object point with z < 0 (hundredths of a millimetre from
//! a slicer's first-layer offset on a steep warp) is clamped to z = 0 and the E of the
//! segments ending there is scaled by (h − depth)/h (h = job layer height); the report counts
//! such points. The clamp comes after every offset (`--z-offset` included, which may not be
//! deeper than half a layer). It takes only what a right placement gives: an object point
//! mapped below the part's bottom by more than the shape check's tolerance, or more than a
//! handful of them ([`shape`]: 0.02 mm normal to the layer, 5 points), refuse the unwarp as
//! `unwarp.shape-mismatch` (a wrong `--offset`, another job's G-code): the nozzle would plough
//! the bed.

use crate::emit::Emitter;
use crate::job::Job;
use crate::register::Registration;
use crate::toolpath::ToolPoint;

mod core;
mod driver;
mod error;
pub mod flow;
mod options;
pub mod outside;
mod report;
pub mod section;
pub mod segment;
pub mod shape;
pub mod travel;

pub use crate::emit::DEFAULT_TRAVEL_FEED;
pub use driver::Unwarper;
pub use error::{OutsideReason, UnwarpError, ERROR_CODES};
pub use flow::Flow;
pub use options::{UnwarpOptions, PARAMS};
pub use report::UnwarpReport;

/// Feed for the retractions warpslice adds, mm/min (40 mm/s).
pub const RETRACT_FEED: f64 = 2400.0;

/// The result of [`unwarp`].
#[derive(Clone, Debug)]
pub struct UnwarpOutput {
    /// The output G-code.
    pub gcode: Vec<u8>,
    /// What the unwarp did.
    pub report: UnwarpReport,
    /// Pass 1's result.
    pub registration: Registration,
    /// The toolpath (with `collect_toolpath`).
    pub toolpath: Vec<ToolPoint>,
}

/// One-shot unwarp of a whole G-code in memory.
pub fn unwarp(
    gcode: &[u8],
    job: &Job,
    opts: &UnwarpOptions,
    emitter: Box<dyn Emitter>,
) -> Result<UnwarpOutput, UnwarpError> {
    Unwarper::new(job, opts, emitter)?.run(gcode)
}
