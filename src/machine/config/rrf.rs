//! RepRapFirmware (3.3 or later): the `config.g` fragment and the header's summary.
//!
//! - `M584` maps every axis letter to a driver and declares the extruder drive (`E`: RRF 3.3
//!   and later require the extruders in `M584`). Extra axes are created with `R1` (rotary) and
//!   `S1` (NIST length rule: left out of the feed length when a linear axis moves; RRF's
//!   default for rotary axes) or `S0` (`--feed all-axes`: degrees counted like mm), or `R0`
//!   (linear, mm; also a rotary axis the machine file lists in `firmware_linear_axes`, whose
//!   degrees then count like mm, as Open5x's Duet 2 configuration does with U and V).
//! - `M208 <L><min> S1` / `M208 <L><max> S0` for every finite limit: RRF defaults every axis to
//!   0…200 and, with `M564 S1` (its default), clamps a homed axis there, so a rotary axis going
//!   negative would be clipped. An unlimited rotary axis gets ±[`RRF_UNLIMITED_ROTARY_DEG`].
//! - `M203` the largest speeds (mm/min, °/min) the print-time estimate assumed.
//! - `M669 K0` where the letters are raw motor positions the firmware's own kinematics must not
//!   convert ([`AxisDrive::RawPolar`]).
//! - `G93` (inverse-time feed) exists from RRF [`RRF_G93_VERSION`] (its documentation says 3.2).

use super::{num, title, AxisDrive, ConfigAxis, ConfigInput, FirmwareConfig};
use crate::machine::{FeedMode, Flavour};

/// The first RepRapFirmware version with `G93` inverse-time feed (its documentation says 3.2;
/// the code has it from 3.5.0).
pub const RRF_G93_VERSION: &str = "3.5.0";
/// The first RepRapFirmware version whose `M584` declares the extruder drives and takes `R`/`S`
/// for the axes it creates.
pub const RRF_MIN_VERSION: &str = "3.3";
/// The `M208` range written for a rotary axis without limits (a slip ring, a mandrel), degrees:
/// RepRapFirmware clamps every homed axis to its `M208` range, so "unlimited" is a range wider
/// than any file turns it (warpslice resets such an axis modulo 360° at each layer change).
pub const RRF_UNLIMITED_ROTARY_DEG: f64 = 100_000.0;

/// `R1 S1`, `R1 S0` or `R0`: how `M584` creates extra axis `a` for `feed`.
fn create(a: &ConfigAxis, feed: FeedMode) -> &'static str {
    match (a.firmware_rotary, feed) {
        (false, _) => "R0",
        (true, FeedMode::AllAxes) => "R1 S0",
        (true, _) => "R1 S1",
    }
}

/// The `M208` commands of axis `a` (`(code, note)`), or none when the machine gives no limit
/// for a linear axis (the note says to keep the machine's own).
fn m208(a: &ConfigAxis) -> Vec<(String, String)> {
    let mut out = Vec::new();
    for (v, s, end) in [(a.min, 1, "minimum"), (a.max, 0, "maximum")] {
        if v.is_finite() {
            out.push((
                format!("M208 {}{} S{s}", a.name, num(v)),
                format!("axis {} {end}, {}", a.name, a.unit()),
            ));
        } else if a.rotary {
            let w = if s == 1 {
                -RRF_UNLIMITED_ROTARY_DEG
            } else {
                RRF_UNLIMITED_ROTARY_DEG
            };
            out.push((
                format!("M208 {}{} S{s}", a.name, num(w)),
                format!(
                    "axis {} turns without limit: a range wider than any layer turns it",
                    a.name
                ),
            ));
        }
    }
    out
}

