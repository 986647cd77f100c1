//! A G-code reader of the tests' own, sharing nothing with `warpslice::gcode`: it reads a
//! slicer's file and warpslice's 3-axis output the way a firmware would (RepRapFirmware /
//! Marlin semantics of G0/G1, G90/G91, M82/M83, G92, G10/G11, G20/G21, G28), and records every
//! move with the `;TYPE:` in force. Arcs and inches are refused (warpslice's slicer settings
//! forbid arcs; inches never occur in the three slicers' files).

use glam::DVec3;

/// The class a `;TYPE:` comment gives the moves after it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Typed {
    /// No `;TYPE:` comment so far (Slic3r's files have none).
    Untyped,
    /// Skirt, brim, wipe or prime tower, the start G-code's custom lines: printed flat.
    Flat,
    /// Anything else the slicer names (walls, infill, support, …): the object.
    Object,
}

impl Typed {
    /// The class of a `;TYPE:` name of PrusaSlicer (`Skirt/Brim`, `Wipe tower`, `Custom`, …)
    /// or CuraEngine (`SKIRT`, `PRIME-TOWER`, …).
    pub fn of(name: &str) -> Typed {
        let n = name.trim().to_ascii_lowercase();
        let flat = ["skirt", "brim", "wipe", "prime", "custom", "purge"];
        if flat.iter().any(|w| n.contains(w)) {
            Typed::Flat
        } else {
            Typed::Object
        }
    }
}

/// One move (G0/G1), or a firmware retraction (G10/G11: `fw` set, no motion).
#[derive(Clone, Copy, Debug)]
pub struct Move {
    /// 1-based line number.
    pub line: usize,
    pub from: DVec3,
    pub to: DVec3,
    /// E added by this move (mm of filament; negative for a retraction).
    pub e: f64,
    pub typed: Typed,
    /// `Some(true)` for G10 (firmware retract), `Some(false)` for G11.
    pub fw: Option<bool>,
    /// The line names no axis, only E (and F): a retraction or its push-back.
    pub e_only: bool,
}

impl Move {
    /// Whether the move deposits material: E grows while the nozzle moves.
    pub fn extrudes(&self) -> bool {
        self.e > 0.0 && self.to != self.from
    }
    /// Whether the nozzle moves.
    pub fn moves(&self) -> bool {
        self.to != self.from
    }
    pub fn length(&self) -> f64 {
        (self.to - self.from).length()
    }
    pub fn at(&self, t: f64) -> DVec3 {
        self.from.lerp(self.to, t)
    }
}

/// A file as read.
#[derive(Debug, Default)]
pub struct Written {
    pub moves: Vec<Move>,
    /// `; warpslice model_to_output = dx dy dz`, if the file has it.
    pub model_to_output: Option<DVec3>,
    /// Whether any `;TYPE:` comment occurs.
    pub typed: bool,
}

impl Written {
    /// E over the whole file: (net, the sum of the positive steps), mm of filament. Every move
    /// counts, whatever other axes it moves (a machine file's rotary-only pieces too).
    pub fn e_totals(&self) -> (f64, f64) {
        let net = self.moves.iter().map(|m| m.e).sum();
        let pos = self.moves.iter().map(|m| m.e.max(0.0)).sum();
        (net, pos)
    }

    /// The positive E steps of the lines that name an axis (not `G1 E…` alone), mm: what the
    /// file deposits, without the push-backs after retractions, whose number follows the
    /// travels a file plans (a lifted travel gets a retraction of the unwarp's own).
    pub fn extruded_by_moves(&self) -> f64 {
        self.moves
            .iter()
            .filter(|m| !m.e_only)
            .map(|m| m.e.max(0.0))
            .sum()
    }

    /// The extrusions (see [`Move::extrudes`]).
    pub fn extrusions(&self) -> impl Iterator<Item = &Move> {
        self.moves.iter().filter(|m| m.extrudes())
    }
}

fn number(s: &str, line: usize) -> Result<f64, String> {
    s.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| format!("line {line}: {s:?} is not a number"))
}

