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
                    .find(|n| ["E", "F"].contains(&n.to_ascii_uppercase().as_str()))
                {
                    return Err(refuse(format!(
                        "in Klipper's G1 the letter '{bad}' is the {}, not an axis (rename it with axis_names)",
                        if bad.eq_ignore_ascii_case("E") { "extruder" } else { "feed rate" }
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

    /// Header comment lines (without the leading `; warpslice machine = …` line): a
    /// `; flavour …` line, then `;   …` lines a user pastes (without `;   `) into the firmware's
    /// configuration, each with its reason after `; `.
    ///
    /// RepRapFirmware (3.3 and later): `M584 … R1` creates rotary axes, `R0` linear ones, and
    /// `S1` keeps a rotary axis out of the feed-rate length when a linear axis moves (NIST
    /// RS274 §2.1.2.5; RRF's default for `R1`) while `S0` counts its degrees like millimetres:
    /// `S0` for `--feed all-axes`, `S1` otherwise (`tip` computes F for exactly that rule).
    pub fn header(self, limits: &[AxisLimit], feed: FeedMode) -> Vec<String> {
        let extra: Vec<&AxisLimit> = limits
            .iter()
            .filter(|l| !["X", "Y", "Z"].contains(&l.name.as_str()))
            .collect();
        let mut lines = Vec::new();
        match self {
            Flavour::RepRapFirmware => {
                lines.push(
                    "; flavour RepRapFirmware 3.3 or later: this file expects in config.g".into(),
                );
                let mut m = String::from(";   M584");
                for (i, l) in limits.iter().enumerate() {
                    m.push_str(&format!(" {}<driver{i}>", l.name));
                }
                m.push_str(&format!(
                    " E<driver{}>   ; your board's drivers; E: RRF 3.3 and later need the extruder drive(s) declared in M584",
                    limits.len()
                ));
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
                for l in limits {
                    lines.extend(rrf_m208(l));
                }
                lines.push(
                    ";   M564 H1 S1   ; RRF's default: moves need homed axes and are clamped to the M208 limits, so the limits above must hold every value this file writes (M564 S0 would drop the clamp everywhere: not advised)".into(),
                );
                if feed == FeedMode::InverseTime {
                    lines.push(format!(
                        ";   G93 inverse-time feed: RepRapFirmware {RRF_G93_VERSION} or later (older versions read F as mm/min)"
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
            }
            Flavour::Klipper if extra.is_empty() => lines.push("; flavour Klipper (3-axis)".into()),
            Flavour::Klipper => {
                lines.push(format!(
                    "; flavour Klipper (extra G-code axes: mainline since {KLIPPER_GCODE_AXIS_SINCE}): this file expects in printer.cfg"
                ));
                for l in &extra {
                    lines.push(format!(
                        ";   [manual_stepper {}]   ; axis {}, {}: step_pin, dir_pin, enable_pin, microsteps, rotation_distance ({}){}",
                        klipper_stepper(l),
                        l.name,
                        if l.rotary { "rotary, degrees" } else { "linear, mm" },
                        if l.rotary {
                            "degrees per motor turn"
                        } else {
                            "mm per motor turn"
                        },
                        klipper_travel(l)
                    ));
                }
                for l in limits.iter().filter(|l| !extra.contains(l)) {
                    let travel = klipper_travel(l);
                    if let Some(t) = travel.strip_prefix(", ") {
                        lines.push(format!(
                            ";   [stepper_{}] {t}   ; axis {} travel, mm",
                            l.name.to_ascii_lowercase(),
                            l.name
                        ));
                    }
                }
                lines.push(
                    ";   and, before this file's moves (the start G-code or a [delayed_gcode]):"
                        .into(),
                );
                for l in &extra {
                    lines.push(format!(
                        ";   MANUAL_STEPPER STEPPER={} GCODE_AXIS={} LIMIT_VELOCITY=<{u}/s> LIMIT_ACCEL=<{u}/s²> INSTANTANEOUS_CORNER_VELOCITY=<{u}/s>",
                        klipper_stepper(l),
                        l.name,
                        u = if l.rotary { "deg" } else { "mm" }
                    ));
                }
                lines.push(format!(
                    ";   INSTANTANEOUS_CORNER_VELOCITY: an extra axis' junction speed defaults to {KLIPPER_EXTRA_AXIS_CORNER_DEFAULT} mm/s (deg/s); this file splits curved moves into short pieces, so set it near the axis' speed on the path or every junction slows the print"
                ));
                lines.push(
                    ";   Klipper times a move by its X Y Z length (the largest E or extra-axis change when X Y Z are still, which it runs as an extrude-only move: mind max_extrude_only_velocity and LIMIT_ACCEL): --feed tip computes F for that rule; Klipper has no G93".into(),
                );
                if extra
                    .iter()
                    .any(|l| l.rotary && !(l.min.is_finite() && l.max.is_finite()))
                {
                    lines.push(
                        ";   Klipper's G92 sets X Y Z E only: an unlimited rotary axis is written unwrapped (no resets), so give it no position limits".into(),
                    );
                }
            }
        }
        lines
    }
}

/// Klipper's `[manual_stepper]` section name warpslice suggests for extra axis `l`.
fn klipper_stepper(l: &AxisLimit) -> String {
    format!("axis_{}", l.name.to_ascii_lowercase())
}

/// The `position_min` / `position_max` advice of a Klipper extra axis.
fn klipper_travel(l: &AxisLimit) -> String {
    let n = crate::num::fmt_shortest;
    match (l.min.is_finite(), l.max.is_finite()) {
        (true, true) => format!(", position_min: {}, position_max: {}", n(l.min), n(l.max)),
        (true, false) => format!(", position_min: {}", n(l.min)),
        (false, true) => format!(", position_max: {}", n(l.max)),
        (false, false) => String::new(),
    }
}

/// The first RepRapFirmware version with `G93` inverse-time feed (its documentation says 3.2;
/// the code has it from 3.5.0).
pub const RRF_G93_VERSION: &str = "3.5.0";
/// Since when mainline Klipper takes extra G-code axes (`MANUAL_STEPPER … GCODE_AXIS=`).
pub const KLIPPER_GCODE_AXIS_SINCE: &str = "2025-05";
/// Klipper's default `INSTANTANEOUS_CORNER_VELOCITY` of an extra axis, mm/s (deg/s).
pub const KLIPPER_EXTRA_AXIS_CORNER_DEFAULT: f64 = 1.0;
/// The `M208` range written for a rotary axis without limits (a slip ring, a mandrel), degrees:
/// RepRapFirmware clamps every homed axis to its `M208` range, so "unlimited" is a range wider
/// than any file turns it (warpslice resets such an axis modulo 360° at each layer change).
pub const RRF_UNLIMITED_ROTARY_DEG: f64 = 100_000.0;

/// The `M208` lines of axis `l`: `M208 <L><min> S1` (minimum) and `M208 <L><max> S0`
/// (maximum) for each finite end; an unlimited rotary axis gets
/// ±[`RRF_UNLIMITED_ROTARY_DEG`]; an unlimited linear axis keeps the machine's own limits (a
/// note says so).
fn rrf_m208(l: &AxisLimit) -> Vec<String> {
    let n = crate::num::fmt_shortest;
    let unit = if l.rotary { "degrees" } else { "mm" };
    let mut out = Vec::new();
    for (v, s, end) in [(l.min, 1, "minimum"), (l.max, 0, "maximum")] {
        if v.is_finite() {
            out.push(format!(
                ";   M208 {}{} S{s}   ; axis {} {end}, {unit}",
                l.name,
                n(v),
                l.name
            ));
        } else if l.rotary {
            let w = if s == 1 {
                -RRF_UNLIMITED_ROTARY_DEG
            } else {
                RRF_UNLIMITED_ROTARY_DEG
            };
            out.push(format!(
                ";   M208 {}{} S{s}   ; axis {} turns without limit: a range wider than any layer turns it",
                l.name,
                n(w),
                l.name
            ));
        }
    }
    if out.is_empty() {
        out.push(format!(
            ";   axis {}: keep your M208 {} limits (the machine file gives none)",
            l.name, l.name
        ));
    }
    out
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
        for (letter, why) in [("E", "extruder"), ("F", "feed rate"), ("AA", "one letter")] {
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
