//! Planar G-code in PrusaSlicer's dialect (what [`crate::gcode`]'s reader and the unwarp read):
//! start G-code with temperatures, `;LAYER_CHANGE` / `;Z:z` / `;HEIGHT:h` at every layer,
//! `;TYPE:` before every change of feature (PrusaSlicer's labels), `G1` moves, retractions,
//! end G-code.
//!
//! # E
//! A line of length L at width w and layer height h deposits the cross-section of
//! PrusaSlicer's flow model, a rectangle with semicircular ends
//! (`Flow::mm3_per_mm`: `A = (w − h)·h + π·(h/2)²`, [`Settings::line_area`]); the filament
//! fed is `E = A·L / (π·d²/4)` mm (d the filament diameter). Relative E (`M83`) by default;
//! with `use_relative_e_distances = false`, absolute E (`M82`) reset by `G92 E0` at every
//! layer change, as PrusaSlicer does.
//!
//! # Units
//! X Y Z mm (3 decimals), E mm (5 decimals), F mm/min (the settings' mm/s × 60).

use std::fmt::Write as _;

use super::order::RETRACT_BEFORE_TRAVEL;
use super::{Path, Role, Settings};

/// Writes one G-code file; tracks the nozzle, E and what was extruded.
pub struct Writer {
    /// The settings (a copy: a [`super::slicing::Slicing`] keeps its writer between layers).
    s: Settings,
    out: String,
    at: Option<[f64; 2]>,
    z: f64,
    e_abs: f64,
    retracted: bool,
    role: Option<Role>,
    /// Filament fed by extruding moves, mm (retractions and push-backs excluded).
    pub filament_mm: f64,
    /// Number of retractions written.
    pub retractions: usize,
}

/// `v` with `decimals` decimals and no negative zero.
fn num(v: f64, decimals: usize) -> String {
    let t = format!("{v:.decimals$}");
    if t.trim_start_matches('-')
        .trim_matches(['0', '.'])
        .is_empty()
    {
        t.trim_start_matches('-').to_string()
    } else {
        t
    }
}

impl Writer {
    /// A writer with the start G-code written.
    pub fn new(s: &Settings, header: &str) -> Writer {
        let mut w = Writer {
            s: *s,
            out: String::with_capacity(1 << 16),
            at: None,
            z: 0.0,
            e_abs: 0.0,
            retracted: false,
            role: None,
            filament_mm: 0.0,
            retractions: 0,
        };
        w.start(header);
        w
    }

    fn line(&mut self, text: &str) {
        self.out.push_str(text);
        self.out.push('\n');
    }

    fn start(&mut self, header: &str) {
        let s = self.s;
        for l in header.lines() {
            let _ = writeln!(self.out, "; {l}");
        }
        self.line("M107");
        if s.bed_temperature > 0.0 {
            let _ = writeln!(self.out, "M140 S{}", num(s.bed_temperature, 0));
        }
        let _ = writeln!(self.out, "M104 S{}", num(s.temperature, 0));
        if s.bed_temperature > 0.0 {
            let _ = writeln!(self.out, "M190 S{}", num(s.bed_temperature, 0));
        }
        let _ = writeln!(self.out, "M109 S{}", num(s.temperature, 0));
        self.line("G21 ; mm");
        self.line("G28 ; home");
        self.line("G90 ; absolute XYZ");
        self.line(if s.use_relative_e_distances {
            "M83 ; relative E"
        } else {
            "M82 ; absolute E"
        });
        self.line("G92 E0");
    }

    /// Start a layer whose top is at `z` and whose height is `h`.
    pub fn layer(&mut self, z: f64, h: f64) {
        if self.at.is_some() {
            self.retract();
        }
        self.line(";LAYER_CHANGE");
        let _ = writeln!(self.out, ";Z:{}", num(z, 3));
        let _ = writeln!(self.out, ";HEIGHT:{}", num(h, 3));
        if !self.s.use_relative_e_distances {
            // a retracted filament stays pulled back by retract_length across the reset
            self.e_abs = if self.retracted {
                -self.s.retract_length
            } else {
                0.0
            };
            let _ = writeln!(self.out, "G92 E{}", num(self.e_abs, 5));
        }
        let _ = writeln!(
            self.out,
            "G1 Z{} F{}",
            num(z, 3),
            num(self.s.travel_speed * 60.0, 0)
        );
        self.z = z;
    }