/// Read a whole file.
pub fn read(bytes: &[u8]) -> Result<Written, String> {
    let text = std::str::from_utf8(bytes).map_err(|e| format!("not UTF-8: {e}"))?;
    let mut w = Written::default();
    let mut pos = DVec3::ZERO;
    let (mut rel_xyz, mut rel_e, mut e_pos) = (false, false, 0.0);
    let mut typed = Typed::Untyped;
    for (i, raw) in text.lines().enumerate() {
        let n = i + 1;
        let line = raw.trim();
        if let Some(r) = line.strip_prefix("; warpslice model_to_output =") {
            let v = r
                .split_whitespace()
                .map(|s| number(s, n))
                .collect::<Result<Vec<f64>, String>>()?;
            if v.len() != 3 {
                return Err(format!("line {n}: model_to_output has {} numbers", v.len()));
            }
            w.model_to_output = Some(DVec3::new(v[0], v[1], v[2]));
            continue;
        }
        // Bambu Studio and OrcaSlicer label features `; FEATURE: Outer wall`
        let feature = line
            .strip_prefix(';')
            .and_then(|c| c.trim_start().strip_prefix("FEATURE:"));
        if let Some(t) = line.strip_prefix(";TYPE:").or(feature) {
            typed = Typed::of(t);
            w.typed = true;
            continue;
        }
        let code = line.split(';').next().unwrap_or("").trim();
        let mut words = code.split_whitespace();
        let Some(cmd) = words.next() else { continue };
        let cmd = cmd.to_ascii_uppercase();
        let cmd = match cmd.as_str() {
            "G00" => "G0",
            "G01" => "G1",
            c => c,
        };
        match cmd {
            "G90" => (rel_xyz, rel_e) = (false, false),
            "G91" => (rel_xyz, rel_e) = (true, true),
            "M82" => rel_e = false,
            "M83" => rel_e = true,
            "G20" => return Err(format!("line {n}: G20 (inches)")),
            "G2" | "G3" | "G02" | "G03" => return Err(format!("line {n}: an arc ({cmd})")),
            "G28" => {
                let axes: Vec<char> = words.filter_map(|w| w.chars().next()).collect();
                let all = axes.is_empty();
                for (k, c) in ['X', 'Y', 'Z'].into_iter().enumerate() {
                    if all || axes.contains(&c) {
                        pos[k] = 0.0;
                    }
                }
            }
            "G92" => {
                for wd in words {
                    let (k, v) = wd.split_at(1);
                    let v = number(v, n)?;
                    match k.to_ascii_uppercase().as_str() {
                        "E" => e_pos = v,
                        "X" => pos.x = v,
                        "Y" => pos.y = v,
                        "Z" => pos.z = v,
                        _ => {}
                    }
                }
            }
            "G10" | "G11" if !code.contains('P') && !code.contains('L') => w.moves.push(Move {
                line: n,
                from: pos,
                to: pos,
                e: 0.0,
                typed,
                fw: Some(cmd == "G10"),
                e_only: false,
            }),
            "G0" | "G1" => {
                let (mut to, mut e) = (pos, None);
                let mut axis_word = false;
                for wd in words {
                    let (k, v) = wd.split_at(1);
                    let k = k.to_ascii_uppercase();
                    axis_word |= k != "E" && k != "F";
                    let axis = match k.as_str() {
                        "X" => Some(0),
                        "Y" => Some(1),
                        "Z" => Some(2),
                        "E" => {
                            e = Some(number(v, n)?);
                            None
                        }
                        _ => None,
                    };
                    if let Some(a) = axis {
                        let v = number(v, n)?;
                        to[a] = if rel_xyz { pos[a] + v } else { v };
                    }
                }
                let de = match e {
                    Some(v) if rel_e => v,
                    Some(v) => v - e_pos,
                    None => 0.0,
                };
                e_pos += de;
                w.moves.push(Move {
                    line: n,
                    from: pos,
                    to,
                    e: de,
                    typed,
                    fw: None,
                    e_only: !axis_word && e.is_some(),
                });
                pos = to;
            }
            _ => {}
        }
    }
    Ok(w)
}
