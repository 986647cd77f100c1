//! [`MachineEmitter`]: the unwarp driver's [`Emitter`] for a 4/5-axis machine.
//!
//! For every toolpath point (output frame tip `p`, tool axis `n`) the emitter runs the
//! machine's inverse kinematics seeded with the previous axes (continuity, branch), splits the
//! move in machine space ([`super::tessellate::tessellate_planned`]: the firmware's linear axis interpolation stays
//! within 0.02 mm / 0.1° of the intended path), computes F per [`FeedMode`] and writes
//! `G1 <axis letters> E F` lines (linear axes in mm, rotary axes in degrees, 3 decimals; E via
//! [`EWriter`], the move's filament shared among its pieces by tip length without drift).
//! Retractions in place are `G1 E F`.
//!
//! ## Region boundaries
//! - [`Emitter::begin_region`] (the head is at the slicer's position, tool vertical): the
//!   previous axes are `inverse(p, +Z)`; `G93` for inverse-time feed.
//! - [`Emitter::end_region`] (after the driver's lift): a tessellated travel back to the
//!   vertical tool axis at the same tip point (the rest pose), `G94` after inverse-time feed.
//!
//! ## Outside the region
//! Unless the machine's axes are the output's X Y Z and the output is not moved
//! ([`Emitter::converts_outside`]), the unwarp hands the start and end G-code's moves over as
//! points with tool axis +Z ([`crate::unwarp::outside`]): they are written like any point, with
//! `tip` feed where `inverse-time` is asked for (`G94` is in force there), and the pose carries
//! over into the region (`begin_region` keeps it). After homing, a move giving only some of
//! X Y Z is written with the axes that depend on those alone at the rest pose
//! ([`rest_dependence`]), or not at all ([`Emitter::outside_partial`]).
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
//!   "rot-revolv=0 resets at layer change the rotation angle to mod(360)") — except for
//!   Klipper, whose `G92` sets only X Y Z E: there the axis is written unwrapped, no reset.
//! - **Triple-Z bed** (seed 001): the Z motors are written raw; their travel goes below zero
//!   (see [`super::threez`]) and the flavour's header gives the firmware that minimum.
//! - **B head**: the collision clip is in the kinematics; the ramp and z-offset come from the
//!   unwarp options.
//!
//! ## Reach and speeds
//! Every G1 goes through `write_g1`, which first checks its raw axes against the machine
//! file's travel and the rotary ranges ([`super::reach`]): a value outside is
//! [`MachineError::Travel`] with the output line it would have been (1-based: the lines the
//! caller reports through [`Emitter::lines_written`] plus those this call wrote) and the input
//! line of the toolpath point ([`ToolPoint::line`]). It then adds the move to the speed
//! accounting ([`super::speed`]: the firmware's duration at the F in force, slowed where an
//! axis would exceed its `max_feed`; in `tip` mode [`super::feed`] lowers F itself and the
//! moves it slowed are counted). The report and the file's last comment line give the
//! margins, the slowed moves and the estimated time. A `G1` whose written axis words and E
//! equal the previous line's (a move the firmware reads as none) is not written.
//!
//! ## Branch flips
//! Where the kinematics has two solutions for one pose ([`Machine::other_branch`]: the A/B
//! table's `(A, B)` and `(−A, B ± 180°)`), the branch the path is on is the one its first pose
//! took, kept by continuity. Near a pole the two differ in where the table carries the tip: on
//! a 100 mm tall part at 30° tilt, Y ≈ ±50 mm. When a move would take a linear axis past its
//! travel on the current branch and the other branch carries the whole move within it, the
//! emitter flips before the move, as a swing lift ([`SWING_TAG`], counted and listed with the
//! swings): it lifts the tip, turns the rotary axes to the other solution in steps of at most
//! [`FLIP_STEP_DEG`] with the tip held over the same point, and sets down. Otherwise the
//! travel error stands.
//!
//! ## Errors
//! Unreachable orientations, axis limits and travel are returned from [`Emitter::point`]; the
//! driver stops with `UnwarpError::Emit` naming the G-code line. Never a silently wrong file.

use glam::DVec3;

use super::angles::wrap180;
use super::axis_buf::AxisBuf;
use super::config::{build as build_config, input_for, ConfigInput};
use super::feed::{fastest, output_feed, FeedMode, FeedMove};
use super::flavour::Flavour;
use super::reach::Reach;
use super::speed::AxisSpeeds;
use super::tessellate::{
    tessellate_planned, Bounds, MachineMove, Plan, TessellationReport, DEFAULT_BOUNDS,
};
use super::{AxisLimit, Machine, MachineError, MachineSpec};
use crate::emit::clearance::{segment_distance, HeadProfile, Printed, HEAD_CLEARANCE_MM};
use crate::emit::{EWriter, EmitError, Emitter, MachineReport, SwingPlace, DEFAULT_TRAVEL_FEED};
use crate::gcode::write::{push_e, push_fixed, push_mm, push_mm_read, written_value, MM_DECIMALS};
use crate::job::Job;
use crate::toolpath::{Feature, ToolPoint};

/// Lift of the tip for a single-revolution rotate-around, mm.
pub const ROTATE_AROUND_LIFT_MM: f64 = 1.0;
/// Decimals of F in inverse-time mode (F = 1/minutes can be small).
pub const INVERSE_TIME_DECIMALS: u32 = 5;
/// Trailing comment of the lines of a rotate-around (not toolpath points).
pub const ROTATE_AROUND_TAG: &str = "; rotate-around";
/// Trailing comment of the lines of a swing lift ([`SWING_RATE_DEG_PER_MM`]): lift, turn in
/// the air along the pieces the swing would have printed, set down.
pub const SWING_TAG: &str = "; swing-lift";

/// Feed of the move laying the filament a region's last lifted pieces carried at the region's
/// last pose, mm/min (the move has no length: the firmware times it by its E, a prime's pace;
/// the amount is a few µm of filament).
pub const CARRIED_E_FEED: f64 = 1200.0;

/// The tag of that line.
pub const CARRIED_E_TAG: &str = " ; warpslice: filament of the lifted pieces at the region's end";
/// A piece of a move whose rotary axes turn faster than this per mm of tip path
/// (the largest |Δ| of one rotary axis over the piece's tip length, °/mm; a piece with no tip
/// motion turns infinitely fast) is part of a **swing**: the tool axis circles a point less than
/// 180°/(π·600) ≈ 0.095 mm away, a cone's apex or a pole of the kinematics, where pax-5axis and
/// open5x-ab turn a rotary axis about 175° within 0.15 mm of extrusion (issue 10 §2,
/// "singularities"). Printed as written, the nozzle dwells on the part, extruding, for the
/// seconds the axis takes to turn.
pub const SWING_RATE_DEG_PER_MM: f64 = 600.0;
/// A run of consecutive swing pieces of one move whose rotary axes turn at least this much in
/// all (the largest summed |Δ| of one axis, degrees) is a swing lift: the head lifts
/// [`ROTATE_AROUND_LIFT_MM`] along +Z at the run's start, turns through the run's poses in the
/// air, and sets down at its end; the run's filament goes to the next extruding piece, as a
/// rotate-around's does. A shorter turn is printed as is.
pub const SWING_MIN_TURN_DEG: f64 = 45.0;
/// Two swing runs of one move with less tip path than this between them are one swing lift,
/// mm (the tool axis circling an apex turns slower for a piece or two where the path is
/// farthest from it: lifting, setting down and lifting again there gains nothing).
pub const SWING_JOIN_MM: f64 = 0.1;

