//! Machines: turn the toolpath (tip `p`, tool axis `n`, output frame) into the axes of a real
//! printer, and back.
//!
//! ## The seam
//! Every machine implements [`Machine`]:
//! - [`Machine::inverse`]`(p, n, previous)` → axis values in the order of
//!   [`Machine::axis_names`]. `previous` (the axes of the previous output point) picks the
//!   branch and keeps rotary axes continuous (unwrapped across ±180°, held near singular poses).
//! - [`Machine::forward`]`(axes)` → `(tip, tool axis)` in the output (part) frame.
//! - [`Machine::realised_axis`]`(p, n)`: the tool axis the machine actually gives when asked for
//!   `n` at `p` without a previous pose (e.g. the B head drops the Y component and clips the
//!   angle). `forward(inverse(p, n, None)) == (p, realised_axis(p, n))` is the law
//!   ([`laws`]). The angle between `n` and the realised axis is what a report calls "dropped".
//! - [`Machine::axis_set`]: the name and axes ([`AxisSet`], see [`axes`]), which also does the
//!   checks all machines share (input `(p, n)`, travel limits, axis count).
//!
//! ## Units
//! Linear axes in mm, rotary axes in **degrees** (as written to G-code), raw values (no `G92`
//! offsets). The tool axis `n` is the unit vector from the tip into the nozzle.
//!
//! ## Machines (one file each)
//! [`cartesian`], [`bhead`] (FullControl Prusa B), [`rtn`] (Slicer4RTN, RotBot), [`pax`]
//! (5-axis head), [`abtable`] (Open5x A/B table), [`threez`] (RatRig triple-Z bed),
//! [`rtheta`] (Core R-Theta), [`lathe`] (rotating mandrel). Presets are JSON files in
//! `presets/`, compiled in with `include_str!` (so they work in wasm), see [`spec`]; a user's
//! file is read by the caller and parsed with [`MachineSpec::from_json`] (no filesystem here).
//!
//! ## Around the kinematics
//! - [`laws`]: the law tests every machine passes (round trip, continuity), callable from wasm.
//! - [`batch`]: CSV in, CSV out (`warpslice kinematics inverse|forward`).
//! - [`tessellate`]: split moves until the firmware's linear axis interpolation stays within
//!   0.02 mm / 0.1° of the intended path (seed 001 §4.5); reports the worst error.
//!   [`bound`]: the lemmas of the machines' closed-form error bounds
//!   ([`Machine::interpolation_bound`]), which spare the check's samples.
//! - [`feed`]: output F for `tip`, `xyz`, `all-axes` and `inverse-time` (G93) feed modes;
//!   [`length_rule`]: how each firmware measures a move's length (what `tip` divides by).
//! - [`travel`]: the machine file's linear travel and per-axis largest feed; [`reach`]: every
//!   written move inside the travel (a violation is [`MachineError::Travel`], naming the output
//!   and input lines) and the margins; [`speed`]: moves an axis' feed limit slows, and the
//!   print-time estimate with that slow-down.

use core::fmt;

use glam::{DMat3, DVec3};

pub mod abtable;
pub mod angles;
pub mod axes;
pub mod axis_buf;
pub mod batch;
pub mod bhead;
pub mod bound;
pub mod cartesian;
pub mod config;
pub mod drift;
pub mod emit;
pub mod feed;
pub mod flavour;
pub mod head;
pub mod lathe;
pub mod laws;
pub mod length_rule;
pub mod options;
pub mod pax;
pub mod reach;
pub mod rtheta;
pub mod rtn;
pub mod spec;
pub mod speed;
pub mod tessellate;
pub mod threez;
pub mod threez_bound;
pub mod travel;
pub mod view;

pub use crate::emit::FeedMode;
pub use crate::emit::MachineReport;
pub(crate) use axes::{check_limits, require};
pub use axes::{AxisLimit, AxisSet, InverseResult, UNLIMITED};
pub use emit::MachineEmitter;
pub use flavour::Flavour;
pub use options::MachineOptions;
pub use spec::{preset, preset_names, MachineSpec};

