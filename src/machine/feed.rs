//! Feed-rate modes: keep the programmed tool-tip speed whatever the firmware counts as the
//! length of a move.
//!
//! A move of tip length L (mm) at programmed tip feed f (mm/min) should take `T = L / f`
//! minutes. With `D = sqrt(Σ Δaxisᵢ²)` the machine-space length over all axes (mm and degrees
//! mixed, as RepRapFirmware `S0` axes count them) and `D_fw` the length by the output flavour's
//! own rule ([`super::length_rule`]):
//! - [`FeedMode::Tip`] (the default): `F = f · D_fw / L`, so `T = D_fw / F = L / f` on that
//!   firmware, whatever axes move.
//! - [`FeedMode::Xyz`]: the firmware counts only the linear axes and F is the tip feed:
//!   `F = f` (unchanged).
//! - [`FeedMode::AllAxes`]: the firmware divides D by F: `F = D / T = f · D / L`.
//! - [`FeedMode::InverseTime`]: `G93`, F is moves per minute: `F = 1 / T = f / L`.
//!
//! A move with no tip length (a pure rotation, L ≈ 0) keeps `T = D / f`: F = f in tip and
//! all-axes mode and `f / D` in inverse-time mode. A move with nothing to do (D = 0 too) keeps
//! F = f.

pub use crate::emit::FeedMode;

/// In `tip` mode an F within this relative difference of the programmed feed f is written as f:
/// it bounds the speed error this rounding adds (0.1 %, a tenth of the 1 % the tests allow), and
/// keeps the slicer's own F words where the firmware's length is the tip's (X Y Z moves, where
/// only the 3-decimal rounding of the written axes separates the two).
pub const TIP_FEED_SNAP: f64 = 1e-3;

/// The machine-space length the firmware measures between two axis vectors.
pub fn axis_length(from: &[f64], to: &[f64]) -> f64 {
    from.iter()
        .zip(to)
        .map(|(a, b)| (b - a) * (b - a))
        .sum::<f64>()
        .sqrt()
}

/// The output F of a move from `from` to `to` axes with tip length `tip_length` (mm) at
/// programmed tip feed `f` (mm/min); `firmware_length` is the move's length by the flavour's
/// rule (used by [`FeedMode::Tip`]).
pub fn output_feed(
    mode: FeedMode,
    from: &[f64],
    to: &[f64],
    tip_length: f64,
    firmware_length: f64,
    f: f64,
) -> f64 {
    let d = axis_length(from, to);
    let eps = crate::tolerance::LENGTH_EPSILON;
    match mode {
        FeedMode::Tip => {
            let fo = if tip_length > eps && firmware_length > eps {
                f * firmware_length / tip_length
            } else {
                f
            };
            if (fo - f).abs() <= TIP_FEED_SNAP * f {
                f
            } else {
                fo
            }
        }
        FeedMode::Xyz => f,
        FeedMode::AllAxes => {
            if tip_length > eps {
                f * d / tip_length
            } else {
                f
            }
        }
        FeedMode::InverseTime => {
            if tip_length > eps {
                f / tip_length
            } else if d > eps {
                f / d
            } else {
                f
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_move_takes_tip_length_over_feed() {
        // 3 mm of tip at 600 mm/min = 0.005 min; the axes move (3, 0, 0, 4°) → D = 5.
        let (a, b) = ([0.0, 0.0, 0.0, 0.0], [3.0, 0.0, 0.0, 4.0]);
        assert_eq!(output_feed(FeedMode::Xyz, &a, &b, 3.0, 3.0, 600.0), 600.0);
        let f = output_feed(FeedMode::AllAxes, &a, &b, 3.0, 3.0, 600.0);
        assert!((5.0 / f - 0.005).abs() < 1e-15);
        let g = output_feed(FeedMode::InverseTime, &a, &b, 3.0, 3.0, 600.0);
        assert!((1.0 / g - 0.005).abs() < 1e-15);
        // Tip: the firmware counts 2 mm for this move (its own rule) → F = 400, T = 0.005.
        let t = output_feed(FeedMode::Tip, &a, &b, 3.0, 2.0, 600.0);
        assert!((2.0 / t - 0.005).abs() < 1e-15);
        // Pure rotation: 4° at 600 → inverse time 150 per minute; tip keeps F = f.
        let c = [0.0, 0.0, 0.0, 4.0];
        assert_eq!(
            output_feed(FeedMode::InverseTime, &a, &c, 0.0, 4.0, 600.0),
            150.0
        );
        assert_eq!(output_feed(FeedMode::Tip, &a, &c, 0.0, 4.0, 600.0), 600.0);
        // a firmware length within 0.1 % of the tip's keeps the slicer's F
        assert_eq!(
            output_feed(FeedMode::Tip, &a, &b, 3.0, 3.0009, 600.0),
            600.0
        );
        assert!(output_feed(FeedMode::Tip, &a, &b, 3.0, 3.0031, 600.0) > 600.5);
        assert_eq!(FeedMode::parse("tip"), Some(FeedMode::Tip));
        assert_eq!(FeedMode::parse("all-axes"), Some(FeedMode::AllAxes));
        assert_eq!(FeedMode::parse("fast"), None);
    }
}
