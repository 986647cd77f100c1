//! Does the file end the print? A G-code cut short (a failed copy or download, a slicer killed
//! while writing) prints most of the part and leaves the heaters on. Pass 1 looks for what
//! every slicer's end G-code does after the last layer, and the unwarp warns when none of it
//! comes after the warped region ([`super::Registration::end_gcode_missing`]).
//!
//! **What counts as an end** (any one line after the region's last line):
//! - a heater turned off: `M104`, `M109`, `M140` or `M190` with `S0` (PrusaSlicer's, Slic3r's
//!   and CuraEngine's default end G-code all start with `M104 S0`);
//! - the motors switched off: `M84` or `M18` (all three defaults end with `M84`);
//! - a firmware macro, a first word of letters, digits and at least one underscore, any case
//!   (`END_PRINT`, `print_end`: Klipper users' end G-code is often only that).
//!
//! Conservative on purpose: a file whose end G-code does any of these is not warned about, even
//! if it was cut after that line; an end G-code that does none of them (heaters left on on
//! purpose) is warned about, which is the point. Comments do not count: slicers write their
//! statistics and configuration as comments after the end G-code whatever it holds, and a file
//! cut inside the object has none of the lines above after its last extrusion.

/// Whether the line (raw bytes, without terminator) is one of the end G-code's lines above.
pub fn ends_print(raw: &[u8]) -> bool {
    let code = raw.split(|&b| b == b';').next().unwrap_or(&[]);
    let text = String::from_utf8_lossy(code);
    let mut words = text.split_whitespace();
    let Some(first) = words.next() else {
        return false;
    };
    let first = first.to_ascii_uppercase();
    // an optional line number
    let (first, mut words): (String, Vec<&str>) = if first.starts_with('N')
        && first.len() > 1
        && first[1..].bytes().all(|b| b.is_ascii_digit())
    {
        match words.next() {
            Some(w) => (w.to_ascii_uppercase(), words.collect()),
            None => return false,
        }
    } else {
        (first, words.collect())
    };
    match first.as_str() {
        "M84" | "M18" => true,
        "M104" | "M109" | "M140" | "M190" => {
            words.retain(|w| w.len() > 1 && w.as_bytes()[0].eq_ignore_ascii_case(&b'S'));
            words
                .iter()
                .any(|w| w[1..].parse::<f64>().is_ok_and(|v| v == 0.0))
        }
        m => {
            m.contains('_')
                && m.as_bytes()[0].is_ascii_uppercase()
                && m.bytes()
                    .all(|b| b.is_ascii_uppercase() || b.is_ascii_digit() || b == b'_')
        } // (`first` is upper-cased: Klipper's commands and macros are case-insensitive)
    }
}

#[cfg(test)]
mod tests {
    use super::ends_print;

    #[test]
    fn the_three_slicers_default_end_lines_end_the_print() {
        for l in [
            "M104 S0 ; turn off temperature",
            "M140 S0",
            "M84",
            "N12 M18",
            "m104 s0",
            "M109 S0.0",
            "END_PRINT",
            "PRINT_END EXTRUDER=0",
            "end_print",
        ] {
            assert!(ends_print(l.as_bytes()), "{l}");
        }
        for l in [
            "M104 S200",
            "M107",
            "G28 X0",
            "; M84 in a comment",
            "M117 Done",
            "G1 X0 Y200",
            "",
        ] {
            assert!(!ends_print(l.as_bytes()), "{l}");
        }
    }
}
