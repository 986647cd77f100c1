//! [`CheckStream`]: a machine G-code checked as it streams in (push bytes, then finish).
//!
//! Every line goes through [`AxisReader`] (the collision walker's reader: positions with
//! `G90`/`G91`/`G92`, E with `M82`/`M83`/`G92 E`, layers, line widths), then:
//! - **reach**: the move's raw axes against the machine's travel and rotary ranges
//!   ([`Reach`], the emitter's check): one finding per axis outside, with the end it passes;
//! - **collisions**: [`walk_line`] through the [`Checker`] (the emitter's on-by-default check);
//!   a machine the checker cannot judge (the lathe) is checked without, with a warning;
//! - **speeds and time**: [`AxisSpeeds`] (the emitter's estimate): F is modal, `G93` makes it
//!   inverse time (`T = 1/F` minutes) until `G94`; otherwise `T = D/F` with D the flavour's
//!   move length ([`crate::machine::length_rule`]). `G0` is timed like `G1` at the F in force;
//! - **E and tilt**: every E change of a `G0`/`G1` adds to the net E; a move that extrudes
//!   adds its tool axis' tilt `acos(n_z)` (n from [`Machine::forward`] at the move's end, part
//!   frame) to the histogram.
//!
//! Arcs (`G2`/`G3`) are not walked (no 4/5-axis firmware interpolates rotary axes on arcs
//! the same way): each is a warning.

use glam::DVec3;

use super::options::CheckOptions;
use super::report::{CheckReport, Finding, FindingCounts, FindingKind, TILT_BINS, TILT_BIN_DEG};
use super::CheckError;
use crate::collision::{walk_line, AxisReader, Checker, ReadLine};
use crate::emit::CollisionFinding;
use crate::machine::length_rule::LengthRule;
use crate::machine::reach::Reach;
use crate::machine::speed::AxisSpeeds;
use crate::machine::{AxisLimit, FeedMode, Machine, MachineError, MachineSpec};

/// Arc lines named in the warnings, at most (the count is always given).
pub const ARC_WARNINGS_LISTED: usize = 5;

/// The warning of a check told to leave the collisions out (`skip_collisions`).
pub const SKIPPED_COLLISIONS: &str = "collisions not checked (skip_collisions)";

/// One point of the checked tip path (the preview's).
#[derive(Clone, Debug, PartialEq)]
pub struct PathPoint {
    /// 1-based file line of the move ending here.
    pub line: u64,
    /// Tip, part frame, mm.
    pub p: DVec3,
    /// Unit tool axis (tip → nozzle), part frame.
    pub n: DVec3,
    /// E change of the move, mm.
    pub de: f64,
    /// Layer.
    pub layer: u32,
    /// The move does not extrude.
    pub travel: bool,
    /// The machine's axis values after the move (machine order, as read: linear mm, rotary
    /// degrees), the pose [`crate::collision::posed_head`] draws the head at.
    pub axes: Vec<f64>,
    /// The head parts the collision check found in collision on this move (each once, in the
    /// order found; every one, whatever `max_findings` lists).
    pub collisions: Vec<String>,
}

/// The state of a check (see the module documentation).
pub struct CheckStream {
    machine: Box<dyn Machine>,
    limits: Vec<AxisLimit>,
    checker: Option<Checker>,
    reader: AxisReader,
    reach: Reach,
    speeds: AxisSpeeds,
    rule: LengthRule,
    options: CheckOptions,
    report: CheckReport,
    feed: f64,
    inverse_time: bool,
    arcs: Vec<u64>,
    arc_count: u64,
    path: Vec<PathPoint>,
    /// The axis letters (the reader's: first letter of each axis name).
    letters: Vec<u8>,
    /// `skip_collisions` left out a check that could run: the head parts it would have
    /// checked ([`CheckStream::finish_with_collisions`]).
    skipped_parts: Option<Vec<String>>,
}