/// The largest turn of one rotary axis per line of a branch flip (see the module's "Branch
/// flips"), degrees. Each line is a linear interpolation of the axes with the tip held over one
/// point at both ends: at R mm from the rotary axes the tip leaves it by at most
/// R·(1 − cos(Δ/2)) ≈ R·Δ²/8, 0.015 mm at R = 100 mm, in the air above the part.
pub const FLIP_STEP_DEG: f64 = 2.0;

/// Trailing comment of an in-place reorientation (a held rotary axis catching up).
pub const REORIENT_TAG: &str = "; reorient";
/// Trailing comment of a move where the splitting hit its depth limit: the interpolation bound
/// is not proven there (the report counts these and gives the error measured).
pub const DISCONTINUITY_TAG: &str = "; discontinuity";

/// The steps of a branch flip ([`MachineEmitter::flip_air`]).
struct Flip {
    /// Along the tool axis, mm.
    lift: f64,
    /// Each line's axes and tip: the lift, then each step's.
    air: Vec<(Vec<f64>, DVec3)>,
    /// The largest turn of one rotary axis, degrees.
    turn: f64,
}

/// A branch flip found by [`MachineEmitter::flipped`]: the pose on the other branch, the
/// lifted turn to it, and the move from it with its swing runs and tessellation report.
struct Flipped {
    pose: Pose,
    flip: Flip,
    moves: Vec<MachineMove>,
    swings: Vec<SwingRun>,
    tess: TessellationReport,
}

/// The previous pose: raw axes, tip, tool axis.
#[derive(Clone, Debug)]
struct Pose {
    axes: AxisBuf,
    p: DVec3,
    n: DVec3,
}

/// The axis values of the last `G1` written: as given, and as the firmware reads them.
struct Written {
    raw: AxisBuf,
    read: AxisBuf,
}

/// The emitter (see the module documentation).
pub struct MachineEmitter {
    machine: Box<dyn Machine>,
    limits: Vec<AxisLimit>,
    /// Each axis' largest feed (the machine file's `max_feed`; `+inf`: none), machine order.
    max_feed: Vec<f64>,
    /// The axes as the firmware is configured (its length rule's rotary flags:
    /// `firmware_linear_axes` count as linear).
    rule_limits: Vec<AxisLimit>,
    /// What the header's configuration summary is built from.
    config: ConfigInput,
    preset: String,
    flavour: Flavour,
    feed: FeedMode,
    /// The interpolation bounds and what the splitting needs of the machine ([`Plan`]).
    plan: Plan,
    /// Unlimited rotary axes (reset modulo 360° at a layer change).
    unlimited: Vec<bool>,
    ew: EWriter,
    last_f: Option<f64>,
    /// The axis values the last `G1` of this region wrote, as the firmware reads them (rounded
    /// to [`MM_DECIMALS`]); `None` at a region's start. A move that would write them again,
    /// with no change of E either, is one the firmware reads as no move: not written.
    written_axes: Option<Written>,
    /// Moves not written because the firmware would read them as no move.
    dropped: u64,
    prev: Option<Pose>,
    last_layer: Option<u32>,
    tess: TessellationReport,
    report: MachineReport,
    /// Filament of a rotate-around's piece, given to the next extruding piece, mm.
    carry_e: f64,
    /// The E mode of the last extruding point (relative E), for carried filament laid later.
    relative_e: bool,
    /// Rotary axes (machine order), for [`swing_runs`].
    rotary: Vec<bool>,
    /// Every written move's axes inside their travel; the range written.
    reach: Reach,
    /// Moves slowed by an axis' largest feed; the time estimate.
    speeds: AxisSpeeds,
    /// Lines the output held before the current call ([`Emitter::lines_written`]).
    line_base: u64,
    /// `(start, upto, n)`: where in `out` the current call started writing, how far it has
    /// been scanned, and the lines in `out[start..upto]`; the next line written is output line
    /// `line_base + n + (lines in out[upto..]) + 1`.
    scan: (usize, usize, u64),
    /// The input line of the toolpath point being written.
    input_line: u64,
    /// Input line of each output line, when recorded ([`MachineEmitter::with_input_lines`]).
    input_lines: Option<crate::emit::InputLines>,
    /// The lines outside the printed region are converted ([`Emitter::converts_outside`]).
    convert_outside: bool,
    /// Outside the printed region (before [`Emitter::begin_region`], after
    /// [`Emitter::end_region`]): `G94` is in force whatever the feed mode.
    outside: bool,
    /// Which output coordinates (x, y, z) each axis depends on at the rest pose
    /// ([`rest_dependence`]), computed on the first partial move.
    rest_deps: Option<Vec<[bool; 3]>>,
    /// The head's clearance profile ([`super::head::clearance_profile`]): lifted turns and the
    /// unwarp's lifted travels clear the whole head.
    profile: HeadProfile,
}

