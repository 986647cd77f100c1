//! Pass 2's state: one G-code line at a time, every object extrusion split, mapped and
//! metered, travels re-planned, everything else passed through in order.
//!
//! ## Order of non-move lines around travels
//! A travel is written when its destination is known (the start of the next extrusion), so
//! the lines that follow a travel in the file wait for it ([`Held`]): a fan, a firmware
//! unretract (`G11`), pushed-back filament (`G1 E+`) after a travel are written after the
//! travel, never in front of it; consecutive travels merge into one, and what waited runs at
//! its end. A line that must run where the file put it — a dwell or pause (`G4`, `M0`, `M1`,
//! `M25`, `M125`, `M226`, `M600`, `M601`) or a head move (`T…`, `G27`, `G28 X Y`) — makes the
//! travel stop there ([`Core::stop_point`]) when another travel follows. A retraction (`G1 E-`
//! in place, `G10`) runs at once: in front of a travel it only oozes less; a `G10` after lines
//! that wait makes the travel stop there first, so the lines keep their order. G10/G11 count as retracted/pushed back (no retraction of warpslice's own
//! inside a G10). Mode lines (G90/G91, M82/M83, G20/G21, `G92 E`) take effect at once: they
//! say how the words that follow read; comments wait only behind lines that wait.
//!
//! ## Head moves the file does not give
//! After `G28 X/Y`, `G27` (park) or a tool change `T…` the head is where the firmware put it.
//! The next travel then climbs straight up, wherever the head is, to above everything printed
//! so far ([`Core::printed_top`] + clearance), crosses at that height and descends onto its
//! target ([`Emitter::lift_from_unknown`]; a machine emitter refuses, its pose is lost).
//! `G28` homing Z, `G29` and `G30` inside the region are refused
//! ([`UnwarpError::ProbeInRegion`]): the nozzle or the probe goes down to the bed where the
//! part stands.
//! Not treated as head moves: `G12` (nozzle clean) and `G60`/`G61` (save/return to a
//! position): slicers do not write them inside a print; they pass through like other lines.

use glam::DVec3;

use super::{segment, travel, UnwarpError, UnwarpOptions, UnwarpReport, RETRACT_FEED};
use crate::emit::clearance::{HeadProfile, Printed, HEAD_CLEARANCE_MM};
use crate::emit::{EmitError, Emitter, DEFAULT_TRAVEL_FEED, E_QUANTUM};
use crate::gcode::write::push_e;
use crate::gcode::{Command, HeadMove, Line, Move, State};
use crate::job::Job;
use crate::num::fmt_shortest as fmt;
use crate::register::Registration;
use crate::tolerance::{BED_Z, LENGTH_EPSILON};
use crate::toolpath::{Feature, Thinning, ToolPoint};
use crate::warp::Warp;

/// A travel's stop within this distance (XY, mm) of the object's extrusions' box is mapped as
/// the object's point (a slicer's wipe or inward move before a retraction lies on the layer);
/// farther out it is a park or purge position and stays at least at the slicer's height.
pub(super) const STOP_MARGIN: f64 = 5.0;

/// What kind of extrusion a move piece is.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Object,
    Flat,
    Dropped,
}

/// A travel waiting for its destination to be known (the start of the next extrusion).
#[derive(Clone, Copy, Debug)]
pub(super) struct Pending {
    f: f64,
    /// The file's last travel piece that moved in X/Y (its end: where the slicer's head went),
    /// and its line.
    last: Option<(u64, Move)>,
}

/// What a held line does when it is written.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Effect {
    None,
    /// The head moves somewhere the file does not say.
    HeadMove(HeadMove),
    /// G10 (true) or G11.
    FirmwareRetract(bool),
    /// `G92 E<v>`: the firmware's E is now v.
    ResetE(f64),
}

/// Something after a pending travel, in file order, written when the travel is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) enum Held {
    /// A non-move line: its bytes in `held_bytes`, its line number, what it does, whether it
    /// must run where the file put it (see [`Core::action`]).
    Line {
        start: usize,
        end: usize,
        line: u64,
        effect: Effect,
        stop: bool,
    },
    /// Filament moved in place (`G1 E`), mm, its feed and the E mode.
    E { e: f64, f: f64, relative: bool },
}

