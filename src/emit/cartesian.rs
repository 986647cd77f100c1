//! The 3-axis emitter.

use crate::gcode::write::{push_e, push_feed, push_mm};
use crate::toolpath::ToolPoint;

use super::{EWriter, EmitError, Emitter};

/// The 3-axis emitter: `G1 X Y Z E F` for extrusions, `G0 X Y Z F` for travels, `G1 E F` for
/// retractions. X, Y, Z are always written (3 decimals), F only when it changes.
#[derive(Debug, Default)]
pub struct Cartesian {
    ew: EWriter,
    last_f: Option<f64>,
}

impl Cartesian {
    /// A new 3-axis emitter (E from 0).
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
    ) -> Result<(), EmitError> {
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

    fn lift_from_unknown(
        &mut self,
        out: &mut Vec<u8>,
        z: f64,
        f: f64,
        _command: &str,
    ) -> Result<(), EmitError> {
        out.extend_from_slice(b"G0 Z");
        push_mm(out, z);
        self.last_f = None;
        self.feed(out, f);
        out.extend_from_slice(b" ; warpslice: the head is where the firmware put it: up first\n");
        Ok(())
    }

    fn reset_e(&mut self, v: f64) {
        self.ew.reset(v);
    }

    fn current_e(&self) -> f64 {
        self.ew.current()
    }
}
