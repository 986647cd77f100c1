//! The streaming G-code reader: byte chunks → lines → modal state and straight move pieces.
//!
//! # Streaming
//! [`Reader::push`] takes chunks of any size; complete lines are interpreted straight from the
//! chunk, and only the unfinished tail of a chunk is copied into a reused buffer (bounded by
//! [`MAX_LINE_BYTES`]). The same bytes give the same lines, states and errors however they are
//! cut into chunks. Lines end at `\n`; one `\r` before it (CRLF) is not part of the line.
//! After an error the reader stays failed and returns the same error again.
//!
//! # Modal state (Marlin semantics, what slicers target)
//! - G0/G1: one straight piece; G2/G3: arcs in the XY plane (G17), see [`super::arc`].
//!   G18/G19 arcs are refused. Every G0–G3 line yields at least one piece, even `G1 F1800`
//!   (a piece with `from == to`, `e == 0`).
//! - G90/G91 set X Y Z **and E** absolute/relative; M82/M83 set E only. Whichever of the four
//!   came last decides the E mode (Marlin 2 `set_relative_mode` clears the M82/M83 bits; RRF
//!   behaves the same). So `M83` then `G91 … G90` leaves E absolute, as the printer would.
//! - I/J are always offsets from the arc's start (not affected by G90/G91); a missing one of
//!   I, J is 0; when R is given it wins over I/J (as in Marlin). An arc with a `P` word (full
//!   turns) is refused ([`GcodeError::BadArc`]): Marlin (with `ARC_P_CIRCLES`) adds P full
//!   circles, LinuxCNC makes P the number of turns, Klipper and RepRapFirmware ignore it, so
//!   the file prints differently on each and no reading is safe. A radius above
//!   [`super::arc::MAX_ARC_RADIUS`] is refused too.
//! - G92 sets the named axes and E to the given values (the G-code's own coordinates change;
//!   [`Command::SetPosition`] tells the consumer). G92 with no words changes nothing.
//! - G28 sets the named axes (all three if none is named) to 0: the reader does not know the
//!   machine's home; slicers move absolutely after homing. G28, G27 (park), G29/G30 (probing)
//!   and tool changes (`T0`, `T?`) are [`Command::HeadMove`]: the firmware moves the head to a
//!   place the file does not give.
//! - G10/G11 without P or L words are [`Command::FirmwareRetract`] (Marlin, RepRapFirmware,
//!   Klipper firmware retraction); RepRapFirmware's `G10 P… S…` (tool temperatures) and
//!   `G10 L…` (offsets) are [`Command::Other`].
//! - G20/G21: inch values (X Y Z E I J R F) are converted to mm; positions are always mm.
//! - F is modal, mm/min; F ≤ 0 is ignored (as Marlin does).
//! - [`super::Move::e`] is always the filament delta of the piece, mm, whatever the E mode.
//!   On an arc, E (and Z) is spread over the pieces proportionally to their length.
//! - The first word after an optional `N` word is the command; only one command per line is
//!   interpreted (slicers write one). Lines that do not start with a recognised command
//!   (`M104 S200`, `T0`, `M117 any text`, garbage) are [`Command::Other`] and are not lexed
//!   further, so they can never fail. A `*` checksum is verified on every line that has one.
//!
//! # Layers
//! `state.layer` is 0-based and is 0 before the first layer start too (start G-code, purge
//! lines). Explicit markers: `;LAYER_CHANGE` (PrusaSlicer, SuperSlicer, Orca; followed by
//! `;Z:<z>`, which sets `state.layer_z`) and `;LAYER:<n>` (Cura; `n` may be negative with a raft:
//! the reader counts markers and ignores `n`). The first explicit marker starts layer 0 even
//! if layers were inferred before it (purge lines in the start G-code); each later marker adds
//! one. Two markers with no move line between them are one layer start (the second is a plain
//! [`Command::Comment`]).
//! Files with no explicit marker so far (Slic3r without layer G-code): the first extruding
//! G0–G3 line whose end Z is above the previous layer's Z by more than [`LAYER_Z_EPSILON`]
//! starts a layer; that line has [`Line::layer_start`] set (its command stays `Move`) and its
//! pieces carry the new index, while the travels before it (the Z move, the approach) carry the
//! previous one. Spiral-vase files without markers would start a layer on every line; printing
//! objects one after another without markers keeps the highest index.
//!
//! # Cost
//! No heap allocation per line in the steady state: the tail buffer, the move pieces and the
//! `;TYPE:` label cache are reused. Errors allocate their message.

