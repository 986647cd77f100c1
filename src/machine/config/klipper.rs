//! Klipper: the `printer.cfg` fragment and the header's summary.
//!
//! Extra axes are `[manual_stepper]` sections registered as G-code axes with
//! `MANUAL_STEPPER STEPPER=… GCODE_AXIS=<letter>` (one upper-case letter, not X Y Z E F N),
//! here in a `[delayed_gcode]` that runs at start-up. `LIMIT_VELOCITY` / `LIMIT_ACCEL` bound
//! the axis' own speed and acceleration (Klipper scales them by move_d / |Δaxis|); an extra
//! axis' junction speed defaults to [`KLIPPER_EXTRA_AXIS_CORNER_DEFAULT`] (units/s):
//! `INSTANTANEOUS_CORNER_VELOCITY` should be near the axis' speed on the path, or every
//! junction of this file's short pieces slows the print. `position_min` / `position_max` of
//! the section bound every move of the axis. Klipper times a move by its X Y Z length (else
//! the largest E or extra-axis change), has no `G93`, and its `G92` sets X Y Z E only (an
//! unlimited rotary axis is written unwrapped, so it gets no position limits).
//!
//! Sources (checked, docs/machines.md "Firmware facts and their sources"):
//! `KevinOConnor/klipper-dev` `klippy/extras/manual_stepper.py` (`command_with_gcode_axis`,
//! `check_move`, `calc_junction`) and `klippy/extras/gcode_move.py` (`cmd_G92`), Klipper
//! `klippy/toolhead.py` (`Move`). The date [`KLIPPER_GCODE_AXIS_SINCE`] is as remembered: no
//! stored source confirms it.

use super::{num, title, ConfigAxis, ConfigInput, FirmwareConfig};
use crate::machine::Flavour;

/// Since when mainline Klipper takes extra G-code axes (`MANUAL_STEPPER … GCODE_AXIS=`), as
/// remembered (not confirmed by a stored source; the files that have it are 2025-copyrighted).
pub const KLIPPER_GCODE_AXIS_SINCE: &str = "2025-05";
/// Klipper's default `INSTANTANEOUS_CORNER_VELOCITY` of an extra axis, mm/s (deg/s)
/// (`manual_stepper.py`: `gcmd.get_float('INSTANTANEOUS_CORNER_VELOCITY', 1., minval=0.)`).
pub const KLIPPER_EXTRA_AXIS_CORNER_DEFAULT: f64 = 1.0;

/// The `[manual_stepper]` section name warpslice suggests for extra axis `a`.
pub fn stepper_name(a: &ConfigAxis) -> String {
    format!("axis_{}", a.name.to_ascii_lowercase())
}

/// `(position_min, position_max)` of axis `a` where finite (none for an unlimited axis).
fn limits(a: &ConfigAxis) -> Vec<(&'static str, f64)> {
    [("position_min", a.min), ("position_max", a.max)]
        .into_iter()
        .filter(|(_, v)| v.is_finite())
        .collect()
}

/// The `MANUAL_STEPPER … GCODE_AXIS=` command of extra axis `a` (`LIMIT_VELOCITY` from the
/// machine file's `max_feed` where it gives one).
fn register(a: &ConfigAxis) -> String {
    let u = if a.rotary { "deg" } else { "mm" };
    let velocity = if a.max_feed.is_finite() {
        num(a.max_feed / 60.0)
    } else {
        format!("<{u}/s>")
    };
    format!(
        "MANUAL_STEPPER STEPPER={} GCODE_AXIS={} LIMIT_VELOCITY={velocity} LIMIT_ACCEL=<{u}/s²> INSTANTANEOUS_CORNER_VELOCITY=<{u}/s>",
        stepper_name(a),
        a.name
    )
}