/// Below this length a projected tool axis (|n_xy| for an azimuth, |n_xz| for a B angle) is
/// taken to be zero: the angle it would define is undefined and the previous value is held.
pub const POLE_EPSILON: f64 = 1e-12;
/// Below this |det| the small linear systems of the machine code (normal equations of a few
/// unit vectors) are taken to be singular: no unique solution, the caller falls back.
pub const SINGULAR_EPSILON: f64 = 1e-12;
/// Slack on a unit vector's length after normalisation (rounding of a few ulps, well below
/// this), and below this length a vector is taken to be zero: its direction is undefined.
pub const UNIT_EPSILON: f64 = 1e-12;
/// Below this |sin| of the angle between two axis directions the axes are taken to be
/// parallel (0.2 millidegree: far below any real machine's misalignment, far above rounding).
pub const PARALLEL_SINE: f64 = 1e-6;
/// Relative slack on a discriminant computed as a difference of squares (rounding of both
/// terms): a value within it below zero is a double root, not "no solution".
pub const DISCRIMINANT_SLACK: f64 = 1e-12;
/// A rotary axis whose travel is at most one turn plus this (degrees) wraps: its values are
/// compared modulo 360°.
pub const ONE_TURN_SLACK_DEG: f64 = 1e-9;
/// Slack on angle limits (degrees) so that values computed exactly at a limit pass.
pub const LIMIT_SLACK_DEG: f64 = 1e-9;
/// Slack on unit vectors given by the user (|n| may differ from 1 by this before it is an error;
/// n is normalised anyway).
pub const UNIT_SLACK: f64 = 1e-6;

/// Where the law tests sample a machine: a box of tip positions (output frame, mm) and the
/// largest tool-axis tilt from vertical (degrees) the machine realises without error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Workspace {
    /// Lowest corner, mm.
    pub min: DVec3,
    /// Highest corner, mm.
    pub max: DVec3,
    /// Largest tilt of `n` from +Z that `inverse` accepts, degrees.
    pub max_tilt_deg: f64,
}

impl Workspace {
    /// The box of a desktop printer, x, y ∈ [−100, 100] mm and z ∈ [0, 200] mm, with tilts up
    /// to `max_tilt_deg`.
    pub fn desktop(max_tilt_deg: f64) -> Workspace {
        Workspace {
            min: DVec3::new(-100.0, -100.0, 0.0),
            max: DVec3::new(100.0, 100.0, 200.0),
            max_tilt_deg,
        }
    }
}

/// One end of a piece of a move: axes (machine order), tip (output frame, mm) and the intended
/// unit tool axis ([`Machine::interpolation_bound`]).
pub type PieceEnd<'a> = (&'a [f64], DVec3, DVec3);

/// What a machine says of itself to the CLI and the web page ([`crate::describe`]): what it
/// can tilt, which warps it can print, whether the part or the head moves.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct Capabilities {
    /// One line: what kind of machine this is.
    pub summary: String,
    /// The largest tool-axis tilt from vertical it realises, degrees (`None`: no limit).
    pub max_tilt_deg: Option<f64>,
    /// A nozzle fixed at this tilt (rotating tilted nozzles), degrees.
    pub fixed_tilt_deg: Option<f64>,
    /// The part (bed, table, mandrel) moves, not only the head: the page can draw the toolpath
    /// in machine coordinates ([`Machine::head_position`]).
    pub moving_bed: bool,
    /// The warps it can print (names of [`crate::warp::WARPS`]).
    pub warps: Vec<&'static str>,
    /// Facts a user should know (limits, clips), one line each.
    pub notes: Vec<String>,
}

/// Every warp's name (machines that print them all).
pub fn all_warps() -> Vec<&'static str> {
    crate::warp::WARPS.iter().map(|w| w.name).collect()
}