impl std::fmt::Debug for CheckStream {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("CheckStream")
            .field("machine", &self.machine.name())
            .field("lines", &self.report.lines)
            .finish()
    }
}

impl CheckStream {
    /// A check of a G-code for `spec` with `options`.
    pub fn new(spec: &MachineSpec, options: &CheckOptions) -> Result<CheckStream, CheckError> {
        let machine = spec.build()?;
        let limits = machine.limits().to_vec();
        let bounds = spec.axis_bounds(&limits)?;
        let flavour = options.flavour.or(spec.flavour).unwrap_or_default();
        let mut report = CheckReport {
            machine: machine.name().to_string(),
            flavour: flavour.name().to_string(),
            tilt_histogram: vec![0; TILT_BINS],
            tilt_bin_deg: TILT_BIN_DEG,
            ..CheckReport::default()
        };
        let head_parts = || -> Result<Vec<String>, MachineError> {
            Ok(spec
                .head()?
                .parts
                .iter()
                .map(|p| p.name().to_string())
                .collect())
        };
        let mut skipped_parts = None;
        let checker = match Checker::new(spec) {
            Ok(_) if options.skip_collisions => {
                report.warnings.push(SKIPPED_COLLISIONS.to_string());
                skipped_parts = Some(head_parts()?);
                None
            }
            Ok(c) => {
                report.collisions_checked = true;
                report.head_parts = head_parts()?;
                Some(c)
            }
            Err(e @ MachineError::CollisionUnsupported { .. }) => {
                report.warnings.push(format!("collisions not checked: {e}"));
                None
            }
            Err(e) => return Err(e.into()),
        };
        Ok(CheckStream {
            reader: AxisReader::new(machine.as_ref()),
            speeds: AxisSpeeds::new(
                bounds.iter().map(|b| b.max_feed).collect(),
                bounds.iter().map(|b| b.rotary).collect(),
            ),
            reach: Reach::new(bounds),
            rule: flavour.length_rule(),
            machine,
            checker,
            options: options.clone(),
            report,
            feed: 0.0,
            inverse_time: false,
            arcs: Vec::new(),
            arc_count: 0,
            path: Vec::new(),
            letters: limits
                .iter()
                .map(|l| l.name.bytes().next().unwrap_or(b'?').to_ascii_uppercase())
                .collect(),
            limits,
            skipped_parts,
        })
    }

    /// Feed the next bytes of the G-code (any chunk size).
    pub fn push(&mut self, bytes: &[u8]) -> Result<(), CheckError> {
        let (reader, mut state) = self.parts();
        reader.push(bytes, |l| state.line(l))
    }

    /// The reader, and the rest of the state a line changes (borrowed apart).
    fn parts(&mut self) -> (&mut AxisReader, Parts<'_>) {
        (
            &mut self.reader,
            Parts {
                machine: self.machine.as_ref(),
                limits: &self.limits,
                checker: self.checker.as_mut(),
                reach: &mut self.reach,
                speeds: &mut self.speeds,
                rule: self.rule,
                options: &self.options,
                report: &mut self.report,
                feed: &mut self.feed,
                inverse_time: &mut self.inverse_time,
                arcs: &mut self.arcs,
                arc_count: &mut self.arc_count,
                path: &mut self.path,
                letters: &self.letters,
            },
        )
    }

    /// The tip path collected so far (drains it; only with `options.path`).
    pub fn take_path(&mut self) -> Vec<PathPoint> {
        std::mem::take(&mut self.path)
    }

    /// The findings counted so far (every line read is judged), for a progress display.
    pub fn counts(&self) -> FindingCounts {
        self.report.counts
    }

