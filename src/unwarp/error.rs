//! Why a G-code cannot be unwarped.

use crate::emit::EmitError;
use crate::error::{Coded, ErrorCode};
use crate::gcode::GcodeError;
use crate::register::RegisterError;
use crate::warp::WarpError;

/// Why a G-code cannot be unwarped.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum UnwarpError {
    /// G91 relative positioning inside the printed region.
    RelativePositioning {
        /// 1-based line number of the G-code.
        line: u64,
    },
    /// G92 with X, Y or Z inside the printed region.
    AxisReset {
        /// 1-based line number of the G-code.
        line: u64,
    },
    /// G20 inches inside the printed region.
    Inches {
        /// 1-based line number of the G-code.
        line: u64,
    },
    /// The G-code cannot be read.
    Gcode(GcodeError),
    /// The streaming calls came in the wrong order.
    Order {
        /// The call that must come first (e.g. `scan`).
        expected: &'static str,
    },
    /// The emitter (a machine) cannot follow the toolpath or refuses the job: the G-code line
    /// being unwarped when it happened (`None`: before the first line).
    Emit {
        /// 1-based line number of the G-code being unwarped, `None` before the first line.
        line: Option<u64>,
        /// What the emitter refused.
        error: EmitError,
    },
    /// A bad option value (name, value, what is allowed).
    Option {
        /// The option's CLI name without dashes (e.g. `max-segment`).
        name: &'static str,
        /// The value given, as text.
        value: String,
        /// What the option accepts (e.g. `a positive number`).
        allowed: &'static str,
    },
    /// The job's warp cannot be built.
    Warp(WarpError),
    /// Pass 1 could not find where the slicer put the part.
    Register(RegisterError),
    /// A command inside the printed region that drives the nozzle or a probe down to the bed
    /// (`G28` homing Z, `G29`, `G30`): where the part stands, it hits the part.
    ProbeInRegion {
        /// 1-based line number of the G-code.
        line: u64,
        /// The line as written.
        command: String,
    },
    /// The object's extrusions do not lie in this job's part ([`super::shape`]): the G-code was
    /// sliced from another warp of the model (another angle, direction or centre), another
    /// model, or `--offset` is wrong.
    ShapeMismatch {
        /// The worst point.
        finding: super::shape::Finding,
        /// Points beyond the tolerance.
        beyond: u64,
    },
    /// `place` is not two finite numbers.
    BadPlace {
        /// The `--place x,y` given, mm (at least one is NaN or infinite).
        place: [f64; 2],
    },
    /// A line outside the printed region (start or end G-code) on a machine output that the
    /// machine cannot carry out exactly in its own axes ([`super::outside`]).
    OutsideMotion {
        /// 1-based line number of the G-code.
        line: u64,
        /// The line as written.
        command: String,
        /// What it does that cannot be converted.
        reason: OutsideReason,
    },
    /// The machine refused a converted line outside the printed region (an axis beyond its
    /// travel, an unreachable pose): the start or end G-code asks for it.
    Outside {
        /// 1-based line number of the G-code.
        line: u64,
        /// The line as written.
        command: String,
        /// What the machine refused (its code is this error's).
        error: EmitError,
    },
}

/// Why a motion line outside the printed region cannot be converted to a machine's axes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum OutsideReason {
    /// A move with X, Y or Z under `G91`.
    Relative,
    /// `G2`/`G3`.
    Arc,
    /// `G92` with X, Y or Z.
    AxisReset,
    /// `G20`.
    Inches,
    /// An extruding move after homing that gives only some of X, Y, Z, on a machine whose
    /// axes it moves also depend on the others.
    PartialExtrusion,
}

impl OutsideReason {
    /// What the line does, and what to change, for the message.
    fn explain(self) -> &'static str {
        match self {
            OutsideReason::Relative => "a relative move (G91) where the head's position is not known (after homing, before X, Y and Z were all given) cannot be converted to the machine's axes; use absolute moves (G90) in the start G-code, or give X, Y and Z first",
            OutsideReason::Arc => "an arc (G2/G3) cannot be converted to the machine's axes; use straight G1 moves in the start and end G-code (or remove the prime or purge line)",
            OutsideReason::AxisReset => "G92 with X, Y or Z redefines the slicer's frame, which the machine's axes cannot follow; remove it from the start and end G-code (G92 E alone is fine)",
            OutsideReason::Inches => "inches (G20) cannot be converted to the machine's millimetre axes; export the G-code in millimetres",
            OutsideReason::PartialExtrusion => "after homing this move extrudes while giving only some of X, Y, Z, and the machine's axes it moves depend on the others; give X, Y and Z in the first move after homing (e.g. G1 X… Y… Z…) or remove the prime line",
        }
    }
}