use glam::{DVec2, DVec3};

use super::arc::{self, Centre};
use super::lexer::{self, BadWord, Word, Words};
use super::{Command, GcodeError, HeadMove, Line, Move};
use crate::toolpath::Feature;

/// Longest accepted line, bytes (without its terminator). G-code lines are under 100 bytes;
/// a longer one means the input is not G-code (or has no line breaks), and refusing it bounds
/// the reader's memory.
pub const MAX_LINE_BYTES: usize = 64 * 1024;
/// Millimetres per inch (G20).
pub const MM_PER_INCH: f64 = 25.4;
/// A marker-less file starts a new layer at an extrusion whose Z is above the previous layer's
/// by more than this, mm (slicers write Z with 3 decimals; layers are ≥ 0.02 mm apart).
pub const LAYER_Z_EPSILON: f64 = 1e-4;
/// First bytes of binary G-code (.bgcode).
const BGCODE_MAGIC: &[u8; 4] = b"GCDE";
/// Most distinct `;TYPE:` labels remembered (slicers use about a dozen).
const TYPE_CACHE_SIZE: usize = 32;

/// Reader settings.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ReadOptions {
    /// Largest distance between an arc and its chords, mm.
    pub arc_chord_tolerance: f64,
    /// Lines (1-based, inclusive) whose arcs are expanded; outside them an arc is checked but
    /// given as one straight piece from its start to its end (with its E): for a reader whose
    /// lines outside a range pass through verbatim (the unwarp's pass 2 outside the warped
    /// region). `None`: every arc is expanded.
    pub arcs_in: Option<[u64; 2]>,
}

impl Default for ReadOptions {
    fn default() -> Self {
        ReadOptions {
            arc_chord_tolerance: crate::tolerance::ARC_CHORD_TOLERANCE,
            arcs_in: None,
        }
    }
}

/// The modal state after the last line read.
#[derive(Clone, Debug, PartialEq)]
pub struct State {
    /// Absolute position, mm (after G92 offsets: the G-code's own coordinates).
    pub position: glam::DVec3,
    /// E is relative: set by M83 or G91, cleared by M82 or G90 (whichever came last).
    pub e_relative: bool,
    /// X Y Z are relative (G91) rather than absolute (G90).
    pub positioning_relative: bool,
    /// Values are in inches (G20) rather than mm (G21); the reader converts them to mm.
    pub inch: bool,
    /// Feed rate, mm/min (0 until the file sets one).
    pub feed: f64,
    /// The slicer's 0-based layer index (0 before the first layer start too).
    pub layer: u32,
    /// The feature type from the last `;TYPE:` comment (`Unknown` before any).
    pub feature: Feature,
    /// Whether an explicit layer marker (`;LAYER_CHANGE`, `;LAYER:`) has been seen.
    pub layer_markers: bool,
    /// The E axis value in the file's coordinates, mm (after G92 E; exact as written in
    /// absolute mode).
    pub e: f64,
    /// The current layer's Z, mm: from PrusaSlicer's `;Z:` after the marker, otherwise the end Z
    /// of the layer's first extruding line. `None` until known.
    pub layer_z: Option<f64>,
}

impl Default for State {
    fn default() -> Self {
        State {
            position: DVec3::ZERO,
            e_relative: false,
            positioning_relative: false,
            inch: false,
            feed: 0.0,
            layer: 0,
            feature: Feature::Unknown,
            layer_markers: false,
            e: 0.0,
            layer_z: None,
        }
    }
}

/// Streaming reader: push byte chunks, get one [`Line`] per complete source line.
///
/// ```
/// use warpslice::gcode::{GcodeError, Line, Reader, State};
/// let mut extruded = 0.0;
/// let mut sink = |line: Line<'_>, _state: &State| {
///     extruded += line.moves.iter().map(|m| m.e).sum::<f64>();
///     Ok::<(), GcodeError>(())
/// };
/// let mut reader = Reader::default();
/// reader.push(b"M83\nG1 X10 E0.5\nG2 X20 I5 E", &mut sink)?;
/// reader.push(b"1.0\nG1 X0 E0.25", &mut sink)?; // a line split across chunks
/// reader.finish(&mut sink)?; // the last line has no terminator
/// assert!((extruded - 1.75).abs() < 1e-12);
/// # Ok::<(), GcodeError>(())
/// ```
///
/// After an error (from the reader or the sink) stop using the reader: reader errors are
/// returned again by every later call.
pub struct Reader {
    /// The unfinished last line of the previous chunks.
    pending: Vec<u8>,
    core: Core,
    /// After [`Reader::finish`]: the number of the last line when it had no line end.
    unterminated: Option<u64>,
}