    /// [`CheckStream::finish`] of a check told to `skip_collisions` on a file whose collisions
    /// were found by the unwarp that wrote it (the same walker over the same lines,
    /// `crate::pipeline::CheckedUnwarper`; `found` in file order): the report then reads as a
    /// check that ran them ([`CheckReport::merge_collisions`]), without walking the file twice.
    /// A check that did not skip them (it found its own), or that cannot judge the machine,
    /// gives `finish`'s report.
    pub fn finish_with_collisions(
        mut self,
        found: &[CollisionFinding],
    ) -> Result<(CheckReport, Vec<PathPoint>), CheckError> {
        let parts = self.skipped_parts.take();
        let max = self.options.max_findings;
        let (mut r, path) = self.finish()?;
        if let Some(parts) = parts {
            r.merge_collisions(found, parts, max);
        }
        Ok((r, path))
    }

    /// The last line (without a newline) and the report.
    pub fn finish(mut self) -> Result<(CheckReport, Vec<PathPoint>), CheckError> {
        let (reader, mut state) = self.parts();
        reader.finish(|l| state.line(l))?;
        let mut r = self.report;
        r.lines = self.reader.lines();
        if r.moves == 0 {
            return Err(CheckError::NoMoves {
                machine: r.machine,
                axes: self.limits.iter().map(|l| l.name.clone()).collect(),
                lines: r.lines,
            });
        }
        if let Some(c) = self.checker.as_mut() {
            r.collision_samples = c.stats().samples;
            // already merged line by line; nothing left
            debug_assert!(c.findings().is_empty());
        }
        r.axes = self.reach.report();
        for (a, &n) in r.axes.iter_mut().zip(&self.speeds.limited_by) {
            a.speed_limited_moves = n;
        }
        r.print_time_min = self.speeds.minutes;
        r.slowdown_min = self.speeds.slowdown_minutes;
        if self.arc_count > 0 {
            r.warnings.push(format!(
                "{} arc move{} (G2/G3) not checked, at line{} {}{}: a multi-axis file should not hold arcs",
                self.arc_count,
                if self.arc_count == 1 { "" } else { "s" },
                if self.arcs.len() == 1 { "" } else { "s" },
                self.arcs
                    .iter()
                    .map(u64::to_string)
                    .collect::<Vec<_>>()
                    .join(", "),
                if self.arc_count > self.arcs.len() as u64 {
                    ", …"
                } else {
                    ""
                }
            ));
        }
        Ok((r, self.path))
    }
}

/// The parts of the state a line changes (borrowed apart from the reader).
struct Parts<'a> {
    machine: &'a dyn Machine,
    limits: &'a [AxisLimit],
    checker: Option<&'a mut Checker>,
    reach: &'a mut Reach,
    speeds: &'a mut AxisSpeeds,
    rule: LengthRule,
    options: &'a CheckOptions,
    report: &'a mut CheckReport,
    feed: &'a mut f64,
    inverse_time: &'a mut bool,
    arcs: &'a mut Vec<u64>,
    arc_count: &'a mut u64,
    path: &'a mut Vec<PathPoint>,
    letters: &'a [u8],
}

