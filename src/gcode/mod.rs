//! G-code in and out: a streaming reader over bytes and a deterministic writer.
//!
//! The reader never copies the file into a `String`. It yields one [`Line`] per source line,
//! in order, with the raw bytes (for verbatim pass-through), what the line did, and — for
//! G0/G1/G2/G3 — the straight pieces it moves along in absolute millimetres (arcs linearised).
//! Values are parsed as f64 (absolute E such as `E12345.67891` keeps every digit).
//!
//! - [`lexer`]: one line's bytes → words, `;`/`( )` comments, `*` checksum.
//! - [`reader`]: the streaming [`Reader`] and the modal [`State`] (the semantics chosen for
//!   G90/G91 vs M82/M83, layers, G28, … are documented there).
//! - [`arc`]: G2/G3 → straight pieces within the chord tolerance.
//! - [`write`](mod@write): deterministic number formatting and [`MoveWriter`].

use glam::DVec3;

use crate::toolpath::Feature;

pub mod arc;
pub mod lexer;
pub mod reader;
pub mod write;

pub use reader::{ReadOptions, Reader, State, MAX_LINE_BYTES};
pub use write::MoveWriter;

/// What one source line did.
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum Command {
    /// Blank line or a comment that changes nothing.
    Comment,
    /// G0/G1/G2/G3. `rapid` for G0, `arc` for G2/G3.
    Move {
        /// G0 (a rapid travel) rather than G1/G2/G3.
        rapid: bool,
        /// G2/G3 (an arc, expanded into straight pieces) rather than G0/G1.
        arc: bool,
    },
    /// G92. `e` is the new E if given; `xyz` whether any of X, Y, Z was given.
    SetPosition {
        /// The new E position (`G92 E…`), mm, if the line sets one.
        e: Option<f64>,
        /// Whether any of X, Y, Z was given (the XYZ position was reset).
        xyz: bool,
    },
    /// M82 (absolute, `relative = false`) or M83 (relative).
    ExtrusionMode {
        /// `true` for M83 (relative E), `false` for M82 (absolute E).
        relative: bool,
    },
    /// G90 (absolute) or G91 (relative): positioning mode for X Y Z (and E unless M82/M83 follow).
    Positioning {
        /// `true` for G91 (relative), `false` for G90 (absolute).
        relative: bool,
    },
    /// G20 (inch = true) or G21 (mm).
    Units {
        /// `true` for G20 (inches), `false` for G21 (millimetres).
        inch: bool,
    },
    /// A layer start: `;LAYER_CHANGE`, `;LAYER:n`, or (in files with no such markers) the first
    /// extrusion at a new, higher Z. The state's `layer` already holds the new index.
    LayerStart,
    /// `;TYPE:…` — the state's `feature` already holds the new feature.
    FeatureType(Feature),
    /// `;WARPSLICE_BEGIN` (true) or `;WARPSLICE_END` (false).
    RegionMarker {
        /// `true` for `;WARPSLICE_BEGIN`, `false` for `;WARPSLICE_END`.
        begin: bool,
    },
    /// A command after which the head is somewhere the file does not say: the firmware moves
    /// it on its own (see [`HeadMove`]). The reader's position is unchanged, except that G28
    /// sets the homed axes to 0.
    HeadMove(HeadMove),
    /// G10 (`retract = true`) or G11: firmware retraction and unretraction (PrusaSlicer's
    /// `--use-firmware-retraction`); the length is the firmware's, not in the file.
    FirmwareRetract {
        /// `true` for G10 (retract), `false` for G11 (unretract).
        retract: bool,
    },
    /// A dwell or a pause that must happen where the head is: `G4`, `M0`, `M1`, `M25`, `M125`
    /// (park and pause), `M226`, `M600` (filament change), `M601`.
    Dwell,
    /// Anything else (temperatures, fans, M-codes, unknown commands): pass through verbatim.
    Other,
}

/// What moves the head on its own ([`Command::HeadMove`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum HeadMove {
    /// G28: homing. `z`: Z is homed too (named, or no axis named: all axes).
    Home {
        /// Z is homed (the nozzle, or a probe, goes down to the bed's trigger point).
        z: bool,
    },
    /// G27: park the nozzle (Marlin: raise Z, then move to the park position).
    Park,
    /// G29 (bed probing / mesh levelling) or G30 (single Z probe): the probe goes down to the
    /// bed at points the firmware chooses.
    Probe,
    /// A tool change `T…` (`T1`, Prusa's `T?`, …): a tool changer or IDEX docks and picks
    /// tools, so the head may end anywhere.
    ToolChange,
}

impl HeadMove {
    /// The command as users know it (`G28`, `T<n>`…), for messages.
    pub fn name(self) -> &'static str {
        match self {
            HeadMove::Home { z: true } => "G28 (homing Z)",
            HeadMove::Home { z: false } => "G28 X/Y (homing)",
            HeadMove::Park => "G27 (park)",
            HeadMove::Probe => "G29/G30 (bed probing)",
            HeadMove::ToolChange => "T (tool change)",
        }
    }
}

/// One straight piece of a move, absolute millimetres in the G-code's own frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Move {
    /// Start of the piece, absolute mm (the G-code's own frame).
    pub from: DVec3,
    /// End of the piece, absolute mm (the G-code's own frame).
    pub to: DVec3,
    /// Filament pushed along this piece, mm (a delta, whatever the file's E mode).
    pub e: f64,
    /// Feed rate in force, mm/min.
    pub f: f64,
    /// The slicer's layer index in force (0 before the first layer start).
    pub layer: u32,
    /// The feature type in force.
    pub feature: Feature,
    /// G0.
    pub rapid: bool,
}

