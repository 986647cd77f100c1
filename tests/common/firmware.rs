//! What a firmware does with a machine G-code's feed: each firmware's move-length rule, written
//! for the tests from the firmwares' own documents and sources (facts, not the crate's code:
//! nothing here calls `warpslice::machine`), and a reader of the motion lines with modal F.
//!
//! A firmware times a `G1` as `T = D / F` (F in mm/min, or in its length unit per minute),
//! with D its move length:
//! - **RepRapFirmware 3** (`M584` docs: `R1` creates a rotary axis, `S1` — the default for
//!   rotary axes — makes the feed rate apply to the linear axes only when any moves, as in NIST
//!   RS274NGC; linear axes, X Y Z and those created `R0` such as U V W, are counted): D = the
//!   Euclidean norm of the linear axes' changes when one of them moves, else the norm of the
//!   rotary axes' changes, else |ΔE|.
//! - **Marlin 2.1** (`AXISn_ROTATES`: a rotational axis is left out of the move's length when a
//!   linear axis moves, NIST style; extruder-only moves are timed by E): the same rule.
//! - **Klipper** (`klippy/toolhead.py`, class `Move`: `move_d` is the norm of `axes_d[:3]`, the X
//!   Y Z changes; when it is below 1e-9 the move is "extrude only" and `move_d` is the largest
//!   |change| of `axes_d[3:]`: E and every extra G-code axis): D = √(ΔX² + ΔY² + ΔZ²), else
//!   max(|ΔE|, |Δ extra|).

use std::collections::BTreeMap;

/// The firmwares of the flavours.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Firmware {
    /// RepRapFirmware 3.
    Rrf,
    /// Marlin 2.1.
    Marlin,
    /// Klipper.
    Klipper,
}

impl Firmware {
    /// The `--flavour` name.
    pub fn flavour(self) -> &'static str {
        match self {
            Firmware::Rrf => "reprapfirmware",
            Firmware::Marlin => "marlin",
            Firmware::Klipper => "klipper",
        }
    }

    /// The move length D of a move changing the axes by `delta` (letter → change, mm or
    /// degrees; `rotary` says which letters are rotary) and the filament by `de` (see the
    /// module documentation for the rules).
    pub fn move_length(self, delta: &BTreeMap<char, f64>, rotary: &[char], de: f64) -> f64 {
        let norm = |keep: &dyn Fn(char) -> bool| {
            delta
                .iter()
                .filter(|(c, _)| keep(**c))
                .map(|(_, d)| d * d)
                .sum::<f64>()
                .sqrt()
        };
        match self {
            Firmware::Rrf | Firmware::Marlin => {
                let linear = norm(&|c| !rotary.contains(&c));
                let turning = norm(&|c| rotary.contains(&c));
                if linear > 0.0 {
                    linear
                } else if turning > 0.0 {
                    turning
                } else {
                    de.abs()
                }
            }
            Firmware::Klipper => {
                let xyz = norm(&|c| "XYZ".contains(c));
                if xyz >= 1e-9 {
                    xyz
                } else {
                    delta
                        .iter()
                        .filter(|(c, _)| !"XYZ".contains(**c))
                        .map(|(_, d)| d.abs())
                        .fold(de.abs(), f64::max)
                }
            }
        }
    }
}

/// One motion line: the position after it (every letter seen so far), its filament change, the
/// modal F in force for it, and whether it names every letter of `letters` (a machine line).
#[derive(Clone, Debug)]
pub struct Motion {
    pub line: usize,
    pub pos: BTreeMap<char, f64>,
    pub de: f64,
    pub f: f64,
    pub full: bool,
}

/// The motion lines (`G0`/`G1`) of `text` with modal F, `G92` renames and `M82`/`M83` E modes.
pub fn motions(text: &str, letters: &[char]) -> Vec<Motion> {
    let mut pos: BTreeMap<char, f64> = BTreeMap::new();
    let (mut e, mut relative, mut f) = (0.0, false, 0.0);
    let mut out = Vec::new();
    for (i, raw) in text.lines().enumerate() {
        let code = raw.split(';').next().unwrap_or("");
        let mut words = code.split_whitespace();
        let Some(cmd) = words.next() else { continue };
        let words: Vec<(char, f64)> = words
            .map(|w| {
                let mut c = w.chars();
                let letter = c.next().unwrap().to_ascii_uppercase();
                let v: f64 = c
                    .as_str()
                    .parse()
                    .unwrap_or_else(|_| panic!("line {}: bad number in '{w}'", i + 1));
                (letter, v)
            })
            .collect();
        match cmd {
            "M82" => relative = false,
            "M83" => relative = true,
            "G92" => {
                for (c, v) in &words {
                    if *c == 'E' {
                        e = *v;
                    } else {
                        pos.insert(*c, *v);
                    }
                }
            }
            "G0" | "G1" => {
                let mut de = 0.0;
                let mut seen = 0;
                for (c, v) in &words {
                    match c {
                        'F' => f = *v,
                        'E' => {
                            de = if relative { *v } else { v - e };
                            e = if relative { e + v } else { *v };
                        }
                        _ => {
                            if letters.contains(c) {
                                seen += 1;
                            }
                            pos.insert(*c, *v);
                        }
                    }
                }
                out.push(Motion {
                    line: i + 1,
                    pos: pos.clone(),
                    de,
                    f,
                    full: seen == letters.len(),
                });
            }
            _ => {}
        }
    }
    out
}

#[cfg(test)]
mod own {
    use super::*;

    #[test]
    fn the_rules_differ_where_the_firmwares_do() {
        let d: BTreeMap<char, f64> = [('X', 3.0), ('U', 4.0), ('A', 90.0)].into_iter().collect();
        assert_eq!(Firmware::Rrf.move_length(&d, &['A'], 0.1), 5.0);
        assert_eq!(Firmware::Klipper.move_length(&d, &['A'], 0.1), 3.0);
        let r: BTreeMap<char, f64> = [('X', 0.0), ('A', -30.0), ('U', 4.0)].into_iter().collect();
        assert_eq!(Firmware::Marlin.move_length(&r, &['A'], 0.1), 4.0);
        assert_eq!(Firmware::Klipper.move_length(&r, &['A'], 0.1), 30.0);
    }
}
