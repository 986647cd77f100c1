//! Marlin 2.1: the `Configuration.h` block and the header's summary.
//!
//! Marlin names the axes after X Y Z internally I J K U V W (`AXIS4` … `AXIS9`), each given its
//! G-code letter by `AXISn_NAME` (one of A B C U V W) and made rotary by `AXISn_ROTATES`.
//! Facts from Marlin's `SanityCheck.h`: `AXIS5_ROTATES` requires `AXIS4_ROTATES` (and so on:
//! the rotary axes come first); every extra axis requires `I_MIN_POS` / `I_MAX_POS`,
//! `I_HOME_DIR`, `I_ENABLE_ON` and `INVERT_I_DIR` (J, K, … alike); `LINEAR_ADVANCE` refuses an
//! I axis. A rotary axis (`AXISn_ROTATES`) is left out of the move length whenever a linear axis
//! moves (NIST); `--feed tip` computes F for that rule.
//!
//! The block puts the rotary axes first, in the machine's order, then the linear ones. That
//! reordering is sound: a G-code word names its axis by letter (`AXISn_NAME`), never by index,
//! so the file reads the same; only which driver and which entry of the per-axis arrays
//! (`DEFAULT_AXIS_STEPS_PER_UNIT`, …) belong to a letter follow the order the block gives.

use super::{num, rrf::RRF_UNLIMITED_ROTARY_DEG, title, ConfigAxis, ConfigInput, FirmwareConfig};
use crate::machine::Flavour;

/// Marlin's internal names of the extra axes `AXIS4` … `AXIS9`.
pub const MARLIN_AXIS_IDS: &[&str] = &["I", "J", "K", "U", "V", "W"];
/// The first Marlin release with `AXISn_ROTATES` and up to nine axes.
pub const MARLIN_MIN_VERSION: &str = "2.1.0";

/// The extra axes in the order Marlin can configure them: the firmware-rotary ones first (in
/// the machine's order), then the linear ones.
pub fn marlin_order<'a>(extra: &[&'a ConfigAxis]) -> Vec<&'a ConfigAxis> {
    let mut v = extra.to_vec();
    v.sort_by_key(|a| !a.firmware_rotary);
    v
}

