//! The motion lines outside the printed region on a machine output: the start and end G-code,
//! a prime or purge line, the slicer's travels before the first and after the last object
//! point. They are in the slicer's frame, so a machine that converts them
//! ([`Emitter::converts_outside`]: every machine but the 3-axis one with the letters X Y Z and
//! an output not moved by `--place` / `--z-offset`) gets each of them converted, or the unwarp
//! refuses the line by name — none is written in the slicer's frame.
//!
//! ## The rule
//! - **Rest pose.** Outside the region the tool holds the machine's rest pose: tool axis +Z,
//!   realised next to the previous pose (a machine that cannot point its nozzle vertically,
//!   the rotating tilted nozzle, holds its rotation; the A/B table's B at A = 0 and the polar
//!   bed's C follow the position as their kinematics do).
//! - **Absolute moves** (`G0`/`G1` with X, Y or Z): the end point g is placed like the flat
//!   skirt, `p = (g_x + s_x, g_y + s_y, max(g_z + z_offset, 0))` with `s = place − (dx, dy)`
//!   (zero without `--place`), and handed to the emitter as a point with tool axis +Z: the
//!   machine's inverse kinematics, interpolation splitting, feed and the same reach check as
//!   the region's points (a violation is `machine.travel`, wrapped as [`UnwarpError::Outside`]
//!   with the line and what to change). E passes as the file has it (the emitter's E writer
//!   is set to the slicer's E before the line); `G0`/`G1` with only E or F pass verbatim.
//! - **After the region** the head left it lifted, back at the rest pose (the unwarp's lift,
//!   then [`Emitter::end_region`]). A coordinate the end G-code has not given yet stays where
//!   the head is (the slicer's `G1 Z<top + 1>` lifts straight up from where the unwarped part
//!   ended, not from the slicer's last point, which a warp moved). Each travel of the end G-code is planned with the region's
//!   travel planner (straight, or up, across and down clear of everything printed), and a
//!   target inside the printed material's shadow lower than its top + the travel clearance is
//!   raised to that height (the slicer's `G1 Z<top + 1>` meant "above the part", and the
//!   unwarped part can be taller than the slicer's): commented `; warpslice: raised …`.
//! - **Homing** (`G28`, also `G27`, `G29`, `G30` and tool changes) passes verbatim; the head
//!   is then where the firmware put it: X, Y and Z are unknown until moves give them again. A
//!   move that gives only some (`G1 Z5` after `G28`) is written with the axes that depend on
//!   the given coordinates alone ([`Emitter::outside_partial`]; on the polar machine `Z`);
//!   when an axis it would move also depends on an unknown coordinate (the lathe's `Z` is the
//!   radius, y and z) it is not written but kept as a comment, and the next move that gives
//!   X, Y and Z goes there in one move, as the slicer's file does from home. An extruding
//!   such move is refused.
//! - **Relative moves** (`G91` with X, Y or Z, as Cura's end G-code lifts and wipes): from a
//!   known position, the target is where the head is plus the slicer's delta (the placement
//!   is a translation; never below the bed), then as an absolute move. Where the position is
//!   not known (after homing) such a move is refused.
//! - **Refused by name** ([`OutsideReason`]): relative moves from an unknown position, arcs
//!   (`G2`/`G3`), `G92` with X, Y or Z and inches (`G20`) outside the region: the machine
//!   cannot carry them out exactly in its own axes.
//!
//! The region is entered from the rest pose by the region's own travel planner (from the last
//! converted position; from an unknown pose the first move goes straight to its target, as
//! the slicer's does).

use glam::DVec3;

use super::core::{Core, Kind};
use super::{travel, OutsideReason, UnwarpError};
use crate::emit::EmitError;
use crate::gcode::lexer::{split, Words};
use crate::gcode::{Command, Line, Move, State};
use crate::toolpath::{Feature, ToolPoint};

/// Which of X, Y, Z the code part of `raw` names.
fn axis_words(raw: &[u8]) -> [bool; 3] {
    let mut seen = [false; 3];
    for w in Words::new(split(raw).code).flatten() {
        match w.letter {
            b'X' => seen[0] = true,
            b'Y' => seen[1] = true,
            b'Z' => seen[2] = true,
            _ => {}
        }
    }
    seen
}

fn command_text(line: &Line<'_>) -> String {
    String::from_utf8_lossy(line.raw).trim().to_string()
}