impl From<GcodeError> for UnwarpError {
    fn from(e: GcodeError) -> Self {
        UnwarpError::Gcode(e)
    }
}

impl std::fmt::Display for UnwarpError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            UnwarpError::RelativePositioning { line } => write!(
                f,
                "G-code line {line}: relative positioning (G91) inside the printed region is not supported; export absolute coordinates"
            ),
            UnwarpError::AxisReset { line } => write!(
                f,
                "G-code line {line}: G92 resets X/Y/Z inside the printed region; remove it (only G92 E is allowed there)"
            ),
            UnwarpError::Inches { line } => {
                write!(f, "G-code line {line}: inches (G20) inside the printed region; export the G-code in millimetres")
            }
            UnwarpError::Gcode(e) => e.fmt(f),
            UnwarpError::Warp(e) => e.fmt(f),
            UnwarpError::Register(e) => e.fmt(f),
            UnwarpError::Option {
                name,
                value,
                allowed,
            } => write!(f, "option {name} = {value} is not allowed: {allowed}"),
            UnwarpError::Order { expected } => write!(f, "unwarp: call {expected} first"),
            UnwarpError::Emit { line: Some(line), error } => write!(f, "G-code line {line}: {error}"),
            UnwarpError::Emit { line: None, error } => error.fmt(f),
            UnwarpError::ProbeInRegion { line, command } => write!(
                f,
                "G-code line {line}: '{command}' inside the printed region drives the nozzle or the probe down to the bed, where the part stands; move it to the start G-code (before the first layer), or home only X and Y (G28 X Y)"
            ),
            UnwarpError::ShapeMismatch { finding: w, beyond } if w.face == super::shape::SECTION_FACE => write!(
                f,
                "G-code line {}: this G-code does not fit this job's warped mesh: on layer {} its object extrusion at X{:.3} Y{:.3} Z{:.3} lies {:.3} mm outside the warped mesh's cross-section at z = {:.3} mm (the layer's mid-height, where the slicer cut it; {:.3} mm allowed; {beyond} points beyond). It was sliced from another warp of the model or other warp parameters (angle, direction, centre, strength: their boxes can agree), or from another model, or --offset is wrong: unwarp with the job written beside the warped STL you sliced, or slice this job's warped STL again; leave --offset out to have the placement found",
                w.line,
                w.layer,
                w.gcode.x,
                w.gcode.y,
                w.gcode.z,
                w.overshoot,
                w.model.z,
                w.allowed
            ),
            UnwarpError::ShapeMismatch { finding: w, beyond } => write!(
                f,
                "G-code line {}: this G-code does not fit this job's part: its object extrusion at X{:.3} Y{:.3} Z{:.3} maps {:.3} mm {} (model point {:.3}, {:.3}, {:.3} at the layer's mid-height; {:.3} mm allowed; {beyond} points beyond). It was sliced from another warp of the model (another angle, direction or centre: their boxes can agree) or from another model, or --offset is wrong: unwarp with the job written beside the warped STL you sliced, or slice this job's warped STL again; leave --offset out to have the placement found",
                w.line,
                w.gcode.x,
                w.gcode.y,
                w.gcode.z,
                w.overshoot,
                super::shape::FACES[w.face],
                w.model.x,
                w.model.y,
                w.model.z,
                w.allowed
            ),
            UnwarpError::OutsideMotion { line, command, reason } => write!(
                f,
                "G-code line {line}: '{command}' outside the printed region (start or end G-code, written for the slicer's printer): {}",
                reason.explain()
            ),
            UnwarpError::Outside { line, command, error } => write!(
                f,
                "G-code line {line}: '{command}' outside the printed region (start or end G-code), converted to the machine's axes: {error}. The start and end G-code are in the slicer's frame and are placed and converted like the part: change or remove this move in the slicer's start/end G-code (or unwarp to 3-axis G-code)"
            ),
            UnwarpError::BadPlace { place } => {
                write!(f, "place {},{} is not a position: give two finite numbers x,y in mm", place[0], place[1])
            }
        }
    }
}

