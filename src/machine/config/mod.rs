//! The firmware configuration a machine's output needs, per flavour: a fragment a user pastes
//! into the firmware's own configuration (`--config-out FILE`, the web page's second download,
//! wasm `firmware_config`), and its summary as comment lines in the G-code header.
//!
//! One builder per firmware, each in its own file, computes both from the same facts
//! ([`ConfigInput`]: the axes as checked — letters, rotary or linear, the limits every written
//! move was checked against, the largest feeds — the feed mode, and how the machine's letters
//! map to motors, [`AxisDrive`]):
//! - [`rrf`]: RepRapFirmware `config.g` — `M584` (with `E`), `M92` placeholders, `M208` for
//!   every axis (negative rotary limits included), `M203`, `M564` advice, `M669` where the
//!   machine needs it; minimum version 3.3 (3.5.0 for `G93`).
//! - [`marlin`]: Marlin 2.1 `Configuration.h` — `AXISn_NAME` / `AXISn_ROTATES` with the rotary
//!   axes first (Marlin requires `AXIS5_ROTATES` only after `AXIS4_ROTATES`: the letters are
//!   reordered, which is sound because a G-code word names its axis by letter, not by index),
//!   `I_MIN_POS` / `I_MAX_POS`, `I_HOME_DIR`, `I_ENABLE_ON`, `INVERT_I_DIR`, the steps per unit
//!   as a placeholder, and the Linear Advance warning (Marlin refuses `LINEAR_ADVANCE` with an
//!   extra axis).
//! - [`klipper`]: Klipper `printer.cfg` — a `[manual_stepper]` section per extra axis with its
//!   position limits, and the `MANUAL_STEPPER … GCODE_AXIS=` lines (mainline since 2025-05)
//!   with the `INSTANTANEOUS_CORNER_VELOCITY` advice.
//!
//! Every value the user must supply (drivers, pins, steps) is a `<…>` placeholder, so the
//! firmware refuses the fragment until it is filled in rather than driving the wrong motor.

pub mod klipper;
pub mod marlin;
pub mod rrf;

use super::{AxisLimit, FeedMode, Flavour, MachineError};

/// How the machine's axis letters map to motors, as far as the firmware's kinematics setting
/// is concerned (the [`super::Machine::axis_drive`] of each kind).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
#[non_exhaustive]
pub enum AxisDrive {
    /// X Y Z are the machine's Cartesian coordinates: keep the firmware's own XY kinematics
    /// (Cartesian or CoreXY); the extra letters are plain axes.
    #[default]
    Cartesian,
    /// X is a radius and C a turntable angle, written raw: every letter must drive its own
    /// motor (Cartesian kinematics), not the firmware's polar kinematics, which would read X Y
    /// as Cartesian coordinates and convert them again.
    RawPolar,
    /// The bed's three Z motors are three axes (Z U V), each driven alone: not one Z with three
    /// drivers and the firmware's own levelling.
    SeparateZ,
}

/// One axis as the configuration gives it.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigAxis {
    /// The G-code letter.
    pub name: String,
    /// The axis turns (degrees) in the kinematics.
    pub rotary: bool,
    /// The firmware is configured to treat it as rotary (false for a rotary axis the machine
    /// file lists in `firmware_linear_axes`, e.g. Open5x's Duet 2 U V: its degrees count in
    /// the move length like millimetres).
    pub firmware_rotary: bool,
    /// Lowest value written (mm or degrees; `-inf`: unlimited).
    pub min: f64,
    /// Highest value written (mm or degrees; `+inf`: unlimited).
    pub max: f64,
    /// Largest feed, mm/min or °/min (`+inf`: the machine file gives none).
    pub max_feed: f64,
}

impl ConfigAxis {
    /// An X, Y or Z axis (the firmware's first three), not an extra one.
    pub fn is_xyz(&self) -> bool {
        ["X", "Y", "Z"].contains(&self.name.as_str())
    }
    /// "degrees" or "mm".
    pub fn unit(&self) -> &'static str {
        if self.rotary {
            "degrees"
        } else {
            "mm"
        }
    }
    /// Both ends finite.
    pub fn limited(&self) -> bool {
        self.min.is_finite() && self.max.is_finite()
    }
}

impl From<&AxisLimit> for ConfigAxis {
    /// An axis with its kinematic limits, configured as it turns, no feed limit.
    fn from(l: &AxisLimit) -> ConfigAxis {
        ConfigAxis {
            name: l.name.clone(),
            rotary: l.rotary,
            firmware_rotary: l.rotary,
            min: l.min,
            max: l.max,
            max_feed: f64::INFINITY,
        }
    }
}

