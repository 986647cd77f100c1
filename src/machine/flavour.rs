//! Firmware flavours of the machine G-code: which firmware reads the file, what header it
//! gets, and where it is refused.
//!
//! - [`Flavour::RepRapFirmware`]: every axis letter is a G-code word; the header lists the
//!   `M584` axis mapping the file expects (rotary axes created with `R1`, and `S1` or `S0` as
//!   the feed mode needs: RepRapFirmware 3.2 and later).
//! - [`Flavour::Marlin`] (2.1): axes beyond X Y Z are `AXIS4_NAME`, `AXIS5_NAME`, … in
//!   `Configuration.h`, named from A B C U V W; the header says which letter is which.
//! - [`Flavour::Klipper`]: Klipper has no kinematics for rotary or independently addressed
//!   extra axes (a tilting head, a rotating nozzle or table, three independent Z motors, a polar
//!   printer with a tilt): only the 3-axis `cartesian` machine is accepted; every other machine
//!   is refused with that reason ([`MachineError::UnsupportedFlavour`]).

use serde::{Deserialize, Serialize};

use super::length_rule::LengthRule;
use super::{AxisLimit, FeedMode, MachineError};

/// The firmware the output is for.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
#[non_exhaustive]
pub enum Flavour {
    /// RepRapFirmware 3 (Duet).
    #[default]
    RepRapFirmware,
    /// Marlin 2.1 with extra axes.
    Marlin,
    /// Klipper (3-axis only).
    Klipper,
}

/// Letters Marlin 2.1 accepts for `AXIS4_NAME` … `AXIS9_NAME`.
pub const MARLIN_EXTRA_LETTERS: &[&str] = &["A", "B", "C", "U", "V", "W"];

impl Flavour {
    /// Parse `reprapfirmware` (or `rrf`), `marlin`, `klipper`.
    pub fn parse(s: &str) -> Option<Flavour> {
        match s.to_ascii_lowercase().as_str() {
            "reprapfirmware" | "rrf" => Some(Flavour::RepRapFirmware),
            "marlin" => Some(Flavour::Marlin),
            "klipper" => Some(Flavour::Klipper),
            _ => None,
        }
    }