/// Pass 2 state.
pub(super) struct Core {
    pub(super) job: Job,
    pub(super) warp: Box<dyn Warp>,
    pub(super) opts: UnwarpOptions,
    pub(super) reg: Registration,
    pub(super) dx: f64,
    pub(super) dy: f64,
    /// Output shift of the slicer-frame points: `place` − (dx, dy), or zero.
    pub(super) shift: DVec3,
    pub(super) out: Vec<u8>,
    pub(super) emit: Box<dyn Emitter>,
    /// The first error the emitter returned (the driver stops at the end of that line).
    pub(super) emit_error: Option<UnwarpError>,
    /// Whether the object's extrusions lie in the job's part ([`super::shape`]).
    pub(super) shape: super::shape::ShapeCheck,
    /// The slicer's own E position (absolute files), to re-synchronise after the region.
    pub(super) slicer_e: f64,
    /// Output position and tool axis, output frame.
    pub(super) cur: Option<(DVec3, DVec3)>,
    pub(super) pending: Option<Pending>,
    /// What came after the pending travel, in order ([`Held`]).
    pub(super) held: Vec<Held>,
    pub(super) held_bytes: Vec<u8>,
    /// The head moved where the file does not say, on this line (the next travel is a full lift).
    pub(super) lost: Option<(u64, HeadMove)>,
    /// A firmware retraction (G10) is in force.
    pub(super) fw_retracted: bool,
    /// The highest extrusion point written so far, output frame z (−∞ before any).
    pub(super) printed_top: f64,
    /// Filament the slicer retracted and has not yet pushed back, mm.
    pub(super) retracted: f64,
    pub(super) grid: travel::HeightGrid,
    /// The head's clearance profile (the emitter's; `None`: travels for the tip only).
    pub(super) head: Option<HeadProfile>,
    pub(super) inside: bool,
    pub(super) done_region: bool,
    /// Smallest z component of an object extrusion's tool axis (cos of the largest tilt).
    pub(super) min_nz: f64,
    /// The file's E mode at the last line (M83 = relative).
    pub(super) e_relative: bool,
    pub(super) report: UnwarpReport,
    pub(super) toolpath: Vec<ToolPoint>,
    /// Which toolpath points are kept (`toolpath_every`).
    pub(super) thinning: Thinning,
    pub(super) stack: Vec<(f64, DVec3, u32)>,
    pub(super) pieces: Vec<(f64, DVec3)>,
    /// The lines outside the region are converted by the emitter ([`super::outside`]).
    pub(super) convert_outside: bool,
    /// Outside the region: which of the slicer's X Y Z the file gave since the last homing.
    pub(super) known: [bool; 3],
    /// Outside the region: where the converted lines left the tip (output frame), `None` while
    /// the pose is unknown.
    pub(super) outside_pose: Option<DVec3>,
    /// After the region: the coordinates the file has not given since (they stay the head's).
    pub(super) keep: [bool; 3],
}

impl Core {
    fn nl(&mut self) {
        self.out.push(b'\n');
        self.report.lines_out += 1;
    }

    pub(super) fn header(&mut self) {
        let m = self.report.model_to_output;
        let lines = [
            format!(
                "; generated by warpslice {} (non-planar unwarp of a planar slicer's G-code)",
                env!("CARGO_PKG_VERSION")
            ),
            format!("; warpslice job = {}", self.job.to_json_line()),
            format!(
                "; warpslice registration: translation {} {} 0, residual {:.4} mm{}",
                fmt(m[0]),
                fmt(m[1]),
                self.reg.residual,
                if self.reg.overridden {
                    " (given with --offset)"
                } else {
                    ""
                }
            ),
            format!(
                "; warpslice model_to_output = {} {} {}",
                fmt(m[0]),
                fmt(m[1]),
                fmt(m[2])
            ),
        ];
        for l in lines {
            self.out.extend_from_slice(l.as_bytes());
            self.nl();
        }
        self.counted(|c| c.emit.header(&mut c.out));
    }