/// Everything but the tail buffer (so a line borrowed from it can be interpreted).
struct Core {
    opts: ReadOptions,
    state: State,
    /// Number of the next line (1-based).
    line_no: u64,
    moves: Vec<Move>,
    magic_checked: bool,
    failed: Option<GcodeError>,
    /// G17 (XY plane) in force; G18/G19 clear it.
    plane_xy: bool,
    /// Whether any layer start (explicit or inferred) happened.
    layer_started: bool,
    /// A G0–G3 line since the last explicit marker.
    moved_since_marker: bool,
    /// Z of the last inferred layer start.
    inferred_z: f64,
    type_cache: Vec<(Vec<u8>, Feature)>,
}

type Sink<'s, E> = dyn FnMut(Line<'_>, &State) -> Result<(), E> + 's;

impl Reader {
    /// A reader at the start of a file (line 1, default [`State`]).
    pub fn new(opts: ReadOptions) -> Reader {
        Reader {
            pending: Vec::new(),
            unterminated: None,
            core: Core {
                opts,
                state: State::default(),
                line_no: 1,
                moves: Vec::new(),
                magic_checked: false,
                failed: None,
                plane_xy: true,
                layer_started: false,
                moved_since_marker: false,
                inferred_z: f64::NEG_INFINITY,
                type_cache: Vec::new(),
            },
        }
    }

    /// The modal state after the last line delivered.
    pub fn state(&self) -> &State {
        &self.core.state
    }

    /// After [`Reader::finish`]: the number of the file's last line if it had no line end
    /// (a file cut short ends so, possibly in the middle of a number).
    pub fn unterminated_line(&self) -> Option<u64> {
        self.unterminated
    }