    /// The name written to the header.
    pub fn name(self) -> &'static str {
        match self {
            Flavour::RepRapFirmware => "reprapfirmware",
            Flavour::Marlin => "marlin",
            Flavour::Klipper => "klipper",
        }
    }

    /// How this firmware measures a move's length (see [`LengthRule`]): RepRapFirmware (rotary
    /// axes `S1`) and Marlin (`AXISn_ROTATES`) the NIST rule, Klipper its X Y Z rule.
    pub fn length_rule(self) -> LengthRule {
        match self {
            Flavour::RepRapFirmware | Flavour::Marlin => LengthRule::Nist,
            Flavour::Klipper => LengthRule::KlipperXyz,
        }
    }

    /// Check that this firmware can drive `limits` (the machine's axes) with `feed`; the error
    /// says why not.
    ///
    /// `G93` (inverse-time feed) exists only in RepRapFirmware (3.5.0 and later): Klipper's
    /// G-code reference lists no G93, and mainline Marlin 2.1 has none (its feature request is
    /// still open), so both read F as mm/min and the move would crawl or race.
    pub fn check(
        self,
        machine: &str,
        limits: &[AxisLimit],
        feed: FeedMode,
    ) -> Result<(), MachineError> {
        let refuse = |reason: String| MachineError::UnsupportedFlavour {
            machine: machine.to_string(),
            flavour: self.name().to_string(),
            reason,
        };
        if feed == FeedMode::InverseTime && self != Flavour::RepRapFirmware {
            return Err(refuse(format!(
                "{} has no G93 (inverse-time feed): use --feed tip (exact speeds without G93), or --flavour reprapfirmware (3.5.0 or later)",
                match self {
                    Flavour::Marlin => "Marlin 2.1",
                    _ => "Klipper",
                }
            )));
        }
        let names: Vec<&str> = limits.iter().map(|l| l.name.as_str()).collect();
        match self {
            Flavour::RepRapFirmware => Ok(()),
            Flavour::Marlin => {
                let extra: Vec<&str> = names
                    .iter()
                    .copied()
                    .filter(|n| !["X", "Y", "Z"].contains(n))
                    .collect();
                if let Some(bad) = extra.iter().find(|n| !MARLIN_EXTRA_LETTERS.contains(n)) {
                    return Err(refuse(format!(
                        "Marlin 2.1 names extra axes only {}; axis '{bad}' cannot be given (rename it with axis_names)",
                        MARLIN_EXTRA_LETTERS.join(" ")
                    )));
                }
                if extra.len() > 6 {
                    return Err(refuse("Marlin 2.1 drives at most 9 axes".into()));
                }
                Ok(())
            }
            Flavour::Klipper => {
                if names == ["X", "Y", "Z"] && limits.iter().all(|l| !l.rotary) {
                    Ok(())
                } else {
                    Err(refuse(format!(
                        "Klipper has no rotary-axis (or independent extra-axis) kinematics for this machine's axes {}; use reprapfirmware or marlin",
                        names.join(" ")
                    )))
                }
            }
        }
    }

    /// Header comment lines (without the leading `; warpslice machine = …` line).
    ///
    /// RepRapFirmware (3.2 and later): `M584 … R1` creates rotary axes, `R0` linear ones, and
    /// `S1` keeps a rotary axis out of the feed-rate length (NIST RS274 §2.1.2.5; RRF's default
    /// for `R1`) while `S0` counts its degrees like millimetres: `S1` for `--feed xyz` and
    /// `inverse-time`, `S0` for `--feed all-axes` (see [`FeedMode`]).
    pub fn header(self, limits: &[AxisLimit], feed: FeedMode) -> Vec<String> {
        let extra: Vec<&AxisLimit> = limits
            .iter()
            .filter(|l| !["X", "Y", "Z"].contains(&l.name.as_str()))
            .collect();
        let mut lines = Vec::new();
        match self {
            Flavour::RepRapFirmware => {
                lines.push("; flavour RepRapFirmware 3: this file expects the axis mapping".into());
                let mut m = String::from(";   M584");
                for (i, l) in limits.iter().enumerate() {
                    m.push_str(&format!(" {}<driver{i}>", l.name));
                }
                lines.push(m);
                for l in &extra {
                    lines.push(format!(
                        ";   axis {} is {} (create it with M584 … {}{})",
                        l.name,
                        if l.rotary {
                            "rotary, degrees"
                        } else {
                            "linear, mm"
                        },
                        l.name,
                        match (l.rotary, feed) {
                            (false, _) => " R0",
                            (true, FeedMode::AllAxes) => " R1 S0",
                            (true, _) => " R1 S1",
                        }
                    ));
                }
            }
            Flavour::Marlin => {
                lines.push("; flavour Marlin 2.1: extra axes are set in Configuration.h as".into());
                for (i, l) in extra.iter().enumerate() {
                    lines.push(format!(
                        ";   #define AXIS{}_NAME '{}'   // {}",
                        i + 4,
                        l.name,
                        if l.rotary {
                            "rotary (AXIS*_ROTATES), degrees"
                        } else {
                            "linear, mm"
                        }
                    ));
                }
            }
            Flavour::Klipper => lines.push("; flavour Klipper (3-axis)".into()),
        }
        for l in limits {
            if l.min.is_finite() || l.max.is_finite() {
                lines.push(format!(
                    ";   axis {} travel [{}, {}] {}",
                    l.name,
                    l.min,
                    l.max,
                    if l.rotary { "deg" } else { "mm" }
                ));
            }
        }
        lines
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// RepRapFirmware counts an axis created with `S0` in the feed length: right for
    /// `--feed all-axes`, wrong for `xyz`, whose F is the tip speed alone.
    #[test]
    fn reprapfirmware_header_creates_rotary_axes_for_the_feed_mode() {
        let limits = [
            AxisLimit::linear("X"),
            AxisLimit::linear("U"),
            AxisLimit::rotary("A", -90.0, 90.0),
        ];
        let xyz = Flavour::RepRapFirmware
            .header(&limits, FeedMode::Xyz)
            .join("\n");
        assert!(
            xyz.contains("M584 … A R1 S1") && xyz.contains("M584 … U R0"),
            "{xyz}"
        );
        let all = Flavour::RepRapFirmware
            .header(&limits, FeedMode::AllAxes)
            .join("\n");
        assert!(all.contains("M584 … A R1 S0"), "{all}");
        let marlin = Flavour::Marlin.header(&limits, FeedMode::Xyz).join("\n");
        assert!(
            marlin.contains("#define AXIS4_NAME 'U'") && marlin.contains("AXIS5_NAME 'A'"),
            "{marlin}"
        );
    }
}
