//! Walk a machine G-code (warpslice's or any other tool's) through the [`Checker`]: every
//! `G0`/`G1` with the machine's axis letters is a move, checked, then (if it extrudes)
//! deposited as a bead.
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
use crate::gcode::lexer::{split, Words};
use crate::machine::{MachineError, MachineSpec};

/// Line width when the G-code gives none, mm (PrusaSlicer's 0.4 mm nozzle default).
pub const DEFAULT_LINE_WIDTH_MM: f64 = 0.45;

/// The G-code walker over a [`Checker`]: feed it bytes, then [`Walker::finish`].
#[derive(Debug)]
pub struct Walker {
    checker: Checker,
    letters: Vec<u8>,
    raw: Vec<f64>,
    offset: Vec<f64>,
    relative: bool,
    relative_e: bool,
    e_last: f64,
    line: u64,
    layer: u32,
    width: f64,
    first: bool,
    partial: Vec<u8>,
}

impl Walker {
    /// A walker for `spec`.
    pub fn new(spec: &MachineSpec) -> Result<Walker, MachineError> {
        let checker = Checker::new(spec)?;
        let m = checker.machine();
        let letters = m
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
        Ok(Walker {
            checker,
            letters,
            raw: vec![0.0; k],
            offset: vec![0.0; k],
            relative: false,
            relative_e: true,
            e_last: 0.0,
            line: 0,
            layer: 0,
            width: DEFAULT_LINE_WIDTH_MM,
            first: true,
            partial: Vec::new(),
        })
    }

    /// Stop checking after the first finding ([`Checker::stop_at_first`]): enough to refuse.
    pub fn stop_at_first(&mut self, yes: bool) {
        self.checker.stop_at_first(yes);
    }

    /// The checker (findings, counts, material).
    pub fn checker(&self) -> &Checker {
        &self.checker
    }

    /// Feed the next bytes of the G-code.
    pub fn push(&mut self, bytes: &[u8]) -> Result<(), MachineError> {
        let mut rest = bytes;
        while let Some(i) = rest.iter().position(|&b| b == b'\n') {
            if self.partial.is_empty() {
                self.line(&rest[..i])?;
            } else {
                let mut l = std::mem::take(&mut self.partial);
                l.extend_from_slice(&rest[..i]);
                self.line(&l)?;
            }
            rest = &rest[i + 1..];
        }
        self.partial.extend_from_slice(rest);
        Ok(())
    }

    /// The last line (without a newline), and every finding.
    pub fn finish(mut self) -> Result<(Vec<CollisionFinding>, Checker), MachineError> {
        if !self.partial.is_empty() {
            let l = std::mem::take(&mut self.partial);
            self.line(&l)?;
        }
        let f = self.checker.take_findings();
        Ok((f, self.checker))
    }

    fn line(&mut self, bytes: &[u8]) -> Result<(), MachineError> {
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
                self.checker.set_layer_height(h);
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
        for w in Words::new(s.code).flatten() {
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
        if m == Some(82.0) {
            self.relative_e = false;
        } else if m == Some(83.0) {
            self.relative_e = true;
        }
        let Some(g) = g else { return Ok(()) };
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
            if vals.iter().all(Option::is_none) {
                return Ok(());
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
            let extrudes = e.is_some_and(|e| {
                if self.relative_e {
                    e > 0.0
                } else {
                    e > self.e_last
                }
            });
            if let (Some(e), false) = (e, self.relative_e) {
                self.e_last = e;
            }
            if std::mem::take(&mut self.first) {
                // where the head was before the first move is unknown: check where it goes
                self.checker
                    .check_move(&to, &to, self.line, self.layer, true)?;
            } else {
                self.checker
                    .check_move(&from, &to, self.line, self.layer, false)?;
            }
            if extrudes {
                self.checker.deposit(&from, &to, self.width)?;
            }
            self.raw = to;
        }
        Ok(())
    }
}
