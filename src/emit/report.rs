//! What a machine emitter reports (with each axis' reach and speed, [`AxisReport`]), and how
//! it writes F.
//!
//! The feed modes are explained with their formulas in [`crate::machine::feed`].

use serde::{Deserialize, Serialize};

/// How the output F is computed.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
#[non_exhaustive]
pub enum FeedMode {
    /// F from the flavour's own move-length rule D: F = f·D/L, so the move takes tip length /
    /// tip feed on that firmware (the default).
    #[default]
    Tip,
    /// F = tip feed (right only where the firmware's length is the tip's).
    Xyz,
    /// F scaled so the move takes tip_length / f with rotary degrees counted in the length.
    AllAxes,
    /// G93 inverse time: F = 1 / minutes.
    InverseTime,
}

impl FeedMode {
    /// Parse `tip`, `xyz`, `all-axes`, `inverse-time`.
    pub fn parse(s: &str) -> Option<FeedMode> {
        match s {
            "tip" => Some(FeedMode::Tip),
            "xyz" => Some(FeedMode::Xyz),
            "all-axes" => Some(FeedMode::AllAxes),
            "inverse-time" => Some(FeedMode::InverseTime),
            _ => None,
        }
    }

    /// The CLI name (`tip`, `xyz`, `all-axes`, `inverse-time`).
    pub fn name(self) -> &'static str {
        match self {
            FeedMode::Tip => "tip",
            FeedMode::Xyz => "xyz",
            FeedMode::AllAxes => "all-axes",
            FeedMode::InverseTime => "inverse-time",
        }
    }
}

/// What the machine emitter measured over the file.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct MachineReport {
    /// Preset / machine name.
    pub machine: String,
    /// Firmware flavour.
    pub flavour: String,
    /// Feed mode.
    pub feed: FeedMode,
    /// Toolpath moves received from the unwarp.
    pub moves_in: u64,
    /// Moves written to the G-code (after splitting, rotate-arounds included).
    pub moves_out: u64,
    /// Worst tip deviation of the firmware's interpolation from the intended path, mm.
    pub worst_position_mm: f64,
    /// Worst tool-axis deviation of the interpolation, degrees.
    pub worst_angle_deg: f64,
    /// Largest angle between a requested tool axis and the realised one, degrees.
    pub worst_dropped_deg: f64,
    /// Moves whose realised tool axis is more than
    /// [`crate::tolerance::DROPPED_TILT_WARN_DEG`] from the requested one (warned about).
    #[serde(default)]
    pub dropped_moves: u64,
    /// Moves where splitting hit the depth limit (a discontinuity; error still measured).
    pub depth_limited: u64,
    /// Single-revolution rotate-arounds.
    pub rotate_arounds: u64,
    /// Pose discontinuities crossed in place (rotary axes stepped with the tip held).
    pub reposes: u64,
    /// Filament of the pieces turned around in the air by a rotate-around, mm (given to the
    /// next extruding piece, not lost).
    pub e_skipped_mm: f64,
    /// `G92` modulo-360° resets of unlimited rotary axes.
    pub rotary_resets: u64,
    /// Swing lifts: places near a cone's apex or a kinematic pole where a rotary axis would
    /// swing while the tip barely moves, extruding (`crate::machine::emit::SWING_RATE_DEG_PER_MM`);
    /// the head was lifted, turned in the air and set down instead.
    #[serde(default)]
    pub swing_lifts: u64,
    /// Tip path lifted over by the swing lifts, mm (its filament went to the next piece).
    #[serde(default)]
    pub swing_skipped_mm: f64,
    /// Every swing lift, in file order.
    #[serde(default)]
    pub swings: Vec<SwingPlace>,
    /// The collision check ran (`check_collisions`; see `crate::collision`).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub collisions_checked: bool,
    /// Every collision found (with `allow_collisions`; otherwise the first stops the unwarp).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub collisions: Vec<CollisionFinding>,
    /// Every axis: its travel, the range written and the margins, its largest feed and the
    /// moves it slowed (machine order).
    pub axes: Vec<AxisReport>,
    /// Written moves on which some axis would exceed its largest feed at the written F: the
    /// firmware slows the whole move so the fastest axis is at its limit (not an error).
    pub speed_limited_moves: u64,
    /// Estimated time of the moves written in the printed region, minutes, at the written
    /// feeds with the firmware's slow-down for axis feed limits (no acceleration).
    pub print_time_min: f64,
    /// The part of `print_time_min` that the axis feed limits add, minutes.
    pub slowdown_min: f64,
}

/// One swing lift of a machine file (see [`MachineReport::swing_lifts`]).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct SwingPlace {
    /// The output line (1-based) of the lift.
    pub output_line: u64,
    /// The slicer's input line (1-based) of the move it is in (0: none).
    pub input_line: u64,
    /// The slicer's layer index (0-based).
    pub layer: u32,
    /// The largest turn of one rotary axis in the air, degrees.
    pub turn_deg: f64,
    /// The tip path lifted over, mm.
    pub tip_mm: f64,
}

/// One axis over a machine file: travel, range written, margins, feed limit.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisReport {
    /// The output letter.
    pub axis: String,
    /// Rotary (degrees) rather than linear (mm).
    pub rotary: bool,
    /// Lower end of the travel, mm or degrees (`None`: unlimited).
    pub min: Option<f64>,
    /// Upper end of the travel (`None`: unlimited).
    pub max: Option<f64>,
    /// Lowest raw value written (`None`: no move written).
    pub lowest: Option<f64>,
    /// Highest raw value written.
    pub highest: Option<f64>,
    /// Reach margin to the lower end, `lowest − min` (`None`: unlimited or nothing written).
    pub margin_min: Option<f64>,
    /// Reach margin to the upper end, `max − highest`.
    pub margin_max: Option<f64>,
    /// Largest feed, mm/min or °/min (`None`: no limit).
    pub max_feed: Option<f64>,
    /// Moves on which this axis was the one that limited the speed.
    pub speed_limited_moves: u64,
}

/// One collision of a head part with the printed material or the bed (`crate::collision`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct CollisionFinding {
    /// 1-based line of the output G-code whose move collides.
    pub line: u64,
    /// Layer of the move (1-based count of the slicer's layer-change comments; 0 before).
    pub layer: u32,
    /// The head part (`nozzle`, `heater-block`, … as named in the machine's `head`).
    pub part: String,
    /// What it hits: `material` (printed so far) or `bed`.
    pub obstacle: String,
    /// Penetration depth: the largest overlap along Z of the part with the material column or
    /// the bed at one cell, over the move's sampled poses, mm.
    pub depth_mm: f64,
    /// Where (output frame x, y of that cell, z where the part enters it), mm.
    pub at: [f64; 3],
    /// 1-based line of the slicer's G-code (the unwarp's input) the move came from; `None`
    /// when the machine G-code was checked alone (`warpslice check`: no input file).
    #[serde(default)]
    pub input_line: Option<u64>,
}
