//! Firmware flavours of the machine G-code: which firmware reads the file, what header it
//! gets, and where it is refused. Each header is a block of comment lines `;   …` a user can
//! paste (without the leading `;   `) into the firmware's configuration; the minimum firmware
//! version of each feature warpslice uses is named next to it.
//!
//! - [`Flavour::RepRapFirmware`] (3.3 or later): every axis letter is a G-code word; the header
//!   gives the `M584` axis mapping with the extruder drive (`E`: RRF 3.3 and later require the
//!   extruders in `M584`), rotary axes `R1` with `S1` (NIST length rule) or `S0` (`--feed
//!   all-axes`), linear extra axes `R0`; `M208` minimum (`S1`) and maximum (`S0`) lines for
//!   every axis limit the machine has (RRF defaults every axis to 0…200 and, with `M564 S1`,
//!   its default, clamps a homed axis there: a rotary axis going negative would be clipped);
//!   `M564` advice; inverse time (`G93`) only from RepRapFirmware 3.5.0.
//! - [`Flavour::Marlin`] (2.1): axes beyond X Y Z are `AXIS4_NAME`, `AXIS5_NAME`, … in
//!   `Configuration.h`, named from A B C U V W; the header says which letter is which.
//! - [`Flavour::Klipper`]: extra axes are `[manual_stepper]` sections registered as G-code
//!   axes with `MANUAL_STEPPER STEPPER=… GCODE_AXIS=<letter>` (Klipper mainline since 2025-05);
//!   the header lists both and the `INSTANTANEOUS_CORNER_VELOCITY` advice (an extra axis'
//!   junction speed defaults to 1 mm/s). Klipper's `G92` sets X Y Z E only, so no `G92` is
//!   written on an extra axis (unlimited rotary axes stay unwrapped), and it has no `G93`.
//!   Letters E and F (extruder, feed) cannot name an extra axis
//!   ([`MachineError::UnsupportedFlavour`]).

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
                if let Some(bad) = names
                    .iter()
                    .find(|n| n.len() != 1 || !n.chars().all(|c| c.is_ascii_alphabetic()))
                {
                    return Err(refuse(format!(
                        "Klipper's GCODE_AXIS takes one letter A-Z; axis '{bad}' cannot be given (rename it with axis_names)"
                    )));
                }
                if let Some(bad) = names
                    .iter()
                    .find(|n| ["E", "F", "N"].contains(&n.to_ascii_uppercase().as_str()))
                {
                    // Klipper's manual_stepper.py refuses GCODE_AXIS letters in "XYZEFN"
                    return Err(refuse(format!(
                        "in Klipper's G1 the letter '{bad}' is the {}, not an axis: GCODE_AXIS refuses E, F and N (rename it with axis_names)",
                        match bad.to_ascii_uppercase().as_str() {
                            "E" => "extruder",
                            "F" => "feed rate",
                            _ => "line number",
                        }
                    )));
                }
                Ok(())
            }
        }
    }

    /// Whether this firmware's `G92` can set an extra axis (the modulo-360° resets of unlimited
    /// rotary axes): not Klipper's, which sets X Y Z E only.
    pub fn resets_extra_axes(self) -> bool {
        self != Flavour::Klipper
    }

    /// Header comment lines (without the leading `; warpslice machine = …` line) for axes
    /// `limits` with no feed limits and Cartesian drive: a `; flavour …` line, then `;   …`
    /// lines a user pastes (without `;   `) into the firmware's configuration, each with its
    /// reason after `; ` (see [`super::config`], which the emitter calls with the machine's
    /// full [`super::config::ConfigInput`]).
    pub fn header(self, limits: &[AxisLimit], feed: FeedMode) -> Vec<String> {
        let input = super::config::ConfigInput {
            machine: String::new(),
            axes: limits.iter().map(super::config::ConfigAxis::from).collect(),
            feed,
            drive: super::config::AxisDrive::Cartesian,
        };
        super::config::build(self, &input).header
    }
}