/// A machine's kinematics. See the module documentation for the conventions.
pub trait Machine: Send + Sync + fmt::Debug {
    /// The machine's name and axes.
    fn axis_set(&self) -> &AxisSet;
    /// The preset/machine name (for messages).
    fn name(&self) -> &str {
        self.axis_set().name()
    }
    /// Axis letters in output order.
    fn axis_names(&self) -> Vec<String> {
        self.limits().iter().map(|l| l.name.clone()).collect()
    }
    /// Axis limits, in output order (same length as the axes).
    fn limits(&self) -> &[AxisLimit] {
        self.axis_set().limits()
    }
    /// Inverse kinematics: axes that put the tip at `p` with (the realisable part of) tool axis
    /// `n`. `previous` picks the branch and keeps rotary axes continuous.
    fn inverse(&self, p: DVec3, n: DVec3, previous: Option<&[f64]>) -> InverseResult;
    /// Forward kinematics: `(tip, unit tool axis)` in the output frame.
    fn forward(&self, axes: &[f64]) -> Result<(DVec3, DVec3), MachineError>;
    /// The tool axis the machine realises for `n` at `p` when no previous pose is given.
    fn realised_axis(&self, _p: DVec3, n: DVec3) -> DVec3 {
        n
    }
    /// Whether the machine realises every request it solves exactly: `forward(inverse(p, n,
    /// previous)) = (p, n)` (within the round-trip tolerance of law 1) whatever `previous` —
    /// no dropped component, no clip, no branch hold (the triple-Z bed, the 5-axis head). The
    /// held-axis probe then takes the request as the realised axis, and the interpolation check
    /// takes `(p(s), n(s))` as the exact pose of a sample ([`tessellate`]). Law 1 holds a
    /// machine that says so to `(p, n)` itself, not to [`Machine::realised_axis`]. Default:
    /// `false`.
    fn realises_requests(&self) -> bool {
        false
    }
    /// The tool axis every pose of the machine realises, when it is one (a 3-axis machine:
    /// `forward(axes).1` is this vector bit for bit whatever `axes`, and so is
    /// [`Machine::realised_axis`]). The held-axis probe of [`tessellate`] then has nothing to
    /// find (a realised axis that never moves cannot jump at a move's start) and is skipped.
    /// Law 1 ([`laws::check_round_trip`]) and law 2 hold a machine that says so to it at every
    /// point they solve. Default: `None`.
    fn fixed_tool_axis(&self) -> Option<DVec3> {
        None
    }
    /// A bound (degrees) on how far the realised tool axis can move at the start of a move
    /// from a pose solved for `(p, n)`: for `axes = inverse(p, n, previous)` (whatever
    /// `previous`) and every request `(p', n')` with `n'` a unit vector within `turn` radians of
    /// the unit `n` and `|p' − p| ≤ tip_mm`, `inverse(p', n', Some(axes))` succeeds and its
    /// realised axis `forward(·).1` is within the bound of `forward(axes).1`. `None`: no bound
    /// is known there (a held axis, a switch between branches or ends, a travel limit within
    /// reach). The held-axis probe of [`tessellate`] (a forward, an inverse and a forward per
    /// move) is skipped where the bound is within its limit; law 7
    /// ([`laws::check_start_drift`]) checks the bound against that probe's own computation at
    /// every grid pose. Default: `None` (the probe runs).
    fn start_drift_deg(
        &self,
        _p: DVec3,
        _n: DVec3,
        _axes: &[f64],
        _turn: f64,
        _tip_mm: f64,
    ) -> Option<f64> {
        None
    }
    /// Whether the machine realises every request exactly along each piece its
    /// [`Machine::interpolation_bound`] is given for: `forward(inverse(p(s), n(s), a₀)) =
    /// (p(s), n(s))` within law 1's round-trip tolerance there (the A/B table: a bound is given
    /// only away from its pole hold). The interpolation check then takes the request as the
    /// exact pose of such a piece's samples ([`tessellate`]); law 6
    /// ([`laws::check_interpolation_bound`]) checks the promise at every sample of every bounded
    /// piece. Default: [`Machine::realises_requests`].
    fn realises_bounded_requests(&self) -> bool {
        self.realises_requests()
    }
    /// The largest angle (radians) by which the realised axis may differ from
    /// `realised_axis(p, n)` when `previous` picks a branch (e.g. holding B near the pole).
    fn branch_freedom(&self, _p: DVec3, _n: DVec3) -> f64 {
        0.0
    }
    /// The machine's other solution for the same pose, where its kinematics has two for one
    /// tip and tool axis (`axes` is one of them; the A/B table's `(A, B)` and `(−A, B ± 180°)`):
    /// the emitter turns to it in the air where the path would leave the linear travel on the
    /// branch it is on ([`emit`], "Branch flips"). `None` (the default): one solution, or the
    /// other is not reachable (its rotary limits).
    fn other_branch(&self, _p: DVec3, _n: DVec3, _axes: &[f64]) -> Option<Vec<f64>> {
        None
    }
    /// Where the law tests sample this machine.
    fn workspace(&self) -> Workspace;
    /// `true` promises (and the law [`laws::check_fixed_pose`] checks) that a straight tip
    /// segment with one tool axis n, whose ends solve to the same rotary axes, is solved all
    /// along to those rotary axes with linear axes affine in the tip: the firmware's linear
    /// interpolation is then exact, and the interpolation check skips such moves
    /// (see [`tessellate`]). False for the triple-Z bed (no rotary axes; its motor heights are
    /// not affine in the bed's pose).
    fn linear_at_fixed_pose(&self) -> bool {
        false
    }
    /// A proven upper bound `(tip mm, tool axis degrees)` of the firmware's interpolation error
    /// over the piece from the pose `from = (axes a₀, tip p₀, intended axis n₀)` to
    /// `to = (a₁, p₁, n₁)`, where `forward(aᵢ)` realises `(pᵢ, nᵢ)` and n₀, n₁ are unit (see
    /// [`bound`] for what is bounded and the lemmas). It also promises that `inverse` succeeds
    /// all along the piece. `None` (the default): no closed form here, the interpolation check
    /// samples the piece. The law [`laws::check_interpolation_bound`] checks it.
    fn interpolation_bound(&self, _from: PieceEnd, _to: PieceEnd) -> Option<(f64, f64)> {
        None
    }
    /// What the machine says of itself (see [`Capabilities`]).
    fn capabilities(&self) -> Capabilities;
    /// How the firmware must map this machine's axis letters to motors (its kinematics
    /// setting, [`config::AxisDrive`]); by default X Y Z are Cartesian coordinates.
    fn axis_drive(&self) -> config::AxisDrive {
        config::AxisDrive::Cartesian
    }
    /// Refuse a job this machine would print wrong although every point is reachable (the
    /// lathe: a cylindrical warp whose axis is not the mandrel's). `model_to_output` moves the
    /// job's model frame to the output frame.
    fn check_job(
        &self,
        _job: &crate::job::Job,
        _model_to_output: DVec3,
    ) -> Result<(), MachineError> {
        Ok(())
    }
    /// The head's orientation in the output (part) frame for these axis values: the columns are
    /// the tool frame's x, y and z (= the tool axis) axes ([`head`]: the heater block's box is
    /// placed with it). `None` (the default): the machine does not say how the head is turned
    /// about the tool axis, and the collision check takes each box as the cylinder about the
    /// tool axis that contains it.
    fn head_frame(&self, _axes: &[f64]) -> Option<DMat3> {
        None
    }
    /// [`Machine::forward`] and [`Machine::head_frame`] at once, `(tip, tool axis, frame)`:
    /// what the collision check asks at every sampled pose. A machine whose frame comes from
    /// its forward kinematics ([`head::fixed_head_pose`]) computes the tip once; the result is
    /// the same as the two calls' (law 5, [`laws::check_head_frame`]).
    fn pose(&self, axes: &[f64]) -> Result<(DVec3, DVec3, Option<DMat3>), MachineError> {
        let (p, n) = self.forward(axes)?;
        Ok((p, n, self.head_frame(axes)))
    }
    /// Whether the axes are the output frame's X Y Z themselves (the 3-axis machine with the
    /// letters X Y Z): a slicer's start and end G-code then mean the same on this machine and
    /// pass through verbatim when the output is not moved ([`emit`], "Outside the region").
    fn axes_are_output_xyz(&self) -> bool {
        false
    }
    /// Where the head is in the machine's own frame for these axis values (mm), for drawing the
    /// toolpath in machine coordinates: by default the first three axes are X Y Z.
    fn head_position(&self, axes: &[f64]) -> DVec3 {
        DVec3::new(
            axes.first().copied().unwrap_or(0.0),
            axes.get(1).copied().unwrap_or(0.0),
            axes.get(2).copied().unwrap_or(0.0),
        )
    }
}