    /// Run `f` (which writes to `out`) and count the lines it wrote; the emitter is told first
    /// how many lines the output already has (so its errors can name their output line).
    pub(super) fn counted<R>(&mut self, f: impl FnOnce(&mut Core) -> R) -> R {
        self.emit.lines_written(self.report.lines_out);
        let start = self.out.len();
        let r = f(self);
        self.report.lines_out += self.out[start..].iter().filter(|&&b| b == b'\n').count() as u64;
        r
    }

    /// Keep the first emitter error, naming the G-code line.
    fn keep_error(&mut self, r: Result<(), EmitError>) {
        if let Err(error) = r {
            if self.emit_error.is_none() {
                self.emit_error = Some(UnwarpError::Emit {
                    line: Some(self.report.lines_in),
                    error,
                });
            }
        }
    }

    pub(super) fn line(&mut self, line: &Line<'_>, state: &State) -> Result<(), UnwarpError> {
        self.line_inner(line, state)?;
        match self.emit_error.take() {
            Some(e) => Err(e),
            None => Ok(()),
        }
    }

    fn line_inner(&mut self, line: &Line<'_>, state: &State) -> Result<(), UnwarpError> {
        self.report.lines_in = line.number;
        self.e_relative = state.e_relative;
        let n = line.number;
        let in_region = n >= self.reg.region[0] && n <= self.reg.region[1];
        if in_region && !self.inside {
            self.inside = true;
            if state.inch {
                return Err(UnwarpError::Inches { line: n });
            }
            let mut p = state_position_before(line, state);
            self.cur = Some((p, DVec3::Z));
            if self.convert_outside {
                // the head is where the converted lines left it (unknown after homing)
                self.cur = self.outside_pose.map(|q| (q, DVec3::Z));
                p = self.outside_pose.unwrap_or(self.map_point(Kind::Flat, p).0);
            }
            // the firmware's E is the slicer's at this point (absolute files: E words continue
            // from it)
            self.emit.reset_e(self.slicer_e);
            let r = self.counted(|c| c.emit.begin_region(&mut c.out, p, DVec3::Z));
            self.keep_error(r);
        }
        if !in_region && self.inside && !self.done_region {
            self.end_region();
        }
        // The slicer's own E position (for re-synchronising absolute E after the region).
        for m in line.moves {
            self.slicer_e += m.e;
        }
        if let Command::SetPosition { e: Some(v), .. } = line.command {
            self.slicer_e = v;
        }
        if !self.inside || self.done_region {
            if self.convert_outside {
                return self.outside_line(line, state);
            }
            self.passthrough(line.raw);
            return Ok(());
        }
        match line.command {
            Command::Positioning { relative: true } => {
                return Err(UnwarpError::RelativePositioning { line: n })
            }
            Command::Units { inch: true } => return Err(UnwarpError::Inches { line: n }),
            Command::SetPosition { xyz: true, .. } => {
                return Err(UnwarpError::AxisReset { line: n })
            }
            Command::SetPosition { e: Some(v), .. } if self.holds_line() => {
                // after lines that wait: waits too, and resets E when it is written
                self.action(n, line.raw, Effect::ResetE(v), false)
            }
            Command::SetPosition { e: Some(v), .. } => {
                self.emit.reset_e(v);
                self.passthrough(line.raw);
            }
            Command::ExtrusionMode { .. } if self.holds_line() => {
                // the E mode must change where the E words after it are written: what waits
                // runs now, in front of the travel
                self.write_held();
                self.passthrough(line.raw);
            }
            Command::Move { .. } => {
                if state.positioning_relative {
                    return Err(UnwarpError::RelativePositioning { line: n });
                }
                for m in line.moves {
                    self.piece(n, m, state.e_relative)?;
                }
            }
            Command::HeadMove(HeadMove::Home { z: true } | HeadMove::Probe) => {
                return Err(UnwarpError::ProbeInRegion {
                    line: n,
                    command: String::from_utf8_lossy(line.raw).trim().to_string(),
                })
            }
            Command::HeadMove(h) => self.action(n, line.raw, Effect::HeadMove(h), true),
            Command::FirmwareRetract { retract: true } => {
                // a retraction runs at once (in front of a pending travel it only oozes less);
                // after lines that wait, the travel stops where they run, then it retracts
                if self.holds_line() {
                    self.stop_here(state.e_relative);
                }
                self.passthrough(line.raw);
                self.fw_retracted = true;
            }
            Command::FirmwareRetract { retract: false } => {
                self.action(n, line.raw, Effect::FirmwareRetract(false), false)
            }
            Command::Dwell => self.action(n, line.raw, Effect::None, true),
            Command::Other => self.action(n, line.raw, Effect::None, false),
            // comments, markers and mode lines take effect at once (a comment waits only
            // behind lines that wait, to keep their order)
            _ if self.holds_line() => self.action(n, line.raw, Effect::None, false),
            _ => self.passthrough(line.raw),
        }
        Ok(())
    }