impl Parts<'_> {
    fn add(&mut self, f: Finding) {
        if self.report.findings.len() < self.options.max_findings {
            self.report.findings.push(f);
        }
    }

    fn line(&mut self, l: &ReadLine<'_>) -> Result<(), CheckError> {
        let Some(g) = l.g else { return Ok(()) };
        if let Some(b) = l.bad_word {
            let code = crate::gcode::lexer::split(l.bytes).code;
            let word = String::from_utf8_lossy(&code[b.start..b.end.min(code.len())]);
            return Err(CheckError::BadNumber {
                line: l.number,
                word: word.into_owned(),
            });
        }
        let moves = g == 0.0 || g == 1.0 || g == 92.0;
        for w in crate::gcode::lexer::Words::new(crate::gcode::lexer::split(l.bytes).code).flatten()
        {
            if w.letter == b'F' {
                if let Some(f) = w.value {
                    *self.feed = f;
                }
            }
            // a move's axis, E or F word without a number (`XNaN` reads as X alone) would
            // leave the value unchanged: the move cannot be read
            let named = w.letter == b'E' || w.letter == b'F' || self.letters.contains(&w.letter);
            if moves && named && w.value.is_none() {
                return Err(CheckError::BadNumber {
                    line: l.number,
                    word: String::from_utf8_lossy(crate::gcode::lexer::split(l.bytes).code)
                        .trim()
                        .to_string(),
                });
            }
        }
        if g == 93.0 {
            *self.inverse_time = true;
        } else if g == 94.0 {
            *self.inverse_time = false;
        } else if g == 2.0 || g == 3.0 {
            *self.arc_count += 1;
            if self.arcs.len() < ARC_WARNINGS_LISTED {
                self.arcs.push(l.number);
            }
        }
        let mode = if *self.inverse_time {
            FeedMode::InverseTime
        } else {
            FeedMode::Tip
        };
        if g != 0.0 && g != 1.0 {
            return Ok(());
        }
        self.report.total_e_mm += l.de;
        let Some(m) = &l.motion else {
            self.speeds.add_extruder_move(mode, l.de, *self.feed);
            return Ok(());
        };
        self.report.moves += 1;
        if *self.inverse_time {
            self.report.inverse_time_moves += 1;
        }
        // reach: every axis outside, with the end it passes
        let outside: Vec<usize> = self.reach.outside(&m.to).collect();
        for i in outside {
            let b = &self.reach.bounds()[i];
            let v = m.to[i];
            self.report.counts.reach += 1;
            let f = Finding {
                kind: FindingKind::Reach,
                line: l.number,
                layer: l.layer,
                axis: Some(b.name.clone()),
                value: Some(v),
                limit: Some(if v < b.min { b.min } else { b.max }),
                collision: None,
            };
            self.add(f);
        }
        self.reach.observe(&m.to);
        // collisions: the emitter's check, line by line
        let mut collisions: Vec<String> = Vec::new();
        if let Some(c) = self.checker.as_deref_mut() {
            walk_line(c, l)?;
            for cf in c.take_findings() {
                self.report.counts.collision += 1;
                if !collisions.contains(&cf.part) {
                    collisions.push(cf.part.clone());
                }
                self.add(Finding {
                    kind: FindingKind::Collision,
                    line: cf.line,
                    layer: cf.layer,
                    axis: None,
                    value: None,
                    limit: None,
                    collision: Some(cf),
                });
            }
        }
        // speeds and time (the first move's start is unknown: not timed)
        if !m.first {
            let d = self.rule.length(self.limits, &m.from, &m.to, l.de);
            if let Some(lim) = self.speeds.add_move(mode, &m.from, &m.to, *self.feed, d) {
                self.report.counts.speed += 1;
                let f = Finding {
                    kind: FindingKind::Speed,
                    line: l.number,
                    layer: l.layer,
                    axis: Some(self.limits[lim.axis].name.clone()),
                    value: Some(lim.speed),
                    limit: Some(lim.max_feed),
                    collision: None,
                };
                let worse = self.report.worst_speed.as_ref().is_none_or(|w| {
                    lim.speed / lim.max_feed
                        > w.value.unwrap_or(0.0) / w.limit.unwrap_or(f64::INFINITY)
                });
                if worse {
                    self.report.worst_speed = Some(f.clone());
                }
                self.add(f);
            }
        }
        // E, tilt, path
        let (p, n) = self.machine.forward(&m.to)?;
        if m.extrudes {
            self.report.extruding_moves += 1;
            self.report.extruded_mm += l.de;
            let tilt = crate::num::deg(crate::num::acos(n.z.clamp(-1.0, 1.0)));
            let bin = ((tilt / TILT_BIN_DEG) as usize).min(TILT_BINS - 1);
            self.report.tilt_histogram[bin] += 1;
            self.report.largest_tilt_deg = self.report.largest_tilt_deg.max(tilt);
        }
        if self.options.path {
            self.path.push(PathPoint {
                line: l.number,
                p,
                n,
                de: l.de,
                layer: l.layer,
                travel: !m.extrudes,
                axes: m.to.clone(),
                collisions,
            });
        }
        Ok(())
    }
}