/// Errors of the machine area.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum MachineError {
    /// The machine cannot give this tool axis at this point.
    UnreachableOrientation {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The tool tip asked for, output frame, mm.
        p: DVec3,
        /// The tool axis asked for (tip → nozzle), output frame.
        n: DVec3,
        /// Why the machine cannot give it (e.g. the tilt exceeds the head's range).
        reason: String,
    },
    /// An axis would leave its travel.
    AxisLimit {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The axis' letter in the G-code (e.g. `B`).
        axis: String,
        /// The value the axis would take (mm, or degrees for a rotary axis).
        value: f64,
        /// Lower end of the axis' travel (mm, or degrees for a rotary axis).
        min: f64,
        /// Upper end of the axis' travel (mm, or degrees for a rotary axis).
        max: f64,
        /// The tool tip being reached, output frame, mm.
        p: DVec3,
    },
    /// A written move would take an axis outside its travel (machine file `travel`, or a
    /// rotary axis' range).
    Travel {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The axis' letter in the G-code.
        axis: String,
        /// The value the move would write (mm, or degrees).
        value: f64,
        /// Lower end of the travel.
        min: f64,
        /// Upper end of the travel.
        max: f64,
        /// The output G-code line (1-based, as written) the move would be.
        output_line: u64,
        /// The input G-code line (1-based, the slicer's) the move came from; 0: none.
        input_line: u64,
        /// The tool tip at the end of the move, output frame, mm.
        p: DVec3,
    },
    /// A zero or non-finite tool axis or position.
    InvalidInput {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The tool tip given, output frame, mm.
        p: DVec3,
        /// The tool axis given (tip → nozzle), output frame.
        n: DVec3,
    },
    /// `forward` got the wrong number of axis values.
    WrongAxisCount {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// Number of axes the machine has.
        expected: usize,
        /// Number of axis values given.
        got: usize,
    },
    /// `forward` got a non-finite axis value.
    InvalidAxes {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The axis values given, in the machine's axis order (mm or degrees).
        axes: Vec<f64>,
    },
    /// No preset with this name.
    UnknownPreset {
        /// The preset name asked for.
        name: String,
        /// Names of the built-in presets.
        known: Vec<String>,
    },
    /// The machine JSON could not be parsed.
    BadJson {
        /// Where the JSON came from (a file path, `preset <name>`, `machine JSON`).
        source: String,
        /// The parser's message (serde_json's, with line and column) or the read error.
        message: String,
    },
    /// The machine JSON parsed but its parameters are unusable.
    BadSpec {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// Which parameter is unusable and why.
        message: String,
    },
    /// A batch CSV line is invalid (1-based line number).
    BadCsv {
        /// 1-based line number of the CSV text.
        line: usize,
        /// What is wrong with the line (a field that is not a number, a wrong field count).
        message: String,
    },
    /// A cylindrical job's layer axis is not the lathe's mandrel axis (output frame, y and z
    /// in mm): printing would wind the layers round the wrong line.
    MandrelMismatch {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The warp's axis (y, z) moved to the output frame, mm.
        warp: [f64; 2],
        /// The machine's mandrel axis (y, z), output frame, mm.
        mandrel: [f64; 2],
    },
    /// A head part would hit the printed material or the bed (the collision check).
    Collision {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The first finding: output line, layer, head part, obstacle, depth, where.
        finding: Box<crate::emit::CollisionFinding>,
        /// How many findings the file has.
        total: usize,
    },
    /// The collision check cannot judge this machine.
    CollisionUnsupported {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// Why.
        reason: String,
    },
    /// A machine option (`--interpolation`, `--interpolation-caps`) has an unusable value.
    BadOption {
        /// The option's flag name without dashes (`interpolation`).
        name: &'static str,
        /// The value given.
        value: String,
        /// What the option accepts.
        allowed: &'static str,
    },
    /// The firmware flavour cannot drive this machine.
    UnsupportedFlavour {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The flavour's name (`marlin`, `klipper` or `reprapfirmware`).
        flavour: String,
        /// Why the firmware cannot drive the machine (e.g. axis letters it does not accept).
        reason: String,
    },
    /// A command inside the printed region moved the head to a pose the file does not give
    /// (`G28 X Y`, `G27`, a tool change): a multi-axis head cannot be brought back safely from
    /// an unknown pose (its tool may be tilted over the part).
    PoseLost {
        /// Name of the machine (preset or JSON `name`).
        machine: String,
        /// The command (e.g. `T (tool change)`).
        command: String,
    },
}