    /// A non-move line that acts: after a pending travel it waits for it, otherwise it is
    /// written now.
    /// `stop`: the line must run where the file put it (a dwell, a pause, a head move), so a
    /// further travel makes the pending one stop there first.
    fn action(&mut self, line: u64, raw: &[u8], effect: Effect, stop: bool) {
        if self.pending.is_some() {
            let start = self.held_bytes.len();
            self.held_bytes.extend_from_slice(raw);
            self.held.push(Held::Line {
                start,
                end: self.held_bytes.len(),
                line,
                effect,
                stop,
            });
        } else {
            self.passthrough(raw);
            self.apply(line, effect);
        }
    }

    /// What a written line does to the unwarp's idea of the head.
    fn apply(&mut self, line: u64, effect: Effect) {
        match effect {
            Effect::None => {}
            Effect::HeadMove(h) => {
                self.lost = Some((line, h));
                self.cur = None;
            }
            Effect::FirmwareRetract(r) => self.fw_retracted = r,
            Effect::ResetE(v) => self.emit.reset_e(v),
        }
    }

    /// Whether a line waits behind the pending travel.
    fn holds_line(&self) -> bool {
        self.pending.is_some() && self.held.iter().any(|h| matches!(h, Held::Line { .. }))
    }

    /// Whether a line that must run where the file put it waits behind the pending travel.
    fn holds_stop(&self) -> bool {
        self.held
            .iter()
            .any(|h| matches!(h, Held::Line { stop: true, .. }))
    }

    /// Write what waited behind the travel just written, in order.
    fn write_held(&mut self) {
        let held = std::mem::take(&mut self.held);
        let bytes = std::mem::take(&mut self.held_bytes);
        for h in &held {
            match *h {
                Held::Line {
                    start,
                    end,
                    line,
                    effect,
                    ..
                } => {
                    self.passthrough(&bytes[start..end]);
                    self.apply(line, effect);
                }
                Held::E { e, f, relative } => {
                    self.retracted = (self.retracted - e).max(0.0);
                    self.write_e_only(e, f, relative);
                }
            }
        }
        // keep the buffers' capacity
        self.held = held;
        self.held.clear();
        self.held_bytes = bytes;
        self.held_bytes.clear();
    }

    /// Where a travel that stops before another travel (lines ran at its end) goes: its end
    /// mapped as an extrusion of its feature would be; beyond [`STOP_MARGIN`] of the object's
    /// extrusions (a park or purge position), never below the slicer's own height there (a
    /// point far from the part maps below the bed under most warps).
    pub(super) fn stop_point(&self, line: u64, m: &Move) -> (DVec3, DVec3) {
        let flat = self.map_point(Kind::Flat, m.to);
        match self.kind(line, m) {
            Kind::Object => {
                let (p, n) = self.map_point(Kind::Object, m.to);
                let b = self.reg.gcode_bbox;
                let near = m.to.x >= b.min.x - STOP_MARGIN
                    && m.to.x <= b.max.x + STOP_MARGIN
                    && m.to.y >= b.min.y - STOP_MARGIN
                    && m.to.y <= b.max.y + STOP_MARGIN;
                if near {
                    (p, n)
                } else {
                    (DVec3::new(p.x, p.y, p.z.max(flat.0.z)), n)
                }
            }
            _ => flat,
        }
    }

