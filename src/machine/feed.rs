//! Feed-rate modes: keep the programmed tool-tip speed whatever the firmware counts as the
//! length of a move.
//!
//! A move of tip length L (mm) at programmed tip feed f (mm/min) should take `T = L / f`
//! minutes. With `D = sqrt(Σ Δaxisᵢ²)` the machine-space length over all axes (mm and degrees
//! mixed, as RepRapFirmware `S0` axes count them) and `D_fw` the length by the output flavour's
//! own rule ([`super::length_rule`]):
//! - [`FeedMode::Tip`] (the default): `F = f · D_fw / L`, so `T = D_fw / F = L / f` on that
//!   firmware, whatever axes move — unless an axis would then exceed its largest feed (the
//!   machine file's `max_feed`; seed 001 §4.8: the triple-Z bed's three Z motors at
//!   1900 mm/min): with `T_axes = maxᵢ |Δᵢ| / max_feedᵢ` ([`fastest`]) the move takes
//!   `T = max(L / f, T_axes)` and `F = D_fw / T` (rounded down to the written 0.001 mm/min),
//!   so the limiting axis runs at its limit and no axis beyond it; such a move is reported as
//!   slowed ([`Feed::slowed`]).
//! - [`FeedMode::Xyz`]: the firmware counts only the linear axes and F is the tip feed:
//!   `F = f` (unchanged).
//! - [`FeedMode::AllAxes`]: the firmware divides D by F: `F = D / T = f · D / L`.
//! - [`FeedMode::InverseTime`]: `G93`, F is moves per minute: `F = 1 / T = f / L`.
//!
//! Only `tip` lowers F for the axes' limits; in the other modes F keeps its definition and the
//! firmware slows a move an axis cannot follow (the report estimates it, [`super::speed`]).
//!
//! ## A move without tip motion (a reorientation in place)
//! When the tip moves less than [`NO_TIP_MOTION_MM`] (a pure rotation; at a cone's apex the
//! RTN/RotBot reorientations move it ~1e-8 mm of kinematics noise, and `f · D / L` made feeds
//! like F5·10¹²) the move has no tip time. It is timed by its axes at their largest feeds
//! (the machine file's `max_feed`, °/min for a rotary axis, mm/min for a linear one):
//! `T = T_axes = maxᵢ |Δᵢ| / max_feedᵢ` over the written (rounded) axis changes, so the
//! slowest axis runs at its limit. Then F = D_fw / T (tip), D / T (all-axes), 1 / T
//! (inverse-time); xyz keeps F = f. Where no axis that moves has a finite `max_feed`
//! (`T_axes = 0`), `T = D / f` as before: F = f in tip and all-axes mode and `f / D` in
//! inverse-time mode. A move with nothing to do (D = 0 too) keeps F = f.

pub use crate::emit::FeedMode;

/// In `tip` mode an F within this relative difference of the programmed feed f is written as f:
/// it bounds the speed error this rounding adds (0.1 %, a tenth of the 1 % the tests allow), and
/// keeps the slicer's own F words where the firmware's length is the tip's (X Y Z moves, where
/// only the 3-decimal rounding of the written axes separates the two).
pub const TIP_FEED_SNAP: f64 = 1e-3;

/// A move whose tip travels less than this (mm) has no tip time: it is timed by its axes
/// ([`fastest`]), not by `f · D / L`. It bounds the tip motion a reorientation may have and
/// still be timed as one: half the written 0.001 mm step, so no file can show that motion
/// (an in-place reorientation's tip moves ~1e-8 mm, kinematics noise).
pub const NO_TIP_MOTION_MM: f64 = 5e-4;

/// The shortest time the axes allow a move: `maxᵢ |Δᵢ| / max_feedᵢ` (minutes) and the axis
/// `i` of that maximum (`None` when no moving axis has a finite largest feed: time 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Fastest {
    /// Minutes.
    pub minutes: f64,
    /// The axis (machine order) that sets it.
    pub axis: Option<usize>,
}

/// [`Fastest`] of a move from `from` to `to` (the values the firmware reads) for axes with
/// largest feeds `max_feed` (mm/min or °/min; `+inf`: no limit).
pub fn fastest(max_feed: &[f64], from: &[f64], to: &[f64]) -> Fastest {
    let mut best = Fastest {
        minutes: 0.0,
        axis: None,
    };
    for (i, ((a, b), m)) in from.iter().zip(to).zip(max_feed).enumerate() {
        let t = (b - a).abs() / m;
        if t > best.minutes {
            best = Fastest {
                minutes: t,
                axis: Some(i),
            };
        }
    }
    best
}

/// One move for [`output_feed`].
#[derive(Clone, Copy, Debug)]
pub struct FeedMove<'a> {
    /// Axes before the move (machine order).
    pub from: &'a [f64],
    /// Axes after it.
    pub to: &'a [f64],
    /// The tip's travel L, mm.
    pub tip_length: f64,
    /// The move's length by the flavour's rule, D_fw (used by [`FeedMode::Tip`]).
    pub firmware_length: f64,
    /// The programmed tip feed f, mm/min.
    pub f: f64,
    /// The shortest time its axes allow ([`fastest`], over the written values).
    pub fastest: Fastest,
}