    fn e_word(&mut self, de: f64) -> String {
        if self.s.use_relative_e_distances {
            num(de, 5)
        } else {
            self.e_abs += de;
            num(self.e_abs, 5)
        }
    }

    fn retract(&mut self) {
        if self.retracted || self.s.retract_length <= 0.0 {
            return;
        }
        let e = self.e_word(-self.s.retract_length);
        let f = num(self.s.retract_speed * 60.0, 0);
        let _ = writeln!(self.out, "G1 E{e} F{f}");
        self.retracted = true;
        self.retractions += 1;
    }

    fn unretract(&mut self) {
        if !self.retracted {
            return;
        }
        let e = self.e_word(self.s.retract_length);
        let f = num(self.s.retract_speed * 60.0, 0);
        let _ = writeln!(self.out, "G1 E{e} F{f}");
        self.retracted = false;
    }

    /// Travel through `via` (then [`Writer::path`] travels on to its first point); each hop
    /// retracts as a travel of its length would.
    pub fn travel_via(&mut self, via: &[[f64; 2]]) {
        for &p in via {
            self.travel(p);
        }
    }

    /// Where the nozzle is (`None` before the first move).
    pub fn position(&self) -> Option<[f64; 2]> {
        self.at
    }

    fn travel(&mut self, to: [f64; 2]) {
        let far = match self.at {
            None => true,
            Some(p) => {
                ((p[0] - to[0]).powi(2) + (p[1] - to[1]).powi(2)).sqrt() > RETRACT_BEFORE_TRAVEL
            }
        };
        if far {
            self.retract();
        }
        if self.at != Some(to) {
            let _ = writeln!(
                self.out,
                "G1 X{} Y{} F{}",
                num(to[0], 3),
                num(to[1], 3),
                num(self.s.travel_speed * 60.0, 0)
            );
        }
        self.at = Some(to);
    }

    /// Print `path` (ready to print: a loop already closed) at layer height `h`, speed `v` mm/s.
    pub fn path(&mut self, path: &Path, h: f64, v: f64) {
        let Some(&first) = path.points.first() else {
            return;
        };
        self.travel(first);
        self.unretract();
        if self.role != Some(path.role) {
            let _ = writeln!(self.out, ";TYPE:{}", path.role.label());
            self.role = Some(path.role);
        }
        let per_mm = self.s.line_area(h) / self.s.filament_area();
        let f = num(v * 60.0, 0);
        let mut first_move = true;
        for (i, &p) in path.points.iter().enumerate().skip(1) {
            let Some(a) = self.at else { break };
            let len = ((p[0] - a[0]).powi(2) + (p[1] - a[1]).powi(2)).sqrt();
            if len == 0.0 {
                continue;
            }
            let de = match (path.section.get(i - 1), path.section.get(i)) {
                (Some(s0), Some(s1)) => (s0 + s1) / 2.0 / self.s.filament_area() * len,
                _ => per_mm * len,
            };
            self.filament_mm += de;
            let e = self.e_word(de);
            let _ = write!(self.out, "G1 X{} Y{} E{e}", num(p[0], 3), num(p[1], 3));
            if first_move {
                let _ = write!(self.out, " F{f}");
                first_move = false;
            }
            self.out.push('\n');
            self.at = Some(p);
        }
    }

    /// Write the end G-code and return the file.
    pub fn finish(mut self) -> String {
        self.retract();
        self.line(";TYPE:Custom");
        let _ = writeln!(
            self.out,
            "G1 Z{} F{}",
            num(self.z + 10.0, 3),
            num(self.s.travel_speed * 60.0, 0)
        );
        self.line("M104 S0");
        self.line("M140 S0");
        self.line("M107");
        self.line("M84");
        self.out
    }
}
