//! Where the unwarped toolpath goes: an [`Emitter`] turns toolpath points into G-code lines.
//!
//! This module sits between the two that use it: [`crate::unwarp`] computes every point
//! (output frame, tool axis, E, feed, layer, feature) and hands it over in order, interleaved
//! with the lines that pass through verbatim; the [`Cartesian`] emitter here writes 3-axis
//! G-code (`G1 X Y Z E F`); a machine's emitter ([`crate::machine::emit`]) turns the same
//! points into its axes. Neither of them imports the other: the caller
//! ([`crate::pipeline`]) picks the emitter and hands it to the unwarp.
//!
//! Also here, for every emitter: [`EWriter`] (E words without drift), the machine report an
//! emitter may give ([`MachineReport`]) and the feed modes ([`FeedMode`]).

use std::sync::Arc;

use glam::DVec3;

use crate::error::Coded;
use crate::job::Job;
use crate::toolpath::ToolPoint;

mod cartesian;
pub mod clearance;
mod e_writer;
mod input_lines;
mod report;

pub use cartesian::Cartesian;
pub use e_writer::{EWriter, E_QUANTUM};
pub use input_lines::InputLines;
pub use report::{AxisReport, CollisionFinding, FeedMode, MachineReport, SwingPlace};

/// Feed for travels, lifts and descents warpslice adds when the slicer gave none, mm/min
/// (100 mm/s).
pub const DEFAULT_TRAVEL_FEED: f64 = 6000.0;

/// An emitter's error: whatever the emitter's own area reports (a machine's
/// [`crate::machine::MachineError`]), kept whole with its code and message. Use
/// [`EmitError::downcast_ref`] to get the original back.
#[derive(Clone, Debug)]
pub struct EmitError(Arc<dyn Coded + Send + Sync>);

impl EmitError {
    /// Wrap an emitter's error.
    pub fn new<E: Coded + Send + Sync + 'static>(e: E) -> EmitError {
        EmitError(Arc::new(e))
    }
    /// The original error, if it is an `E`.
    pub fn downcast_ref<E: Coded + 'static>(&self) -> Option<&E> {
        let e: &(dyn std::error::Error + 'static) = &*self.0;
        e.downcast_ref::<E>()
    }
}

impl PartialEq for EmitError {
    fn eq(&self, other: &EmitError) -> bool {
        self.0.code() == other.0.code() && self.0.to_string() == other.0.to_string()
    }
}

impl std::fmt::Display for EmitError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        self.0.fmt(f)
    }
}

impl std::error::Error for EmitError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        self.0.source()
    }
}

impl Coded for EmitError {
    fn code(&self) -> &'static str {
        self.0.code()
    }
}

