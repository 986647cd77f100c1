//! [`MachineEmitter`]: the unwarp driver's [`Emitter`] for a 4/5-axis machine.
//!
//! For every toolpath point (output frame tip `p`, tool axis `n`) the emitter runs the
//! machine's inverse kinematics seeded with the previous axes (continuity, branch), splits the
//! move in machine space ([`tessellate_move`]: the firmware's linear axis interpolation stays
//! within 0.02 mm / 0.1° of the intended path), computes F per [`FeedMode`] and writes
//! `G1 <axis letters> E F` lines (linear axes in mm, rotary axes in degrees, 3 decimals; E via
//! [`EWriter`], the move's filament shared among its pieces by tip length without drift).
//! Retractions in place are `G1 E F`.
//!
//! ## Region boundaries
//! - [`Emitter::begin_region`] (the head is at the slicer's position, tool vertical): the
//!   previous axes are `inverse(p, +Z)`; `G93` for inverse-time feed; for a triple-Z bed the Z
//!   axes get a `G92` offset (below).
//! - [`Emitter::end_region`] (after the driver's lift): a tessellated travel back to the
//!   vertical tool axis at the same tip point, the Z offset removed (`G92` with raw values),
//!   `G94` after inverse-time feed — so the 3-axis end G-code that follows works.
//!
//! ## Machine specifics
//! - **Single-revolution rotary axis** (Slicer4RTN, `revolution: single`): when consecutive
//!   points cross the ±180° seam the head must turn the long way. The emitter lifts the tip
//!   by [`ROTATE_AROUND_LIFT_MM`] (1 mm, Slicer4RTN's "radius + 1 mm" clearance), travels to the
//!   next point in the air while the axis turns around, and descends. The move is split at the
//!   seam first ([`super::tessellate::SEAM_PIECE_MM`]), so only a piece shorter than 0.001 mm is
//!   turned around in the air; its filament is added to the next extruding piece (the report
//!   counts it, `e_skipped_mm`: moved past the seam, not lost).
//! - **Unlimited rotary axes** (RotBot's slip ring, the mandrel, the polar C axis): at a layer
//!   change an axis beyond ±180° is reset with `G92 <letter>` modulo 360° (seed 002:
//!   "rot-revolv=0 resets at layer change the rotation angle to mod(360)").
//! - **Triple-Z bed** (seed 001): RepRapFirmware clamps negative axis values, so the Z axes
//!   (z₀ z₁ z₂) are written with a constant offset `D = (largest ball distance + |ball z|) ·
//!   sin(max tilt)` (rounded up to whole mm): at the region start `G92 Z U V` declares the
//!   level bed's raw heights + D, and every value written is raw + D. A raw value below −D is
//!   an [`MachineError::AxisLimit`]. The header comment says so.
//! - **B head**: the collision clip is in the kinematics; the ramp and z-offset come from the
//!   unwarp options.
//!
//! ## Errors
//! Unreachable orientations and axis limits are returned from [`Emitter::point`]; the driver
//! stops with `UnwarpError::Machine` naming the G-code line. Never a silently wrong file.

use glam::DVec3;

use super::angles::wrap180;
use super::feed::{output_feed, FeedMode};
use super::flavour::Flavour;
use super::tessellate::{tessellate_move, Bounds, TessellationReport, DEFAULT_BOUNDS};
use super::{AxisLimit, Machine, MachineError, MachineSpec};
use crate::emit::{EWriter, EmitError, Emitter, MachineReport, DEFAULT_TRAVEL_FEED};
use crate::gcode::write::{push_e, push_fixed, push_mm};
use crate::job::Job;
use crate::toolpath::{Feature, ToolPoint};

