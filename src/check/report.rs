//! What `warpslice check` reports of a G-code: each finding with its file line, the counts,
//! the axes' ranges and margins, the speeds, the time, the filament and the tilt histogram.

use core::fmt;

use serde::{Deserialize, Serialize};

use crate::emit::{AxisReport, CollisionFinding};

/// Width of a bin of the tilt histogram, degrees.
pub const TILT_BIN_DEG: f64 = 5.0;
/// Bins of the tilt histogram: 0° to 180° (a tool axis pointing down is 180°).
pub const TILT_BINS: usize = 36;

/// What a finding is.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum FindingKind {
    /// An axis outside its travel or rotary range.
    Reach,
    /// A head part into the printed material or the bed.
    Collision,
    /// An axis faster than its largest feed at the written F (the firmware slows the move).
    Speed,
}

impl FindingKind {
    /// `reach`, `collision`, `speed`.
    pub fn name(self) -> &'static str {
        match self {
            FindingKind::Reach => "reach",
            FindingKind::Collision => "collision",
            FindingKind::Speed => "speed",
        }
    }
}

/// One finding, at one line of the file.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Finding {
    /// What it is.
    pub kind: FindingKind,
    /// 1-based line of the file, as an editor shows it.
    pub line: u64,
    /// Layer (count of the slicer's layer-change comments before the line; 0 without).
    pub layer: u32,
    /// The axis (reach, speed).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub axis: Option<String>,
    /// Reach: the axis value (mm or °); speed: the axis speed at the written F (mm/min, °/min).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// Reach: the end of the travel it passes; speed: the axis' largest feed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub limit: Option<f64>,
    /// Collision: the head part, the obstacle, depth and where.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub collision: Option<CollisionFinding>,
}

impl fmt::Display for Finding {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let axis = self.axis.as_deref().unwrap_or("?");
        let v = self.value.unwrap_or(f64::NAN);
        let lim = self.limit.unwrap_or(f64::NAN);
        match (&self.kind, &self.collision) {
            (FindingKind::Reach, _) => write!(
                f,
                "line {}: reach: axis {axis} = {v:.3} is beyond its limit {lim}",
                self.line
            ),
            (FindingKind::Speed, _) => write!(
                f,
                "line {}: speed: axis {axis} would move at {v:.0}/min, over its largest feed {lim:.0}/min (the firmware slows the move)",
                self.line
            ),
            (FindingKind::Collision, Some(c)) => write!(
                f,
                "line {}: collision: the {} goes {:.3} mm into the {} at ({:.3}, {:.3}, {:.3}) (no input line: a machine G-code checked alone has no slicer's line to name)",
                self.line,
                c.part,
                c.depth_mm,
                if c.obstacle == "bed" { "bed" } else { "printed material" },
                c.at[0],
                c.at[1],
                c.at[2]
            ),
            (FindingKind::Collision, None) => write!(f, "line {}: collision", self.line),
        }
    }
}

/// Findings per kind.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
pub struct FindingCounts {
    /// Axis values outside their travel (one per axis and line).
    pub reach: u64,
    /// Head part / obstacle pairs per move.
    pub collision: u64,
    /// Moves an axis' largest feed slows.
    pub speed: u64,
}

impl FindingCounts {
    /// All findings.
    pub fn total(&self) -> u64 {
        self.reach + self.collision + self.speed
    }
}