impl std::error::Error for UnwarpError {
    fn source(&self) -> Option<&(dyn std::error::Error + 'static)> {
        match self {
            UnwarpError::Gcode(e) => Some(e),
            UnwarpError::Warp(e) => Some(e),
            UnwarpError::Register(e) => Some(e),
            UnwarpError::Emit { error, .. } | UnwarpError::Outside { error, .. } => Some(error),
            _ => None,
        }
    }
}

impl From<WarpError> for UnwarpError {
    fn from(e: WarpError) -> Self {
        UnwarpError::Warp(e)
    }
}

impl From<RegisterError> for UnwarpError {
    fn from(e: RegisterError) -> Self {
        UnwarpError::Register(e)
    }
}

impl Coded for UnwarpError {
    fn code(&self) -> &'static str {
        match self {
            UnwarpError::RelativePositioning { .. } => "unwarp.relative-positioning",
            UnwarpError::AxisReset { .. } => "unwarp.axis-reset",
            UnwarpError::Inches { .. } => "unwarp.inches",
            UnwarpError::Order { .. } => "unwarp.order",
            UnwarpError::BadPlace { .. } => "unwarp.bad-place",
            UnwarpError::ShapeMismatch { .. } => "unwarp.shape-mismatch",
            UnwarpError::ProbeInRegion { .. } => "unwarp.probe-in-region",
            UnwarpError::Option { .. } => "unwarp.option",
            UnwarpError::Gcode(e) => e.code(),
            UnwarpError::Warp(e) => e.code(),
            UnwarpError::Register(e) => e.code(),
            UnwarpError::Emit { error, .. } => error.code(),
            UnwarpError::Outside { error, .. } => error.code(),
            UnwarpError::OutsideMotion { reason, .. } => match reason {
                OutsideReason::Relative => "unwarp.outside-relative",
                OutsideReason::Arc => "unwarp.outside-arc",
                OutsideReason::AxisReset => "unwarp.outside-axis-reset",
                OutsideReason::Inches => "unwarp.outside-inches",
                OutsideReason::PartialExtrusion => "unwarp.outside-partial-extrusion",
            },
        }
    }
}

/// The codes of the unwarp's own errors (see [`crate::error`]); wrapped errors report theirs.
pub const ERROR_CODES: &[ErrorCode] = &[
    ErrorCode {
        code: "unwarp.relative-positioning",
        area: "unwarp",
        summary: "G91 relative positioning inside the printed region",
    },
    ErrorCode {
        code: "unwarp.axis-reset",
        area: "unwarp",
        summary: "G92 X/Y/Z inside the printed region",
    },
    ErrorCode {
        code: "unwarp.inches",
        area: "unwarp",
        summary: "G20 inches inside the printed region",
    },
    ErrorCode {
        code: "unwarp.order",
        area: "unwarp",
        summary: "the streaming calls came in the wrong order",
    },
    ErrorCode {
        code: "unwarp.bad-place",
        area: "unwarp",
        summary: "place is not two finite numbers",
    },
    ErrorCode {
        code: "unwarp.shape-mismatch",
        area: "unwarp",
        summary: "the object's extrusions do not lie in this job's part (another warp or model, a wrong --offset)",
    },
    ErrorCode {
        code: "unwarp.probe-in-region",
        area: "unwarp",
        summary: "G28 homing Z, G29 or G30 inside the printed region",
    },
    ErrorCode {
        code: "unwarp.option",
        area: "unwarp",
        summary: "an unwarp option outside its range",
    },
    ErrorCode {
        code: "unwarp.outside-relative",
        area: "unwarp",
        summary: "a relative (G91) move in the start/end G-code of a machine output",
    },
    ErrorCode {
        code: "unwarp.outside-arc",
        area: "unwarp",
        summary: "an arc (G2/G3) in the start/end G-code of a machine output",
    },
    ErrorCode {
        code: "unwarp.outside-axis-reset",
        area: "unwarp",
        summary: "G92 X/Y/Z in the start/end G-code of a machine output",
    },
    ErrorCode {
        code: "unwarp.outside-inches",
        area: "unwarp",
        summary: "G20 inches in the start/end G-code of a machine output",
    },
    ErrorCode {
        code: "unwarp.outside-partial-extrusion",
        area: "unwarp",
        summary: "an extruding move after homing that gives only some of X Y Z, on a machine that needs all",
    },
];