/// Lift of the tip for a single-revolution rotate-around, mm.
pub const ROTATE_AROUND_LIFT_MM: f64 = 1.0;
/// Decimals of F in inverse-time mode (F = 1/minutes can be small).
pub const INVERSE_TIME_DECIMALS: u32 = 5;
/// Trailing comment of the lines of a rotate-around (not toolpath points).
pub const ROTATE_AROUND_TAG: &str = "; rotate-around";
/// Trailing comment of an in-place reorientation (a held rotary axis catching up).
pub const REORIENT_TAG: &str = "; reorient";
/// Trailing comment of a move where the splitting hit its depth limit: the interpolation bound
/// is not proven there (the report counts these and gives the error measured).
pub const DISCONTINUITY_TAG: &str = "; discontinuity";

/// The previous pose: raw axes, tip, tool axis.
#[derive(Clone, Debug)]
struct Pose {
    axes: Vec<f64>,
    p: DVec3,
    n: DVec3,
}

/// The emitter (see the module documentation).
pub struct MachineEmitter {
    machine: Box<dyn Machine>,
    limits: Vec<AxisLimit>,
    preset: String,
    flavour: Flavour,
    feed: FeedMode,
    bounds: Bounds,
    /// Offset added to each axis when written (the triple-Z Z axes), mm.
    offsets: Vec<f64>,
    /// Unlimited rotary axes (reset modulo 360° at a layer change).
    unlimited: Vec<bool>,
    ew: EWriter,
    last_f: Option<f64>,
    prev: Option<Pose>,
    last_layer: Option<u32>,
    tess: TessellationReport,
    report: MachineReport,
    /// Filament of a rotate-around's piece, given to the next extruding piece, mm.
    carry_e: f64,
}

impl std::fmt::Debug for MachineEmitter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("MachineEmitter")
            .field("machine", &self.preset)
            .field("flavour", &self.flavour)
            .field("feed", &self.feed)
            .finish()
    }
}

impl MachineEmitter {
    /// Build for `spec` (flavour: `flavour`, else the spec's, else RepRapFirmware).
    pub fn new(
        spec: &MachineSpec,
        flavour: Option<Flavour>,
        feed: FeedMode,
    ) -> Result<MachineEmitter, MachineError> {
        let machine = spec.build()?;
        let limits = machine.limits().to_vec();
        let flavour = flavour.or(spec.flavour).unwrap_or_default();
        flavour.check(machine.name(), &limits, feed)?;
        let offsets = machine.written_offsets();
        let d = offsets.iter().copied().fold(0.0, f64::max);
        let unlimited = limits
            .iter()
            .map(|l| l.rotary && !(l.min.is_finite() && l.max.is_finite()))
            .collect();
        let report = MachineReport {
            machine: machine.name().to_string(),
            flavour: flavour.name().to_string(),
            feed,
            z_axes_offset_mm: d,
            ..MachineReport::default()
        };
        Ok(MachineEmitter {
            preset: machine.name().to_string(),
            machine,
            limits,
            flavour,
            feed,
            bounds: DEFAULT_BOUNDS,
            offsets,
            unlimited,
            ew: EWriter::default(),
            last_f: None,
            prev: None,
            last_layer: None,
            carry_e: 0.0,
            tess: TessellationReport::default(),
            report,
        })
    }

    /// Use other interpolation bounds (tests).
    pub fn with_bounds(mut self, bounds: Bounds) -> MachineEmitter {
        self.bounds = bounds;
        self
    }

    /// The measurements so far.
    pub fn report(&self) -> MachineReport {
        let mut r = self.report.clone();
        let t = &self.tess;
        r.moves_in = t.moves_in as u64;
        r.moves_out = t.moves_out as u64 + r.rotate_arounds * 2;
        r.worst_position_mm = t.worst_position_mm;
        r.worst_angle_deg = t.worst_angle_deg;
        r.worst_dropped_deg = t.worst_dropped_deg;
        r.depth_limited = t.depth_limited as u64;
        r.reposes = t.reposes as u64;
        r
    }