impl Move {
    /// An extruding move: pushes filament and moves in X, Y or Z.
    pub fn is_extrusion(&self) -> bool {
        self.e > 0.0 && self.from != self.to
    }
}

/// One source line: raw bytes, line number, what it did, and its move pieces.
#[derive(Debug)]
pub struct Line<'a> {
    /// The line as in the file, without its terminator (`\n` or `\r\n`).
    pub raw: &'a [u8],
    /// 1-based line number.
    pub number: u64,
    /// What the line did (and, for moves, whether G0 or an arc).
    pub command: Command,
    /// The straight pieces of a move (one for G0/G1, several for an arc, none otherwise).
    pub moves: &'a [Move],
    /// This line starts a layer: an explicit marker (`command == LayerStart`) or, in files with
    /// no markers, the move whose extrusion starts a new, higher layer (see [`reader`]).
    pub layer_start: bool,
}

/// Why G-code could not be read. Messages name the line and what to do.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum GcodeError {
    /// Binary G-code (`.bgcode`, magic `GCDE`).
    Binary,
    /// A word that does not parse (`line`, the text of the word).
    BadNumber {
        /// 1-based line number of the G-code.
        line: u64,
        /// The word that does not parse, as written (e.g. `X1.2.3`, `*abc`).
        word: String,
    },
    /// A motion word without a number (`X`, `XNaN`, `Einf`) or given twice on one line
    /// (`E3.2e0`: exponent notation is not G-code; firmwares read `e0` as a second E word).
    BadWord {
        /// 1-based line number of the G-code.
        line: u64,
        /// The letter.
        letter: char,
        /// What is wrong with it.
        why: &'static str,
    },
    /// `*` checksum that does not match the line.
    Checksum {
        /// 1-based line number of the G-code.
        line: u64,
        /// The checksum computed from the line: XOR of its bytes before `*`.
        expected: u8,
        /// The checksum written after `*` on the line.
        found: u8,
    },
    /// An arc that cannot be expanded (radius too small for the chord, zero radius, no centre).
    BadArc {
        /// 1-based line number of the G-code.
        line: u64,
        /// Why the arc cannot be expanded (e.g. no centre, not in the XY plane).
        reason: String,
    },
    /// Line ends are carriage returns alone (classic Mac OS): the whole file reads as one
    /// over-long line.
    CrLineEnds {
        /// 1-based line number of the G-code.
        line: u64,
    },
    /// A line longer than the reader accepts; `bytes` is the limit it exceeds.
    LineTooLong {
        /// 1-based line number of the G-code.
        line: u64,
        /// The longest line the reader accepts ([`MAX_LINE_BYTES`]), bytes.
        bytes: usize,
    },
}

impl std::fmt::Display for GcodeError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            GcodeError::Binary => write!(
                f,
                "this is binary G-code (.bgcode); export plain-text G-code from the slicer (PrusaSlicer: Printer Settings → General → Firmware → uncheck 'Supports binary G-code')"
            ),
            GcodeError::BadNumber { line, word } => {
                // control bytes shown escaped (a NUL echoed raw cuts a terminal's line)
                write!(f, "G-code line {line}: cannot read the number in '{}'", word.escape_debug())?;
                if word.contains('\0') {
                    write!(f, " (a NUL byte inside the line: the file is damaged; export or copy it again)")?;
                }
                Ok(())
            }
            GcodeError::BadWord { line, letter, why } => write!(
                f,
                "G-code line {line}: the word {letter} {why}; write each word once, as a plain decimal number (no exponent, NaN or inf)"
            ),
            GcodeError::Checksum { line, expected, found } => write!(
                f,
                "G-code line {line}: checksum *{found} does not match the line (expected *{expected})"
            ),
            GcodeError::BadArc { line, reason } => write!(
                f,
                "G-code line {line}: cannot expand the arc ({reason}); turn off arc fitting in the slicer"
            ),
            GcodeError::CrLineEnds { line } => write!(
                f,
                "G-code line {line}: the lines end with a carriage return (CR) alone, not a line feed (LF or CR LF): convert the line ends (an editor's 'Unix (LF)' line ends, or `tr '\\r' '\\n'`)"
            ),
            GcodeError::LineTooLong { line, bytes } => {
                write!(f, "G-code line {line} is longer than {bytes} bytes; is this really G-code?")
            }
        }
    }
}

impl std::error::Error for GcodeError {}

crate::error_codes!(GcodeError, ERROR_CODES, "gcode" {
    Binary => "gcode.binary", "binary G-code (.bgcode) instead of plain text";
    BadNumber => "gcode.bad-number", "a G-code word whose number does not parse";
    BadWord => "gcode.bad-word", "a motion word without a number, or given twice on a line";
    Checksum => "gcode.checksum", "a line whose checksum does not match";
    BadArc => "gcode.bad-arc", "an arc (G2/G3) that cannot be expanded";
    LineTooLong => "gcode.line-too-long", "a line longer than the reader accepts";
    CrLineEnds => "gcode.cr-line-ends", "lines end with CR alone (classic Mac OS line ends)";
} wraps {});