/// A pose a lifted turn passes through in the air ([`MachineEmitter::lifted_turn`]): the tip
/// `p` and tool axis `n` on the path (lifted by the turn's lift when written), the axes that
/// seed the inverse kinematics (the piece's own: same rotary values, same branch), the tip
/// length of the move to it and its feed.
struct AirPose<'a> {
    p: DVec3,
    n: DVec3,
    seed: &'a [f64],
    tip_length: f64,
    f: f64,
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
        let rotary = limits.iter().map(|l| l.rotary).collect();
        let axis_bounds = spec.axis_bounds(&limits)?;
        let max_feed: Vec<f64> = axis_bounds.iter().map(|b| b.max_feed).collect();
        let speeds = AxisSpeeds::new(
            max_feed.clone(),
            axis_bounds.iter().map(|b| b.rotary).collect(),
        );
        let flavour = flavour.or(spec.flavour).unwrap_or_default();
        // a head that turns itself (not a part turned under it) tilts in its tool axis'
        // vertical plane
        let mut profile =
            super::head::clearance_profile(&spec.head()?, !machine.capabilities().moving_bed);
        profile.tilt_range = realised_tilt_range(machine.as_ref());
        let config = input_for(spec, machine.as_ref(), feed)?;
        flavour.check(machine.name(), &limits, feed)?;
        let rule_limits = limits
            .iter()
            .zip(&config.axes)
            .map(|(l, a)| AxisLimit {
                rotary: a.firmware_rotary,
                ..l.clone()
            })
            .collect();
        let unlimited = limits
            .iter()
            .map(|l| l.rotary && !(l.min.is_finite() && l.max.is_finite()))
            .collect();
        let report = MachineReport {
            machine: machine.name().to_string(),
            flavour: flavour.name().to_string(),
            feed,
            ..MachineReport::default()
        };
        let plan = Plan::new(machine.as_ref(), &DEFAULT_BOUNDS);
        Ok(MachineEmitter {
            plan,
            preset: machine.name().to_string(),
            machine,
            limits,
            max_feed,
            rule_limits,
            config,
            flavour,
            feed,
            unlimited,
            ew: EWriter::default(),
            last_f: None,
            written_axes: None,
            dropped: 0,
            prev: None,
            last_layer: None,
            carry_e: 0.0,
            relative_e: false,
            rotary,
            tess: TessellationReport::default(),
            report,
            reach: Reach::new(axis_bounds),
            speeds,
            line_base: 0,
            scan: (0, 0, 0),
            input_line: 0,
            input_lines: None,
            convert_outside: false,
            outside: true,
            rest_deps: None,
            profile,
        })
    }

    /// Record the input line of every output line (for the collision check's findings; a run
    /// per change of input line).
    pub fn with_input_lines(mut self, yes: bool) -> MachineEmitter {
        self.input_lines = yes.then(crate::emit::InputLines::default);
        self
    }

    /// Use other interpolation bounds (`--interpolation`, `--interpolation-caps`).
    pub fn with_bounds(mut self, bounds: Bounds) -> MachineEmitter {
        self.plan = Plan::new(self.machine.as_ref(), &bounds);
        self
    }

    /// The measurements so far.
    pub fn report(&self) -> MachineReport {
        let mut r = self.report.clone();
        let t = &self.tess;
        r.moves_in = t.moves_in as u64;
        r.moves_out = (t.moves_out as u64 + r.rotate_arounds * 2 + r.swing_lifts * 2)
            .saturating_sub(self.dropped);
        r.worst_position_mm = t.worst_position_mm;
        r.worst_angle_deg = t.worst_angle_deg;
        r.worst_dropped_deg = t.worst_dropped_deg;
        r.dropped_moves = t.dropped_moves as u64;
        r.depth_limited = t.depth_limited as u64;
        r.reposes = t.reposes as u64;
        r.axes = self.reach.report();
        for (a, &n) in r.axes.iter_mut().zip(&self.speeds.limited_by) {
            a.speed_limited_moves = n;
        }
        r.speed_limited_moves = self.speeds.limited;
        r.print_time_min = self.speeds.minutes;
        r.slowdown_min = self.speeds.slowdown_minutes;
        r
    }

    /// A call that writes G1 lines starts writing at the end of `out`.
    fn start_lines(&mut self, out: &[u8]) {
        self.scan = (out.len(), out.len(), 0);
    }

    /// Axis `i` at `value` is outside its travel, on the next line written to `out`, with the
    /// tip at `p`.
    fn travel_error(&mut self, out: &[u8], i: usize, value: f64, p: DVec3) -> MachineError {
        let b = &self.reach.bounds()[i];
        let (axis, min, max) = (b.name.clone(), b.min, b.max);
        MachineError::Travel {
            machine: self.preset.clone(),
            axis,
            value,
            min,
            max,
            output_line: self.next_output_line(out),
            input_line: self.input_line,
            p,
        }
    }

    /// The 1-based output line the next line written to `out` will be.
    fn next_output_line(&mut self, out: &[u8]) -> u64 {
        let (start, upto, n) = self.scan;
        let upto = upto.clamp(start, out.len());
        let more = out[upto..].iter().filter(|&&b| b == b'\n').count() as u64;
        self.scan = (start, out.len(), n + more);
        self.line_base + n + more + 1
    }

    /// The feed mode in force: outside the printed region `G94` (mm/min) is, so inverse-time
    /// feed is written as `tip` there.
    fn feed_now(&self) -> FeedMode {
        if self.outside && self.feed == FeedMode::InverseTime {
            FeedMode::Tip
        } else {
            self.feed
        }
    }

    fn write_feed(&mut self, out: &mut Vec<u8>, f: f64) {
        if !(f.is_finite() && f > 0.0) {
            return;
        }
        if self.feed_now() == FeedMode::InverseTime {
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
        if let Err(i) = self.reach.check(axes) {
            return Err(self.travel_error(out, i, axes[i], p));
        }
        // the axis words, and the move as the firmware reads them: the written (rounded)
        // values, from the same rounding
        let start = out.len();
        out.extend_from_slice(b"G1");
        let to_read = AxisBuf::from_fn(axes.len(), |i| {
            out.push(b' ');
            out.extend_from_slice(self.limits[i].name.as_bytes());
            push_mm_read(out, axes[i])
        });
        let e_before = self.ew.current();
        let e_word = e.map(|(de, relative)| self.ew.advance(de, relative));
        if self.written_axes.as_ref().map(|w| &w.read) == Some(&to_read)
            && self.ew.current() == e_before
        {
            // every axis word as the last line wrote it and E unchanged: the firmware reads no
            // move (the tip moved less than the written step; a filament change below the E
            // step stays in the E writer's exact total): the line is taken back
            out.truncate(start);
            self.dropped += 1;
            return Ok(());
        }
        let de = e.map_or(0.0, |(de, _)| de);
        if let Some(v) = e_word {
            out.extend_from_slice(b" E");
            push_e(out, v);
        }
        let mode = self.feed_now();
        // most moves start where the last line ended: its values as read are known (borrowed,
        // not copied: the feed, its time and the firmware's length are all read from them here)
        let computed;
        let from_read: &[f64] = match &self.written_axes {
            Some(w) if crate::num::same_bits(&w.raw, from) => &w.read,
            _ => {
                computed = AxisBuf::from_fn(from.len(), |i| written_value(from[i], MM_DECIMALS));
                &computed
            }
        };
        let firmware_length =
            self.flavour
                .length_rule()
                .length(&self.rule_limits, from_read, &to_read, de);
        let feed = output_feed(
            mode,
            &FeedMove {
                from,
                to: axes,
                tip_length,
                firmware_length,
                f,
                fastest: fastest(&self.max_feed, from_read, &to_read),
            },
        );
        let fo = feed.f;
        // the feed in force: the one written, else the modal one
        let f_fw = if fo.is_finite() && fo > 0.0 {
            fo
        } else {
            self.last_f.unwrap_or(0.0)
        };
        if let Some((axis, minutes)) = feed.slowed {
            self.speeds.add_slowed(axis, minutes);
        }
        // timed as the firmware reads it: the written values
        self.speeds
            .add_move(mode, from_read, &to_read, f_fw, firmware_length);
        self.write_feed(out, fo);
        match &mut self.written_axes {
            // the same machine writes the same number of axes on every line
            Some(w) if w.raw.len() == axes.len() => {
                w.raw.copy_from_slice(axes);
                w.read = to_read;
            }
            w => {
                *w = Some(Written {
                    raw: AxisBuf::from_slice(axes),
                    read: to_read,
                })
            }
        }
        out.extend_from_slice(tag.as_bytes());
        out.push(b'\n');
        Ok(())
    }

    /// `G92` the unlimited rotary axes back into ±180° (layer change); not for Klipper, whose
    /// `G92` sets X Y Z E only (the axis stays unwrapped).
    fn reset_rotary(&mut self, out: &mut Vec<u8>) {
        if !self.flavour.resets_extra_axes() {
            return;
        }
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
                if let Some(wa) = self.written_axes.as_mut() {
                    wa.raw[i] = w;
                    wa.read[i] = written_value(w, MM_DECIMALS);
                }
                self.report.rotary_resets += 1;
            }
        }
    }

    /// Filament carried from pieces lifted over (a swing lift or a rotate-around) that no
    /// extruding piece took before a travel, a retraction or the region's end: laid at the last
    /// pose, before the head leaves it (a deposit written with the pose's axes, not a prime),
    /// so the volume is kept. Full matrix, sm_cube × conic-in-30 on rotbot: the region's last
    /// 0.005 mm of filament was lost before.
    fn lay_carried_e(&mut self, out: &mut Vec<u8>) -> Result<(), MachineError> {
        let Some(prev) = self.prev.clone().filter(|_| self.carry_e != 0.0) else {
            return Ok(());
        };
        let e = Some((std::mem::take(&mut self.carry_e), self.relative_e));
        self.write_g1(
            out,
            &prev.axes,
            &prev.axes,
            prev.p,
            e,
            0.0,
            CARRIED_E_FEED,
            CARRIED_E_TAG,
        )
    }

    /// [`Emitter::point`], with the printed material for lifted turns when known.
    fn point_at(
        &mut self,
        out: &mut Vec<u8>,
        tp: &ToolPoint,
        relative_e: bool,
        printed: Option<&dyn Printed>,
    ) -> Result<(), EmitError> {
        self.start_lines(out);
        self.input_line = tp.line;
        if self.input_lines.is_some() {
            let next = self.next_output_line(out);
            if let Some(m) = self.input_lines.as_mut() {
                m.push(next, tp.line);
            }
        }
        if tp.travel {
            self.lay_carried_e(out).map_err(EmitError::new)?;
        } else {
            // the E mode of the file's extrusions (a travel the unwarp plans itself may say
            // relative in an absolute file: it writes no E)
            self.relative_e = relative_e;
        }
        if tp.travel && tp.e != 0.0 {
            let v = self.ew.advance(tp.e, relative_e);
            out.extend_from_slice(b"G1 E");
            push_e(out, v);
            let f = if self.feed_now() == FeedMode::InverseTime {
                tp.f / tp.e.abs()
            } else {
                tp.f
            };
            self.write_feed(out, f);
            self.speeds.add_extruder_move(self.feed_now(), tp.e, f);
            out.push(b'\n');
            return Ok(());
        }
        if !tp.travel && !self.outside {
            if self.last_layer.is_some_and(|l| l != tp.layer) {
                self.reset_rotary(out);
            }
            self.last_layer = Some(tp.layer);
        }
        self.move_to(out, tp, relative_e, printed)
            .map_err(EmitError::new)
    }

    /// How far a lifted turn lifts the tip along +Z: [`ROTATE_AROUND_LIFT_MM`], or more where
    /// the head would not clear the printed material (`printed`; `None`: the tip's 1 mm) by
    /// [`HEAD_CLEARANCE_MM`] at every pose of the turn: the head's profile at the largest tilt of
    /// `from` and `poses`, over the segment from `from`'s tip to the last pose's, padded by the
    /// farthest pose from it, set on the lowest of their tips.
    fn turn_lift(
        &self,
        printed: Option<&dyn Printed>,
        from: &Pose,
        poses: &[(DVec3, DVec3)],
    ) -> f64 {
        let Some(printed) = printed else {
            return ROTATE_AROUND_LIFT_MM;
        };
        let (a, b) = (from.p, poses.last().map_or(from.p, |q| q.0));
        let (mut pad, mut tilt, mut low) = (0.0f64, tilt_of(from.n), from.p.z);
        for &(p, n) in poses {
            pad = pad.max(segment_distance(p.truncate(), a.truncate(), b.truncate()));
            tilt = tilt.max(tilt_of(n));
            low = low.min(p.z);
        }
        let z = printed.head_clear_z(&self.profile, a.truncate(), b.truncate(), pad, tilt);
        ROTATE_AROUND_LIFT_MM.max(z + HEAD_CLEARANCE_MM - low)
    }

    /// The axes of a lifted turn's lines ([`MachineEmitter::lifted_turn`]): the lift at
    /// `from`'s pose, then each of `poses` lifted by `lift` (`inverse(p + lift, n)` seeded with
    /// the pose's own axes, so every rotary value is the pose's).
    fn air_axes(
        &self,
        from: &Pose,
        lift: f64,
        poses: &[AirPose<'_>],
    ) -> Result<Vec<Vec<f64>>, MachineError> {
        let up = DVec3::Z * lift;
        let mut axes = Vec::with_capacity(poses.len() + 1);
        axes.push(
            self.machine
                .inverse(from.p + up, from.n, Some(&from.axes))?,
        );
        for q in poses {
            axes.push(self.machine.inverse(q.p + up, q.n, Some(q.seed))?);
        }
        Ok(axes)
    }

    /// A lifted turn: from `from`, lift the tip by `lift` along +Z with the pose held (feed
    /// `f_lift`), pass through `poses` each lifted the same way ([`MachineEmitter::air_axes`]),
    /// and set down on `land` (tip `land_p`, feed `f_lift`). Nothing is extruded. Every line
    /// ends with `tag`. The one shape of a rotate-around, a swing lift and a branch flip.
    #[allow(clippy::too_many_arguments)]
    fn lifted_turn(
        &mut self,
        out: &mut Vec<u8>,
        from: &Pose,
        lift: f64,
        f_lift: f64,
        poses: &[AirPose<'_>],
        land: (&[f64], DVec3),
        tag: &str,
    ) -> Result<(), MachineError> {
        let up = DVec3::Z * lift;
        let air = self.air_axes(from, lift, poses)?;
        self.write_g1(
            out,
            &from.axes,
            &air[0],
            from.p + up,
            None,
            lift,
            f_lift,
            tag,
        )?;
        for (q, w) in poses.iter().zip(air.windows(2)) {
            self.write_g1(out, &w[0], &w[1], q.p + up, None, q.tip_length, q.f, tag)?;
        }
        let at = &air[air.len() - 1];
        self.write_g1(out, at, land.0, land.1, None, lift, f_lift, tag)
    }

    /// The lift and the lifted poses of a swing lift from `from` over the pieces `run`.
    fn swing_air<'a>(
        &self,
        from: &Pose,
        run: &'a [MachineMove],
        tp: &ToolPoint,
        printed: Option<&dyn Printed>,
    ) -> (f64, Vec<AirPose<'a>>) {
        let at: Vec<(DVec3, DVec3)> = run.iter().map(|m| (m.p, m.n)).collect();
        let lift = self.turn_lift(printed, from, &at);
        let poses = run
            .iter()
            .map(|m| AirPose {
                p: m.p,
                n: m.n,
                seed: &m.axes,
                tip_length: m.tip_length,
                f: tp.f.max(m.f),
            })
            .collect();
        (lift, poses)
    }

    /// Lifted turn-around to `to` (a single-revolution axis crosses its seam), at feed `f`.
    fn rotate_around(
        &mut self,
        out: &mut Vec<u8>,
        from: &Pose,
        to: &Pose,
        f: f64,
        printed: Option<&dyn Printed>,
    ) -> Result<(), MachineError> {
        let lift = self.turn_lift(printed, from, &[(to.p, to.n)]);
        let pose = AirPose {
            p: to.p,
            n: to.n,
            seed: &to.axes,
            tip_length: (to.p - from.p).length(),
            f,
        };
        let land = (&to.axes[..], to.p);
        self.lifted_turn(out, from, lift, f, &[pose], land, ROTATE_AROUND_TAG)?;
        self.report.rotate_arounds += 1;
        Ok(())
    }

    /// A swing lift ([`SWING_MIN_TURN_DEG`]): a lifted turn from `from` through the poses of
    /// `run` (the turn the swing would have printed), set down on the run's last pose. The
    /// run's filament goes to the next extruding piece. Each place goes into the report.
    fn swing_lift(
        &mut self,
        out: &mut Vec<u8>,
        from: &Pose,
        run: &[MachineMove],
        turn_deg: f64,
        tp: &ToolPoint,
        printed: Option<&dyn Printed>,
    ) -> Result<(), MachineError> {
        let output_line = self.next_output_line(out);
        let (lift, poses) = self.swing_air(from, run, tp, printed);
        let last = &run[run.len() - 1];
        self.lifted_turn(
            out,
            from,
            lift,
            tp.f,
            &poses,
            (&last.axes, last.p),
            SWING_TAG,
        )?;
        let tip: f64 = run.iter().map(|m| m.tip_length).sum();
        for m in run {
            // piece by piece, in order (the E written after is the same bits as before)
            self.carry_e += m.e;
        }
        self.report.swing_lifts += 1;
        self.report.swing_skipped_mm += tip;
        self.report.swings.push(SwingPlace {
            output_line,
            input_line: self.input_line,
            layer: tp.layer,
            turn_deg,
            tip_mm: tip,
        });
        Ok(())
    }

    /// Whether `axes` lie within the travel.
    fn in_travel(&self, axes: &[f64]) -> bool {
        self.reach.outside(axes).next().is_none()
    }

    /// Whether the move `moves` from `prev` stays within the travel: its pieces, and the
    /// lifted turns of its swing runs `swings` (lifted along +Z, they reach farther on a tilted
    /// table).
    fn move_in_travel(
        &self,
        prev: &Pose,
        moves: &[MachineMove],
        swings: &[SwingRun],
        tp: &ToolPoint,
        printed: Option<&dyn Printed>,
    ) -> bool {
        if !moves.iter().all(|m| self.in_travel(&m.axes)) {
            return false;
        }
        swings.iter().all(|run| {
            let from = match run.pieces.start {
                0 => prev.clone(),
                k => Pose {
                    axes: AxisBuf::from_slice(&moves[k - 1].axes),
                    p: moves[k - 1].p,
                    n: moves[k - 1].n,
                },
            };
            let (lift, poses) = self.swing_air(&from, &moves[run.pieces.clone()], tp, printed);
            self.air_axes(&from, lift, &poses)
                .is_ok_and(|air| air.iter().all(|a| self.in_travel(a)))
        })
    }

    /// The previous pose on the machine's other branch, the flip to it and the move to `tp`
    /// from it with its tessellation report (`self.tess` plus the move), when the flip's lifted
    /// turn and the move stay within the travel (the module's "Branch flips"); `None` otherwise.
    fn flipped(
        &self,
        prev: &Pose,
        tp: &ToolPoint,
        printed: Option<&dyn Printed>,
    ) -> Option<Flipped> {
        let alt = self.machine.other_branch(prev.p, prev.n, &prev.axes)?;
        if !self.in_travel(&alt) {
            return None;
        }
        let pose = Pose {
            axes: AxisBuf::from_slice(&alt),
            p: prev.p,
            n: prev.n,
        };
        let flip = self.flip_air(prev, &pose.axes, printed).ok()?;
        if !flip.air.iter().all(|(a, _)| self.in_travel(a)) {
            return None;
        }
        let mut tess = self.tess;
        let moves = tessellate_planned(
            self.machine.as_ref(),
            &self.plan,
            (&pose.axes, prev.p, prev.n),
            tp,
            &mut tess,
        )
        .ok()?;
        let swings = swing_runs(&pose.axes, &moves, &self.rotary);
        if !self.move_in_travel(&pose, &moves, &swings, tp, printed) {
            return None;
        }
        Some(Flipped {
            pose,
            flip,
            moves,
            swings,
            tess,
        })
    }

    /// The lifted turn of a branch flip from `from` to the axes `to` (the same tip and tool
    /// axis on the other branch): the rotary axes interpolated in steps of at most
    /// [`FLIP_STEP_DEG`], each step's tool axis n the one those axes give, the tip at
    /// `p + L·n` — lifted along the tool axis, so a table's nozzle only rises and the table
    /// carries the part no farther out than the turn's ends do (lifting along +Z would carry it
    /// L·sin(tilt) farther: past the travel at the pole of a tall part). L is the
    /// [`MachineEmitter::turn_lift`] over those tips, divided by the cosine of the largest tilt
    /// so every tip is at least that high.
    fn flip_air(
        &self,
        from: &Pose,
        to: &[f64],
        printed: Option<&dyn Printed>,
    ) -> Result<Flip, MachineError> {
        let turn = (0..from.axes.len())
            .filter(|&i| self.rotary[i])
            .map(|i| (to[i] - from.axes[i]).abs())
            .fold(0.0, f64::max);
        let count = (turn / FLIP_STEP_DEG).ceil().max(1.0) as usize;
        let mut steps = vec![(from.axes.to_vec(), from.n)];
        for k in 1..=count {
            let s = k as f64 / count as f64;
            let axes: Vec<f64> = (0..from.axes.len())
                .map(|i| from.axes[i] + (to[i] - from.axes[i]) * s)
                .collect();
            let n = self.machine.forward(&axes)?.1;
            steps.push((axes, n));
        }
        let cos = steps
            .iter()
            .map(|(_, n)| n.z / n.length())
            .fold(1.0, f64::min)
            .max(0.1);
        // twice: the second pass pads by the tips' spread at the first pass's lift
        let mut lift = 0.0;
        for _ in 0..2 {
            let at: Vec<(DVec3, DVec3)> = steps
                .iter()
                .map(|(_, n)| (from.p + (*n * lift).with_z(0.0), *n))
                .collect();
            lift = f64::max(lift, self.turn_lift(printed, from, &at) / cos);
        }
        let mut air = Vec::with_capacity(steps.len());
        for (seed, n) in &steps {
            let tip = from.p + *n * lift;
            air.push((self.machine.inverse(tip, *n, Some(seed))?, tip));
        }
        Ok(Flip { lift, air, turn })
    }

    /// The branch flip `flip` from `from` to `to` ([`MachineEmitter::flip_air`]): lift along
    /// the tool axis, turn, set down, with nothing extruded, every line tagged [`SWING_TAG`] and
    /// the place listed with the swing lifts.
    fn flip_branch(
        &mut self,
        out: &mut Vec<u8>,
        from: &Pose,
        to: &Pose,
        flip: &Flip,
        tp: &ToolPoint,
    ) -> Result<(), MachineError> {
        let output_line = self.next_output_line(out);
        let mut at = (&from.axes[..], from.p);
        for (axes, tip) in &flip.air {
            let length = (*tip - at.1).length();
            self.write_g1(out, at.0, axes, *tip, None, length, tp.f, SWING_TAG)?;
            at = (axes, *tip);
        }
        self.write_g1(out, at.0, &to.axes, to.p, None, flip.lift, tp.f, SWING_TAG)?;
        self.report.swing_lifts += 1;
        self.report.swings.push(SwingPlace {
            output_line,
            input_line: self.input_line,
            layer: tp.layer,
            turn_deg: flip.turn,
            tip_mm: 0.0,
        });
        Ok(())
    }

    /// Move from the previous pose to `tp` (tessellated).
    fn move_to(
        &mut self,
        out: &mut Vec<u8>,
        tp: &ToolPoint,
        relative: bool,
        printed: Option<&dyn Printed>,
    ) -> Result<(), MachineError> {
        let Some(prev) = self.prev.clone() else {
            let mut axes = self.machine.inverse(tp.p, tp.n, None)?;
            if self.reach.outside(&axes).next().is_some() {
                // the first pose: the other branch when only it is within the travel
                if let Some(alt) = self.machine.other_branch(tp.p, tp.n, &axes) {
                    if self.reach.outside(&alt).next().is_none() {
                        axes = alt;
                    }
                }
            }
            let e = (!tp.travel).then_some((tp.e, relative));
            self.write_g1(out, &axes, &axes, tp.p, e, 0.0, tp.f, "")?;
            self.prev = Some(Pose {
                axes: AxisBuf::from_slice(&axes),
                p: tp.p,
                n: tp.n,
            });
            return Ok(());
        };
        // the report counts the move as written: on this branch, or on the other after a flip
        let mut tess = self.tess;
        let mut moves = tessellate_planned(
            self.machine.as_ref(),
            &self.plan,
            (&prev.axes, prev.p, prev.n),
            tp,
            &mut tess,
        )?;
        let mut prev = prev;
        // extruding or not: a travel's turn in place (a held axis catching up at the end of a
        // planar skirt) is done in the air too
        let mut swings = swing_runs(&prev.axes, &moves, &self.rotary);
        if !self.move_in_travel(&prev, &moves, &swings, tp, printed) {
            if let Some(f) = self.flipped(&prev, tp, printed) {
                self.flip_branch(out, &prev, &f.pose, &f.flip, tp)?;
                (prev, moves, swings, tess) = (f.pose, f.moves, f.swings, f.tess);
            }
        }
        self.tess = tess;
        let mut from = prev.clone();
        let mut k = 0;
        while k < moves.len() {
            if let Some(run) = swings.iter().find(|r| r.pieces.start == k) {
                self.swing_lift(
                    out,
                    &from,
                    &moves[run.pieces.clone()],
                    run.turn_deg,
                    tp,
                    printed,
                )?;
                let last = &moves[run.pieces.end - 1];
                from = Pose {
                    axes: AxisBuf::from_slice(&last.axes),
                    p: last.p,
                    n: last.n,
                };
                k = run.pieces.end;
                continue;
            }
            let m = &moves[k];
            k += 1;
            if m.rotate_around {
                // the piece turned around in the air (≤ SEAM_PIECE_MM): its filament goes to
                // the next extruding piece, so the volume is kept
                self.report.e_skipped_mm += m.e;
                if !m.travel {
                    self.carry_e += m.e;
                }
                let to = Pose {
                    axes: AxisBuf::from_slice(&m.axes),
                    p: m.p,
                    n: m.n,
                };
                self.rotate_around(out, &from, &to, tp.f.max(m.f), printed)?;
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
                axes: AxisBuf::from_slice(&m.axes),
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
                "; warpslice machine axes = {} (linear mm, rotary degrees, no offsets)",
                self.limits
                    .iter()
                    .map(|l| if l.rotary {
                        format!("{}°", l.name)
                    } else {
                        l.name.clone()
                    })
                    .collect::<Vec<_>>()
                    .join(" "),
            ),
            format!(
                "; warpslice feed = {}",
                match self.feed {
                    FeedMode::Tip =>
                        "tip (F = tool-tip feed × the move's length by the firmware's own rule / its tip length: every move takes tip length / tip feed)",
                    FeedMode::Xyz => "xyz (F = tool-tip speed; the firmware must count only X Y Z)",
                    FeedMode::AllAxes =>
                        "all-axes (F scaled so rotary degrees counted in the move length keep the tip speed)",
                    FeedMode::InverseTime => "inverse-time (G93 in the printed region, G94 after it)",
                }
            ),
            format!(
                "; warpslice interpolation bound = {} mm / {} deg{}",
                self.plan.bounds().max_position_mm,
                self.plan.bounds().max_angle_deg,
                match (self.plan.bounds().max_step_mm, self.plan.bounds().max_step_deg) {
                    (Some(mm), Some(deg)) => format!("; moves capped at {mm} mm / {deg} deg"),
                    _ => String::new(),
                }
            ),
        ];
        lines.push(format!(
            "; warpslice machine travel (raw values, checked on every move) = {}",
            self.reach
                .bounds()
                .iter()
                .map(|b| {
                    let unit = if b.rotary { "deg" } else { "mm" };
                    let feed = if b.max_feed.is_finite() {
                        format!(" max {} {unit}/min", crate::num::fmt_shortest(b.max_feed))
                    } else {
                        " no feed limit".to_string()
                    };
                    if b.min.is_finite() || b.max.is_finite() {
                        format!("{} [{}, {}]{feed}", b.name, b.min, b.max)
                    } else {
                        format!("{} unlimited{feed}", b.name)
                    }
                })
                .collect::<Vec<_>>()
                .join(", ")
        ));
        // the firmware's configuration for the limits as checked (the kinematic ranges within
        // the file's travel): its summary
        let config = build_config(self.flavour, &self.config);
        let summary = config.header.len() > 1;
        lines.extend(config.header);
        if summary {
            lines.push(format!(
                ";   (the whole fragment for {}, ready to paste: --config-out FILE)",
                config.file
            ));
        }
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
        self.outside = false;
        if !self.convert_outside {
            // the slicer's lines before the region passed through (not this emitter's): the
            // head is where they left it, and the next G1 is always written
            self.written_axes = None;
            self.prev = self.machine.inverse(p, n, None).ok().map(|axes| Pose {
                axes: AxisBuf::from_slice(&axes),
                p,
                n,
            });
        }
        Ok(())
    }

    fn point(
        &mut self,
        out: &mut Vec<u8>,
        tp: &ToolPoint,
        relative_e: bool,
    ) -> Result<(), EmitError> {
        self.point_at(out, tp, relative_e, None)
    }

    fn point_over(
        &mut self,
        out: &mut Vec<u8>,
        tp: &ToolPoint,
        relative_e: bool,
        printed: &dyn Printed,
    ) -> Result<(), EmitError> {
        self.point_at(out, tp, relative_e, Some(printed))
    }

    fn head_profile(&self) -> Option<HeadProfile> {
        Some(self.profile.clone())
    }

    fn lines_written(&mut self, n: u64) {
        self.line_base = n;
    }

    fn end_region(&mut self, out: &mut Vec<u8>) -> Result<(), EmitError> {
        self.start_lines(out);
        self.lay_carried_e(out).map_err(EmitError::new)?;
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
                    line: self.input_line,
                };
                self.move_to(out, &tp, true, None).map_err(EmitError::new)?;
            }
        }
        if self.feed == FeedMode::InverseTime {
            out.extend_from_slice(b"G94 ; warpslice: feed back to mm/min\n");
            // the firmware's modal F is an inverse-time value now
            self.last_f = None;
        }
        self.outside = true;
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

    fn converts_outside(&mut self, moved: bool) -> bool {
        self.convert_outside = moved || !self.machine.axes_are_output_xyz();
        self.convert_outside
    }

    fn outside_pose_lost(&mut self) {
        self.prev = None;
        self.last_f = None;
        // homing moved the head: the next G1 is written even if its words equal the last ones
        self.written_axes = None;
    }

    fn forget_feed(&mut self) {
        self.last_f = None;
    }

    fn outside_partial(
        &mut self,
        out: &mut Vec<u8>,
        known: [Option<f64>; 3],
        e: Option<(f64, bool)>,
        f: f64,
    ) -> Result<bool, EmitError> {
        self.start_lines(out);
        self.prev = None;
        self.written_axes = None;
        let deps = self
            .rest_deps
            .get_or_insert_with(|| rest_dependence(self.machine.as_ref()))
            .clone();
        let is_known = |d: &[bool; 3]| (0..3).all(|k| !d[k] || known[k].is_some());
        let touches_known = |d: &[bool; 3]| (0..3).any(|k| d[k] && known[k].is_some());
        // an axis moved by a known coordinate must be set by known coordinates only
        if deps.iter().any(|d| touches_known(d) && !is_known(d)) {
            return Ok(false);
        }
        let write: Vec<usize> = (0..deps.len())
            .filter(|&i| touches_known(&deps[i]))
            .collect();
        if write.is_empty() {
            return Ok(false);
        }
        // the unknown coordinates anywhere in the workspace: the written axes do not depend on them
        let w = self.machine.workspace();
        let c = (w.min + w.max) * 0.5;
        let at = DVec3::new(
            known[0].unwrap_or(c.x),
            known[1].unwrap_or(c.y),
            known[2].unwrap_or(c.z),
        );
        let axes = self
            .machine
            .inverse(at, DVec3::Z, None)
            .map_err(EmitError::new)?;
        let p = DVec3::new(
            known[0].unwrap_or(f64::NAN),
            known[1].unwrap_or(f64::NAN),
            known[2].unwrap_or(f64::NAN),
        );
        for &i in &write {
            let b = &self.reach.bounds()[i];
            if !(axes[i] >= b.min && axes[i] <= b.max) {
                return Err(EmitError::new(self.travel_error(out, i, axes[i], p)));
            }
        }
        out.extend_from_slice(b"G1");
        for &i in &write {
            out.push(b' ');
            out.extend_from_slice(self.limits[i].name.as_bytes());
            push_mm(out, axes[i]);
        }
        if let Some((de, relative)) = e {
            let v = self.ew.advance(de, relative);
            out.extend_from_slice(b" E");
            push_e(out, v);
        }
        self.write_feed(out, f);
        out.extend_from_slice(b" ; warpslice: the other axes are where homing left them\n");
        Ok(true)
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
            "; warpslice machine report: {} moves in, {} out; worst interpolation {:.5} mm / {:.4} deg; largest dropped tool-axis angle {:.3} deg; {} rotate-arounds ({:.5} mm E carried past the seam); {} swing lifts ({:.3} mm of tip path lifted over); {} rotary resets; {} re-poses; {}; {}\n",
            r.moves_in, r.moves_out, r.worst_position_mm, r.worst_angle_deg, r.worst_dropped_deg,
            r.rotate_arounds, r.e_skipped_mm, r.swing_lifts, r.swing_skipped_mm, r.rotary_resets, r.reposes,
            speed_summary(&r),
            margins_summary(&r.axes)
        );
        out.extend_from_slice(line.as_bytes());
    }

    fn machine_report(&self) -> Option<MachineReport> {
        Some(self.report())
    }
    fn input_line_of(&self, line: u64) -> Option<u64> {
        self.input_lines.as_ref()?.of(line)
    }
    fn forget_input_lines_before(&mut self, line: u64) {
        if let Some(m) = self.input_lines.as_mut() {
            m.forget_before(line);
        }
    }
}