    fn write_feed(&mut self, out: &mut Vec<u8>, f: f64) {
        if !(f.is_finite() && f > 0.0) {
            return;
        }
        if self.feed == FeedMode::InverseTime {
            out.extend_from_slice(b" F");
            push_fixed(out, f, INVERSE_TIME_DECIMALS);
        } else if self.last_f != Some(f) {
            out.extend_from_slice(b" F");
            crate::gcode::write::push_feed(out, f);
            self.last_f = Some(f);
        }
    }

    /// `G1` to raw `axes` (+ E when `e` is given), F for a move of `tip_length` at tip feed `f`.
    #[allow(clippy::too_many_arguments)]
    fn write_g1(
        &mut self,
        out: &mut Vec<u8>,
        from: &[f64],
        axes: &[f64],
        p: DVec3,
        e: Option<(f64, bool)>,
        tip_length: f64,
        f: f64,
        tag: &str,
    ) -> Result<(), MachineError> {
        out.extend_from_slice(b"G1");
        for (i, l) in self.limits.iter().enumerate() {
            let v = axes[i] + self.offsets[i];
            if self.offsets[i] > 0.0 && v < 0.0 {
                return Err(MachineError::AxisLimit {
                    machine: self.preset.clone(),
                    axis: l.name.clone(),
                    value: axes[i],
                    min: -self.offsets[i],
                    max: f64::INFINITY,
                    p,
                });
            }
            out.push(b' ');
            out.extend_from_slice(l.name.as_bytes());
            push_mm(out, v);
        }
        if let Some((de, relative)) = e {
            let v = self.ew.advance(de, relative);
            out.extend_from_slice(b" E");
            push_e(out, v);
        }
        let fo = output_feed(self.feed, from, axes, tip_length, f);
        self.write_feed(out, fo);
        out.extend_from_slice(tag.as_bytes());
        out.push(b'\n');
        Ok(())
    }

    /// `G92` the unlimited rotary axes back into ±180° (layer change).
    fn reset_rotary(&mut self, out: &mut Vec<u8>) {
        let Some(prev) = self.prev.as_mut() else {
            return;
        };
        for (i, l) in self.limits.iter().enumerate() {
            if self.unlimited[i] && prev.axes[i].abs() > 180.0 {
                let w = wrap180(prev.axes[i]);
                out.extend_from_slice(b"G92 ");
                out.extend_from_slice(l.name.as_bytes());
                push_mm(out, w);
                out.extend_from_slice(
                    b" ; warpslice: rotary axis back to [-180, 180] at a layer change\n",
                );
                prev.axes[i] = w;
                self.report.rotary_resets += 1;
            }
        }
    }

    /// Lifted turn-around to `to` (a single-revolution axis crosses its seam).
    fn rotate_around(
        &mut self,
        out: &mut Vec<u8>,
        from: &Pose,
        to: &Pose,
        f: f64,
    ) -> Result<(), MachineError> {
        let lift = DVec3::Z * ROTATE_AROUND_LIFT_MM;
        let up0 = self
            .machine
            .inverse(from.p + lift, from.n, Some(&from.axes))?;
        let up1 = self.machine.inverse(to.p + lift, to.n, Some(&to.axes))?;
        let tag = ROTATE_AROUND_TAG;
        self.write_g1(
            out,
            &from.axes,
            &up0,
            from.p,
            None,
            ROTATE_AROUND_LIFT_MM,
            f,
            tag,
        )?;
        let len = (to.p - from.p).length();
        self.write_g1(out, &up0, &up1, to.p, None, len, f, tag)?;
        self.write_g1(
            out,
            &up1,
            &to.axes,
            to.p,
            None,
            ROTATE_AROUND_LIFT_MM,
            f,
            tag,
        )?;
        self.report.rotate_arounds += 1;
        Ok(())
    }