/// The `Configuration.h` block and the header (see the module documentation).
pub fn build(input: &ConfigInput) -> FirmwareConfig {
    let extra = input.extra();
    let ordered = marlin_order(&extra);
    let reordered = ordered.iter().zip(&extra).any(|(a, b)| a.name != b.name);
    let mut header =
        vec!["; flavour Marlin 2.1: extra axes are set in Configuration.h as".to_string()];
    let mut text = vec![
        title("//", "Marlin", "Configuration.h", input),
        format!(
            "// Marlin {MARLIN_MIN_VERSION} or later (AXISn_NAME / AXISn_ROTATES, up to 9 axes). Marlin calls the axes after X Y Z I J K U V W and names them by AXISn_NAME; a rotary axis must come before every linear one (AXIS5_ROTATES requires AXIS4_ROTATES)."
        ),
    ];
    if reordered {
        let note = format!(
            "rotary axes first: the machine's order {} is configured as {} (sound: G-code names an axis by its letter, not its index; wire the drivers in this order)",
            extra.iter().map(|a| a.name.as_str()).collect::<Vec<_>>().join(" "),
            ordered.iter().map(|a| a.name.as_str()).collect::<Vec<_>>().join(" ")
        );
        header.push(format!(";   {note}"));
        text.push(format!("// {note}"));
    }
    for (k, a) in ordered.iter().enumerate() {
        let (n, id) = (k + 4, MARLIN_AXIS_IDS[k]);
        let kind = match (a.rotary, a.firmware_rotary) {
            (_, true) => "rotary (AXIS*_ROTATES), degrees",
            (true, false) => "linear (turns in degrees, configured linear: no AXIS*_ROTATES; its degrees count in the move length like mm)",
            (false, false) => "linear, mm",
        };
        header.push(format!(";   #define AXIS{n}_NAME '{}'   // {kind}", a.name));
        text.push(format!(
            "#define {id}_DRIVER_TYPE <driver type, e.g. TMC2209>   // axis {}",
            a.name
        ));
        text.push(format!("#define AXIS{n}_NAME '{}'   // {kind}", a.name));
        if a.firmware_rotary {
            text.push(format!("#define AXIS{n}_ROTATES   // left out of the move length when a linear axis moves (NIST), which --feed tip computes F for"));
        }
        let (lo, hi, why) = if a.limited() {
            (
                a.min,
                a.max,
                "the range every move of this file was checked against",
            )
        } else if a.rotary {
            (
                a.min.max(-RRF_UNLIMITED_ROTARY_DEG),
                a.max.min(RRF_UNLIMITED_ROTARY_DEG),
                "turns without limit: a range wider than any layer turns it",
            )
        } else {
            (f64::NAN, f64::NAN, "")
        };
        if lo.is_finite() && hi.is_finite() {
            text.push(format!(
                "#define {id}_MIN_POS {}   // {}: {why}",
                num(lo),
                a.unit()
            ));
            text.push(format!("#define {id}_MAX_POS {}", num(hi)));
        } else {
            text.push(format!(
                "#define {id}_MIN_POS <lowest {}>   // the machine file gives no travel for {}",
                a.unit(),
                a.name
            ));
            text.push(format!("#define {id}_MAX_POS <highest {}>", a.unit()));
        }
        text.push(format!(
            "#define {id}_HOME_DIR -1   // homing direction: -1 toward {id}_MIN_POS, 1 toward {id}_MAX_POS (where your endstop is)"
        ));
        text.push(format!(
            "#define {id}_ENABLE_ON 0   // your driver's enable level"
        ));
        text.push(format!(
            "#define INVERT_{id}_DIR false   // your motor's direction"
        ));
    }
    for a in &input.axes {
        if a.min.is_finite() || a.max.is_finite() {
            header.push(format!(
                ";   axis {} travel [{}, {}] {}",
                a.name,
                a.min,
                a.max,
                if a.rotary { "deg" } else { "mm" }
            ));
        }
    }
    for a in input.axes.iter().filter(|a| a.is_xyz() && a.limited()) {
        text.push(format!(
            "// axis {}: this file writes within [{}, {}] mm: {}_MIN_POS / {}_MAX_POS must hold it",
            a.name,
            num(a.min),
            num(a.max),
            a.name,
            a.name
        ));
    }
    if !extra.is_empty() {
        let steps: Vec<String> = ["X", "Y", "Z"]
            .iter()
            .map(|l| format!("<{l}: yours>"))
            .chain(ordered.iter().map(|a| {
                format!(
                    "<{}: steps per {}>",
                    a.name,
                    if a.rotary { "degree" } else { "mm" }
                )
            }))
            .chain(["<E: yours>".to_string()])
            .collect();
        text.push(format!(
            "#define DEFAULT_AXIS_STEPS_PER_UNIT {{ {} }}   // X, Y, Z, {}, E: motor steps × microsteps × gear ratio / travel per turn",
            steps.join(", "),
            MARLIN_AXIS_IDS[..ordered.len()].join(", ")
        ));
        if ordered.iter().all(|a| a.max_feed.is_finite()) {
            text.push(format!(
                "// largest speeds the print-time estimate assumed (DEFAULT_MAX_FEEDRATE is per second): {}",
                ordered
                    .iter()
                    .map(|a| format!(
                        "{} {} {}/s",
                        a.name,
                        num(a.max_feed / 60.0),
                        if a.rotary { "deg" } else { "mm" }
                    ))
                    .collect::<Vec<_>>()
                    .join(", ")
            ));
        }
        let la = "LINEAR_ADVANCE: leave it disabled: Marlin 2.1 refuses it with an extra axis (\"does not currently support the inclusion of an I axis\")";
        header.push(format!(";   {la}"));
        text.push(format!("// {la}"));
    }
    let g93 = "Marlin 2.1 has no G93 (inverse-time feed): --feed tip writes every move's F for Marlin's own move length instead";
    header.push(format!(";   {g93}"));
    text.push(format!("// {g93}"));
    FirmwareConfig {
        flavour: Flavour::Marlin,
        file: "Configuration.h",
        header,
        text: text.join("\n") + "\n",
    }
}