/// Tilts asked of the machine by [`realised_tilt_range`], degrees.
pub const TILT_PROBES_DEG: [f64; 8] = [0.0, 10.0, 20.0, 30.0, 45.0, 60.0, 75.0, 89.0];

/// The range of tilts (radians from +Z) the machine realises, probed: `realised_axis` at the
/// workspace's centre for [`TILT_PROBES_DEG`] at four azimuths (a 3-axis head gives [0, 0],
/// the RTN's fixed nozzle [45°, 45°], a tilting head [0, its largest probed tilt]). A sampled
/// range, not a proof: a machine realising a tilt between probes but beyond both ends would be
/// taken at the nearest end (none of the kinds does: their realised tilt is the request clamped
/// to a range, or a constant).
fn realised_tilt_range(machine: &dyn Machine) -> [f64; 2] {
    let w = machine.workspace();
    let c = (w.min + w.max) * 0.5;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for t in TILT_PROBES_DEG {
        for k in 0..4 {
            let (t, a) = (crate::num::rad(t), crate::num::rad(90.0 * k as f64));
            let n = DVec3::new(
                crate::num::sin(t) * crate::num::cos(a),
                crate::num::sin(t) * crate::num::sin(a),
                crate::num::cos(t),
            );
            let r = tilt_of(machine.realised_axis(c, n));
            if r.is_finite() {
                lo = lo.min(r);
                hi = hi.max(r);
            }
        }
    }
    if lo <= hi {
        [lo, hi]
    } else {
        [0.0, std::f64::consts::PI]
    }
}