    /// Feed a chunk; `sink` is called for every complete line, in order.
    pub fn push<E: From<GcodeError>>(
        &mut self,
        chunk: &[u8],
        sink: &mut dyn FnMut(Line<'_>, &State) -> Result<(), E>,
    ) -> Result<(), E> {
        if let Some(e) = &self.core.failed {
            return Err(e.clone().into());
        }
        let mut chunk = chunk;
        if !self.core.magic_checked {
            let have = self.pending.len();
            let take = (BGCODE_MAGIC.len() - have).min(chunk.len());
            let prefix_matches = self.pending[..] == BGCODE_MAGIC[..have]
                && chunk[..take] == BGCODE_MAGIC[have..have + take];
            if !prefix_matches {
                self.core.magic_checked = true;
            } else if have + take == BGCODE_MAGIC.len() {
                return Err(self.core.fail(GcodeError::Binary).into());
            } else {
                self.pending.extend_from_slice(chunk);
                return Ok(());
            }
        }
        if !self.pending.is_empty() {
            match find_newline(chunk) {
                None => return self.append(chunk),
                Some(p) => {
                    self.append::<E>(&chunk[..p])?;
                    self.core.line(&self.pending, sink)?;
                    self.pending.clear();
                    chunk = &chunk[p + 1..];
                }
            }
        }
        while let Some(p) = find_newline(chunk) {
            self.core.line(&chunk[..p], sink)?;
            chunk = &chunk[p + 1..];
        }
        self.append(chunk)
    }

    /// End of input: flush a last line without terminator.
    pub fn finish<E: From<GcodeError>>(
        &mut self,
        sink: &mut dyn FnMut(Line<'_>, &State) -> Result<(), E>,
    ) -> Result<(), E> {
        if let Some(e) = &self.core.failed {
            return Err(e.clone().into());
        }
        self.core.magic_checked = true;
        if !self.pending.is_empty() {
            self.unterminated = Some(self.core.line_no);
            let r = self.core.line(&self.pending, sink);
            self.pending.clear();
            r?;
        }
        Ok(())
    }

    /// Add to the unfinished line, refusing it before copying if it gets too long (one `\r`
    /// beyond the limit is allowed: it may be the CR of a CRLF).
    fn append<E: From<GcodeError>>(&mut self, bytes: &[u8]) -> Result<(), E> {
        let n = self.pending.len() + bytes.len();
        let last = bytes.last().or(self.pending.last()).copied();
        if n > MAX_LINE_BYTES + 1 || (n == MAX_LINE_BYTES + 1 && last != Some(b'\r')) {
            let line = self.core.line_no;
            // a CR inside the over-long line: CR-only line ends
            let cr = self
                .pending
                .iter()
                .chain(bytes)
                .take(MAX_LINE_BYTES)
                .any(|&b| b == b'\r');
            let e = if cr {
                GcodeError::CrLineEnds { line }
            } else {
                GcodeError::LineTooLong {
                    line,
                    bytes: MAX_LINE_BYTES,
                }
            };
            return Err(self.core.fail(e).into());
        }
        self.pending.extend_from_slice(bytes);
        Ok(())
    }
}

impl Default for Reader {
    fn default() -> Self {
        Reader::new(ReadOptions::default())
    }
}

/// Whether a word the lexer could not read is a tool word (`T?`, `Tx`, `tc`).
fn is_tool_word(s: &[u8]) -> bool {
    let s = trim_start(s);
    matches!(s.first(), Some(b'T' | b't'))
}

/// Position of the first `\n`.
#[inline]
fn find_newline(s: &[u8]) -> Option<usize> {
    let i = lexer::find_any(s, b"\n");
    (i < s.len()).then_some(i)
}

/// Integer G/M code number, if the value is a whole number below 10000.
#[inline]
fn code_number(v: f64) -> Option<u32> {
    if (0.0..10000.0).contains(&v) && v == (v as u32) as f64 {
        Some(v as u32)
    } else {
        None
    }
}

/// The words of a G0–G3 or G92 line (already in the file's units).
#[derive(Default)]
struct MoveWords {
    axes: [Option<f64>; 3],
    e: Option<f64>,
    f: Option<f64>,
    i: Option<f64>,
    j: Option<f64>,
    r: Option<f64>,
    /// A `P` word (an arc's full turns) appeared.
    p_seen: bool,
    /// Which of X Y Z appeared (even without a value, `G28 X`).
    axis_seen: [bool; 3],
}

impl Core {
    fn fail(&mut self, e: GcodeError) -> GcodeError {
        self.failed = Some(e.clone());
        e
    }

    /// Interpret one line (terminator removed except a possible `\r`) and hand it to the sink.
    fn line<E: From<GcodeError>>(&mut self, raw: &[u8], sink: &mut Sink<'_, E>) -> Result<(), E> {
        let number = self.line_no;
        self.line_no += 1;
        let raw = raw.strip_suffix(b"\r").unwrap_or(raw);
        if raw.len() > MAX_LINE_BYTES {
            let e = if raw.contains(&b'\r') {
                GcodeError::CrLineEnds { line: number }
            } else {
                GcodeError::LineTooLong {
                    line: number,
                    bytes: MAX_LINE_BYTES,
                }
            };
            return Err(self.fail(e).into());
        }
        self.moves.clear();
        let mut text = raw;
        if number == 1 {
            text = text.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(text);
        }
        let (command, layer_start) = match self.interpret(text, number) {
            Ok(c) => c,
            Err(e) => return Err(self.fail(e).into()),
        };
        sink(
            Line {
                raw,
                number,
                command,
                moves: &self.moves,
                layer_start,
            },
            &self.state,
        )
    }

    /// What the line does; updates the state and fills `self.moves`.
    fn interpret(&mut self, text: &[u8], line: u64) -> Result<(Command, bool), GcodeError> {
        let split = lexer::split(text);
        if let Some((xor, digits)) = split.checksum {
            let found = lexer::parse_checksum(digits).ok_or_else(|| GcodeError::BadNumber {
                line,
                word: format!("*{}", String::from_utf8_lossy(digits)),
            })?;
            if found != xor {
                return Err(GcodeError::Checksum {
                    line,
                    expected: xor,
                    found,
                });
            }
        }
        let mut words = Words::new(split.code);
        let first = loop {
            match words.next() {
                None => break None,
                Some(Ok(Word { letter: b'N', .. })) => continue,
                Some(Ok(w)) => break Some(w),
                // `T?`, `Tx`, `Tc` (Prusa MMU): a tool change without a number
                Some(Err(BadWord { start, .. })) if is_tool_word(&split.code[start..]) => {
                    return Ok((Command::HeadMove(HeadMove::ToolChange), false))
                }
                Some(Err(_)) => return Ok((Command::Other, false)),
            }
        };
        let Some(first) = first else {
            let c = self.comment(split.comment);
            return Ok((c, c == Command::LayerStart));
        };
        let code = match first.value.and_then(code_number) {
            Some(c) => c,
            None if first.letter == b'T' => {
                return Ok((Command::HeadMove(HeadMove::ToolChange), false))
            }
            None => return Ok((Command::Other, false)),
        };
        let s = &mut self.state;
        let command = match (first.letter, code) {
            (b'G', 0..=3) => return self.motion(code, &mut words, split.code, line),
            (b'G', 17) => {
                self.plane_xy = true;
                Command::Other
            }
            (b'G', 18 | 19) => {
                self.plane_xy = false;
                Command::Other
            }
            (b'G', 20 | 21) => {
                s.inch = code == 20;
                Command::Units { inch: s.inch }
            }
            (b'G', 28) => {
                let w = read_words(&mut words, split.code, line, true)?;
                let any = w.axis_seen.contains(&true);
                for (k, seen) in w.axis_seen.iter().enumerate() {
                    if *seen || !any {
                        s.position[k] = 0.0;
                    }
                }
                Command::HeadMove(HeadMove::Home {
                    z: w.axis_seen[2] || !any,
                })
            }
            (b'G', 27) => Command::HeadMove(HeadMove::Park),
            (b'G', 4) | (b'M', 0 | 1 | 25 | 125 | 226 | 600 | 601) => Command::Dwell,
            (b'G', 29 | 30) => Command::HeadMove(HeadMove::Probe),
            // RepRapFirmware's `G10 P<tool> S<temp>` and `G10 L…` (offsets) are not retraction
            (b'G', 10 | 11)
                if !words.any(|w| {
                    matches!(
                        w,
                        Ok(Word {
                            letter: b'P' | b'L',
                            ..
                        })
                    )
                }) =>
            {
                Command::FirmwareRetract {
                    retract: code == 10,
                }
            }
            (b'T', _) => Command::HeadMove(HeadMove::ToolChange),
            (b'G', 90 | 91) => {
                let relative = code == 91;
                s.positioning_relative = relative;
                s.e_relative = relative;
                Command::Positioning { relative }
            }
            (b'G', 92) => {
                let w = read_words(&mut words, split.code, line, false)?;
                let u = if s.inch { MM_PER_INCH } else { 1.0 };
                let mut xyz = false;
                for (k, v) in w.axes.iter().enumerate() {
                    if let Some(v) = v {
                        s.position[k] = v * u;
                        xyz = true;
                    }
                }
                let e = w.e.map(|v| v * u);
                if let Some(e) = e {
                    s.e = e;
                }
                Command::SetPosition { e, xyz }
            }
            (b'M', 82 | 83) => {
                s.e_relative = code == 83;
                Command::ExtrusionMode {
                    relative: s.e_relative,
                }
            }
            _ => Command::Other,
        };
        Ok((command, false))
    }

    /// A line with no code: markers in its `;` comment.
    fn comment(&mut self, comment: Option<&[u8]>) -> Command {
        let Some(c) = comment else {
            return Command::Comment;
        };
        let c = trim_end(c);
        // PrusaSlicer, Slic3r PE and CuraEngine write `;TYPE:Label`; Bambu Studio and
        // OrcaSlicer `; FEATURE: Label` (their G-code processor's role tag)
        let label = c
            .strip_prefix(b"TYPE:")
            .or_else(|| trim_start(c).strip_prefix(b"FEATURE:"));
        if let Some(label) = label {
            let f = self.feature_of(label);
            self.state.feature = f;
            return Command::FeatureType(f);
        }
        if c == b"LAYER_CHANGE" {
            return self.explicit_layer_start();
        }
        if let Some(n) = c.strip_prefix(b"LAYER:") {
            let n = n.strip_prefix(b"-").unwrap_or(n);
            if !n.is_empty() && n.iter().all(u8::is_ascii_digit) {
                return self.explicit_layer_start();
            }
            return Command::Comment;
        }
        if let Some(rest) = c.strip_prefix(b"WARPSLICE_") {
            for (word, begin) in [(&b"BEGIN"[..], true), (&b"END"[..], false)] {
                if let Some(after) = rest.strip_prefix(word) {
                    if after.is_empty() || after[0] == b' ' || after[0] == b'\t' {
                        return Command::RegionMarker { begin };
                    }
                }
            }
            return Command::Comment;
        }
        if let Some(z) = c.strip_prefix(b"Z:") {
            if self.state.layer_markers && !self.moved_since_marker {
                if let Some(v) = lexer::parse_value(trim_start(z)) {
                    self.state.layer_z = Some(v);
                }
            }
            return Command::Comment;
        }
        Command::Comment
    }

    fn explicit_layer_start(&mut self) -> Command {
        if !self.state.layer_markers {
            self.state.layer_markers = true;
            self.state.layer = 0;
        } else if !self.moved_since_marker {
            return Command::Comment;
        } else {
            self.state.layer = self.state.layer.saturating_add(1);
        }
        self.layer_started = true;
        self.moved_since_marker = false;
        self.state.layer_z = None;
        Command::LayerStart
    }

    /// Feature of a `;TYPE:` label, through a small cache (labels repeat every layer).
    fn feature_of(&mut self, label: &[u8]) -> Feature {
        if let Some((_, f)) = self.type_cache.iter().find(|(l, _)| l == label) {
            return *f;
        }
        let f = match core::str::from_utf8(label) {
            Ok(s) => Feature::from_type_label(s),
            Err(_) => Feature::Unknown,
        };
        if self.type_cache.len() < TYPE_CACHE_SIZE {
            self.type_cache.push((label.to_vec(), f));
        }
        f
    }

    /// G0–G3.
    fn motion(
        &mut self,
        code: u32,
        words: &mut Words<'_>,
        text: &[u8],
        line: u64,
    ) -> Result<(Command, bool), GcodeError> {
        let w = read_words(words, text, line, false)?;
        let s = &mut self.state;
        let u = if s.inch { MM_PER_INCH } else { 1.0 };
        let from = s.position;
        let mut to = from;
        for (k, v) in w.axes.iter().enumerate() {
            if let Some(v) = v {
                to[k] = if s.positioning_relative {
                    to[k] + v * u
                } else {
                    v * u
                };
            }
        }
        let mut e = 0.0;
        if let Some(v) = w.e {
            let v = v * u;
            if s.e_relative {
                e = v;
                s.e += v;
            } else {
                e = v - s.e;
                s.e = v;
            }
        }
        if let Some(f) = w.f {
            if f > 0.0 {
                s.feed = f * u;
            }
        }
        self.moved_since_marker = true;
        let mut layer_start = false;
        if !s.layer_markers && e > 0.0 && to != from && to.z > self.inferred_z + LAYER_Z_EPSILON {
            if self.layer_started {
                s.layer = s.layer.saturating_add(1);
            } else {
                s.layer = 0;
                self.layer_started = true;
            }
            self.inferred_z = to.z;
            s.layer_z = Some(to.z);
            layer_start = true;
        }
        if e > 0.0 && to != from && s.layer_z.is_none() {
            s.layer_z = Some(to.z);
        }
        let template = Move {
            from,
            to,
            e,
            f: s.feed,
            layer: s.layer,
            feature: s.feature,
            rapid: code == 0,
        };
        let arc = code >= 2;
        let chord_only = self.opts.arcs_in.is_some_and(|[a, b]| line < a || line > b);
        if !arc {
            self.moves.push(template);
        } else {
            if w.p_seen {
                return Err(GcodeError::BadArc {
                    line,
                    reason: "its P word (full turns) means extra circles to Marlin (ARC_P_CIRCLES), the number of turns to LinuxCNC and nothing to Klipper or RepRapFirmware, so what it prints depends on the firmware".into(),
                });
            }
            if !self.plane_xy {
                return Err(GcodeError::BadArc {
                    line,
                    reason: "only arcs in the XY plane (G17) are supported".into(),
                });
            }
            let centre = match (w.r, w.i, w.j) {
                (Some(r), _, _) => Centre::Radius(r * u),
                (None, None, None) => {
                    return Err(GcodeError::BadArc {
                        line,
                        reason: "no centre: give I and J, or R".into(),
                    })
                }
                (None, i, j) => {
                    Centre::Offset(DVec2::new(i.unwrap_or(0.0) * u, j.unwrap_or(0.0) * u))
                }
            };
            let moves = &mut self.moves;
            let mut prev = from;
            // outside `arcs_in` (lines that pass through verbatim) the arc is checked, not
            // expanded: one piece from its start to its end carries its E
            let tolerance = if chord_only {
                f64::INFINITY
            } else {
                self.opts.arc_chord_tolerance
            };
            arc::linearise(from, to, centre, code == 2, tolerance, |p| {
                moves.push(Move {
                    from: prev,
                    to: p,
                    e: 0.0,
                    ..template
                });
                prev = p;
            })
            .map_err(|reason| GcodeError::BadArc { line, reason })?;
            spread_e(moves, e);
        }
        self.state.position = to;
        Ok((
            Command::Move {
                rapid: code == 0,
                arc,
            },
            layer_start,
        ))
    }
}

/// Spread `e` over the pieces proportionally to their length (equally if all are points);
/// the last piece takes the remainder so the sum is `e` up to one rounding.
fn spread_e(moves: &mut [Move], e: f64) {
    let n = moves.len();
    if n == 0 || e == 0.0 {
        return;
    }
    let total: f64 = moves.iter().map(|m| (m.to - m.from).length()).sum();
    let mut given = 0.0;
    for (k, m) in moves.iter_mut().enumerate() {
        if k + 1 == n {
            m.e = e - given;
        } else {
            let share = if total > 0.0 {
                (m.to - m.from).length() / total
            } else {
                1.0 / n as f64
            };
            m.e = e * share;
            given += m.e;
        }
    }
}

/// Read the remaining words of a G0–G3/G28/G92 line; other letters are ignored. A motion word
/// (X Y Z E F I J R) given twice, or without a number (only G28 names bare axes: `bare`), is a
/// [`GcodeError::BadWord`]: `E3.2e0` would otherwise be read as E0, `XNaN` as no X.
fn read_words(
    words: &mut Words<'_>,
    text: &[u8],
    line: u64,
    bare: bool,
) -> Result<MoveWords, GcodeError> {
    let mut w = MoveWords::default();
    let mut seen = 0u32;
    for r in words {
        let word = r.map_err(|BadWord { start, end }| GcodeError::BadNumber {
            line,
            word: String::from_utf8_lossy(&text[start..end.min(text.len())]).into_owned(),
        })?;
        let v = word.value;
        if let Some(k) = b"XYZEFIJR".iter().position(|&c| c == word.letter) {
            let bad = |why| GcodeError::BadWord {
                line,
                letter: word.letter as char,
                why,
            };
            if seen & (1 << k) != 0 {
                return Err(bad("is given twice"));
            }
            seen |= 1 << k;
            if v.is_none() && !bare {
                return Err(bad("has no number"));
            }
        }
        match word.letter {
            b'X' => {
                w.axes[0] = v;
                w.axis_seen[0] = true;
            }
            b'Y' => {
                w.axes[1] = v;
                w.axis_seen[1] = true;
            }
            b'Z' => {
                w.axes[2] = v;
                w.axis_seen[2] = true;
            }
            b'E' => w.e = v,
            b'F' => w.f = v,
            b'I' => w.i = v,
            b'J' => w.j = v,
            b'R' => w.r = v,
            b'P' => w.p_seen = true,
            _ => {}
        }
    }
    Ok(w)
}

fn trim_start(s: &[u8]) -> &[u8] {
    let n = s.iter().take_while(|&&b| b == b' ' || b == b'\t').count();
    &s[n..]
}

fn trim_end(s: &[u8]) -> &[u8] {
    let mut n = s.len();
    while n > 0 && matches!(s[n - 1], b' ' | b'\t' | b'\r') {
        n -= 1;
    }
    &s[..n]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_huge_chunk_without_newline_is_refused_before_it_is_copied() {
        let mut reader = Reader::default();
        let mut sink = |_: Line<'_>, _: &State| Ok::<(), GcodeError>(());
        reader.push(b"G1 X1\n;abc", &mut sink).unwrap();
        let big = vec![b'a'; 4 * MAX_LINE_BYTES];
        let r = reader.push(&big, &mut sink);
        assert_eq!(
            r,
            Err(GcodeError::LineTooLong {
                line: 2,
                bytes: MAX_LINE_BYTES
            })
        );
        assert!(reader.pending.capacity() < 2 * MAX_LINE_BYTES);
    }
}