pub use super::config::klipper::{KLIPPER_EXTRA_AXIS_CORNER_DEFAULT, KLIPPER_GCODE_AXIS_SINCE};
pub use super::config::rrf::{RRF_G93_VERSION, RRF_UNLIMITED_ROTARY_DEG};

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
        // Marlin: the rotary axis first (AXIS5_ROTATES requires AXIS4_ROTATES), said so
        let marlin = Flavour::Marlin.header(&limits, FeedMode::Xyz).join("\n");
        assert!(
            marlin.contains("#define AXIS4_NAME 'A'   // rotary")
                && marlin.contains("AXIS5_NAME 'U'   // linear")
                && marlin.contains("machine's order U A is configured as A U"),
            "{marlin}"
        );
    }

    /// `M208 <L><v> S<s>` lines of a RepRapFirmware header: (letter, S, value).
    fn m208(lines: &[String]) -> Vec<(String, u8, f64)> {
        lines
            .iter()
            .filter_map(|l| l.strip_prefix(";   M208 "))
            .map(|t| {
                let code = t.split(';').next().unwrap();
                let w: Vec<&str> = code.split_whitespace().collect();
                assert_eq!(w.len(), 2, "{t}");
                let (letter, v) = w[0].split_at(1);
                let s = match w[1] {
                    "S1" => 1,
                    "S0" => 0,
                    other => panic!("M208 {other}"),
                };
                (letter.to_string(), s, v.parse().expect("an M208 number"))
            })
            .collect()
    }

    /// Every preset × flavour: the header block's lines are there and parse as the firmware's
    /// own commands: RepRapFirmware's `M584` names every axis and an extruder drive, `M208`
    /// gives each finite limit (S1 minimum, S0 maximum; ±100000 for an unlimited rotary axis),
    /// `M564` advice, `G93`'s minimum version with inverse time; Klipper a `[manual_stepper]`
    /// and a `MANUAL_STEPPER … GCODE_AXIS=` line per extra axis; Marlin an `AXISn_NAME` each.
    #[test]
    fn every_preset_gets_a_parseable_header_in_every_flavour() {
        for name in crate::machine::preset_names() {
            let m = crate::machine::preset(name).unwrap().build().unwrap();
            let limits = m.limits();
            let extra: Vec<&AxisLimit> = limits
                .iter()
                .filter(|l| !["X", "Y", "Z"].contains(&l.name.as_str()))
                .collect();
            for feed in [FeedMode::Tip, FeedMode::InverseTime] {
                let rrf = Flavour::RepRapFirmware.header(limits, feed);
                let m584 = rrf
                    .iter()
                    .find_map(|l| l.strip_prefix(";   M584 "))
                    .expect("M584");
                let words: Vec<&str> = m584.split(';').next().unwrap().split_whitespace().collect();
                let mut want: Vec<String> = limits.iter().map(|l| l.name.clone()).collect();
                want.push("E".into());
                let got: Vec<String> = words
                    .iter()
                    .map(|w| {
                        let (letter, drv) = w.split_at(1);
                        assert!(drv.starts_with("<driver") && drv.ends_with('>'), "{w}");
                        letter.to_string()
                    })
                    .collect();
                assert_eq!(got, want, "{name}: M584 {m584}");
                let lines = m208(&rrf);
                for l in limits {
                    let get = |s: u8| {
                        lines
                            .iter()
                            .find(|(n, ss, _)| *n == l.name && *ss == s)
                            .map(|x| x.2)
                    };
                    for (s, v, wide) in [
                        (1, l.min, -RRF_UNLIMITED_ROTARY_DEG),
                        (0, l.max, RRF_UNLIMITED_ROTARY_DEG),
                    ] {
                        let want = if v.is_finite() {
                            Some(v)
                        } else if l.rotary {
                            Some(wide)
                        } else {
                            None
                        };
                        assert_eq!(get(s), want, "{name}: M208 {} S{s}", l.name);
                    }
                }
                assert!(
                    rrf.iter().any(|l| l.starts_with(";   M564 H1 S1")),
                    "{name}"
                );
                assert_eq!(
                    rrf.iter().any(|l| l.contains("G93") && l.contains("3.5.0")),
                    feed == FeedMode::InverseTime,
                    "{name}"
                );

                let kl = Flavour::Klipper.header(limits, feed);
                if extra.is_empty() {
                    assert_eq!(kl, ["; flavour Klipper (3-axis)"], "{name}");
                }
                for l in &extra {
                    let stepper = format!("axis_{}", l.name.to_ascii_lowercase());
                    let section = kl
                        .iter()
                        .find(|x| x.starts_with(&format!(";   [manual_stepper {stepper}]")))
                        .unwrap_or_else(|| panic!("{name}: no section for {}", l.name));
                    if l.min.is_finite() {
                        assert!(
                            section.contains(&format!(
                                "position_min: {}",
                                crate::num::fmt_shortest(l.min)
                            )),
                            "{section}"
                        );
                    }
                    assert!(
                        kl.iter().any(|x| x.starts_with(&format!(
                            ";   MANUAL_STEPPER STEPPER={stepper} GCODE_AXIS={} ",
                            l.name
                        )) && x.contains("INSTANTANEOUS_CORNER_VELOCITY=")),
                        "{name}: {kl:?}"
                    );
                }
                for l in limits
                    .iter()
                    .filter(|l| !extra.contains(l) && l.min.is_finite())
                {
                    let want = format!(
                        ";   [stepper_{}] position_min: {}",
                        l.name.to_ascii_lowercase(),
                        crate::num::fmt_shortest(l.min)
                    );
                    assert!(kl.iter().any(|x| x.starts_with(&want)), "{name}: {kl:?}");
                }
                let marlin = Flavour::Marlin.header(limits, feed);
                let defs = marlin.iter().filter(|l| l.contains("#define AXIS")).count();
                assert_eq!(defs, extra.len(), "{name}");
            }
        }
    }

    /// The refusals, by name (code `machine.unsupported-flavour`): Marlin and Klipper with
    /// inverse time, Klipper with an axis lettered E or F or with a longer name.
    #[test]
    fn refusals_are_named() {
        use crate::error::Coded;
        let xyz = [
            AxisLimit::linear("X"),
            AxisLimit::linear("Y"),
            AxisLimit::linear("Z"),
        ];
        for f in [Flavour::Marlin, Flavour::Klipper] {
            let e = f.check("m", &xyz, FeedMode::InverseTime).unwrap_err();
            assert_eq!(e.code(), "machine.unsupported-flavour");
            assert!(e.to_string().contains("has no G93"), "{e}");
        }
        assert!(Flavour::RepRapFirmware
            .check("m", &xyz, FeedMode::InverseTime)
            .is_ok());
        for (letter, why) in [
            ("E", "extruder"),
            ("F", "feed rate"),
            ("N", "line number"),
            ("AA", "one letter"),
        ] {
            let mut l = xyz.to_vec();
            l.push(AxisLimit::rotary(letter, -90.0, 90.0));
            let e = Flavour::Klipper.check("m", &l, FeedMode::Tip).unwrap_err();
            assert_eq!(e.code(), "machine.unsupported-flavour");
            assert!(e.to_string().contains(why), "{e}");
        }
        let mut ok = xyz.to_vec();
        ok.push(AxisLimit::rotary("A", -90.0, 90.0));
        assert!(Flavour::Klipper.check("m", &ok, FeedMode::Tip).is_ok());
    }
}