    /// The pending travel stops at the file's last travel point; the held lines run there.
    /// On a dropped layer (the anchor's, a dropped skirt's) the head does not go there: they
    /// run where the head is, and the travel stays pending.
    fn stop_here(&mut self, relative: bool) {
        match self.pending.and_then(|p| p.last) {
            Some((line, m)) if self.kind(line, &m) != Kind::Dropped => {
                let (p, n) = self.stop_point(line, &m);
                self.travel_to(p, n, relative);
            }
            _ => self.write_held(),
        }
    }

    pub(super) fn passthrough(&mut self, raw: &[u8]) {
        self.emit.raw(&mut self.out, raw);
        self.report.lines_out += 1;
    }

    /// Hand a point to the emitter (counting the lines it writes) and keep it.
    fn emit_point(&mut self, mut tp: ToolPoint, relative: bool) {
        if self.emit_error.is_some() {
            return;
        }
        tp.line = self.report.lines_in;
        let r = self.counted(|c| c.emit.point_over(&mut c.out, &tp, relative, &c.grid));
        self.keep_error(r);
        if !tp.travel || tp.e == 0.0 {
            self.cur = Some((tp.p, tp.n));
        }
        if self.opts.collect_toolpath && self.thinning.keeps(tp.layer) {
            self.toolpath.push(tp);
        }
    }

    fn kind(&self, line: u64, m: &Move) -> Kind {
        let flat = !m.feature.is_object() || (!self.reg.typed && self.reg.in_skirt_run(line));
        if flat {
            return if self.opts.drop_skirt {
                Kind::Dropped
            } else {
                Kind::Flat
            };
        }
        if self.job.anchor.is_some() && m.layer == self.reg.first_layer {
            return Kind::Dropped;
        }
        Kind::Object
    }

    /// G-code point → model frame.
    fn to_model(&self, g: DVec3) -> DVec3 {
        let q = DVec3::new(g.x - self.dx, g.y - self.dy, g.z - self.job.stl_z_offset);
        self.warp.inverse(q)
    }

    /// Model frame → output frame, before the bed clamp.
    fn model_to_output(&self, p: DVec3) -> DVec3 {
        DVec3::new(
            p.x + self.dx + self.shift.x,
            p.y + self.dy + self.shift.y,
            p.z + self.opts.z_offset,
        )
    }

    /// How far an output point lies below the bed (0 above it), mm: the clamp comes after every
    /// offset, so nothing is written below the bed (`--z-offset` is bounded by the options'
    /// check, see [`crate::unwarp::UnwarpOptions::validate_for`]).
    fn below_bed(out: DVec3) -> f64 {
        (BED_Z - out.z).max(0.0)
    }

    pub(super) fn map_point(&self, kind: Kind, g: DVec3) -> (DVec3, DVec3) {
        let (out, n) = match kind {
            Kind::Object => {
                let p = self.to_model(g);
                (self.model_to_output(p), self.warp.tool_axis(p))
            }
            _ => (
                DVec3::new(
                    g.x + self.shift.x,
                    g.y + self.shift.y,
                    g.z + self.opts.z_offset,
                ),
                DVec3::Z,
            ),
        };
        (DVec3::new(out.x, out.y, out.z.max(BED_Z)), n)
    }

