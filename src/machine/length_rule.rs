//! How a firmware measures the length of a move: the distance it divides by F to time the move.
//!
//! A firmware plans a `G1` of axis changes `Δᵢ` (mm for linear axes, degrees for rotary ones)
//! and filament `ΔE` at feed F (mm/min, or degrees/min) as taking `T = D / F` minutes, where D is
//! its own move length. Two rules are in use (facts from the firmwares' documents and sources):
//!
//! - [`LengthRule::Nist`] — NIST RS274/NGC §2.1.2.5 as RepRapFirmware 3 (rotary axes created
//!   with `M584 … R1 S1`, linear ones `R0`, including U V W) and Marlin 2.1 (`AXISn_ROTATES`)
//!   apply it: `D = √(Σ_linear Δᵢ²)` when any linear axis moves, else `D = √(Σ_rotary Δᵢ²)`
//!   when a rotary axis moves, else `D = |ΔE|` (an extruder-only move).
//! - [`LengthRule::KlipperXyz`] — Klipper's toolhead (`toolhead.py`, mainline since the extra
//!   `GCODE_AXIS` axes of 2025-05): `D = √(ΔX² + ΔY² + ΔZ²)`; when that is (below 1e-9) zero,
//!   `D = max(|ΔE|, |Δ extra axis|…)` — the largest change of E and of every other G-code axis.
//!   Klipper's X Y Z are the axes lettered X, Y, Z; every other letter is an extra axis
//!   (`MANUAL_STEPPER … GCODE_AXIS=`), linear or rotary alike.
//!
//! [`super::feed`] uses the rule of the output's flavour for `--feed tip`: `F = f · D / L` for a
//! move of tip length L at programmed tip feed f, so that `T = D / F = L / f`.

use super::AxisLimit;

/// Below this XYZ length (mm) Klipper takes a move for one without XYZ motion (its toolhead's
/// `move_d < .000000001` test).
pub const KLIPPER_XYZ_STILL_MM: f64 = 1e-9;

/// A firmware's move-length rule (see the module documentation).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum LengthRule {
    /// RepRapFirmware 3 (`S1` rotary axes) and Marlin 2.1 (`AXISn_ROTATES`): the linear axes'
    /// norm when any linear axis moves, else the rotary axes' norm, else |ΔE|.
    Nist,
    /// Klipper: the X Y Z norm, else the largest |Δ| of E and the extra axes.
    KlipperXyz,
}

impl LengthRule {
    /// The move length D (mm or degrees, as the firmware counts it) from axes `from` to `to`
    /// (machine order, the values written to the file) with filament change `de` (mm).
    pub fn length(self, limits: &[AxisLimit], from: &[f64], to: &[f64], de: f64) -> f64 {
        let deltas = limits
            .iter()
            .zip(from.iter().zip(to))
            .map(|(l, (a, b))| (l, b - a));
        match self {
            LengthRule::Nist => {
                let norm = |rotary: bool| {
                    deltas
                        .clone()
                        .filter(|(l, _)| l.rotary == rotary)
                        .map(|(_, d)| d * d)
                        .sum::<f64>()
                        .sqrt()
                };
                let linear = norm(false);
                if linear > 0.0 {
                    return linear;
                }
                let rotary = norm(true);
                if rotary > 0.0 {
                    rotary
                } else {
                    de.abs()
                }
            }
            LengthRule::KlipperXyz => {
                let is_xyz = |l: &AxisLimit| ["X", "Y", "Z"].contains(&l.name.as_str());
                let xyz = deltas
                    .clone()
                    .filter(|(l, _)| is_xyz(l))
                    .map(|(_, d)| d * d)
                    .sum::<f64>()
                    .sqrt();
                if xyz >= KLIPPER_XYZ_STILL_MM {
                    return xyz;
                }
                deltas
                    .filter(|(l, _)| !is_xyz(l))
                    .map(|(_, d)| d.abs())
                    .fold(de.abs(), f64::max)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn axes() -> Vec<AxisLimit> {
        vec![
            AxisLimit::linear("X"),
            AxisLimit::linear("Y"),
            AxisLimit::linear("Z"),
            AxisLimit::linear("U"),
            AxisLimit::rotary("A", -180.0, 180.0),
        ]
    }

    #[test]
    fn nist_counts_linear_axes_u_included_and_rotary_only_when_they_move_alone() {
        let l = axes();
        let o = [0.0; 5];
        // X 3, U 4, A 90°: the linear norm 5 (U counted, A left out)
        let d = LengthRule::Nist.length(&l, &o, &[3.0, 0.0, 0.0, 4.0, 90.0], 0.1);
        assert_eq!(d, 5.0);
        // A alone
        assert_eq!(
            LengthRule::Nist.length(&l, &o, &[0.0, 0.0, 0.0, 0.0, -30.0], 0.1),
            30.0
        );
        // E alone
        assert_eq!(LengthRule::Nist.length(&l, &o, &o, -0.8), 0.8);
    }

    #[test]
    fn klipper_counts_xyz_and_else_the_largest_extra_change() {
        let l = axes();
        let o = [0.0; 5];
        // U is an extra axis for Klipper: X 3, U 4 → 3
        let d = LengthRule::KlipperXyz.length(&l, &o, &[3.0, 0.0, 0.0, 4.0, 90.0], 0.1);
        assert_eq!(d, 3.0);
        // XYZ still: max(|ΔU|, |ΔA|, |ΔE|)
        let d = LengthRule::KlipperXyz.length(&l, &o, &[0.0, 0.0, 0.0, 4.0, -30.0], 0.1);
        assert_eq!(d, 30.0);
        let d = LengthRule::KlipperXyz.length(&l, &o, &[0.0, 0.0, 0.0, 0.0, 0.5], 2.0);
        assert_eq!(d, 2.0);
    }
}