/// The check of one G-code.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CheckReport {
    /// Machine name.
    pub machine: String,
    /// The flavour whose length rule timed the moves.
    pub flavour: String,
    /// Lines read.
    pub lines: u64,
    /// `G0`/`G1` lines that move a machine axis.
    pub moves: u64,
    /// Of those, the ones that extrude.
    pub extruding_moves: u64,
    /// Lines in inverse-time feed (`G93`).
    pub inverse_time_moves: u64,
    /// Findings per kind.
    pub counts: FindingCounts,
    /// The first findings (up to `max_findings`), in file order.
    pub findings: Vec<Finding>,
    /// Whether the collision check ran (not for a machine it cannot judge, see `warnings`).
    pub collisions_checked: bool,
    /// The head parts checked (names from the machine's `head`).
    pub head_parts: Vec<String>,
    /// Poses sampled by the collision check.
    pub collision_samples: u64,
    /// Every axis: travel, range in the file, margins (negative: outside), largest feed,
    /// moves it slowed.
    pub axes: Vec<AxisReport>,
    /// The fastest axis over its largest feed (the speed finding of largest ratio).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub worst_speed: Option<Finding>,
    /// Estimated time of the file's moves, minutes, at its feeds with the firmware's
    /// slow-down (no acceleration; the emitter's estimate, `crate::machine::speed`).
    pub print_time_min: f64,
    /// The part of `print_time_min` that the axis feed limits add, minutes.
    pub slowdown_min: f64,
    /// Net filament of the file (sum of E changes of `G0`/`G1`, retractions included), mm.
    pub total_e_mm: f64,
    /// Filament of the extruding moves (positive E changes with motion), mm.
    pub extruded_mm: f64,
    /// Extruding moves per bin of tool-axis tilt from +Z of the part frame (bin i:
    /// `[i·TILT_BIN_DEG, (i+1)·TILT_BIN_DEG)`, [`TILT_BINS`] bins, 180° in the last).
    pub tilt_histogram: Vec<u64>,
    /// Width of a histogram bin, degrees.
    pub tilt_bin_deg: f64,
    /// Largest tilt of an extruding move, degrees.
    pub largest_tilt_deg: f64,
    /// What the check could not judge (an arc, a machine the collision check cannot hold).
    pub warnings: Vec<String>,
}

impl CheckReport {
    /// Nothing that stops the file from running safely: no reach and no collision finding.
    /// Speed findings are reported, not failed (issue 10 §2: the firmware slows such a move down,
    /// and the time estimate includes it), so they leave the exit code at 0.
    pub fn is_clean(&self) -> bool {
        self.counts.reach == 0 && self.counts.collision == 0
    }

    /// The collision findings `found` (file order) of a walk this check left out
    /// (`skip_collisions`) over the same file, with the `head_parts` it checked: counted, and
    /// listed where the check's own walk lists them — in line order, on one line after its
    /// reach findings and before its speed finding — up to `max_findings` in all; the skip's
    /// warning goes. `collision_samples` stays 0 (the walk's count is not known here).
    pub fn merge_collisions(
        &mut self,
        found: &[CollisionFinding],
        head_parts: Vec<String>,
        max_findings: usize,
    ) {
        let rank = |k: FindingKind| match k {
            FindingKind::Reach => 0,
            FindingKind::Collision => 1,
            FindingKind::Speed => 2,
        };
        self.collisions_checked = true;
        self.head_parts = head_parts;
        self.counts.collision = found.len() as u64;
        self.warnings
            .retain(|w| w != super::stream::SKIPPED_COLLISIONS);
        self.findings
            .extend(found.iter().take(max_findings).map(|c| Finding {
                kind: FindingKind::Collision,
                line: c.line,
                layer: c.layer,
                axis: None,
                value: None,
                limit: None,
                collision: Some(c.clone()),
            }));
        // stable: the collisions of one line keep the walk's order
        self.findings.sort_by_key(|f| (f.line, rank(f.kind)));
        self.findings.truncate(max_findings);
    }

    /// One line: counts, time, filament, tilt.
    pub fn summary(&self) -> String {
        let c = &self.counts;
        format!(
            "{} finding{} ({} reach, {} collision, {} speed) in {} lines, {} moves ({} extruding); collisions {}; estimated time {:.1} min ({:.1} min slow-down); E {:.3} mm net, {:.3} mm extruded; largest tilt {:.2}°",
            c.total(),
            if c.total() == 1 { "" } else { "s" },
            c.reach,
            c.collision,
            c.speed,
            self.lines,
            self.moves,
            self.extruding_moves,
            if self.collisions_checked {
                format!("checked with {}", self.head_parts.join(", "))
            } else {
                "not checked".to_string()
            },
            self.print_time_min,
            self.slowdown_min,
            self.total_e_mm,
            self.extruded_mm,
            self.largest_tilt_deg
        )
    }
}