/// The F to write for a move, and whether an axis' largest feed lowered it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Feed {
    /// The F to write (mm/min, or moves per minute in inverse time).
    pub f: f64,
    /// `tip` mode: the axis (machine order) whose `max_feed` lowered F below the tip feed's,
    /// and the minutes this adds to the move (`T_axes − L / f`).
    pub slowed: Option<(usize, f64)>,
}

/// `v` rounded down to the written F's 0.001 mm/min ([`crate::gcode::write::FEED_DECIMALS`]):
/// a feed lowered to an axis' limit stays at or below it once written.
fn floor_written(v: f64) -> f64 {
    let k = 10f64.powi(crate::gcode::write::FEED_DECIMALS as i32);
    (v * k).floor() / k
}

/// The machine-space length the firmware measures between two axis vectors.
pub fn axis_length(from: &[f64], to: &[f64]) -> f64 {
    from.iter()
        .zip(to)
        .map(|(a, b)| (b - a) * (b - a))
        .sum::<f64>()
        .sqrt()
}

/// The output F of move `m` in feed mode `mode` (see the module documentation).
pub fn output_feed(mode: FeedMode, m: &FeedMove) -> Feed {
    let FeedMove {
        from,
        to,
        tip_length,
        firmware_length,
        f,
        fastest,
    } = *m;
    let d = axis_length(from, to);
    let eps = crate::tolerance::LENGTH_EPSILON;
    // a reorientation in place, timed by its axes at their largest feeds
    let in_place = tip_length < NO_TIP_MOTION_MM && fastest.minutes > 0.0;
    let plain = |f| Feed { f, slowed: None };
    plain(match mode {
        FeedMode::Tip => {
            if in_place && firmware_length > eps {
                return plain(floor_written(firmware_length / fastest.minutes));
            }
            if !(tip_length >= NO_TIP_MOTION_MM && firmware_length > eps) {
                return plain(f);
            }
            let t_tip = tip_length / f;
            if let (Some(axis), true) = (fastest.axis, fastest.minutes > t_tip) {
                return Feed {
                    f: floor_written(firmware_length / fastest.minutes),
                    slowed: Some((axis, fastest.minutes - t_tip)),
                };
            }
            let fo = f * firmware_length / tip_length;
            if (fo - f).abs() <= TIP_FEED_SNAP * f {
                f
            } else {
                fo
            }
        }
        FeedMode::Xyz => f,
        FeedMode::AllAxes => {
            if in_place && d > eps {
                d / fastest.minutes
            } else if tip_length >= NO_TIP_MOTION_MM {
                f * d / tip_length
            } else {
                f
            }
        }
        FeedMode::InverseTime => {
            if in_place {
                1.0 / fastest.minutes
            } else if tip_length >= NO_TIP_MOTION_MM {
                f / tip_length
            } else if d > eps {
                f / d
            } else {
                f
            }
        }
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A move with no axis limit (the unit tests below give every axis `+inf`).
    fn mv<'a>(from: &'a [f64], to: &'a [f64], l: f64, d_fw: f64, f: f64) -> FeedMove<'a> {
        FeedMove {
            from,
            to,
            tip_length: l,
            firmware_length: d_fw,
            f,
            fastest: fastest(&[f64::INFINITY; 4], from, to),
        }
    }

    #[test]
    fn a_reorientation_in_place_runs_its_axes_at_their_largest_feed() {
        // the tip moves 3e-8 mm (kinematics noise) while A turns 90° and X 2 mm; A's largest
        // feed 3600 °/min, X's 12000 mm/min: T = max(90/3600, 2/12000) = 0.025 min
        let (a, b) = ([0.0, 0.0, 0.0, 0.0], [2.0, 0.0, 0.0, 90.0]);
        let lim = fastest(&[12000.0, 12000.0, 720.0, 3600.0], &a, &b);
        assert_eq!(lim.axis, Some(3));
        assert_eq!(lim.minutes, 0.025);
        let m = FeedMove {
            fastest: lim,
            ..mv(&a, &b, 3e-8, 2.0, 1800.0)
        };
        // tip: the firmware's length is X's 2 mm → F = 2 / 0.025 = 80
        assert_eq!(output_feed(FeedMode::Tip, &m).f, 80.0);
        // all axes: √(4 + 8100) / 0.025
        let d = (4.0f64 + 8100.0).sqrt();
        assert_eq!(output_feed(FeedMode::AllAxes, &m).f, d / 0.025);
        assert_eq!(output_feed(FeedMode::InverseTime, &m).f, 40.0);
        assert_eq!(output_feed(FeedMode::Xyz, &m).f, 1800.0);
        // without any axis limit: F = f (f / D in inverse time), never f · D / L ≈ 5·10¹⁰
        let free = mv(&a, &b, 3e-8, 2.0, 1800.0);
        assert_eq!(output_feed(FeedMode::Tip, &free).f, 1800.0);
        assert_eq!(output_feed(FeedMode::AllAxes, &free).f, 1800.0);
        assert_eq!(output_feed(FeedMode::InverseTime, &free).f, 1800.0 / d);
        // a tip motion the file can show (0.01 mm) is timed by it: F = f · D / L
        let shown = mv(&a, &b, 0.01, 2.0, 1800.0);
        assert_eq!(output_feed(FeedMode::Tip, &shown).f, 1800.0 * 2.0 / 0.01);
    }

    /// The triple-Z bed (seed 001 §4.8: Z motors at 1900 mm/min): a 10 mm tip move at
    /// 6000 mm/min (10/6000 = 1/600 min) that drives X 10 mm and Z 5 mm: Z would run at
    /// 5 · 600 = 3000 > 1900 mm/min, so T = 5/1900 min and F = D_fw / T = √125 · 380 (rounded
    /// down to 0.001), Z at its limit.
    #[test]
    fn tip_feed_is_lowered_so_the_fastest_axis_runs_at_its_limit() {
        let (a, b) = ([0.0, 0.0, 0.0], [10.0, 0.0, 5.0]);
        let max = [12000.0, 12000.0, 1900.0];
        let d = 125f64.sqrt();
        let m = FeedMove {
            fastest: fastest(&max, &a, &b),
            ..mv(&a, &b, 10.0, d, 6000.0)
        };
        let out = output_feed(FeedMode::Tip, &m);
        let want = (d * 380.0 * 1000.0).floor() / 1000.0;
        assert_eq!(out.f, want);
        let (axis, added) = out.slowed.unwrap();
        assert_eq!(axis, 2);
        assert!((added - (5.0 / 1900.0 - 10.0 / 6000.0)).abs() < 1e-15);
        // Z's speed at the written F: 5 mm in D_fw / F minutes, at most 1900
        let z = 5.0 / (d / out.f);
        assert!(z <= 1900.0 && z > 1900.0 * (1.0 - 1e-6), "{z}");
        // at 1500 mm/min Z runs at 5 · 150 = 750: F = f · D_fw / L, not slowed
        let slow = FeedMove { f: 1500.0, ..m };
        let out = output_feed(FeedMode::Tip, &slow);
        assert_eq!((out.f, out.slowed), (1500.0 * d / 10.0, None));
        // the other modes keep their F (the firmware slows the move)
        assert_eq!(output_feed(FeedMode::Xyz, &m).slowed, None);
        assert_eq!(output_feed(FeedMode::InverseTime, &m).f, 600.0);
    }

    #[test]
    fn a_move_takes_tip_length_over_feed() {
        // 3 mm of tip at 600 mm/min = 0.005 min; the axes move (3, 0, 0, 4°) → D = 5.
        let (a, b) = ([0.0, 0.0, 0.0, 0.0], [3.0, 0.0, 0.0, 4.0]);
        assert_eq!(
            output_feed(FeedMode::Xyz, &mv(&a, &b, 3.0, 3.0, 600.0)).f,
            600.0
        );
        let f = output_feed(FeedMode::AllAxes, &mv(&a, &b, 3.0, 3.0, 600.0)).f;
        assert!((5.0 / f - 0.005).abs() < 1e-15);
        let g = output_feed(FeedMode::InverseTime, &mv(&a, &b, 3.0, 3.0, 600.0)).f;
        assert!((1.0 / g - 0.005).abs() < 1e-15);
        // Tip: the firmware counts 2 mm for this move (its own rule) → F = 400, T = 0.005.
        let t = output_feed(FeedMode::Tip, &mv(&a, &b, 3.0, 2.0, 600.0)).f;
        assert!((2.0 / t - 0.005).abs() < 1e-15);
        // Pure rotation: 4° at 600 → inverse time 150 per minute; tip keeps F = f.
        let c = [0.0, 0.0, 0.0, 4.0];
        assert_eq!(
            output_feed(FeedMode::InverseTime, &mv(&a, &c, 0.0, 4.0, 600.0)).f,
            150.0
        );
        assert_eq!(
            output_feed(FeedMode::Tip, &mv(&a, &c, 0.0, 4.0, 600.0)).f,
            600.0
        );
        // a firmware length within 0.1 % of the tip's keeps the slicer's F
        assert_eq!(
            output_feed(FeedMode::Tip, &mv(&a, &b, 3.0, 3.0009, 600.0)).f,
            600.0
        );
        assert!(output_feed(FeedMode::Tip, &mv(&a, &b, 3.0, 3.0031, 600.0)).f > 600.5);
        assert_eq!(FeedMode::parse("tip"), Some(FeedMode::Tip));
        assert_eq!(FeedMode::parse("all-axes"), Some(FeedMode::AllAxes));
        assert_eq!(FeedMode::parse("fast"), None);
    }
}