/// What a configuration is built from.
#[derive(Clone, Debug, PartialEq)]
pub struct ConfigInput {
    /// The machine's name (preset or JSON `name`).
    pub machine: String,
    /// The axes in the machine's order.
    pub axes: Vec<ConfigAxis>,
    /// The feed mode of the output.
    pub feed: FeedMode,
    /// How the letters map to motors.
    pub drive: AxisDrive,
}

impl ConfigInput {
    /// The extra axes (not X, Y, Z), in the machine's order.
    pub fn extra(&self) -> Vec<&ConfigAxis> {
        self.axes.iter().filter(|a| !a.is_xyz()).collect()
    }
}

/// A firmware configuration: the paste-able fragment and the header's summary of it.
#[derive(Clone, Debug, PartialEq)]
pub struct FirmwareConfig {
    /// The firmware.
    pub flavour: Flavour,
    /// The configuration file it belongs in (`config.g`, `Configuration.h`, `printer.cfg`).
    pub file: &'static str,
    /// The G-code header lines (comments): a `; flavour …` line, then `;   …` lines.
    pub header: Vec<String>,
    /// The fragment: lines in the firmware's own syntax, its comments included.
    pub text: String,
}

/// Build the configuration of `flavour` for `input` (the flavour has accepted the machine:
/// [`Flavour::check`]).
pub fn build(flavour: Flavour, input: &ConfigInput) -> FirmwareConfig {
    match flavour {
        Flavour::RepRapFirmware => rrf::build(input),
        Flavour::Marlin => marlin::build(input),
        Flavour::Klipper => klipper::build(input),
    }
}

/// `v` as the shortest decimal that reads back to it.
pub(crate) fn num(v: f64) -> String {
    crate::num::fmt_shortest(v)
}

/// The first line of every fragment: what it is, for which machine and feed, where it goes.
pub(crate) fn title(comment: &str, firmware: &str, file: &str, input: &ConfigInput) -> String {
    format!(
        "{comment} warpslice {}: {firmware} configuration for machine '{}' (feed {}); paste into {file} and replace every <…> with your machine's value",
        env!("CARGO_PKG_VERSION"),
        input.machine,
        input.feed.name()
    )
}

/// The axes of `machine` (built from `spec`) as its firmware is configured: the limits every
/// written move is checked against (the kinematic ranges within the file's `travel`), the
/// largest feeds, and `firmware_rotary` false for the rotary axes `spec` lists in
/// `firmware_linear_axes` (a name there that is no rotary axis is
/// [`MachineError::BadSpec`]).
pub fn input_for(
    spec: &super::MachineSpec,
    machine: &dyn super::Machine,
    feed: FeedMode,
) -> Result<ConfigInput, MachineError> {
    let limits = machine.limits();
    let linear = spec.firmware_linear_axes.as_deref().unwrap_or_default();
    for n in linear {
        if !limits.iter().any(|l| l.rotary && &l.name == n) {
            return Err(MachineError::BadSpec {
                machine: machine.name().to_string(),
                message: format!(
                    "firmware_linear_axes names '{n}', which is not a rotary axis of this machine (its rotary axes: {}); list only rotary axes the firmware is configured to treat as linear",
                    limits
                        .iter()
                        .filter(|l| l.rotary)
                        .map(|l| l.name.as_str())
                        .collect::<Vec<_>>()
                        .join(" ")
                ),
            });
        }
    }
    let bounds = spec.axis_bounds(limits)?;
    Ok(ConfigInput {
        machine: machine.name().to_string(),
        axes: bounds
            .iter()
            .map(|b| ConfigAxis {
                name: b.name.clone(),
                rotary: b.rotary,
                firmware_rotary: b.rotary && !linear.contains(&b.name),
                min: b.min,
                max: b.max,
                max_feed: b.max_feed,
            })
            .collect(),
        feed,
        drive: machine.axis_drive(),
    })
}