/// The `config.g` fragment and the header (see the module documentation).
pub fn build(input: &ConfigInput) -> FirmwareConfig {
    let extra = input.extra();
    let mut header =
        vec!["; flavour RepRapFirmware 3.3 or later: this file expects in config.g".to_string()];
    let mut text = vec![
        title(";", "RepRapFirmware", "config.g", input),
        format!(
            "; RepRapFirmware {RRF_MIN_VERSION} or later (extruder drives and R/S in M584){}; create the axes (M584) before any M350/M92/M906/M208 that names them",
            if input.feed == FeedMode::InverseTime {
                format!(", {RRF_G93_VERSION} or later for G93 inverse-time feed")
            } else {
                String::new()
            }
        ),
    ];

    // M584: one line in the header; in config.g the X Y Z + E line, then one per kind of
    // extra axis (R/S apply to the axes a command creates)
    let drivers: Vec<String> = input
        .axes
        .iter()
        .enumerate()
        .map(|(i, a)| format!("{}<driver{i}>", a.name))
        .collect();
    let e_driver = format!("E<driver{}>", input.axes.len());
    header.push(format!(
        ";   M584 {} {e_driver}   ; your board's drivers; E: RRF 3.3 and later need the extruder drive(s) declared in M584",
        drivers.join(" ")
    ));
    let base: Vec<&str> = input
        .axes
        .iter()
        .zip(&drivers)
        .filter(|(a, _)| a.is_xyz())
        .map(|(_, d)| d.as_str())
        .collect();
    text.push(format!(
        "M584 {} {e_driver}   ; your board's drivers for X Y Z and the extruder (RRF 3.3 and later need the extruder drive(s) declared in M584){}",
        base.join(" "),
        if input.drive == AxisDrive::SeparateZ {
            "; Z is one motor here (not Z0:1:2): the bed's other two motors are axes of their own"
        } else {
            ""
        }
    ));
    for a in &extra {
        let what = match (a.rotary, a.firmware_rotary) {
            (true, true) => "rotary, degrees",
            (true, false) => "rotary, degrees, configured as a linear axis (its degrees count in the move length like mm; --feed tip computes F for that)",
            (false, _) => "linear, mm",
        };
        header.push(format!(
            ";   axis {} is {what} (create it with M584 … {} {})",
            a.name,
            a.name,
            create(a, input.feed)
        ));
    }
    // config.g: one M584 per way of creating (R/S apply to every axis a command creates)
    for how in ["R1 S1", "R1 S0", "R0"] {
        let group: Vec<(&ConfigAxis, &String)> = input
            .axes
            .iter()
            .zip(&drivers)
            .filter(|(a, _)| !a.is_xyz() && create(a, input.feed) == how)
            .collect();
        if group.is_empty() {
            continue;
        }
        let letters: Vec<&str> = group.iter().map(|(a, _)| a.name.as_str()).collect();
        let why = match how {
            "R1 S1" => "rotary, degrees; S1: left out of the feed-rate length when a linear axis moves (NIST), which --feed tip computes F for".to_string(),
            "R1 S0" => "rotary, degrees; S0: their degrees count in the feed-rate length like mm, which --feed all-axes computes F for".to_string(),
            _ => {
                let turning: Vec<&str> = group
                    .iter()
                    .filter(|(a, _)| a.rotary)
                    .map(|(a, _)| a.name.as_str())
                    .collect();
                if turning.is_empty() {
                    "linear, mm".to_string()
                } else {
                    format!(
                        "linear (mm){}: {} turn in degrees but are configured linear (firmware_linear_axes), so their degrees count in the move length like mm, which --feed tip computes F for",
                        if turning.len() == letters.len() { "" } else { " and" },
                        turning.join(" ")
                    )
                }
            }
        };
        text.push(format!(
            "M584 {} {how}   ; axes {}: {why}",
            group
                .iter()
                .map(|(_, d)| d.as_str())
                .collect::<Vec<_>>()
                .join(" "),
            letters.join(" ")
        ));
    }
    if !extra.is_empty() {
        text.push(format!(
            "M92 {}   ; steps per {} of your drive (motor steps × microsteps × gear ratio / travel per turn)",
            extra
                .iter()
                .map(|a| format!(
                    "{}<steps per {}>",
                    a.name,
                    if a.rotary { "degree" } else { "mm" }
                ))
                .collect::<Vec<_>>()
                .join(" "),
            if extra.iter().all(|a| a.rotary) {
                "degree"
            } else {
                "mm or degree"
            }
        ));
    }

    for a in &input.axes {
        let lines = m208(a);
        if lines.is_empty() {
            let keep = format!(
                "axis {}: keep your M208 {} limits (the machine file gives none)",
                a.name, a.name
            );
            header.push(format!(";   {keep}"));
            text.push(format!("; {keep}"));
        }
        for (code, note) in lines {
            header.push(format!(";   {code}   ; {note}"));
            text.push(format!("{code}   ; {note}"));
        }
    }

    let feeds: Vec<String> = input
        .axes
        .iter()
        .filter(|a| a.max_feed.is_finite())
        .map(|a| format!("{}{}", a.name, num(a.max_feed)))
        .collect();
    if !feeds.is_empty() {
        text.push(format!(
            "M203 {}   ; largest speeds, mm/min (degrees/min for a rotary axis): the machine file's max_feed, which the print-time estimate assumes",
            feeds.join(" ")
        ));
    }

    let m564 = "M564 H1 S1   ; RRF's default: moves need homed axes and are clamped to the M208 limits, so the limits above must hold every value this file writes (M564 S0 would drop the clamp everywhere: not advised)";
    header.push(format!(";   {m564}"));
    text.push(m564.to_string());

    match input.drive {
        AxisDrive::RawPolar => {
            let m669 = "M669 K0   ; Cartesian kinematics: every letter drives its own motor; this file writes the radius (X) and the turntable angle raw, and RRF's polar kinematics (M669 K7) would read X Y as Cartesian coordinates and convert them again";
            header.push(format!(";   {m669}"));
            text.push(m669.to_string());
        }
        AxisDrive::SeparateZ => {
            let note = "the bed's three Z motors are the axes written here, one motor each: no M584 Z0:1:2 and no M671 levelling on them";
            header.push(format!(";   {note}"));
            text.push(format!("; {note}"));
        }
        AxisDrive::Cartesian => {
            text.push("; M669: keep your own (K0 Cartesian, K1 CoreXY, …): this file writes X Y Z as the machine's Cartesian coordinates".into());
        }
    }
    if input.feed == FeedMode::InverseTime {
        let g93 = format!(
            "G93 inverse-time feed: RepRapFirmware {RRF_G93_VERSION} or later (older versions read F as mm/min)"
        );
        header.push(format!(";   {g93}"));
        text.push(format!("; {g93}"));
    }
    FirmwareConfig {
        flavour: Flavour::RepRapFirmware,
        file: "config.g",
        header,
        text: text.join("\n") + "\n",
    }
}