/// Turns toolpath points into G-code.
pub trait Emitter: Send {
    /// Before anything is written: refuse a job this emitter would print wrong although every
    /// point is reachable. `model_to_output` moves the job's model frame to the output.
    fn check_job(&mut self, _job: &Job, _model_to_output: DVec3) -> Result<(), EmitError> {
        Ok(())
    }
    /// The output holds `n` lines before whatever the next call writes (the caller counts every
    /// line it writes, the emitter's included): an emitter that names output lines in its
    /// errors (1-based, as written) counts from here.
    fn lines_written(&mut self, _n: u64) {}
    /// Header lines after warpslice's own (`; warpslice machine = …`).
    fn header(&mut self, _out: &mut Vec<u8>) {}
    /// The printed region starts; the head is at `p` with tool axis `n` (output frame).
    fn begin_region(&mut self, _out: &mut Vec<u8>, _p: DVec3, _n: DVec3) -> Result<(), EmitError> {
        Ok(())
    }
    /// The printed region ends (after the driver's lift): leave the machine ready for the
    /// 3-axis G-code that follows.
    fn end_region(&mut self, _out: &mut Vec<u8>) -> Result<(), EmitError> {
        Ok(())
    }
    /// The head is somewhere the unwarp does not know (after `G28 X Y`, `G27`, a tool change:
    /// `command` names it): move it straight up (or down) to tip height `z`, output frame, at
    /// feed `f`, wherever it is; the next point is a travel at that height. The default writes
    /// 3-axis `G0 Z<z> F<f>`; an emitter that cannot move from an unknown pose refuses.
    fn lift_from_unknown(
        &mut self,
        out: &mut Vec<u8>,
        z: f64,
        f: f64,
        command: &str,
    ) -> Result<(), EmitError> {
        let _ = command;
        out.extend_from_slice(b"G0 Z");
        crate::gcode::write::push_mm(out, z);
        out.extend_from_slice(b" F");
        crate::gcode::write::push_feed(out, f);
        out.extend_from_slice(b" ; warpslice: the head is where the firmware put it: up first\n");
        Ok(())
    }
    /// Whether this emitter converts the motion lines outside the printed region (start and end
    /// G-code, in the slicer's frame) instead of passing them through verbatim; `moved`: the
    /// output is moved from the slicer's frame (`--place`, `--z-offset`). Asked once, before
    /// the first line; when `true` the unwarp hands those moves over as [`Emitter::point`]s
    /// with the rest tool axis +Z (never collected in the toolpath) or as
    /// [`Emitter::outside_partial`], and the emitter keeps its pose across
    /// [`Emitter::begin_region`]. The 3-axis emitter (the default) never converts: its output
    /// is the slicer's own printer.
    fn converts_outside(&mut self, _moved: bool) -> bool {
        false
    }
    /// Outside the region, the head moved where the file does not say (`G28`, `G27`, a probe,
    /// a tool change): its pose is unknown until a move gives X, Y and Z.
    fn outside_pose_lost(&mut self) {}
    /// A line written verbatim may have set the firmware's modal feed: write F on the next move.
    fn forget_feed(&mut self) {}
    /// Outside the region, with the pose unknown, a move gives only some coordinates: `known`
    /// are the output-frame X Y Z known (the others are wherever homing left them), `e` the
    /// filament (delta, mm) and the file's E mode, `f` the feed (mm/min). `Ok(true)`: written
    /// exactly (the axes it changes depend on the known coordinates only); `Ok(false)`: it
    /// cannot be written without the unknown ones (nothing written; the caller keeps it for the
    /// next move that gives them). The default writes nothing (`Ok(false)`).
    fn outside_partial(
        &mut self,
        _out: &mut Vec<u8>,
        _known: [Option<f64>; 3],
        _e: Option<(f64, bool)>,
        _f: f64,
    ) -> Result<bool, EmitError> {
        Ok(false)
    }
    /// A line that passes through verbatim (without its terminator).
    fn raw(&mut self, out: &mut Vec<u8>, raw: &[u8]) {
        out.extend_from_slice(raw);
        out.push(b'\n');
    }
    /// Move to `tp` from the previous point: an extrusion (`!tp.travel`), a travel
    /// (`tp.travel`, `tp.e == 0`) or, when `tp.travel` and `tp.e != 0`, a retraction or
    /// unretraction in place. `relative_e`: the file's E mode (M83) in force. A machine that
    /// cannot reach the point returns the error; the driver stops with it.
    fn point(
        &mut self,
        out: &mut Vec<u8>,
        tp: &ToolPoint,
        relative_e: bool,
    ) -> Result<(), EmitError>;
    /// [`Emitter::point`] with the material printed so far, for the lifts the emitter makes on
    /// its own (a machine's rotate-around, a swing lift: [`clearance`]). The default ignores it.
    fn point_over(
        &mut self,
        out: &mut Vec<u8>,
        tp: &ToolPoint,
        relative_e: bool,
        printed: &dyn clearance::Printed,
    ) -> Result<(), EmitError> {
        let _ = printed;
        self.point(out, tp, relative_e)
    }
    /// The head's clearance profile ([`clearance::HeadProfile`]), for travels that clear the
    /// whole head; `None` (the default, 3-axis output): travels are planned for the tip only.
    fn head_profile(&self) -> Option<clearance::HeadProfile> {
        None
    }
    /// `G92 E v` passed through: the firmware's E is now v.
    fn reset_e(&mut self, v: f64);
    /// The firmware's E after the last point (absolute mode).
    fn current_e(&self) -> f64;
    /// End of the output (flush anything held back).
    fn finish(&mut self, _out: &mut Vec<u8>) {}
    /// The machine's measurements (machine emitters only).
    fn machine_report(&self) -> Option<MachineReport> {
        None
    }
    /// The input line of output line `line` (1-based), where the emitter records them
    /// ([`InputLines`]: the machine emitter with the collision check); `None` otherwise.
    fn input_line_of(&self, _line: u64) -> Option<u64> {
        None
    }
    /// No later [`Emitter::input_line_of`] asks for an output line before `line`.
    fn forget_input_lines_before(&mut self, _line: u64) {}
}
