//! Walk a machine G-code (warpslice's or any other tool's) through the [`Checker`]: every
//! `G0`/`G1` with the machine's axis letters is a move, checked, then (if it extrudes)
//! deposited as a bead.
//!
//! The reading itself is [`AxisReader`] (positions, E, layer, line width per line): the
//! [`Walker`] and `crate::check` (`warpslice check`, which also needs feeds and E) both read
//! through it, so they see the same moves.
//!
//! - Positions: absolute (`G90`) or relative (`G91`); missing axes keep their value (0 before
//!   the first). The first move is checked at its end only (where the head came from is not
//!   in the file). `G92` on an axis keeps the raw position and shifts the written one (raw =
//!   written + offset).
//! - E: `M82`/`M83` (relative by default, as warpslice writes for PrusaSlicer), `G92 E`. A move
//!   extrudes when E grows.
//! - Line width: the slicer's `;WIDTH:` comments, else [`DEFAULT_LINE_WIDTH_MM`]; layer
//!   height: `;HEIGHT:`, else [`super::sweep::DEFAULT_LAYER_HEIGHT_MM`].
//! - Layer: the count of the slicer's layer-change comments (`;LAYER_CHANGE`, `;LAYER:`).
//! - Lines are 1-based, as an editor shows them.

use super::sweep::Checker;
use crate::emit::CollisionFinding;
use crate::gcode::lexer::{split, BadWord, Words};
use crate::machine::{Machine, MachineError, MachineSpec};

/// Line width when the G-code gives none, mm (PrusaSlicer's 0.4 mm nozzle default).
pub const DEFAULT_LINE_WIDTH_MM: f64 = 0.45;

/// A `G0`/`G1` that names at least one of the machine's axes.
#[derive(Clone, Debug, PartialEq)]
pub struct AxisMove {
    /// Raw axes before the move (machine order; 0 before the first move).
    pub from: Vec<f64>,
    /// Raw axes after the move.
    pub to: Vec<f64>,
    /// The file's first move (where the head came from is unknown).
    pub first: bool,
    /// E grows on this move.
    pub extrudes: bool,
}

/// One line as [`AxisReader`] read it.
#[derive(Clone, Debug)]
pub struct ReadLine<'a> {
    /// 1-based line number.
    pub number: u64,
    /// The line's bytes (no newline).
    pub bytes: &'a [u8],
    /// The first `G` number of the line.
    pub g: Option<f64>,
    /// The move, when the line is a `G0`/`G1` naming a machine axis.
    pub motion: Option<AxisMove>,
    /// E change of a `G0`/`G1` (mm; relative or absolute E resolved), 0 without E.
    pub de: f64,
    /// Layer (count of layer-change comments so far).
    pub layer: u32,
    /// Line width in force, mm.
    pub width: f64,
    /// Layer height in force (`;HEIGHT:`), mm.
    pub height: f64,
    /// A word whose number does not parse (the walker skips it; `crate::check` refuses it).
    pub bad_word: Option<BadWord>,
}

/// The modal state of a machine G-code read line by line (see the module documentation).
#[derive(Clone, Debug)]
pub struct AxisReader {
    letters: Vec<u8>,
    raw: Vec<f64>,
    offset: Vec<f64>,
    relative: bool,
    relative_e: bool,
    e_last: f64,
    line: u64,
    layer: u32,
    width: f64,
    height: f64,
    first: bool,
    partial: Vec<u8>,
}

impl AxisReader {
    /// A reader of `machine`'s axes (their letters: the first letter of each axis name).
    pub fn new(machine: &dyn Machine) -> AxisReader {
        let letters = machine
            .axis_names()
            .iter()
            .map(|s| {
                s.as_bytes()
                    .first()
                    .copied()
                    .unwrap_or(b'?')
                    .to_ascii_uppercase()
            })
            .collect::<Vec<u8>>();
        let k = letters.len();
        AxisReader {
            letters,
            raw: vec![0.0; k],
            offset: vec![0.0; k],
            relative: false,
            relative_e: true,
            e_last: 0.0,
            line: 0,
            layer: 0,
            width: DEFAULT_LINE_WIDTH_MM,
            height: super::sweep::DEFAULT_LAYER_HEIGHT_MM,
            first: true,
            partial: Vec::new(),
        }
    }

