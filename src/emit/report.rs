//! What a machine emitter reports, and how it writes F.
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
}