impl fmt::Display for MachineError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            MachineError::UnreachableOrientation { machine, p, n, reason } => write!(
                f,
                "machine {machine}: tool axis ({:.6}, {:.6}, {:.6}) at point ({:.4}, {:.4}, {:.4}) cannot be reached: {reason}; lower the tilt of the warp or choose another machine",
                n.x, n.y, n.z, p.x, p.y, p.z
            ),
            MachineError::AxisLimit { machine, axis, value, min, max, p } => write!(
                f,
                "machine {machine}: axis {axis} = {value:.6} is outside its travel [{min}, {max}] at point ({:.4}, {:.4}, {:.4}); move the part or widen the limit in the machine JSON",
                p.x, p.y, p.z
            ),
            MachineError::Travel { machine, axis, value, min, max, output_line, input_line, p } => {
                let input = if *input_line > 0 {
                    format!("from input line {input_line}")
                } else {
                    "added by warpslice".to_string()
                };
                write!(
                    f,
                    "machine {machine}: output line {output_line} ({input}): axis {axis} = {value:.3} is outside its travel [{min}, {max}] with the tip at ({:.3}, {:.3}, {:.3}); move the part with --place x,y, print a smaller part or use another warp (or correct the travel in the machine JSON)",
                    p.x, p.y, p.z
                )
            }
            MachineError::InvalidInput { machine, p, n } => write!(
                f,
                "machine {machine}: invalid input point ({}, {}, {}) / tool axis ({}, {}, {}): the position must be finite and the tool axis a finite non-zero vector",
                p.x, p.y, p.z, n.x, n.y, n.z
            ),
            MachineError::WrongAxisCount { machine, expected, got } => write!(
                f,
                "machine {machine}: expected {expected} axis values, got {got}"
            ),
            MachineError::InvalidAxes { machine, axes } => write!(
                f,
                "machine {machine}: axis values {axes:?} must all be finite numbers"
            ),
            MachineError::UnknownPreset { name, known } => write!(
                f,
                "unknown machine preset '{name}'; known presets: {} (or give a path to a machine JSON file)",
                known.join(", ")
            ),
            MachineError::BadJson { source, message } => {
                write!(f, "machine JSON {source} is invalid: {message}")
            }
            MachineError::BadSpec { machine, message } => {
                write!(f, "machine {machine}: {message}; fix the machine JSON")
            }
            MachineError::BadCsv { line, message } => write!(
                f,
                "kinematics input line {line}: {message}"
            ),
            MachineError::MandrelMismatch { machine, warp, mandrel } => write!(
                f,
                "the cylindrical warp's layers are coaxial about the line y = {}, z = {} (along X, in the output) but machine {machine} turns about y = {}, z = {}: set \"axis_y_mm\": {}, \"axis_z_mm\": {} in the machine JSON, or --place the part so that its warp axis lies on the mandrel",
                crate::num::fmt_shortest(warp[0]), crate::num::fmt_shortest(warp[1]), crate::num::fmt_shortest(mandrel[0]), crate::num::fmt_shortest(mandrel[1]), crate::num::fmt_shortest(warp[0]), crate::num::fmt_shortest(warp[1])
            ),
            MachineError::Collision { machine, finding: c, total } => write!(
                f,
                "machine {machine}: output line {} (layer {}; {}): the {} goes {:.3} mm into the {} at ({:.3}, {:.3}, {:.3}) (at least {total} collision{} in the file); lower the warp's tilt, move the part (--place), give the machine's real head in its JSON \"head\", or write it anyway with allow_collisions (--allow-collisions) to list every finding",
                c.line, c.layer,
                c.input_line.map_or_else(
                    || "no input line: the machine G-code was checked without the slicer's file".to_string(),
                    |l| format!("from input line {l}")
                ),
                c.part, c.depth_mm,
                if c.obstacle == "bed" { "bed" } else { "printed material" },
                c.at[0], c.at[1], c.at[2], if *total == 1 { "" } else { "s" }
            ),
            MachineError::CollisionUnsupported { machine, reason } => write!(
                f,
                "machine {machine}: the collision check cannot judge this machine: {reason}; the unwarp skips the check on it and says so in its warnings"
            ),
            MachineError::BadOption { name, value, allowed } => write!(
                f,
                "--{name} {value}: expected {allowed}"
            ),
            MachineError::UnsupportedFlavour { machine, flavour, reason } => write!(
                f,
                "machine {machine}: flavour {flavour} refused: {reason}"
            ),
            MachineError::PoseLost { machine, command } => write!(
                f,
                "machine {machine}: {command} inside the printed region leaves the head in a pose the G-code does not give, and a multi-axis head cannot be brought back from an unknown pose safely; move the command before the first or after the last layer (start or end G-code), or unwarp to 3-axis G-code"
            ),
        }
    }
}