    fn piece(&mut self, line: u64, m: &Move, relative: bool) -> Result<(), UnwarpError> {
        let moved = (m.to - m.from).length_squared() > 0.0;
        if !moved {
            if m.e == 0.0 {
                // a feed-only G1: keep the feed modal state ours
                return Ok(());
            }
            // after a travel a push-back waits for it; a retraction runs at once (earlier
            // only oozes less)
            if self.pending.is_some() && m.e > 0.0 {
                match self.held.last_mut() {
                    // consecutive pushes back merge into one (a dropped layer's travels)
                    Some(Held::E { e, f, .. }) => {
                        *e += m.e;
                        *f = m.f;
                    }
                    _ => self.held.push(Held::E {
                        e: m.e,
                        f: m.f,
                        relative,
                    }),
                }
                return Ok(());
            }
            let mut e = m.e;
            if self.pending.is_some() && e < 0.0 {
                if let Some(Held::E { e: held, .. }) = self.held.last_mut() {
                    // a push-back still waiting for its travel and this retraction cancel:
                    // the file pushed filament in and pulled it out again with nothing printed
                    // between (a dropped layer's travels); written at once, the retraction
                    // came first and the filament was pulled out twice as far
                    let cancel = held.min(-e);
                    *held -= cancel;
                    e += cancel;
                    if *held <= 0.0 {
                        self.held.pop();
                    }
                    if e == 0.0 {
                        return Ok(());
                    }
                }
            }
            self.retracted = (self.retracted - e).max(0.0);
            self.write_e_only(e, m.f, relative);
            return Ok(());
        }
        if m.e <= 0.0 {
            if self.holds_stop() {
                // lines ran at the end of the previous travel: it stops there
                self.stop_here(relative);
            }
            if m.e < 0.0 {
                // a wipe: retract in place
                self.retracted -= m.e;
                self.write_e_only(m.e, m.f, relative);
            }
            let p = self.pending.get_or_insert(Pending { f: m.f, last: None });
            p.f = m.f;
            // a stop goes where the head last moved in X/Y, at that height: a Z move after it
            // (a layer change, a z-hop) is the next travel's business, replanned anyway
            if m.from.truncate() != m.to.truncate() {
                p.last = Some((line, *m));
            }
            return Ok(());
        }
        // An extrusion.
        self.report.e_in += m.e;
        let kind = self.kind(line, m);
        if kind == Kind::Dropped {
            if self.job.anchor.is_some()
                && m.feature.is_object()
                && (self.reg.typed || !self.reg.in_skirt_run(line))
            {
                self.report.e_anchor += m.e;
            } else {
                self.report.e_skirt += m.e;
            }
            // the head does not go there: what follows starts with a travel (lines held
            // behind it stay held: the dropped layer is not a place to stop at)
            self.pending.get_or_insert(Pending { f: m.f, last: None });
            return Ok(());
        }
        let (start, n0) = self.map_point(kind, m.from);
        self.travel_to(start, n0, relative);
        match kind {
            Kind::Flat => {
                self.report.e_skirt += m.e;
                let (end, n1) = self.map_point(kind, m.to);
                // the ramp's height is the slicer's (above the bed): the z-offset lifts the
                // nozzle, it does not change how much is extruded
                let e = m.e * self.opts.flow.at(m.to.z);
                // a skirt found by geometry (no ;TYPE:) is named as such in the toolpath
                let feature = if m.feature.is_object() {
                    Feature::Skirt
                } else {
                    m.feature
                };
                self.write_extrusion(end, n1, e, m, feature, relative, false);
            }
            Kind::Object => self.object_piece(m, relative),
            Kind::Dropped => {}
        }
        Ok(())
    }