    /// Move from the previous pose to `tp` (tessellated).
    fn move_to(
        &mut self,
        out: &mut Vec<u8>,
        tp: &ToolPoint,
        relative: bool,
    ) -> Result<(), MachineError> {
        let Some(prev) = self.prev.clone() else {
            let axes = self.machine.inverse(tp.p, tp.n, None)?;
            let e = (!tp.travel).then_some((tp.e, relative));
            self.write_g1(out, &axes, &axes, tp.p, e, 0.0, tp.f, "")?;
            self.prev = Some(Pose {
                axes,
                p: tp.p,
                n: tp.n,
            });
            return Ok(());
        };
        let moves = tessellate_move(
            self.machine.as_ref(),
            (&prev.axes, prev.p, prev.n),
            tp,
            &self.bounds,
            &mut self.tess,
        )?;
        let mut from = prev.clone();
        for m in &moves {
            if m.rotate_around {
                // the piece turned around in the air (≤ SEAM_PIECE_MM): its filament goes to
                // the next extruding piece, so the volume is kept
                self.report.e_skipped_mm += m.e;
                if !m.travel {
                    self.carry_e += m.e;
                }
                let to = Pose {
                    axes: m.axes.clone(),
                    p: m.p,
                    n: m.n,
                };
                self.rotate_around(out, &from, &to, tp.f.max(m.f))?;
            } else {
                let e = (!m.travel).then(|| (m.e + std::mem::take(&mut self.carry_e), relative));
                let tag = if m.depth_limited {
                    DISCONTINUITY_TAG
                } else if m.reorient {
                    REORIENT_TAG
                } else {
                    ""
                };
                self.write_g1(out, &from.axes, &m.axes, m.p, e, m.tip_length, m.f, tag)?;
            }
            from = Pose {
                axes: m.axes.clone(),
                p: m.p,
                n: m.n,
            };
        }
        self.prev = Some(Pose {
            axes: from.axes,
            p: tp.p,
            n: tp.n,
        });
        Ok(())
    }
}

impl Emitter for MachineEmitter {
    fn header(&mut self, out: &mut Vec<u8>) {
        let mut lines = vec![
            format!("; warpslice machine = {} {}", self.preset, self.flavour.name()),
            format!(
                "; warpslice machine axes = {} (linear mm, rotary degrees{})",
                self.limits
                    .iter()
                    .map(|l| if l.rotary {
                        format!("{}°", l.name)
                    } else {
                        l.name.clone()
                    })
                    .collect::<Vec<_>>()
                    .join(" "),
                if self.offsets.iter().any(|&o| o > 0.0) {
                    ""
                } else {
                    ", no offsets"
                }
            ),
            format!(
                "; warpslice feed = {}",
                match self.feed {
                    FeedMode::Xyz => "xyz (F = tool-tip speed; the firmware must count only X Y Z)",
                    FeedMode::AllAxes =>
                        "all-axes (F scaled so rotary degrees counted in the move length keep the tip speed)",
                    FeedMode::InverseTime => "inverse-time (G93 in the printed region, G94 after it)",
                }
            ),
            format!(
                "; warpslice interpolation bound = {} mm / {} deg",
                self.bounds.max_position_mm, self.bounds.max_angle_deg
            ),
        ];
        let d = self.report.z_axes_offset_mm;
        if d > 0.0 {
            let names: Vec<&str> = self
                .limits
                .iter()
                .zip(&self.offsets)
                .filter(|(_, &o)| o > 0.0)
                .map(|(l, _)| l.name.as_str())
                .collect();
            lines.push(format!(
                "; warpslice z axes offset = {d} mm: RepRapFirmware clamps negative axis values, so {} are written as raw + {d} mm (G92 at the start of the printed region, removed at its end)",
                names.join(" ")
            ));
        }
        lines.extend(self.flavour.header(&self.limits, self.feed));
        for l in lines {
            out.extend_from_slice(l.as_bytes());
            out.push(b'\n');
        }
    }

    fn check_job(&mut self, job: &Job, model_to_output: DVec3) -> Result<(), EmitError> {
        self.machine
            .check_job(job, model_to_output)
            .map_err(EmitError::new)
    }

