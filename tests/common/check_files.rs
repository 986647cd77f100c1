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

// ---- the collision cases of issue 10 §5 (tests/collision_check.rs; the page's fixtures,
// examples/finding_cases.rs) ----

/// A pad of `layers` layers of 0.2 mm, lines along Y from y0 to y1 at x = x0, x0 + 0.45, … <
/// x1, each line printed towards +Y then a travel back; `rot` is appended to every move (the
/// rotary axes).
pub fn rotary_pad(
    g: &mut Lines,
    (x0, x1): (f64, f64),
    (y0, y1): (f64, f64),
    layers: u32,
    rot: &str,
) {
    g.add("M83");
    g.add(";WIDTH:0.45");
    g.add(&format!("G1 Z5{rot}"));
    for k in 1..=layers {
        let z = 0.2 * k as f64;
        g.add(";LAYER_CHANGE");
        let mut x = x0;
        while x < x1 {
            // lifted travel back to the line's start, then print it
            g.add(&format!("G1 Z{:.3}{rot}", z + 1.0));
            g.add(&format!("G1 X{x:.3} Y{y0:.3}{rot}"));
            g.add(&format!("G1 Z{z:.3}{rot}"));
            g.add(&format!("G1 X{x:.3} Y{y1:.3}{rot} E0.5"));
            x += 0.45;
        }
    }
}

/// A clean cartesian print: a pad of 10 layers, then a lift and a travel away.
pub fn clean_pad_case() -> String {
    let mut g = Lines::default();
    rotary_pad(&mut g, (10.0, 20.0), (10.0, 20.0), 10, "");
    g.add("G1 Z10");
    g.add("G1 X40 Y40");
    g.0
}

/// The cartesian pad (top at 2.0 mm) and the nozzle plunged to Z 1 at its middle: the text,
/// the plunge's line and the way back out's (it starts inside the pad).
pub fn plunge_case() -> (String, u64, u64) {
    let mut g = Lines::default();
    rotary_pad(&mut g, (10.0, 20.0), (10.0, 20.0), 10, "");
    g.add("G1 Z10");
    g.add("G1 X15 Y15");
    let plunge = g.add("G1 Z1.0");
    let retreat = g.add("G1 Z10");
    (g.0, plunge, retreat)
}

/// B head (seed 000, r = 46 mm): written X, Z putting the tip at (px, pz) with tilt B
/// (docs/machines.md: X = p_x + r sin B, Z = p_z + r cos B − r).
pub fn bhead_axes(px: f64, pz: f64, b_deg: f64) -> (f64, f64) {
    let (r, b) = (46.0, b_deg.to_radians());
    (px + r * b.sin(), pz + r * b.cos() - r)
}

/// The B head tilted 45° beside a 20 mm wall (fullcontrol-prusa-b).
pub struct WallCase {
    /// The G-code.
    pub text: String,
    /// The approach's line: the tip to x = 57 (6.8 mm from the wall's face), the heater block
    /// and the heat sink across the wall.
    pub approach: u64,
    /// The way back's line.
    pub retreat: u64,
    /// Written X of the approach's end.
    pub x_near: f64,
    /// Written Z of both.
    pub z: f64,
    /// Tilt B, degrees.
    pub b: f64,
}

/// A wall 20 mm high (one bead at x = 50 from y = 20 to 60, 100 layers), then the head tilted
/// to B = −45° (leaning towards −X, the wall) far from it and brought to the tip x = 57,
/// z = 10, and back.
pub fn bhead_wall_case() -> WallCase {
    let mut g = Lines::default();
    g.add("M83");
    g.add(";WIDTH:0.45");
    for k in 1..=100 {
        let z = 0.2 * k as f64;
        g.add(";LAYER_CHANGE");
        g.add(&format!("G1 X50 Y20 Z{z:.3} B0"));
        g.add("G1 X50 Y60 E1");
    }
    g.add("G1 Z40");
    let b = -45.0;
    let (x_far, z) = bhead_axes(80.0, 10.0, b);
    g.add("G1 X80 Y40 Z40 B0");
    g.add(&format!("G1 X{x_far:.3} Y40 Z{z:.3} B{b}"));
    let (x_near, _) = bhead_axes(57.0, 10.0, b);
    let approach = g.add(&format!("G1 X{x_near:.3} Y40 Z{z:.3} B{b}"));
    let retreat = g.add(&format!("G1 X{x_far:.3} Y40 Z{z:.3} B{b}"));
    WallCase {
        text: g.0,
        approach,
        retreat,
        x_near,
        z,
        b,
    }
}

/// The B head lowered to its tip 0.3 mm above the plate at x = `px`, tilted by `b` degrees
/// (fullcontrol-prusa-b): the text and the descent's line.
pub fn bhead_bed_case(px: f64, b: f64) -> (String, u64) {
    let mut g = Lines::default();
    g.add("G1 X100 Y100 Z20 B0");
    let (x, z) = bhead_axes(px, 0.3, b);
    g.add(&format!("G1 X{x:.3} Y100 Z20 B0"));
    let down = g.add(&format!("G1 X{x:.3} Y100 Z{z:.3} B{b}"));
    (g.0, down)
}

/// An RTN rotate-around (rtn-slicer4rtn) beside a pad 6 mm high: A = 179 leans the head to +Y
/// (away from the pad); lifted 1 mm, the turn to A = −179 the long way passes A = 0, the lean
/// to −Y, towards the pad. The text and the lift's, turn's and descent's lines.
pub fn rtn_rotate_around_case() -> (String, u64, u64, u64) {
    let mut g = Lines::default();
    rotary_pad(&mut g, (0.0, 10.0), (0.0, 10.0), 30, " A179"); // top at 6.0 mm, face at y = 10.225
    g.add("G1 Z20 A179");
    g.add("G1 X5 Y12.225 A179");
    g.add("G1 Z2 A179");
    let lift = g.add("G1 Z3 ; rotate-around");
    let turn = g.add("G1 A-179 ; rotate-around");
    let descend = g.add("G1 Z2 ; rotate-around");
    (g.0, lift, turn, descend)
}