    fn object_piece(&mut self, m: &Move, relative: bool) {
        let (from, to) = (m.from, m.to);
        // the end of every object extrusion lies in the part (its start is the previous end, or
        // where a travel or a head move left the head)
        let gross = self.shape.point(
            self.warp.as_ref(),
            &self.job,
            (self.dx, self.dy),
            m.layer,
            self.report.lines_in,
            to,
            m.feature,
        );
        if let (Some(finding), None) = (gross, &self.emit_error) {
            self.emit_error = Some(UnwarpError::ShapeMismatch {
                finding,
                beyond: self.shape.beyond,
            });
        }
        let p0 = self.to_model(from);
        let mut stack = std::mem::take(&mut self.stack);
        let mut pieces = std::mem::take(&mut self.pieces);
        pieces.clear();
        {
            let map = |t: f64| self.to_model(from.lerp(to, t));
            segment::split(
                &map,
                p0,
                self.opts.tolerance,
                self.opts.max_segment,
                &mut stack,
                &mut pieces,
            );
        }
        if pieces.len() > 1 {
            self.report.moves_split += 1;
        }
        let h = self.job.layer_height;
        let (mut t0, mut a) = (0.0, p0);
        for &(t1, b) in &pieces {
            let mid = (a + b) * 0.5;
            let det = self.warp.jacobian_det(mid);
            let mut e = m.e * (t1 - t0) / det * self.opts.flow.at(mid.z.max(BED_Z));
            let out = self.model_to_output(b);
            let depth = Core::below_bed(out);
            self.report.object_points += 1;
            if depth > 0.0 {
                // clamped to the bed: the bead is `depth` thinner
                self.report.clamped_points += 1;
                self.report.deepest_below_bed = self.report.deepest_below_bed.max(depth);
                e *= ((h - depth) / h).clamp(0.0, 1.0);
            }
            let n = self.warp.tool_axis(b);
            let out = DVec3::new(out.x, out.y, out.z.max(BED_Z));
            self.write_extrusion(out, n, e, m, m.feature, relative, true);
            t0 = t1;
            a = b;
        }
        self.stack = stack;
        self.pieces = pieces;
    }

    fn write_e_only(&mut self, e: f64, f: f64, relative: bool) {
        let (p, n) = self.cur.unwrap_or((DVec3::ZERO, DVec3::Z));
        self.emit_point(
            ToolPoint {
                p,
                n,
                e,
                f,
                layer: 0,
                feature: Feature::Unknown,
                travel: true,
                line: 0,
            },
            relative,
        );
    }

    #[allow(clippy::too_many_arguments)]
    fn write_extrusion(
        &mut self,
        p: DVec3,
        n: DVec3,
        e: f64,
        m: &Move,
        feature: Feature,
        relative: bool,
        object: bool,
    ) {
        self.report.e_out += e;
        self.report.segments_out += 1;
        if object && n.z < self.min_nz {
            // the angle itself is taken once, at the end (acos is monotonic)
            self.min_nz = n.z;
        }
        if let Some((a, _)) = self.cur {
            self.grid.mark_segment(a, p);
        }
        self.printed_top = self.printed_top.max(p.z);
        self.emit_point(
            ToolPoint {
                p,
                n,
                e,
                f: m.f,
                layer: m.layer,
                feature,
                travel: false,
                line: 0,
            },
            relative,
        );
    }

    fn write_travel(&mut self, p: DVec3, n: DVec3, f: f64) {
        self.emit_point(
            ToolPoint {
                p,
                n,
                e: 0.0,
                f,
                layer: 0,
                feature: Feature::Unknown,
                travel: true,
                line: 0,
            },
            true,
        );
    }

    /// Go to `target` (output frame) if not there: straight, or retract–lift–move–descend;
    /// then write what waited behind the travel.
    fn travel_to(&mut self, target: DVec3, n: DVec3, relative: bool) {
        let pending = self.pending.take();
        let f = pending.map_or(DEFAULT_TRAVEL_FEED, |p| p.f);
        if let Some((line, what)) = self.lost.take() {
            self.travel_from_unknown(line, what, target, n, f, relative);
        } else if let Some((cur, cur_n)) = self.cur {
            if (target - cur).length() > LENGTH_EPSILON {
                let head = self.head.as_ref().map(|profile| travel::HeadClearance {
                    profile,
                    tilt: crate::num::acos(cur_n.z.clamp(-1.0, 1.0))
                        .max(crate::num::acos(n.z.clamp(-1.0, 1.0))),
                    turn: crate::num::angle_between(cur_n, n),
                });
                match travel::plan(&self.grid, cur, target, self.opts.travel_clearance, head) {
                    travel::TravelPlan::Direct => self.write_travel(target, n, f),
                    travel::TravelPlan::Lift(z) => {
                        self.lifted(relative, |c| {
                            c.write_travel(DVec3::new(cur.x, cur.y, z), cur_n, f);
                            c.write_travel(DVec3::new(target.x, target.y, z), n, f);
                            c.write_travel(target, n, f);
                        });
                    }
                }
            }
        } else {
            self.write_travel(target, n, f);
        }
        self.write_held();
        // a held line moved the head (a tool change after the travel): back from wherever
        if let Some((line, what)) = self.lost.take() {
            self.travel_from_unknown(line, what, target, n, f, relative);
        }
    }