    /// Feed the next bytes; `each` gets every complete line, in order.
    pub fn push<E>(
        &mut self,
        bytes: &[u8],
        mut each: impl FnMut(&ReadLine<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        let mut rest = bytes;
        while let Some(i) = rest.iter().position(|&b| b == b'\n') {
            if self.partial.is_empty() {
                let l = self.line(&rest[..i]);
                each(&l)?;
            } else {
                let mut buf = std::mem::take(&mut self.partial);
                buf.extend_from_slice(&rest[..i]);
                let l = self.line(&buf);
                each(&l)?;
            }
            rest = &rest[i + 1..];
        }
        self.partial.extend_from_slice(rest);
        Ok(())
    }

    /// The last line (without a newline), if any.
    pub fn finish<E>(
        &mut self,
        mut each: impl FnMut(&ReadLine<'_>) -> Result<(), E>,
    ) -> Result<(), E> {
        if !self.partial.is_empty() {
            let buf = std::mem::take(&mut self.partial);
            let l = self.line(&buf);
            each(&l)?;
        }
        Ok(())
    }

    /// Lines read so far.
    pub fn lines(&self) -> u64 {
        self.line
    }

    fn line<'a>(&mut self, bytes: &'a [u8]) -> ReadLine<'a> {
        self.line += 1;
        let s = split(bytes);
        if let Some(c) = s.comment {
            let c = c.trim_ascii_start();
            if c.starts_with(b"LAYER_CHANGE") || c.starts_with(b"LAYER:") {
                self.layer += 1;
            } else if let Some(h) = c
                .strip_prefix(b"HEIGHT:")
                .and_then(|h| std::str::from_utf8(h).ok())
                .and_then(|h| h.trim().parse::<f64>().ok())
            {
                self.height = h;
            } else if let Some(w) = c.strip_prefix(b"WIDTH:") {
                if let Some(w) = std::str::from_utf8(w)
                    .ok()
                    .and_then(|w| w.trim().parse::<f64>().ok())
                    .filter(|w| w.is_finite() && *w > 0.0)
                {
                    self.width = w;
                }
            }
        }
        let mut g: Option<f64> = None;
        let mut m: Option<f64> = None;
        let mut vals: Vec<Option<f64>> = vec![None; self.letters.len()];
        let mut e: Option<f64> = None;
        let mut bad_word = None;
        for w in Words::new(s.code) {
            let w = match w {
                Ok(w) => w,
                Err(b) => {
                    bad_word = bad_word.or(Some(b));
                    continue;
                }
            };
            match w.letter {
                b'G' => g = g.or(w.value),
                b'M' => m = m.or(w.value),
                b'E' => e = w.value,
                l => {
                    if let Some(i) = self.letters.iter().position(|&x| x == l) {
                        vals[i] = w.value;
                    }
                }
            }
        }
        let mut out = ReadLine {
            number: self.line,
            bytes,
            g,
            motion: None,
            de: 0.0,
            layer: self.layer,
            width: self.width,
            height: self.height,
            bad_word,
        };
        if m == Some(82.0) {
            self.relative_e = false;
        } else if m == Some(83.0) {
            self.relative_e = true;
        }
        let Some(g) = g else { return out };
        if g == 90.0 {
            self.relative = false;
        } else if g == 91.0 {
            self.relative = true;
        } else if g == 92.0 {
            if let Some(e) = e {
                self.e_last = e;
            }
            for (i, v) in vals.iter().enumerate() {
                if let Some(v) = v {
                    self.offset[i] = self.raw[i] - v;
                }
            }
        } else if g == 0.0 || g == 1.0 {
            if let Some(e) = e {
                out.de = if self.relative_e { e } else { e - self.e_last };
                if !self.relative_e {
                    self.e_last = e;
                }
            }
            if vals.iter().all(Option::is_none) {
                return out;
            }
            let from = self.raw.clone();
            let mut to = from.clone();
            for (i, v) in vals.iter().enumerate() {
                if let Some(v) = v {
                    to[i] = if self.relative {
                        from[i] + v
                    } else {
                        v + self.offset[i]
                    };
                }
            }
            self.raw.clone_from(&to);
            out.motion = Some(AxisMove {
                from,
                to,
                first: std::mem::take(&mut self.first),
                extrudes: out.de > 0.0,
            });
        }
        out
    }
}

/// The G-code walker over a [`Checker`]: feed it bytes, then [`Walker::finish`].
#[derive(Debug)]
pub struct Walker {
    checker: Checker,
    reader: AxisReader,
}

/// Check one line's move (if any) and deposit its bead (if it extrudes): what the walker does
/// with each line, and `crate::check` with each line it reads.
pub fn walk_line(checker: &mut Checker, l: &ReadLine<'_>) -> Result<(), MachineError> {
    let Some(m) = &l.motion else { return Ok(()) };
    checker.set_layer_height(l.height);
    if m.first {
        // where the head was before the first move is unknown: check where it goes
        checker.check_move(&m.to, &m.to, l.number, l.layer, true)?;
    } else {
        checker.check_move(&m.from, &m.to, l.number, l.layer, false)?;
    }
    if m.extrudes {
        checker.deposit(&m.from, &m.to, l.width)?;
    }
    Ok(())
}

impl Walker {
    /// A walker for `spec`.
    pub fn new(spec: &MachineSpec) -> Result<Walker, MachineError> {
        let checker = Checker::new(spec)?;
        let reader = AxisReader::new(checker.machine());
        Ok(Walker { checker, reader })
    }

    /// Stop checking after the first finding ([`Checker::stop_at_first`]): enough to refuse.
    pub fn stop_at_first(&mut self, yes: bool) {
        self.checker.stop_at_first(yes);
    }

    /// Check without the speed bounds ([`Checker::exhaustive`]): the bounds' reference.
    pub fn exhaustive(&mut self, yes: bool) {
        self.checker.exhaustive(yes);
    }

    /// The checker (findings, counts, material).
    pub fn checker(&self) -> &Checker {
        &self.checker
    }

    /// Every finding so far, to be completed by the caller ([`Checker::findings_mut`]).
    pub fn findings_mut(&mut self) -> &mut [CollisionFinding] {
        self.checker.findings_mut()
    }

    /// The lines read whole so far: a later finding is on a later line.
    pub fn lines_read(&self) -> u64 {
        self.reader.lines()
    }

    /// Feed the next bytes of the G-code.
    pub fn push(&mut self, bytes: &[u8]) -> Result<(), MachineError> {
        let checker = &mut self.checker;
        self.reader.push(bytes, |l| walk_line(checker, l))
    }

    /// The last line (without a newline), and every finding.
    pub fn finish(mut self) -> Result<(Vec<CollisionFinding>, Checker), MachineError> {
        let checker = &mut self.checker;
        self.reader.finish(|l| walk_line(checker, l))?;
        let f = self.checker.take_findings();
        Ok((f, self.checker))
    }
}