/// The configuration of the machine `spec` for `flavour` (else the spec's, else
/// RepRapFirmware) and `feed`: the flavour's refusals first ([`Flavour::check`]), as the
/// emitter does, so a fragment is never written for a file that would not be.
pub fn for_spec(
    spec: &super::MachineSpec,
    flavour: Option<Flavour>,
    feed: FeedMode,
) -> Result<FirmwareConfig, MachineError> {
    let machine = spec.build()?;
    let flavour = flavour.or(spec.flavour).unwrap_or_default();
    let input = input_for(spec, machine.as_ref(), feed)?;
    flavour.check(machine.name(), machine.limits(), feed)?;
    Ok(build(flavour, &input))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::Coded;

    /// An A/B table lettered X Y Z U A with U configured linear in the firmware
    /// (`firmware_linear_axes`): Marlin gets the rotary A first (`AXIS5_ROTATES` would need
    /// `AXIS4_ROTATES`), RepRapFirmware creates U with `R0`, and the emitter's length rule
    /// counts U as linear; a `firmware_linear_axes` entry that is no rotary axis is refused by
    /// name, as is an axis letter Marlin cannot give.
    #[test]
    fn a_linear_configured_axis_before_a_rotary_one_is_reordered_for_marlin() {
        let mut spec = crate::machine::preset("open5x-ab").unwrap();
        spec.axis_names = Some(["X", "Y", "Z", "U", "A"].map(String::from).to_vec());
        spec.max_feed = None;
        spec.firmware_linear_axes = Some(vec!["U".into()]);
        let marlin = for_spec(&spec, Some(Flavour::Marlin), FeedMode::Tip).unwrap();
        let defines: Vec<&str> = marlin
            .text
            .lines()
            .filter(|l| l.starts_with("#define AXIS"))
            .map(|l| l.split("//").next().unwrap().trim())
            .collect();
        assert_eq!(
            defines,
            [
                "#define AXIS4_NAME 'A'",
                "#define AXIS4_ROTATES",
                "#define AXIS5_NAME 'U'"
            ],
            "{}",
            marlin.text
        );
        let rrf = for_spec(&spec, None, FeedMode::Tip).unwrap();
        assert!(
            rrf.text.contains("M584 U<driver3> R0") && rrf.text.contains("M584 A<driver4> R1 S1"),
            "{}",
            rrf.text
        );

        spec.firmware_linear_axes = Some(vec!["X".into()]);
        let e = for_spec(&spec, None, FeedMode::Tip).unwrap_err();
        assert_eq!(e.code(), "machine.bad-spec");
        assert!(
            e.to_string().contains("'X', which is not a rotary axis"),
            "{e}"
        );

        spec.firmware_linear_axes = None;
        spec.axis_names = Some(["X", "Y", "Z", "D", "A"].map(String::from).to_vec());
        let e = for_spec(&spec, Some(Flavour::Marlin), FeedMode::Tip).unwrap_err();
        assert_eq!(e.code(), "machine.unsupported-flavour");
        assert!(e.to_string().contains("axis 'D' cannot be given"), "{e}");
    }

    /// Every preset × flavour: the fragment and the header state the firmware's minimum
    /// version, and a fragment line that is not a comment is in the firmware's own syntax.
    #[test]
    fn every_fragment_states_its_minimum_version_in_the_firmwares_syntax() {
        for name in crate::machine::preset_names() {
            let spec = crate::machine::preset(name).unwrap();
            for f in [Flavour::RepRapFirmware, Flavour::Marlin, Flavour::Klipper] {
                for feed in [FeedMode::Tip, FeedMode::InverseTime] {
                    let Ok(c) = for_spec(&spec, Some(f), feed) else {
                        assert!(feed == FeedMode::InverseTime && f != Flavour::RepRapFirmware);
                        continue;
                    };
                    let (version, comment) = match f {
                        Flavour::RepRapFirmware => ("RepRapFirmware 3.3 or later", ";"),
                        Flavour::Marlin => ("Marlin 2.1.0 or later", "//"),
                        _ => ("Klipper mainline 2025-05 or later", "#"),
                    };
                    assert!(c.text.contains(version), "{name} {f:?}: {}", c.text);
                    assert!(c.header[0].starts_with("; flavour "), "{name}");
                    for l in c.text.lines().filter(|l| !l.trim().is_empty()) {
                        let ok = l.starts_with(comment)
                            || match f {
                                Flavour::RepRapFirmware => l.starts_with('M'),
                                Flavour::Marlin => l.starts_with("#define "),
                                _ => true,
                            };
                        assert!(ok, "{name} {f:?}: {l}");
                    }
                    if f == Flavour::RepRapFirmware {
                        assert_eq!(
                            c.text.contains("3.5.0 or later for G93"),
                            feed == FeedMode::InverseTime,
                            "{name}"
                        );
                    }
                }
            }
        }
    }
}