    /// A lift written by `moves`, with a retraction around it if the slicer did not retract.
    fn lifted(&mut self, relative: bool, moves: impl FnOnce(&mut Core)) {
        self.report.lifts += 1;
        let add = self.retracted <= LENGTH_EPSILON
            && !self.fw_retracted
            && self.opts.retract_length > 0.0;
        if add {
            self.report.retracts_added += 1;
            self.write_e_only(-self.opts.retract_length, RETRACT_FEED, relative);
        }
        moves(self);
        if add {
            self.write_e_only(self.opts.retract_length, RETRACT_FEED, relative);
        }
    }

    /// The head is where a `what` on `line` left it: straight up (or down) to above everything
    /// printed so far, across, and down onto `target`.
    fn travel_from_unknown(
        &mut self,
        line: u64,
        what: HeadMove,
        target: DVec3,
        n: DVec3,
        f: f64,
        relative: bool,
    ) {
        let z = self.printed_top.max(target.z) + self.opts.travel_clearance;
        self.lifted(relative, |c| {
            if c.emit_error.is_some() {
                return;
            }
            let r = c.counted(|c| c.emit.lift_from_unknown(&mut c.out, z, f, what.name()));
            if let Err(error) = r {
                c.emit_error = Some(UnwarpError::Emit {
                    line: Some(line),
                    error,
                });
                return;
            }
            c.write_travel(DVec3::new(target.x, target.y, z), n, f);
            c.write_travel(target, n, f);
        });
    }

    /// Leave the region: lift clear of the part and re-synchronise absolute E.
    pub(super) fn end_region(&mut self) {
        self.done_region = true;
        if self.holds_stop() {
            // lines ran at the end of the last travel: it stops there
            self.stop_here(self.e_relative);
        }
        // what is still held (filament the slicer pushed back at the end of a travel that
        // leads out of the region, lines on a dropped layer) is written in place
        self.pending = None;
        self.write_held();
        if let Some((cur, n)) = self.cur {
            let (_, top) = self.grid.clearance_needed(cur, cur);
            let mut z = top.max(cur.z) + self.opts.travel_clearance;
            if let Some(profile) = &self.head {
                // the emitter turns the tool axis back to vertical up there: the head clears
                let tilt = crate::num::acos(n.z.clamp(-1.0, 1.0));
                let c = cur.truncate();
                let head = self.grid.head_clear_z(profile, c, c, 0.0, tilt);
                z = z.max(head + HEAD_CLEARANCE_MM);
            }
            if z > cur.z {
                self.write_travel(DVec3::new(cur.x, cur.y, z), n, DEFAULT_TRAVEL_FEED);
            }
        }
        if self.emit_error.is_none() {
            let r = self.counted(|c| c.emit.end_region(&mut c.out));
            self.keep_error(r);
        }
        // the end G-code starts from the rest pose where the lift left the tip
        self.outside_pose = self.cur.map(|(p, _)| p);
        self.known = [self.outside_pose.is_some(); 3];
        self.keep = self.known;
        if !self.e_relative && (self.emit.current_e() - self.slicer_e).abs() > E_QUANTUM {
            let line = format!(
                "G92 E{} ; warpslice: back to the slicer's E",
                fmt_e(self.slicer_e)
            );
            self.passthrough(line.as_bytes());
            self.emit.reset_e(self.slicer_e);
        }
    }
}

/// Where the head was before `line` (its first move's start, or the state's position).
fn state_position_before(line: &Line<'_>, state: &State) -> DVec3 {
    line.moves.first().map_or(state.position, |m| m.from)
}

fn fmt_e(v: f64) -> String {
    let mut b = Vec::new();
    push_e(&mut b, v);
    String::from_utf8(b).unwrap_or_default()
}