/// The tilt of tool axis `n` from +Z, radians.
fn tilt_of(n: DVec3) -> f64 {
    crate::num::acos(n.z.clamp(-1.0, 1.0))
}

/// A run of swing pieces to lift over ([`swing_runs`]).
#[derive(Clone, Debug, PartialEq)]
pub struct SwingRun {
    /// The pieces of the move (indices).
    pub pieces: std::ops::Range<usize>,
    /// The largest summed |Δ| of one rotary axis over the run, degrees.
    pub turn_deg: f64,
}

/// The swing runs of one move's `pieces`, reached from the axes `start`: runs of
/// consecutive pieces each turning a rotary axis (`rotary[i]`) faster than
/// [`SWING_RATE_DEG_PER_MM`] per mm of tip, joined when less than [`SWING_JOIN_MM`] of tip path
/// lies between them (the pieces between are lifted over too: one lift, not several), whose
/// largest summed turn of one axis reaches [`SWING_MIN_TURN_DEG`]. A rotate-around piece is
/// never in a run and separates runs (it has its own lifted turn).
pub fn swing_runs(start: &[f64], pieces: &[MachineMove], rotary: &[bool]) -> Vec<SwingRun> {
    // |Δ| of rotary axis i from the axes `a` to `b`, degrees (0 for a linear axis)
    let turn_of = |i: usize, a: &[f64], b: &[f64]| {
        if rotary[i] {
            (b[i] - a[i]).abs()
        } else {
            0.0
        }
    };
    let before = |k: usize| {
        if k == 0 {
            start
        } else {
            &pieces[k - 1].axes[..]
        }
    };
    let swings = |k: usize| {
        let m = &pieces[k];
        let turn = (0..rotary.len())
            .map(|i| turn_of(i, before(k), &m.axes))
            .fold(0.0, f64::max);
        !m.rotate_around
            && turn > 0.0
            && (m.tip_length <= 0.0 || turn / m.tip_length > SWING_RATE_DEG_PER_MM)
    };
    let mut runs: Vec<SwingRun> = Vec::new();
    // raw runs, joined across short gaps without a rotate-around (the hot path: most moves
    // have no swinging piece and allocate nothing)
    let mut raw: Vec<std::ops::Range<usize>> = Vec::new();
    let mut k = 0;
    while k < pieces.len() {
        if !swings(k) {
            k += 1;
            continue;
        }
        let s = k;
        while k < pieces.len() && swings(k) {
            k += 1;
        }
        if let Some(last) = raw.last_mut() {
            let gap = &pieces[last.end..s];
            let gap_mm: f64 = gap.iter().map(|m| m.tip_length).sum();
            if gap_mm < SWING_JOIN_MM && !gap.iter().any(|m| m.rotate_around) {
                last.end = k;
                continue;
            }
        }
        raw.push(s..k);
    }
    for r in raw {
        // the largest summed turn of one axis over the run (the joined gap's pieces included)
        let turn = (0..rotary.len())
            .map(|i| {
                r.clone()
                    .map(|k| turn_of(i, before(k), &pieces[k].axes))
                    .sum::<f64>()
            })
            .fold(0.0, f64::max);
        if turn >= SWING_MIN_TURN_DEG {
            runs.push(SwingRun {
                pieces: r,
                turn_deg: turn,
            });
        }
    }
    runs
}