    fn begin_region(&mut self, out: &mut Vec<u8>, p: DVec3, n: DVec3) -> Result<(), EmitError> {
        if self.feed == FeedMode::InverseTime {
            out.extend_from_slice(b"G93 ; warpslice: inverse-time feed (F = 1/minutes)\n");
        }
        self.prev = self
            .machine
            .inverse(p, n, None)
            .ok()
            .map(|axes| Pose { axes, p, n });
        if self.offsets.iter().any(|&o| o > 0.0) {
            if let Some(prev) = &self.prev {
                out.extend_from_slice(b"G92");
                for (i, l) in self.limits.iter().enumerate() {
                    if self.offsets[i] > 0.0 {
                        out.push(b' ');
                        out.extend_from_slice(l.name.as_bytes());
                        push_mm(out, prev.axes[i] + self.offsets[i]);
                    }
                }
                out.extend_from_slice(b" ; warpslice: z axes offset (level bed, raw + offset)\n");
            }
        }
        Ok(())
    }

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
            let f = if self.feed == FeedMode::InverseTime {
                tp.f / tp.e.abs()
            } else {
                tp.f
            };
            self.write_feed(out, f);
            out.push(b'\n');
            return Ok(());
        }
        if !tp.travel {
            if self.last_layer.is_some_and(|l| l != tp.layer) {
                self.reset_rotary(out);
            }
            self.last_layer = Some(tp.layer);
        }
        self.move_to(out, tp, relative_e).map_err(EmitError::new)
    }

    fn end_region(&mut self, out: &mut Vec<u8>) -> Result<(), EmitError> {
        if let Some(prev) = self.prev.clone() {
            if prev.n.angle_between(DVec3::Z) > 0.0 {
                out.extend_from_slice(b"; warpslice: tool axis back to vertical\n");
                let tp = ToolPoint {
                    p: prev.p,
                    n: DVec3::Z,
                    e: 0.0,
                    f: DEFAULT_TRAVEL_FEED,
                    layer: 0,
                    feature: Feature::Unknown,
                    travel: true,
                };
                self.move_to(out, &tp, true).map_err(EmitError::new)?;
            }
            if self.offsets.iter().any(|&o| o > 0.0) {
                if let Some(prev) = &self.prev {
                    out.extend_from_slice(b"G92");
                    for (i, l) in self.limits.iter().enumerate() {
                        if self.offsets[i] > 0.0 {
                            out.push(b' ');
                            out.extend_from_slice(l.name.as_bytes());
                            push_mm(out, prev.axes[i]);
                        }
                    }
                    out.extend_from_slice(b" ; warpslice: z axes offset removed\n");
                }
                for o in self.offsets.iter_mut() {
                    *o = 0.0;
                }
            }
        }
        if self.feed == FeedMode::InverseTime {
            out.extend_from_slice(b"G94 ; warpslice: feed back to mm/min\n");
        }
        Ok(())
    }

    fn lift_from_unknown(
        &mut self,
        _out: &mut Vec<u8>,
        _z: f64,
        _f: f64,
        command: &str,
    ) -> Result<(), EmitError> {
        Err(EmitError::new(MachineError::PoseLost {
            machine: self.preset.clone(),
            command: command.to_string(),
        }))
    }

    fn reset_e(&mut self, v: f64) {
        self.ew.reset(v);
    }

    fn current_e(&self) -> f64 {
        self.ew.current()
    }

    fn finish(&mut self, out: &mut Vec<u8>) {
        let r = self.report();
        let line = format!(
            "; warpslice machine report: {} moves in, {} out; worst interpolation {:.5} mm / {:.4} deg; largest dropped tool-axis angle {:.3} deg; {} rotate-arounds ({:.5} mm E carried past the seam); {} rotary resets; {} re-poses\n",
            r.moves_in, r.moves_out, r.worst_position_mm, r.worst_angle_deg, r.worst_dropped_deg,
            r.rotate_arounds, r.e_skipped_mm, r.rotary_resets, r.reposes
        );
        out.extend_from_slice(line.as_bytes());
    }

    fn machine_report(&self) -> Option<MachineReport> {
        Some(self.report())
    }
}