impl std::error::Error for MachineError {}

crate::error_codes!(MachineError, ERROR_CODES, "machine" {
    UnreachableOrientation => "machine.unreachable-orientation", "the machine cannot give this tool axis here";
    AxisLimit => "machine.axis-limit", "an axis would leave its travel";
    Travel => "machine.travel", "a written move would take an axis outside its travel";
    InvalidInput => "machine.invalid-input", "a non-finite point or a zero tool axis";
    WrongAxisCount => "machine.wrong-axis-count", "the wrong number of axis values";
    InvalidAxes => "machine.invalid-axes", "a non-finite axis value";
    UnknownPreset => "machine.unknown-preset", "no machine preset of this name";
    BadJson => "machine.bad-json", "the machine JSON does not parse";
    BadSpec => "machine.bad-spec", "the machine's parameters are unusable";
    BadCsv => "machine.bad-csv", "a kinematics CSV line is invalid";
    MandrelMismatch => "machine.mandrel-mismatch", "a cylindrical job whose axis is not the mandrel's";
    BadOption => "machine.bad-option", "a machine option (--interpolation, …) has an unusable value";
    UnsupportedFlavour => "machine.unsupported-flavour", "the firmware flavour cannot drive this machine";
    Collision => "machine.collision", "a head part would hit the printed material or the bed";
    CollisionUnsupported => "machine.collision-unsupported", "the collision check cannot judge this machine";
    PoseLost => "machine.pose-lost", "a head move (G28 X Y, G27, a tool change) inside the printed region";
} wraps {});