/// A move's step when probing [`rest_dependence`], mm (well above rounding, small against any
/// workspace).
pub const REST_PROBE_STEP_MM: f64 = 7.3;
/// An axis value that changes by more than this (mm or degrees) when a coordinate moves by
/// [`REST_PROBE_STEP_MM`] depends on that coordinate (rounding of the kinematics is far below).
pub const REST_PROBE_SLACK: f64 = 1e-9;

/// Which output coordinates (x, y, z) each axis depends on at the rest pose (tool axis +Z, no
/// previous pose): `inverse(p, +Z)` at five points of the machine's [`Machine::workspace`] (its
/// centre and four points between the centre and the corners) against the same with one
/// coordinate moved by [`REST_PROBE_STEP_MM`]. A probe the kinematics refuse counts as
/// depending (conservative: such a move is not written from partial coordinates). Used for
/// moves after homing that give only some coordinates ([`Emitter::outside_partial`]): e.g. on
/// the polar machine Z depends on z alone, so `G1 Z5` after `G28` is `G1 Z5`, while X and C
/// depend on x and y.
pub fn rest_dependence(machine: &dyn Machine) -> Vec<[bool; 3]> {
    let count = machine.limits().len();
    let w = machine.workspace();
    let at = |fx: f64, fy: f64, fz: f64| {
        DVec3::new(
            w.min.x + fx * (w.max.x - w.min.x),
            w.min.y + fy * (w.max.y - w.min.y),
            w.min.z + fz * (w.max.z - w.min.z),
        )
    };
    let samples = [
        at(0.5, 0.5, 0.5),
        at(0.25, 0.25, 0.25),
        at(0.75, 0.25, 0.5),
        at(0.25, 0.75, 0.75),
        at(0.75, 0.75, 0.25),
    ];
    let mut deps = vec![[false; 3]; count];
    let mut probed = false;
    for s in samples {
        let Ok(a0) = machine.inverse(s, DVec3::Z, None) else {
            continue;
        };
        probed = true;
        for k in 0..3 {
            let mut q = s;
            q[k] += REST_PROBE_STEP_MM;
            match machine.inverse(q, DVec3::Z, None) {
                Ok(a1) => {
                    for (d, (v0, v1)) in deps.iter_mut().zip(a0.iter().zip(&a1)) {
                        if (v1 - v0).abs() > REST_PROBE_SLACK {
                            d[k] = true;
                        }
                    }
                }
                Err(_) => deps.iter_mut().for_each(|d| d[k] = true),
            }
        }
    }
    if !probed {
        return vec![[true; 3]; count];
    }
    deps
}

