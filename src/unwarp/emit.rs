//! Where unwarp's toolpath goes: an [`Emitter`] turns toolpath points into G-code lines.
//!
//! The unwarp driver computes every point (output frame, tool axis, E, feed, layer, feature)
//! and hands it over in order, interleaved with the lines that pass through verbatim. The
//! [`Cartesian`] emitter writes 3-axis G-code (`G1 X Y Z E F`); a machine's emitter (see
//! [`crate::machine`]) turns the same points into its axes.

use glam::DVec3;

use crate::gcode::write::{push_e, push_feed, push_mm};
use crate::machine::{MachineError, MachineReport};
use crate::toolpath::ToolPoint;

use super::EWriter;

/// Turns toolpath points into G-code.
pub trait Emitter: Send {
    /// Header lines after warpslice's own (`; warpslice machine = …`).
    fn header(&mut self, _out: &mut Vec<u8>) {}
    /// The printed region starts; the head is at `p` with tool axis `n` (output frame).
    fn begin_region(
        &mut self,
        _out: &mut Vec<u8>,
        _p: DVec3,
        _n: DVec3,
    ) -> Result<(), MachineError> {
        Ok(())
    }
    /// The printed region ends (after the driver's lift): leave the machine ready for the
    /// 3-axis G-code that follows.
    fn end_region(&mut self, _out: &mut Vec<u8>) -> Result<(), MachineError> {
        Ok(())
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
    ) -> Result<(), MachineError>;
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
}

/// The 3-axis emitter: `G1 X Y Z E F` for extrusions, `G0 X Y Z F` for travels, `G1 E F` for
/// retractions. X, Y, Z are always written (3 decimals), F only when it changes.
#[derive(Debug, Default)]
pub struct Cartesian {
    ew: EWriter,
    last_f: Option<f64>,
}

impl Cartesian {
    pub fn new() -> Cartesian {
        Cartesian::default()
    }

    fn feed(&mut self, out: &mut Vec<u8>, f: f64) {
        if self.last_f != Some(f) && f.is_finite() && f > 0.0 {
            out.extend_from_slice(b" F");
            push_feed(out, f);
            self.last_f = Some(f);
        }
    }
}

fn xyz(out: &mut Vec<u8>, tp: &ToolPoint) {
    out.extend_from_slice(b" X");
    push_mm(out, tp.p.x);
    out.extend_from_slice(b" Y");
    push_mm(out, tp.p.y);
    out.extend_from_slice(b" Z");
    push_mm(out, tp.p.z);
}

impl Emitter for Cartesian {
    fn point(
        &mut self,
        out: &mut Vec<u8>,
        tp: &ToolPoint,
        relative_e: bool,
    ) -> Result<(), MachineError> {
        if tp.travel && tp.e != 0.0 {
            let v = self.ew.advance(tp.e, relative_e);
            out.extend_from_slice(b"G1 E");
            push_e(out, v);
        } else if tp.travel {
            out.extend_from_slice(b"G0");
            xyz(out, tp);
        } else {
            let v = self.ew.advance(tp.e, relative_e);
            out.extend_from_slice(b"G1");
            xyz(out, tp);
            out.extend_from_slice(b" E");
            push_e(out, v);
        }
        self.feed(out, tp.f);
        out.push(b'\n');
        Ok(())
    }

    fn reset_e(&mut self, v: f64) {
        self.ew.reset(v);
    }

    fn current_e(&self) -> f64 {
        self.ew.current()
    }
}
