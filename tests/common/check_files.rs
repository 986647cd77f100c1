//! Hand-built machine G-code files for `warpslice check` (tests/check_gcode.rs natively,
//! tests/check_wasm.rs under wasm): each knows the line of its finding.
#![allow(dead_code)]

/// Lines of text, numbered as an editor shows them.
#[derive(Default)]
pub struct Lines(pub String, pub u64);

impl Lines {
    /// Append a line; its 1-based number.
    pub fn add(&mut self, l: &str) -> u64 {
        self.0.push_str(l);
        self.0.push('\n');
        self.1 += 1;
        self.1
    }
}

/// An RTN (Slicer4RTN) file whose line `bad` turns A to 175°, past the preset's range
/// (±170°, seed 002's `M208 A-170 S1`, `M208 A170 S0`).
pub fn rtn_reach_file() -> (String, u64) {
    let mut g = Lines::default();
    g.add("; hand-written RTN move list");
    g.add("G90");
    g.add("M83");
    g.add("G1 X100 Y100 Z5 A0 F1200");
    // beads 20 mm apart, A turned only in lifted travels (slow enough: at most 85° in a
    // 20 mm move at F300, 1275 °/min < 3600)
    g.add("G1 X100 Y101 Z5 A0 E0.1 F600");
    g.add("G1 Z8 F600");
    g.add("G1 X120 Y100 Z8 A90 F300");
    g.add("G1 Z5 F600");
    g.add("G1 X120 Y101 Z5 A90 E0.1 F600");
    g.add("G1 Z8 F600");
    let bad = g.add("G1 X140 Y100 Z8 A175 F300");
    g.add("G1 X160 Y100 Z8 A100 F300");
    (g.0, bad)
}

/// A B-head file (FullControl style, absolute E) whose line `fast` turns B 60° at F 36000:
/// a pure rotation, so the firmware takes D = 60° at F: B moves at 36000 °/min.
pub fn bhead_speed_file() -> (String, u64) {
    let mut g = Lines::default();
    g.add("; FullControl-style B-axis file");
    g.add("G90");
    g.add("M82");
    g.add("G92 E0");
    g.add("G1 X100 Y100 Z60 B0 F1000");
    g.add("G1 X110 Y100 Z60 B0 E1.0");
    let fast = g.add("G1 B60 F36000");
    g.add("G1 B0 F1000");
    g.add("G1 X100 Y100 Z62");
    (g.0, fast)
}

/// A cartesian pad after `M83` and a lift to Z 5: `layers` layers of 0.2 mm, each `lines`
/// lines 0.45 mm apart from x = `x0` running from y = `y0` to `y1` with `e` mm of filament, each
/// line reached by a lift of 1 mm, a travel and a descent.
pub fn pad(layers: u32, lines: u32, x0: f64, [y0, y1]: [f64; 2], e: f64) -> Lines {
    let mut g = Lines::default();
    g.add("M83");
    g.add("G1 Z5 F600");
    for k in 1..=layers {
        let z = 0.2 * k as f64;
        g.add(";LAYER_CHANGE");
        for i in 0..lines {
            let x = x0 + 0.45 * i as f64;
            g.add(&format!("G1 Z{:.3} F600", z + 1.0));
            g.add(&format!("G1 X{x:.3} Y{y0} F1800"));
            g.add(&format!("G1 Z{z:.3} F600"));
            g.add(&format!("G1 X{x:.3} Y{y1} E{e} F1800"));
        }
    }
    g
}

/// A clean cartesian pad (two layers of lines, F 1800 well under every axis' feed).
pub fn clean_file() -> String {
    let mut g = pad(2, 10, 50.0, [50.0, 60.0], 0.4);
    g.add("G1 Z20 F600");
    g.0
}