/// The `printer.cfg` fragment and the header (see the module documentation).
pub fn build(input: &ConfigInput) -> FirmwareConfig {
    let extra = input.extra();
    let mut text = vec![
        title("#", "Klipper", "printer.cfg", input),
        format!("# Klipper mainline {KLIPPER_GCODE_AXIS_SINCE} or later for extra G-code axes (MANUAL_STEPPER … GCODE_AXIS=); Klipper has no G93"),
    ];
    let mut header = Vec::new();
    if extra.is_empty() {
        header.push("; flavour Klipper (3-axis)".to_string());
    } else {
        header.push(format!(
            "; flavour Klipper (extra G-code axes: mainline since {KLIPPER_GCODE_AXIS_SINCE}): this file expects in printer.cfg"
        ));
    }
    for a in &extra {
        let what = if a.rotary {
            "rotary, degrees"
        } else {
            "linear, mm"
        };
        let per_turn = if a.rotary {
            "degrees per motor turn"
        } else {
            "mm per motor turn"
        };
        let lim: String = limits(a)
            .iter()
            .map(|(k, v)| format!(", {k}: {}", num(*v)))
            .collect();
        header.push(format!(
            ";   [manual_stepper {}]   ; axis {}, {what}: step_pin, dir_pin, enable_pin, microsteps, rotation_distance ({per_turn}){lim}",
            stepper_name(a),
            a.name
        ));
        text.push(String::new());
        text.push(format!("[manual_stepper {}]", stepper_name(a)));
        text.push(format!("# axis {}, {what}", a.name));
        for pin in ["step_pin", "dir_pin", "enable_pin"] {
            text.push(format!("{pin}: <your {pin}>"));
        }
        text.push("microsteps: <16>".into());
        text.push(format!("rotation_distance: <{per_turn}>"));
        for (k, v) in limits(a) {
            text.push(format!("{k}: {}", num(v)));
        }
        if a.rotary && !a.limited() {
            text.push("# no position limits: this axis turns without limit and is written unwrapped (Klipper's G92 sets X Y Z E only)".into());
        }
    }
    for a in input.axes.iter().filter(|a| a.is_xyz()) {
        let lim = limits(a);
        if lim.is_empty() {
            continue;
        }
        let t: Vec<String> = lim
            .iter()
            .map(|(k, v)| format!("{k}: {}", num(*v)))
            .collect();
        // (a 3-axis machine's header says only its flavour: nothing there to configure)
        if !extra.is_empty() {
            header.push(format!(
                ";   [stepper_{}] {}   ; axis {} travel, mm",
                a.name.to_ascii_lowercase(),
                t.join(", "),
                a.name
            ));
        }
        text.push(format!(
            "# in your [stepper_{}]: {} (the travel this file was checked against)",
            a.name.to_ascii_lowercase(),
            t.join(", ")
        ));
    }
    if !extra.is_empty() {
        header.push(
            ";   and, before this file's moves (the start G-code or a [delayed_gcode]):".into(),
        );
        text.push(String::new());
        text.push("[delayed_gcode warpslice_axes]".into());
        text.push("# registers the extra axes at start-up".into());
        text.push("initial_duration: 0.1".into());
        text.push("gcode:".into());
        for a in &extra {
            header.push(format!(";   {}", register(a)));
            text.push(format!("    {}", register(a)));
        }
        let corner = format!(
            "INSTANTANEOUS_CORNER_VELOCITY: an extra axis' junction speed defaults to {KLIPPER_EXTRA_AXIS_CORNER_DEFAULT} mm/s (deg/s); this file splits curved moves into short pieces, so set it near the axis' speed on the path or every junction slows the print"
        );
        header.push(format!(";   {corner}"));
        text.push(format!("# {corner}"));
        let rule = "Klipper times a move by its X Y Z length (the largest E or extra-axis change when X Y Z are still, which it runs as an extrude-only move: mind max_extrude_only_velocity and LIMIT_ACCEL): --feed tip computes F for that rule; Klipper has no G93";
        header.push(format!(";   {rule}"));
        text.push(format!("# {rule}"));
        if extra.iter().any(|a| a.rotary && !a.limited()) {
            let g92 = "Klipper's G92 sets X Y Z E only: an unlimited rotary axis is written unwrapped (no resets), so give it no position limits";
            header.push(format!(";   {g92}"));
            text.push(format!("# {g92}"));
        }
    }
    FirmwareConfig {
        flavour: Flavour::Klipper,
        file: "printer.cfg",
        header,
        text: text.join("\n") + "\n",
    }
}
