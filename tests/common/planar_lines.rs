//! The object's extrusions of a built-in slicer's planar file, as the planar tests read them:
//! each extruding move (tests/common/written.rs, the tests' own G-code reader) with its layer,
//! ends, deposited volume and the `;TYPE:` in force. Shared by `planar_thin_walls.rs` and
//! `planar_bridges.rs` (include with `#[path]` beside `written.rs` as `written`).

use super::written;

/// One extruding move of the object: its layer (0-based), ends and deposited volume (filament
/// length × cross-section, mm³), with the `;TYPE:` in force.
pub struct Line {
    pub layer: usize,
    pub from: [f64; 2],
    pub to: [f64; 2],
    pub volume: f64,
    pub role: String,
}

impl Line {
    /// Its length in XY, mm.
    pub fn length(&self) -> f64 {
        (self.to[0] - self.from[0]).hypot(self.to[1] - self.from[1])
    }
    /// Distance from `p` to the line in XY, mm.
    #[allow(dead_code)]
    pub fn distance(&self, p: [f64; 2]) -> f64 {
        let d = [self.to[0] - self.from[0], self.to[1] - self.from[1]];
        let l2 = d[0] * d[0] + d[1] * d[1];
        let t = if l2 > 0.0 {
            (((p[0] - self.from[0]) * d[0] + (p[1] - self.from[1]) * d[1]) / l2).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (self.from[0] + t * d[0] - p[0]).hypot(self.from[1] + t * d[1] - p[1])
    }
}

/// The object's extrusions of `gcode`, layers `h` mm high (the first too), filament `filament`
/// mm across.
pub fn lines(gcode: &str, h: f64, filament: f64) -> Vec<Line> {
    let mut roles = vec![String::new()];
    let mut now = String::new();
    for l in gcode.lines() {
        if let Some(t) = l.trim().strip_prefix(";TYPE:") {
            now = t.trim().to_string();
        }
        roles.push(now.clone());
    }
    let w = written::read(gcode.as_bytes()).unwrap();
    let area = std::f64::consts::PI * filament * filament / 4.0;
    w.extrusions()
        .filter(|m| m.typed == written::Typed::Object && !m.e_only)
        .map(|m| Line {
            layer: (m.to.z / h).round() as usize - 1,
            from: [m.from.x, m.from.y],
            to: [m.to.x, m.to.y],
            volume: m.e * area,
            role: roles[m.line].clone(),
        })
        .collect()
}