/// `N moves slowed by axis feed limits (A n, …); estimated time h:mm:ss (+s s slow-down)`: the
/// speed part of the report line (CLI and the file's last comment).
pub fn speed_summary(r: &MachineReport) -> String {
    let by: Vec<String> = r
        .axes
        .iter()
        .filter(|a| a.speed_limited_moves > 0)
        .map(|a| format!("{} {}", a.axis, a.speed_limited_moves))
        .collect();
    let secs = (r.print_time_min * 60.0).round() as u64;
    format!(
        "{} moves slowed by axis feed limits{}; estimated time {}:{:02}:{:02} (+{:.1} s slow-down, no acceleration)",
        r.speed_limited_moves,
        if by.is_empty() {
            String::new()
        } else {
            format!(" ({})", by.join(", "))
        },
        secs / 3600,
        secs / 60 % 60,
        secs % 60,
        r.slowdown_min * 60.0
    )
}

/// `reach margins X 12.300/45.600 mm, …` (to the lower/upper end of each limited axis), the
/// margin part of the report line.
pub fn margins_summary(axes: &[crate::emit::AxisReport]) -> String {
    let m: Vec<String> = axes
        .iter()
        .filter_map(|a| {
            let f = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.3}"));
            (a.margin_min.is_some() || a.margin_max.is_some()).then(|| {
                format!(
                    "{} {}/{} {}",
                    a.axis,
                    f(a.margin_min),
                    f(a.margin_max),
                    if a.rotary { "deg" } else { "mm" }
                )
            })
        })
        .collect();
    if m.is_empty() {
        "reach margins: no axis limited".to_string()
    } else {
        format!("reach margins (to min/max) {}", m.join(", "))
    }
}