impl Core {
    /// A line outside the printed region, on an output that converts them (see the module
    /// documentation).
    pub(super) fn outside_line(
        &mut self,
        line: &Line<'_>,
        state: &State,
    ) -> Result<(), UnwarpError> {
        let refuse = |reason| UnwarpError::OutsideMotion {
            line: line.number,
            command: command_text(line),
            reason,
        };
        match line.command {
            Command::Move { arc, .. } => {
                let words = axis_words(line.raw);
                if !words.iter().any(|&w| w) {
                    // filament or feed only: as written
                    self.passthrough(line.raw);
                    self.emit.forget_feed();
                    self.emit.reset_e(self.slicer_e);
                    return Ok(());
                }
                if arc {
                    return Err(refuse(OutsideReason::Arc));
                }
                let relative_xyz = state.positioning_relative;
                if relative_xyz && (self.known != [true; 3] || self.outside_pose.is_none()) {
                    return Err(refuse(OutsideReason::Relative));
                }
                for (k, w) in self.known.iter_mut().zip(words) {
                    *k |= w;
                }
                for (k, w) in self.keep.iter_mut().zip(words) {
                    *k &= !w;
                }
                let keep = self.keep;
                let e_line: f64 = line.moves.iter().map(|m| m.e).sum();
                // the firmware's E before this line is the slicer's
                self.emit.reset_e(self.slicer_e - e_line);
                for m in line.moves {
                    if relative_xyz {
                        // from where the head is (in the output frame: the slicer's delta,
                        // the placement being a translation), never below the bed
                        let at = self.outside_pose.unwrap_or_default();
                        let mut to = at + (m.to - m.from);
                        to.z = to.z.max(0.0);
                        self.outside_move(line, m, Some(to), keep, state.e_relative)?;
                    } else if self.known == [true; 3] {
                        self.outside_move(line, m, None, keep, state.e_relative)?;
                    } else {
                        self.outside_partial(line, m, state.e_relative)?;
                    }
                }
            }
            Command::HeadMove(_) => {
                self.passthrough(line.raw);
                self.known = [false; 3];
                self.keep = [false; 3];
                self.outside_pose = None;
                self.emit.outside_pose_lost();
            }
            Command::SetPosition { xyz: true, .. } => return Err(refuse(OutsideReason::AxisReset)),
            Command::SetPosition { e: Some(v), .. } => {
                self.passthrough(line.raw);
                self.emit.reset_e(v);
            }
            Command::Units { inch: true } => return Err(refuse(OutsideReason::Inches)),
            _ => self.passthrough(line.raw),
        }
        Ok(())
    }

    /// An emitter error on an outside line, naming the line.
    fn outside_error(&self, line: &Line<'_>, error: EmitError) -> UnwarpError {
        UnwarpError::Outside {
            line: line.number,
            command: command_text(line),
            error,
        }
    }

    /// Hand one rest-pose point of an outside line to the emitter.
    fn outside_point(
        &mut self,
        line: &Line<'_>,
        p: DVec3,
        e: f64,
        m: &Move,
        travel: bool,
        relative: bool,
    ) -> Result<(), UnwarpError> {
        let tp = ToolPoint {
            p,
            n: DVec3::Z,
            e,
            f: m.f,
            layer: m.layer,
            feature: Feature::Unknown,
            travel,
            line: line.number,
        };
        let r = self.counted(|c| c.emit.point(&mut c.out, &tp, relative));
        r.map_err(|error| self.outside_error(line, error))?;
        if !travel || e == 0.0 {
            self.outside_pose = Some(p);
        }
        Ok(())
    }

    /// A piece whose X, Y and Z are all known: placed, planned and converted. `keep`: the
    /// coordinates the file has not given since the region ended stay where the head is.
    /// `moved_to`: the output-frame target of a relative (`G91`) piece, computed from where the
    /// head is.
    fn outside_move(
        &mut self,
        line: &Line<'_>,
        m: &Move,
        moved_to: Option<DVec3>,
        keep: [bool; 3],
        relative: bool,
    ) -> Result<(), UnwarpError> {
        let mut target = match moved_to {
            Some(t) => t,
            None => {
                let (mut t, _) = self.map_point(Kind::Flat, m.to);
                if let Some(at) = self.outside_pose {
                    for k in (0..3).filter(|&k| keep[k]) {
                        t[k] = at[k];
                    }
                }
                t
            }
        };
        let clearance = self.opts.travel_clearance;
        if self.done_region {
            let (_, top) = self.grid.clearance_needed(target, target);
            if top.is_finite() && target.z < top + clearance {
                target.z = top + clearance;
                let note = format!(
                    "; warpslice: the next move raised to Z{:.3}, {} mm above the print below it",
                    target.z, clearance
                );
                self.passthrough(note.as_bytes());
            }
        }
        if m.e > 0.0 {
            return self.outside_point(line, target, m.e, m, false, relative);
        }
        if m.e < 0.0 {
            // a wipe: retract in place first
            let at = self.outside_pose.unwrap_or(target);
            self.outside_point(line, at, m.e, m, true, relative)?;
        }
        if let Some(a) = self.outside_pose {
            // outside the region the tool axis is vertical (the rest pose)
            let head = self.head.as_ref().map(|profile| travel::HeadClearance {
                profile,
                tilt: 0.0,
                turn: 0.0,
            });
            if let travel::TravelPlan::Lift(z) =
                travel::plan(&self.grid, a, target, clearance, head)
            {
                self.outside_point(line, DVec3::new(a.x, a.y, z), 0.0, m, true, relative)?;
                let over = DVec3::new(target.x, target.y, z);
                self.outside_point(line, over, 0.0, m, true, relative)?;
            }
        }
        self.outside_point(line, target, 0.0, m, true, relative)
    }

    /// A piece after homing that gives only some of X, Y, Z.
    fn outside_partial(
        &mut self,
        line: &Line<'_>,
        m: &Move,
        relative: bool,
    ) -> Result<(), UnwarpError> {
        let (p, _) = self.map_point(Kind::Flat, m.to);
        let known = [0, 1, 2].map(|k| self.known[k].then_some(p[k]));
        let e = (m.e != 0.0).then_some((m.e, relative));
        let r = self.counted(|c| c.emit.outside_partial(&mut c.out, known, e, m.f));
        match r {
            Ok(true) => Ok(()),
            Ok(false) if m.e == 0.0 => {
                let note = format!(
                    "; warpslice: not written ({}): the machine's axes it moves depend on coordinates homing left unknown; the next move that gives X, Y and Z goes there",
                    command_text(line)
                );
                self.passthrough(note.as_bytes());
                Ok(())
            }
            Ok(false) => Err(UnwarpError::OutsideMotion {
                line: line.number,
                command: command_text(line),
                reason: OutsideReason::PartialExtrusion,
            }),
            Err(error) => Err(self.outside_error(line, error)),
        }
    }
}
